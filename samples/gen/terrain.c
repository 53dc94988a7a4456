/* terrain.c: analytic truth surfaces for synthetic sheets.
 *
 * Every shape but the cone is a sum of separable terms
 *     h(x,y) = c + sum_k X_k(x) * Y_k(y)
 * (a Gaussian is exp(-dx^2/2s^2) * exp(-dy^2/2s^2), a plane wave
 * sin(ax + by + p) = sin(ax + p) cos(by) + cos(ax + p) sin(by), a tilt is
 * t*x * 1), so the per-pixel cost is a few multiply-adds over tables of
 * one row and one column: a 10000 x 10000 DEM takes well under a second. */
#include "samples/gen/gen.h"
#include "samples/gen/gen_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_TERMS 12

typedef struct sep_terms {
    int n;
    double c;             /* constant */
    double *x[MAX_TERMS]; /* w values each */
    double *y[MAX_TERMS]; /* h values each */
} sep_terms;

td_gen_params td_gen_defaults(void)
{
    td_gen_params p;
    memset(&p, 0, sizeof p);
    p.w = 1000;
    p.h = 1000;
    p.seed = 1;
    p.terrain = TD_GEN_HILLS;
    p.base = 0.0;
    p.interval = 0.0;
    p.line_width = 2.0;
    p.break_min = 1.0;
    p.break_max = 3.0;
    p.fringe[0] = 0.6;
    return p;
}

static void terms_free(sep_terms *t)
{
    int k;
    for (k = 0; k < t->n; k++) {
        free(t->x[k]);
        free(t->y[k]);
    }
    t->n = 0;
}

/* Append a term; its tables are left for the caller to fill. */
static int term_add(sep_terms *t, int w, int h, double **X, double **Y,
                    td_ctx *cx)
{
    if (t->n >= MAX_TERMS)
        return td_seterr(cx, TD_EINTERNAL, "terrain: too many terms");
    t->x[t->n] = td_malloc((size_t)w * sizeof(double), cx);
    t->y[t->n] = td_malloc((size_t)h * sizeof(double), cx);
    if (!t->x[t->n] || !t->y[t->n]) {
        free(t->x[t->n]);
        free(t->y[t->n]);
        return TD_ENOMEM;
    }
    *X = t->x[t->n];
    *Y = t->y[t->n];
    t->n++;
    return 0;
}

/* amp * exp(-((x-cx)^2 + (y-cy)^2) / (2 s^2)), all in pixels. */
static int add_gauss(sep_terms *t, int w, int h, double gx, double gy, double s,
                     double amp, td_ctx *cx)
{
    double *X, *Y;
    int i, rc = term_add(t, w, h, &X, &Y, cx);
    if (rc)
        return rc;
    for (i = 0; i < w; i++) {
        double d = (i + 0.5 - gx) / s;
        X[i] = amp * exp(-0.5 * d * d);
    }
    for (i = 0; i < h; i++) {
        double d = (i + 0.5 - gy) / s;
        Y[i] = exp(-0.5 * d * d);
    }
    return 0;
}

/* A plane tx * (x - w/2) + ty * (y - h/2) (slopes per pixel). */
static int add_tilt(sep_terms *t, int w, int h, double tx, double ty,
                    td_ctx *cx)
{
    double *X, *Y;
    int i, rc = term_add(t, w, h, &X, &Y, cx);
    if (rc)
        return rc;
    for (i = 0; i < w; i++)
        X[i] = tx * (i + 0.5 - 0.5 * w);
    for (i = 0; i < h; i++)
        Y[i] = 1.0;
    if ((rc = term_add(t, w, h, &X, &Y, cx)) != 0)
        return rc;
    for (i = 0; i < w; i++)
        X[i] = 1.0;
    for (i = 0; i < h; i++)
        Y[i] = ty * (i + 0.5 - 0.5 * h);
    return 0;
}

/* amp * sin(a x + b y + ph) as two separable terms. */
static int add_wave(sep_terms *t, int w, int h, double a, double b, double ph,
                    double amp, td_ctx *cx)
{
    double *X1, *Y1, *X2, *Y2;
    int i, rc;
    if ((rc = term_add(t, w, h, &X1, &Y1, cx)) != 0 ||
        (rc = term_add(t, w, h, &X2, &Y2, cx)) != 0)
        return rc;
    for (i = 0; i < w; i++) {
        X1[i] = amp * sin(a * (i + 0.5) + ph);
        X2[i] = amp * cos(a * (i + 0.5) + ph);
    }
    for (i = 0; i < h; i++) {
        Y1[i] = cos(b * (i + 0.5));
        Y2[i] = sin(b * (i + 0.5));
    }
    return 0;
}

