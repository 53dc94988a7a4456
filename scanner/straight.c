/* straight.c: the map grid's straight lines out of the ink mask (model and
 * contract in straight.h).  Counts run in row order for both directions,
 * so the mask is read twice, cache-friendly, whatever its size. */
#include "scanner/straight.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { SIDE = 6, NSLOPE = 27, MAX_LINES = 64, MAX_RUN = 3, MIN_PEAKS = 6 };
#define RATIO 1.4          /* a peak at least this many times its sides */
#define SLOPE_STEP 0.002   /* Hough slope bins (px per px) */
#define MAX_SLOPE 0.0262   /* tan 1.5 degrees: a scan's skew at most */
#define MAX_DRIFT 600.0    /* |slope| x the longest side, px (bounded) */
#define NEAR 0.75 /* a run erased holds a pixel this near the line's centre */

td_straight_params td_straight_defaults(void)
{
    td_straight_params p;
    p.on = 1;
    p.strip = 128;
    p.cover = 0.3;
    p.contrast = 0.15;
    p.span = 0.4;
    p.line_cover = 0.35;
    p.max_width = 6.0;
    return p;
}

/* Band counts for vertical lines: c[s * w + x] = rows of strip s with ink
 * at x - 1, x or x + 1 (mask values 0 or 1). */
static void count_vertical(const td_grid_u8 *g, int S, int *c)
{
    int w = g->w, ns = (g->h + S - 1) / S, s;
#pragma omp parallel for schedule(dynamic)
    for (s = 0; s < ns; s++) { /* each strip its own row of counts */
        int *row = c + (size_t)s * w, x, y,
            y1 = (s + 1) * S < g->h ? (s + 1) * S : g->h;
        for (y = s * S; y < y1; y++) {
            const uint8_t *r = g->data + (size_t)y * g->stride;
            row[0] += (r[0] | (w > 1 ? r[1] : 0)) != 0;
            for (x = 1; x + 1 < w; x++)
                row[x] += (r[x - 1] | r[x] | r[x + 1]) != 0;
            if (w > 1)
                row[w - 1] += (r[w - 2] | r[w - 1]) != 0;
        }
    }
}

/* Band counts for horizontal lines: c[s * h + y] = columns of strip s
 * (S columns) with ink at y - 1, y or y + 1. */
static void count_horizontal(const td_grid_u8 *g, int S, int *c)
{
    int y;
#pragma omp parallel for schedule(static)
    for (y = 0; y < g->h; y++) {
        const uint8_t *r = g->data + (size_t)y * g->stride;
        const uint8_t *a = y > 0 ? r - g->stride : r;
        const uint8_t *b = y + 1 < g->h ? r + g->stride : r;
        int x, s;
        for (s = 0; s * S < g->w; s++) {
            int sum = 0, x1 = (s + 1) * S < g->w ? (s + 1) * S : g->w;
            for (x = s * S; x < x1; x++)
                sum += (a[x] | r[x] | b[x]) != 0;
            c[(size_t)s * g->h + y] = sum;
        }
    }
}

typedef struct peak {
    int s, u, used;
} peak;

/* Whether u is a peak of strip row c (nu long, len rows in the strip). */
static int is_peak(const int *c, int nu, int u, int len,
                   const td_straight_params *p)
{
    int k, v = c[u], side = 0;
    if (v < p->cover * len)
        return 0;
    for (k = -2; k <= 2; k++)
        if (k && u + k >= 0 && u + k < nu &&
            (c[u + k] > v || (k < 0 && c[u + k] == v)))
            return 0;
    if (u - SIDE >= 0)
        side = c[u - SIDE];
    if (u + SIDE < nu && c[u + SIDE] > side)
        side = c[u + SIDE];
    return v - side >= p->contrast * len && v >= RATIO * side;
}

/* The strip's centre row (the last strip may be short). */
static double centre(int s, int S, int nv)
{
    return fmin(s * S + 0.5 * S, 0.5 * (s * S + nv));
}

