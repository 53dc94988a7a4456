/* model.h: synthetic initial terrains for the erosion experiments.
 *
 * The paper's initial terrain (Fujita, Muraoka, Chiba §3, Fig. 2a): a
 * terrain whose centre is a little higher, with white noise added.  Every
 * random value comes from a seeded generator, so the same parameters give
 * the same bytes on every machine. */
#ifndef TD_TERRAIN_GEN_H
#define TD_TERRAIN_GEN_H

#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct td_mound_params {
    int w, h;        /* grid size (512 x 512) */
    double height;   /* mound height at the centre (w / 8) */
    double radius;   /* mound radius as a fraction of min(w, h) / 2 (0.9) */
    double noise;    /* white-noise amplitude as a fraction of height (0.02) */
    uint64_t seed;   /* noise seed (1) */
} td_mound_params;

td_mound_params td_mound_defaults(void);

/* Fill g (caller-allocated, any size; p->w, p->h are not used here) with
 * the mound: height * (1 - r^2)^2 inside the radius, 0 outside, plus
 * uniform white noise in [-noise, +noise] * height.  0 or TD_EINVAL. */
int td_terrain_mound(td_grid_f32 *g, const td_mound_params *p, td_ctx *cx);

/* Add uniform white noise in [-amp, +amp] (height units) from `seed` to
 * every cell that is not nodata.  0 or TD_EINVAL. */
int td_terrain_noise(td_grid_f32 *g, double amp, uint64_t seed, td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
