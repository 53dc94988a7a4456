/* streams.c: the water plate drawn from the terrain (tdgen --streams):
 * streams where the flow of the surface gathers, as printed maps draw
 * them, so that each crosses the contours at the bottom of their V
 * (contours point upstream where they cross a valley).
 *
 * Flow: the surface's pits are filled and its flats tilted towards their
 * outlets (priority flood from the sheet's edge, each cell raised to at
 * least its flooding neighbour plus a millimetre), then every cell drains
 * to its steepest lower neighbour of eight (D8) and the edge cells drain
 * off the sheet.  The
 * cells draining at least td_gen_stream_area cells are stream; each
 * stream is walked from its head down to where it meets one already drawn
 * or ends, smoothed (a moving mean over 9 cells: D8 paths are stairs) and
 * drawn 1.2 px wide at its head, wider downstream (up to 2.4 px), but not
 * where it crosses a flat of the surface (SRTM's whole-metre terraces,
 * whose edges are the contours: a stream drawn there would run along
 * them, over their ink, for hundreds of px). */
#include "samples/gen/gen.h"
#include "samples/gen/gen_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define FLAT 1e-3 /* m: a step of the surface this low is flat */

/* Contract in gen_int.h. */
double td_gen_stream_area(const td_gen_params *p)
{
    double S = p->w < p->h ? p->w : p->h;
    return (S / 14.0) * (S / 14.0);
}

/* A binary min-heap of (level, cell). */
typedef struct heap {
    double *z;
    int32_t *c;
    size_t n;
} heap;

static void heap_push(heap *h, double z, int32_t c)
{
    size_t i = h->n++;
    while (i > 0 && h->z[(i - 1) / 2] > z) {
        h->z[i] = h->z[(i - 1) / 2], h->c[i] = h->c[(i - 1) / 2];
        i = (i - 1) / 2;
    }
    h->z[i] = z, h->c[i] = c;
}

static int32_t heap_pop(heap *h)
{
    int32_t top = h->c[0];
    double z = h->z[--h->n];
    int32_t c = h->c[h->n];
    size_t i = 0;
    for (;;) {
        size_t k = 2 * i + 1;
        if (k >= h->n)
            break;
        if (k + 1 < h->n && h->z[k + 1] < h->z[k])
            k++;
        if (h->z[k] >= z)
            break;
        h->z[i] = h->z[k], h->c[i] = h->c[k];
        i = k;
    }
    h->z[i] = z, h->c[i] = c;
    return top;
}

static const int DX[8] = {1, 1, 0, -1, -1, -1, 0, 1},
                 DY[8] = {0, 1, 1, 1, 0, -1, -1, -1};

/* zf: the surface g with its pits filled and its flats tilted (priority
 * flood from the edge, +1 mm a step).  seen: n zeroed bytes. */
static int fill(const td_grid_f32 *g, double *zf, uint8_t *seen, td_ctx *cx)
{
    size_t n = (size_t)g->w * (size_t)g->h;
    heap h;
    int x, y, k;
    h.n = 0;
    h.z = td_calloc(n, sizeof *h.z, cx);
    h.c = td_calloc(n, sizeof *h.c, cx);
    if (!h.z || !h.c) {
        free(h.z), free(h.c);
        return TD_ENOMEM;
    }
    for (y = 0; y < g->h; y++)
        for (x = 0; x < g->w; x++) {
            size_t i = (size_t)y * g->w + x;
            zf[i] = g->data[(size_t)y * g->stride + x];
            if (x == 0 || y == 0 || x == g->w - 1 || y == g->h - 1) {
                seen[i] = 1;
                heap_push(&h, zf[i], (int32_t)i);
            }
        }
    while (h.n) {
        int32_t c = heap_pop(&h);
        int cx0 = c % g->w, cy0 = c / g->w;
        for (k = 0; k < 8; k++) {
            int u = cx0 + DX[k], v = cy0 + DY[k];
            size_t j;
            if (u < 0 || v < 0 || u >= g->w || v >= g->h)
                continue;
            j = (size_t)v * g->w + u;
            if (seen[j])
                continue;
            seen[j] = 1;
            if (zf[j] < zf[c] + 1e-3)
                zf[j] = zf[c] + 1e-3;
            heap_push(&h, zf[j], (int32_t)j);
        }
    }
    free(h.z), free(h.c);
    return 0;
}

/* The steepest lower neighbour of each cell on zf (w x h; -1: none, the
 * edge's cells that drain off the sheet). */
static void receivers(const double *zf, int w, int h, int32_t *rcv)
{
    int x, y, k;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            double z = zf[(size_t)y * w + x], best = 0.0;
            int32_t to = -1;
            for (k = 0; k < 8; k++) {
                int u = x + DX[k], v = y + DY[k];
                double s;
                if (u < 0 || v < 0 || u >= w || v >= h)
                    continue;
                s = (z - zf[(size_t)v * w + u]) / (k & 1 ? 1.41421356 : 1.0);
                if (s > best)
                    best = s, to = v * w + u;
            }
            rcv[(size_t)y * w + x] = to;
        }
}

/* Cells drained by each cell (itself included), upstream first (Kahn's
 * order over the receiver forest). */
