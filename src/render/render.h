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

/* The height colour ramp of the tint (green - yellow - brown - white),
 * t in [0, 1] (clamped), rgb in [0, 1]. */
void td_render_ramp(double t, double rgb[3]);

/* ---- perspective views (view.c; paper 001 §2.6) ---- */

typedef enum {
    TD_VIEW_SHADED = 0, /* flat-shaded patches */
    TD_VIEW_WIRE = 1,   /* the patches' edges, hidden lines removed */
    TD_VIEW_BOTH = 2    /* shaded, edges drawn over */
} td_view_style;

typedef enum {
    TD_DRAPE_HILLSHADE = 0, /* grey, by the light alone */
    TD_DRAPE_TINT = 1,      /* the height ramp, shaded */
    TD_DRAPE_IMAGE = 2      /* an image over the DEM (the scan), shaded */
} td_view_drape;

#define TD_VIEW_MAX_LIGHTS 4

typedef struct td_view_params {
    td_view_style style;   /* (TD_VIEW_SHADED) */
    td_view_drape drape;   /* (TD_DRAPE_HILLSHADE) */
    double azimuth;        /* where the camera stands, seen from the DEM's
                              centre: degrees clockwise from north (200) */
    double elevation;      /* camera above the horizon, degrees (35) */
    double fov;            /* horizontal field of view, degrees (40) */
    double distance;       /* camera to the centre in cells; 0: auto, the
                              whole model in the picture (0) */
    double exaggeration;   /* vertical: heights x this / cellsize; 0: auto,
                              the relief 15-50 % of the longest side (0) */
    double cellsize;       /* cell size in height units (1) */
    int patch;             /* N x N cells per quad patch (3, the paper's) */
    int nlights;           /* lights at infinity (1) */
    double light[TD_VIEW_MAX_LIGHTS][2]; /* azimuth, altitude (315, 45) */
    double ambient;        /* light everywhere, 0..1 (0.2) */
    int zbuffer;           /* 0: the paper's order (farthest patch first);
                              1: a depth buffer per pixel (ours) (0) */
} td_view_params;

/* The camera a view is drawn with (td_view_camera_of). */
typedef struct td_view_camera {
    double c[3], r[3], u[3], f[3]; /* position; right, up, forward */
    double focal, cx, cy;          /* pixels; the picture's centre */
    double zmin, zscale;           /* world z = (height - zmin) x zscale */
    double ztop;                   /* world z of the highest point */
} td_view_camera;

td_view_params td_view_defaults(void);

/* The camera for dem in a w x h picture under p (world: x = column + 0.5
 * east, y = -(row + 0.5) north, z up, in cells).  0, TD_EINVAL (bad
 * parameters, no data). */
int td_view_camera_of(const td_grid_f32 *dem, const td_view_params *p,
                      int w, int h, td_view_camera *cam, td_ctx *cx);

/* Picture coordinates (x right, y down; pixel centres at + 0.5) of the
 * point at (column, row) (cell units; a cell's centre is col + 0.5) and
 * height z.  0 when it lies behind the camera. */
int td_view_project(const td_view_camera *cam, double col, double row,
                    double z, double *px, double *py);

/* Draw dem in perspective into out (RGB, its size the picture's) by the
 * paper's method (001 §2.6): quad patches of p->patch cells, each with the
 * mean of its corners' heights; painted from the farthest to the nearest
 * (the order of their centres' depth), each flat-shaded by Lambert's law
 * with its normal from its centre to two corners.  Patches at the edge of
 * the data: with 2 or more corners inside, the others take the mean of
 * those (the paper: the border contour's height); fewer, left out.
 * drape: the image for TD_DRAPE_IMAGE (any size; stretched over the
 * DEM), else NULL.  With p->zbuffer the patches are drawn in any order
 * and each pixel keeps the nearest (depth interpolated as 1/z across each
 * triangle), edges tested against it.  0, TD_EINVAL, TD_ENOMEM. */
int td_view_render(const td_grid_f32 *dem, const td_image *drape,
                   const td_view_params *p, td_image *out, td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
