/* flow_int.h: what src/flow/flow.c, src/flow/flow_fill.c (the tiled priority-flood
 * fill under D8 and D-infinity) and src/flow/flow_d8.c (D8 counts) share.  Not
 * public. */
#ifndef TD_FLOW_INT_H
#define TD_FLOW_INT_H

#include "src/core/core.h"

#include <stdint.h>

/* Code byte values shared by both files (flow.c adds its own above 9). */
enum { TD_FL_ROOT = 8, TD_FL_NODATA = 9 };

/* Default tile side of the fill (256: with the ranked queue, as fast as
 * 512 and 2-6 MB smaller on two threads). */
#define TD_PFLOOD_TILE 256

/* Priority-flood depression filling of the w x h heights dem into z (not
 * the same buffer), in square tiles of side `tile` (0: TD_PFLOOD_TILE;
 * any size >= 2 gives the same result).  On entry code[i] == TD_FL_NODATA
 * marks nodata cells, any other value a valid cell.  On return z holds,
 * for every valid cell, the lowest level at which water can leave the
 * grid from it (nodata cells: their dem value); code holds TD_FL_NODATA,
 * TD_FL_ROOT for the outlets (valid cells on the grid edge or next to
 * nodata) and 0 for the rest.  *raised (may be NULL) gets the number of
 * cells raised.  Tiles are flooded on `threads` OpenMP threads (0: the
 * OpenMP default); the result does not depend on it.  Progress as stage
 * "flow" from p0 to p1.  Memory: 2 bytes
 * per cell of labels (freed on return) plus the label graph (a few labels
 * per tile side) and each thread's tile-sized queues.  0, TD_ENOMEM, TD_ECANCEL, TD_EINVAL (more than
 * 2^32 - 2 cells). */
int td_flow_fill_tiles(const float *dem, float *z, uint8_t *code, int w, int h,
              int tile, int threads, double *raised, double p0, double p1,
              td_ctx *cx);

/* D8 counts (src/flow/flow_d8.c): code holds each valid cell's direction k
 * (0..7: E, SE, S, SW, W, NW, N, NE), TD_FL_ROOT for outlets, TD_FL_NODATA;
 * acc (w * h) gets each cell's count (0 on nodata).  code is overwritten.
 * On `threads` row bands (the result does not depend on it).  *outflow,
 * *outlets, *done: rain that left, outlets, cells counted.  Memory: 1 byte
 * per cell (in-degrees).  0 or TD_ENOMEM. */
int td_d8_accumulate(uint8_t *code, uint32_t *acc, int w, int h,
                     int threads, double *outflow, double *outlets,
                     double *done, td_ctx *cx);

#endif
