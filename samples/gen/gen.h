/* gen.h: synthetic contour sheets with a known truth.
 *
 * An analytic terrain -> its true contour polylines (marching squares at
 * pixel centres, same coordinate frame as the tracer: x = col + 0.5) ->
 * a rendered "scan" with line width, blur, noise, specks, breaks and colour.
 * Used by tests/, tests/bench/, samples/ and the tdgen tool. */
#ifndef TD_GEN_H
#define TD_GEN_H

#include "../../src/grid.h"
#include "../../src/lines.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    TD_GEN_HILLS,   /* several summits, a saddle, a depression, a tilt so
                       some contours leave the sheet (the default) */
    TD_GEN_CONE,    /* one cone in the centre: concentric closed rings */
    TD_GEN_PLANE,   /* tilted plane: parallel open lines, all edge */
    TD_GEN_RIDGES   /* many contours, dense (for benchmarks) */
} td_gen_terrain_kind;

typedef struct td_gen_params {
    int w, h;              /* sheet size in pixels */
    unsigned seed;         /* every random choice follows from it */
    td_gen_terrain_kind terrain;
    double base, interval; /* contour levels base + k * interval */
    double line_width;     /* ink line width in px (1..6) */
    double blur;           /* Gaussian blur sigma in px, 0 = none */
    double noise;          /* Gaussian noise sd in grey levels, 0 = none */
    int specks;            /* number of random ink specks (1-6 px blobs) */
    int breaks;            /* number of breaks cut into the lines */
    double break_min, break_max; /* break length range in px */
    int colour;            /* 0: black on white grey image; 1: brown ink on
                              cream paper RGB, with blue and black distractors
                              if distractors != 0 */
    int distractors;
} td_gen_params;

td_gen_params td_gen_defaults(void);

/* The truth surface sampled at pixel centres (w x h), heights in metres. */
int td_gen_terrain(const td_gen_params *p, td_grid_f32 **dem, td_ctx *cx);

/* True contours of dem at base + k*interval: one td_line per connected
 * contour, with height, closed (ring) or edge (ends on the grid border).
 * Caller frees with td_lines_free. */
int td_gen_contours(const td_grid_f32 *dem, double base, double interval,
                    td_lines **out, td_ctx *cx);

/* Render lines as a scanned sheet per p (size p->w x p->h). */
int td_gen_render(const td_lines *lines, const td_gen_params *p,
                  td_image **sheet, td_ctx *cx);

/* All three in one: sheet, truth lines and the truth DEM (any out pointer
 * may be NULL when not wanted). */
int td_gen_sheet(const td_gen_params *p, td_image **sheet, td_lines **truth,
                 td_grid_f32 **dem, td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
