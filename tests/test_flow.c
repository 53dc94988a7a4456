/* test_flow.c: rain-flow pass counts (src/flow/flow.c) on surfaces whose flow
 * is known: a cone, a V-valley, a pit, a walled flat with one gap, nodata
 * holes, a ridge-valley wave for the classes; the priority-flood fill
 * against a brute-force minimax fill; conservation of rain at the outlets. */
#include "tests/tt.h"

#include "src/flow/flow.h"
#include "src/flow/flow_int.h"
#include "samples/gen/gen.h"
#include "src/model/model.h"

#include <float.h>
#include <stdlib.h>
#include <string.h>

static const td_flow_method ALL[3] = {TD_FLOW_SOBEL, TD_FLOW_D8,
                                      TD_FLOW_DINF};
static const char *const NAME[3] = {"sobel", "d8", "dinf"};

static td_grid_f32 *run(const td_grid_f32 *dem, td_flow_method m,
                        td_flow_stats *st)
{
    td_flow_params p = td_flow_defaults();
    td_grid_f32 *out = td_grid_f32_new(dem->w, dem->h, NULL);
    td_ctx cx;
    td_ctx_init(&cx);
    p.method = m;
    if (!out || td_flow_run(dem, &p, out, st, &cx) != 0) {
        fprintf(stderr, "  flow failed: %s\n", td_errmsg(&cx));
        td_grid_f32_free(out);
        return NULL;
    }
    return out;
}

/* Cone around the point (w/2, h/2) between cell centres: no flat apex. */
static td_grid_f32 *cone(int w, int h)
{
    td_grid_f32 *g = td_grid_f32_new(w, h, NULL);
    int x, y;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++)
            TD_AT(g, x, y) = (float)(100.0 - hypot(x + 0.5 - w / 2.0,
                                                   y + 0.5 - h / 2.0));
    return g;
}

/* A cone sheds all water outward: everything reaches the edge, nothing
 * converges, so a cell at distance r from the top collects at most the
 * cells of its ray (about r of them; + 2 for the quantised directions). */
static void test_cone_outward(void)
{
    td_grid_f32 *dem = cone(64, 64), *acc;
    td_flow_stats st;
    int m, x, y;
    for (m = 0; m < 3; m++) {
        double worst = 0;
        if (!(acc = run(dem, ALL[m], &st))) {
            TT_CHECK(0);
            continue;
        }
        TT_NEAR(st.outflow, 64 * 64, 1e-6 * 64 * 64);
        TT_CHECK(st.pit_stops == 0 && st.capped == 0 && st.raised == 0);
        for (y = 0; y < 64; y++)
            for (x = 0; x < 64; x++) {
                double r = hypot(x + 0.5 - 32, y + 0.5 - 32);
                double ex = TD_AT(acc, x, y) - (r + 2);
                worst = ex > worst ? ex : worst;
            }
        TT_CHECKF(worst <= 0, "%s: a cell collects %.2f more than its ray",
                  NAME[m], worst);
        td_grid_f32_free(acc);
    }
    td_grid_f32_free(dem);
}

/* z = |x - c| + 0.1 (h - 1 - y): a V-valley along column c draining
 * south.  Known counts: every cell of a row flows across to the axis. */
static td_grid_f32 *vvalley(int w, int h, int c)
{
    td_grid_f32 *g = td_grid_f32_new(w, h, NULL);
    int x, y;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++)
            TD_AT(g, x, y) = (float)(abs(x - c) + 0.1 * (h - 1 - y));
    return g;
}

