/* Spur removal: the paper's rule and the length-bounded default. */
#include "tests/tt.h"
#include "tests/util/gridtest.h"
#include "scanner/despur.h"
#include "scanner/skel.h"

static size_t kind(const td_grid_u8 *g, int c_want, int at_least)
{
    size_t n = 0;
    int x, y;
    for (y = 0; y < g->h; y++)
        for (x = 0; x < g->w; x++)
            if (TD_AT(g, x, y)) {
                int c = td_skel_crossings(td_skel_nbits(g, x, y));
                n += at_least ? c >= c_want : c == c_want;
            }
    return n;
}

/* A straight 1-px line of 70 px with whiskers of 2-5 px on both sides. */
static td_grid_u8 *whiskered(void)
{
    td_grid_u8 *g = td_grid_u8_new(90, 30, NULL);
    int x, k;
    for (x = 10; x < 80; x++)
        TD_AT(g, x, 15) = 1;
    for (k = 1; k <= 3; k++) TD_AT(g, 20 + k, 15 - k) = 1;  /* diagonal, 3 px */
    for (k = 1; k <= 5; k++) TD_AT(g, 40, 15 + k) = 1;      /* straight, 5 px */
    for (k = 1; k <= 2; k++) TD_AT(g, 60 - k, 15 - k) = 1;  /* diagonal, 2 px */
    return g;
}

static void test_length_removes_whiskers(void)
{
    td_grid_u8 *g = whiskered();
    td_despur_params p = td_despur_defaults();
    td_despur_stats st;
    td_ctx cx;
    int x;
    td_ctx_init(&cx);
    TT_CHECK(td_despur(g, &p, &st, &cx) == 0);
    TT_CHECKF(st.spurs == 3, "%zu spurs", st.spurs);
    TT_CHECK(kind(g, 3, 1) == 0);  /* no junction left */
    TT_CHECK(kind(g, 1, 0) == 2);  /* the line's two ends */
    for (x = 10; x < 80; x++)
        TT_CHECKF(TD_AT(g, x, 15), "line pixel %d erased", x);
    TT_CHECK(tg_count(g) == 70);
    td_grid_u8_free(g);
}

/* A branch longer than --spur-max is a line, not a spur: kept by the
 * length rule, erased by the paper's rule. */
static void test_long_branch(void)
{
    td_grid_u8 *g = td_grid_u8_new(90, 60, NULL), *c;
    td_despur_params p = td_despur_defaults();
    td_despur_stats st;
    int x, k;
    for (x = 10; x < 80; x++)
        TD_AT(g, x, 10) = 1;
    for (k = 1; k <= 30; k++)
        TD_AT(g, 45, 10 + k) = 1;
    c = td_grid_u8_dup(g, NULL);
    TT_CHECK(td_despur(g, &p, &st, NULL) == 0);
    TT_CHECK(tg_count(g) == 100);
    p.mode = TD_SPUR_PAPER;
    TT_CHECK(td_despur(c, &p, &st, NULL) == 0);
    /* the paper pairs the branch's end with the junction: the 30 px go,
     * and so do both ends of the main line whose nearest junction it is */
    TT_CHECKF(TD_AT(c, 45, 30) == 0, "branch kept by paper rule");
    TT_CHECK(st.spurs >= 1);
    td_grid_u8_free(g);
    td_grid_u8_free(c);
}

/* A broken line without junctions is never touched by either rule. */
static void test_break_kept(void)
{
    td_grid_u8 *g = td_grid_u8_new(60, 10, NULL);
    td_despur_params p = td_despur_defaults();
    int x, mode;
    for (mode = 0; mode < 2; mode++) {
        for (x = 5; x < 55; x++)
            TD_AT(g, x, 5) = (x < 28 || x > 30);
        p.mode = mode ? TD_SPUR_PAPER : TD_SPUR_LENGTH;
        TT_CHECK(td_despur(g, &p, NULL, NULL) == 0);
        TT_CHECK(tg_count(g) == 47);
    }
    td_grid_u8_free(g);
}

/* The paper's documented weakness: a break end closer to a junction than
 * the whisker's end makes it erase the contour piece up to the junction. */
static void test_paper_weakness(void)
{
    td_grid_u8 *g = td_grid_u8_new(80, 30, NULL), *c;
    td_despur_params p = td_despur_defaults();
    int x;
    for (x = 5; x < 75; x++)
        TD_AT(g, x, 15) = (x < 40 || x > 42); /* break at 40..42 */
    TD_AT(g, 30, 14) = TD_AT(g, 30, 13) = TD_AT(g, 30, 12) = 1; /* whisker */
    c = td_grid_u8_dup(g, NULL);
    p.mode = TD_SPUR_PAPER;
    TT_CHECK(td_despur(g, &p, NULL, NULL) == 0);
    TT_CHECKF(TD_AT(g, 35, 15) == 0, "paper rule should erase 31..39");
    p.mode = TD_SPUR_LENGTH;
    TT_CHECK(td_despur(c, &p, NULL, NULL) == 0);
    TT_CHECK(TD_AT(c, 35, 15) == 1 && TD_AT(c, 30, 12) == 0);
    td_grid_u8_free(g);
    td_grid_u8_free(c);
}

static void test_parse(void)
{
    td_despur_params p = td_despur_defaults();
    td_ctx cx;
    td_ctx_init(&cx);
    TT_CHECK(td_despur_parse_mode("paper", &p, &cx) == 0 && p.mode == TD_SPUR_PAPER);
    TT_CHECK(td_despur_parse_mode("bogus", &p, &cx) == TD_EINVAL);
}

int main(void)
{
    TT_RUN(test_length_removes_whiskers);
    TT_RUN(test_long_branch);
    TT_RUN(test_break_kept);
    TT_RUN(test_paper_weakness);
    TT_RUN(test_parse);
    return tt_summary();
}
