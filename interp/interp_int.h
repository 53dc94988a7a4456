/* interp_int.h: row scanning helpers shared by the interpolation files.
 * Rows are float, NaN = undetermined.  The searches test the first cell,
 * then count the NaNs of 32 cells at a time (a loop compilers vectorise;
 * with 16 they unroll it instead), then find the cell one by one. */
#ifndef TD_INTERP_INT_H
#define TD_INTERP_INT_H

#include "interp/rasterise.h"

enum { TD_FIND_BLOCK = 32 };

/* How many of the TD_FIND_BLOCK floats at row are NaN. */
static inline int td_nan_block(const float *row)
{
    int k, n = 0;
    for (k = 0; k < TD_FIND_BLOCK; k++)
        n += row[k] != row[k];
    return n;
}

/* First column >= c of row[0..w) that is NaN (nan = 1) or not NaN
 * (nan = 0); w when there is none. */
static inline int td_row_find(const float *row, int c, int w, int nan)
{
    if (c < w && (row[c] != row[c]) == nan) /* dense: found at once */
        return c;
    for (; c + TD_FIND_BLOCK <= w; c += TD_FIND_BLOCK) {
        int n = td_nan_block(row + c);
        if (nan ? n > 0 : n < TD_FIND_BLOCK)
            break;
    }
    for (; c < w; c++)
        if ((row[c] != row[c]) == nan)
            return c;
    return w;
}

/* The runs of undetermined (NaN) cells of a grid, row by row: row r's
 * runs are run[off[r]] .. run[off[r+1] - 1], each columns [c0, c1). */
typedef struct td_nan_runs {
    size_t *off;   /* h + 1 entries */
    int (*run)[2];
    size_t n, cap; /* runs, allocated */
} td_nan_runs;

/* Find the NaN runs of g into *nr (zeroed by the caller; free with
 * td_nan_runs_free, also after an error).  Returns 0 or TD_ENOMEM. */
int td_nan_runs_find(const td_grid_f32 *g, td_nan_runs *nr, td_ctx *cx);
void td_nan_runs_free(td_nan_runs *nr);

#endif
