/* multidir_sweep.c: phase 1 of the multidir method in one pass down the rows.
 *
 * Walking each direction separately (td_interp_walk) writes the diagonal
 * and vertical spans down columns, a cache line per cell, and needs an
 * 8-byte sum per cell.  Here every scan line crossing the current row
 * keeps its open span's running estimate (z, dz, w), so a row receives the
 * x, y, diagonal and anti-diagonal estimates in turn, in that order, as
 * contiguous vector loops, and is blended at once:
 *
 *          y  diag   anti          line states indexed by scan line:
 *          |    \     /             y:    c
 *     row r  . . c . . . .           diag: c - r + h - 1
 *                                    anti: c + r
 *
 * A span's step dz and weight need the next anchor along its line, which
 * lies below: a first pass from the bottom row up records, for every
 * anchor, the steps to the next anchor along y, diag and anti.  The float
 * operations are those of linear_span in multidir.c (z += dz from the
 * first anchor, sum += w z and w in direction order from 0), so the result
 * is bit-identical to walking the directions one by one.  The rows are
 * swept in bands on threads; a band starts from each line's last anchor
 * above it and steps its span down by the same additions (band_enter). */
#include "interp/multidir_int.h"

#include "interp/interp_int.h"
#include "interp/rasterise.h"

#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

enum { NV = 3 }; /* directions crossing rows: y, diag, anti */

/* An anchor: its column and the steps to the next anchor below it, per
 * direction (0 when none). */
typedef struct sw_next {
    int c, n[NV];
} sw_next;

typedef struct sw_state {
    td_grid_f32 *g;
    td_multidir_weight m;
    int nv;          /* 1 (x and y only) or 3 */
    size_t nl;       /* scan lines per direction (w + h - 1) */
    float *z[NV], *dz[NV], *w[NV]; /* open span per line; w 0: none */
    int *nextrow[NV];              /* lookahead: last anchor row seen */
    sw_next *next;   /* anchors in reverse row-major order */
    size_t nnext, cap, k; /* anchors, allocated, next one to read + 1 */
    float *bz, *bw;       /* the row's sums of w z and of w */
    int *rowcount;   /* anchors per row */
} sw_state;

static const int sw_dc[NV] = {0, 1, -1};

/* Index offset of the scan lines crossing row r: line = c + base. */
static size_t line_base(const sw_state *s, int j, int r)
{
    return j == 0 ? 0 : j == 1 ? (size_t)(s->g->h - 1 - r) : (size_t)r;
}

/* Room for na more anchors (lookahead asks once for all of them: 16
 * bytes per anchor, no slack; grown by half when asked again). */
static int reserve(sw_state *s, int na, td_ctx *cx)
{
    size_t cap = s->cap ? s->cap + s->cap / 2 + 1024 : 0;
    sw_next *v;
    if (s->nnext + (size_t)na <= s->cap)
        return 0;
    if (cap < s->nnext + (size_t)na)
        cap = s->nnext + (size_t)na;
    if (cap > SIZE_MAX / sizeof *v ||
        !(v = realloc(s->next, cap * sizeof *v)))
        return td_seterr(cx, TD_ENOMEM, "multidir: out of memory for %zu "
                         "line cells", cap);
    s->next = v;
    s->cap = cap;
    return 0;
}

/* Bottom-up pass: the anchors, each with the steps to the next anchor
 * below it on each line, from the last in row-major order to the first.
 * The anchors are counted and placed per row on threads (row r's block
 * starts after the rows below it); then each direction walks them bottom
 * up on a thread of its own, into its own nextrow and its own n[j]: the
 * one pass's numbers (10000^2 benchmark sheet 0.25 -> 0.12 s). */