/* Every strip's peaks into *pk (n of them). */
static int find_peaks(const int *c, int nu, int ns, int S, int nv,
                      const td_straight_params *p, peak **pk, size_t *n,
                      td_ctx *cx)
{
    size_t cap = 0;
    int s, u;
    *pk = NULL;
    *n = 0;
    for (s = 0; s < ns; s++) {
        int len = (s + 1) * S < nv ? S : nv - s * S;
        for (u = 0; u < nu; u++) {
            if (!is_peak(c + (size_t)s * nu, nu, u, len, p))
                continue;
            if (*n == cap) {
                peak *q = realloc(*pk, (cap = cap ? 2 * cap : 256) *
                                           sizeof *q);
                if (!q)
                    return td_seterr(cx, TD_ENOMEM, "out of memory");
                *pk = q;
            }
            (*pk)[(*n)++] = (peak){s, u, 0};
        }
    }
    return 0;
}

/* Hough vote of the unused peaks over (slope, intercept): slope bins of
 * SLOPE_STEP up to MAX_SLOPE, intercept bins of 2 px (a peak votes for
 * its bin and both neighbours); each cell counts a strip once.  Returns the best cell's count, its line in *a, *b. */
static int vote(const peak *pk, size_t n, int nu, int S, int nv, int *acc,
                int *last, int nb, double *a, double *b)
{
    int best = 0, k;
    size_t i, cells = (size_t)NSLOPE * nb;
    for (i = 0; i < cells; i++)
        acc[i] = 0, last[i] = -1;
    for (i = 0; i < n; i++) {
        double v = centre(pk[i].s, S, nv);
        if (pk[i].used)
            continue;
        for (k = 0; k < NSLOPE; k++) {
            double sl = (k - NSLOPE / 2) * SLOPE_STEP;
            int ib0 = (int)floor((pk[i].u - sl * v + MAX_DRIFT) / 2.0), ib;
            for (ib = ib0 - 1; ib <= ib0 + 1; ib++) { /* +-2 px */
                size_t cell = (size_t)k * nb + (size_t)ib;
                if (ib < 0 || ib >= nb || last[cell] == pk[i].s)
                    continue;
                last[cell] = pk[i].s;
                if (++acc[cell] > best) {
                    best = acc[cell];
                    *b = sl;
                    *a = 2.0 * ib + 1.0 - MAX_DRIFT;
                }
            }
        }
    }
    (void)nu;
    return best;
}

/* The peaks within 3 px of u = a + b v (the nearest per strip), least
 * squares refit, then twice: drop those off by more than 1.5 px and
 * refit.  Marks the kept ones in keep[]; returns how many. */
static int refine(const peak *pk, size_t n, int ns, int S, int nv,
                  double *a, double *b, char *keep)
{
    int pass, m = 0;
    size_t i;
    memset(keep, 0, n);
    for (pass = 0; pass < 3; pass++) {
        double sv = 0, su = 0, svv = 0, svu = 0, d;
        double tol = pass == 0 ? 3.0 : 1.5;
        int s;
        m = 0;
        for (s = 0; s < ns; s++) {
            size_t bi = n;
            double bd = tol;
            for (i = 0; i < n; i++) {
                double r;
                if (pk[i].used || pk[i].s != s)
                    continue;
                r = fabs(*a + *b * centre(s, S, nv) - pk[i].u);
                if (r <= bd)
                    bd = r, bi = i;
            }
            for (i = 0; i < n; i++)
                if (pk[i].s == s)
                    keep[i] = i == bi;
            if (bi < n) {
                double v = centre(s, S, nv);
                sv += v, su += pk[bi].u, svv += v * v, svu += v * pk[bi].u;
                m++;
            }
        }
        if (m < 2)
            return m;
        d = m * svv - sv * sv;
        *b = d > 0 ? (m * svu - sv * su) / d : 0.0;
        *a = (su - *b * sv) / m;
    }
    return fabs(*b) <= MAX_SLOPE ? m : 0;
}

/* Pixel (u across the line, v along it). */
static uint8_t *px(td_grid_u8 *g, int vertical, int u, int v)
{
    return vertical ? g->data + (size_t)v * g->stride + u
                    : g->data + (size_t)u * g->stride + v;
}

