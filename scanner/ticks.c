/* ticks.c: see ticks.h. */
#include "scanner/ticks.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define CELL 8     /* px: the bucket grid of the closed lines' vertices */
#define NEAR 2.0   /* a spur's junction within this of the line */
#define MIN_TIP 1.5
#define MAX_TIP 10.0

typedef struct vref {
    uint32_t line, k;
} vref;

long td_ticks_mark(td_lines *ls, const td_spur_rec *rec, size_t n,
                   int min_in, td_ctx *cx)
{
    size_t i, k, nv = 0, *start = NULL, *cnt = NULL;
    vref *v = NULL;
    long gw = 0, gh = 0, marked = 0;
    double maxx = 0, maxy = 0;
    for (i = 0; i < ls->n; i++)
        if (ls->v[i].closed)
            for (k = 0; k < ls->v[i].n; k++) {
                maxx = fmax(maxx, ls->v[i].xy[2 * k]);
                maxy = fmax(maxy, ls->v[i].xy[2 * k + 1]);
                nv++;
            }
    if (nv == 0 || n == 0)
        return 0;
    gw = (long)(maxx / CELL) + 2;
    gh = (long)(maxy / CELL) + 2;
    if (!(start = td_calloc((size_t)(gw * gh) + 1, sizeof *start, cx)) ||
        !(v = td_malloc(nv * sizeof *v, cx)) ||
        !(cnt = td_calloc(2 * ls->n + 1, sizeof *cnt, cx))) {
        marked = TD_ENOMEM;
        goto done;
    }
    /* counting sort of the vertices by cell */
    for (i = 0; i < ls->n; i++)
        if (ls->v[i].closed)
            for (k = 0; k < ls->v[i].n; k++) {
                const double *p = ls->v[i].xy + 2 * k;
                if (p[0] >= 0 && p[1] >= 0)
                    start[(long)(p[1] / CELL) * gw + (long)(p[0] / CELL) +
                          1]++;
            }
    for (i = 0; i < (size_t)(gw * gh); i++)
        start[i + 1] += start[i];
    {
        size_t *fill = td_malloc((size_t)(gw * gh) * sizeof *fill, cx);
        if (!fill) {
            marked = TD_ENOMEM;
            goto done;
        }
        memcpy(fill, start, (size_t)(gw * gh) * sizeof *fill);
        for (i = 0; i < ls->n; i++)
            if (ls->v[i].closed)
                for (k = 0; k < ls->v[i].n; k++) {
                    const double *p = ls->v[i].xy + 2 * k;
                    if (p[0] >= 0 && p[1] >= 0)
                        v[fill[(long)(p[1] / CELL) * gw + (long)(p[0] / CELL)]++] =
                            (vref){(uint32_t)i, (uint32_t)k};
                }
        free(fill);
    }
    /* each spur to the nearest closed line's vertex: its side */
    for (i = 0; i < n; i++) {
        const td_spur_rec *r = &rec[i];
        long cx0 = (long)(r->jx / CELL), cy0 = (long)(r->jy / CELL), gx, gy;
        double bd = NEAR * NEAR, len = hypot(r->tx - r->jx, r->ty - r->jy);
        const vref *best = NULL;
        if (len < MIN_TIP || len > MAX_TIP)
            continue;
        for (gy = cy0 - 1; gy <= cy0 + 1; gy++)
            for (gx = cx0 - 1; gx <= cx0 + 1; gx++) {
                size_t a;
                if (gx < 0 || gy < 0 || gx >= gw || gy >= gh)
                    continue;
                for (a = start[gy * gw + gx]; a < start[gy * gw + gx + 1];
                     a++) {
                    const double *p = ls->v[v[a].line].xy + 2 * v[a].k;
                    double d = (p[0] - r->jx) * (p[0] - r->jx) +
                               (p[1] - r->jy) * (p[1] - r->jy);
                    if (d < bd)
                        bd = d, best = &v[a];
                }
            }
        if (best) {
            const td_line *l = &ls->v[best->line];
            size_t m = l->n, a = (best->k + m - 2) % m, b = (best->k + 2) % m;
            double tx = l->xy[2 * b] - l->xy[2 * a],
                   ty = l->xy[2 * b + 1] - l->xy[2 * a + 1];
            double ux = r->tx - r->jx, uy = r->ty - r->jy;
            /* side 0 (left on the screen, y down) is towards (ty, -tx) */
            int side = ux * ty - uy * tx > 0 ? 0 : 1;
            int inner = td_line_signed_area(l) > 0 ? 1 : 0;
            cnt[2 * best->line + (side == inner ? 0 : 1)]++;
        }
    }
    for (i = 0; i < ls->n; i++) {
        size_t in = cnt[2 * i], out = cnt[2 * i + 1];
        ls->v[i].depression =
            ls->v[i].closed && in >= (size_t)min_in && in > 2 * out;
        marked += ls->v[i].depression;
    }
done:
    free(start);
    free(v);
    free(cnt);
    return marked;
}
