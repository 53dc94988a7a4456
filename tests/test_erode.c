/* test_erode: velocity-field erosion (src/erode.h) and the mound generator
 * (src/terrain_gen.h) on small generated terrains with known behaviour. */
#include "../src/erode.h"
#include "../src/terrain_gen.h"
#include "tt.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static td_grid_f32 *mound(int n, double relief, uint64_t seed)
{
    td_mound_params mp = td_mound_defaults();
    td_grid_f32 *g = td_grid_f32_new(n, n, NULL);
    mp.height = relief;
    mp.seed = seed;
    if (g)
        td_terrain_mound(g, &mp, NULL);
    return g;
}

static td_grid_f32 *run(const td_grid_f32 *in, const td_erode_params *p,
                        td_erode_stats *st)
{
    td_grid_f32 *o = td_grid_f32_new(in->w, in->h, NULL);
    td_ctx cx;
    td_ctx_init(&cx);
    if (o && td_erode_run(in, p, o, NULL, st, &cx) != 0) {
        fprintf(stderr, "  erode: %s\n", td_errmsg(&cx));
        td_grid_f32_free(o);
        return NULL;
    }
    return o;
}

static double sum(const td_grid_f32 *g)
{
    double s = 0;
    size_t i;
    for (i = 0; i < (size_t)g->w * g->h; i++)
        if (!g->has_nodata || g->data[i] != g->nodata)
            s += g->data[i];
    return s;
}

/* Mean squared discrete Laplacian: the energy at the shortest wavelengths. */
static double hf_energy(const td_grid_f32 *g)
{
    double s = 0;
    int x, y, n = 0;
    for (y = 1; y < g->h - 1; y++)
        for (x = 1; x < g->w - 1; x++) {
            double l = TD_AT(g, x, y) - 0.25 * (TD_AT(g, x - 1, y) +
                       TD_AT(g, x + 1, y) + TD_AT(g, x, y - 1) +
                       TD_AT(g, x, y + 1));
            s += l * l;
            n++;
        }
    return s / n;
}

/* Closed basin (a nodata ring around a mound): nothing leaves, so every
 * eroded grain is deposited: eroded == deposited to rounding, and the
 * terrain's volume is unchanged up to float32 storage rounding. */
static void test_mass_closed_basin(void)
{
    td_grid_f32 *g = mound(64, 8, 3), *o;
    td_erode_params p = td_erode_defaults();
    td_erode_stats st;
    int i;
    g->has_nodata = 1;
    g->nodata = -9999;
    for (i = 0; i < 64; i++) {
        TD_AT(g, i, 0) = TD_AT(g, i, 63) = -9999;
        TD_AT(g, 0, i) = TD_AT(g, 63, i) = -9999;
    }
    p.steps = 10;
    o = run(g, &p, &st);
    TT_CHECK(o != NULL);
    if (!o)
        goto done;
    TT_CHECKF(st.total.eroded > 10, "eroded %g", st.total.eroded);
    TT_CHECK(st.total.outflow == 0 && st.total.drained == 0);
    TT_CHECKF(st.residual < 1e-6 && st.max_residual < 1e-6,
              "residual %g, worst step %g", st.residual, st.max_residual);
    TT_CHECKF(fabs(sum(o) - sum(g)) < 1e-5 * st.total.eroded,
              "volume before %.9g after %.9g (eroded %g)", sum(g), sum(o),
              st.total.eroded);
    TT_CHECK(TD_AT(o, 0, 0) == -9999 && TD_AT(o, 63, 17) == -9999);
done:
    td_grid_f32_free(g);
    td_grid_f32_free(o);
}

/* A flat plane: no lower neighbour anywhere, the terrain stays the same
 * bytes and every cell holds its own particle's water only. */
static void test_flat_plane_unchanged(void)
{
    td_grid_f32 *g = td_grid_f32_new(48, 40, NULL), *o, *w;
    td_erode_params p = td_erode_defaults();
    td_erode_fields f = {NULL, NULL, NULL};
    td_ctx cx;
    size_t i, n = 48 * 40;
    int same = 1;
    td_ctx_init(&cx);
    for (i = 0; i < n; i++)
        g->data[i] = 5.0f;
    o = td_grid_f32_new(48, 40, NULL);
    w = td_grid_f32_new(48, 40, NULL);
    f.water = w;
    p.steps = 5;
    TT_CHECK(td_erode_run(g, &p, o, &f, NULL, &cx) == 0);
    TT_CHECK(memcmp(o->data, g->data, n * sizeof(float)) == 0);
    for (i = 0; i < n; i++)
        same &= w->data[i] == (float)p.water;
    TT_CHECK(same);
    td_grid_f32_free(g);
    td_grid_f32_free(o);
    td_grid_f32_free(w);
}

