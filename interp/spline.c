/* spline.c: a C2 arc-length curve per contour and its signed curvature
 * (003 §4, Fig. 1; ALGORITHMS.md B2 steps 1-2).
 *
 * The paper threads a quintic spline through the sample points.  Traced
 * contours are pixel staircases: an interpolating spline through them has
 * a curvature that flips sign at every step.  So each contour is
 * resampled at equal arc length (spacing, 2 px), smoothed along the curve
 * with a Gaussian (smooth, 3 px; periodic on rings, truncated and
 * renormalised at open ends), and a cubic spline interpolates the smoothed
 * samples.  The cubic is already C2, all kappa = (f' x f'')_z / |f'|^3
 * needs; the quintic's extra continuity buys nothing once the data are
 * smoothed.  The spline's second derivatives M solve, for knots h apart,
 *
 *     M[i-1] + 4 M[i] + M[i+1] = 6 (y[i+1] - 2 y[i] + y[i-1]) / h^2
 *
 * (cyclic on rings, M = 0 at open ends), by Gauss-Seidel: the system is
 * diagonally dominant (4 against 1 + 1), each sweep halves the error. */
#include "interp/homotopy_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void hm_curve_free(td_rv_curve *c)
{
    if (!c)
        return;
    free(c->x);
    free(c->y);
    free(c->s);
    free(c->kappa);
    free(c->oxy);
    free(c->ocum);
    memset(c, 0, sizeof *c);
}

void hm_curve_at(const td_rv_curve *c, double s, double *x, double *y)
{
    size_t hint = 0;
    hm_curve_at_hint(c, s, x, y, &hint);
}

void hm_curve_at_hint(const td_rv_curve *c, double s, double *x, double *y,
                      size_t *hint)
{
    size_t lo = 0, hi, i, j, k;
    double t, seg;
    if (c->no == 1 || c->len <= 0) {
        *x = c->oxy[0], *y = c->oxy[1];
        return;
    }
    if (c->closed)
        s = fmod(fmod(s, c->len) + c->len, c->len);
    else
        s = fmin(fmax(s, 0), c->len);
    hi = c->closed ? c->no : c->no - 1; /* ocum[hi] = len */
    for (k = *hint, i = 0; i < 4 && k < hi; i++, k++) /* walking forward */
        if (c->ocum[k] <= s && s < c->ocum[k + 1])
            break;
    if (i < 4 && k < hi && c->ocum[k] <= s && s < c->ocum[k + 1])
        lo = k;
    else
        while (hi - lo > 1) {
            size_t m = (lo + hi) / 2;
            if (c->ocum[m] <= s)
                lo = m;
            else
                hi = m;
        }
    *hint = lo;
    i = lo, j = (lo + 1) % c->no;
    seg = c->ocum[lo + 1] - c->ocum[lo];
    t = seg > 0 ? (s - c->ocum[lo]) / seg : 0;
    *x = c->oxy[2 * i] + t * (c->oxy[2 * j] - c->oxy[2 * i]);
    *y = c->oxy[2 * i + 1] + t * (c->oxy[2 * j + 1] - c->oxy[2 * i + 1]);
}

/* The oriented copy of l and its cumulative lengths. */
static int copy_oriented(const td_line *l, int orient, td_rv_curve *c,
                         td_ctx *cx)
{
    size_t i, n = l->n;
    if (!(c->oxy = td_malloc(2 * n * sizeof *c->oxy, cx)) ||
        !(c->ocum = td_malloc((n + 1) * sizeof *c->ocum, cx)))
        return TD_ENOMEM;
    for (i = 0; i < n; i++) {
        size_t k = orient < 0 ? n - 1 - i : i;
        c->oxy[2 * i] = l->xy[2 * k];
        c->oxy[2 * i + 1] = l->xy[2 * k + 1];
    }
    c->no = n;
    c->ocum[0] = 0;
    for (i = 1; i <= n; i++) {
        size_t a = i - 1, b = i % n;
        if (i == n && !c->closed) {
            c->ocum[n] = c->ocum[n - 1];
            break;
        }
        c->ocum[i] = c->ocum[i - 1] + hypot(c->oxy[2 * b] - c->oxy[2 * a],
                                            c->oxy[2 * b + 1] - c->oxy[2 * a + 1]);
    }
    c->len = c->closed ? c->ocum[n] : c->ocum[n - 1];
    return 0;
}

/* Gaussian smoothing of v (n samples, sigma in samples) into out; wk:
 * scratch for the 3 sigma + 1 weights. */
static void smooth1(const double *v, size_t n, int closed, double sigma,
                    double *wk, double *out)
{
    long r = (long)ceil(3 * sigma), i, k, nn = (long)n;
    for (k = 0; k <= r; k++)
        wk[k] = exp(-0.5 * k * k / (sigma * sigma));
    for (i = 0; i < nn; i++) {
        double sw = 0, s = 0;
        if (!closed && (i == 0 || i == nn - 1)) {
            out[i] = v[i];
            continue;
        }
        for (k = -r; k <= r; k++) {
            long j = i + k;
            if (closed)
                j = ((j % nn) + nn) % nn;
            else if (j < 0 || j >= nn)
                continue;
            s += wk[k < 0 ? -k : k] * v[j];
            sw += wk[k < 0 ? -k : k];
        }
        out[i] = s / sw;
    }
}