/* The line refitted to its own ink: the peaks sit on whole columns of 3-px
 * band counts, so a can be a pixel or two off the ink.  Least squares over
 * the centres of the narrow runs (at most 2 px: the line alone, no contour
 * on it) within 2.5 px of the line, then twice over those within 1 px of
 * the fit (contours crossing steeply leave narrow runs beside it). */
static void centre_ink(td_grid_u8 *g, int vertical, int nu, int nv, double *a,
                       double *b)
{
    int pass;
    for (pass = 0; pass < 3; pass++) {
        double sv = 0, su = 0, svv = 0, svu = 0, d, tol = pass ? 1.0 : 2.5;
        int v, m = 0;
        for (v = 0; v < nv; v++) {
            double x = *a + *b * v, c;
            int lo = (int)floor(x - 2.5) + 1, hi, u;
            if (lo < 0)
                lo = 0;
            for (u = lo; u <= x + 2.5 && u < nu && !*px(g, vertical, u, v); u++)
                ;
            if (u > x + 2.5 || u >= nu || (u > 0 && *px(g, vertical, u - 1, v)))
                continue; /* no ink, or a run from further out */
            for (hi = u; hi + 1 < nu && *px(g, vertical, hi + 1, v); hi++)
                ;
            c = 0.5 * (u + hi);
            if (hi - u + 1 > 2 || fabs(c - x) > tol)
                continue;
            sv += v, su += c, svv += (double)v * v, svu += v * c;
            m++;
        }
        d = m * svv - sv * sv;
        if (m < 16 || !(d > 0))
            return;
        *b = (m * svu - sv * su) / d;
        *a = (su - *b * sv) / m;
    }
}

/* The ink pixel on the line at v: the one nearest its centre a + b v,
 * within NEAR px; -1 when there is none. */
static int on_line(td_grid_u8 *g, int vertical, int nu, int v, double a,
                   double b)
{
    double x = a + b * v;
    int u0 = (int)lround(x), k;
    for (k = 0; k <= 2; k++) { /* u0, u0 - 1, u0 + 1 */
        int c = k == 0 ? u0 : k == 1 ? u0 - 1 : u0 + 1;
        if (c >= 0 && c < nu && fabs(c - x) <= NEAR && *px(g, vertical, c, v))
            return c;
    }
    return -1;
}

/* The share of the line's length with ink within 1 px of it. */
static double continuity(td_grid_u8 *g, int vertical, int nu, int nv,
                         double a, double b)
{
    int v, hit = 0;
    for (v = 0; v < nv; v++) {
        int u = (int)lround(a + b * v);
        hit += (u >= 0 && u < nu && *px(g, vertical, u, v)) ||
               (u > 0 && u - 1 < nu && *px(g, vertical, u - 1, v)) ||
               (u + 1 >= 0 && u + 1 < nu && *px(g, vertical, u + 1, v));
    }
    return nv > 0 ? (double)hit / nv : 0.0;
}

/* The line's ink width: the median run across it, sampled every 4 px. */
static double line_width(td_grid_u8 *g, int vertical, int nu, int nv,
                         double a, double b)
{
    int hist[16] = {0}, n = 0, v, k, acc = 0;
    for (v = 0; v < nv; v += 4) {
        int u = on_line(g, vertical, nu, v, a, b), lo, hi;
        if (u < 0)
            continue;
        lo = hi = u;
        while (lo > 0 && *px(g, vertical, lo - 1, v) && u - lo < 15)
            lo--;
        while (hi + 1 < nu && *px(g, vertical, hi + 1, v) && hi - u < 15)
            hi++;
        hist[hi - lo + 1 < 16 ? hi - lo + 1 : 15]++;
        n++;
    }
    for (k = 0; k < 16 && 2 * (acc += hist[k]) < n; k++)
        ;
    return n ? k : 0;
}

