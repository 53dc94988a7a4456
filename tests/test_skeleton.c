/* test_skeleton.c: the straight skeleton of a key outline
 * (src/model/skeleton.c, paper 004 §3) against roofs known exactly: a
 * rectangle (the hip roof) and convex polygons, where the time the front
 * passes a point is its distance to the nearest edge's line; orthogonal
 * outlines with reflex corners, edge and split events, where the straight
 * skeleton is the L-infinity medial axis and the time is the L-infinity
 * distance to the outline; the contours at equal steps; the paper's
 * B-spline and Delaunay surface (tin.c) near the roof; bad outlines. */
#include "tests/tt.h"
#include "src/model/model.h"

#include <stdlib.h>
#include <string.h>

static int inside(const double *xy, int n, double x, double y)
{
    int i, j, c = 0;
    for (i = 0, j = n - 1; i < n; j = i++)
        if ((xy[2 * i + 1] > y) != (xy[2 * j + 1] > y) &&
            x < (xy[2 * j] - xy[2 * i]) * (y - xy[2 * i + 1]) /
                        (xy[2 * j + 1] - xy[2 * i + 1]) +
                    xy[2 * i])
            c = !c;
    return c;
}

/* Distance from (x, y) to the line through a, b (Euclid). */
static double line_dist(double x, double y, const double *a, const double *b)
{
    double dx = b[0] - a[0], dy = b[1] - a[1];
    return fabs((x - a[0]) * dy - (y - a[1]) * dx) / hypot(dx, dy);
}

/* L-infinity distance from (x, y) to the axis-parallel segment a-b. */
static double linf(double x, double y, const double *a, const double *b)
{
    double x0 = fmin(a[0], b[0]), x1 = fmax(a[0], b[0]);
    double y0 = fmin(a[1], b[1]), y1 = fmax(a[1], b[1]);
    double dx = x < x0 ? x0 - x : x > x1 ? x - x1 : 0;
    double dy = y < y0 ? y0 - y : y > y1 ? y - y1 : 0;
    return fmax(dx, dy);
}

/* Roof of outline xy on a W x H grid against the expected time at every
 * cell centre inside (metric 0: nearest edge line, 1: L-infinity to the
 * outline); no cell outside may be set.  Returns the largest error. */
static double roof_error1(const char *name, const double *xy, int n, int W,
                          int H, int metric, int con, size_t *splits)
{
    td_grid_f32 *g = td_grid_f32_new(W, H, NULL);
    td_skeleton_params p = td_skeleton_defaults();
    td_skeleton_stats st;
    double err = 0;
    long wrong = 0;
    int x, y, i;
    p.construction = con;
    g->has_nodata = 1, g->nodata = -9999;
    for (i = 0; i < W * H; i++)
        g->data[i] = -9999;
    TT_CHECKF(td_skeleton(xy, (size_t)n, &p, g, NULL, NULL, &st, NULL) == 0, "%s",
              name);
    for (y = 0; y < H; y++)
        for (x = 0; x < W; x++) {
            double px = x + 0.5, py = y + 0.5, d = HUGE_VAL;
            float v = g->data[(size_t)y * W + x];
            if (!inside(xy, n, px, py)) {
                wrong += v != -9999;
                continue;
            }
            for (i = 0; i < n; i++)
                d = fmin(d, metric ? linf(px, py, xy + 2 * i,
                                          xy + 2 * ((i + 1) % n))
                                   : line_dist(px, py, xy + 2 * i,
                                               xy + 2 * ((i + 1) % n)));
            if (v == -9999)
                wrong++;
            else
                err = fmax(err, fabs(v - d));
        }
    TT_CHECKF(wrong == 0, "%s: %ld cells on the wrong side of the outline",
              name, wrong);
    if (splits)
        *splits = st.splits;
    td_grid_f32_free(g);
    return err;
}

/* roof_error1 by both constructions (the paper's and the queue): the
 * larger error; splits: the fewer split events of the two. */
static double roof_error(const char *name, const double *xy, int n, int W,
                         int H, int metric, size_t *splits)
{
    size_t s0 = 0, s1 = 0;
    double e0 = roof_error1(name, xy, n, W, H, metric, TD_SKEL_PAPER, &s0);
    double e1 = roof_error1(name, xy, n, W, H, metric, TD_SKEL_QUEUE, &s1);
    if (splits)
        *splits = s0 < s1 ? s0 : s1;
    return fmax(e0, e1);
}

static void test_hip_roof(void)
{
    static const double rect[] = {10, 10, 90, 10, 90, 50, 10, 50};
    double e = roof_error("rectangle", rect, 4, 100, 60, 0, NULL);
    TT_CHECKF(e < 1e-4, "rectangle: error %g", e);
}