/* HILLS: summits A and B 2.8 sigma apart (a saddle between them, rings
 * around each and common rings around both), summit C, depression D, tilt.
 * Positions in units of S from the sheet centre, jittered by the seed. */
static int hills_terms(const td_gen_params *p, sep_terms *t, td_ctx *cx)
{
    static const double f[4][4] = {
        /* u, v, sigma, amplitude */
        {-0.20, -0.10, 0.100, 200.0},
        {0.07, -0.16, 0.095, 180.0},
        {0.24, 0.20, 0.085, 150.0},
        {-0.18, 0.24, 0.075, -100.0},
    };
    td_rng r = td_rng_make(p->seed, 1);
    double S = p->w < p->h ? p->w : p->h;
    double du = td_rng_range(&r, -0.03, 0.03),
           dv = td_rng_range(&r, -0.03, 0.03);
    double ang = td_rng_range(&r, 0.0, 2.0 * TD_PI);
    int k, rc;
    t->c = 160.0;
    for (k = 0; k < 4; k++) {
        /* A and B move together so the saddle stays */
        double ju = k < 2 ? du : td_rng_range(&r, -0.03, 0.03);
        double jv = k < 2 ? dv : td_rng_range(&r, -0.03, 0.03);
        double amp = f[k][3] * td_rng_range(&r, 0.92, 1.08);
        rc = add_gauss(t, p->w, p->h, 0.5 * p->w + (f[k][0] + ju) * S,
                       0.5 * p->h + (f[k][1] + jv) * S, f[k][2] * S, amp, cx);
        if (rc)
            return rc;
    }
    return add_tilt(t, p->w, p->h, 120.0 / S * cos(ang), 120.0 / S * sin(ang),
                    cx);
}

/* RIDGES: four plane waves of absolute wavelength 350..900 px in spread
 * directions; each has slope amplitude G, so the steepest slope is <= 4G. */
static int ridges_terms(const td_gen_params *p, sep_terms *t, td_ctx *cx)
{
    const double G = 0.36;
    td_rng r = td_rng_make(p->seed, 2);
    int k, rc;
    t->c = 300.0;
    for (k = 0; k < 4; k++) {
        double lam = td_rng_range(&r, 350.0, 900.0);
        double th = k * TD_PI / 4.0 + td_rng_range(&r, -0.3, 0.3);
        double kk = 2.0 * TD_PI / lam;
        double ph = td_rng_range(&r, 0.0, 2.0 * TD_PI);
        rc =
            add_wave(t, p->w, p->h, kk * cos(th), kk * sin(th), ph, G / kk, cx);
        if (rc)
            return rc;
    }
    return 0;
}

static int plane_terms(const td_gen_params *p, sep_terms *t, td_ctx *cx)
{
    td_rng r = td_rng_make(p->seed, 3);
    double S = p->w < p->h ? p->w : p->h;
    double ang = td_rng_range(&r, 0.35, 1.2); /* away from the axes */
    t->c = 200.0;
    return add_tilt(t, p->w, p->h, 300.0 / S * cos(ang), 300.0 / S * sin(ang),
                    cx);
}

/* VALLEYS: the thalwegs as fractions of the sheet (x0, y0, x1, y1). */
static const double valley_seg[5][4] = {
    {0.50, 0.00, 0.50, 1.00}, /* main valley, flowing down the sheet */
    {0.15, 0.05, 0.50, 0.55}, /* tributaries joining it */
    {0.85, 0.02, 0.50, 0.40},
    {0.05, 0.50, 0.50, 0.85},
    {0.95, 0.45, 0.50, 0.75},
};

size_t td_gen_valley_segments(const td_gen_params *p, double (*seg)[4],
                              size_t max)
{
    size_t k;
    for (k = 0; k < 5 && k < max; k++) {
        seg[k][0] = valley_seg[k][0] * p->w, seg[k][1] = valley_seg[k][1] * p->h;
        seg[k][2] = valley_seg[k][2] * p->w, seg[k][3] = valley_seg[k][3] * p->h;
    }
    return 5;
}

static double seg_dist2(double x, double y, const double *s)
{
    double dx = s[2] - s[0], dy = s[3] - s[1];
    double t = ((x - s[0]) * dx + (y - s[1]) * dy) / (dx * dx + dy * dy);
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    dx = x - s[0] - t * dx, dy = y - s[1] - t * dy;
    return dx * dx + dy * dy;
}

