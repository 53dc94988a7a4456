/* horizon.c: horizon angles by profile sweeps with an upper convex hull.
 *
 * Paper 000 §3.2, Alg. 3.1: for each of k directions cut the DEM into
 * parallel profiles along the direction and find, in one pass per profile,
 * the elevation angle of every point's horizon.  The paper's procedure
 * walks peaks and inflection points with a forward index; ours (same idea,
 * exact and simpler to prove) keeps the upper convex hull of the profile
 * points already passed on a stack:
 *
 *   height                                  far  <---- sweep ----  near
 *     |          B                          points enter the hull from the
 *     |        .' `.     D                  near end; a new point pops
 *     |  P   .'     `. .' `.                every hull vertex on or under
 *     | .  .'         C     `E              the segment from it to the
 *     +--------------------------> X        vertex below (here C), so each
 *                                           point is pushed and popped once;
 *   an observer P finds its horizon point (B) by climbing the stack from
 *   the vertex the previous observer found (bisection after a few steps).
 *
 * The surface is the bilinear interpolation of the cell centres, and the
 * reference is a ray from each cell centre along the azimuth.  Geometry
 * (ours): the azimuth is mapped onto a major axis k (the one it advances
 * along fastest, k growing in the look direction) and a minor axis j,
 * so the ray moves a = dj/dk (|a| <= 1) per major step.
 *
 *   profiles   lines j = q + a k, q integer: one per minor unit, stepping
 *              one major cell at a time and sampled at every whole k,
 *              linearly between the two cells of that column (the bilinear
 *              surface there).  The crossings of whole j between columns
 *              (x below), where the surface along the line has its other
 *              kinks, are left out of the profiles: beyond NEAR steps they
 *              changed no test result, and the rays' own marches (near
 *              field, tails) do include them.
 *
 *        k ->    0     1     2     3
 *        j=2     .     .     .   x-o--     o  profile sample
 *        j=1     .   x-o-----o-x   .       x  whole-j crossing
 *        j=0     o-x   .     .     .
 *
 *   cells      cell (k, j) lies between the profiles q0 = floor(j - a k)
 *              and q0 + 1, at fractions f and 1 - f of a minor unit from
 *              them; it asks both hulls for its horizon tangent (its own
 *              height, its own position along the azimuth) and takes
 *              (1 - f) t(q0) + f t(q0 + 1): the lateral error of either
 *              profile is first order in f, of the blend second order.
 *   near field the blend is good where the horizon is a few cells away;
 *              near the cell the terrain's lateral slope would dominate.
 *              So profiles enter their hull only points NEAR or more major
 *              steps beyond the observer, and every cell marches its own
 *              ray over the first NEAR steps exactly: every grid-line
 *              crossing is a fixed two-cell stencil (same offsets and
 *              weights for all cells), the exact interior peak of every
 *              bilinear piece within MIDS steps (a piece is a quadratic
 *              in t; see piece_peak) and the ray's initial slope (the
 *              limit t -> 0 in the first cell).
 *   edges      a ray leaving the grid sideways must not see what the
 *              profiles beside it see beyond its exit: profiles leave out
 *              the strip within one row of the exit-side edge, and each
 *              cell marches its own ray (the same stencils) from 2 rows
 *              before that edge to its exit (tails_row).  On the entry
 *              side profiles extend the surface linearly one row outwards.
 *   memory     directions nearer north-south than east-west run on the
 *              transposed DEM, so profiles follow memory rows; BLOCK
 *              neighbouring profiles are swept side by side.
 *
 * Cost per direction: every cell pushes one sample into one hull
 * and asks two hulls, plus at most 2 NEAR + 3 + 2 MIDS stencil taps and
 * its share of the edge strips: O(n^2) per direction, O(k n^2) in all
 * (tests/bench/bench_horizon.c measures the growth).
 *
 * Earth curvature: a point at distance d along the azimuth appears d^2/(2R)
 * lower.  Storing Z = z - X^2/(2R) in the hull (X along the profile) makes
 * every tangent from an observer at X_o equal to (Z - Z_o)/(X - X_o) +
 * X_o/R: a constant shift, so the hull and the argmax are exact. */
#include "src/sun/sun.h"

#include <math.h>
#include <omp.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

enum { NEAR = 24,      /* major steps every cell's own ray covers */
       PAD = NEAR + 3, /* NaN border of the work copy */
       BLOCK = 16,     /* profiles swept side by side */
       MIDS = 12       /* major steps with exact piece peaks */ };

td_horizon_params td_horizon_defaults(void)
{
    td_horizon_params p;
    p.directions = 36;
    p.cell_size = 1.0;
    p.curvature = 0;
    p.earth_radius = 6371000.0;
    return p;
}

/* A padded copy of the DEM, nodata and the border NaN, so samples need no
 * bounds checks and NaN samples drop out of every max. */
