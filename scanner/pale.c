/* pale.c: faded contours traced apart from the ink.  See pale.h. */
#include "scanner/pale.h"

#include "scanner/straight.h"
#include "scanner/thin.h"
#include "src/io/io.h"

#include <math.h>
#include <stddef.h>
#include <stdlib.h>

td_pale_params td_pale_defaults(void)
{
    td_pale_params p;
    p.depth = 0.15;
    p.hue_cos = 0.9;
    p.apart = 2;
    p.min_points = 12;
    return p;
}

#define PALE_BLOCK 32 /* rows per block of work */

#define BIT(b, st, x, y) (((b)[(size_t)(y) * (st) + ((x) >> 3)] >> ((x)&7)) & 1)

typedef struct ridge_ctx {
    const td_image *im;
    float d[3];                 /* paper - ink, RGB */
    float inv;                  /* 1 / |d|^2 */
    float depth;                /* p->depth */
    float cos2;                 /* p->hue_cos^2 */
    float dn;                   /* |d| */
    float o[TD_PALETTE_MAX][3]; /* the other inks' paper - ink, unit */
    int no;
} ridge_ctx;

/* How far colour c lies along paper -> ink, in paper-to-ink distances,
 * up to a constant (only differences are used: a lighter paper shifts
 * it, the ridge test does not see that). */
static float along(const ridge_ctx *rc, const uint8_t *c)
{
    return -((float)c[0] * rc->d[0] + (float)c[1] * rc->d[1] +
             (float)c[2] * rc->d[2]) *
           rc->inv;
}

/* The four directions of the ridge test: along a row, a column and the
 * two diagonals. */
static const int dir4[4][2] = {{1, 0}, {0, 1}, {1, 1}, {1, -1}};

/* Whether, along one of the directions in dirs (bit k: dir4[k]; those
 * along which pixel x of row y, 2 px inside the sheet, is a ridge), the
 * pixel's difference from the two pixels 2 px off points from paper to
 * contour ink within the cosine and more than to any other ink. */
static int pale_hue(const ridge_ctx *rc, int x, int y, unsigned dirs)
{
    int k;
    for (k = 0; k < 4; k++) {
        int dx = dir4[k][0], dy = dir4[k][1], c, j;
        float e[3], ed = 0, ee = 0;
        const uint8_t *p0, *pa, *pb;
        if (!(dirs >> k & 1u))
            continue;
        p0 = rc->im->data + (size_t)y * rc->im->stride + (size_t)x * 3;
        pa = rc->im->data + (size_t)(y - 2 * dy) * rc->im->stride +
             (size_t)(x - 2 * dx) * 3;
        pb = rc->im->data + (size_t)(y + 2 * dy) * rc->im->stride +
             (size_t)(x + 2 * dx) * 3;
        for (c = 0; c < 3; c++) {
            e[c] = 0.5f * ((float)pa[c] + (float)pb[c]) - (float)p0[c];
            ed += e[c] * rc->d[c];
            ee += e[c] * e[c];
        }
        if (!(ed > 0 && ed * ed >= rc->cos2 * ee * rc->dn * rc->dn))
            continue;
        for (j = 0; j < rc->no; j++) /* nearer another ink's way */
            if (e[0] * rc->o[j][0] + e[1] * rc->o[j][1] + e[2] * rc->o[j][2] >
                ed / rc->dn)
                break;
        if (j == rc->no)
            return 1;
    }
    return 0;
}

/* Per pixel x of a row (r[2]; r[0..4] the rows 2 up .. 2 down) the
 * directions along which it is at least as far along as both neighbours
 * and depth further than both pixels 2 px off, into pk (0 at the ink of
 * mask row m); branch-free so that the compiler vectorises it. */
static void peak_row(const float *const *r, const uint8_t *m, int w,
                     float depth, uint8_t *pk)
{
    const float *r0 = r[0], *r1 = r[1], *r2 = r[2], *r3 = r[3], *r4 = r[4];
    int x;
#pragma omp simd
    for (x = 2; x < w - 2; x++) {
        float s = r2[x], t = s - depth;
        unsigned f;
        f = (unsigned)((r2[x - 1] <= s) & (r2[x + 1] <= s) & (r2[x - 2] <= t) &
                       (r2[x + 2] <= t));
        f |= (unsigned)((r1[x] <= s) & (r3[x] <= s) & (r0[x] <= t) &
                        (r4[x] <= t))
             << 1;
        f |= (unsigned)((r1[x - 1] <= s) & (r3[x + 1] <= s) & (r0[x - 2] <= t) &
                        (r4[x + 2] <= t))
             << 2;
        f |= (unsigned)((r3[x - 1] <= s) & (r1[x + 1] <= s) & (r4[x - 2] <= t) &
                        (r0[x + 2] <= t))
             << 3;
        pk[x] = (uint8_t)(f * (unsigned)(m[x] == 0));
    }
}

