/* sun.h: horizons and insolation (one header for src/sun/).
 *
 *   horizon     horizon elevation angles of every DEM cell, per azimuth
 *   insolation  daily clear-sky insolation and sky-view factor
 */
#ifndef TD_SUN_H
#define TD_SUN_H

#include "src/core/core.h"


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

/* ---- insolation ---- */
/* insolation.h: daily clear-sky insolation, sky-view factor and horizon
 * angles of every DEM cell (paper 000 §3.2; docs/insolation.md).
 *
 * Two methods, as in the paper:
 *   TD_INSOL_HORIZON         the fast method (Alg. 3.1): k horizon angles
 *                            per cell from the profile sweep (horizon.h),
 *                            O(k n^2).
 *   TD_INSOL_HIDDEN_SURFACE  the reference: m viewpoints on the sky
 *                            hemisphere, one z-buffer (hidden-surface) pass
 *                            per viewpoint deciding which cells see that
 *                            sky direction, O(m n^2).
 *
 * Conventions: azimuth in degrees clockwise from north, north = row 0;
 * elevation in degrees above the horizontal.  Ground vectors are
 * (east, north, up).  Output units: W/m^2 (irradiance), Wh/m^2 per day
 * (irradiation).  The sky-view factor is the radiative (cosine-weighted)
 * one of a horizontal surface: the fraction of isotropic diffuse sky
 * radiation a horizontal surface at the cell receives, 1 on open flat
 * ground. */

typedef enum td_insol_method {
    TD_INSOL_HORIZON = 0,
    TD_INSOL_HIDDEN_SURFACE = 1
} td_insol_method;

typedef struct td_insol_params {
    double latitude;       /* degrees, -90..90 (required, default 0) */
    int day;               /* day of the year 1..366 (default 172) */
    double step_minutes;   /* time step of the day's sum (default 10) */
    td_insol_method method;/* default TD_INSOL_HORIZON */
    int directions;        /* k horizon azimuths (horizon method, 36) */
    int viewpoints;        /* m sky viewpoints (hidden-surface, 1024) */
    double cell_size;      /* ground size of a cell, height units (1) */
    double solar_constant; /* W/m^2 at 1 AU (1367) */
    double transmittance;  /* clear-sky beam transmittance at zenith (0.7) */
    double diffuse_coef;   /* Liu-Jordan diffuse coefficient (0.3) */
    int curvature;         /* nonzero: Earth curvature in the horizons,
                              horizon method only (0) */
    double earth_radius;   /* R in height units (6371000, metres) */
} td_insol_params;

/* Defaults as listed above. */
td_insol_params td_insol_defaults(void);

/* What td_insolation_run returns; every grid has the DEM's size and the
 * DEM's nodata (-9999 when it has none) on nodata cells. */
typedef struct td_insol_result {
    td_grid_f32 *total;    /* direct + diffuse, Wh/m^2 per day */
    td_grid_f32 *direct;   /* direct beam on the cell's slope, Wh/m^2 */
    td_grid_f32 *diffuse;  /* diffuse, Wh/m^2 */
    td_grid_f32 *skyview;  /* radiative sky-view factor, 0..1 */
    int k;                 /* number of horizon bands */
    td_grid_f32 **horizons;/* k bands, band i at azimuth i * 360 / k,
                              degrees >= 0 (hidden-surface: estimated
                              from the viewpoint grid, see below) */
    int az_count, el_count;/* hidden-surface viewpoint grid, else 0 */
} td_insol_result;

/* Run the whole stage on dem.  On success *out is a new result (free with
 * td_insol_result_free).  Progress: "horizon" or "hidden-surface", then
 * "insolation".  Returns 0, TD_EINVAL (bad parameters or grid), TD_ENOMEM,
 * TD_ECANCEL; *out is NULL on failure. */
int td_insolation_run(const td_grid_f32 *dem, const td_insol_params *p,
                      td_insol_result **out, td_ctx *cx);

/* Frees r and every grid in it; NULL is a no-op. */
void td_insol_result_free(td_insol_result *r);

/* ---- building blocks (public for tests and other stages) ------------- */

/* Solar declination in degrees for day 1..366 (Cooper 1969). */
double td_sun_declination(int day);

/* The unit vector towards the sun (east, north, up) at latitude lat_deg,
 * day `day`, local solar time `hour` (12 = noon). */
void td_sun_vector(double lat_deg, int day, double hour, double s[3]);

/* Clear-sky irradiance for a sun at elevation sin_el (> 0): *beam the
 * beam (direct normal) irradiance, *diffuse the diffuse horizontal one,
 * W/m^2 (model in insolation.c and docs/insolation.md).  Both 0 when the
 * sun is at or below the horizontal. */
void td_clear_sky(const td_insol_params *p, double sin_el, double *beam,
                  double *diffuse);

/* One hidden-surface pass: vis (caller-allocated u8, dem's size) gets 1
 * where the cell centre sees the sky direction (azimuth az_deg, elevation
 * el_deg > 0) past all terrain, else 0 (nodata cells 0).  Parallel
 * projection towards that direction, the DEM drawn as two triangles per
 * 2x2 cell centres into a z-buffer.  Returns 0, TD_EINVAL, TD_ENOMEM,
 * TD_ETOOBIG. */
int td_insol_visibility(const td_grid_f32 *dem, double cell_size,
                        double az_deg, double el_deg, td_grid_u8 *vis,
                        td_ctx *cx);

/* Horizon angle (degrees) at azimuth az_deg of cell index `at` (y * stride
 * + x of the bands), linearly interpolated between the two nearest of the
 * k bands. */
double td_insol_horizon_at(td_grid_f32 *const *bands, int k, size_t at,
                           double az_deg);

#ifdef __cplusplus
}
#endif
#endif
