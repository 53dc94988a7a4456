/* model_int.h: what the model files share inside src/model. */
#ifndef TD_MODEL_INT_H
#define TD_MODEL_INT_H

#include "src/model/model.h"

/* The cells of row `row` whose centres lie in the convex polygon vx, vy
 * (nv corners, cells: 0,0 the top-left corner): [*c0, *c1], clipped to
 * [lo, hi].  0 when the row misses it. */
int td_convex_span(const double *vx, const double *vy, int nv, int row,
                   int lo, int hi, int *c0, int *c1);

/* The trapezoid x, y (4 corners, cells) swept by a skeleton edge whose
 * line is n . p = c + t: each cell centre inside gets the time the line
 * passed it, clamped to [t0, t1], where that is higher than the cell's
 * value (or the cell is nodata). */
void td_skeleton_quad(td_grid_f32 *g, const double *x, const double *y,
                      double nx, double ny, double c, double t0, double t1);

/* The event-queue construction (skeleton_queue.c) on a clean outline
 * (counter-clockwise, no repeated points, size its extent): as
 * td_skeleton. */
int td_skeleton_queue(const double *xy, size_t n, double size,
                      const td_skeleton_params *prm, td_grid_f32 *dem,
                      td_lines *contours, td_lines *peaks,
                      td_skeleton_stats *st, td_ctx *cx);

#endif
