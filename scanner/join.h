/* join.h: join traced lines across gaps the 5x5 bridge cannot span.
 * ALGORITHMS.md A.4 "beyond".  Not in the paper: the paper bridges only
 * inside its 5x5 window.  A break of b px in a line of width w leaves a
 * skeleton gap of about b + w px (thinning pulls both ends back), so breaks
 * of 2-4 px in 3-6 px lines need this step. */
#ifndef TD_JOIN_H
#define TD_JOIN_H

#include "../src/lines.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct td_join_params {
    double max_gap;   /* longest gap joined, px (default 16) */
    double max_angle; /* largest angle, degrees, between each end's outward
                         tangent and the gap (default 40) */
    double tangent;   /* length along the line over which an end's tangent is
                         measured, px (default 8) */
    int w, h;         /* sheet size: ends on the border are never joined */
} td_join_params;

typedef struct td_join_stats {
    size_t joins;      /* gaps joined (including closures) */
    size_t closures;   /* lines closed by joining their own two ends */
    size_t ends_open;  /* open ends left (not on the border) */
} td_join_stats;

td_join_params td_join_defaults(int w, int h);

/* Join open lines of *ls whose ends face each other across a gap, and close
 * lines whose two ends meet.  Pairs are taken cheapest first (gap length
 * weighted by the tangent disagreement), each end at most once.  *ls is
 * replaced by the joined set (ids renumbered in order); bridged counts add
 * up.  st may be NULL.  Returns 0 or TD_ENOMEM (then *ls is unchanged). */
int td_join(td_lines **ls, const td_join_params *p, td_join_stats *st,
            td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