typedef struct work {
    float *buf;
    const float *z;     /* element (0, 0) */
    ptrdiff_t stride;
    int w, h, tr;       /* size; tr: the DEM transposed (x <-> y) */
} work;

/* One azimuth as a major/minor sweep.  Element steps are signed: +1 in k
 * is one cell along the look direction. */
typedef struct sweep {
    const float *z;     /* work cell at k = 0, j = 0 */
    ptrdiff_t zk, zj;
    float *t;           /* per cell: tangent sum, weight sum (scratch) */
    ptrdiff_t tk, tj;   /* cell steps in t (pairs) */
    int M, N;
    double a;           /* minor change per major step */
    double L;           /* ground distance per major step along a profile */
    double c1a;         /* X offset per minor unit off a profile */
    double inv2r, invr; /* 1 / (2 R), 1 / R; 0 without curvature */
    double ylo, yhi;    /* minor range profiles sample (see at_column) */
    const struct column *col; /* per major index, shared by all profiles */
} sweep;

/* Where every profile j = q + a k stands at column k, less q: floor(a k)
 * and the fraction. */
typedef struct column {
    int jk;             /* floor(a k) */
    double f;           /* a k - jk */
} column;

/* A profile's upper hull: n points (X, Z), X decreasing towards the top. */
typedef struct hull {
    double *x, *z;
    int n;
} hull;

/* Push (x, z), x smaller than every hull point, keeping the upper hull. */
static void hull_push(hull *h, double x, double z)
{
    int n = h->n;
    while (n >= 2) {
        double xt = h->x[n - 1], zt = h->z[n - 1];
        double xs = h->x[n - 2], zs = h->z[n - 2];
        if ((zt - z) * (xs - x) > (zs - z) * (xt - x))
            break; /* the top is above the segment new -> second */
        n--;
    }
    h->x[n] = x;
    h->z[n] = z;
    h->n = n + 1;
}

/* 1 when hull vertex b is seen higher than vertex a from (xo, zo). */
static int steeper(const hull *h, int b, int a, double xo, double zo)
{
    return (h->z[b] - zo) * (h->x[a] - xo) > (h->z[a] - zo) * (h->x[b] - xo);
}

/* Index of the first hull vertex in [lo, hi] not followed by a steeper
 * one: the peak, the slopes along the stack being unimodal. */
