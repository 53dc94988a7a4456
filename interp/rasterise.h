/* rasterise.h: labelled contour lines -> a height grid, and what the
 * interpolation methods share: the span walker, the gap runs and the
 * summit tent.  The one-call driver is interp/interp.h.
 *
 *   labelled lines --td_rasterise_lines--> grid: line height on every cell
 *   a line passes through (4-connected, no gaps), NaN elsewhere
 *   --td_scanline_fill | td_multidir_fill--> DEM (NaN = undetermined,
 *   turned into the grid's nodata value at the end)
 *
 * Cell coordinates: a DEM cell (col,row) covers scan pixels
 * [col*step, (col+1)*step) x [row*step, (row+1)*step); a line point in pixel
 * units (x,y) falls in cell (floor(x/step), floor(y/step)). */
#ifndef TD_INTERP_RASTERISE_H
#define TD_INTERP_RASTERISE_H

#include "src/core/core.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Draw every line of ls into g (whose w,h the caller chose) with its
 * height: g is first set to NaN everywhere, then each segment (the closing
 * one too for closed lines) is drawn by exact grid traversal, so the cells
 * form a 4-connected chain that no horizontal, vertical or diagonal scan
 * can slip through.  Point coordinates are divided by step (>= 1).  Where
 * two lines share a cell the later one wins.
 * Errors (g left NaN): TD_EINVAL when ls is empty, when a line has no
 * height (message names its id: "run topodig label first"), has no
 * points, a non-finite coordinate or height, or no point inside the
 * grid. */
int td_rasterise_lines(const td_lines *ls, double step, td_grid_f32 *g,
                       td_ctx *cx);

/* The contour interval of a labelled set: the smallest positive difference
 * between two distinct line heights (1e-6 relative tolerance), or 0 when
 * all lines share one height. */
double td_interp_interval(const td_lines *ls);

/* Scan directions of the span walker. */
enum { TD_DIR_X = 0, TD_DIR_Y = 1, TD_DIR_DIAG = 2, TD_DIR_ANTI = 3 };

/* One span: two consecutive anchor cells A (first in row-major order) and B
 * on a scan line, n steps apart (n >= 2, so at least one cell between).
 * The cell k steps from A (0 <= k <= n) is at index ia + k*di and at
 * column ca + k*dc, row ra + k*dr.  sl is the length of one step in cells
 * (1 or sqrt 2). */
typedef struct td_span {
    size_t ia;
    ptrdiff_t di;
    int ca, ra, dc, dr, n;
    float za, zb;
    double sl;
} td_span;

typedef void (*td_span_fn)(const td_span *s, void *user);

/* Call fn for every pair of consecutive anchor cells (non-NaN in g) that
 * has cells between them along direction dir (TD_DIR_*).  Every scan line
 * is walked from its first cell in row-major order to its last (the grid
 * in vertical strips for cache locality); when fn is called, every cell
 * strictly between the two anchors has been visited already, so fn may
 * write NaN cells between them without changing which cells later spans
 * see as anchors.
 * Progress is reported as stage `stage` (may be NULL: none).
 * Returns 0, TD_ENOMEM or TD_ECANCEL. */
int td_interp_walk(const td_grid_f32 *g, int dir, td_span_fn fn, void *user,
                   const char *stage, td_ctx *cx);

/* Like td_interp_walk, but only for spans with NaN cells between their
 * anchors (runs of undetermined cells with a determined cell at both
 * ends), found from the undetermined cells and their neighbours: fast
 * when anchors are dense (a grid already mostly filled).  Spans are handed
 * over row by row, x spans at their first cell, the others at their last;
 * fn may fill the run's cells in place.  Returns 0, TD_ENOMEM or
 * TD_ECANCEL. */
int td_interp_walk_gaps(const td_grid_f32 *g, int dir, td_span_fn fn,
                        void *user, const char *stage, td_ctx *cx);

/* Slope of the surface into span s at its anchor A (end 0) or B (end 1),
 * height units per cell, positive when the surface rises towards the
 * span: (z(anchor) - z(cell k steps outside)) / (k*sl) for the farthest
 * determined cell k <= kmax with no NaN before it.  Returns 0 and *slope,
 * or -1 when no determined cell lies outside the anchor. */
int td_interp_slope(const td_grid_f32 *g, const td_span *s, int end,
                    int kmax, double *slope);

/* Paper §2.5 (Fig. 6) for one cell of a gap between two anchors of equal
 * height z: the two lines through the anchors with slopes s1 (from A) and
 * s2 (from B), both positive into the gap (summit) or both negative (pit),
 * meet at Px; the cell at distance d1 from A and d2 from B gets the lower
 * (summit) or higher (pit) of the two lines, at most 0.99 interval away
 * from z (reaching the next contour's height would draw a contour that is
 * not on the map).  Any other pair of slopes: z (flat, as the paper). */
double td_interp_tent(double z, double s1, double s2, double d1, double d2,
                      double interval);

#ifdef __cplusplus
}
#endif
#endif