static void test_vvalley_axis(void)
{
    const int w = 41, h = 30, c = 20;
    td_grid_f32 *dem = vvalley(w, h, c), *acc;
    td_flow_stats st;
    int x, y, bad = 0;
    /* paper's method: Sobel directions are exactly across and down */
    if ((acc = run(dem, TD_FLOW_SOBEL, &st)) != NULL) {
        for (y = 0; y < h; y++) {
            bad += TD_AT(acc, c, y) != (float)((y + 1) * w);
            for (x = c + 1; x < w; x++)
                bad += TD_AT(acc, x, y) != (float)(w - x);
        }
        TT_CHECKF(bad == 0, "sobel: %d cells off the known count", bad);
        TT_CHECK(st.outflow == w * h && st.outlets == 1);
        td_grid_f32_free(acc);
    } else
        TT_CHECK(0);
    /* D8: edge cells are outlets, interior rows flow to the axis */
    if ((acc = run(dem, TD_FLOW_D8, &st)) != NULL) {
        bad = 0;
        for (y = 1; y < h - 1; y++) {
            bad += TD_AT(acc, c, y) != (float)((w - 2) * y);
            for (x = c + 1; x < w - 1; x++)
                bad += TD_AT(acc, x, y) != (float)(w - 1 - x);
        }
        TT_CHECKF(bad == 0, "d8: %d cells off the known count", bad);
        TT_CHECK(TD_AT(acc, c, h - 1) == (float)((w - 2) * (h - 2) + 1));
        TT_CHECK(st.outflow == w * h);
        td_grid_f32_free(acc);
    } else
        TT_CHECK(0);
    /* D-inf: spreads a little downslope, still concentrates on the axis */
    if ((acc = run(dem, TD_FLOW_DINF, &st)) != NULL) {
        double axis = TD_AT(acc, c, h - 2), side = 0;
        for (x = 1; x < w - 1; x++)
            if (x != c && TD_AT(acc, x, h - 2) > side)
                side = TD_AT(acc, x, h - 2);
        TT_NEAR(st.outflow, w * h, 1e-6 * w * h);
        TT_CHECKF(axis >= 0.9 * (w - 2) * (h - 2), "axis %.1f", axis);
        TT_CHECKF(axis >= 20 * side, "axis %.1f, side %.1f", axis, side);
        td_grid_f32_free(acc);
    } else
        TT_CHECK(0);
    td_grid_f32_free(dem);
}

/* A plane draining south with one deep pit: D8/D-inf fill it and carry
 * its water on; the paper's method stops the drops that reach it. */
static void test_pit_filled_and_drains(void)
{
    const int w = 21, h = 21, px = 10, py = 8;
    td_grid_f32 *dem = td_grid_f32_new(w, h, NULL), *acc, *fill;
    td_flow_stats st;
    td_ctx cx;
    int x, y, m;
    td_ctx_init(&cx);
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++)
            TD_AT(dem, x, y) = (float)(h - 1 - y);
    TD_AT(dem, px, py) -= 5;
    fill = td_grid_f32_new(w, h, NULL);
    TT_CHECK(td_flow_fill(dem, fill, 0, &cx) == 0);
    TT_CHECK(TD_AT(fill, px, py) == (float)(h - 2 - py)); /* spill level */
    TT_CHECK(TD_AT(fill, px, py + 1) == (float)(h - 2 - py));
    for (m = 1; m < 3; m++) {
        double bottom = 0;
        if (!(acc = run(dem, ALL[m], &st))) {
            TT_CHECK(0);
            continue;
        }
        TT_CHECK(st.raised == 1);
        TT_NEAR(st.outflow, w * h, 1e-6 * w * h);
        TT_CHECKF(TD_AT(acc, px, py) >= py, "%s: pit collected %g", NAME[m],
                  TD_AT(acc, px, py));
        for (x = 0; x < w; x++)
            bottom += TD_AT(acc, x, h - 1);
        /* everything not leaving through the sides reaches the bottom */
        TT_CHECKF(bottom >= (w - 2) * (h - 2), "%s: bottom %.1f", NAME[m],
                  bottom);
        td_grid_f32_free(acc);
    }
    if ((acc = run(dem, TD_FLOW_SOBEL, &st)) != NULL) {
        TT_CHECK(st.pit_stops >= py);
        TT_CHECK(st.outflow + st.pit_stops + st.capped == w * h);
        td_grid_f32_free(acc);
    }
    td_grid_f32_free(fill);
    td_grid_f32_free(dem);
}

/* A flat floor walled in by high edge cells with one low gap on the right:
 * flats drain along the flood tree to the gap, so the gap cell collects
 * every interior cell. */
