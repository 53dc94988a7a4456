#include "src/core/core.h"

#include <stdlib.h>
#include <string.h>

/* One allocator for all typed grids: the struct and its pixels in two
 * blocks so `data` can be handed over or replaced by the caller. */
static void *grid_new(int w, int h, size_t elem, size_t struct_size,
                      void **data, td_ctx *cx)
{
    size_t n;
    void *g;
    if (td_check_dims(w, h, "grid", cx) != 0)
        return NULL;
    if (td_mul3((size_t)w, (size_t)h, elem, &n) != 0) {
        td_seterr(cx, TD_ETOOBIG, "grid: %d x %d overflows", w, h);
        return NULL;
    }
    g = td_calloc(1, struct_size, cx);
    if (!g)
        return NULL;
    *data = td_calloc(n, 1, cx);
    if (!*data) {
        free(g);
        return NULL;
    }
    return g;
}

#define GRID_NEW(T, ET)                                                      \
    T *g;                                                                    \
    void *data = NULL;                                                       \
    g = grid_new(w, h, sizeof(ET), sizeof(T), &data, cx);                    \
    if (!g)                                                                  \
        return NULL;                                                         \
    g->w = w;                                                                \
    g->h = h;                                                                \
    g->stride = (size_t)w;                                                   \
    g->data = data;                                                          \
    return g

td_grid_u8 *td_grid_u8_new(int w, int h, td_ctx *cx) { GRID_NEW(td_grid_u8, uint8_t); }
td_grid_u16 *td_grid_u16_new(int w, int h, td_ctx *cx) { GRID_NEW(td_grid_u16, uint16_t); }
td_grid_f32 *td_grid_f32_new(int w, int h, td_ctx *cx) { GRID_NEW(td_grid_f32, float); }

void td_grid_u8_free(td_grid_u8 *g)
{
    if (g) {
        free(g->data);
        free(g);
    }
}

void td_grid_u16_free(td_grid_u16 *g)
{
    if (g) {
        free(g->data);
        free(g);
    }
}

void td_grid_f32_free(td_grid_f32 *g)
{
    if (g) {
        free(g->data);
        free(g);
    }
}

td_grid_u8 *td_grid_u8_dup(const td_grid_u8 *g, td_ctx *cx)
{
    td_grid_u8 *d = td_grid_u8_new(g->w, g->h, cx);
    int y;
    if (!d)
        return NULL;
    for (y = 0; y < g->h; y++)
        memcpy(d->data + (size_t)y * d->stride, g->data + (size_t)y * g->stride,
               (size_t)g->w);
    return d;
}

td_image *td_image_new(int w, int h, int channels, td_ctx *cx)
{
    td_image *im;
    size_t n;
    if (channels != 1 && channels != 3) {
        td_seterr(cx, TD_EINVAL, "image: %d channels (1 or 3 supported)",
                  channels);
        return NULL;
    }
    if (td_check_dims(w, h, "image", cx) != 0)
        return NULL;
    if (td_mul3((size_t)w, (size_t)h, (size_t)channels, &n) != 0) {
        td_seterr(cx, TD_ETOOBIG, "image: %d x %d overflows", w, h);
        return NULL;
    }
    im = td_calloc(1, sizeof *im, cx);
    if (!im)
        return NULL;
    im->data = td_calloc(n, 1, cx);
    if (!im->data) {
        free(im);
        return NULL;
    }
    im->w = w;
    im->h = h;
    im->channels = channels;
    im->stride = (size_t)w * (size_t)channels;
    im->src_bits = 8;
    return im;
}

void td_image_free(td_image *im)
{
    if (im) {
        free(im->data);
        free(im);
    }
}
