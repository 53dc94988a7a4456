/* thin.h: Hilditch thinning of an ink mask to a 1-pixel-wide skeleton.
 * Paper 001 §2.2 (the paper's ref. 2, Hilditch 1969); ALGORITHMS.md A.2. */
#ifndef TD_THIN_H
#define TD_THIN_H

#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct td_thin_stats {
    int passes;        /* raster passes made, the last one removing nothing */
    size_t removed;    /* pixels removed */
    size_t remaining;  /* skeleton pixels left */
} td_thin_stats;

/* Thin g in place: cells are 0 (paper) or 1 (ink) on entry; on return the 1s
 * are Hilditch's skeleton: 8-connected, 1 pixel wide, end points kept, the
 * number of 8-connected components and of holes (4-connected background
 * components) unchanged.  Cells outside the grid count as paper.  Extra
 * memory: O(h) plus the list of pixels removed in one pass.  st may be NULL.
 * Returns 0, TD_ENOMEM or TD_ECANCEL (progress callback). */
int td_thin_hilditch(td_grid_u8 *g, td_thin_stats *st, td_ctx *cx);

/* Re-thin only around the given pixel indices (y * stride + x) of an
 * already thinned grid, e.g. after spur removal left a corner 2 px thick.
 * Same rules as td_thin_hilditch; only rows within 1 of an index are
 * scanned in the first pass. */
int td_thin_hilditch_near(td_grid_u8 *g, const size_t *idx, size_t n,
                          td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