static void test_flat_drains_to_outlet(void)
{
    const int w = 23, h = 15, gy = 7;
    td_grid_f32 *dem = td_grid_f32_new(w, h, NULL), *acc;
    td_flow_stats st;
    int x, y, m;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++)
            TD_AT(dem, x, y) = (x == 0 || y == 0 || x == w - 1 ||
                                y == h - 1) ? 10.0f : 1.0f;
    TD_AT(dem, w - 1, gy) = 0.0f;
    for (m = 1; m < 3; m++) {
        if (!(acc = run(dem, ALL[m], &st))) {
            TT_CHECK(0);
            continue;
        }
        TT_NEAR(TD_AT(acc, w - 1, gy), (w - 2) * (h - 2) + 1, 1e-6 * w * h);
        TT_NEAR(st.outflow, w * h, 1e-6 * w * h);
        TT_CHECK(st.raised == 0);
        /* the flat drains into the three cells beside the gap
         * (breadth-first from all three together) */
        TT_NEAR(TD_AT(acc, w - 2, gy - 1) + TD_AT(acc, w - 2, gy) +
                TD_AT(acc, w - 2, gy + 1), (w - 2) * (h - 2), 1e-6 * w * h);
        TT_CHECKF(st.max_pass == (w - 2) * (h - 2) + 1, "%s: max %g",
                  NAME[m], st.max_pass);
        td_grid_f32_free(acc);
    }
    /* all flat: every edge cell is an outlet, all rain leaves */
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++)
            TD_AT(dem, x, y) = 3.0f;
    if ((acc = run(dem, TD_FLOW_D8, &st)) != NULL) {
        TT_CHECK(st.outflow == w * h);
        TT_CHECK(st.outlets == 2 * (w + h) - 4);
        /* each cell drains to its nearest edge: short paths only */
        TT_CHECKF(st.max_pass <= h, "max %g", st.max_pass);
        td_grid_f32_free(acc);
    }
    td_grid_f32_free(dem);
}

/* One flat across every row band (a walled 60 x 240 floor, one gap at the
 * bottom): on 1 to 4 threads the counts are the same, and the gap's
 * neighbour collects the whole floor. */
static void test_flat_across_bands(void)
{
    const int w = 60, h = 240;
    td_grid_f32 *dem = td_grid_f32_new(w, h, NULL), *ref = NULL;
    int x, y, t;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++)
            TD_AT(dem, x, y) = (x == 0 || y == 0 || x == w - 1 ||
                                y == h - 1) ? 10.0f : 1.0f;
    TD_AT(dem, w / 2, h - 1) = 0.0f;
    for (t = 1; t <= 4; t++) {
        td_flow_params p = td_flow_defaults();
        td_grid_f32 *acc = td_grid_f32_new(w, h, NULL);
        td_flow_stats st;
        td_ctx cx;
        td_ctx_init(&cx);
        p.method = TD_FLOW_D8;
        p.threads = t;
        TT_CHECK(acc && td_flow_run(dem, &p, acc, &st, &cx) == 0);
        TT_NEAR(TD_AT(acc, w / 2, h - 1), (w - 2) * (h - 2) + 1, 0.5);
        if (t == 1)
            ref = acc;
        else {
            TT_CHECKF(memcmp(ref->data, acc->data, sizeof *acc->data *
                             (size_t)(w * h)) == 0, "%d threads differ", t);
            td_grid_f32_free(acc);
        }
    }
    td_grid_f32_free(ref);
    td_grid_f32_free(dem);
}

static int nodata_at(const td_grid_f32 *dem, int x, int y)
{
    float v = TD_AT(dem, x, y);
    return isnan(v) || (dem->has_nodata && v == dem->nodata);
}

/* src/flow/flow_d8.c on its own: one path that snakes down column 0, up column
 * 1, down column 2, ... so it crosses every row band's border in both
 * directions (a hand-over round per crossing).  The cell k steps along the
 * path collects k + 1; the last cell is the outlet.  1 to 4 bands, w x 64
 * cells. */