/* Erase the line where it runs alone: at each v the run of ink across it
 * (through its pixel within NEAR px of the line's centre: a contour 2 px
 * beside a 1-px line is not the line) when at most maxrun px
 * long (the line's median width, at least MAX_RUN; one px more took more
 * of the contours crossing it on the printed Orkhon sheet: own 0.985 ->
 * 0.979); a longer run is a contour crossing there, and stays, so the
 * contours keep their ink and are not cut. */
static void erase(td_grid_u8 *g, int vertical, int nu, int nv, double a,
                  double b, int maxrun)
{
    int v, u;
    for (v = 0; v < nv; v++) {
        int start = on_line(g, vertical, nu, v, a, b), lo, hi;
        if (start < 0)
            continue;
        lo = hi = start;
        while (lo > 0 && *px(g, vertical, lo - 1, v) && hi - lo < maxrun)
            lo--;
        while (hi + 1 < nu && *px(g, vertical, hi + 1, v) && hi - lo < maxrun)
            hi++;
        if (hi - lo + 1 > maxrun)
            continue;
        for (u = lo; u <= hi; u++)
            *px(g, vertical, u, v) = 0;
    }
}

/* One direction: count, find the peaks, vote, erase the lines found;
 * *found += lines erased. */
static int one_direction(td_grid_u8 *g, int vertical,
                         const td_straight_params *p, size_t *found,
                         td_ctx *cx)
{
    int S = p->strip > 16 ? p->strip : 16;
    int nu = vertical ? g->w : g->h, nv = vertical ? g->h : g->w;
    int ns = (nv + S - 1) / S, nb = (int)((nu + 2 * MAX_DRIFT) / 2) + 2;
    int need = (int)ceil(p->span * ns), lines, rc = TD_ENOMEM;
    int *c = NULL, *acc = NULL, *last = NULL;
    peak *pk = NULL;
    char *keep = NULL;
    size_t n = 0, i;
    if (ns < 6)
        return 0; /* too short a sheet to tell a line */
    if (need < MIN_PEAKS)
        need = MIN_PEAKS;
    if (!(c = td_calloc((size_t)ns * nu, sizeof *c, cx)) ||
        !(acc = td_malloc((size_t)NSLOPE * nb * sizeof *acc, cx)) ||
        !(last = td_malloc((size_t)NSLOPE * nb * sizeof *last, cx)))
        goto done;
    if (vertical)
        count_vertical(g, S, c);
    else
        count_horizontal(g, S, c);
    if ((rc = find_peaks(c, nu, ns, S, nv, p, &pk, &n, cx)) != 0)
        goto done;
    rc = TD_ENOMEM;
    if (!(keep = td_malloc(n + 1, cx)))
        goto done;
    for (lines = 0; lines < MAX_LINES; lines++) {
        double a = 0, b = 0, w;
        int mm;
        if (vote(pk, n, nu, S, nv, acc, last, nb, &a, &b) < need)
            break;
        mm = refine(pk, n, ns, S, nv, &a, &b, keep);
        if (mm < need) {
            for (i = 0; i < n; i++) /* not a line: do not vote again */
                pk[i].used |= keep[i];
            continue;
        }
        for (i = 0; i < n; i++)
            pk[i].used |= keep[i];
        centre_ink(g, vertical, nu, nv, &a, &b);
        w = line_width(g, vertical, nu, nv, a, b);
        if (!(w > 0) || w > p->max_width ||
            continuity(g, vertical, nu, nv, a, b) < p->line_cover)
            continue;
        erase(g, vertical, nu, nv, a, b, w > MAX_RUN ? (int)w : MAX_RUN);
        (*found)++;
    }
    rc = 0;
done:
    free(c);
    free(acc);
    free(last);
    free(pk);
    free(keep);
    return rc;
}

/* See straight.h. */
int td_straight_remove(td_grid_u8 *mask, const td_straight_params *p,
                       size_t *found, td_ctx *cx)
{
    size_t n = 0;
    int rc = 0;
    if (p->on)
        rc = one_direction(mask, 1, p, &n, cx);
    if (rc == 0 && p->on)
        rc = one_direction(mask, 0, p, &n, cx);
    if (found)
        *found = n;
    return rc;
}
