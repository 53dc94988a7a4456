/* defringe.c: colour fringes and bled colour taken out of a colour scan
 * (model and contract in defringe.h).
 *
 * Row bands of BAND rows; a band reads r + r_bg rows either side (edges
 * held):
 *
 *   rows  y0-r-rbg .. y1+r+rbg : hmax  (per-channel max across 2 rbg + 1)
 *   rows  y0-r     .. y1+r     : bg (max of hmax down 2 rbg + 1), f
 *   rows  y0       .. y1       : F (the weighted window of f), v'
 */
#include "scanner/defringe.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define BAND 32
#define MAX_RADIUS 8

td_defringe_params td_defringe_defaults(void)
{
    td_defringe_params p;
    p.radius = 3;
    p.bg_radius = 3;
    return p;
}

static int clampi(int v, int lo, int hi)
{
    return v < lo ? lo : v > hi ? hi : v;
}

typedef struct band {
    uint8_t *hmax; /* (BAND + 2 r + 2 rbg) rows of 3 w */
    uint8_t *bg;   /* (BAND + 2 r) rows */
    float *f;      /* (BAND + 2 r) rows */
    float *t;      /* (BAND + 2 r) rows: f summed across */
} band;

/* Contract in defringe.h. */
void td_rgb_row_max(const td_image *im, int y, int r, uint8_t *out)
{
    const uint8_t *row =
        im->data + (size_t)clampi(y, 0, im->h - 1) * im->stride;
    int x, k, c;
    for (x = 0; x < im->w; x++)
        for (c = 0; c < 3; c++) {
            uint8_t m = 0;
            for (k = -r; k <= r; k++) {
                uint8_t v = row[3 * clampi(x + k, 0, im->w - 1) + c];
                m = v > m ? v : m;
            }
            out[3 * x + c] = m;
        }
}

/* bg and f of row y (band row j), from hmax rows j .. j + 2 rbg. */
static void row_f(const td_image *im, int y, int rbg, const band *b, int j)
{
    size_t n = 3 * (size_t)im->w, i;
    const uint8_t *row =
        im->data + (size_t)clampi(y, 0, im->h - 1) * im->stride;
    uint8_t *bg = b->bg + (size_t)j * n;
    float *f = b->f + (size_t)j * n;
    int k;
    memcpy(bg, b->hmax + (size_t)j * n, n);
    for (k = 1; k <= 2 * rbg; k++) {
        const uint8_t *h = b->hmax + (size_t)(j + k) * n;
        for (i = 0; i < n; i++)
            bg[i] = h[i] > bg[i] ? h[i] : bg[i];
    }
    for (i = 0; i < n; i++)
        f[i] = bg[i] > 0 ? 1.0f - (float)row[i] / (float)bg[i] : 0.0f;
}

/* t = f of band row j summed across x - r .. x + r (edges held). */
static void row_sum(int w, int r, const band *b, int j)
{
    size_t n = 3 * (size_t)w;
    const float *f = b->f + (size_t)j * n;
    float *t = b->t + (size_t)j * n;
    int x, k, c;
    for (c = 0; c < 3; c++) { /* a running sum */
        float s = 0;
        for (k = -r; k <= r; k++)
            s += f[3 * clampi(k, 0, w - 1) + c];
        for (x = 0; x < w; x++) {
            t[3 * x + c] = s;
            s += f[3 * clampi(x + r + 1, 0, w - 1) + c] -
                 f[3 * clampi(x - r, 0, w - 1) + c];
        }
    }
}

/* Output row y (band row j + r): F down the window of t, then v'. */
static void row_out(const td_image *im, int r, const band *b, int j, int y,
                    uint8_t *out)
{
    size_t n = 3 * (size_t)im->w;
    const uint8_t *row = im->data + (size_t)y * im->stride;
    const uint8_t *bg = b->bg + (size_t)(j + r) * n;
    const float *f = b->f + (size_t)(j + r) * n;
    int x, k, c;
    for (x = 0; x < im->w; x++) {
        const float *fp = f + 3 * x;
        float F[3] = {0, 0, 0}, lf, lF;
        lf = 0.299f * fp[0] + 0.587f * fp[1] + 0.114f * fp[2];
        for (k = 0; k <= 2 * r; k++) {
            const float *t = b->t + (size_t)(j + k) * n + 3 * x;
            F[0] += t[0], F[1] += t[1], F[2] += t[2];
        }
        lF = 0.299f * F[0] + 0.587f * F[1] + 0.114f * F[2];
        if (lf < (float)TD_DEFRINGE_MIN || lF <= 1e-6f) {
            memcpy(out + 3 * x, row + 3 * x, 3);
            continue;
        }
        for (c = 0; c < 3; c++) {
            float a = F[c] * lf / lF, v;
            a = a < 0 ? 0 : a > 1 ? 1 : a;
            v = (float)bg[3 * x + c] * (1.0f - a);
            out[3 * x + c] = (uint8_t)(v + 0.5f);
        }
    }
}

static void do_band(const td_image *im, td_image *out,
                    const td_defringe_params *p, const band *b, int y0)
{
    int r = p->radius, rbg = p->bg_radius, y1 = y0 + BAND, j, nf;
    y1 = y1 > im->h ? im->h : y1;
    nf = y1 - y0 + 2 * r;
    for (j = 0; j < nf + 2 * rbg; j++)
        td_rgb_row_max(im, y0 - r - rbg + j, rbg,
                       b->hmax + (size_t)j * 3 * im->w);
    for (j = 0; j < nf; j++) {
        row_f(im, y0 - r + j, rbg, b, j);
        row_sum(im->w, r, b, j);
    }
    for (j = 0; j < y1 - y0; j++)
        row_out(im, r, b, j, y0 + j,
                out->data + (size_t)(y0 + j) * out->stride);
}

/* Contract in defringe.h. */
int td_defringe(const td_image *im, td_image *out, const td_defringe_params *p,
                td_ctx *cx)
{
    int y0, fail = 0;
    size_t n;
    if (!im || !out || im == out || im->channels != 3 || out->channels != 3 ||
        out->w != im->w || out->h != im->h || p->radius < 0 ||
        p->radius > MAX_RADIUS || p->bg_radius < 0 || p->bg_radius > MAX_RADIUS)
        return td_seterr(cx, TD_EINVAL, "defringe: bad images or radii");
    n = 3 * (size_t)im->w;
#pragma omp parallel
    {
        band b;
        size_t rows = BAND + 2 * (size_t)p->radius;
        b.hmax = malloc((rows + 2 * (size_t)p->bg_radius) * n);
        b.bg = malloc(rows * n);
        b.f = malloc(rows * n * sizeof *b.f);
        b.t = malloc(rows * n * sizeof *b.t);
        if (!b.hmax || !b.bg || !b.f || !b.t) {
#pragma omp atomic write
            fail = 1;
        }
#pragma omp for schedule(dynamic)
        for (y0 = 0; y0 < im->h; y0 += BAND)
            if (b.hmax && b.bg && b.f && b.t)
                do_band(im, out, p, &b, y0);
        free(b.hmax);
        free(b.bg);
        free(b.f);
        free(b.t);
    }
    return fail ? td_seterr(cx, TD_ENOMEM, "out of memory") : 0;
}