static void fill_valleys(const td_gen_params *p, td_grid_f32 *g)
{
    double seg[5][4], k = 6;
    int i, j, m;
    td_gen_valley_segments(p, seg, 5);
    for (i = 0; i < g->h; i++) {
        float *out = g->data + (size_t)i * g->stride;
        for (j = 0; j < g->w; j++) {
            double x = j + 0.5, y = i + 0.5, sum = 0;
            for (m = 0; m < 5; m++)
                sum += exp(-0.35 * sqrt(seg_dist2(x, y, seg[m]) + 64) / k);
            out[j] = (float)(0.3 * (p->h - y) - k * log(sum));
        }
    }
}

/* Pixel by pixel over the term tables (one pass over memory per row). */
static int fill_terms(const sep_terms *t, td_grid_f32 *g, td_ctx *cx)
{
    double fy[MAX_TERMS];
    int i, j, k;
    (void)cx;
    for (i = 0; i < g->h; i++) {
        float *out = g->data + (size_t)i * g->stride;
        for (k = 0; k < t->n; k++)
            fy[k] = t->y[k][i];
        for (j = 0; j < g->w; j++) {
            double v = t->c;
            for (k = 0; k < t->n; k++)
                v += fy[k] * t->x[k][j];
            out[j] = (float)v;
        }
    }
    return 0;
}

static void fill_cone(const td_gen_params *p, td_grid_f32 *g)
{
    double S = p->w < p->h ? p->w : p->h, R = 0.45 * S;
    int i, j;
    for (i = 0; i < g->h; i++) {
        double dy = i + 0.5 - 0.5 * p->h;
        float *out = g->data + (size_t)i * g->stride;
        for (j = 0; j < g->w; j++) {
            double dx = j + 0.5 - 0.5 * p->w;
            out[j] = (float)(400.0 * (1.0 - sqrt(dx * dx + dy * dy) / R));
        }
    }
}

/* Catmull-Rom weights for fraction t in [0,1). */
static void cr_weights(double t, double *w)
{
    double t2 = t * t, t3 = t2 * t;
    w[0] = 0.5 * (-t3 + 2 * t2 - t);
    w[1] = 0.5 * (3 * t3 - 5 * t2 + 2);
    w[2] = 0.5 * (-3 * t3 + 4 * t2 + t);
    w[3] = 0.5 * (t3 - t2);
}

static int clampi(long v, int n)
{
    return v < 0 ? 0 : v >= n ? n - 1 : (int)v;
}

/* A real DEM stretched over the sheet (bicubic, edges clamped).  Source
 * cell c's centre sits at sheet x = (c + 0.5) * w / sw. */
static int fill_dem(const td_gen_params *p, td_grid_f32 *g, td_ctx *cx)
{
    const td_grid_f32 *s = p->dem_in;
    double sx, sy;
    int i, j, k, m;
    if (!s || s->w < 2 || s->h < 2)
        return td_seterr(cx, TD_EINVAL, "terrain: no source DEM");
    sx = (double)s->w / p->w;
    sy = (double)s->h / p->h;
    for (i = 0; i < s->h; i++)
        for (j = 0; j < s->w; j++)
            if (!isfinite(TD_AT(s, j, i)) || TD_AT(s, j, i) == s->nodata)
                return td_seterr(cx, TD_EINVAL, "terrain: source DEM has a "
                                 "nodata cell at column %d, row %d", j, i);
    for (i = 0; i < g->h; i++) {
        double fy = (i + 0.5) * sy - 0.5, wy[4];
        long y0 = (long)floor(fy);
        float *out = g->data + (size_t)i * g->stride;
        cr_weights(fy - y0, wy);
        for (j = 0; j < g->w; j++) {
            double fx = (j + 0.5) * sx - 0.5, wx[4], z = 0;
            long x0 = (long)floor(fx);
            cr_weights(fx - x0, wx);
            for (k = 0; k < 4; k++) {
                const float *row = s->data + (size_t)clampi(y0 - 1 + k, s->h) *
                                                 s->stride;
                double r = 0;
                for (m = 0; m < 4; m++)
                    r += wx[m] * row[clampi(x0 - 1 + m, s->w)];
                z += wy[k] * r;
            }
            out[j] = (float)z;
        }
    }
    return 0;
}

