/* flow.h: rain-flow pass counts and ridge/valley/slope classes (Fujita et
 * al., paper 000 §3.1; ALGORITHMS.md C2), with a linear-time improvement.
 *
 * Rain falls evenly on every valid cell (one unit per cell); each unit
 * flows downhill; a cell's pass count is the number of units whose path
 * includes it (its own rain included, so every valid cell counts >= 1).
 * Frequently passed cells are valleys, rarely passed ones ridges.
 *
 * Methods:
 *   TD_FLOW_SOBEL  the paper's method: every drop is traced on its own
 *                  over the raw DEM along the negative Sobel gradient
 *                  (quantised to the nearest of the 8 neighbours); a drop
 *                  stops where that neighbour is not lower (a pit or flat:
 *                  the paper handles no depressions), at the grid edge or
 *                  nodata (it drains out), or after max_steps moves.
 *                  Cost: cells x mean path length.
 *   TD_FLOW_D8     priority-flood depression filling (no epsilon; in
 *                  tiles on threads, Barnes 2016: the same result), then
 *                  steepest descent on the filled DEM; cells with no lower
 *                  neighbour (filled pits and flats) drain by shortest
 *                  paths to the nearest exit of their flat; linear-time
 *                  accumulation (row bands on threads).
 *   TD_FLOW_DINF   as D8 but Tarboton's D-infinity split between two
 *                  neighbours (flats as in D8).
 *
 * Edges and nodata: nodata cells get no rain and hold nodata in the output;
 * they act like the outside of the grid.  D8/DINF: every valid cell on the
 * grid edge or next to nodata is an outlet (its water leaves the grid
 * there, as in the priority-flood seeds).  SOBEL: a drop leaves when its
 * next move would go off the grid or onto nodata.  Square cells are assumed (the cell
 * size cancels out of every direction).  Full notes: docs/flow.md. */
#ifndef TD_FLOW_H
#define TD_FLOW_H

#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum td_flow_method {
    TD_FLOW_SOBEL = 0,
    TD_FLOW_D8 = 1,
    TD_FLOW_DINF = 2
} td_flow_method;

typedef struct td_flow_params {
    td_flow_method method; /* TD_FLOW_SOBEL, the paper's method */
    long max_steps;        /* SOBEL: moves per drop; 0: 4 (w + h) [0] */
    int tile;              /* D8/DINF: tile side of the fill; 0: 512 [0].
                              Any side gives the same result (speed only) */
    int threads;           /* D8/DINF: OpenMP threads for the fill and the
                              directions; 0: the OpenMP default [0].  The
                              result is the same for any count */
} td_flow_params;

/* Counts over a run (all methods unless noted). */
typedef struct td_flow_stats {
    double cells;     /* valid cells = rain units */
    double outflow;   /* units that left the grid (edge or nodata) */
    double outlets;   /* cells where water leaves the grid */
    double pit_stops; /* SOBEL: drops that stopped in a pit or on a flat */
    double capped;    /* SOBEL: drops stopped by max_steps */
    double moves;     /* SOBEL: drop moves in all */
    double raised;    /* D8/DINF: cells raised by depression filling */
    double max_pass;  /* largest pass count */
} td_flow_stats;

/* Classes written by td_flow_classify. */
enum { TD_FLOW_NODATA = 0, TD_FLOW_RIDGE = 1, TD_FLOW_SLOPE = 2,
       TD_FLOW_VALLEY = 3 };

/* Defaults: method TD_FLOW_SOBEL, max_steps 0 (4 (w + h)). */
td_flow_params td_flow_defaults(void);

/* Pass counts of dem into passes (caller-allocated, same w and h; its
 * nodata and has_nodata are set to dem's).  st may be NULL.  Counts are
 * accumulated in 32-bit unsigned integers (SOBEL, D8) or doubles (DINF)
 * and stored as float (exact below 2^24).  D8 working memory: 1 byte per
 * cell beyond dem and passes (passes holds the filled DEM, then the
 * counts), 2 more while filling (labels), plus the flats' queue (4 bytes
 * per flat cell at most).  Reports progress as stage "flow".  0, TD_EINVAL
 * (bad size or params), TD_ENOMEM, TD_ECANCEL. */
int td_flow_run(const td_grid_f32 *dem, const td_flow_params *p,
                td_grid_f32 *passes, td_flow_stats *st, td_ctx *cx);

/* Priority-flood depression filling (Barnes et al. 2014, with upslope
 * tracing that skips the priority queue where it cannot change the
 * result, run in tiles of side `tile` joined through their border spill
 * levels, Barnes 2016; 0: 512; every side gives the same result): filled
 * (caller-allocated, same size) gets, for every valid cell, the lowest
 * level at which water can leave the grid from it (so no valid cell is
 * lower than all its neighbours unless it is an outlet).  Flats stay flat
 * (no epsilon).  Nodata cells (NaN too) get dem's nodata value.  0,
 * TD_EINVAL, TD_ENOMEM, TD_ECANCEL. */
int td_flow_fill(const td_grid_f32 *dem, td_grid_f32 *filled, int tile,
                 td_ctx *cx);

/* Classes from pass counts by quantiles of the valid cells' counts:
 * RIDGE where count <= Q(ridge_q), VALLEY where count >= Q(valley_q),
 * SLOPE otherwise, NODATA on nodata.  Q(q) is the value at rank
 * floor(q (N - 1)) of the N sorted counts, so ties at the quantile all go
 * to the class (many cells collect only their own rain, so the ridge share
 * can exceed ridge_q).  Needs 0 <= ridge_q < valley_q <= 1.  classes is
 * caller-allocated with the same size.  Uses 4 bytes per valid cell
 * temporarily.  0, TD_EINVAL, TD_ENOMEM. */
int td_flow_classify(const td_grid_f32 *passes, double ridge_q,
                     double valley_q, td_grid_u8 *classes, td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
