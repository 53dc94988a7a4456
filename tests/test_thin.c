/* Hilditch thinning on hand-made patterns with a known skeleton shape. */
#include "tests/tt.h"
#include "tests/util/gridtest.h"
#include "scanner/thin.h"
#include "scanner/skel.h"

#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

static int thin(td_grid_u8 *g)
{
    td_ctx cx;
    td_ctx_init(&cx);
    return td_thin_hilditch(g, NULL, &cx);
}

static size_t count_kind(const td_grid_u8 *g, int want_cross, int at_least)
{
    size_t n = 0;
    int x, y;
    for (y = 0; y < g->h; y++)
        for (x = 0; x < g->w; x++) {
            int c;
            if (!TD_AT(g, x, y))
                continue;
            c = td_skel_crossings(td_skel_nbits(g, x, y));
            n += at_least ? c >= want_cross : c == want_cross;
        }
    return n;
}

/* A 5-px bar thins to one centred line spanning nearly its length. */
static void test_bar(void)
{
    td_grid_u8 *g = td_grid_u8_new(80, 20, NULL);
    int x, y, minx = 99, maxx = -1;
    tg_thick_segment(g, 10, 10, 70, 10, 5);
    TT_CHECK(thin(g) == 0);
    TT_CHECK(tg_components8(g) == 1);
    TT_CHECK(tg_blocks2x2(g) == 0);
    for (y = 0; y < g->h; y++)
        for (x = 0; x < g->w; x++)
            if (TD_AT(g, x, y)) {
                TT_CHECKF(y >= 8 && y <= 11, "pixel at row %d", y);
                if (x < minx) minx = x;
                if (x > maxx) maxx = x;
            }
    TT_CHECKF(minx <= 11 && maxx >= 68, "span %d..%d", minx, maxx);
    TT_CHECK(count_kind(g, 1, 0) == 2); /* two end points */
    td_grid_u8_free(g);
}

/* A plus sign: four end points kept, one junction, no hole. */
static void test_cross(void)
{
    td_grid_u8 *g = td_grid_u8_new(60, 60, NULL);
    tg_thick_segment(g, 5, 30, 55, 30, 5);
    tg_thick_segment(g, 30, 5, 30, 55, 5);
    TT_CHECK(thin(g) == 0);
    TT_CHECK(tg_components8(g) == 1);
    TT_CHECK(tg_holes4(g) == 0);
    TT_CHECK(tg_blocks2x2(g) == 0);
    TT_CHECKF(count_kind(g, 1, 0) == 4, "%zu end points", count_kind(g, 1, 0));
    TT_CHECK(count_kind(g, 3, 1) >= 1);
    td_grid_u8_free(g);
}

/* A thick ring becomes a closed 1-px curve in the middle of the band. */
static void test_ring(void)
{
    td_grid_u8 *g = td_grid_u8_new(50, 50, NULL);
    int x, y;
    tg_ring(g, 25, 25, 10, 16);
    TT_CHECK(thin(g) == 0);
    TT_CHECK(tg_components8(g) == 1);
    TT_CHECK(tg_holes4(g) == 1);
    TT_CHECK(tg_blocks2x2(g) == 0);
    TT_CHECK(count_kind(g, 2, 0) == tg_count(g)); /* every pixel inside a line */
    for (y = 0; y < g->h; y++)
        for (x = 0; x < g->w; x++)
            if (TD_AT(g, x, y)) {
                double r = hypot(x + 0.5 - 25, y + 0.5 - 25);
                TT_CHECKF(r > 11 && r < 15, "radius %.2f at %d,%d", r, x, y);
            }
    td_grid_u8_free(g);
}

/* A 2-px-wide diagonal (4-connected staircase band) becomes 1 px, connected. */
static void test_diagonal2(void)
{
    td_grid_u8 *g = td_grid_u8_new(40, 40, NULL);
    int i;
    for (i = 2; i < 36; i++) {
        TD_AT(g, i, i) = 1;
        TD_AT(g, i + 1, i) = 1;
    }
    TT_CHECK(thin(g) == 0);
    TT_CHECK(tg_components8(g) == 1);
    TT_CHECK(tg_blocks2x2(g) == 0);
    TT_CHECKF(tg_count(g) >= 32 && tg_count(g) <= 36, "%zu px", tg_count(g));
    TT_CHECK(count_kind(g, 1, 0) == 2);
    td_grid_u8_free(g);
}

/* A filled disk shrinks to a tiny skeleton: one component, no hole. */
static void test_disk(void)
{
    td_grid_u8 *g = td_grid_u8_new(40, 40, NULL);
    tg_disk(g, 20, 20, 11);
    TT_CHECK(thin(g) == 0);
    TT_CHECK(tg_components8(g) == 1);
    TT_CHECK(tg_holes4(g) == 0);
    TT_CHECK(tg_blocks2x2(g) == 0);
    TT_CHECKF(tg_count(g) <= 9, "%zu px left", tg_count(g));
    td_grid_u8_free(g);
}

