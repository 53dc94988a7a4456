/* Tests of the free ends that continue each other (scanner/endpair.c):
 * a contour broken by a gap, a V cut at its apex, ends side by side that
 * do not face, ends at the border, and each end kept by its best partner
 * only. */
#include "tests/tt.h"

#include "scanner/endpair.h"

#include <math.h>
#include <stdlib.h>

/* Add a polyline of n points (x, y pairs) to ls. */
static void add(td_lines *ls, const double *xy, size_t n)
{
    td_ctx cx;
    td_line *l;
    size_t k;
    td_ctx_init(&cx);
    l = td_lines_add(ls, &cx);
    TT_CHECK(l != NULL);
    for (k = 0; l && k < n; k++)
        TT_CHECK(td_line_push(l, xy[2 * k], xy[2 * k + 1], &cx) == 0);
}

/* A straight run from (x0, y0) to (x1, y1) sampled every px. */
static void add_run(td_lines *ls, double x0, double y0, double x1, double y1)
{
    double xy[2 * 512], L = hypot(x1 - x0, y1 - y0);
    size_t n = (size_t)ceil(L) + 1, k;
    if (n > 512)
        n = 512;
    for (k = 0; k < n; k++) {
        double t = (double)k / (double)(n - 1);
        xy[2 * k] = x0 + t * (x1 - x0);
        xy[2 * k + 1] = y0 + t * (y1 - y0);
    }
    add(ls, xy, n);
}

/* Lines of the straight runs r (x0, y0, x1, y1 each), n of them. */
static td_lines *runs_of(const double *r, size_t n)
{
    td_ctx cx;
    td_lines *ls;
    size_t i;
    td_ctx_init(&cx);
    ls = td_lines_new(&cx);
    TT_CHECK(ls != NULL);
    for (i = 0; ls && i < n; i++)
        add_run(ls, r[4 * i], r[4 * i + 1], r[4 * i + 2], r[4 * i + 3]);
    return ls;
}

static size_t pairs_of(const td_lines *ls, double gap, td_end_pair **p)
{
    td_ctx cx;
    size_t n = 0;
    td_ctx_init(&cx);
    TT_CHECK(td_end_pairs(ls, NULL, NULL, 400, 400, gap, p, &n, &cx) == 0);
    return n;
}

/* A line broken by a 10 px gap pairs its two pieces, last end of the
 * first with the first end of the second; at a 30 px gap (over
 * max_gap) nothing. */
static void test_broken_line(void)
{
    static const double r[] = {50, 200, 150, 200, 160, 201, 300, 201};
    td_lines *ls = runs_of(r, 2);
    td_end_pair *p = NULL;
    size_t n = pairs_of(ls, 24, &p);
    TT_CHECKF(n == 1 && p[0].a == 0 && p[0].alast == 1 && p[0].b == 1 &&
                  p[0].blast == 0 && fabs(p[0].d - 10.05) < 0.1 &&
                  p[0].ax == 150 && p[0].bx == 160 && p[0].by == 201,
              "%zu pairs", n);
    free(p);
    n = pairs_of(ls, 8, &p);
    TT_CHECKF(n == 0, "gap over max_gap: %zu pairs", n);
    free(p);
    td_lines_free(ls);
}

/* The two arms of a V whose apex a stream cut away (60 degrees open):
 * each arm's tangent 60 degrees off the chord, paired. */
static void test_vee_arms(void)
{
    double s = sin(M_PI / 6), c = cos(M_PI / 6);
    /* apex at (200, 200) pointing up; arms from 6 px off the apex */
    const double r[] = {200 - 80 * s, 200 + 80 * c, 200 - 6 * s,  200 + 6 * c,
                        200 + 6 * s,  200 + 6 * c,  200 + 80 * s, 200 + 80 * c};
    td_lines *ls = runs_of(r, 2);
    td_end_pair *p = NULL;
    size_t n = pairs_of(ls, 24, &p);
    TT_CHECKF(n == 1 && p[0].alast == 1 && p[0].blast == 0, "%zu pairs", n);
    free(p);
    td_lines_free(ls);
}

/* Ends of two parallel lines side by side (4 px apart, both ending at x
 * 150) do not face each other; ends at the sheet's border are left out. */
static void test_no_pair(void)
{
    static const double r[] = {
        50,  200, 150, 200, 50,  204,
        150, 204, 0,   300, 100, 300, /* starts on the border */
        0.5, 310, 100, 310};          /* within 2 px of it */
    td_lines *ls = runs_of(r, 4);
    td_end_pair *p = NULL;
    size_t n = pairs_of(ls, 24, &p);
    TT_CHECKF(n == 0, "%zu pairs", n);
    free(p);
    td_lines_free(ls);
}

/* Three pieces in a row: the middle one's ends each pair with the piece
 * they face; a fourth end across the gap but further and bent away loses
 * to the straight one. */
static void test_best_partner(void)
{
    static const double r[] = {20,  100, 100, 100, 108, 100, 200,
                               100, 210, 100, 300, 100, /* 3: 10 px off, bent */
                               214, 90,  300, 40};
    td_lines *ls = runs_of(r, 4);
    td_end_pair *p = NULL;
    size_t n = pairs_of(ls, 24, &p);
    TT_CHECKF(n == 2 && p[0].a == 0 && p[0].b == 1 && p[1].a == 1 &&
                  p[1].alast == 1 && p[1].b == 2 && p[1].blast == 0,
              "%zu pairs (first %zu-%zu)", n, n ? p[0].a : 0, n ? p[0].b : 0);
    free(p);
    td_lines_free(ls);
}

int main(void)
{
    TT_RUN(test_broken_line);
    TT_RUN(test_vee_arms);
    TT_RUN(test_no_pair);
    TT_RUN(test_best_partner);
    return tt_summary();
}