static void snake(int w)
{
    const int h = 64;
    uint8_t *code = malloc((size_t)w * h);
    uint32_t *acc = malloc(sizeof *acc * (size_t)w * h);
    int t, x, y;
    for (t = 1; t <= 4 && code && acc; t++) {
        double out, outlets, done;
        int bad = 0, k = 0;
        for (x = 0; x < w; x++)
            for (y = 0; y < h; y++) {
                int down = !(x & 1), last = down ? y == h - 1 : y == 0;
                code[y * w + x] = x == w - 1 && last ? TD_FL_ROOT
                                  : last ? 0 /* E */ : down ? 2 : 6;
            }
        TT_CHECK(td_d8_accumulate(code, acc, w, h, t, &out, &outlets, &done,
                                  NULL) == 0);
        for (x = 0; x < w; x++)
            for (y = 0; y < h; y++, k++) {
                int yy = x & 1 ? h - 1 - y : y;
                bad += acc[yy * w + x] != (uint32_t)k + 1;
            }
        TT_CHECKF(bad == 0, "%d wide, %d bands: %d counts off the path "
                  "position", w, t, bad);
        TT_CHECK(out == (double)w * h && outlets == 1 &&
                 done == (double)w * h);
    }
    free(code);
    free(acc);
}

/* 9 wide: one block of rows per band.  8192 wide: blocks of 16 rows, so
 * the path also crosses the blocks inside each band, down and up. */
static void test_d8_bands_snake(void)
{
    snake(9);
    snake(8192);
}

/* Brute-force fill: repeat W = max(dem, min over valid neighbours of W)
 * from +inf inside and dem on the seeds (grid edge, next to nodata) until
 * nothing changes; nodata cells get the nodata value. */
static void brute_fill(const td_grid_f32 *dem, float *wv)
{
    int w = dem->w, h = dem->h, x, y, k, changed = 1;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            int seed = x == 0 || y == 0 || x == w - 1 || y == h - 1;
            for (k = 0; k < 9 && !seed; k++)
                seed = nodata_at(dem, x + k % 3 - 1, y + k / 3 - 1);
            wv[y * w + x] = nodata_at(dem, x, y) ? dem->nodata
                            : seed ? TD_AT(dem, x, y) : FLT_MAX;
        }
    while (changed) {
        changed = 0;
        for (y = 1; y < h - 1; y++)
            for (x = 1; x < w - 1; x++) {
                float lo = FLT_MAX, v;
                if (nodata_at(dem, x, y))
                    continue;
                for (k = 0; k < 9; k++)
                    if (k != 4 && wv[(y + k / 3 - 1) * w + x + k % 3 - 1] < lo)
                        lo = wv[(y + k / 3 - 1) * w + x + k % 3 - 1];
                v = TD_AT(dem, x, y) > lo ? TD_AT(dem, x, y) : lo;
                if (v < wv[y * w + x]) {
                    wv[y * w + x] = v;
                    changed = 1;
                }
            }
    }
}

/* Tile sides for the tiled fill: 0 = the default (one tile here). */
static const int TILES[6] = {0, 2, 3, 7, 16, 50};

/* Counts with tiles of side `tile` on `threads` threads equal those with
 * the default tile on the default threads. */
static int same_by_tile(const td_grid_f32 *dem, td_flow_method m, int tile,
                        int threads)
{
    td_flow_params p = td_flow_defaults();
    td_grid_f32 *a = run(dem, m, NULL), *b = td_grid_f32_new(dem->w, dem->h,
                                                              NULL);
    td_ctx cx;
    int same = 0;
    td_ctx_init(&cx);
    p.method = m;
    p.tile = tile;
    p.threads = threads;
    if (a && b && td_flow_run(dem, &p, b, NULL, &cx) == 0)
        same = memcmp(a->data, b->data, sizeof *a->data * (size_t)dem->w *
                      (size_t)dem->h) == 0;
    td_grid_f32_free(a);
    td_grid_f32_free(b);
    return same;
}

/* Generated hills with noise (many pits) and nodata holes: every unit of
 * rain reaches an outlet (D8 exactly, D-inf within 1e-6); nodata cells
 * stay nodata; the paper's drops end somewhere. */