/* Contract in gen.h. */
int td_gen_terrain(const td_gen_params *p, td_grid_f32 **dem, td_ctx *cx)
{
    sep_terms t;
    td_grid_f32 *g = NULL;
    int rc = 0;
    memset(&t, 0, sizeof t);
    *dem = NULL;
    if (!(g = td_grid_f32_new(p->w, p->h, cx)))
        return cx && cx->code ? cx->code : TD_ENOMEM;
    switch (p->terrain) {
    case TD_GEN_HILLS:
        rc = hills_terms(p, &t, cx);
        break;
    case TD_GEN_RIDGES:
        rc = ridges_terms(p, &t, cx);
        break;
    case TD_GEN_PLANE:
        rc = plane_terms(p, &t, cx);
        break;
    case TD_GEN_CONE:
        fill_cone(p, g);
        break;
    case TD_GEN_VALLEYS:
        fill_valleys(p, g);
        break;
    case TD_GEN_DEM:
        rc = fill_dem(p, g, cx);
        break;
    default:
        rc = td_seterr(cx, TD_EINVAL, "terrain: unknown kind %d",
                       (int)p->terrain);
    }
    if (rc)
        goto fail;
    if (p->terrain != TD_GEN_CONE && p->terrain != TD_GEN_VALLEYS &&
        p->terrain != TD_GEN_DEM && (rc = fill_terms(&t, g, cx)) != 0)
        goto fail;
    terms_free(&t);
    *dem = g;
    return 0;
fail:
    terms_free(&t);
    td_grid_f32_free(g);
    return rc;
}

/* Squared slope at (i,j): central differences, one-sided at the border. */
static double slope2_at(const td_grid_f32 *g, int i, int j)
{
    int jl = j > 0 ? j - 1 : j, jr = j + 1 < g->w ? j + 1 : j;
    int iu = i > 0 ? i - 1 : i, id = i + 1 < g->h ? i + 1 : i;
    double gx =
        jr > jl ? ((double)TD_AT(g, jr, i) - TD_AT(g, jl, i)) / (jr - jl) : 0;
    double gy =
        id > iu ? ((double)TD_AT(g, j, id) - TD_AT(g, j, iu)) / (id - iu) : 0;
    return gx * gx + gy * gy;
}

/* Contract in gen.h. */
double td_gen_max_slope(const td_grid_f32 *dem)
{
    double best = 0.0;
    int i, j;
    for (i = 0; i < dem->h; i++) {
        const float *r = dem->data + (size_t)i * dem->stride;
        int inner = i > 0 && i + 1 < dem->h;
        float b = 0.0f; /* interior: 4 * squared slope, in float */
        for (j = 1; inner && j + 1 < dem->w; j++) {
            float gx = r[j + 1] - r[j - 1];
            float gy = r[j + dem->stride] - r[j - dem->stride];
            float g2 = gx * gx + gy * gy;
            b = g2 > b ? g2 : b;
        }
        if (0.25 * b > best) /* recheck the row's maximum in double */
            for (j = 1; j + 1 < dem->w; j++)
                best = fmax(best, slope2_at(dem, i, j));
        if (inner) {
            best = fmax(best, slope2_at(dem, i, 0));
            best = fmax(best, slope2_at(dem, i, dem->w - 1));
        } else {
            for (j = 0; j < dem->w; j++)
                best = fmax(best, slope2_at(dem, i, j));
        }
    }
    return sqrt(best);
}

/* The 98th percentile of the slope (height units per px), from a histogram
 * of every 4th cell of every 4th row. */
static double slope_p98(const td_grid_f32 *dem)
{
    enum { NB = 4096 };
    static const double top = 20.0; /* m/px: anything steeper in the last bin */
    size_t hist[NB], n = 0, acc = 0;
    int i, j, b;
    memset(hist, 0, sizeof hist);
    for (i = 0; i < dem->h; i += 4)
        for (j = 0; j < dem->w; j += 4) {
            double s = sqrt(slope2_at(dem, i, j)) / top * NB;
            hist[s >= NB - 1 ? NB - 1 : (int)s]++;
            n++;
        }
    for (b = 0; b < NB; b++)
        if ((acc += hist[b]) >= 0.98 * n)
            break;
    return (b + 1) * top / NB;
}

/* Contract in gen.h. */
double td_gen_auto_interval(const td_gen_params *p, const td_grid_f32 *dem)
{
    static const double m[4] = {1.0, 2.0, 2.5, 5.0};
    double need, dec;
    int k;
    if (p->interval > 0.0)
        return p->interval;
    need = 6.5 * (p->terrain == TD_GEN_DEM ? slope_p98(dem)
                                            : td_gen_max_slope(dem));
    if (need < 10.0)
        need = 10.0;
    for (dec = 1.0; dec < 1e12; dec *= 10.0)
        for (k = 0; k < 4; k++)
            if (m[k] * dec >= need - 1e-9)
                return m[k] * dec;
    return need;
}