/* Anything of mask (nonzero) or other (bits) within r px of (x, y). */
static int near_ink(const td_grid_u8 *mask, const uint8_t *other, size_t stride,
                    int x, int y, int r)
{
    int u, v;
    for (v = y - r; v <= y + r; v++)
        for (u = x - r; u <= x + r; u++) {
            if (u < 0 || v < 0 || u >= mask->w || v >= mask->h)
                continue;
            if (mask->data[(size_t)v * mask->stride + u] ||
                (other && BIT(other, stride, u, v)))
                return 1;
        }
    return 0;
}

/* The ridges of rows [ya, yb) into bits (rows stride bytes), buf holding
 * along for rows ya - 2 .. yb + 1 (w floats each) and then w bytes. */
static void ridge_rows(const ridge_ctx *rc, const td_grid_u8 *mask,
                       const uint8_t *other, int apart, int ya, int yb,
                       float *buf, uint8_t *bits, size_t stride)
{
    const td_image *im = rc->im;
    uint8_t *pk = (uint8_t *)(buf + (size_t)(yb - ya + 4) * (size_t)im->w);
    int y, x, k, r0 = ya - 2 < 0 ? 0 : ya - 2,
                 r1 = yb + 2 > im->h ? im->h : yb + 2;
    for (y = r0; y < r1; y++) {
        const uint8_t *px = im->data + (size_t)y * im->stride;
        float *row = buf + (size_t)(y - (ya - 2)) * (size_t)im->w;
#pragma omp simd
        for (x = 0; x < im->w; x++)
            row[x] = along(rc, px + 3 * (size_t)x);
    }
    for (y = ya < 2 ? 2 : ya; y < yb && y < im->h - 2; y++) {
        const float *r[5];
        uint8_t *b = bits + (size_t)y * stride;
        for (k = 0; k < 5; k++)
            r[k] = buf + (size_t)(y - 2 + k - (ya - 2)) * (size_t)im->w;
        peak_row(r, mask->data + (size_t)y * mask->stride, im->w, rc->depth,
                 pk);
        for (x = 2; x < im->w - 2; x++)
            if (pk[x] && pale_hue(rc, x, y, pk[x]) &&
                !near_ink(mask, other, stride, x, y, apart))
                b[x >> 3] |= (uint8_t)(1u << (x & 7));
    }
}

/* A piece of a faint grid line: open, straight (its chord at least
 * GRID_CHORD of its length) and within GRID_SKEW degrees of a row or a
 * column.  Where the grid is faint in the ink too the grid finder does
 * not see it (on the new print of Orkhon its line at x = 326 came out in
 * pieces of 20-110 px, 0.14 of its length); a contour runs that straight
 * and square for 12 px or more only by chance. */
#define GRID_CHORD 0.98
#define GRID_SKEW 1.5
static int grid_like(const td_line *l)
{
    double len = td_line_length(l), dx, dy, a;
    if (l->closed || l->n < 2 || !(len > 0))
        return 0;
    dx = fabs(l->xy[2 * (l->n - 1)] - l->xy[0]);
    dy = fabs(l->xy[2 * (l->n - 1) + 1] - l->xy[1]);
    if (sqrt(dx * dx + dy * dy) < GRID_CHORD * len)
        return 0;
    a = atan2(fmin(dx, dy), fmax(dx, dy)) * 180.0 / 3.14159265358979;
    return a <= GRID_SKEW;
}

/* The layer's sub-steps (grid, specks, thinning, spurs, tracing) report
 * to the caller's progress as one stage, "faded lines", step k of 5. */
typedef struct pale_prog {
    td_ctx *outer;
    int k;
} pale_prog;

static int pale_progress(const char *stage, double frac, void *user)
{
    const pale_prog *pp = user;
    (void)stage;
    return pp->outer->progress("faded lines",
                               (pp->k + fmin(fmax(frac, 0.0), 1.0)) / 5.0,
                               pp->outer->progress_user);
}

/* Contract in pale.h. */
int td_pale_find(const td_image *im, const td_palette *pal,
                 const td_grid_u8 *mask, const uint8_t *other,
                 const td_pale_params *p, uint8_t **bits, td_ctx *cx)
{
    size_t stride = ((size_t)im->w + 7) / 8;
    ridge_ctx rc;
    int c, k, err = 0;
    float dd = 0;
    *bits = NULL;
    if (im->channels != 3 || pal->n == 0 || pal->chosen < 0 || im->w < 5 ||
        im->h < 5)
        return 0;
    for (c = 0; c < 3; c++) {
        rc.d[c] = (float)pal->ink[pal->paper].rgb[c] -
                  (float)pal->ink[pal->chosen].rgb[c];
        dd += rc.d[c] * rc.d[c];
    }
    if (dd < 100.0f)
        return 0;
    rc.im = im;
    rc.inv = 1.0f / dd;
    rc.dn = sqrtf(dd);
    rc.no = 0;
    for (k = 0; k < pal->n; k++) {
        float n2 = 0;
        if (k == pal->paper || k == pal->chosen || (pal->also >> k & 1u))
            continue;
        for (c = 0; c < 3; c++) {
            rc.o[rc.no][c] =
                (float)pal->ink[pal->paper].rgb[c] - (float)pal->ink[k].rgb[c];
            n2 += rc.o[rc.no][c] * rc.o[rc.no][c];
        }
        if (n2 < 100.0f)
            continue;
        for (c = 0; c < 3; c++)
            rc.o[rc.no][c] /= sqrtf(n2);
        rc.no++;
    }
    rc.depth = (float)p->depth;
    rc.cos2 = (float)(p->hue_cos * p->hue_cos);
    if (!(*bits = td_calloc(stride * (size_t)im->h + 1, 1, cx)))
        return TD_ENOMEM;
#pragma omp parallel
    {
        float *buf =
            malloc((size_t)(PALE_BLOCK + 5) * (size_t)im->w * sizeof *buf);
        int blk, nblk = (im->h + PALE_BLOCK - 1) / PALE_BLOCK;
        if (!buf) {
#pragma omp atomic write
            err = TD_ENOMEM;
        }
#pragma omp for schedule(dynamic, 1)
        for (blk = 0; blk < nblk; blk++)
            if (buf) {
                int ya = blk * PALE_BLOCK;
                ridge_rows(&rc, mask, other, p->apart, ya,
                           ya + PALE_BLOCK > im->h ? im->h : ya + PALE_BLOCK,
                           buf, *bits, stride);
            }
        free(buf);
    }
    if (err) {
        free(*bits);
        *bits = NULL;
        return td_seterr(cx, TD_ENOMEM, "faded lines: out of memory");
    }
    return 0;
}