static void test_conservation_nodata(void)
{
    td_gen_params gp = td_gen_defaults();
    td_grid_f32 *dem = NULL, *acc;
    td_flow_stats st;
    td_ctx cx;
    int x, y, m;
    double valid = 0;
    td_ctx_init(&cx);
    gp.w = 150;
    gp.h = 110;
    TT_CHECK(td_gen_terrain(&gp, &dem, &cx) == 0);
    if (!dem)
        return;
    TT_CHECK(td_terrain_noise(dem, 2.0, 7, &cx) == 0);
    dem->nodata = -9999.0f;
    dem->has_nodata = 1;
    for (y = 0; y < gp.h; y++)
        for (x = 0; x < gp.w; x++) {
            if (hypot(x - 60, y - 50) < 9 || (x > 120 && y < 10))
                TD_AT(dem, x, y) = -9999.0f;
            valid += TD_AT(dem, x, y) != -9999.0f;
        }
    TD_AT(dem, 30, 30) = NAN; /* NaN is nodata too */
    valid--;
    for (m = 0; m < 3; m++) {
        int nd_ok = 1;
        if (!(acc = run(dem, ALL[m], &st))) {
            TT_CHECK(0);
            continue;
        }
        TT_CHECK(st.cells == valid);
        for (y = 0; y < gp.h; y++)
            for (x = 0; x < gp.w; x++)
                nd_ok &= (TD_AT(dem, x, y) == -9999.0f ||
                          isnan(TD_AT(dem, x, y))) ==
                         (TD_AT(acc, x, y) == -9999.0f);
        TT_CHECK(TD_AT(acc, 60, 50) == -9999.0f && TD_AT(acc, 130, 2) ==
                 -9999.0f && TD_AT(acc, 30, 30) == -9999.0f);
        if (ALL[m] == TD_FLOW_D8)
            TT_CHECKF(st.outflow == valid, "d8 %.0f of %.0f", st.outflow,
                      valid);
        else if (ALL[m] == TD_FLOW_DINF)
            TT_NEAR(st.outflow, valid, 1e-6 * valid);
        else
            TT_CHECK(st.outflow + st.pit_stops + st.capped == valid);
        TT_CHECK(st.max_pass <= valid);
        TT_CHECKF(nd_ok, "%s: nodata cells differ from the DEM's", NAME[m]);
        td_grid_f32_free(acc);
    }
    /* the tiled fill around the holes equals the brute force, and the
     * counts do not depend on the tile side */
    {
        td_grid_f32 *fill = td_grid_f32_new(gp.w, gp.h, NULL);
        float *ref = malloc(sizeof *ref * (size_t)(gp.w * gp.h));
        int t, i, diff;
        if (fill && ref) {
            brute_fill(dem, ref);
            for (t = 0; t < 6; t++) {
                TT_CHECK(td_flow_fill(dem, fill, TILES[t], &cx) == 0);
                for (i = 0, diff = 0; i < gp.w * gp.h; i++)
                    diff += fill->data[i] != ref[i];
                TT_CHECKF(diff == 0, "tile %d: %d cells differ", TILES[t],
                          diff);
            }
            for (m = 1; m < 3; m++)
                for (t = 1; t < 6; t++)
                    TT_CHECKF(same_by_tile(dem, ALL[m], TILES[t], 1 + t % 4),
                              "%s: tile %d changes the counts", NAME[m],
                              TILES[t]);
        }
        free(ref);
        td_grid_f32_free(fill);
    }
    td_grid_f32_free(dem);
}

/* The flood (src/flow/flow_fill.c: tiles, labels, drained-cell sweeps, upslope
 * tracing), in one tile or many, equals the brute force: noisy, quantised
 * (flats) and smooth DEMs. */