static int lookahead(sw_state *s, td_ctx *cx)
{
    const td_grid_f32 *g = s->g;
    int r, j;
    size_t all = 0, *off;
    if (!(off = td_malloc(((size_t)g->h + 1) * sizeof *off, cx)))
        return TD_ENOMEM;
#pragma omp parallel for schedule(static)
    for (r = 0; r < g->h; r++) { /* the anchors counted first: one block */
        const float *row = g->data + (size_t)r * g->stride;
        int c, na = 0;
        for (c = td_row_find(row, 0, g->w, 0); c < g->w;
             c = td_row_find(row, c + 1, g->w, 0))
            na++;
        s->rowcount[r] = na;
    }
    for (r = g->h - 1; r >= 0; r--) /* blocks bottom row first */
        off[r] = all, all += (size_t)s->rowcount[r];
    if (reserve(s, (int)(all < INT_MAX ? all : INT_MAX), cx) != 0) {
        free(off);
        return TD_ENOMEM;
    }
#pragma omp parallel for schedule(static)
    for (r = 0; r < g->h; r++) { /* each row's anchors right to left */
        const float *row = g->data + (size_t)r * g->stride;
        sw_next *e = s->next + off[r] + (size_t)s->rowcount[r];
        int c;
        for (c = td_row_find(row, 0, g->w, 0); c < g->w;
             c = td_row_find(row, c + 1, g->w, 0))
            (--e)->c = c;
    }
    s->nnext = all;
#pragma omp parallel for schedule(static, 1)
    for (j = 0; j < s->nv; j++) {
        int *nextrow = s->nextrow[j], q;
        size_t k = 0;
        memset(nextrow, 0xff, s->nl * sizeof *nextrow); /* -1 */
        for (q = g->h - 1; q >= 0; q--) {
            size_t base = line_base(s, j, q), end = k + (size_t)s->rowcount[q];
            for (; k < end; k++) {
                sw_next *e = &s->next[k];
                int *nr = &nextrow[e->c + base];
                e->n[j] = *nr >= 0 ? *nr - q : 0;
                *nr = q;
            }
        }
    }
    free(off);
    s->k = s->nnext;
    return 0;
}

/* The x estimates of one row into bz, bw (cleared first); e[0..na) are
 * the row's anchors, right to left. */
static void row_x(sw_state *s, const float *row, const sw_next *e, int na)
{
    int i, c;
    memset(s->bz, 0, (size_t)s->g->w * sizeof *s->bz);
    memset(s->bw, 0, (size_t)s->g->w * sizeof *s->bw);
    for (i = 1; i < na; i++) {
        int a = e[i].c, b = e[i - 1].c, n = b - a;
        float za = row[a], zb = row[b], dz, z = za, w;
        if (n < 2 || za == zb)
            continue;
        dz = (zb - za) / (float)n;
        w = td_multidir_span_weight(s->m, n, 1.0);
        for (c = a + 1; c < b; c++) {
            z += dz;
            s->bz[c] += w * z;
            s->bw[c] += w;
        }
    }
}

/* One direction's open spans step one cell down into this row and add
 * their estimates (x, y only). */
static void row_cross1(float *restrict bz, float *restrict bw,
                       float *restrict z, const float *restrict dz,
                       const float *restrict w, int n)
{
    int c;
    for (c = 0; c < n; c++) {
        float zc = z[c] + dz[c], wc = w[c];
        z[c] = zc;
        bz[c] = wc != 0 ? bz[c] + wc * zc : bz[c];
        bw[c] = wc != 0 ? bw[c] + wc : bw[c];
    }
}

/* The hot loop, all three crossing directions at once (bz, bw stay in
 * registers; no branch, vectorised): each open span steps one cell down
 * into this row and adds its estimate, y, diag, anti in turn, to the x
 * sums; then the row's undetermined cells take the blend.  Lines with no
 * open span have w 0 and add nothing. */
static void row_cross3(float *restrict row, const float *restrict bz,
                       const float *restrict bw, float *restrict z0,
                       float *restrict z1, float *restrict z2,
                       const float *restrict dz0, const float *restrict dz1,
                       const float *restrict dz2, const float *restrict w0,
                       const float *restrict w1, const float *restrict w2,
                       int n)
{
    int c;
    for (c = 0; c < n; c++) {
        float a = bz[c], b = bw[c], v = row[c];
        float y = z0[c] + dz0[c], d = z1[c] + dz1[c], t = z2[c] + dz2[c];
        z0[c] = y;
        z1[c] = d;
        z2[c] = t;
        a = w0[c] != 0 ? a + w0[c] * y : a;
        b = w0[c] != 0 ? b + w0[c] : b;
        a = w1[c] != 0 ? a + w1[c] * d : a;
        b = w1[c] != 0 ? b + w1[c] : b;
        a = w2[c] != 0 ? a + w2[c] * t : a;
        b = w2[c] != 0 ? b + w2[c] : b;
        row[c] = v != v && b > 0 ? a / b : v;
    }
}

/* Open the spans that start at this row's anchors (or close the lines
 * through them when the next anchor is adjacent, missing or level). */
