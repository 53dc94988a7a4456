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
 *     |        .' `.     D                  near end; a new point P pops
 *     |  P   .'     `. .' `.                every hull vertex that lies on
 *     | .  .'         C     `E              or under the segment from P to
 *     +--------------------------> u        the vertex below it (here C),
 *                                           so the stack top after popping
 *   is P's horizon point (B) and each point is pushed and popped once:
 *   O(length) per profile, O(k n^2) in all.
 *
 * Sub-cell sampling (ours).  For an azimuth that is not along an axis the
 * profiles are lines  minor = q + a * major  (|a| <= 1, q integer, one
 * profile per minor unit), sampled at every whole and half major step with
 * bilinear interpolation.  A cell C lies between two neighbouring profiles
 * and its own ray runs parallel to both:
 *
 *        profile q+1  o--o--o--o--o--o--o     C asks each profile's hull
 *                      C ---- ray ---->       which point is seen highest
 *        profile q    o--o--o--o--o--o--o     from C (its own height and
 *                                             position), then samples its
 *   own ray (bilinear) at that point and its two hull neighbours each side
 *   and keeps the largest tangent.  Where the ray leaves the grid sideways
 *   before such a point, the on-grid part of the ray is marched instead.
 *   The first cell of the ray, where a quadratic bilinear piece peaks at
 *   the cell itself, is covered by the one-sided slope (near_slope).
 *   Along the axes and diagonals the profiles pass through the cells and
 *   the result is the exact horizon of the sampled profile; otherwise it
 *   is a lower bound on the ray's horizon (measured in tests/test_horizon.c
 *   and docs/insolation.md).
 *
 * Earth curvature: a point at ground distance d appears d^2/(2R) lower.
 * With u the distance along the profile, storing z - u^2/(2R) in the hull
 * gives every slope seen from an observer at u_o shifted by the constant
 * -u_o/R, so the hull (and the argmax) is unchanged and exact. */
#include "horizon.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

td_horizon_params td_horizon_defaults(void)
{
    td_horizon_params p;
    p.directions = 36;
    p.cell_size = 1.0;
    p.curvature = 0;
    p.earth_radius = 6371000.0;
    return p;
}

/* The DEM seen as major index i (0..M-1) by minor index j (0..N-1) for one
 * azimuth; the look direction advances di (+1/-1) major and di*a minor. */
typedef struct sweep {
    const float *z;
    size_t zi, zj;      /* element steps of dem for +1 in i, j */
    float *t;
    size_t ti, tj;      /* same for the tangent accumulator (out) */
    int M, N, di;
    double a;           /* minor change per +1 major */
    double L;           /* ground distance per major step */
    double inv2r;       /* 1 / (2 R), 0 without curvature */
    float nod;
    int has_nod;
} sweep;

/* A profile's upper hull: n points (u, z), u decreasing towards the top. */
typedef struct hull {
    double *u, *z;
    int *i2;            /* each point's major position times 2 */
    int n;
} hull;

static int is_nod(const sweep *s, float v)
{
    return isnan(v) || (s->has_nod && v == s->nod);
}

/* Push (u, z), u smaller than every hull point, keeping the upper hull. */
static void hull_push(hull *h, double u, double z, int i2)
{
    int n = h->n;
    while (n >= 2) {
        double ut = h->u[n - 1], zt = h->z[n - 1];
        double us = h->u[n - 2], zs = h->z[n - 2];
        /* pop the top when it is on or under the segment P -> second */
        if ((zt - z) * (us - u) > (zs - z) * (ut - u))
            break;
        n--;
    }
    h->u[n] = u;
    h->z[n] = z;
    h->i2[n] = i2;
    h->n = n + 1;
}

/* 1 when hull vertex b is seen higher than vertex a from (uo, zo). */
static int steeper(const hull *h, int b, int a, double uo, double zo)
{
    return (h->z[b] - zo) * (h->u[a] - uo) > (h->z[a] - zo) * (h->u[b] - uo);
}