/* Second derivatives of the cubic spline through v (knots h apart):
 * started from the second differences, which the smoothed data make
 * close to the solution, then Gauss-Seidel sweeps (each at least halves
 * the error: 20 sweeps, 1e-6 of the start's error). */
static void spline_m(const double *v, size_t n, int closed, double h,
                     double *m)
{
    size_t i, it;
    double k = 6 / (h * h);
    if (n < 3)
        return;
    for (i = 1; i + 1 < n; i++)
        m[i] = (v[i + 1] - 2 * v[i] + v[i - 1]) / (h * h);
    m[0] = closed ? (v[1] - 2 * v[0] + v[n - 1]) / (h * h) : 0;
    m[n - 1] = closed ? (v[0] - 2 * v[n - 1] + v[n - 2]) / (h * h) : 0;
    for (it = 0; it < 20; it++) {
        if (closed)
            m[0] = (k * (v[1] - 2 * v[0] + v[n - 1]) - m[n - 1] - m[1]) / 4;
        for (i = 1; i + 1 < n; i++)
            m[i] = (k * (v[i + 1] - 2 * v[i] + v[i - 1]) - m[i - 1] - m[i + 1]) / 4;
        if (closed)
            m[n - 1] = (k * (v[0] - 2 * v[n - 1] + v[n - 2]) - m[n - 2] - m[0]) / 4;
    }
}

/* First derivative of the spline at knot i. */
static double spline_d1(const double *v, const double *m, size_t n, int closed,
                        double h, size_t i)
{
    if (closed || i + 1 < n) {
        size_t b = (i + 1) % n;
        return (v[b] - v[i]) / h - h * (2 * m[i] + m[b]) / 6;
    }
    return (v[i] - v[i - 1]) / h + h * (m[i - 1] + 2 * m[i]) / 6;
}

/* Resample, smooth, fit and take kappa (y-up frame: the pixel frame's
 * cross product with its sign flipped). */
static int fit(td_rv_curve *c, const td_homotopy_params *p, td_ctx *cx)
{
    size_t n, i, k;
    double h, *tmp = NULL, *mx = NULL, *my = NULL;
    int rc = TD_ENOMEM;
    n = (size_t)fmax(c->closed ? 4 : 2, floor(c->len / p->spacing + 0.5) +
                                            (c->closed ? 0 : 1));
    h = c->len / (double)(c->closed ? n : n - 1);
    if (!(c->x = td_malloc(n * sizeof(double), cx)) ||
        !(c->y = td_malloc(n * sizeof(double), cx)) ||
        !(c->s = td_malloc(n * sizeof(double), cx)) ||
        !(c->kappa = td_calloc(n, sizeof(double), cx)) ||
        !(tmp = td_malloc(n * sizeof *tmp, cx)) ||
        !(mx = td_malloc(n * sizeof *mx, cx)) ||
        !(my = td_malloc(n * sizeof *my, cx)))
        goto fail;
    c->n = n;
    for (i = 0, k = 0; i < n; i++) {
        c->s[i] = i * h;
        hm_curve_at_hint(c, c->s[i], &c->x[i], &c->y[i], &k);
    }
    if (h > 0 && p->smooth > 0) {
        double sg = fmin(p->smooth / h, (double)n); /* wider is pointless */
        double *wk = td_malloc(((size_t)ceil(3 * sg) + 1) * sizeof *wk, cx);
        if (!wk)
            goto fail;
        smooth1(c->x, n, c->closed, sg, wk, tmp);
        memcpy(c->x, tmp, n * sizeof *tmp);
        smooth1(c->y, n, c->closed, sg, wk, tmp);
        memcpy(c->y, tmp, n * sizeof *tmp);
        free(wk);
    }
    if (h > 0 && n >= 3) {
        spline_m(c->x, n, c->closed, h, mx);
        spline_m(c->y, n, c->closed, h, my);
        for (i = 0; i < n; i++) {
            double dx = spline_d1(c->x, mx, n, c->closed, h, i);
            double dy = spline_d1(c->y, my, n, c->closed, h, i);
            double d2 = dx * dx + dy * dy, d = d2 * sqrt(d2);
            c->kappa[i] = d > 0 ? -(dx * my[i] - dy * mx[i]) / d : 0;
        }
    }
    rc = 0;
fail:
    free(tmp);
    free(mx);
    free(my);
    return rc;
}

int hm_curve_build(const td_line *l, long index, int orient,
                   const td_homotopy_params *p, td_rv_curve *c, td_ctx *cx)
{
    int rc;
    memset(c, 0, sizeof *c);
    c->line = index;
    c->closed = l->closed && l->n > 2;
    c->orient = orient;
    c->z = l->height;
    if (l->n == 0)
        return 0;
    if ((rc = copy_oriented(l, orient, c, cx)) != 0)
        return rc;
    return fit(c, p, cx);
}