static int hull_peak(const hull *h, int lo, int hi, double xo, double zo)
{
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (steeper(h, mid + 1, mid, xo, zo))
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* The tangent from (xo, zo) (left of all points) to the hull, or NAN for an
 * empty hull.  Slopes along the stack rise, then fall; the search climbs
 * from *hint (the previous observer's vertex: usually a step or two away)
 * and bisects after a few steps; *hint gets the vertex found. */
static double hull_tangent(const hull *h, double xo, double zo, int *hint)
{
    int k = *hint < h->n ? *hint : h->n - 1, steps = 0;
    if (k < 0)
        return NAN;
    if (k + 1 < h->n && steeper(h, k + 1, k, xo, zo)) {
        while (++k + 1 < h->n && steeper(h, k + 1, k, xo, zo))
            if (++steps == 4) {
                k = hull_peak(h, k + 1, h->n - 1, xo, zo);
                break;
            }
    } else {
        while (k > 0 && steeper(h, k - 1, k, xo, zo)) {
            k--;
            if (++steps == 4) {
                k = hull_peak(h, 0, k, xo, zo);
                break;
            }
        }
    }
    *hint = k;
    return (h->z[k] - zo) / (h->x[k] - xo);
}

static float zat(const sweep *s, int k, int j)
{
    return s->z[(ptrdiff_t)k * s->zk + (ptrdiff_t)j * s->zj];
}

/* The profile's height at column k, row j + f (0 <= f < 1): linear
 * between the two cells; NAN outside [ylo, yhi] (the exit-side strip is
 * left to the tail march); on the entry side the surface is extended
 * linearly one row outwards (the blend of a cell in the edge row needs a
 * profile outside it). */
static double at_column(const sweep *s, int k, int j, double f)
{
    double y = j + f;
    if (!(y >= s->ylo && y <= s->yhi))
        return NAN;
    if (j < 0 || j >= s->N - 1) { /* linear extension, one row at most */
        int e = j < 0 ? 0 : s->N - 1, in = j < 0 ? 1 : s->N - 2;
        return s->N < 2 ? zat(s, k, e)
                        : zat(s, k, e) + fabs(y - e) * (zat(s, k, e) -
                                                         zat(s, k, in));
    }
    return f > 0.0 ? (1.0 - f) * zat(s, k, j) + f * zat(s, k, j + 1)
                   : zat(s, k, j);
}

/* Push the sample of profile q at column k. */
static void push_column(const sweep *s, hull *h, int q, int k)
{
    const column *c = &s->col[k];
    double z, x;
    z = at_column(s, k, q + c->jk, c->f);
    x = k * s->L;
    if (!isnan(z))
        hull_push(h, x, z - x * x * s->inv2r);
}

/* The column table of a sweep (M entries). */
static void columns(const sweep *s, column *col)
{
    int k;
    for (k = 0; k < s->M; k++) {
        double y = s->a * k;
        col[k].jk = (int)floor(y);
        col[k].f = y - col[k].jk;
    }
}

/* Cell (k, j), e minor units off profile q at its column: add w times its
 * tangent to the profile's hull into the cell's sums. */
static void observe(const sweep *s, const hull *h, int k, int j, double e,
                    double w, int *hint)
{
    ptrdiff_t at;
    double zc, xo, t;
    if (j < 0 || j >= s->N || w <= 0.0 || h->n == 0)
        return;
    zc = zat(s, k, j);
    if (isnan(zc))
        return;
    xo = k * s->L + s->c1a * e;
    t = hull_tangent(h, xo, zc - xo * xo * s->inv2r, hint) + xo * s->invr;
    at = 2 * ((ptrdiff_t)k * s->tk + (ptrdiff_t)j * s->tj);
    s->t[at] += (float)(w * t);
    s->t[at + 1] += (float)w;
}

/* One profile j = q + a k being swept: its hull, the columns [ka, kb]
 * where it is near the grid, and its hull_tangent hint. */
typedef struct prof {
    hull h;
    int q, ka, kb, hint[2]; /* hints of the cells below and above it */
} prof;

/* Start profile q; 0 when it misses the grid. */
static int prof_start(const sweep *s, prof *p, int q)
{
    p->q = q;
    p->h.n = 0;
    p->hint[0] = p->hint[1] = 0;
    p->ka = 0;
    p->kb = s->M - 1;
    if (s->a != 0.0) { /* -2 <= q + a k <= N + 1 */
        double k0 = (-2.0 - q) / s->a, k1 = (s->N + 1.0 - q) / s->a;
        p->ka = (int)fmax(0.0, ceil(fmin(k0, k1)));
        p->kb = (int)fmin(s->M - 1.0, floor(fmax(k0, k1)));
    } else if (q < -1.0 || q > s->N) {
        p->kb = -1;
    }
    return p->ka <= p->kb;
}

/* Column k of a profile swept from the far end (large k): push the
 * samples NEAR columns beyond, then the cells beside the profile at k ask
 * its hull. */
static void prof_step(const sweep *s, prof *p, int k)
{
    int j = p->q + s->col[k].jk;
    double f = s->col[k].f;
    if (k + NEAR <= p->kb)
        push_column(s, &p->h, p->q, k + NEAR);
    if (j < -1 || j >= s->N || p->h.n == 0)
        return;
    observe(s, &p->h, k, j, -f, 1.0 - f, &p->hint[0]);
    observe(s, &p->h, k, j + 1, 1.0 - f, f, &p->hint[1]);
}

/* Profiles q0 .. q0 + n - 1 swept side by side, column by column: a
 * cache line of the grid is used by neighbouring profiles a few steps
 * apart instead of once per profile. */
static void prof_block(const sweep *s, long q0, int n, prof *pr)
{
    int i, k, kmin = s->M, kmax = -1;
    for (i = 0; i < n; i++)
        if (prof_start(s, &pr[i], (int)(q0 + i))) {
            kmin = pr[i].ka < kmin ? pr[i].ka : kmin;
            kmax = pr[i].kb > kmax ? pr[i].kb : kmax;
        }
    for (k = kmax; k >= kmin; k--)
        for (i = 0; i < n; i++)
            if (k >= pr[i].ka && k <= pr[i].kb)
                prof_step(s, &pr[i], k);
}

/* The work copy: (w + 2 PAD) x (h + 2 PAD), NaN outside and on nodata;
 * transposed when tr (so every sweep runs along the rows of memory). */
static int work_new(work *wk, const td_grid_f32 *dem, int tr, td_ctx *cx)
{
    size_t W, H, i;
    int y;
    wk->w = tr ? dem->h : dem->w;
    wk->h = tr ? dem->w : dem->h;
    wk->tr = tr;
    W = (size_t)wk->w + 2 * PAD;
    H = (size_t)wk->h + 2 * PAD;
    if (!(wk->buf = td_malloc(sizeof(float) * W * H, cx)))
        return TD_ENOMEM;
    for (i = 0; i < W * H; i++)
        wk->buf[i] = NAN;
    wk->stride = (ptrdiff_t)W;
    wk->z = wk->buf + PAD * W + PAD;
#pragma omp parallel for schedule(static)
    for (y = 0; y < wk->h; y++) {
        float *dst = wk->buf + (size_t)(y + PAD) * W + PAD;
        size_t step = tr ? dem->stride : 1;
        const float *src = dem->data + (tr ? (size_t)y
                                           : (size_t)y * dem->stride);
        int x;
        for (x = 0; x < wk->w; x++) {
            float v = src[(size_t)x * step];
            dst[x] = dem->has_nodata && v == dem->nodata ? NAN : v;
        }
    }
    return 0;
}

/* Map the direction (gx, gy) (work-copy columns and rows, |gx| >= |gy|)
 * onto a major (column) / minor (row) sweep over the work copy and the
 * scratch sums (stride w). */
static void sweep_setup(sweep *s, const work *wk, double gx, double gy,
                        const td_horizon_params *p, float *sum)
{
    int di = gx > 0 ? 1 : -1;
    ptrdiff_t x0 = di > 0 ? 0 : wk->w - 1; /* k = 0 */
    s->M = wk->w;
    s->N = wk->h;
    s->a = gy / fabs(gx);
    if (fabs(s->a - floor(s->a + 0.5)) < 1e-9)
        s->a = floor(s->a + 0.5);
    s->zk = di;
    s->zj = wk->stride;
    s->tk = di;
    s->tj = wk->w;
    s->z = wk->z + x0;
    s->t = sum + 2 * x0;
    s->L = p->cell_size * sqrt(1.0 + s->a * s->a);
    s->c1a = p->cell_size * s->a / sqrt(1.0 + s->a * s->a);
    s->inv2r = p->curvature ? 0.5 / p->earth_radius : 0.0;
    s->invr = 2.0 * s->inv2r;
    s->ylo = s->a < 0 ? 1.0 : s->a > 0 ? -1.0 + 1e-9 : 0.0;
    s->yhi = s->a < 0 ? s->N - 1e-9 : s->a > 0 ? s->N - 2.0 : s->N - 1.0;
}

/* A stencil on the ray: tangent = c1 (z[o1] - z0) + c2 (z[o2] - z0) - d,
 * offsets from the cell in the work copy; m its major distance. */
typedef struct tap {
    ptrdiff_t o1, o2;
    float c1, c2, d, m;
} tap;

/* The ray point t cells from the centre as a two-cell stencil (the point
 * is on a grid line, so the bilinear surface is linear there). */
static tap crossing_tap(double t, double gx, double gy, double cs,
                        double inv2r, ptrdiff_t stride)
{
    double px = t * gx, py = t * gy, f;
    long ix, iy;
    tap tp;
    if (fabs(px - floor(px + 0.5)) < 1e-9) { /* on a column line */
        ix = lround(px);
        iy = (long)floor(py + 1e-9);
        f = py - iy;
        tp.o1 = iy * stride + ix;
        tp.o2 = tp.o1 + stride;
    } else {
        iy = lround(py);
        ix = (long)floor(px + 1e-9);
        f = px - ix;
        tp.o1 = iy * stride + ix;
        tp.o2 = tp.o1 + 1;
    }
    if (f < 1e-9) {
        f = 0.0;
        tp.o2 = tp.o1;
    }
    tp.c1 = (float)((1.0 - f) / (t * cs));
    tp.c2 = (float)(f / (t * cs));
    tp.d = (float)(t * cs * inv2r);
    tp.m = (float)(t * fmax(fabs(gx), fabs(gy)));
    return tp;
}

/* Every grid-line crossing of a ray within `steps` major steps, nearest
 * first: the same pattern for every cell.  Returns the count (at most
 * 2 steps + 2). */
static int ray_taps(double gx, double gy, int steps, double cs, double inv2r,
                    ptrdiff_t stride, tap *tp)
{
    double ax = fabs(gx), ay = fabs(gy), tmax = steps / fmax(ax, ay) + 1e-9;
    int n = 0, i = 1, j = 1;
    for (;;) {
        double tx = ax > 1e-12 ? i / ax : HUGE_VAL;
        double ty = ay > 1e-12 ? j / ay : HUGE_VAL, t;
        if (tx < HUGE_VAL && fabs(tx - ty) <= 1e-9 * tx) { /* a node */
            t = tx;
            i++;
            j++;
        } else if (tx < ty) {
            t = tx;
            i++;
        } else {
            t = ty;
            j++;
        }
        if (t > tmax)
            return n;
        tp[n++] = crossing_tap(t, gx, gy, cs, inv2r, stride);
    }
}

/* A point inside a cell: tangent = sum c[i] (z[o[i]] - z0) - d. */
typedef struct qtap {
    ptrdiff_t o[4];
    float c[4], d;
    int ia, ib;         /* the piece's ends: taps ia, ib of the pattern */
    float ta, tm, tb;   /* ray parameter (cells) at its ends and middle */
} qtap;

/* The bilinear pieces of the ray between its crossings within MIDS major
 * steps, but the first (whose tangent is largest at an end): the stencil
 * of each piece's midpoint and its ends (for piece_peak; a piece is a
 * quadratic in t and may peak inside).  Returns the count. */
static int mid_taps(double gx, double gy, const tap *pat, int np, double cs,
                    double inv2r, ptrdiff_t stride, qtap *q)
{
    double am = fmax(fabs(gx), fabs(gy));
    int i, n = 0, c;
    for (i = 1; i < np && pat[i].m <= MIDS; i++) {
        double t = 0.5 * (pat[i - 1].m + pat[i].m) / am;
        double px = t * gx, py = t * gy, fx, fy;
        long ix = (long)floor(px), iy = (long)floor(py);
        fx = px - ix;
        fy = py - iy;
        q[n].o[0] = iy * stride + ix;
        q[n].o[1] = q[n].o[0] + 1;
        q[n].o[2] = q[n].o[0] + stride;
        q[n].o[3] = q[n].o[2] + 1;
        q[n].c[0] = (float)((1 - fx) * (1 - fy) / (t * cs));
        q[n].c[1] = (float)(fx * (1 - fy) / (t * cs));
        q[n].c[2] = (float)((1 - fx) * fy / (t * cs));
        q[n].c[3] = (float)(fx * fy / (t * cs));
        for (c = 1; c < 4; c++)
            if (q[n].c[c] < 1e-7f) {
                q[n].c[c] = 0.0f;
                q[n].o[c] = q[n].o[0];
            }
        if (q[n].c[0] < 1e-7f) { /* keep o[0] finite-weighted */
            q[n].c[0] = 0.0f;
            q[n].o[0] = q[n].o[3];
        }
        q[n].d = (float)(t * cs * inv2r);
        q[n].ia = i - 1;
        q[n].ib = i;
        q[n].ta = (float)(pat[i - 1].m / am);
        q[n].tm = (float)t;
        q[n].tb = (float)(pat[i].m / am);
        n++;
    }
    return n;
}

/* The ray's initial slope inside the cell (limit t -> 0; between the
 * centre and the first grid line the bilinear surface is a quadratic
 * z0 + b t + c t^2, so the tangent b + c t is largest at an end: b here,
 * the other end is a crossing):
 * b = (z[x+sx] - z0) |gx| / cs + (z[y+sy] - z0) |gy| / cs. */
static tap slope_tap(double gx, double gy, double cs, ptrdiff_t stride)
{
    tap tp;
    int hx = fabs(gx) > 1e-12, hy = fabs(gy) > 1e-12;
    tp.o1 = hx ? (gx > 0 ? 1 : -1) : (gy > 0 ? stride : -stride);
    tp.o2 = hy ? (gy > 0 ? stride : -stride) : tp.o1;
    tp.c1 = (float)(hx ? fabs(gx) / cs : 0.0);
    tp.c2 = (float)(hy ? fabs(gy) / cs : 0.0);
    tp.d = 0.0f;
    tp.m = 0.0f;
    return tp;
}

/* A direction's stencils: pat, the whole ray (np taps), of which the first
 * nn are within NEAR major steps; slope, the initial slope. */
typedef struct taps {
    tap *pat, slope;
    int *first;         /* see first_taps */
    float cs, inv2r;    /* cell size, 1 / (2 R) */
    qtap mid[4 * MIDS + 4];
    int np, nn, nm;
    int di;             /* +1: the ray runs towards larger columns */
    double a;
} taps;

static float max_taps(const float *z, const tap *tp, int n, float best)
{
    int i;
    for (i = 0; i < n; i++) {
        float t = tp[i].c1 * (z[tp[i].o1] - z[0]) +
                  tp[i].c2 * (z[tp[i].o2] - z[0]) - tp[i].d;
        best = t > best ? t : best; /* NaN t: kept */
    }
    return best;
}

/* First index of pat with major distance >= m. */
static int tap_index(const taps *tt, double m)
{
    int i = m <= 0.0 ? 0 : tt->first[m < tt->np ? (int)m : tt->np];
    while (i < tt->np && tt->pat[i].m < m)
        i++;
    return i;
}

/* tt->first[s]: the first tap at major distance >= s, s = 0 .. np. */
static void first_taps(taps *tt)
{
    int s, i = 0;
    for (s = 0; s <= tt->np; s++) {
        while (i < tt->np && tt->pat[i].m < s)
            i++;
        tt->first[s] = i;
    }
}

/* The tails of row y's rays: from where a ray comes within 2 minor units
 * of the grid's exit-side edge (the profiles leave out that strip) to where
 * it leaves the grid, by the side or by the far end; into row (max).  The
 * row fixes the distance to that edge, so all but the cells near the far
 * end share the same taps. */
static void tails_row(const taps *tt, const float *z, int y, int w, int h,
                      float *row)
{
    double aa = fabs(tt->a), edge, d0, d1;
    int x, j0, j1;
    if (tt->a == 0.0)
        return;
    edge = tt->a < 0 ? y : h - 1 - y;       /* minor units to the edge */
    d0 = fmax((edge - 2.0) / aa, NEAR);
    d1 = edge / aa + 1e-3;                  /* beyond: NaN padding */
    if (d1 <= d0)
        return;
    j0 = tap_index(tt, d0);
    j1 = tap_index(tt, d1);
    for (x = 0; x < w; x++) {
        double rest = (tt->di > 0 ? w - 1 - x : x) + 1e-3; /* to the end */
        if (rest <= d0)
            continue;
        row[x] = max_taps(z + x, tt->pat + j0,
                          (rest < d1 ? tap_index(tt, rest) : j1) - j0, row[x]);
    }
}

/* atan(t) in degrees for t >= 0, within 2e-7 rad: reduced to |v| <=
 * tan(pi/8) by atan(t) = pi/2 - atan(1/t) and atan(u) = pi/4 +
 * atan((u - 1) / (u + 1)), then the Taylor series to v^13. */
static float atan_deg(float t)
{
    float u = t > 1.0f ? 1.0f / t : t, v, v2, r, base = 0.0f;
    if (u > 0.41421356f) {
        v = (u - 1.0f) / (u + 1.0f);
        base = 0.78539816f;
    } else {
        v = u;
    }
    v2 = v * v;
    r = v * (1.0f + v2 * (-1.0f / 3 + v2 * (1.0f / 5 + v2 * (-1.0f / 7 +
             v2 * (1.0f / 9 + v2 * (-1.0f / 11 + v2 * (1.0f / 13)))))));
    r += base;
    r = t > 1.0f ? 1.5707963f - r : r;
    return r * (float)(180.0 / M_PI);
}

/* The largest tangent of the bilinear piece q (a quadratic in t through
 * its ends and middle, heights h relative to the cell) for every cell of
 * a row: the middle, and the interior peak of (h(t) - curvature) / t,
 * where h = al + be t + ga t^2 gives t* = sqrt(al / ga) and the tangent
 * be - 2 sqrt(al ga) (al < 0, ga < 0); into row (max).  Pieces shorter
 * than 0.05 cell keep their middle only (float cancellation).  The
 * Makefile builds this file with -fno-math-errno, so sqrtf vectorises. */
TD_CLONES static void piece_peak(const taps *tt, const qtap *q,
                                 const float *z, int w, float *restrict row)
{
    const tap *a = &tt->pat[q->ia], *b = &tt->pat[q->ib];
    const float *restrict m0 = z + q->o[0], *restrict m1 = z + q->o[1];
    const float *restrict m2 = z + q->o[2], *restrict m3 = z + q->o[3];
    const float *restrict a1 = z + a->o1, *restrict a2 = z + a->o2;
    const float *restrict b1 = z + b->o1, *restrict b2 = z + b->o2;
    const float ta = q->ta, tb = q->tb, cs = tt->cs, k2 = tt->inv2r;
    const float hh = tb - ta, on = hh > 0.05f ? 1.0f : 0.0f;
    const float sa = ta * cs, sm = q->tm * cs, sb = tb * cs;
    const float c0 = q->c[0], c1 = q->c[1], c2 = q->c[2], c3 = q->c[3];
    const float ac1 = a->c1, ac2 = a->c2, bc1 = b->c1, bc2 = b->c2;
    const float qd = q->d;
    int x;
    for (x = 0; x < w; x++) {
        float tmv = c0 * (m0[x] - z[x]) + c1 * (m1[x] - z[x]) +
                    c2 * (m2[x] - z[x]) + c3 * (m3[x] - z[x]) - qd;
        float ha = (ac1 * (a1[x] - z[x]) + ac2 * (a2[x] - z[x])) * sa;
        float hb = (bc1 * (b1[x] - z[x]) + bc2 * (b2[x] - z[x])) * sb;
        float hm = (tmv + qd) * sm, ga, be, al, r, ts, t, ratio;
        ga = 2.0f * (ha - 2.0f * hm + hb) / (hh * hh);
        be = (hb - ha) / hh - ga * (ta + tb);
        al = ha - be * ta - ga * ta * ta;
        ratio = al / ga; /* unconditional: a guarded division blocks SIMD */
        r = al < 0.0f ? ratio : 0.0f;
        r = r > 0.0f ? r * on : 0.0f; /* al < 0 and ga < 0 */
        ts = sqrtf(r);
        t = (be - 2.0f * sqrtf(r) * -ga) / cs - ts * cs * k2;
        t = ts > ta ? t : tmv;
        t = ts < tb ? t : tmv;
        t = t > tmv ? t : tmv;
        row[x] = t > row[x] ? t : row[x]; /* NaN t: kept */
    }
}

/* Row y of the work grid: the far-field blend, the near-field taps, the
 * tail; degrees clamped at 0 (nodata cells: nodata) into o[x * ostep]. */
TD_CLONES static void finish_row(const work *wk, const float *sum,
                                 const taps *tt, int y, float *row, float *o,
                                 size_t ostep, float nod)
{
    const int w = wk->w, h = wk->h;
    const float *z = wk->z + (ptrdiff_t)y * wk->stride;
    const float *ts = sum + 2 * (size_t)y * w;
    int x, i;
    for (x = 0; x < w; x++) { /* both profiles seen, else: the tail */
        float wsum = ts[2 * x + 1] > 1e-3f ? ts[2 * x + 1] : 1e-3f;
        float b = ts[2 * x] / wsum;
        row[x] = ts[2 * x + 1] > 0.999f ? b : 0.0f;
    }
    for (i = 0; i <= tt->nn; i++) {
        const tap *tp = i < tt->nn ? &tt->pat[i] : &tt->slope;
        const float *z1 = z + tp->o1, *z2 = z + tp->o2;
        float c1 = tp->c1, c2 = tp->c2, d = tp->d;
        for (x = 0; x < w; x++) {
            float t = c1 * (z1[x] - z[x]) + c2 * (z2[x] - z[x]) - d;
            row[x] = t > row[x] ? t : row[x]; /* NaN t: kept */
        }
    }
    for (i = 0; i < tt->nm; i++)
        piece_peak(tt, &tt->mid[i], z, w, row);
    tails_row(tt, z, y, w, h, row);
    for (x = 0; x < w; x++)
        row[x] = isnan(z[x]) ? nod : atan_deg(row[x] > 0.0f ? row[x] : 0.0f);
    for (x = 0; x < w; x++)
        o[(size_t)x * ostep] = row[x];
}

static int check_args(const td_grid_f32 *dem, const td_horizon_params *p,
                      const td_grid_f32 *out, td_ctx *cx)
{
    if (!dem || !dem->data || !p || !out || !out->data)
        return td_seterr(cx, TD_EINVAL, "horizon: missing grid");
    if (out->w != dem->w || out->h != dem->h)
        return td_seterr(cx, TD_EINVAL, "horizon: output is %dx%d, DEM "
                         "%dx%d", out->w, out->h, dem->w, dem->h);
    if (!(p->cell_size > 0.0) || !isfinite(p->cell_size))
        return td_seterr(cx, TD_EINVAL, "horizon: cell size must be > 0");
    if (p->curvature && !(p->earth_radius > 0.0))
        return td_seterr(cx, TD_EINVAL, "horizon: earth radius must be > 0");
    return td_check_dims(dem->w, dem->h, "horizon: DEM", cx);
}

/* Every profile, in blocks of BLOCK neighbours: even blocks, then odd
 * ones (neighbouring profiles share cells), in parallel.  hb holds BLOCK
 * hulls of cap = 2 M + 2 points per thread (M + 1 would do). */
static void sweep_profiles(const sweep *s, double *hb, int nth)
{
    long qmin, qmax, b, nb;
    int par;
    qmin = (long)floor(fmin(0.0, -s->a * (s->M - 1))) - 1;
    qmax = (long)ceil(s->N - 1 + fmax(0.0, -s->a * (s->M - 1))) + 1;
    nb = (qmax - qmin) / BLOCK + 1;
    for (par = 0; par < 2; par++) {
#pragma omp parallel num_threads(nth)
        {
            size_t cap = 2 * (size_t)s->M + 2;
            double *mine = hb + 2 * cap * BLOCK * (size_t)omp_get_thread_num();
            prof pr[BLOCK];
            int i;
            for (i = 0; i < BLOCK; i++) {
                pr[i].h.x = mine + 2 * cap * i;
                pr[i].h.z = pr[i].h.x + cap;
            }
#pragma omp for schedule(dynamic, 1)
            for (b = par; b < nb; b += 2) {
                long q0 = qmin + b * BLOCK;
                long n = q0 + BLOCK - 1 <= qmax ? BLOCK : qmax - q0 + 1;
                prof_block(s, q0, (int)n, pr);
            }
        }
    }
}

/* The direction's stencils (see taps). */
static void taps_setup(taps *tt, const sweep *s, const work *wk, double gx,
                       double gy, double cs)
{
    tt->np = ray_taps(gx, gy, s->M, cs, s->inv2r, wk->stride, tt->pat);
    first_taps(tt);
    tt->nn = tap_index(tt, NEAR + 1e-6);
    tt->slope = slope_tap(gx, gy, cs, wk->stride);
    tt->cs = (float)cs;
    tt->inv2r = (float)s->inv2r;
    tt->nm = mid_taps(gx, gy, tt->pat, tt->np, cs, s->inv2r, wk->stride,
                      tt->mid);
    tt->di = gx > 0 ? 1 : -1;
    tt->a = s->a;
}

/* One direction on nth threads (arguments checked).  Directions nearer
 * north-south than east-west run on the transposed DEM, so profiles always
 * follow memory rows. */
static int direction(const td_grid_f32 *dem, double azimuth_deg,
                     const td_horizon_params *p, td_grid_f32 *out, int nth,
                     td_ctx *cx)
{
    work wk = {NULL, NULL, 0, 0, 0, 0};
    sweep s;
    taps tt = {NULL};
    column *col = NULL;
    float *sum = NULL, *rows = NULL;
    double *hb = NULL, gx, gy, t;
    int rc, y, big = dem->w > dem->h ? dem->w : dem->h;
    gx = sin(azimuth_deg * M_PI / 180.0);
    gy = -cos(azimuth_deg * M_PI / 180.0); /* north = row 0 */
    rc = TD_ENOMEM;
    if (work_new(&wk, dem, fabs(gy) > fabs(gx), cx) != 0 ||
        !(sum = td_calloc(2 * (size_t)dem->w * dem->h, sizeof(float), cx)) ||
        !(rows = td_malloc(sizeof(float) * (size_t)big * nth, cx)) ||
        !(tt.pat = td_malloc(sizeof(tap) * (2 * (size_t)big + 4), cx)) ||
        !(col = td_malloc(sizeof(column) * (size_t)big, cx)) ||
        !(tt.first = td_malloc(sizeof(int) * (2 * (size_t)big + 5), cx)) ||
        !(hb = td_malloc(sizeof(double) * 2 * (2 * (size_t)big + 2) * BLOCK *
                         nth, cx)))
        goto fail;
    if (wk.tr) {
        t = gx;
        gx = gy;
        gy = t;
    }
    sweep_setup(&s, &wk, gx, gy, p, sum);
    columns(&s, col);
    s.col = col;
    sweep_profiles(&s, hb, nth);
    taps_setup(&tt, &s, &wk, gx, gy, p->cell_size);
    out->has_nodata = 1;
    out->nodata = dem->has_nodata ? dem->nodata : -9999.0f;
#pragma omp parallel for schedule(static) num_threads(nth)
    for (y = 0; y < wk.h; y++)
        finish_row(&wk, sum, &tt, y, rows + (size_t)big * omp_get_thread_num(),
                   out->data + (wk.tr ? (size_t)y : (size_t)y * out->stride),
                   wk.tr ? out->stride : 1, out->nodata);
    rc = 0;
fail:
    free(col);
    free(tt.first);
    free(tt.pat);
    free(hb);
    free(rows);
    free(sum);
    free(wk.buf);
    return rc;
}

/* See horizon.h. */
int td_horizon_direction(const td_grid_f32 *dem, double azimuth_deg,
                         const td_horizon_params *p, td_grid_f32 *out,
                         td_ctx *cx)
{
    int rc;
    if ((rc = check_args(dem, p, out, cx)) != 0)
        return rc;
    if (!isfinite(azimuth_deg))
        return td_seterr(cx, TD_EINVAL, "horizon: azimuth is not finite");
    return direction(dem, azimuth_deg, p, out, omp_get_max_threads(), cx);
}

/* See horizon.h.  The directions run in parallel, one thread each (no
 * barrier per direction); errors and progress go through cx one thread at
 * a time. */
int td_horizon_sweep(const td_grid_f32 *dem, const td_horizon_params *p,
                     td_grid_f32 *const *bands, td_ctx *cx)
{
    int i, rc = 0, done = 0;
    if (!p || p->directions < 1 || p->directions > 3600 || !bands)
        return td_seterr(cx, TD_EINVAL, "horizon: directions must be "
                         "1..3600");
    for (i = 0; i < p->directions; i++)
        if ((rc = check_args(dem, p, bands[i], cx)) != 0)
            return rc;
#pragma omp parallel for schedule(dynamic, 1)
    for (i = 0; i < p->directions; i++) {
        td_ctx mine;
        int r, stop;
#pragma omp atomic read
        stop = rc;
        if (stop)
            continue;
        td_ctx_init(&mine);
        r = direction(dem, 360.0 * i / p->directions, p, bands[i], 1, &mine);
#pragma omp critical(td_horizon_sweep)
        {
            if (r != 0 && rc == 0)
                rc = td_seterr(cx, r, "%s", td_errmsg(&mine));
            else if (rc == 0)
                rc = td_progress(cx, "horizon",
                                 (double)++done / p->directions);
        }
    }
    return rc;
}