/* The hull point seen highest from (uo, zo) (uo left of all points), or
 * -1 for an empty hull.  Slopes along the stack rise, then fall. */
static int hull_tangent(const hull *h, double uo, double zo)
{
    int k = h->n - 1, steps = 0, lo, hi;
    if (k < 0)
        return -1;
    while (k > 0 && steeper(h, k - 1, k, uo, zo)) {
        k--;
        if (++steps == 6 && k > 0) {
            lo = 0; /* the peak is in [0, k] */
            hi = k;
            while (lo < hi) {
                int mid = (lo + hi + 1) / 2;
                if (steeper(h, mid - 1, mid, uo, zo))
                    hi = mid - 1;
                else
                    lo = mid;
            }
            k = lo;
            break;
        }
    }
    return k;
}

/* The DEM at whole major index i and minor position y (bilinear when
 * i is not whole: i2 = 2 * i), or NAN outside the grid or on nodata. */
static double sample(const sweep *s, int i2, double y)
{
    int i = i2 >> 1, j, ci, cj;
    double fy, fx = (i2 & 1) ? 0.5 : 0.0, v = 0.0;
    if (y < -1e-9 || y > s->N - 1 + 1e-9 || i + (fx > 0) >= s->M)
        return NAN;
    j = (int)floor(y + 1e-9);
    fy = y - j;
    if (fy < 1e-9)
        fy = 0.0;
    if (fy > 0.0 && j + 1 >= s->N)
        return NAN;
    for (ci = 0; ci <= (fx > 0); ci++)
        for (cj = 0; cj <= (fy > 0); cj++) {
            float z = s->z[(size_t)(i + ci) * s->zi + (size_t)(j + cj) * s->zj];
            if (is_nod(s, z))
                return NAN;
            v += (ci ? fx : 1.0 - fx) * (cj ? fy : 1.0 - fy) * z;
        }
    return v;
}

/* Push the profile point at major position i2 / 2 into the hull. */
static void push_at(const sweep *s, hull *h, double q, int i2)
{
    double u = s->di * 0.5 * i2 * s->L, z = sample(s, i2, q + s->a * 0.5 * i2);
    if (!isnan(z))
        hull_push(h, u, z - u * u * s->inv2r, i2);
}

/* Tangent from cell (i, j) (height zc, distance u) to its own ray sampled
 * at major position i2 / 2; NAN where the ray is off the grid. */
static double ray_tangent(const sweep *s, int i, int j, double zc, double u,
                          int i2)
{
    double z = sample(s, i2, j + s->a * (0.5 * i2 - i)), up;
    if (isnan(z))
        return NAN;
    up = s->di * 0.5 * i2 * s->L;
    return (z - zc) / (up - u) - (up - u) * s->inv2r;
}

/* The ray of cell (i, j) marched at every half major step while it stays
 * on the grid: the largest tangent. */
static double ray_march(const sweep *s, int i, int j, double zc, double u)
{
    double best = 0.0, t;
    int i2;
    for (i2 = 2 * i + s->di; i2 >= 0 && i2 <= 2 * (s->M - 1); i2 += s->di) {
        if (isnan(t = ray_tangent(s, i, j, zc, u, i2)))
            break;
        best = t > best ? t : best;
    }
    return best;
}

/* Cell (i, j) at distance u along the profile: the profile's hull point
 * seen highest from the cell (and its hull neighbours) names where its
 * horizon lies; the cell's own ray is sampled there (bilinear) and the
 * largest tangent is kept in the cell's accumulator.  When the ray leaves
 * the grid (sideways) before that point, the profile's hull says nothing
 * about the ray's part on the grid: that part is marched. */
