/* profile.c: two DEMs along one line, sampled and drawn as a cross-section
 * plot (compare --profile: what a teacher shows of a reconstruction beside
 * the terrain it came from).  Pure stages: no file I/O. */
#include "src/compare/compare.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Bilinear sample of g at (x, y) in cells (0,0 the top-left corner); NaN
 * outside or when a corner has no data. */
static double sample(const td_grid_f32 *g, double x, double y)
{
    double fx, fy, v[4];
    long ix, iy;
    int k;
    x -= 0.5, y -= 0.5;
    if (x < 0)
        x = x > -0.5 ? 0 : x;
    if (y < 0)
        y = y > -0.5 ? 0 : y;
    ix = (long)floor(x), iy = (long)floor(y);
    fx = x - ix, fy = y - iy;
    for (k = 0; k < 4; k++) {
        long X = ix + (k & 1), Y = iy + (k >> 1);
        float f;
        if (X >= g->w && fx == 0 && (k & 1))
            X = g->w - 1;
        if (Y >= g->h && fy == 0 && (k >> 1))
            Y = g->h - 1;
        if (X < 0 || Y < 0 || X >= g->w || Y >= g->h)
            return NAN;
        f = g->data[(size_t)Y * g->w + X];
        if (!isfinite(f) || (g->has_nodata && f == g->nodata))
            return NAN;
        v[k] = f;
    }
    return (1 - fy) * ((1 - fx) * v[0] + fx * v[1]) +
           fy * ((1 - fx) * v[2] + fx * v[3]);
}

/* See compare.h. */
int td_compare_profile(const td_grid_f32 *a, const td_grid_f32 *b,
                       double x0, double y0, double x1, double y1, size_t n,
                       double *va, double *vb, td_ctx *cx)
{
    size_t i;
    if (a->w != b->w || a->h != b->h)
        return td_seterr(cx, TD_EINVAL, "profile: the DEMs differ in size "
                         "(%d x %d, %d x %d)", a->w, a->h, b->w, b->h);
    if (n < 2 || !isfinite(x0 + y0 + x1 + y1))
        return td_seterr(cx, TD_EINVAL, "profile: bad line");
    for (i = 0; i < n; i++) {
        double t = (double)i / (double)(n - 1);
        double x = x0 + t * (x1 - x0), y = y0 + t * (y1 - y0);
        va[i] = sample(a, x, y);
        vb[i] = sample(b, x, y);
    }
    return 0;
}

static void put(td_image *im, int x, int y, const uint8_t c[3])
{
    uint8_t *p;
    if (x < 0 || y < 0 || x >= im->w || y >= im->h)
        return;
    p = im->data + ((size_t)y * im->w + x) * 3;
    p[0] = c[0], p[1] = c[1], p[2] = c[2];
}

static void seg(td_image *im, double x0, double y0, double x1, double y1,
                const uint8_t c[3], int thick)
{
    int k, n = (int)ceil(fmax(fabs(x1 - x0), fabs(y1 - y0))) + 1, d;
    for (k = 0; k <= n; k++) {
        double t = (double)k / n;
        int x = (int)lround(x0 + t * (x1 - x0)), y = (int)lround(y0 + t * (y1 - y0));
        for (d = 0; d < thick; d++)
            put(im, x, y + d, c);
    }
}

/* A round tick step near span / 5 (1, 2, 5 x 10^k). */
static double tick_step(double span)
{
    double r = span / 5, p = pow(10, floor(log10(r))), m = r / p;
    return (m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10) * p;
}

/* See compare.h. */
int td_compare_profile_image(const double *va, const double *vb, size_t n,
                             double length, int w, int h, td_image **out,
                             td_ctx *cx)
{
    static const uint8_t black[3] = {0, 0, 0}, grey[3] = {215, 215, 215},
                         red[3] = {200, 30, 30}, ink[3] = {60, 60, 60};
    const int L = 70, R = 20, T = 20, B = 40; /* margins */
    double lo = HUGE_VAL, hi = -HUGE_VAL, st, v;
    td_image *im;
    size_t i;
    int k;
    *out = NULL;
    if (n < 2 || w < L + R + 40 || h < T + B + 40)
        return td_seterr(cx, TD_EINVAL, "profile: picture too small");
    for (i = 0; i < n; i++) {
        if (isfinite(va[i]))
            lo = fmin(lo, va[i]), hi = fmax(hi, va[i]);
        if (isfinite(vb[i]))
            lo = fmin(lo, vb[i]), hi = fmax(hi, vb[i]);
    }
    if (!(lo <= hi))
        return td_seterr(cx, TD_EINVAL, "profile: no data along the line");
    if (hi - lo < 1e-9)
        lo -= 1, hi += 1;
    st = tick_step(hi - lo);
    lo = floor(lo / st) * st, hi = ceil(hi / st) * st;
    if (!(im = td_image_new(w, h, 3, cx)))
        return TD_ENOMEM;
    memset(im->data, 255, (size_t)w * h * 3);
#define PX(i) (L + (double)(i) / (double)(n - 1) * (w - L - R))
#define PY(z) (h - B - ((z) - lo) / (hi - lo) * (h - T - B))
    for (v = lo; v <= hi + 1e-9 * st; v += st) { /* height ticks */
        char t[32];
        seg(im, L, PY(v), w - R, PY(v), grey, 1);
        snprintf(t, sizeof t, "%.10g", fabs(v) < 1e-9 * st ? 0.0 : v);
        td_draw_text(im, 4, (int)PY(v) - 5, t, 2, ink);
    }
    if (length > 0) { /* distance ticks */
        double ds = tick_step(length), d;
        for (d = 0; d <= length + 1e-9 * ds; d += ds) {
            char t[32];
            double x = L + d / length * (w - L - R);
            seg(im, x, h - B, x, h - B + 5, black, 1);
            snprintf(t, sizeof t, "%.10g", d);
            td_draw_text(im, (int)x - 4 * (int)strlen(t), h - B + 10, t, 2,
                         ink);
        }
    }
    seg(im, L, T, L, h - B, black, 1);
    seg(im, L, h - B, w - R, h - B, black, 1);
    for (k = 0; k < 2; k++) { /* B (the reference) black, A red on top */
        const double *p = k ? va : vb;
        for (i = 0; i + 1 < n; i++)
            if (isfinite(p[i]) && isfinite(p[i + 1]))
                seg(im, PX(i), PY(p[i]), PX(i + 1), PY(p[i + 1]),
                    k ? red : black, 2);
    }
#undef PX
#undef PY
    *out = im;
    return 0;
}
