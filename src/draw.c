#include "draw.h"

#include <math.h>
#include <stdlib.h>

void td_draw_colour(size_t i, uint8_t rgb[3])
{
    double h = fmod(0.13 + 0.618033988749895 * (double)i, 1.0) * 6.0;
    double f = h - floor(h), v = 0.85, s = 0.9;
    double p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
    double r, g, b;
    switch ((int)h) {
    case 0: r = v; g = t; b = p; break;
    case 1: r = q; g = v; b = p; break;
    case 2: r = p; g = v; b = t; break;
    case 3: r = p; g = q; b = v; break;
    case 4: r = t; g = p; b = v; break;
    default: r = v; g = p; b = q; break;
    }
    rgb[0] = (uint8_t)(r * 255);
    rgb[1] = (uint8_t)(g * 255);
    rgb[2] = (uint8_t)(b * 255);
}

static void put(td_image *im, long x, long y, const uint8_t rgb[3])
{
    uint8_t *p;
    if (x < 0 || y < 0 || x >= im->w || y >= im->h)
        return;
    p = im->data + (size_t)y * im->stride + (size_t)x * 3;
    p[0] = rgb[0];
    p[1] = rgb[1];
    p[2] = rgb[2];
}

/* Bresenham between pixel centres (x,y in pixel units, centre at +0.5). */
static void segment(td_image *im, double x0, double y0, double x1, double y1,
                    const uint8_t rgb[3])
{
    long ax = (long)floor(x0), ay = (long)floor(y0);
    long bx = (long)floor(x1), by = (long)floor(y1);
    long dx = labs(bx - ax), dy = -labs(by - ay);
    long sx = ax < bx ? 1 : -1, sy = ay < by ? 1 : -1, err = dx + dy;
    for (;;) {
        long e2;
        put(im, ax, ay, rgb);
        if (ax == bx && ay == by)
            break;
        e2 = 2 * err;
        if (e2 >= dy) {
            err += dy;
            ax += sx;
        }
        if (e2 <= dx) {
            err += dx;
            ay += sy;
        }
    }
}

void td_draw_line(td_image *im, const td_line *l, const uint8_t rgb[3])
{
    size_t i;
    if (l->n == 1)
        put(im, (long)l->xy[0], (long)l->xy[1], rgb);
    for (i = 1; i < l->n; i++)
        segment(im, l->xy[2 * i - 2], l->xy[2 * i - 1], l->xy[2 * i],
                l->xy[2 * i + 1], rgb);
    if (l->closed && l->n > 2)
        segment(im, l->xy[2 * l->n - 2], l->xy[2 * l->n - 1], l->xy[0],
                l->xy[1], rgb);
}

/* A red 3x3 box around an open end that is not on the sheet border. */
static void mark_end(td_image *im, double x, double y)
{
    static const uint8_t red[3] = {230, 0, 0};
    long cx = (long)floor(x), cy = (long)floor(y), dx, dy;
    if (cx <= 0 || cy <= 0 || cx >= im->w - 1 || cy >= im->h - 1)
        return;
    for (dy = -1; dy <= 1; dy++)
        for (dx = -1; dx <= 1; dx++)
            if (dx || dy)
                put(im, cx + dx, cy + dy, red);
}

int td_draw_overlay(const td_image *scan, const td_lines *ls, td_image **out,
                    td_ctx *cx)
{
    td_image *im = td_image_new(scan->w, scan->h, 3, cx);
    int x, y, c;
    size_t i;
    *out = NULL;
    if (!im)
        return cx ? cx->code : TD_ENOMEM;
    for (y = 0; y < scan->h; y++) {
        const uint8_t *s = scan->data + (size_t)y * scan->stride;
        uint8_t *d = im->data + (size_t)y * im->stride;
        for (x = 0; x < scan->w; x++)
            for (c = 0; c < 3; c++) {
                int v = s[scan->channels == 3 ? 3 * x + c : x];
                d[3 * x + c] = (uint8_t)(255 - (255 - v) * 2 / 5);
            }
    }
    for (i = 0; i < ls->n; i++) {
        uint8_t rgb[3];
        td_draw_colour(i, rgb);
        td_draw_line(im, &ls->v[i], rgb);
    }
    for (i = 0; i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        if (l->closed || l->n == 0)
            continue;
        mark_end(im, l->xy[0], l->xy[1]);
        mark_end(im, l->xy[2 * l->n - 2], l->xy[2 * l->n - 1]);
    }
    *out = im;
    return 0;
}