/* Already thin lines are left alone: end points are kept. */
static void test_thin_is_fixpoint(void)
{
    static const char *const rows[] = {
        "..........", ".#######..", "........#.", ".........#",
        "....###..#", "...#...##.", "..........", NULL};
    td_grid_u8 *g = tg_from_ascii(rows), *c = td_grid_u8_dup(g, NULL);
    int x, y, same = 1;
    TT_CHECK(thin(g) == 0);
    for (y = 0; y < g->h; y++)
        for (x = 0; x < g->w; x++)
            same &= TD_AT(g, x, y) == TD_AT(c, x, y);
    if (!same)
        tg_dump(g);
    TT_CHECK(same);
    td_grid_u8_free(g);
    td_grid_u8_free(c);
}

/* n random shapes on g: disks and rings of radius r0 .. r0 + rn - 1 (rings
 * 2 .. 1 + ringn px wide) and bars 1 .. barn px thick to a random point. */
static void random_shapes(td_grid_u8 *g, int n, int r0, int rn, int ringn,
                          int barn, unsigned *seed)
{
    int k;
    for (k = 0; k < n; k++) {
        double x = rand_r(seed) % g->w, y = rand_r(seed) % g->h;
        double r = r0 + rand_r(seed) % rn;
        switch (rand_r(seed) % 3) {
        case 0: tg_disk(g, x, y, r); break;
        case 1: tg_ring(g, x, y, r, r + 2 + rand_r(seed) % ringn); break;
        default:
            tg_thick_segment(g, x, y, rand_r(seed) % g->w, rand_r(seed) % g->h,
                             1 + rand_r(seed) % barn);
        }
    }
}

/* Random unions of disks, rings and bars: topology kept, result thin and a
 * fixpoint of a second run. */
static void test_random_topology(void)
{
    unsigned seed = 12345;
    int trial;
    for (trial = 0; trial < 40; trial++) {
        td_grid_u8 *g = td_grid_u8_new(90, 70, NULL), *c;
        size_t comp, holes, n1;
        random_shapes(g, 5, 3, 12, 5, 6, &seed);
        comp = tg_components8(g);
        holes = tg_holes4(g);
        TT_CHECK(thin(g) == 0);
        TT_CHECKF(tg_components8(g) == comp, "trial %d: components %zu -> %zu",
                  trial, comp, tg_components8(g));
        TT_CHECKF(tg_holes4(g) == holes, "trial %d: holes %zu -> %zu", trial,
                  holes, tg_holes4(g));
        TT_CHECKF(tg_blocks2x2(g) == 0, "trial %d: 2x2 blocks", trial);
        n1 = tg_count(g);
        c = td_grid_u8_dup(g, NULL);
        TT_CHECK(thin(c) == 0);
        TT_CHECK(tg_count(c) == n1);
        td_grid_u8_free(c);
        td_grid_u8_free(g);
    }
}

/* The wavefront on threads gives the bytes of one pass down the rows: a
 * 700 x 420 field of thick random shapes (rings, disks, bars touching and
 * crossing: every deletion near another row's), thinned on 1 thread (the
 * raster order) and on 2, 3 and 4; the skeleton, the passes and the pixels
 * removed must agree. */
static void test_threads_same_as_one_pass(void)
{
#ifdef _OPENMP
    unsigned seed = 777;
    td_grid_u8 *g = td_grid_u8_new(700, 420, NULL), *ref;
    td_thin_stats s1, sn;
    td_ctx cx;
    int t;
    td_ctx_init(&cx);
    random_shapes(g, 260, 2, 14, 6, 7, &seed);
    ref = td_grid_u8_dup(g, NULL);
    omp_set_num_threads(1);
    TT_CHECK(td_thin_hilditch(ref, &s1, &cx) == 0);
    TT_CHECK(s1.passes > 3 && s1.removed > 10000);
    for (t = 2; t <= 4; t++) {
        td_grid_u8 *c = td_grid_u8_dup(g, NULL);
        int y, diff = 0;
        omp_set_num_threads(t);
        TT_CHECK(td_thin_hilditch(c, &sn, &cx) == 0);
        for (y = 0; y < g->h; y++)
            diff += memcmp(c->data + (size_t)y * c->stride,
                           ref->data + (size_t)y * ref->stride,
                           (size_t)g->w) != 0;
        TT_CHECKF(diff == 0, "%d threads: %d rows differ", t, diff);
        TT_CHECK(sn.passes == s1.passes && sn.removed == s1.removed);
        td_grid_u8_free(c);
    }
    omp_set_num_threads(omp_get_num_procs());
    td_grid_u8_free(ref);
    td_grid_u8_free(g);
#endif
}

static void test_empty_and_single(void)
{
    td_grid_u8 *g = td_grid_u8_new(1, 1, NULL);
    td_thin_stats st;
    td_ctx cx;
    td_ctx_init(&cx);
    TT_CHECK(td_thin_hilditch(g, &st, &cx) == 0 && st.remaining == 0);
    TD_AT(g, 0, 0) = 1;
    TT_CHECK(td_thin_hilditch(g, &st, &cx) == 0 && st.remaining == 1);
    td_grid_u8_free(g);
}

int main(void)
{
    TT_RUN(test_bar);
    TT_RUN(test_cross);
    TT_RUN(test_ring);
    TT_RUN(test_diagonal2);
    TT_RUN(test_disk);
    TT_RUN(test_thin_is_fixpoint);
    TT_RUN(test_random_topology);
    TT_RUN(test_threads_same_as_one_pass);
    TT_RUN(test_empty_and_single);
    return tt_summary();
}
