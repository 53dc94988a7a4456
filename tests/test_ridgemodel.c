/* test_ridgemodel.c: the ridgeline model (src/model/ridgemodel.c, paper
 * 000 §2.1-2.4): heights inside the skirts of a level and a sloping
 * segment and at a bend (the highest surface wins), a free end's cap,
 * Algorithm 2.4's heights on hand-made trees, a cycle refused, the two
 * deletion algorithms (2.2 lists, 2.3 winners) equal to a full render bit
 * for bit after random adds and deletes, and the recursive generation
 * (2.5, src/model/ridgegen.c). */
#include "tests/tt.h"
#include "src/model/model.h"

#include <stdlib.h>
#include <string.h>

/* The z-buffer at cell (col, row). */
static double zat(const td_ridgemodel *m, int col, int row)
{
    const td_grid_f32 *z = td_ridgemodel_zbuffer(m);
    return z->data[(size_t)row * z->w + col];
}

static td_ridgemodel *model(int w, int h, double slope, int method)
{
    td_ridge_params p = td_ridge_defaults();
    p.slope = slope, p.smooth = 0, p.method = method;
    return td_ridgemodel_new(w, h, &p, NULL);
}

/* A level segment at 100 and a sloping one, slope 45 degrees (1 per
 * cell): z(s) minus the distance to the segment, within 0.5 % of the
 * relief (exact here: the skirts are planes). */
static void test_one_segment(void)
{
    td_ridgemodel *m = model(200, 200, 45, TD_RM_WINNERS);
    TT_CHECK(td_ridgemodel_add(m, 50, 100, 100, 150, 100, 100, NULL) == 0);
    TT_CHECK(td_ridgemodel_render(m, NULL) == 0);
    TT_NEAR(zat(m, 100, 130), 100 - 30.5, 0.5);  /* below the segment */
    TT_NEAR(zat(m, 70, 60), 100 - 39.5, 0.5);    /* above it */
    TT_NEAR(zat(m, 100, 100), 100 - 0.5, 0.5);   /* on it */
    TT_NEAR(zat(m, 5, 100), 100 - hypot(44.5, 0.5), 1.0); /* the cap */
    TT_NEAR(zat(m, 100, 199), 0.5, 0.01);
    TT_CHECK(zat(m, 0, 0) == 0.0f); /* beyond every skirt: the base */
    td_ridgemodel_free(m);
    m = model(200, 200, 45, TD_RM_WINNERS);
    TT_CHECK(td_ridgemodel_add(m, 50, 100, 100, 150, 100, 50, NULL) == 0);
    TT_CHECK(td_ridgemodel_render(m, NULL) == 0);
    /* z at x = 100.5: 100 - 50 x 50.5 / 100 = 74.75; 20.5 cells away */
    TT_NEAR(zat(m, 100, 120), 74.75 - 20.5, 0.01);
    TT_NEAR(zat(m, 140, 90), 100 - 50 * 0.905 - 9.5, 0.01);
    td_ridgemodel_free(m);
}

/* A right-angled bend at (100, 100): inside the corner each skirt gives
 * 100 minus the distance to its own segment and the higher one wins;
 * outside it the gap is closed by the fan (no cell left at the base). */
static void test_bend(void)
{
    td_ridgemodel *m = model(200, 200, 45, TD_RM_LISTS);
    TT_CHECK(td_ridgemodel_add(m, 40, 100, 100, 100, 100, 100, NULL) == 0);
    TT_CHECK(td_ridgemodel_add(m, 100, 100, 100, 100, 40, 100, NULL) == 1);
    TT_CHECK(td_ridgemodel_render(m, NULL) == 0);
    TT_NEAR(zat(m, 80, 80), 100 - 19.5, 0.01);
    TT_NEAR(zat(m, 90, 70), 100 - 9.5, 0.01);  /* B's skirt wins */
    TT_NEAR(zat(m, 60, 90), 100 - 9.5, 0.01);  /* A's skirt wins */
    /* the outer corner: the fan, between the true cone and 8 % steeper */
    {
        double d = hypot(20.5, 20.5), h = zat(m, 120, 120);
        TT_CHECKF(h <= 100 - d + 0.01 && h >= 100 - 1.09 * d,
                  "corner %g, cone %g", h, 100 - d);
    }
    td_ridgemodel_free(m);
}

/* Algorithm 2.4 on a hand-made tree (slope 45: heights = leaf + path):
 *
 *   L1 (0,50) --- N1 (50,50) --- N2 (100,50) --- L2 (100,60)
 *                                  |
 *                                  L3 (100,130)
 *
 * N2's nearest leaf is L2 (10), N1's is L1 (50, not 50 + 10). */
