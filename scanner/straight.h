/* straight.h: long straight lines across the sheet (the map grid, a
 * graticule, the neatline) found in the ink mask and erased before
 * thinning (ours, not the paper's).  A contour never runs straight across
 * the whole sheet; a grid line does, and where it crosses contours it
 * merges them into one skeleton, so traced lines jump along it.
 *
 *   the mask in strips of `strip` rows: per strip, how many rows have ink
 *   within 1 px of each column (a 3-px band);
 *
 *        band  x-6   x   x+6
 *   strip  .    .    #    .     a peak: ink in >= cover of the rows at x,
 *          .    #    #    .     `contrast` of them and 1.4 times as many as
 *          .    .    #    #     6 px to either side (contours are not
 *                               straight)
 *
 *   the peaks voted into lines (Hough: slope up to 1.5 degrees, a scan's
 *   skew, intercept in 2 px); a line through peaks in at least `span` of
 *   the strips, each within 1.5 px of its least-squares fit, with ink
 *   within 1 px along `line_cover` of its length and at most `max_width`
 *   wide, is a grid line.  It is erased where it runs alone (the run of
 *   ink across it at most its width, and at least 3 px); where a contour
 *   crosses it (a longer run) the ink stays, so the contours are not cut.
 *   The same on the transposed mask for horizontal lines. */
#ifndef TD_STRAIGHT_H
#define TD_STRAIGHT_H

#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct td_straight_params {
    int on;           /* 1: find and erase (default 1) */
    int strip;        /* rows per strip (default 128) */
    double cover;     /* share of a strip's rows with ink at the peak (0.3) */
    double contrast;  /* ... more than 6 px to either side (0.15; and at
                         least 1.4 times as many) */
    double span;      /* share of the strips with a peak on it (0.4) */
    double line_cover; /* share of its length with ink within 1 px (0.35;
                          a faded grid on a new print reads as contour
                          ink along 36-41 % of it: docs/scanner.md) */
    double max_width;  /* wider lines are no grid (default 6 px) */
} td_straight_params;

td_straight_params td_straight_defaults(void);

/* Erase the straight lines of mask (1 = ink) in place; *found (may be
 * NULL) gets how many lines were erased.  Uses O(width + height) x the
 * number of strips extra memory.  Returns 0 or TD_ENOMEM. */
int td_straight_remove(td_grid_u8 *mask, const td_straight_params *p,
                       size_t *found, td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
