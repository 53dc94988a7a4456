/* flank.h: traced lines that run along another ink's stroke (ours; not in
 * the papers).
 *
 * On a colour scan the contour ink is told from the other inks by colour,
 * and a red road's edges (road red mixed with paper, with the scanner's
 * colour fringe) look like thin brown: the palette's veto clears the road
 * where its red fills 2 x 2 blocks (binarise.h), but a one-pixel flank
 * survives along it, thins to a line and is traced.  Such a line runs
 * along the road, takes in the contours that cross it, and the labeller
 * then sees a "contour" along the road that separates the two sides of
 * the sheet by one interval.
 *
 *        contour           the stretch of a traced line that stays within
 *     ------+------         TD_FLANK_NEAR px of the other ink's strokes
 *   road ===#=======        for more than TD_FLANK_MIN px is cut out; a
 *     ------+------         contour crossing the road stays near it over
 *                           the road's width only, and keeps its pieces
 *                           for the joiner.
 * The other ink's map is patchy (its 2 x 2 blocks come and go along a
 * thin road): gaps of up to TD_FLANK_GAP px between near stretches count
 * as near.  A shorter stretch is cut at an open line's end when it hooks
 * along the road (at least TD_FLANK_HOOK px, turned TD_FLANK_TURN degrees
 * off the line's course): the joiner would pair the hook's tip, heading
 * along the road, with the next contour's end. */
#ifndef TD_FLANK_H
#define TD_FLANK_H

#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

#define TD_FLANK_NEAR 2   /* px (a 5 x 5 window) */
#define TD_FLANK_MIN 12.0 /* px along the line */
#define TD_FLANK_GAP 10.0 /* px */
#define TD_FLANK_HOOK 4.0 /* px: an end's hook along the other ink */
#define TD_FLANK_TURN 50.0 /* degrees: its turn off the line's course */
#define TD_FLANK_CORNER                                                        \
    3.0 /* px: the hook's corner at most this far past the stretch beside      \
           the other ink (the crossing leaves a gap in its map), the hook      \
           then along the ink within TD_FLANK_ALONG degrees of its axis        \
           over TD_FLANK_AXIS px round the tip */
#define TD_FLANK_TIP                                                           \
    8.0 /* px: ... when the stretch beside it is shorter than this */
#define TD_FLANK_ALONG 30.0
#define TD_FLANK_AXIS 4

/* Whether any pixel of bits (as below) lies within TD_FLANK_NEAR px of
 * (x, y). */
int td_flank_near(const uint8_t *bits, int w, int h, double x, double y);

/* The main axis (*ux, *uy, unit; the covariance of their coordinates) of
 * the pixels of bits (as below) within r px of (floor x, floor y): the
 * (2r + 1)^2 square, or the disc of radius r when disc.  Returns how many
 * pixels it rests on (*ux, *uy untouched when none). */
int td_flank_axis(const uint8_t *bits, int w, int h, double x, double y, int r,
                  int disc, double *ux, double *uy);

/* Cut out of ls every stretch that runs along another ink: within
 * TD_FLANK_NEAR px of its strokes in bits (w x h, one bit a pixel, rows of
 * (w + 7) / 8 bytes, as td_binarise_other_ink gives; NULL: nothing to
 * do).  A closed line cut opens; pieces keep the line's attributes (new
 * ends are not junction ends); pieces of one point are dropped.  Returns
 * the number of stretches cut, or TD_ENOMEM. */
long td_flank_cut(td_lines *ls, const uint8_t *bits, int w, int h, td_ctx *cx);

#ifdef __cplusplus
}
#endif

#endif
