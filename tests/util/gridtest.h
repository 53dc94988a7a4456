/* gridtest.h: small helpers for tests on binary grids: hand-drawn patterns
 * and topology counts (components, holes). */
#ifndef TD_GRIDTEST_H
#define TD_GRIDTEST_H

#include "src/core/core.h"

/* Grid from ASCII rows ('#' = 1, anything else 0), NULL-terminated. */
td_grid_u8 *tg_from_ascii(const char *const *rows);
/* Shapes drawn with value 1. */
void tg_disk(td_grid_u8 *g, double cx, double cy, double r);
void tg_ring(td_grid_u8 *g, double cx, double cy, double rin, double rout);
void tg_thick_segment(td_grid_u8 *g, double x0, double y0, double x1,
                      double y1, double width);
/* 8-connected components of nonzero cells. */
size_t tg_components8(const td_grid_u8 *g);
/* Holes: 4-connected components of zero cells not connected to the outside. */
size_t tg_holes4(const td_grid_u8 *g);
/* Number of 2x2 blocks entirely ink (0 for a 1-px-wide skeleton). */
size_t tg_blocks2x2(const td_grid_u8 *g);
size_t tg_count(const td_grid_u8 *g);
/* Print a grid as ASCII to stderr (for failing tests). */
void tg_dump(const td_grid_u8 *g);

#endif