/* Random convex polygons (points on an ellipse at random angles), either
 * way round. */
static void test_convex(void)
{
    uint64_t r = 12345;
    int k;
    for (k = 0; k < 20; k++) {
        double a[24], xy[48];
        int n = 3 + k % 10, i, j;
        for (i = 0; i < n; i++) {
            r ^= r << 13, r ^= r >> 7, r ^= r << 17;
            a[i] = (double)(r >> 11) / 9007199254740992.0 * 2 * M_PI;
        }
        for (i = 1; i < n; i++) /* sort the angles */
            for (j = i; j > 0 && a[j - 1] > a[j]; j--) {
                double t = a[j];
                a[j] = a[j - 1], a[j - 1] = t;
            }
        for (i = 0; i < n; i++) {
            int q = k & 1 ? n - 1 - i : i;
            xy[2 * i] = 60 + 50 * cos(a[q]);
            xy[2 * i + 1] = 45 + 35 * sin(a[q]);
        }
        {
            double e = roof_error("convex", xy, n, 120, 90, 0, NULL);
            TT_CHECKF(e < 1e-3, "convex polygon %d (%d corners): error %g",
                      k, n, e);
        }
    }
}

/* Orthogonal outlines with reflex corners: edge events, arms that shrink
 * to nothing, and split events (a slot cut from one side). */
static void test_orthogonal(void)
{
    static const double L[] = {10, 10, 90, 10, 90, 40, 50, 40, 50, 90, 10, 90};
    static const double comb[] = {10, 10, 110, 10, 110, 90, 95, 90, 95, 40,
                                  80, 40, 80, 90, 60, 90, 60, 50, 45, 50,
                                  45, 90, 30, 90, 30, 30, 20, 30, 20, 90,
                                  10, 90};
    static const double slot[] = {10, 10, 55, 10, 55, 40, 65, 40,
                                  65, 10, 110, 10, 110, 50, 10, 50};
    static const double slot2[] = {10, 10, 40, 10, 40, 45, 48, 45,
                                   48, 10, 110, 10, 110, 70, 80, 70,
                                   80, 30, 72, 30, 72, 70, 10, 70};
    size_t sp = 0, sp2 = 0;
    TT_CHECK(roof_error("L", L, 6, 100, 100, 1, NULL) < 1e-4);
    TT_CHECK(roof_error("comb", comb, 16, 120, 100, 1, NULL) < 1e-4);
    TT_CHECK(roof_error("slot", slot, 8, 120, 60, 1, &sp) < 1e-4);
    TT_CHECK(roof_error("slot2", slot2, 12, 120, 80, 1, &sp2) < 1e-4);
    TT_CHECKF(sp >= 1 && sp2 >= 1, "split events: %zu, %zu", sp, sp2);
}

/* Orthogonal staircases: a base and a top of random steps on a grid of
 * 10 (many events at one time: equal steps shrink together).  The queue's
 * roof is the L-infinity distance on every one; the paper's construction,
 * one event a step, goes wrong on about a third of them (docs/models.md),
 * so it is not held to this. */
static void test_staircases(void)
{
    uint64_t r = 4242;
    int k, worst_k = -1;
    double worst = 0;
    for (k = 0; k < 60; k++) {
        double xy[2 * 48];
        int m = 2 + k % 14, n = 0, i;
        xy[2 * n] = 5, xy[2 * n + 1] = 5, n++;
        for (i = 0; i < m; i++) {
            double x0 = 5 + (int)(90.0 * i / m), x1 = 5 + (int)(90.0 * (i + 1) / m);
            double h;
            r ^= r << 13, r ^= r >> 7, r ^= r << 17;
            h = 20 + (double)((r >> 11) % 6) * 10;
            xy[2 * n] = x0, xy[2 * n + 1] = h, n++;
            xy[2 * n] = x1, xy[2 * n + 1] = h, n++;
        }
        xy[2 * n] = xy[2 * (n - 1)], xy[2 * n + 1] = 5, n++;
        {
            double e = roof_error1("staircase", xy, n, 100, 100, 1,
                                   TD_SKEL_QUEUE, NULL);
            if (e > worst)
                worst = e, worst_k = k;
        }
    }
    TT_CHECKF(worst < 1e-4, "staircase %d: error %g", worst_k, worst);
}

/* Contours every 5: the rectangle's rings at 5, 10, 15 (its roof ends at
 * 20), each the outline shrunk by its time. */