static void row_open(sw_state *s, const float *row, int r, const sw_next *e,
                     int na)
{
    const td_grid_f32 *g = s->g;
    int i, j;
    for (i = 0; i < na; i++, e++) {
        int c = e->c;
        float za = row[c];
        for (j = 0; j < s->nv; j++) {
            size_t l = (size_t)c + line_base(s, j, r);
            int n = e->n[j];
            float zb = n >= 2 ? TD_AT(g, c + n * sw_dc[j], r + n) : za;
            s->z[j][l] = s->dz[j][l] = s->w[j][l] = 0;
            if (zb == za)
                continue;
            s->z[j][l] = za;
            s->dz[j][l] = (zb - za) / (float)n;
            s->w[j][l] = td_multidir_span_weight(s->m, n,
                                                 j ? sqrt(2.0) : 1.0);
        }
    }
}

/* Row r: x, then each crossing direction, then blend into the NaN cells
 * (the lines through this row's anchors are opened after the blend: the
 * anchors themselves are not blended, and the new spans start below). */
static void row_sweep(sw_state *s, int r)
{
    float *row = s->g->data + (size_t)r * s->g->stride;
    const sw_next *e;
    size_t b1 = line_base(s, 1, r), b2 = line_base(s, 2, r);
    int w = s->g->w, na = s->rowcount[r], c;
    s->k -= (size_t)na;
    e = na ? s->next + s->k : NULL;
    row_x(s, row, e, na);
    if (s->nv == NV) {
        row_cross3(row, s->bz, s->bw, s->z[0], s->z[1] + b1, s->z[2] + b2,
                   s->dz[0], s->dz[1] + b1, s->dz[2] + b2, s->w[0],
                   s->w[1] + b1, s->w[2] + b2, w);
    } else {
        row_cross1(s->bz, s->bw, s->z[0], s->dz[0], s->w[0], w);
        for (c = 0; c < w; c++)
            if (row[c] != row[c] && s->bw[c] > 0)
                row[c] = s->bz[c] / s->bw[c];
    }
    row_open(s, row, r, e, na);
}

static void sw_free(sw_state *s)
{
    int j;
    for (j = 0; j < NV; j++) {
        free(s->z[j]);
        free(s->dz[j]);
        free(s->w[j]);
        free(s->nextrow[j]);
    }
    free(s->next);
    free(s->bz);
    free(s->bw);
    free(s->rowcount);
}

/* ---- row bands on threads ----
 * A band starting at row r0 needs each line's open span as the rows above
 * left it: set by the line's last anchor above r0 (row_open's values)
 * and stepped down by repeated additions, exactly as the sweep steps it,
 * so every band gives the bytes one pass would. */

#define SW_BANDS 16

/* The per-line arrays of one band's state (z, dz, w; bz, bw for a row). */
static int band_alloc(sw_state *b, const sw_state *s, td_ctx *cx)
{
    int j;
    *b = *s;
    for (j = 0; j < NV; j++)
        b->z[j] = b->dz[j] = b->w[j] = NULL, b->nextrow[j] = NULL;
    b->bz = b->bw = NULL;
    for (j = 0; j < s->nv; j++)
        if (!(b->z[j] = td_calloc(s->nl, sizeof *b->z[j], cx)) ||
            !(b->dz[j] = td_calloc(s->nl, sizeof *b->dz[j], cx)) ||
            !(b->w[j] = td_calloc(s->nl, sizeof *b->w[j], cx)))
            return TD_ENOMEM;
    if (!(b->bz = td_malloc((size_t)s->g->w * sizeof *b->bz, cx)) ||
        !(b->bw = td_malloc((size_t)s->g->w * sizeof *b->bw, cx)))
        return TD_ENOMEM;
    return 0;
}

static void band_free(sw_state *b)
{
    int j;
    for (j = 0; j < NV; j++)
        free(b->z[j]), free(b->dz[j]), free(b->w[j]);
    free(b->bz), free(b->bw);
}

/* The open spans entering row r0: from each line's last anchor above r0
 * (at[j][line]: its index in next, its row in row[j][line]; -1: none),
 * as row_open set them and the rows down to r0 - 1 stepped them. */
static void band_enter(sw_state *b, int r0, long *const at[NV],
                       int *const row[NV])
{
    const td_grid_f32 *g = b->g;
    size_t l;
    int j;
    for (j = 0; j < b->nv; j++)
        for (l = 0; l < b->nl; l++) {
            const sw_next *e;
            int ra = row[j][l], c, n, k;
            float za, zb, z, dz;
            if (at[j][l] < 0)
                continue;
            e = &b->next[at[j][l]];
            c = e->c, n = e->n[j];
            za = TD_AT(g, c, ra);
            zb = n >= 2 ? TD_AT(g, c + n * sw_dc[j], ra + n) : za;
            if (zb == za || ra + n < r0)
                continue; /* closed, or its span ended above r0 */
            dz = (zb - za) / (float)n;
            z = za;
            for (k = ra + 1; k < r0; k++)
                z = z + dz;
            b->z[j][l] = z;
            b->dz[j][l] = dz;
            b->w[j][l] = td_multidir_span_weight(b->m, n,
                                                 j ? sqrt(2.0) : 1.0);
        }
}

