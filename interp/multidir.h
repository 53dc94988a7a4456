/* multidir.h: interpolation along several scan directions, blended
 * (`--method multidir`, the default; an improvement beside the paper's
 * scanline method, measured in docs/benchmarks-interp.md).
 *
 * Every cell looks along 4 lines through it (x, y and both diagonals; or
 * x and y only with ndir = 2) for the nearest contour cell on each side.
 * Each line whose two contour cells differ in height gives a linear
 * estimate; the estimates are blended with a weight that falls with the
 * distances (see td_multidir_weight):
 *
 *        \  |  /          z = sum_i w_i z_i / sum_i w_i
 *         \ | /           z_i = linear between the two contour cells on
 *      ----(c)----              line i (different heights only)
 *         / | \           w_i = 1/(d1 + d2)   (default, "span": inverse
 *        /  |  \                              span length)
 *                             = 1/(d1 d2)     ("prod")
 *
 * Cells that no line resolves (inside a summit ring or a pit, where every
 * line meets the same contour on both sides) get the paper's §2.5 summit
 * extrapolation along all 4 lines (slopes from the cells already filled),
 * blended the same way; flat when summit = 0.  Peninsulas need nothing
 * special: the line along the peninsula's axis resolves them.
 * The linear phase runs in one pass down the rows for all directions
 * (multidir_sweep.c); the summit phase only over the cells it left.  Memory on
 * top of the grid: 16 bytes per line cell, then 8 bytes per cell (of
 * which only the pages holding undetermined cells are touched). */
#ifndef TD_INTERP_MULTIDIR_H
#define TD_INTERP_MULTIDIR_H

#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    TD_MULTIDIR_PROD = 0, /* 1 / (d1 * d2): inverse of the linear error */
    TD_MULTIDIR_SPAN = 1, /* 1 / (d1 + d2): inverse span length (default:
                             as accurate as prod, 1.4x faster) */
    TD_MULTIDIR_SPAN2 = 2 /* 1 / (d1 + d2)^2 */
} td_multidir_weight;

typedef struct td_multidir_params {
    double interval; /* contour interval, > 0 (caps the summit) */
    int summit;      /* 1: §2.5 extrapolation along 4 lines (default) */
    int slope_cells; /* cells used for the summit slope (default 4) */
    int ndir;        /* 4 (default) or 2 (x and y only) */
    td_multidir_weight weight; /* default TD_MULTIDIR_SPAN */
} td_multidir_params;

td_multidir_params td_multidir_defaults(void);

/* Fill g in place as td_scanline_fill does (contour heights on line cells,
 * NaN elsewhere in; heights where determinable, NaN elsewhere out).  Uses
 * two extra float grids (allocated, touched only where undetermined cells
 * remain after the linear phase).  Returns 0, TD_EINVAL, TD_ENOMEM,
 * TD_ECANCEL. */
int td_multidir_fill(td_grid_f32 *g, const td_multidir_params *p,
                     td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
