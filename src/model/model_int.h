/* model_int.h: what the model files share inside src/model. */
#ifndef TD_MODEL_INT_H
#define TD_MODEL_INT_H

/* The cells of row `row` whose centres lie in the convex polygon vx, vy
 * (nv corners, cells: 0,0 the top-left corner): [*c0, *c1], clipped to
 * [lo, hi].  0 when the row misses it. */
int td_convex_span(const double *vx, const double *vy, int nv, int row,
                   int lo, int hi, int *c0, int *c1);

#endif