static int accumulate(const int32_t *rcv, size_t n, float *acc, td_ctx *cx)
{
    uint8_t *in = td_calloc(n, 1, cx); /* donors left, at most 8 */
    int32_t *q = td_calloc(n, sizeof *q, cx);
    size_t i, head = 0, tail = 0;
    if (!in || !q) {
        free(in), free(q);
        return TD_ENOMEM;
    }
    for (i = 0; i < n; i++) {
        acc[i] = 1.0f;
        if (rcv[i] >= 0)
            in[rcv[i]]++;
    }
    for (i = 0; i < n; i++)
        if (!in[i])
            q[tail++] = (int32_t)i;
    while (head < tail) {
        int32_t c = q[head++], r = rcv[c];
        if (r < 0)
            continue;
        acc[r] += acc[c];
        if (--in[r] == 0)
            q[tail++] = r;
    }
    free(in), free(q);
    return 0;
}

/* Draw the stream from head c down, smoothed; marks its cells in `done`
 * and stops after the first cell already drawn. */
static void draw_stream(uint8_t *lay, const td_gen_params *p,
                        const td_grid_f32 *dem, const int32_t *rcv,
                        const float *acc, uint8_t *done, int32_t c, double area,
                        double *xy, size_t cap)
{
    size_t n = 0, i;
    double px = 0, py = 0, pz = 0;
    while (c >= 0 && n < cap) {
        xy[2 * n] = c % p->w;
        xy[2 * n + 1] = c / p->w;
        n++;
        if (done[c])
            break;
        done[c] = 1;
        c = rcv[c];
    }
    for (i = 0; i < n; i++) {
        size_t a = i >= 4 ? i - 4 : 0, b = i + 4 < n ? i + 4 : n - 1, j;
        double sx = 0, sy = 0, x, y, wd;
        size_t k = (size_t)xy[2 * i + 1] * p->w + (size_t)xy[2 * i];
        double z =
            dem->data[(size_t)xy[2 * i + 1] * dem->stride + (size_t)xy[2 * i]];
        if (i == 0 || i + 1 == n) {
            x = xy[2 * i], y = xy[2 * i + 1];
        } else {
            for (j = a; j <= b; j++)
                sx += xy[2 * j], sy += xy[2 * j + 1];
            x = sx / (double)(b - a + 1), y = sy / (double)(b - a + 1);
        }
        wd = 1.2 + 0.6 * log2(acc[k] / area);
        wd = wd > 2.4 ? 2.4 : wd;
        if (i > 0 && pz - z > FLAT) /* not across flats */
            td_gen_draw_seg(lay, p->w, p->h, px, py, x, y, 0.5 * wd + 0.5);
        px = x, py = y, pz = z;
    }
}

/* Contract in gen_int.h. */
int td_gen_streams(const td_gen_params *p, const td_grid_f32 *dem, td_image *im,
                   td_ctx *cx)
{
    static const uint8_t blue[3] = {30, 90, 200};
    size_t n = (size_t)p->w * (size_t)p->h, i, cap = 2 * (size_t)(p->w + p->h);
    int32_t *rcv = NULL;
    float *acc = NULL;
    uint8_t *lay = NULL, *done = NULL;
    double *xy = NULL, *zf = NULL, area = td_gen_stream_area(p);
    int rc = TD_ENOMEM;
    if (!p->streams)
        return 0;
    if (!dem || dem->w != p->w || dem->h != p->h || im->channels != 3)
        return td_seterr(cx, TD_EINVAL,
                         "streams: the surface is not the "
                         "colour sheet's size");
    cap = cap < n ? n : cap;
    if (!(rcv = td_calloc(n, sizeof *rcv, cx)) ||
        !(acc = td_calloc(n, sizeof *acc, cx)) ||
        !(lay = td_calloc(n, 1, cx)) || !(done = td_calloc(n, 1, cx)) ||
        !(xy = td_calloc(2 * cap, sizeof *xy, cx)) ||
        !(zf = td_calloc(n, sizeof *zf, cx)))
        goto fail;
    if ((rc = fill(dem, zf, done, cx)) != 0)
        goto fail;
    receivers(zf, p->w, p->h, rcv);
    free(zf);
    zf = NULL;
    memset(done, 0, n);
    if ((rc = accumulate(rcv, n, acc, cx)) != 0)
        goto fail;
    /* heads: stream cells no stream cell drains into */
    for (i = 0; i < n; i++)
        if (acc[i] >= area && rcv[i] >= 0)
            done[rcv[i]] = 2; /* has a stream donor (cleared below) */
    for (i = 0; i < n; i++)
        if (acc[i] >= area && done[i] != 2)
            done[i] = 3; /* a head */
    for (i = 0; i < n; i++)
        done[i] = done[i] == 3 ? 3 : 0;
    for (i = 0; i < n; i++)
        if (done[i] == 3) {
            done[i] = 0;
            draw_stream(lay, p, dem, rcv, acc, done, (int32_t)i, area, xy, cap);
        }
    if (p->print)
        td_gen_overprint(im, lay, blue);
    else
        td_gen_composite(im, lay, blue);
    rc = 0;
fail:
    free(rcv), free(acc), free(lay), free(done), free(xy), free(zf);
    return rc;
}