static void test_fill_matches_brute_force(void)
{
    int seed, i, t;
    for (seed = 1; seed <= 6; seed++) {
        td_gen_params gp = td_gen_defaults();
        td_grid_f32 *dem = NULL, *fill;
        float *ref;
        td_ctx cx;
        int diff = 0;
        td_ctx_init(&cx);
        gp.w = 60 + 7 * seed;
        gp.h = 50;
        gp.seed = (unsigned)seed;
        TT_CHECK(td_gen_terrain(&gp, &dem, &cx) == 0);
        if (!dem)
            return;
        if (seed <= 4)
            td_terrain_noise(dem, seed * 3.0, (uint64_t)seed, &cx);
        else /* smooth (most cells drain without climbing), a few pits */
            for (i = 0; i < 6 * seed; i++)
                dem->data[(i * 7919 + 13) % (gp.w * gp.h)] -= 4.0f + i % 5;
        if (seed == 4) /* quantised heights: many flats */
            for (i = 0; i < gp.w * gp.h; i++)
                dem->data[i] = floorf(dem->data[i] / 20.0f);
        fill = td_grid_f32_new(gp.w, gp.h, NULL);
        ref = malloc(sizeof *ref * (size_t)(gp.w * gp.h));
        brute_fill(dem, ref);
        for (t = 0; t < 6; t++) { /* one tile, and tiles cut by the edges */
            TT_CHECK(td_flow_fill(dem, fill, TILES[t], &cx) == 0);
            for (i = 0, diff = 0; i < gp.w * gp.h; i++)
                diff += fill->data[i] != ref[i];
            TT_CHECKF(diff == 0, "seed %d tile %d: %d cells differ", seed,
                      TILES[t], diff);
        }
        free(ref);
        td_grid_f32_free(fill);
        td_grid_f32_free(dem);
    }
}

/* Ridges and valleys of z = 10 cos(2 pi (x + ph) / 32) + 0.05 (h - 1 - y)
 * draining south.  ph = 0.5: crests between cells 31|32 and 63|64, valley
 * floors between 15|16, 47|48, 79|80.  ph = 0: crests on the cells 32, 64
 * and floors on 16, 48, 80; there the Sobel gradient on the crest cell
 * points along the crest (its two sides cancel), so the paper's drops run
 * down the crest: only D8 and D-inf are held to ph = 0 (docs/flow.md). */
static void test_classes_ridge_valley(void)
{
    const int w = 96, h = 64;
    td_grid_f32 *dem = td_grid_f32_new(w, h, NULL), *acc;
    td_grid_u8 *cls = td_grid_u8_new(w, h, NULL);
    td_flow_stats st;
    td_ctx cx;
    int x, y, m, t;
    td_ctx_init(&cx);
    for (t = 0; t < 6; t++) {
        double ph = t < 3 ? 0.5 : 0.0;
        int ridge = 0, valley = 0, nr = 0, nv = 0;
        m = t % 3;
        if (ph == 0 && ALL[m] == TD_FLOW_SOBEL)
            continue;
        for (y = 0; y < h; y++)
            for (x = 0; x < w; x++)
                TD_AT(dem, x, y) = (float)(10 * cos(2 * M_PI * (x + ph) /
                                                    32.0) +
                                           0.05 * (h - 1 - y));
        if (!(acc = run(dem, ALL[m], &st))) {
            TT_CHECK(0);
            continue;
        }
        TT_CHECK(td_flow_classify(acc, 0.2, 0.9, cls, &cx) == 0);
        for (y = 1; y < h - 1; y++)
            for (x = 1; x < w - 1; x++) {
                int r = ph > 0 ? x % 32 == 0 || x % 32 == 31 : x % 32 == 0;
                int v = ph > 0 ? x % 32 == 15 || x % 32 == 16 : x % 32 == 16;
                if (r)
                    nr++, ridge += TD_AT(cls, x, y) == TD_FLOW_RIDGE;
                if (v && y >= 4) /* a floor needs a few rows of catchment */
                    nv++, valley += TD_AT(cls, x, y) == TD_FLOW_VALLEY;
            }
        TT_CHECKF(ridge == nr, "%s: %d of %d crest cells are ridge",
                  NAME[m], ridge, nr);
        TT_CHECKF(valley >= 0.95 * nv, "%s: %d of %d floor cells are valley",
                  NAME[m], valley, nv);
        td_grid_f32_free(acc);
    }
    td_grid_u8_free(cls);
    td_grid_f32_free(dem);
}

