/* blobring.c: tiny summit rings from dots of ink (contract in blobring.h). */
#include "scanner/blobring.h"
#include "scanner/width.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define WIN 31 /* the dot's window, px */

/* The dot under (cx0, cy0): its area and centroid, by a flood fill within
 * the window around it; 0 when there is no ink there or the ink reaches
 * the window's edge (no dot: part of something bigger). */
static int dot(const uint8_t *bits, int w, int h, int cx0, int cy0,
               double *area, double *mx, double *my)
{
    unsigned char seen[WIN * WIN];
    int stack[2 * WIN * WIN], top = 0, x0 = cx0 - WIN / 2, y0 = cy0 - WIN / 2;
    long n = 0;
    double sx = 0, sy = 0;
    memset(seen, 0, sizeof seen);
    if (!td_packed_at(bits, w, h, cx0, cy0))
        return 0;
    seen[(cy0 - y0) * WIN + (cx0 - x0)] = 1;
    stack[top++] = cx0, stack[top++] = cy0;
    while (top) {
        int y = stack[--top], x = stack[--top], dx, dy;
        n++, sx += x, sy += y;
        if (x == x0 || y == y0 || x == x0 + WIN - 1 || y == y0 + WIN - 1)
            return 0;
        for (dy = -1; dy <= 1; dy++)
            for (dx = -1; dx <= 1; dx++) {
                int nx = x + dx, ny = y + dy;
                unsigned char *s = &seen[(ny - y0) * WIN + (nx - x0)];
                if (*s || !td_packed_at(bits, w, h, nx, ny))
                    continue;
                *s = 1;
                stack[top++] = nx, stack[top++] = ny;
            }
    }
    *area = (double)n;
    *mx = sx / n + 0.5; /* pixel centres */
    *my = sy / n + 0.5;
    return 1;
}

long td_blob_rings(const uint8_t *bits, int w, int h, td_lines *ls,
                   td_ctx *cx)
{
    double pen = td_pen_width(ls, cx);
    long done = 0;
    size_t i, k;
    if (pen < 0)
        return TD_ENOMEM;
    if (pen == 0)
        return 0;
    for (i = 0; i < ls->n; i++) {
        td_line *l = &ls->v[i];
        double b[4], a, mx, my, r;
        int n;
        if (!l->closed || l->edge || l->n < 1 || l->n > 9)
            continue;
        td_line_box(l, b);
        if (b[2] - b[0] > 2.01 || b[3] - b[1] > 2.01 ||
            !dot(bits, w, h, (int)floor(0.5 * (b[0] + b[2])),
                 (int)floor(0.5 * (b[1] + b[3])), &a, &mx, &my))
            continue;
        r = sqrt(a / 3.14159265358979) - 0.5 * pen;
        if (r < 1.5)
            continue;
        n = (int)ceil(2 * 3.14159265358979 * r);
        n = n < 8 ? 8 : n;
        l->n = 0;
        for (k = 0; k < (size_t)n; k++) {
            double t = 2 * 3.14159265358979 * (double)k / n;
            if (td_line_push(l, mx + r * cos(t), my - r * sin(t), cx) != 0)
                return TD_ENOMEM;
        }
        done++;
    }
    return done;
}

/* all n points of l on one spot */
static int one_spot(const td_line *l)
{
    size_t k;
    for (k = 1; k < l->n; k++)
        if (l->xy[2 * k] != l->xy[0] || l->xy[2 * k + 1] != l->xy[1])
            return 0;
    return l->n > 0;
}

long td_point_rings(td_lines *ls, td_ctx *cx)
{
    static const double d[4][2] = {{1, 0}, {0, -1}, {-1, 0}, {0, 1}};
    long done = 0;
    size_t i, k;
    for (i = 0; i < ls->n; i++) {
        td_line *l = &ls->v[i];
        double x, y;
        if (!l->closed || !one_spot(l))
            continue;
        x = l->xy[0], y = l->xy[1];
        l->n = 0;
        for (k = 0; k < 4; k++)
            if (td_line_push(l, x + TD_POINT_RING_R * d[k][0],
                             y + TD_POINT_RING_R * d[k][1], cx) != 0)
                return TD_ENOMEM;
        done++;
    }
    return done;
}
