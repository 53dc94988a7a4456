/* render.h: pictures of a DEM so a result can be looked at: shaded relief
 * (hillshade), optionally tinted by height, with contour lines drawn over
 * it.  Pure stage: grid in, RGB image out. */
#ifndef TD_RENDER_H
#define TD_RENDER_H

#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    TD_RENDER_HILLSHADE = 0, /* grey shaded relief */
    TD_RENDER_TINT = 1       /* shaded relief times a height colour ramp */
} td_render_style;

typedef struct td_render_params {
    td_render_style style;
    double azimuth;   /* light from, degrees clockwise from north (315) */
    double altitude;  /* light above the horizon, degrees (45) */
    double zfactor;   /* vertical exaggeration; 0 = auto (default) */
    double cellsize;  /* cell size in height units (1: a pixel = 1 m) */
    double interval;  /* contour overlay every interval, 0 = none (0) */
    double base;      /* contours at base + k * interval (0) */
} td_render_params;

td_render_params td_render_defaults(void);

/* Shade dem (Horn's 3x3 gradient, the formula gdaldem hillshade uses):
 *
 *     a b c      dz/dx = ((c + 2f + i) - (a + 2d + g)) / (8 cellsize)
 *     d e f      dz/dy = ((g + 2h + i) - (a + 2b + c)) / (8 cellsize)
 *     g h i      shade = cos(zen) cos(slope)
 *                        + sin(zen) sin(slope) cos(az - aspect)
 *
 * with slope = atan(zfactor |grad|).  Nodata neighbours take the centre's height; nodata cells are drawn pale
 * blue-grey.  With interval > 0, cells where the contour band
 * floor((z - base)/interval) changes to the right or below are drawn
 * brown.  *out is a new RGB image of dem's size (td_image_free).  Returns
 * 0, TD_EINVAL (bad parameters), TD_ENOMEM. */
int td_render_hillshade(const td_grid_f32 *dem, const td_render_params *p,
                        td_image **out, td_ctx *cx);

/* The vertical exaggeration zfactor = 0 stands for: the one that draws the
 * 90th percentile of dem's nonzero slopes at 45 degrees (so a DEM in
 * metres on a grid of pixels is not drawn almost black, nor a gentle one
 * almost flat); 1 when the DEM is flat. */
double td_render_auto_zfactor(const td_grid_f32 *dem, double cellsize);

#ifdef __cplusplus
}
#endif
#endif