static void test_tree_heights(void)
{
    td_ridgemodel *m = model(200, 200, 45, TD_RM_WINNERS);
    double xyz[3 * 8];
    size_t n, i;
    td_ridgemodel_add(m, 0, 50, NAN, 50, 50, NAN, NULL);
    td_ridgemodel_add(m, 50, 50, NAN, 100, 50, NAN, NULL);
    td_ridgemodel_add(m, 100, 50, NAN, 100, 60, NAN, NULL);
    td_ridgemodel_add(m, 100, 50, NAN, 100, 130, NAN, NULL);
    TT_CHECK(td_ridgemodel_tree_heights(m, 200, NULL) == 0);
    n = td_ridgemodel_nodes(m, xyz, 8);
    TT_CHECK(n == 5);
    for (i = 0; i < n && i < 8; i++) {
        double x = xyz[3 * i], y = xyz[3 * i + 1], z = xyz[3 * i + 2];
        double want = x == 50 ? 250 : x == 100 && y == 50 ? 210 : 200;
        TT_CHECKF(fabs(z - want) < 1e-9, "node (%g,%g): %g, want %g", x, y,
                  z, want);
    }
    TT_CHECK(td_ridgemodel_render(m, NULL) == 0);
    TT_NEAR(zat(m, 50, 60), 250 - 10.5, 1.0); /* under N1 */
    td_ridgemodel_free(m);
    /* the same with 30 degrees: leaf + tan(30) x path */
    m = model(200, 200, 30, TD_RM_WINNERS);
    td_ridgemodel_add(m, 0, 50, NAN, 50, 50, NAN, NULL);
    td_ridgemodel_add(m, 50, 50, NAN, 100, 50, NAN, NULL);
    TT_CHECK(td_ridgemodel_tree_heights(m, 10, NULL) == 0);
    n = td_ridgemodel_nodes(m, xyz, 8);
    for (i = 0; i < n && i < 8; i++)
        if (xyz[3 * i] == 50)
            TT_NEAR(xyz[3 * i + 2], 10 + tan(M_PI / 6) * 50, 1e-9);
    td_ridgemodel_free(m);
}

/* A ring of ridges is no tree: one clear error naming where. */
static void test_cycle_refused(void)
{
    td_ridgemodel *m = model(100, 100, 30, TD_RM_WINNERS);
    td_ctx cx;
    td_ctx_init(&cx);
    td_ridgemodel_add(m, 10, 10, NAN, 50, 10, NAN, NULL);
    td_ridgemodel_add(m, 50, 10, NAN, 50, 50, NAN, NULL);
    td_ridgemodel_add(m, 50, 50, NAN, 10, 10, NAN, NULL);
    TT_CHECK(td_ridgemodel_tree_heights(m, 0, &cx) == TD_EINVAL);
    TT_CHECKF(strstr(td_errmsg(&cx), "cycle") != NULL, "%s", td_errmsg(&cx));
    td_ridgemodel_free(m);
}

static uint64_t rng = 88172645463325252u;
static double urand(void)
{
    rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
    return (double)(rng >> 11) / 9007199254740992.0;
}

/* Random segments between the points of a 7 x 7 lattice (so they share
 * nodes), random heights per lattice point; 200 random adds and deletes
 * on a model, then the same live segments rendered afresh: the z-buffers
 * are equal bit for bit, for 2.2 and for 2.3. */