int td_multidir_sweep(td_grid_f32 *g, const td_multidir_params *p,
                      const char *stage, td_ctx *cx)
{
    sw_state s;
    int j, r, k, rc = TD_ENOMEM, fail = 0, cancel = 0, nb;
    long *at[SW_BANDS][NV], *cur[NV];
    int *row[SW_BANDS][NV], *curr[NV];
    size_t kstart[SW_BANDS + 1], kk, l;
    memset(&s, 0, sizeof s);
    memset(at, 0, sizeof at), memset(row, 0, sizeof row);
    memset(cur, 0, sizeof cur), memset(curr, 0, sizeof curr);
    s.g = g;
    s.m = p->weight;
    s.nv = p->ndir == 2 ? 1 : NV;
    s.nl = (size_t)g->w + (size_t)g->h - 1;
    nb = g->h < 64 * SW_BANDS ? 1 : SW_BANDS;
    for (j = 0; j < s.nv; j++)
        if (!(s.nextrow[j] = td_malloc(s.nl * sizeof *s.nextrow[j], cx)) ||
            !(cur[j] = td_malloc(s.nl * sizeof *cur[j], cx)) ||
            !(curr[j] = td_malloc(s.nl * sizeof *curr[j], cx)))
            goto fail;
    for (k = 1; k < nb; k++)
        for (j = 0; j < s.nv; j++)
            if (!(at[k][j] = td_malloc(s.nl * sizeof *at[k][j], cx)) ||
                !(row[k][j] = td_malloc(s.nl * sizeof *row[k][j], cx)))
                goto fail;
    if (!(s.rowcount = td_malloc((size_t)g->h * sizeof *s.rowcount, cx)) ||
        (rc = lookahead(&s, cx)) != 0)
        goto fail;
    /* one pass down the anchors: each band's entry state (the last anchor
     * above its first row, per line) and where its anchors start */
    for (j = 0; j < s.nv; j++)
        for (l = 0; l < s.nl; l++)
            cur[j][l] = -1, curr[j][l] = -1;
    kk = s.nnext;
    kstart[0] = kk;
    for (k = 1, r = 0; r < g->h; r++) {
        int i, na = s.rowcount[r];
        for (; k < nb && r == (int)((long)k * g->h / nb); k++) {
            for (j = 0; j < s.nv; j++) {
                memcpy(at[k][j], cur[j], s.nl * sizeof *cur[j]);
                memcpy(row[k][j], curr[j], s.nl * sizeof *curr[j]);
            }
            kstart[k] = kk;
        }
        kk -= (size_t)na;
        for (i = 0; i < na; i++) {
            const sw_next *e = &s.next[kk + (size_t)i];
            for (j = 0; j < s.nv; j++) {
                l = (size_t)e->c + line_base(&s, j, r);
                cur[j][l] = (long)(kk + (size_t)i);
                curr[j][l] = r;
            }
        }
    }
    rc = 0;
#pragma omp parallel for schedule(dynamic, 1) reduction(| : fail, cancel)
    for (k = 0; k < nb; k++) {
        sw_state b;
        int r0 = (int)((long)k * g->h / nb);
        int r1 = (int)((long)(k + 1) * g->h / nb), rr;
        if (band_alloc(&b, &s, NULL) != 0) {
            band_free(&b);
            fail = 1;
            continue;
        }
        if (k > 0)
            band_enter(&b, r0, at[k], row[k]);
        b.k = kstart[k];
        for (rr = r0; rr < r1 && !cancel; rr++) {
            row_sweep(&b, rr);
            if (k == 0 && stage && (rr & 1023) == 1023)
                cancel |= td_progress(cx, stage, (double)rr / g->h) != 0;
        }
        band_free(&b);
    }
    if (fail)
        rc = td_seterr(cx, TD_ENOMEM, "multidir: out of memory");
    else if (cancel)
        rc = cx && cx->code ? cx->code : TD_ECANCEL;
fail:
    for (k = 0; k < SW_BANDS; k++)
        for (j = 0; j < NV; j++)
            free(at[k][j]), free(row[k][j]);
    for (j = 0; j < NV; j++)
        free(cur[j]), free(curr[j]);
    sw_free(&s);
    return rc;
}
