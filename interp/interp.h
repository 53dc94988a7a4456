/* interp.h: the front door of interp/: labelled contour lines -> a DEM
 * by one of the methods, in one call.
 *
 *   td_interp_lines: td_rasterise_lines (rasterise.h), then
 *   td_scanline_fill (scanline.h, the paper's x/y passes, 001 §2.4-2.5),
 *   td_multidir_fill (multidir.h, the default) or td_homotopy_fill
 *   (homotopy.h, 003), then td_smooth_bands (smooth.h) when asked,
 *   NaN -> nodata.
 *
 * Cell coordinates: a DEM cell (col,row) covers scan pixels
 * [col*step, (col+1)*step) x [row*step, (row+1)*step). */
#ifndef TD_INTERP_H
#define TD_INTERP_H

#include "interp/homotopy.h"
#include "interp/multidir.h"
#include "interp/rasterise.h"
#include "interp/scanline.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    TD_INTERP_SCANLINE = 0, /* the paper's x then y pass (001 §2.4-2.5) */
    TD_INTERP_MULTIDIR = 1, /* 4 directions blended (the default) */
    TD_INTERP_HOMOTOPY = 2  /* along ridge/valley lines (003), homotopy.h */
} td_interp_method;

struct td_homotopy_stats;

/* Everything td_interp_lines needs: the driver's own settings and each
 * method's parameters (their interval is set by the driver).  Defaults:
 * multidir, step 1, interval 0 (found from the lines), nodata -9999, no
 * smoothing, the methods' own defaults.  The homotopy method takes its
 * summit and peninsula settings from `scanline` (it falls back to it). */
typedef struct td_interp_params {
    td_interp_method method;
    int step;           /* one DEM cell per step x step scan pixels */
    double interval;    /* contour interval, <= 0: td_interp_interval */
    float nodata;       /* written where undeterminable (-9999) */
    int smooth;         /* sweeps of td_smooth_bands afterwards (0) */
    td_scanline_params scanline;
    td_multidir_params multidir;
    td_homotopy_params homotopy;
    struct td_homotopy_stats *hstats; /* homotopy: out, may be NULL */
    size_t *undetermined;             /* out, may be NULL: cells of the DEM left
                                         nodata (counted in the pass that writes it) */
} td_interp_params;

td_interp_params td_interp_defaults(void);

/* Labelled lines on a w x h pixel scan -> a new DEM of ceil(w/step) x
 * ceil(h/step) cells (*out, free with td_grid_f32_free), has_nodata set.
 * Errors as td_rasterise_lines, TD_ENOMEM, TD_ECANCEL. */
int td_interp_lines(const td_lines *ls, int w, int h,
                    const td_interp_params *p, td_grid_f32 **out,
                    td_ctx *cx);

/* As td_interp_lines, and *ls (lines the caller gives up) is freed and
 * set NULL as soon as the method needs them no more: right after they are
 * rasterised for multidir and scanline (4 bytes per cell of the DEM
 * then, not also 16 per line vertex), after the fill for homotopy; on an
 * error it may be freed too.  The same DEM as td_interp_lines. */
int td_interp_lines_take(td_lines **ls, int w, int h,
                         const td_interp_params *p, td_grid_f32 **out,
                         td_ctx *cx);

/* As td_interp_lines, with the lines beyond the sheet's edges beside it
 * (a neighbouring sheet's labelled lines, in this sheet's pixel frame):
 * the grid is interpolated margin px (rounded up to a multiple of step)
 * wider on every side, with the parts of `beside` that reach into that
 * band, and cut back to the sheet, so two neighbours interpolated so meet
 * at their shared edge.  The interval, when not given, is found from ls
 * alone; beside lines without a height are left out.  beside NULL or
 * empty, or margin <= 0: td_interp_lines. */
int td_interp_lines_beside(const td_lines *ls, const td_lines *beside,
                           int margin, int w, int h,
                           const td_interp_params *p, td_grid_f32 **out,
                           td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
