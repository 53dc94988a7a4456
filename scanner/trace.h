/* trace.h: skeleton -> contour polylines.  Paper 001 §2.3 (Fig. 3);
 * ALGORITHMS.md A.4. */
#ifndef TD_TRACE_H
#define TD_TRACE_H

#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* 5x5 gap bridging: none, the paper's (the ring's first pixel
 * counter-clockwise), ours (the ring's pixel straight ahead, within 50
 * degrees of the line's last 6 px; the default). */
enum { TD_BRIDGE_NONE = 0, TD_BRIDGE_PAPER = 1, TD_BRIDGE_AHEAD = 2 };

typedef struct td_trace_params {
    int bridge;     /* TD_BRIDGE_*: 5x5 gap bridging (default AHEAD) */
    int edge_dist;  /* an open line ending within this many px of the sheet
                       border is extended to the border and flagged edge
                       (thinning pulls line ends back from the border by
                       about half the line width); default 3, 0 = off */
    int min_closed; /* fewest points a closed line has (default 4) */
    int cut;        /* nonzero (ours, the default): lines stop at skeleton
                       junctions (>= 3 branches: touching contours) instead
                       of passing along the first branch counter-clockwise
                       (the paper, 0); td_join then pairs the ends across
                       the junction by direction */
} td_trace_params;

typedef struct td_trace_stats {
    size_t lines, closed, open, edge;
    size_t bridged;   /* gaps bridged by the 5x5 search or ring closure */
    size_t junctions; /* skeleton pixels with >= 3 branches when tracing
                         started (touching contours), split by the trace */
    size_t points;    /* skeleton pixels traced (= points written) */
} td_trace_stats;

td_trace_params td_trace_defaults(void);

/* Trace every skeleton pixel of skel (cells 0/1) into exactly one line
 * (with p->cut, junction pixels into none).
 * skel is used for visit marks and restored before returning.  *out gets a
 * new td_lines (caller frees with td_lines_free).  st may be NULL.
 * Returns 0, TD_ENOMEM or TD_ECANCEL. */
int td_trace(td_grid_u8 *skel, const td_trace_params *p, td_lines **out,
             td_trace_stats *st, td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
