/* detint.c: inks over a tint shown over the paper (model and contract in
 * detint.h).
 *
 * Row bands of BAND rows; a band reads r rows either side (edges held):
 * hmax (per-channel max across 2 r + 1) of rows y0 - r .. y1 + r, then
 * bg of each output row the max of 2 r + 1 hmax rows.  Whether a
 * background is a tint is a table over the palette tables' 33^3 nodes
 * (td_palette_node). */
#include "scanner/detint.h"

#include "scanner/defringe.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define BAND 32
#define MAX_RADIUS 8
#define TINT_INK_MAX                                                           \
    0.1 /* a tint pixel: no ink explains it at this coverage or more           \
           (0.4, the palette labels' coverage, took the crowded new            \
           print's canyon walls inside the tint for tint: own 0.966 ->         \
           0.928; 0.1 and 0.05 gave 0.964-0.966) */

typedef struct band {
    uint8_t *hmax;     /* (BAND + 2 r) rows of 3 w: per-channel max across */
    uint8_t *bg;       /* one row: the background */
    uint8_t *tint;     /* (BAND + 2 R) rows of w: tint classes spread across */
    uint8_t *cls, *tn; /* one row each: classes; spread down too */
} band;

static int clampi(int v, int lo, int hi)
{
    return v < lo ? lo : v > hi ? hi : v;
}

int td_detint_any(const td_palette *pal)
{
    int i;
    for (i = 0; i < pal->n; i++)
        if (pal->ink[i].role == TD_INKROLE_TINT)
            return 1;
    return 0;
}

/* tab[node]: bits 0-6 1 + the tint a pixel of that colour is (no ink
 * at coverage TINT_INK_MAX or more explains it, and it lies nearer that
 * tint than the paper or another tint), or 0; bit 7 a background of that
 * colour is nearer a tint than the paper. */
static void tint_table(const td_palette *pal, uint8_t *tab)
{
    const int N = TD_PALETTE_LUT_N;
    int r, g, b;
    for (r = 0; r < N; r++)
        for (g = 0; g < N; g++)
            for (b = 0; b < N; b++) {
                double a;
                int k = td_palette_classify(pal, r * 8 > 255 ? 255 : r * 8,
                                            g * 8 > 255 ? 255 : g * 8,
                                            b * 8 > 255 ? 255 : b * 8, &a);
                int i, near = pal->paper;
                double c[3] = {r * 8 > 255 ? 255 : r * 8,
                               g * 8 > 255 ? 255 : g * 8,
                               b * 8 > 255 ? 255 : b * 8},
                       dn = INFINITY;
                for (i = 0; i < pal->n; i++)
                    if (i == pal->paper ||
                        pal->ink[i].role == TD_INKROLE_TINT) {
                        double d = 0;
                        int q;
                        for (q = 0; q < 3; q++)
                            d += (c[q] - pal->ink[i].rgb[q]) *
                                 (c[q] - pal->ink[i].rgb[q]);
                        if (d < dn)
                            dn = d, near = i;
                    }
                /* a tint pixel: no ink at TINT_INK_MAX coverage or more,
                   and nearer the tint than the paper */
                tab[(r * N + g) * N + b] =
                    (uint8_t)((near != pal->paper &&
                                       !(k >= 0 && k < pal->n &&
                                         pal->ink[k].role == TD_INKROLE_INK &&
                                         a >= TINT_INK_MAX)
                                   ? near + 1
                                   : 0) |
                              (near != pal->paper ? 0x80 : 0));
            }
}

/* Row y's (held) tint classes (tab) spread across x - R .. x + R (the
 * largest index there; 0 none). */
static void row_tint(const td_image *im, const uint8_t *tab, int y, int R,
                     uint8_t *cls, uint8_t *out)
{
    const uint8_t *row =
        im->data + (size_t)clampi(y, 0, im->h - 1) * im->stride;
    int x, k;
    for (x = 0; x < im->w; x++)
        cls[x] = tab[td_palette_node(row + 3 * x)] & 0x7f;
    for (x = 0; x < im->w; x++) {
        uint8_t m = 0;
        for (k = x - R < 0 ? 0 : x - R; k <= x + R && k < im->w; k++)
            m = cls[k] > m ? cls[k] : m;
        out[x] = m;
    }
}

