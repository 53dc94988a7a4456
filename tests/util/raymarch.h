/* raymarch.h: brute-force horizon by marching one ray over the bilinear
 * surface of the cell centres (the reference for src/sun/horizon.c). */
#ifndef TD_RAYMARCH_H
#define TD_RAYMARCH_H

#include "src/core/core.h"

/* Horizon elevation angle (degrees, >= 0) of cell (x, y) towards azimuth
 * az (degrees clockwise from north, north = row 0), cell size cs: the
 * exact maximum of the tangent over the ray until it leaves the grid.
 * No nodata handling. */
double tr_exact_march(const td_grid_f32 *g, int x, int y, double az,
                      double cs);

#endif