static void test_contours(void)
{
    int con;
    for (con = TD_SKEL_PAPER; con <= TD_SKEL_QUEUE; con++) {
    static const double rect[] = {10, 10, 90, 10, 90, 50, 10, 50};
    td_skeleton_params p = td_skeleton_defaults();
    td_lines *c = td_lines_new(NULL);
    size_t i, k;
    p.construction = con;
    p.contour_step = 5;
    TT_CHECK(td_skeleton(rect, 4, &p, NULL, c, NULL, NULL, NULL) == 0);
    TT_CHECKF(c->n >= 3 && c->n <= 4, "%zu contours", c->n);
    for (i = 0; i < c->n && i < 3; i++) {
        const td_line *l = &c->v[i];
        double t = l->height, x0 = HUGE_VAL, x1 = -HUGE_VAL;
        TT_NEAR(t, 5.0 * (double)(i + 1), 1e-9);
        TT_CHECK(l->closed && l->n == 4);
        for (k = 0; k < l->n; k++)
            x0 = fmin(x0, l->xy[2 * k]), x1 = fmax(x1, l->xy[2 * k]);
        TT_NEAR(x0, 10 + t, 1e-6);
        TT_NEAR(x1, 90 - t, 1e-6);
    }
    td_lines_free(c);
    }
}

/* A star of 400 random corners (random radii at sorted random angles:
 * many reflex corners, split events everywhere): the queue gives the
 * paper's roof, contours and summits. */
static void test_queue_as_paper(void)
{
    enum { N = 400, W = 260 };
    uint64_t r = 777;
    double a[N], xy[2 * N];
    td_grid_f32 *g[2];
    td_lines *c[2], *pk[2];
    td_skeleton_stats st[2];
    double mx = 0, relief = 0;
    int i, j, con;
    for (i = 0; i < N; i++) {
        r ^= r << 13, r ^= r >> 7, r ^= r << 17;
        a[i] = (double)(r >> 11) / 9007199254740992.0 * 2 * M_PI;
    }
    for (i = 1; i < N; i++)
        for (j = i; j > 0 && a[j - 1] > a[j]; j--) {
            double t = a[j];
            a[j] = a[j - 1], a[j - 1] = t;
        }
    for (i = 0; i < N; i++) {
        double rad;
        r ^= r << 13, r ^= r >> 7, r ^= r << 17;
        rad = 40 + 85 * (double)(r >> 11) / 9007199254740992.0;
        xy[2 * i] = 130 + rad * cos(a[i]), xy[2 * i + 1] = 130 + rad * sin(a[i]);
    }
    for (con = 0; con < 2; con++) {
        td_skeleton_params p = td_skeleton_defaults();
        p.construction = con ? TD_SKEL_QUEUE : TD_SKEL_PAPER;
        p.contour_step = 4;
        g[con] = td_grid_f32_new(W, W, NULL);
        c[con] = td_lines_new(NULL), pk[con] = td_lines_new(NULL);
        g[con]->has_nodata = 1, g[con]->nodata = -9999;
        for (i = 0; i < W * W; i++)
            g[con]->data[i] = -9999;
        TT_CHECK(td_skeleton(xy, N, &p, g[con], c[con], pk[con], &st[con],
                             NULL) == 0);
    }
    for (i = 0; i < W * W; i++) {
        TT_CHECK((g[0]->data[i] == -9999) == (g[1]->data[i] == -9999));
        mx = fmax(mx, fabs(g[0]->data[i] - g[1]->data[i]));
        relief = fmax(relief, g[0]->data[i]);
    }
    TT_CHECKF(mx < 1e-4 * relief, "queue against paper: largest difference "
              "%g (relief %g)", mx, relief);
    TT_NEAR(st[1].max_time, st[0].max_time, 1e-9 * W);
    TT_CHECKF(c[0]->n == c[1]->n, "contours %zu / %zu", c[0]->n, c[1]->n);
    for (con = 0; con < 2; con++) /* every summit in the other's list */
        for (i = 0; i < (int)pk[con]->n; i++) {
            const td_line *q = &pk[con]->v[i];
            double best = HUGE_VAL;
            size_t k;
            for (k = 0; k < pk[!con]->n; k++) {
                const td_line *b = &pk[!con]->v[k];
                best = fmin(best, fmax(hypot(q->xy[0] - b->xy[0],
                                             q->xy[1] - b->xy[1]),
                                       fabs(q->height - b->height)));
            }
            /* 0.1: where a sliver of 0.003 cells splits off first */
            TT_CHECKF(best < 0.1, "%s summit %d at %g %g: nearest of the "
                      "other %g away", con ? "queue" : "paper", i, q->xy[0],
                      q->xy[1], best);
        }
    TT_CHECKF(st[0].splits > 20, "%zu split events", st[0].splits);
    for (con = 0; con < 2; con++) {
        td_grid_f32_free(g[con]);
        td_lines_free(c[con]), td_lines_free(pk[con]);
    }
}