static void do_band(const td_image *im, const td_palette *pal,
                    const uint8_t *tab, int r, band *bd, td_image *out, int y0)
{
    size_t n = 3 * (size_t)im->w, i, w = (size_t)im->w;
    int R = r + 1, y1 = y0 + BAND > im->h ? im->h : y0 + BAND, j, k, x, c;
    const uint8_t *P = pal->ink[pal->paper].rgb;
    for (j = 0; j < y1 - y0 + 2 * r; j++)
        td_rgb_row_max(im, y0 - r + j, r, bd->hmax + (size_t)j * n);
    for (j = 0; j < y1 - y0 + 2 * R; j++)
        row_tint(im, tab, y0 - R + j, R, bd->cls, bd->tint + (size_t)j * w);
    for (j = 0; j < y1 - y0; j++) {
        const uint8_t *row = im->data + (size_t)(y0 + j) * im->stride;
        uint8_t *o = out->data + (size_t)(y0 + j) * out->stride;
        memcpy(bd->bg, bd->hmax + (size_t)j * n, n);
        for (k = 1; k <= 2 * r; k++) {
            const uint8_t *h = bd->hmax + (size_t)(j + k) * n;
            for (i = 0; i < n; i++)
                bd->bg[i] = h[i] > bd->bg[i] ? h[i] : bd->bg[i];
        }
        memcpy(bd->tn, bd->tint + (size_t)j * w, w);
        for (k = 1; k <= 2 * R; k++) {
            const uint8_t *h = bd->tint + (size_t)(j + k) * w;
            for (i = 0; i < w; i++)
                bd->tn[i] = h[i] > bd->tn[i] ? h[i] : bd->tn[i];
        }
        for (x = 0; x < im->w; x++) {
            const uint8_t *v = row + 3 * x, *B = bd->bg + 3 * x;
            int t = bd->tn[x];
            if (!t || !(tab[td_palette_node(B)] & 0x80)) {
                memcpy(o + 3 * x, v, 3);
                continue;
            }
            for (c = 0; c < 3; c++) {
                int d = pal->ink[t - 1].rgb[c],
                    q = d > 0 ? (v[c] * P[c] + d / 2) / d : 255;
                o[3 * x + c] = (uint8_t)(q > 255 ? 255 : q);
            }
        }
    }
}

/* Contract in detint.h. */
int td_detint(const td_image *im, const td_palette *pal, int r, td_image *out,
              td_ctx *cx)
{
    uint8_t *tab;
    size_t n;
    int y0, fail = 0;
    if (!im || !out || !pal || im == out || im->channels != 3 ||
        out->channels != 3 || out->w != im->w || out->h != im->h || r < 1 ||
        r > MAX_RADIUS || pal->paper < 0 || pal->paper >= pal->n)
        return td_seterr(cx, TD_EINVAL,
                         "detint: bad images, radius or palette");
    if (!(tab = td_malloc(TD_PALETTE_LUT_SIZE, cx)))
        return TD_ENOMEM;
    tint_table(pal, tab);
    n = 3 * (size_t)im->w;
#pragma omp parallel
    {
        band bd;
        size_t R = (size_t)r + 1;
        bd.hmax = malloc((BAND + 2 * (size_t)r) * n + 1);
        bd.bg = malloc(n + 1);
        bd.tint = malloc((BAND + 2 * R) * (size_t)im->w + 1);
        bd.cls = malloc((size_t)im->w + 1);
        bd.tn = malloc((size_t)im->w + 1);
        if (!bd.hmax || !bd.bg || !bd.tint || !bd.cls || !bd.tn) {
#pragma omp atomic write
            fail = 1;
        }
#pragma omp for schedule(dynamic)
        for (y0 = 0; y0 < im->h; y0 += BAND)
            if (bd.hmax && bd.bg && bd.tint && bd.cls && bd.tn)
                do_band(im, pal, tab, r, &bd, out, y0);
        free(bd.hmax), free(bd.bg), free(bd.tint), free(bd.cls), free(bd.tn);
    }
    free(tab);
    return fail ? td_seterr(cx, TD_ENOMEM, "out of memory") : 0;
}
