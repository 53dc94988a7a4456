/* endpair.h: which free ends of traced lines continue each other across a
 * gap (ours; not in the papers).
 *
 * The scanner leaves a contour in pieces where something printed over it
 * hid its ink (a road, a stream, a label the joiner did not close) or the
 * ink broke.  The joiner (join.h) joins only what it is sure of; what it
 * leaves open, the labeller may still take as evidence that two pieces
 * are one contour (the same height), outvoted when the rest disagrees:
 *
 *        a.t -->    d    <-- b.t      ends a, b of two lines (or of one:
 *   ======a  . . . . . .  b=====      a ring) at most max_gap apart, each
 *                                     tangent within TD_ENDPAIR_ANGLE of
 *   the chord towards the other; each end keeps the partner it fits best
 *   (d / max_gap + the two angles / 180), and a pair is kept when each is
 *   the other's best.  A stream's V cut at its apex: the two arms point
 *   into the gap at up to TD_ENDPAIR_ANGLE off the chord. */
#ifndef TD_ENDPAIR_H
#define TD_ENDPAIR_H

#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

#define TD_ENDPAIR_ANGLE 75.0  /* degrees */
#define TD_ENDPAIR_TANGENT 8.0 /* px back along the line for the tangent */

typedef struct td_end_pair {
    size_t a, b;      /* lines (a == b: a line's own two ends) */
    int alast, blast; /* the end: 1 the line's last vertex, 0 its first */
    double ax, ay, bx, by; /* the two ends */
    double d;              /* px between them */
    double cost;      /* d / max_gap + (angle a + angle b) / 180 */
} td_end_pair;

/* The pairs of free ends of the open lines of ls that keep (NULL: all)
 * accepts, ends within 2 px of the w x h sheet's border left out, into
 * *out (free it), *n of them, sorted by line and end.  Returns 0 or
 * TD_ENOMEM. */
int td_end_pairs(const td_lines *ls, int (*keep)(size_t i, const void *u),
                 const void *u, int w, int h, double max_gap, td_end_pair **out,
                 size_t *n, td_ctx *cx);

#ifdef __cplusplus
}
#endif

#endif