/* The paper's surface on a square 80 x 80 (roof: a pyramid of 40): the
 * contours every 5 as B-splines, the outline and the summit triangulated;
 * near the roof (the splines round the ridges), the summit's height at
 * the centre, nothing outside the square. */
static void test_tin(void)
{
    static const double sq[] = {10, 10, 90, 10, 90, 90, 10, 90};
    td_grid_f32 *roof = td_grid_f32_new(100, 100, NULL);
    td_grid_f32 *tin = td_grid_f32_new(100, 100, NULL);
    td_lines *c = td_lines_new(NULL), *pk = td_lines_new(NULL);
    td_skeleton_params p = td_skeleton_defaults();
    double s2 = 0, mx = 0;
    size_t i, n = 0;
    roof->has_nodata = tin->has_nodata = 1;
    roof->nodata = tin->nodata = -9999;
    for (i = 0; i < 100 * 100; i++)
        roof->data[i] = tin->data[i] = -9999;
    p.contour_step = 5;
    TT_CHECK(td_skeleton(sq, 4, &p, roof, NULL, NULL, NULL, NULL) == 0);
    TT_CHECK(td_skeleton(sq, 4, &p, tin, c, pk, NULL, NULL) == 0);
    TT_CHECKF(pk->n == 1 && fabs(pk->v[0].height - 40) < 1e-6 &&
                  fabs(pk->v[0].xy[0] - 50) < 1e-6,
              "%zu peaks", pk->n);
    TT_CHECK(td_skeleton_tin(sq, 4, 0.0, c, pk, 2.0, tin, NULL) == 0);
    for (i = 0; i < 100 * 100; i++) {
        TT_CHECK((roof->data[i] == -9999) == (tin->data[i] == -9999));
        if (roof->data[i] == -9999)
            continue;
        s2 += (tin->data[i] - roof->data[i]) * (tin->data[i] - roof->data[i]);
        mx = fmax(mx, tin->data[i]);
        n++;
    }
    /* 4 control points round a square hard (its B-spline passes the
       corners at 2/3 of the way out): 4.39 here, docs/models.md */
    TT_CHECKF(sqrt(s2 / n) < 5.0, "TIN against the roof: RMSE %g (relief "
              "40)", sqrt(s2 / n));
    TT_NEAR(mx, 40, 1.0);
    td_lines_free(c);
    td_lines_free(pk);
    td_grid_f32_free(roof);
    td_grid_f32_free(tin);
}

static void test_bad_outlines(void)
{
    static const double bow[] = {10, 10, 50, 50, 50, 10, 10, 50};
    static const double flat[] = {10, 10, 50, 10, 90, 10};
    /* a corner on another edge; an arm folding back on itself */
    static const double touch[] = {10, 10, 90, 10, 90, 50, 50, 10, 10, 50};
    static const double fold[] = {10, 10, 90, 10, 90, 50, 90, 30, 10, 50};
    static const double dup[] = {10, 10, 90, 10, 90, 10, 90, 50, 10, 50};
    td_skeleton_params p = td_skeleton_defaults();
    td_ctx cx;
    td_ctx_init(&cx);
    TT_CHECK(td_skeleton(bow, 4, &p, NULL, NULL, NULL, NULL, &cx) == TD_EINVAL);
    TT_CHECKF(strstr(td_errmsg(&cx), "crosses or touches itself") != NULL, "%s",
              td_errmsg(&cx));
    TT_CHECK(td_skeleton(bow, 2, &p, NULL, NULL, NULL, NULL, NULL) == TD_EINVAL);
    TT_CHECK(td_skeleton(flat, 3, &p, NULL, NULL, NULL, NULL, NULL) == TD_EINVAL);
    TT_CHECK(td_skeleton(touch, 5, &p, NULL, NULL, NULL, NULL, NULL) == TD_EINVAL);
    TT_CHECK(td_skeleton(fold, 5, &p, NULL, NULL, NULL, NULL, NULL) == TD_EINVAL);
    /* a repeated corner is no crossing */
    TT_CHECK(td_skeleton(dup, 5, &p, NULL, NULL, NULL, NULL, NULL) == 0);
}

int main(void)
{
    TT_RUN(test_hip_roof);
    TT_RUN(test_convex);
    TT_RUN(test_orthogonal);
    TT_RUN(test_staircases);
    TT_RUN(test_contours);
    TT_RUN(test_queue_as_paper);
    TT_RUN(test_tin);
    TT_RUN(test_bad_outlines);
    return tt_summary();
}
