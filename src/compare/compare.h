/* compare.h: differences between two DEMs of the same size (a result and a
 * reference), a colour picture of them, and a cross-section of both along
 * a line (profile.c).  Pure stages: no file I/O. */
#ifndef TD_COMPARE_H
#define TD_COMPARE_H

#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct td_compare_stats {
    size_t n_a, n_b;   /* cells with data in a, in b */
    size_t n_both;     /* cells with data in both: the statistics' cells */
    double coverage;   /* n_both / n_b: how much of the reference a covers */
    double rmse, mae, bias; /* of d = a - b over n_both cells */
    double max_abs;    /* largest |d| and where (column, row) */
    int max_x, max_y;
    double min_b, max_b; /* range of b (for relative figures) */
} td_compare_stats;

/* Compare a with b cell by cell (d = a - b).  A cell has data when it is
 * finite and not the grid's nodata (when has_nodata).  Statistics over the
 * cells with data in both; all zero (max_x = max_y = -1) when there are
 * none.  Returns 0, or TD_EINVAL when the sizes differ (message gives
 * both). */
int td_compare_grids(const td_grid_f32 *a, const td_grid_f32 *b,
                     td_compare_stats *st, td_ctx *cx);

/* The difference picture: blue (a below b) - white (equal) - red (a
 * above b), saturating at |d| = range (range <= 0: 3 x the RMSE of st, at
 * least 1e-6); cells without data in a or b grey (a only: light grey, b
 * only: dark grey, neither: black).  *out is a new RGB image of the grids'
 * size (free with td_image_free).  Returns 0, TD_EINVAL (sizes), TD_ENOMEM. */
int td_compare_diff_image(const td_grid_f32 *a, const td_grid_f32 *b,
                          double range, td_image **out, td_ctx *cx);

/* ---- profile.c: a cross-section of both along one line ---- */

/* n samples (bilinear, NaN without data) of a and b along the line from
 * (x0,y0) to (x1,y1) in cells (0,0 the top-left corner), ends included,
 * into va and vb.  0, or TD_EINVAL (sizes differ, n < 2). */
int td_compare_profile(const td_grid_f32 *a, const td_grid_f32 *b,
                       double x0, double y0, double x1, double y1, size_t n,
                       double *va, double *vb, td_ctx *cx);
/* The cross-section plot, w x h RGB: b (the reference) in black, a in
 * red on top, heights and distances (length: the line's length in map
 * units, 0: none) on round ticks.  *out new; 0, TD_EINVAL (no data, too
 * small), TD_ENOMEM. */
int td_compare_profile_image(const double *va, const double *vb, size_t n,
                             double length, int w, int h, td_image **out,
                             td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