/* A plane tilted along x: every row sees the same particles, so the
 * lowering is the same across the slope (to float rounding) and the upper
 * half of the slope is lowered. */
static void test_tilted_plane_uniform(void)
{
    int W = 64, H = 32, x, y;
    td_grid_f32 *g = td_grid_f32_new(W, H, NULL), *o;
    td_erode_params p = td_erode_defaults();
    double worst = 0, maxd = 0, upper = 0;
    for (y = 0; y < H; y++)
        for (x = 0; x < W; x++)
            TD_AT(g, x, y) = (float)(0.2 * (W - x));
    p.steps = 5;
    o = run(g, &p, NULL);
    TT_CHECK(o != NULL);
    if (!o)
        goto done;
    for (x = 2; x < W - 2; x++) {
        double lo = 1e30, hi = -1e30;
        for (y = 2; y < H - 2; y++) {
            double d = TD_AT(o, x, y) - TD_AT(g, x, y);
            lo = d < lo ? d : lo;
            hi = d > hi ? d : hi;
            maxd = fabs(d) > maxd ? fabs(d) : maxd;
            if (x < W / 2)
                upper += d;
        }
        worst = hi - lo > worst ? hi - lo : worst;
    }
    TT_CHECKF(maxd > 1e-3, "nothing eroded (max |dh| %g)", maxd);
    TT_CHECKF(worst <= 1e-5 * (1 + maxd), "lowering varies across the slope "
              "by %g (max |dh| %g)", worst, maxd);
    TT_CHECKF(upper < 0, "upper half not lowered (sum dh %g)", upper);
done:
    td_grid_f32_free(g);
    td_grid_f32_free(o);
}

/* Same input and parameters -> same bytes, with 1 and with 2 threads; the
 * mound generator is the same bytes for the same seed, other for another. */
static void test_deterministic_threads(void)
{
    td_grid_f32 *g = mound(64, 8, 5), *g2 = mound(64, 8, 5),
                *g3 = mound(64, 8, 6), *a, *b, *c;
    td_erode_params p = td_erode_defaults();
    size_t nb = 64 * 64 * sizeof(float);
    TT_CHECK(memcmp(g->data, g2->data, nb) == 0);
    TT_CHECK(memcmp(g->data, g3->data, nb) != 0);
    p.steps = 6;
    p.threads = 1;
    a = run(g, &p, NULL);
    b = run(g, &p, NULL);
    p.threads = 2;
    c = run(g, &p, NULL);
    TT_CHECK(a && b && c);
    if (a && b && c) {
        TT_CHECK(memcmp(a->data, b->data, nb) == 0);
        TT_CHECKF(memcmp(a->data, c->data, nb) == 0, "2 threads differ");
        TT_CHECK(memcmp(a->data, g->data, nb) != 0);
    }
    td_grid_f32_free(g);
    td_grid_f32_free(g2);
    td_grid_f32_free(g3);
    td_grid_f32_free(a);
    td_grid_f32_free(b);
    td_grid_f32_free(c);
}

/* The paper's Fig. 5 vs Fig. 3: a larger Ke gives finer roughness. */
static void test_larger_ke_more_roughness(void)
{
    td_grid_f32 *g = mound(64, 8, 1), *a, *b;
    td_erode_params p = td_erode_defaults();
    p.steps = 25;
    a = run(g, &p, NULL);
    p.ke = 0.5;
    b = run(g, &p, NULL);
    TT_CHECK(a && b);
    if (a && b)
        TT_CHECKF(hf_energy(b) > 1.1 * hf_energy(a), "Ke 0.5: %g, Ke %g: %g",
                  hf_energy(b), td_erode_defaults().ke, hf_energy(a));
    td_grid_f32_free(g);
    td_grid_f32_free(a);
    td_grid_f32_free(b);
}

int main(void)
{
    TT_RUN(test_mass_closed_basin);
    TT_RUN(test_flat_plane_unchanged);
    TT_RUN(test_tilted_plane_uniform);
    TT_RUN(test_deterministic_threads);
    TT_RUN(test_larger_ke_more_roughness);
    return tt_summary();
}
