#include "tests/util/gridtest.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

td_grid_u8 *tg_from_ascii(const char *const *rows)
{
    int h = 0, w = 0, x, y;
    td_grid_u8 *g;
    while (rows[h]) {
        if ((int)strlen(rows[h]) > w)
            w = (int)strlen(rows[h]);
        h++;
    }
    g = td_grid_u8_new(w, h, NULL);
    for (y = 0; g && y < h; y++)
        for (x = 0; rows[y][x]; x++)
            TD_AT(g, x, y) = rows[y][x] == '#';
    return g;
}

void tg_disk(td_grid_u8 *g, double cx, double cy, double r)
{
    tg_ring(g, cx, cy, -1.0, r);
}

void tg_ring(td_grid_u8 *g, double cx, double cy, double rin, double rout)
{
    int x, y;
    for (y = 0; y < g->h; y++)
        for (x = 0; x < g->w; x++) {
            double d = hypot(x + 0.5 - cx, y + 0.5 - cy);
            if (d <= rout && d > rin)
                TD_AT(g, x, y) = 1;
        }
}

void tg_thick_segment(td_grid_u8 *g, double x0, double y0, double x1,
                      double y1, double width)
{
    int x, y;
    double dx = x1 - x0, dy = y1 - y0, l2 = dx * dx + dy * dy;
    for (y = 0; y < g->h; y++)
        for (x = 0; x < g->w; x++) {
            double px = x + 0.5, py = y + 0.5, t = 0.0, d;
            if (l2 > 0)
                t = ((px - x0) * dx + (py - y0) * dy) / l2;
            t = t < 0 ? 0 : t > 1 ? 1 : t;
            d = hypot(px - (x0 + t * dx), py - (y0 + t * dy));
            if (d <= width / 2)
                TD_AT(g, x, y) = 1;
        }
}

/* Flood fill over cells equal to `val` with connectivity 4 or 8 on a
 * padded label array; returns the number of components. */
static size_t count_comp(const td_grid_u8 *g, int val, int conn, int pad,
                         size_t *touching_border)
{
    int W = g->w + 2 * pad, H = g->h + 2 * pad, x, y;
    int *lab = calloc((size_t)W * H, sizeof *lab);
    int *stack = malloc((size_t)W * H * sizeof *stack);
    size_t n = 0, border = 0;
    for (y = 0; y < H; y++)
        for (x = 0; x < W; x++) {
            int gx = x - pad, gy = y - pad, sp = 0, touches = 0;
            int v = (gx < 0 || gy < 0 || gx >= g->w || gy >= g->h)
                        ? 0 : (TD_AT(g, gx, gy) != 0);
            if (v != val || lab[y * W + x])
                continue;
            n++;
            lab[y * W + x] = 1;
            stack[sp++] = y * W + x;
            while (sp) {
                int c = stack[--sp], cx = c % W, cy = c / W, dx, dy;
                if (cx == 0 || cy == 0 || cx == W - 1 || cy == H - 1)
                    touches = 1;
                for (dy = -1; dy <= 1; dy++)
                    for (dx = -1; dx <= 1; dx++) {
                        int nx = cx + dx, ny = cy + dy, ngx, ngy, nv;
                        if ((!dx && !dy) || (conn == 4 && dx && dy))
                            continue;
                        if (nx < 0 || ny < 0 || nx >= W || ny >= H ||
                            lab[ny * W + nx])
                            continue;
                        ngx = nx - pad;
                        ngy = ny - pad;
                        nv = (ngx < 0 || ngy < 0 || ngx >= g->w || ngy >= g->h)
                                 ? 0 : (TD_AT(g, ngx, ngy) != 0);
                        if (nv != val)
                            continue;
                        lab[ny * W + nx] = 1;
                        stack[sp++] = ny * W + nx;
                    }
            }
            border += touches;
        }
    free(lab);
    free(stack);
    if (touching_border)
        *touching_border = border;
    return n;
}

size_t tg_components8(const td_grid_u8 *g)
{
    return count_comp(g, 1, 8, 0, NULL);
}

size_t tg_holes4(const td_grid_u8 *g)
{
    size_t border = 0, n = count_comp(g, 0, 4, 1, &border);
    return n - border;
}

size_t tg_blocks2x2(const td_grid_u8 *g)
{
    size_t n = 0;
    int x, y;
    for (y = 0; y + 1 < g->h; y++)
        for (x = 0; x + 1 < g->w; x++)
            n += TD_AT(g, x, y) && TD_AT(g, x + 1, y) && TD_AT(g, x, y + 1) &&
                 TD_AT(g, x + 1, y + 1);
    return n;
}

size_t tg_count(const td_grid_u8 *g)
{
    size_t n = 0;
    int x, y;
    for (y = 0; y < g->h; y++)
        for (x = 0; x < g->w; x++)
            n += TD_AT(g, x, y) != 0;
    return n;
}

void tg_dump(const td_grid_u8 *g)
{
    int x, y;
    for (y = 0; y < g->h; y++) {
        for (x = 0; x < g->w; x++)
            fputc(TD_AT(g, x, y) ? '#' : '.', stderr);
        fputc('\n', stderr);
    }
}