static void observe(const sweep *s, const hull *h, int i, int j, double u)
{
    size_t at = (size_t)i * s->ti + (size_t)j * s->tj;
    double zc, t, best = s->t[at];
    int k, c, off = 0;
    if (j < 0 || j >= s->N)
        return;
    zc = s->z[(size_t)i * s->zi + (size_t)j * s->zj];
    if (is_nod(s, (float)zc) ||
        (k = hull_tangent(h, u, zc - u * u * s->inv2r)) < 0)
        return;
    for (c = k - 2; c <= k + 2; c++) {
        if (c < 0 || c >= h->n)
            continue;
        t = ray_tangent(s, i, j, zc, u, h->i2[c]);
        if (isnan(t))
            off = 1;
        else if (t > best)
            best = t;
    }
    if (off) {
        t = ray_march(s, i, j, zc, u);
        best = t > best ? t : best;
    }
    s->t[at] = (float)best;
}

/* One profile minor = q + a * major, swept from far to near; the profile
 * is sampled at every whole and every half major step. */
static void profile(const sweep *s, double q, hull *h)
{
    int i, step = s->di > 0 ? -1 : 1, i0 = s->di > 0 ? s->M - 1 : 0;
    h->n = 0;
    for (i = i0; i >= 0 && i < s->M; i += step) {
        double y = q + s->a * i, u = s->di * i * s->L;
        int j;
        if (i != i0)
            push_at(s, h, q, 2 * i - step);
        if (y < -1e-9 || y > s->N - 1 + 1e-9)
            continue;
        j = (int)floor(y + 1e-9);
        observe(s, h, i, j, u);
        if (y - j > 1e-9)
            observe(s, h, i, j + 1, u);
        push_at(s, h, q, 2 * i);
    }
}

