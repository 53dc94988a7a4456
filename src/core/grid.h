/* grid.h: the raster types every stage shares.
 *
 * Row-major, row 0 = top row of the scan, x = column to the right, y = row
 * downwards.  `stride` is the distance between rows in elements (not bytes);
 * grids made by td_grid_*_new have stride == w.  The structs are plain: read
 * and write `data` directly.  Sizes are checked against TD_MAX_DIM and
 * TD_MAX_PIXELS before anything is allocated. */
#ifndef TD_GRID_H
#define TD_GRID_H

#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct td_grid_u8 {
    int w, h;
    size_t stride;
    uint8_t *data;
} td_grid_u8;

typedef struct td_grid_u16 {
    int w, h;
    size_t stride;
    uint16_t *data;
} td_grid_u16;

typedef struct td_grid_f32 {
    int w, h;
    size_t stride;
    float *data;
    float nodata;    /* value marking cells without data */
    int has_nodata;  /* nonzero when nodata is meaningful */
} td_grid_f32;

/* An 8-bit image of 1 (grey) or 3 (RGB, interleaved) channels, as read from
 * a scan.  stride is in bytes (>= w * channels).  src_bits records the
 * sample depth of the file it came from (1, 8 or 16) for messages. */
typedef struct td_image {
    int w, h, channels;
    size_t stride;
    uint8_t *data;
    int src_bits;
} td_image;

/* Allocate a zero-filled grid of w x h.  Returns NULL (error in cx) when the
 * size is invalid or memory runs out.  Free with the matching _free, which
 * accepts NULL. */
td_grid_u8 *td_grid_u8_new(int w, int h, td_ctx *cx);
td_grid_u16 *td_grid_u16_new(int w, int h, td_ctx *cx);
td_grid_f32 *td_grid_f32_new(int w, int h, td_ctx *cx);
void td_grid_u8_free(td_grid_u8 *g);
void td_grid_u16_free(td_grid_u16 *g);
void td_grid_f32_free(td_grid_f32 *g);

/* A deep copy of g, or NULL with the error in cx. */
td_grid_u8 *td_grid_u8_dup(const td_grid_u8 *g, td_ctx *cx);

/* Allocate a zero-filled image (channels 1 or 3). */
td_image *td_image_new(int w, int h, int channels, td_ctx *cx);
void td_image_free(td_image *im);

#define TD_AT(g, x, y) ((g)->data[(size_t)(y) * (g)->stride + (size_t)(x)])

#ifdef __cplusplus
}
#endif
#endif