/* Contract in pale.h. */
long td_pale_trace(const uint8_t *bits, int w, int h, const td_pale_params *p,
                   const td_despur_params *sp, const td_trace_params *tp,
                   td_lines *lines, td_ctx *cx)
{
    size_t stride = ((size_t)w + 7) / 8, i;
    td_grid_u8 *g = NULL;
    td_lines *pl = NULL;
    td_thin_stats ts;
    td_despur_stats ds;
    td_trace_stats trs;
    int x, y, x0 = w, y0 = h, x1 = -1, y1 = -1, pad, err = 0;
    long added = 0;
    td_straight_params st = td_straight_defaults();
    td_ctx lc;
    pale_prog pp;
    for (y = 0; y < h; y++) /* the ridges' box (by bytes) */
        for (i = 0; i < stride; i++)
            if (bits[(size_t)y * stride + i]) {
                int bx = (int)i * 8;
                x0 = bx < x0 ? bx : x0, x1 = bx + 7 > x1 ? bx + 7 : x1;
                y0 = y < y0 ? y : y0, y1 = y > y1 ? y : y1;
            }
    x1 = x1 >= w ? w - 1 : x1;
    if (x1 < 0)
        return 0;
    /* padded so that only the sheet's own border is near a traced end */
    pad = tp->edge_dist + 4;
    x0 = x0 - pad < 0 ? 0 : x0 - pad, y0 = y0 - pad < 0 ? 0 : y0 - pad;
    x1 = x1 + pad >= w ? w - 1 : x1 + pad;
    y1 = y1 + pad >= h ? h - 1 : y1 + pad;
    if (!(g = td_grid_u8_new(x1 - x0 + 1, y1 - y0 + 1, cx)))
        return TD_ENOMEM;
    for (y = y0; y <= y1; y++) /* grid_new zeroes; the set bits only */
        for (i = (size_t)x0 / 8; i <= (size_t)x1 / 8; i++) {
            unsigned v = bits[(size_t)y * stride + i];
            for (x = (int)i * 8; v; v >>= 1, x++)
                if ((v & 1u) && x >= x0 && x <= x1)
                    g->data[(size_t)(y - y0) * g->stride + (x - x0)] = 1;
        }
    td_ctx_init(&lc);
    if (cx && cx->progress)
        lc.progress = pale_progress, lc.progress_user = &pp;
    pp.outer = cx, pp.k = 0;
    if ((err = td_straight_remove(g, &st, NULL, &lc)) == 0 && ++pp.k &&
        (err = td_cv_remove_specks(g, 8, NULL, &lc)) == 0 && ++pp.k &&
        (err = td_thin_hilditch(g, &ts, &lc)) == 0 && ++pp.k &&
        (err = td_despur(g, sp, &ds, &lc)) == 0 && ++pp.k)
        err = td_trace(g, tp, &pl, &trs, &lc);
    if (err) { /* the inner cause, in the caller's context */
        if (cx && !cx->code)
            td_seterr(cx, lc.code ? lc.code : err, "%s",
                      lc.msg[0] ? lc.msg : "faded lines: failed");
        goto done;
    }
    for (i = 0; i < pl->n && err == 0; i++) {
        td_line *l = &pl->v[i];
        size_t q;
        if (l->n < (size_t)p->min_points || grid_like(l))
            continue;
        for (q = 0; q < l->n; q++)
            l->xy[2 * q] += x0, l->xy[2 * q + 1] += y0;
        if ((err = td_lines_append_copy(lines, l, cx)) == 0) {
            lines->v[lines->n - 1].id = (long)lines->n - 1;
            lines->v[lines->n - 1].pale = 1;
            added++;
        }
    }
done:
    td_lines_free(pl);
    td_grid_u8_free(g);
    return err ? err : added;
}
