/* width.h: ink width of traced lines, measured across the mask.
 *
 * Ours (not in paper 001): printed sheets draw every 5th contour (the
 * index contours) thicker; `topodig label --index-every` uses the widths to
 * check the heights (scanner/label.h). */
#ifndef TD_WIDTH_H
#define TD_WIDTH_H

#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Set ls->v[i].width to the median ink width of line i in px: at every
 * 2nd vertex (traced lines have one per pixel step; not the 4 at an open
 * line's ends; at most 512 samples per line), the run of ink (mask != 0)
 * across the line through the vertex, along the normal of the chord from 3
 * vertices before to 3 after it; vertices off the ink (a bridged gap) and
 * runs longer than 24 px (a blot, a crossing) are skipped.  Lines with
 * fewer than 5 runs get width 0 (not measured).  mask is the binarised
 * scan before thinning, same pixel frame as the lines.  Returns 0 or
 * TD_ENOMEM (widths then unchanged or partly set). */
int td_line_widths(const td_grid_u8 *mask, td_lines *ls, td_ctx *cx);

/* The mask packed one bit per pixel (rows of (w + 7) / 8 bytes, column c
 * in bit c & 7 of byte c >> 3), so a scan can keep it at 1/8 byte per
 * pixel while it thins the mask in place.  free() it; NULL on TD_ENOMEM. */
uint8_t *td_width_pack(const td_grid_u8 *mask, td_ctx *cx);

/* The packed w x h mask's bit at pixel (x, y); 0 off the sheet. */
static inline int td_packed_at(const uint8_t *bits, int w, int h, int x, int y)
{
    if (x < 0 || y < 0 || x >= w || y >= h)
        return 0;
    return bits[(size_t)y * (((size_t)w + 7) / 8) + ((size_t)x >> 3)] >>
               (x & 7) & 1;
}

/* Set (set != 0) or clear the bits of the packed w x h map along every
 * line of ls (only[i] != 0 when only is given): each segment, the
 * closing one of a closed line too, sampled every 1/2 px, each pixel met
 * with its neighbours within grow px (a square). */
void td_packed_lines(uint8_t *bits, int w, int h, const td_lines *ls,
                     const unsigned char *only, int grow, int set);

/* The bit of the pixel holding point (x, y) (pixel c spans [c, c + 1));
 * 0 off the sheet. */
static inline int td_packed_at_pt(const uint8_t *bits, int w, int h, double x,
                                  double y)
{
    if (!(x >= 0 && y >= 0 && x < w && y < h))
        return 0;
    return td_packed_at(bits, w, h, (int)x, (int)y); /* floor: both >= 0 */
}

/* The unit normal (*nx, *ny) of line l at vertex k: the chord from `chord`
 * vertices before k to `chord` after it (wrapping on a closed line,
 * clamped at an open line's ends) turned left; 0 when the chord is
 * shorter than 1 px (no direction), else 1. */
int td_line_normal(const td_line *l, size_t k, size_t chord, double *nx,
                   double *ny);

/* The run of ink across (x, y) along the unit normal (nx, ny), both ways
 * from the point, on the packed w x h mask, as td_line_widths measures
 * it: stepped in 1/4 px, each way ending at the first step on paper; over
 * 24 px each way counts as 25. */
double td_width_across(const uint8_t *bits, int w, int h, double x, double y,
                       double nx, double ny);

/* The largest step of td_width_across's runs not beyond t px: a run
 * longer than t has ink there. */
double td_width_step_below(double t);

/* td_line_widths on a packed w x h mask. */
int td_line_widths_packed(const uint8_t *bits, int w, int h, td_lines *ls,
                          td_ctx *cx);

/* The same for the lines whose width is still 0 (pieces a cut made; the
 * others keep theirs: measured on the same mask, they would not change). */
int td_line_widths_packed_unset(const uint8_t *bits, int w, int h, td_lines *ls,
                                td_ctx *cx);

/* Each line's ink darkness (ours): at samples along it (as the widths),
 * the darkest point within TD_DARK_REACH px across it, as paper minus it
 * (the green channel of a colour scan: the contour inks' darkest), the
 * median over its samples over the paper's level into l->ink (0 with
 * fewer than W_MIN_RUNS samples).  The paper: the median of a sparse
 * sample of im.  Blur spreads a thin line's ink, so its middle is lighter
 * than a thick one's of the same ink: on the printed maps the index
 * contours' middles are 1.4-1.5 times as dark (docs/scanner.md, "Line
 * widths").  Lines on threads.  0, or TD_EINVAL, TD_ENOMEM. */
#define TD_DARK_REACH 1.5
int td_line_darkness(const td_image *im, td_lines *ls, td_ctx *cx);

/* Whether the index contours are told by ink weight (width times
 * darkness): nine in ten of the lines with a width have a darkness (lines
 * read from a file without one are told by their widths). */
int td_lines_inked(const td_lines *ls);

/* Line l's ink weight when inked (above; 0, unknown, without a
 * darkness), else its width. */
static inline double td_line_weight(const td_line *l, int inked)
{
    return inked ? l->width * l->ink : l->width;
}

/* The sheet's pen: the median width of the measured lines 30 px and
 * longer, 0 if none, -1 on TD_ENOMEM. */
double td_pen_width(const td_lines *ls, td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