/* Quantiles on a hand-made grid: values 1..10, nodata kept as class 0. */
static void test_classify_quantiles(void)
{
    td_grid_f32 *p = td_grid_f32_new(11, 1, NULL);
    td_grid_u8 *c = td_grid_u8_new(11, 1, NULL);
    td_ctx cx;
    int i;
    td_ctx_init(&cx);
    for (i = 0; i < 10; i++)
        p->data[i] = (float)(10 - i);
    p->data[10] = -1;
    p->nodata = -1;
    p->has_nodata = 1;
    TT_CHECK(td_flow_classify(p, 0.2, 0.9, c, &cx) == 0);
    /* Q(0.2) = rank 1 = 2, Q(0.9) = rank 8 = 9 */
    for (i = 0; i < 10; i++) {
        int v = 10 - i;
        TT_CHECKF(c->data[i] == (v <= 2 ? 1 : v >= 9 ? 3 : 2), "v %d: %d", v,
                  c->data[i]);
    }
    TT_CHECK(c->data[10] == TD_FLOW_NODATA);
    TT_CHECK(td_flow_classify(p, 0.9, 0.2, c, &cx) == TD_EINVAL);
    td_ctx_clear(&cx);
    TT_CHECK(td_flow_classify(p, -0.1, 0.9, c, &cx) == TD_EINVAL);
    td_grid_f32_free(p);
    td_grid_u8_free(c);
}

static int cancel_cb(const char *s, double f, void *u)
{
    (void)s, (void)f, (void)u;
    return 1;
}

/* One cell, all nodata, bad sizes and parameters, cancelling. */
static void test_edge_cases(void)
{
    td_grid_f32 *one = td_grid_f32_new(1, 1, NULL), *o1 = td_grid_f32_new(1, 1, NULL);
    td_grid_f32 *nd = td_grid_f32_new(5, 4, NULL), *o2 = td_grid_f32_new(5, 4, NULL);
    td_flow_params p = td_flow_defaults();
    td_flow_stats st;
    td_ctx cx;
    int m, i;
    td_ctx_init(&cx);
    for (m = 0; m < 3; m++) {
        p.method = ALL[m];
        TT_CHECK(td_flow_run(one, &p, o1, &st, &cx) == 0);
        TT_CHECK(o1->data[0] == 1.0f && st.outflow + st.pit_stops == 1);
        nd->nodata = 5;
        nd->has_nodata = 1;
        for (i = 0; i < 20; i++)
            nd->data[i] = 5;
        TT_CHECK(td_flow_run(nd, &p, o2, &st, &cx) == 0);
        TT_CHECK(st.cells == 0 && st.outflow == 0 && o2->data[7] == 5);
        TT_CHECK(td_flow_run(nd, &p, o1, &st, &cx) == TD_EINVAL);
        td_ctx_clear(&cx);
    }
    p.method = (td_flow_method)7;
    TT_CHECK(td_flow_run(one, &p, o1, &st, &cx) == TD_EINVAL);
    td_ctx_clear(&cx);
    p = td_flow_defaults();
    p.method = TD_FLOW_D8;
    cx.progress = cancel_cb;
    TT_CHECK(td_flow_run(one, &p, o1, &st, &cx) == TD_ECANCEL);
    td_grid_f32_free(one);
    td_grid_f32_free(o1);
    td_grid_f32_free(nd);
    td_grid_f32_free(o2);
}

int main(void)
{
    TT_RUN(test_cone_outward);
    TT_RUN(test_vvalley_axis);
    TT_RUN(test_pit_filled_and_drains);
    TT_RUN(test_flat_drains_to_outlet);
    TT_RUN(test_flat_across_bands);
    TT_RUN(test_conservation_nodata);
    TT_RUN(test_fill_matches_brute_force);
    TT_RUN(test_classes_ridge_valley);
    TT_RUN(test_classify_quantiles);
    TT_RUN(test_edge_cases);
    TT_RUN(test_d8_bands_snake);
    return tt_summary();
}
