/* bordercut.h: traced lines cut where they turn back at the sheet's
 * border between their ends (ours; not in the papers).
 *
 * Two contours that leave the sheet close together (a steep slope cut by
 * the border) merge in their last pixels before it; thinning leaves a V
 * whose tip lies at the border, and the tracer follows it out along one
 * contour and back along the other:
 *
 *     |\___________  contour A         |  ___________  A
 *     | ___________  contour B   ->    | ___________  B
 *     |/                               |
 *
 * one traced line with two heights, which no labeller can label (on the
 * scanned crowded Front Range 25 sheet such a line took an index
 * contour's two labels with it onto the next contour, and the region
 * beyond came out two intervals low).  A contour never turns back at
 * the sheet's border: it leaves the sheet.  So a line is cut where it
 * turns back within TD_BORDER_NEAR px of the border between its ends
 * (thinning leaves the V's tip a pixel or two short of it): at its point
 * nearest the border, when the line TD_BORDER_ARM px of arc before and
 * after it lies within TD_BORDER_TURN degrees of one direction (a V, not
 * a contour grazing the border on its way); both pieces run on to the
 * border there.  A closed line shorter than TD_BORDER_RING px is a small
 * ring beside the border (a summit's), left whole. */
#ifndef TD_BORDERCUT_H
#define TD_BORDERCUT_H

#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

#define TD_BORDER_NEAR                                                         \
    3.0                     /* px from the border pixels' middle (as the       \
                               tracer's ends run on to it: trace.h) */
#define TD_BORDER_ARM 8.0   /* px of arc: the V's arms */
#define TD_BORDER_TURN 60.0 /* degrees between them at most */
#define TD_BORDER_RING                                                         \
    32.0 /* px: a closed line shorter than this is a small ring, not a V       \
            (its arms would meet round it) */

/* Cut the lines of ls (a w x h sheet) where they turn back at its
 * border between their ends; a closed line opens there.  A cut line's
 * first piece takes its place, the others go at the end, and when any
 * line was cut the lines are renumbered (id = index).  Returns the number
 * of cuts, or a negative error code (TD_ENOMEM) with the error in cx (the
 * lines then valid, some cut). */
long td_border_cut(td_lines *ls, int w, int h, td_ctx *cx);

#ifdef __cplusplus
}
#endif

#endif
