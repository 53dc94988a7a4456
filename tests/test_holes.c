/* Pinhole filling before thinning (td_cv_fill_holes): noisy scans leave
 * pinholes in the ink that Hilditch would keep as tiny loops. */
#include "tests/tt.h"
#include "tests/util/gridtest.h"
#include "scanner/despur.h"
#include "scanner/thin.h"
#include "scanner/skel.h"
#include "src/io/io.h"

#include <stdlib.h>

static td_grid_u8 *pinholed_ring(unsigned seed, int *made)
{
    td_grid_u8 *g = td_grid_u8_new(80, 80, NULL);
    int k;
    tg_ring(g, 40, 40, 20, 27);
    *made = 0;
    for (k = 0; k < 16; k++) {
        double a = (rand_r(&seed) % 3600) * 3.14159265 / 1800;
        double r = 21.5 + (rand_r(&seed) % 40) / 10.0;
        int x = (int)(40 + r * cos(a)), y = (int)(40 + r * sin(a));
        if (TD_AT(g, x + 2, y) == 0 || TD_AT(g, x, y + 2) == 0)
            continue; /* keep holes apart: merged ones may reach 8 px */
        TD_AT(g, x, y) = 0;
        if (k % 4 == 0)
            TD_AT(g, x + 1, y) = TD_AT(g, x, y + 1) = TD_AT(g, x + 1, y + 1) = 0;
        (*made)++;
    }
    return g;
}

/* Pinholes (1 px, 2x2 blocks, and ones touching the paper only at a
 * corner) are filled; the ring's own interior is not. */
static void test_pinholes_filled(void)
{
    unsigned seed;
    for (seed = 1; seed <= 10; seed++) {
        int made, x, y, bad = 0;
        td_grid_u8 *g = pinholed_ring(seed, &made);
        size_t filled = 0;
        TT_CHECK(tg_holes4(g) > 1);
        TT_CHECK(td_cv_fill_holes(g, 8, &filled, NULL) == 0);
        TT_CHECKF(tg_holes4(g) == 1, "seed %u: %zu holes left", seed,
                  tg_holes4(g));
        TT_CHECK(filled > 0);
        TT_CHECK(TD_AT(g, 40, 40) == 0); /* the ring's interior stays paper */
        td_thin_hilditch(g, NULL, NULL);
        {
            td_despur_params dp = td_despur_defaults();
            td_despur(g, &dp, NULL, NULL); /* Hilditch whiskers of the band */
        }
        for (y = 0; y < g->h; y++)
            for (x = 0; x < g->w; x++)
                if (TD_AT(g, x, y))
                    bad += td_skel_crossings(td_skel_nbits(g, x, y)) != 2;
        TT_CHECKF(bad == 0, "seed %u: skeleton is not one clean ring", seed);
        td_grid_u8_free(g);
    }
}

/* A paper pixel touching the outside only diagonally is a hole for
 * 8-connected ink; a 3x3 hole is not filled when the limit is 8. */
static void test_connectivity_and_limit(void)
{
    static const char *const rows[] = {
        ".........", ".######..", ".#.####..", ".######..", "..#####..",
        "..#...#..", "..#...#..", "..#...#..", "..#####..", ".........",
        NULL};
    td_grid_u8 *g = tg_from_ascii(rows);
    TT_CHECK(td_cv_fill_holes(g, 8, NULL, NULL) == 0);
    TT_CHECK(TD_AT(g, 2, 2) == 1);  /* 1-px hole */
    TT_CHECK(TD_AT(g, 4, 6) == 0);  /* the 3x3 hole (9 px) stays */
    TT_CHECK(TD_AT(g, 0, 0) == 0);  /* outside stays */
    td_grid_u8_free(g);
}

int main(void)
{
    TT_RUN(test_pinholes_filled);
    TT_RUN(test_connectivity_and_limit);
    return tt_summary();
}