static void test_edits_equal_render(void)
{
    int method;
    for (method = TD_RM_LISTS; method <= TD_RM_WINNERS; method++) {
        double hz[49];
        long live[400];
        double seg[400][4];
        size_t nlive = 0, i, k;
        td_ridgemodel *m = model(160, 140, 35, method), *f;
        for (i = 0; i < 49; i++)
            hz[i] = 10 + 50 * urand();
        for (i = 0; i < 20; i++) { /* the first ones before the render */
            int a = (int)(urand() * 49), b = (int)(urand() * 49);
            if (a == b)
                continue;
            seg[nlive][0] = a, seg[nlive][1] = b;
            live[nlive++] = td_ridgemodel_add(
                m, 20 + 20 * (a % 7), 10 + 20 * (a / 7), hz[a],
                20 + 20 * (b % 7), 10 + 20 * (b / 7), hz[b], NULL);
        }
        TT_CHECK(td_ridgemodel_render(m, NULL) == 0);
        for (k = 0; k < 200; k++) {
            if (nlive > 0 && (urand() < 0.45 || nlive >= 390)) {
                size_t j = (size_t)(urand() * nlive);
                TT_CHECK(td_ridgemodel_delete(m, live[j], NULL) == 0);
                live[j] = live[--nlive];
                memcpy(seg[j], seg[nlive], sizeof seg[j]);
            } else {
                int a = (int)(urand() * 49), b = (int)(urand() * 49);
                if (a == b)
                    continue;
                seg[nlive][0] = a, seg[nlive][1] = b;
                live[nlive++] = td_ridgemodel_add(
                    m, 20 + 20 * (a % 7), 10 + 20 * (a / 7), hz[a],
                    20 + 20 * (b % 7), 10 + 20 * (b / 7), hz[b], NULL);
                TT_CHECK(live[nlive - 1] >= 0);
            }
        }
        f = model(160, 140, 35, method);
        for (i = 0; i < nlive; i++) {
            int a = (int)seg[i][0], b = (int)seg[i][1];
            td_ridgemodel_add(f, 20 + 20 * (a % 7), 10 + 20 * (a / 7), hz[a],
                              20 + 20 * (b % 7), 10 + 20 * (b / 7), hz[b],
                              NULL);
        }
        TT_CHECK(td_ridgemodel_render(f, NULL) == 0);
        {
            const td_grid_f32 *za = td_ridgemodel_zbuffer(m);
            const td_grid_f32 *zb = td_ridgemodel_zbuffer(f);
            size_t diff = 0;
            for (i = 0; i < (size_t)za->w * za->h; i++)
                diff += za->data[i] != zb->data[i];
            TT_CHECKF(diff == 0, "%s: %zu cells differ from a full render "
                      "(%zu segments live)",
                      method == TD_RM_LISTS ? "2.2 lists" : "2.3 winners",
                      diff, nlive);
        }
        td_ridgemodel_free(m);
        td_ridgemodel_free(f);
    }
}

/* Algorithm 2.5 from one main ridge: new ridges grow from it round by
 * round, every one falling away from where it starts and none above the
 * main ridge; the same seed gives the same ridges, another seed others. */
static void test_generate(void)
{
    td_ridge_params rp = td_ridge_defaults();
    td_ridgegen_params gp = td_ridgegen_defaults();
    double *v[3], slope = 0;
    size_t n[3], i;
    int k;
    rp.slope = 25, rp.smooth = 0;
    for (k = 0; k < 3; k++) {
        v[k] = malloc(12 * sizeof *v[k]);
        n[k] = 2;
        memcpy(v[k], (double[12]){60, 150, 120, 200, 120, 150,
                                  200, 120, 150, 340, 160, 110},
               12 * sizeof(double));
        gp.seed = k == 2 ? 7 : 3;
        TT_CHECK(td_ridgegen(&v[k], &n[k], 400, 300, &rp, &gp, &slope,
                             NULL) == 0);
    }
    TT_CHECKF(n[0] > 20, "%zu segments after 2 rounds", n[0]);
    TT_NEAR(slope, 45, 1e-9);
    TT_CHECK(n[0] == n[1] && !memcmp(v[0], v[1], 6 * n[0] * sizeof(double)));
    TT_CHECK(n[2] != n[0] || memcmp(v[0], v[2], 6 * n[0] * sizeof(double)));
    for (i = 2; i < n[0]; i++) {
        const double *q = v[0] + 6 * i;
        TT_CHECKF(q[5] <= q[2] && q[2] <= 150,
                  "segment %zu rises: %g -> %g", i, q[2], q[5]);
        if (q[5] > q[2] || q[2] > 150)
            break;
    }
    for (k = 0; k < 3; k++)
        free(v[k]);
}

static void test_bad_params(void)
{
    td_ridge_params p = td_ridge_defaults();
    td_ctx cx;
    td_ctx_init(&cx);
    p.slope = 90;
    TT_CHECK(td_ridgemodel_new(10, 10, &p, &cx) == NULL && cx.code == TD_EINVAL);
    p.slope = 30;
    TT_CHECK(td_ridgemodel_new(0, 10, &p, NULL) == NULL);
    {
        td_ridgemodel *m = td_ridgemodel_new(10, 10, &p, NULL);
        td_ridgemodel_add(m, 1, 1, NAN, 5, 5, NAN, NULL);
        TT_CHECK(td_ridgemodel_render(m, &cx) == TD_EINVAL); /* no heights */
        TT_CHECK(td_ridgemodel_add(m, NAN, 1, 0, 5, 5, 0, NULL) == -1);
        td_ridgemodel_free(m);
    }
}

int main(void)
{
    TT_RUN(test_one_segment);
    TT_RUN(test_bend);
    TT_RUN(test_tree_heights);
    TT_RUN(test_cycle_refused);
    TT_RUN(test_edits_equal_render);
    TT_RUN(test_generate);
    TT_RUN(test_bad_params);
    return tt_summary();
}
