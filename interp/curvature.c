/* curvature.c: inflection candidates, the epsilon test, ridge and valley
 * points on one contour (003 §4; ALGORITHMS.md B2 steps 3-4).
 *
 *   kappa   + + + + 0 - - - - - 0 + + 0 - 0 + + + + +
 *   stretch [ convex ][ concave  ][ c ][v][ convex   ]
 *   turn    Theta(s_i) - Theta(s_{i-1}) = integral of kappa ds
 *
 * Zero crossings of kappa split the contour into stretches.  While some
 * stretch turns by less than epsilon (|turn| < epsilon, the paper's test)
 * and more than one stretch is left, the weakest is dissolved: its two
 * bounding candidates are dropped, so it and its neighbours become one
 * stretch whose sign is that of its total turn (at an open end only the
 * inner candidate goes).  Neighbours of one sign are then joined.  On
 * every convex stretch the maximum of kappa is a ridge point, on every
 * concave one the minimum a valley point; the surviving candidates are
 * inflection points.  Extrema on the first or last 2 samples of an open
 * line are not taken: the sheet edge cut that stretch. */
#include "interp/homotopy_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct stretch {
    size_t a, b; /* samples [a, b) (cyclic on rings: b may be < a) */
    double turn;
} stretch;

/* Tangent direction change from sample i to i+1 (y-up frame), wrapped to
 * (-pi, pi]. */
static double dtheta(const td_rv_curve *c, size_t i)
{
    size_t n = c->n, j = (i + 1) % n, k = (i + 2) % n;
    double t0, t1, d;
    if (!c->closed && i + 2 >= n)
        return 0;
    t0 = atan2(-(c->y[j] - c->y[i]), c->x[j] - c->x[i]);
    t1 = atan2(-(c->y[k] - c->y[j]), c->x[k] - c->x[j]);
    d = t1 - t0;
    while (d > M_PI)
        d -= 2 * M_PI;
    while (d <= -M_PI)
        d += 2 * M_PI;
    return d;
}

/* Stretches between sign changes of kappa; *m of them into *out. */
static int split(const td_rv_curve *c, stretch **out, size_t *m, td_ctx *cx)
{
    size_t n = c->n, i, k = 0, first = n;
    stretch *v = td_malloc((n + 1) * sizeof *v, cx);
    if (!v)
        return TD_ENOMEM;
    for (i = 1; i < n + (size_t)c->closed; i++)
        if ((c->kappa[i % n] >= 0) != (c->kappa[i - 1] >= 0)) {
            if (first == n)
                first = i % n;
            else
                v[k - 1].b = i % n;
            v[k].a = i % n, v[k].b = n;
            k++;
        }
    if (!c->closed) {
        memmove(v + 1, v, k * sizeof *v);
        v[0].a = 0, v[0].b = first, k++;
    } else if (k == 0) {
        v[0].a = 0, v[0].b = n, k = 1;
    } else {
        v[k - 1].b = first; /* the last stretch wraps to the first change */
    }
    for (i = 0; i < k; i++)
        v[i].turn = 0;
    for (i = 0; i < k; i++) {
        size_t j = v[i].a;
        do {
            v[i].turn += dtheta(c, (j + n - 1) % n);
            j = (j + 1) % n;
        } while (j != v[i].b % n && !(j == 0 && !c->closed));
    }
    *out = v;
    *m = k;
    return 0;
}

/* Merge stretches [i, j] (cyclic indices) into one at i; remove the rest. */
static void merge(stretch *v, size_t *m, size_t i, size_t j)
{
    size_t k = i;
    while (k != j) {
        size_t nx = (k + 1) % *m;
        v[i].turn += v[nx].turn;
        v[i].b = v[nx].b;
        k = nx;
    }
    if (j >= i) {
        memmove(v + i + 1, v + j + 1, (*m - j - 1) * sizeof *v);
        *m -= j - i;
    } else { /* wrapped: keep i.. as the last, drop 0..j */
        memmove(v, v + j + 1, (*m - j - 1) * sizeof *v);
        *m -= j + 1;
    }
}

static void epsilon_test(const td_rv_curve *c, stretch *v, size_t *m,
                         double eps)
{
    for (;;) {
        size_t i, w = 0;
        for (i = 1; i < *m; i++)
            if (fabs(v[i].turn) < fabs(v[w].turn))
                w = i;
        if (*m <= 1 || fabs(v[w].turn) >= eps)
            break;
        if (c->closed) {
            if (*m == 2)
                merge(v, m, 0, 1);
            else
                merge(v, m, (w + *m - 1) % *m, (w + 1) % *m);
        } else if (w == 0 || w == *m - 1)
            merge(v, m, w == 0 ? 0 : w - 1, w == 0 ? 1 : w);
        else
            merge(v, m, w - 1, w + 1);
    }
    for (size_t i = 0; *m > 1 && i < *m;) { /* join neighbours of one sign */
        size_t j = (i + 1) % *m;
        if ((j != 0 || c->closed) && j != i &&
            (v[i].turn >= 0) == (v[j].turn >= 0))
            merge(v, m, i, j);
        else
            i++;
    }
}

static int push_point(td_ridges *r, size_t *cap, size_t ci, size_t i,
                      int kind, td_ctx *cx)
{
    const td_rv_curve *c = &r->curve[ci];
    td_rv_point *q;
    if (r->npt == *cap) {
        size_t nc = *cap * 2 + 64;
        void *t = realloc(r->pt, nc * sizeof *r->pt);
        if (!t)
            return td_seterr(cx, TD_ENOMEM, "out of memory");
        r->pt = t, *cap = nc;
    }
    q = &r->pt[r->npt++];
    q->curve = ci, q->i = i, q->kind = kind, q->tree = -1;
    q->x = c->x[i], q->y = c->y[i], q->z = c->z, q->s = c->s[i];
    q->kappa = c->kappa[i];
    return 0;
}

/* The extremum of a stretch; n when it is cut by an open end. */
static size_t extremum(const td_rv_curve *c, const stretch *st)
{
    size_t n = c->n, j = st->a, best = st->a;
    double sg = st->turn >= 0 ? 1 : -1;
    do {
        if (sg * c->kappa[j] > sg * c->kappa[best])
            best = j;
        j = (j + 1) % n;
    } while (j != st->b % n && !(j == 0 && !c->closed));
    if (!c->closed && (best < 2 || best + 2 >= n))
        return n;
    return best;
}

int hm_points(td_ridges *r, size_t ci, const td_homotopy_params *p,
              size_t *cap, td_ctx *cx)
{
    const td_rv_curve *c = &r->curve[ci];
    stretch *v = NULL;
    size_t m = 0, i;
    int rc;
    if (c->orient == 0 || c->n < 5)
        return 0;
    if ((rc = split(c, &v, &m, cx)) != 0)
        return rc;
    epsilon_test(c, v, &m, p->epsilon * M_PI / 180);
    for (i = 0; i < m && rc == 0; i++) {
        size_t e = extremum(c, &v[i]);
        if (fabs(v[i].turn) >= p->epsilon * M_PI / 180 && e < c->n)
            rc = push_point(r, cap, ci, e,
                            v[i].turn >= 0 ? TD_RV_RIDGE : TD_RV_VALLEY, cx);
        if (rc == 0 && m > 1 && (c->closed || i > 0))
            rc = push_point(r, cap, ci, v[i].a, TD_RV_INFLECT, cx);
    }
    free(v);
    return rc;
}
