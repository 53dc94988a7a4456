/* widecut.h: lines cut where their ink is too wide to tell the contours
 * in it apart (ours; not in the papers).
 *
 * Where three or more contours crowd into one blob of ink (a canyon wall
 * at a small interval), the skeleton keeps one branch for several
 * contours and a traced line runs from one onto another: a line carrying
 * two heights, which no labeller can label.  The seams (binarise.h) split
 * such ink into ribs, one a contour, but the ribs touch here and there and
 * a line hops between them; so the width is measured on the ink with the
 * seams put back (the caller's mask).  A stretch of a line along
 * which the ink across it is wider than `maxw` px, over at least 4
 * vertices, with another traced line inside that ink (within maxw / 2 +
 * 1 px of the stretch), is cut out: the line ends on both sides of the
 * blob, open ends the labeller handles, instead of jumping through it.
 * A line's own ink (a ring touching itself, a dot) is left alone, and so
 * is a closed line shorter than 8 maxw (a small ring is one contour; drawn
 * as a solid dot its ink is wide all round).
 *
 *     ====a\                      ====a
 *     =====>######=====     ->    =====      =====     (a left open,
 *     ====b/                      ====b                 not paired) */
#ifndef TD_WIDECUT_H
#define TD_WIDECUT_H

#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Cut the lines of ls where the ink of the packed w x h mask bits
 * (width.h's layout) across them is wider than maxw px, as above.  A cut
 * line's pieces are open, flagged td_line.junc at the cut ends, and get
 * width 0 (measure them again); the first keeps the line's id, the others
 * get new ids after the largest.  Pieces of fewer than 3 vertices are
 * dropped.  Returns the number of lines cut, or TD_ENOMEM. */
long td_wide_cut(const uint8_t *bits, int w, int h, td_lines *ls, double maxw,
                 td_ctx *cx);

/* The same; walls (may be NULL) gets every stretch cut out, with the
 * vertex before and after it (where the pieces end): the blobs, for the
 * labeller's faces (faces.h: no face runs through them). */
long td_wide_cut_walls(const uint8_t *bits, int w, int h, td_lines *ls,
                       double maxw, td_lines *walls, td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