/* Map the azimuth onto a major/minor sweep over dem and out. */
static void sweep_setup(sweep *s, const td_grid_f32 *dem, double az_deg,
                        const td_horizon_params *p, td_grid_f32 *out)
{
    double az = az_deg * M_PI / 180.0, dx = sin(az), dy = -cos(az);
    if (fabs(dx) < 1e-12)
        dx = 0.0;
    if (fabs(dy) < 1e-12)
        dy = 0.0;
    s->z = dem->data;
    s->t = out->data;
    if (fabs(dx) >= fabs(dy)) { /* major = column */
        s->zi = 1; s->zj = dem->stride; s->ti = 1; s->tj = out->stride;
        s->M = dem->w; s->N = dem->h;
        s->di = dx > 0 ? 1 : -1;
        s->a = dy / fabs(dx) * s->di;
        s->L = p->cell_size / fabs(dx);
    } else {
        s->zi = dem->stride; s->zj = 1; s->ti = out->stride; s->tj = 1;
        s->M = dem->h; s->N = dem->w;
        s->di = dy > 0 ? 1 : -1;
        s->a = dx / fabs(dy) * s->di;
        s->L = p->cell_size / fabs(dy);
    }
    if (fabs(s->a - floor(s->a + 0.5)) < 1e-9)
        s->a = floor(s->a + 0.5);
    s->inv2r = p->curvature ? 0.5 / p->earth_radius : 0.0;
    s->nod = dem->nodata;
    s->has_nod = dem->has_nodata;
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

/* The slope of the bilinear surface leaving cell (x, y) along the ground
 * direction (gx, gy) (columns, rows; unit length): the limit of the
 * horizon tangent on the ray's first cell, which no profile sample sees
 * (between the centre and the next grid line the bilinear surface is a
 * quadratic q(t) = z0 + b t + c t^2, so (q(t) - z0) / t = b + c t is
 * largest at one end: t -> 0 gives b, the far end is a profile sample). */
static double near_slope(const td_grid_f32 *dem, int x, int y, double gx,
                         double gy, double cs)
{
    int sx = gx > 0 ? 1 : -1, sy = gy > 0 ? 1 : -1;
    double z0 = TD_AT(dem, x, y), b = 0.0, v;
    if (fabs(gx) > 1e-12) {
        if (x + sx < 0 || x + sx >= dem->w)
            return 0.0;
        v = TD_AT(dem, x + sx, y);
        if (isnan(v) || (dem->has_nodata && v == dem->nodata))
            return 0.0;
        b += (v - z0) * fabs(gx);
    }
    if (fabs(gy) > 1e-12) {
        if (y + sy < 0 || y + sy >= dem->h)
            return 0.0;
        v = TD_AT(dem, x, y + sy);
        if (isnan(v) || (dem->has_nodata && v == dem->nodata))
            return 0.0;
        b += (v - z0) * fabs(gy);
    }
    return b / cs;
}

/* Tangents (and the near slope) -> degrees clamped at 0; nodata cells ->
 * nodata. */
static void finish(const td_grid_f32 *dem, double az_deg, double cs,
                   td_grid_f32 *out)
{
    double gx = sin(az_deg * M_PI / 180.0), gy = -cos(az_deg * M_PI / 180.0);
    int y;
    out->has_nodata = 1;
    out->nodata = dem->has_nodata ? dem->nodata : -9999.0f;
#pragma omp parallel for schedule(static)
    for (y = 0; y < dem->h; y++) {
        const float *zr = dem->data + (size_t)y * dem->stride;
        float *o = out->data + (size_t)y * out->stride;
        int x;
        for (x = 0; x < dem->w; x++) {
            double t = o[x], b;
            if (isnan(zr[x]) || (dem->has_nodata && zr[x] == dem->nodata)) {
                o[x] = out->nodata;
                continue;
            }
            b = near_slope(dem, x, y, gx, gy, cs);
            o[x] = (float)(atan(t > b ? t : b) * (180.0 / M_PI));
        }
    }
}

/* See horizon.h. */
int td_horizon_direction(const td_grid_f32 *dem, double azimuth_deg,
                         const td_horizon_params *p, td_grid_f32 *out,
                         td_ctx *cx)
{
    sweep s;
    double *buf = NULL;
    long q, qmin, qmax, par;
    int y, rc, nth = omp_get_max_threads();
    if ((rc = check_args(dem, p, out, cx)) != 0)
        return rc;
    if (!isfinite(azimuth_deg))
        return td_seterr(cx, TD_EINVAL, "horizon: azimuth is not finite");
    sweep_setup(&s, dem, azimuth_deg, p, out);
    buf = td_malloc((sizeof(double) * 4 + sizeof(int) * 2) * (size_t)s.M *
                    (size_t)nth, cx);
    if (!buf)
        return TD_ENOMEM;
    for (y = 0; y < out->h; y++)
        memset(out->data + (size_t)y * out->stride, 0,
               sizeof(float) * (size_t)out->w);
    qmin = (long)floor(fmin(0.0, -s.a * (s.M - 1))) - 1;
    qmax = (long)ceil(s.N - 1 + fmax(0.0, -s.a * (s.M - 1))) + 1;
    /* profiles q and q+1 share cells: even and odd q in two phases */
    for (par = 0; par < 2; par++) {
#pragma omp parallel num_threads(nth)
        {
            size_t m2 = 2 * (size_t)s.M;
            double *mine = (double *)((char *)buf + (size_t)omp_get_thread_num() *
                                      (sizeof(double) * 2 + sizeof(int)) * m2);
            hull h = {mine, mine + m2, (int *)(mine + 2 * m2), 0};
#pragma omp for schedule(dynamic, 16)
            for (q = qmin + par; q <= qmax; q += 2)
                profile(&s, (double)q, &h);
        }
    }
    finish(dem, azimuth_deg, p->cell_size, out);
    free(buf);
    return 0;
}

/* See horizon.h. */
int td_horizon_sweep(const td_grid_f32 *dem, const td_horizon_params *p,
                     td_grid_f32 *const *bands, td_ctx *cx)
{
    int i, rc;
    if (!p || p->directions < 1 || p->directions > 3600)
        return td_seterr(cx, TD_EINVAL, "horizon: directions must be "
                         "1..3600");
    for (i = 0; i < p->directions; i++) {
        double az = 360.0 * i / p->directions;
        if ((rc = td_horizon_direction(dem, az, p, bands[i], cx)) != 0)
            return rc;
        if ((rc = td_progress(cx, "horizon",
                              (double)(i + 1) / p->directions)) != 0)
            return rc;
    }
    return 0;
}
