/* scanline.h: the paper's scanline interpolation with summit extrapolation
 * (001 §2.4-2.5), `--method scanline`.
 *
 *   x pass: along each row, between consecutive contour cells P1(x1,z1) and
 *   P2(x2,z2) with z1 != z2:  z = z1 + (z2 - z1)(x - x1)/(x2 - x1)
 *
 *        z1=100             z2=110
 *   ......#....*....*....*....#......   row y
 *             filled linearly
 *
 *   y pass: every cell still undetermined looks up and down its column for
 *   the nearest determined cells (contours and x-pass cells); different
 *   heights: linear in y.
 *   summit (§2.5, Fig. 6): a gap along x between two determined cells of
 *   the same height: slopes from the last few determined cells outside P1
 *   and P2; when they both rise (fall) into the gap the two lines meet at
 *   Px between them: each cell takes the lower (higher) line, at most one
 *   interval from z1; otherwise the cell takes z1 (flat, the paper).
 *
 * The paper leaves peninsula-shaped areas (Fig. 5 b) flat.  A peninsula
 * along x or y is already resolved by the pass across its axis; with
 * `peninsula` on (the default) two diagonal passes with the x-pass rule run
 * before the summit step, so peninsulas along a diagonal are interpolated
 * along their axis too.  peninsula = 0 is the paper exactly.  Cells no
 * pass can determine (outside the outermost contours) become nodata. */
#ifndef TD_INTERP_SCANLINE_H
#define TD_INTERP_SCANLINE_H

#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct td_scanline_params {
    double interval; /* contour interval, > 0 (caps the summit) */
    int summit;      /* 1: §2.5 extrapolation (default), 0: flat */
    int slope_cells; /* cells outside P1/P2 for the slope (default 4) */
    int peninsula;   /* 1: diagonal passes (default), 0: paper */
} td_scanline_params;

td_scanline_params td_scanline_defaults(void);

/* Fill g in place: g holds contour heights on line cells and NaN
 * elsewhere (td_rasterise_lines); on return every determinable cell holds
 * a height and the rest NaN (the caller turns NaN into nodata).  Uses one
 * extra float grid.  Returns 0, TD_EINVAL (interval <= 0 with summit on),
 * TD_ENOMEM, TD_ECANCEL. */
int td_scanline_fill(td_grid_f32 *g, const td_scanline_params *p,
                     td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
