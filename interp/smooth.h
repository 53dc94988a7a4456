/* smooth.h: band-constrained smoothing of an interpolated DEM (ours, not
 * from the papers; `--smooth N`).
 *
 * Linear interpolation between contours is continuous but its slope is
 * not: where the blend switches from one pair of contour cells to another
 * it leaves straight creases that shaded relief shows plainly.  Here every
 * cell that is not on a contour is moved towards the mean of its 4
 * neighbours (Gauss-Seidel sweeps, row by row), but never out of the band
 * between the two contour heights it lies between, so every contour of the
 * result is where the map draws it:
 *
 *          b               z(x) := mean(a, b, c, d), then clamped to
 *        a x c             [lo, lo + I), lo = base + I floor((z0 - base) / I)
 *          d               (z0 the cell's height before smoothing)
 *
 * Line cells and nodata cells stay as they are; nodata neighbours are left
 * out of the mean.  Memory: the mask of line cells (1 byte per cell). */
#ifndef TD_INTERP_SMOOTH_H
#define TD_INTERP_SMOOTH_H

#include "src/core/core.h"

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Smooth g in place with iters sweeps as above; fixed[y * g->w + x] != 0
 * marks the contour cells (kept), cells equal to g->nodata are skipped.
 * Heights are base + k * interval (interval > 0).  Returns 0, TD_EINVAL
 * or TD_ECANCEL (g then partly smoothed, every cell still in its band). */
int td_smooth_bands(td_grid_f32 *g, const uint8_t *fixed, double base,
                    double interval, int iters, td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
