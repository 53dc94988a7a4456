/* multidir_int.h: internals shared by the files of the multidir method. */
#ifndef TD_INTERP_MULTIDIR_INT_H
#define TD_INTERP_MULTIDIR_INT_H

#include "interp/multidir.h"

/* The weight of an estimate d1 from one end of its span and d2 from the
 * other: 1 / (d1 + d2) (span), its square (span2), 1 / (d1 d2) (prod). */
double td_multidir_cell_weight(td_multidir_weight m, double d1, double d2);

/* The span weight of td_multidir_weight m for the cells of a span of n
 * steps of length sl, where it does not depend on the cell (span, span2;
 * prod does): w(sl, (n - 1) sl) as a float. */
float td_multidir_span_weight(td_multidir_weight m, int n, double sl);

/* Phase 1 of td_multidir_fill for the span and span2 weights, streamed in
 * one pass down the rows: every NaN cell of g that some scan line crosses
 * between two line cells of different height gets the blend of those
 * lines' linear estimates, bit for bit what walking each direction with
 * td_interp_walk and blending would give.  Line cells (non-NaN in g) are
 * the anchors.  Rows in 16 bands on threads (from 1024 rows), each band
 * entering with the spans the rows above left open, stepped as one pass
 * steps them: the same bytes on any thread count.  Extra memory: 16 bytes
 * per line cell, about 200 (w + h) bytes besides.
 * Returns 0, TD_ENOMEM or TD_ECANCEL (g then partly filled). */
int td_multidir_sweep(td_grid_f32 *g, const td_multidir_params *p,
                      const char *stage, td_ctx *cx);

/* Phase 2 of td_multidir_fill (the summit phase) streamed down the rows
 * (multidir_summit.c): every NaN cell of g between two determined cells
 * along a direction gets the blend of the linear or tent estimates, bit
 * for bit what walking each direction over the NaN runs would give.
 * On two threads (x and y, the diagonals), the same bytes on any thread
 * count.  Extra memory: 4 bytes per run start along each crossing
 * direction, about 200 (w + h) bytes and 4 (slope_cells + 8) w bytes
 * besides.
 * Returns 0, TD_ENOMEM or TD_ECANCEL (g then partly filled). */
int td_multidir_summit(td_grid_f32 *g, const td_multidir_params *p,
                       const char *stage, td_ctx *cx);

#endif
