/* horizon.h: horizon elevation angles of every DEM cell, per azimuth.
 *
 * The paper's fast method (000 §3.2, Alg. 3.1): for each of k azimuths the
 * DEM is cut into parallel profiles along that azimuth and one pass per
 * profile gives every point's horizon; O(k n^2) for an n x n DEM.  Here the
 * pass is an upper convex hull kept on a monotone stack, each cell blends
 * the two profiles beside it and marches its own ray near itself and near
 * the grid's edges (horizon.c, docs/insolation.md).
 *
 * Conventions (docs/insolation.md):
 *   azimuth   degrees clockwise from north; north = up = towards row 0,
 *             east = towards larger columns.  Direction i of k is at
 *             azimuth i * 360 / k.
 *   angle     the horizon's elevation angle in degrees seen from the cell
 *             centre at the cell's own height, looking along the azimuth
 *             over the bilinear surface through the cell centres,
 *             clamped at 0 from below (0 where nothing rises above the
 *             horizontal plane, e.g. at the DEM's edge looking outwards).
 *   nodata    nodata cells get the output's nodata; nodata terrain casts
 *             no horizon (it is treated like the outside of the grid). */
#ifndef TD_HORIZON_H
#define TD_HORIZON_H

#include "src/core/grid.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct td_horizon_params {
    int directions;       /* k azimuths for td_horizon_sweep (default 36) */
    double cell_size;     /* ground size of a cell, height units (default 1) */
    int curvature;        /* nonzero: lower distant terrain by d^2 / (2 R)
                             (default 0) */
    double earth_radius;  /* R in height units (default 6371000, metres) */
} td_horizon_params;

/* Defaults as listed above. */
td_horizon_params td_horizon_defaults(void);

/* Horizon angles of every cell of dem along one azimuth (degrees, any
 * value; see the conventions above) into out, which the caller allocates
 * with dem's width and height (any stride).  out->nodata/has_nodata are set
 * from dem (nodata -9999 when dem has none).  The profiles run in parallel
 * (OpenMP).  Scratch: a padded copy of dem and 8 bytes per cell.
 * Returns 0, or TD_EINVAL (sizes differ, bad parameters), TD_ENOMEM. */
int td_horizon_direction(const td_grid_f32 *dem, double azimuth_deg,
                         const td_horizon_params *p, td_grid_f32 *out,
                         td_ctx *cx);

/* All p->directions azimuths: bands[i] (caller-allocated, dem's size)
 * receives azimuth i * 360 / k.  The directions run in parallel (OpenMP,
 * one thread each, the scratch of td_horizon_direction per thread).
 * Progress is reported as "horizon".  Returns 0 or an error as
 * td_horizon_direction, or TD_ECANCEL. */
int td_horizon_sweep(const td_grid_f32 *dem, const td_horizon_params *p,
                     td_grid_f32 *const *bands, td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
