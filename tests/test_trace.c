/* Tracing: the paper's start order and counter-clockwise search, 5x5
 * bridging, closure, the backward leg, edge flags, junction splitting,
 * and gap joining. */
#include "tests/tt.h"
#include "tests/util/gridtest.h"
#include "scanner/join.h"
#include "scanner/thin.h"
#include "scanner/trace.h"
#include "scanner/widecut.h"
#include "scanner/width.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static td_lines *trace(td_grid_u8 *g, int bridge, td_trace_stats *st)
{
    td_trace_params p = td_trace_defaults();
    td_lines *ls = NULL;
    p.bridge = bridge;
    p.cut = 0; /* the paper's tracer: through junctions */
    if (g->w < 20)
        p.edge_dist = 0; /* hand-drawn patterns sit close to the border */
    if (td_trace(g, &p, &ls, st, NULL) != 0)
        return NULL;
    return ls;
}

static int pt_is(const td_line *l, size_t i, int x, int y)
{
    return l->xy[2 * i] == x + 0.5 && l->xy[2 * i + 1] == y + 0.5;
}

/* A small diamond ring: one closed line starting at the first pixel in
 * raster order; the counter-clockwise search (east first) takes the east
 * neighbour of a flat top, and south-west of a pointed top. */
static void test_ring_order(void)
{
    static const char *const flat[] = {
        "..........", "...###....", "..#...#...", "..#...#...",
        "...###....", "..........", NULL};
    static const char *const peak[] = {
        ".........", "....#....", "...#.#...", "..#...#..",
        "...#.#...", "....#....", ".........", NULL};
    td_grid_u8 *g = tg_from_ascii(flat);
    td_lines *ls = trace(g, 1, NULL);
    TT_CHECK(ls && ls->n == 1);
    TT_CHECK(ls->v[0].closed && !ls->v[0].edge);
    TT_CHECK(ls->v[0].n == 10);
    TT_CHECK(pt_is(&ls->v[0], 0, 3, 1) && pt_is(&ls->v[0], 1, 4, 1));
    td_lines_free(ls);
    td_grid_u8_free(g);
    g = tg_from_ascii(peak);
    ls = trace(g, 1, NULL);
    TT_CHECK(ls && ls->n == 1 && ls->v[0].closed && ls->v[0].n == 8);
    TT_CHECK(pt_is(&ls->v[0], 0, 4, 1) && pt_is(&ls->v[0], 1, 3, 2));
    td_lines_free(ls);
    td_grid_u8_free(g);
}

/* An arch starts in its middle (first raster pixel); the backward leg
 * makes it one open line from foot to foot. */
static void test_arch_one_line(void)
{
    static const char *const arch[] = {
        "...........", "...........", "...........", "...........",
        "....###....", "...#...#...", "..#.....#..", "..#.....#..",
        "..#.....#..", "...........", "...........", "...........",
        "...........", NULL};
    td_grid_u8 *g = tg_from_ascii(arch);
    td_lines *ls = trace(g, 1, NULL);
    const td_line *l;
    TT_CHECK(ls && ls->n == 1);
    l = &ls->v[0];
    TT_CHECK(!l->closed && l->n == 11);
    TT_CHECK((pt_is(l, 0, 2, 8) && pt_is(l, 10, 8, 8)) ||
             (pt_is(l, 0, 8, 8) && pt_is(l, 10, 2, 8)));
    td_lines_free(ls);
    td_grid_u8_free(g);
}

/* A one-pixel break is bridged by the 5x5 search, a wider one is not. */
static void test_bridge(void)
{
    td_grid_u8 *g = td_grid_u8_new(40, 10, NULL);
    td_trace_stats st;
    td_lines *ls;
    int x;
    for (x = 5; x < 35; x++)
        TD_AT(g, x, 5) = x != 20;
    ls = trace(g, 1, &st);
    TT_CHECK(ls && ls->n == 1 && ls->v[0].n == 29 && st.bridged == 1);
    td_lines_free(ls);
    ls = trace(g, 0, &st);
    TT_CHECK(ls && ls->n == 2 && st.bridged == 0);
    td_lines_free(ls);
    TD_AT(g, 21, 5) = 0; /* 2-px break: beyond the 5x5 window */
    ls = trace(g, 1, &st);
    TT_CHECK(ls && ls->n == 2);
    td_lines_free(ls);
    td_grid_u8_free(g);
}

/* A ring with a 1-px break is closed by bridging. */
static void test_broken_ring_closes(void)
{
    td_grid_u8 *g = td_grid_u8_new(40, 40, NULL);
    td_lines *ls;
    tg_ring(g, 20, 20, 9, 12);
    TT_CHECK(td_thin_hilditch(g, NULL, NULL) == 0);
    TT_CHECK(TD_AT(g, 30, 20) == 1);
    TD_AT(g, 30, 20) = 0; /* a 1-px break in the right side */
    ls = trace(g, 1, NULL);
    TT_CHECK(ls && ls->n == 1 && ls->v[0].closed && ls->v[0].bridged >= 1);
    td_lines_free(ls);
    td_grid_u8_free(g);
}

/* Lines running off the sheet are flagged edge and reach the border. */
static void test_edge(void)
{
    td_grid_u8 *g = td_grid_u8_new(30, 20, NULL);
    td_lines *ls;
    int x;
    for (x = 2; x < 30; x++)
        TD_AT(g, x, 10) = 1;
    ls = trace(g, 1, NULL);
    TT_CHECK(ls && ls->n == 1 && ls->v[0].edge && !ls->v[0].closed);
    TT_CHECK(ls->v[0].xy[0] == 0.5 || ls->v[0].xy[2 * ls->v[0].n - 2] == 0.5);
    td_lines_free(ls);
    td_grid_u8_free(g);
}

/* Random thinned shapes: every skeleton pixel is in exactly one line, and
 * consecutive points are 8-neighbours or a 5x5 bridge apart. */
static void test_every_pixel_once(void)
{
    unsigned seed = 99;
    int trial;
    for (trial = 0; trial < 30; trial++) {
        td_grid_u8 *g = td_grid_u8_new(80, 60, NULL), *seen;
        td_trace_params p = td_trace_defaults();
        td_lines *ls = NULL;
        size_t i, k, total = 0;
        int bad = 0;
        for (k = 0; k < 6; k++)
            tg_ring(g, rand_r(&seed) % 80, rand_r(&seed) % 60,
                    4 + rand_r(&seed) % 15, 6 + rand_r(&seed) % 20);
        td_thin_hilditch(g, NULL, NULL);
        p.edge_dist = 0;
        p.cut = 0; /* the paper's: every pixel in a line */
        TT_CHECK(td_trace(g, &p, &ls, NULL, NULL) == 0);
        seen = td_grid_u8_new(80, 60, NULL);
        for (i = 0; i < ls->n; i++)
            for (k = 0; k < ls->v[i].n; k++) {
                int x = (int)ls->v[i].xy[2 * k], y = (int)ls->v[i].xy[2 * k + 1];
                bad += !TD_AT(g, x, y) || TD_AT(seen, x, y);
                TD_AT(seen, x, y) = 1;
                total++;
                if (k > 0) {
                    int dx = abs(x - (int)ls->v[i].xy[2 * k - 2]);
                    int dy = abs(y - (int)ls->v[i].xy[2 * k - 1]);
                    bad += dx > 2 || dy > 2;
                }
            }
        TT_CHECKF(!bad && total == tg_count(g), "trial %d: %zu of %zu, bad %d",
                  trial, total, tg_count(g), bad);
        td_lines_free(ls);
        td_grid_u8_free(seen);
        td_grid_u8_free(g);
    }
}

/* Two rings touching at a point: the junction is reported and split. */
static void test_touching_rings(void)
{
    td_grid_u8 *g = td_grid_u8_new(60, 40, NULL);
    td_trace_stats st;
    td_lines *ls;
    size_t i, n = 0;
    tg_ring(g, 20, 20, 9, 10.2);
    tg_ring(g, 39, 20, 9, 10.2);
    td_thin_hilditch(g, NULL, NULL);
    ls = trace(g, 1, &st);
    TT_CHECK(ls && st.junctions > 0);
    for (i = 0; ls && i < ls->n; i++)
        n += ls->v[i].n;
    TT_CHECK(n == tg_count(g));
    td_lines_free(ls);
    td_grid_u8_free(g);
}

/* Ours (cut): two rings touching at a point are cut at the junction and
 * the joiner closes each ring on itself, so no line runs from one ring
 * onto the other: every vertex of each line lies on one ring. */
static void test_touching_rings_cut(void)
{
    td_grid_u8 *g = td_grid_u8_new(120, 70, NULL);
    td_trace_params p = td_trace_defaults();
    td_join_params jp = td_join_defaults(120, 70);
    td_trace_stats st;
    td_lines *ls = NULL;
    size_t i, k, closed = 0, mixed = 0;
    tg_ring(g, 35, 35, 24, 25.5);
    tg_ring(g, 85, 35, 24, 25.5);
    td_thin_hilditch(g, NULL, NULL);
    p.edge_dist = 0;
    TT_CHECK(td_trace(g, &p, &ls, &st, NULL) == 0 && st.junctions > 0);
    jp.min_length = 0;
    TT_CHECK(ls && td_join(&ls, &jp, NULL, NULL) == 0);
    for (i = 0; ls && i < ls->n; i++) {
        int left = 0, right = 0;
        for (k = 0; k < ls->v[i].n; k++) {
            left += ls->v[i].xy[2 * k] < 59.0;
            right += ls->v[i].xy[2 * k] > 61.0;
        }
        mixed += left > 2 && right > 2;
        closed += ls->v[i].closed != 0;
    }
    TT_CHECKF(ls && mixed == 0 && closed == 2, "%zu lines, %zu mixed, %zu "
              "closed", ls ? ls->n : 0, mixed, closed);
    td_lines_free(ls);
    td_grid_u8_free(g);
}

/* Gap joining: a 6-px gap along a line is joined; two parallel lines whose
 * ends are 6 px apart sideways are not. */
static void test_join(void)
{
    td_grid_u8 *g = td_grid_u8_new(80, 40, NULL);
    td_join_params jp = td_join_defaults(80, 40);
    td_join_stats js;
    td_lines *ls;
    int x;
    for (x = 5; x < 75; x++) {
        TD_AT(g, x, 10) = (x < 35 || x > 40);
        TD_AT(g, x, 20) = x < 40;
        TD_AT(g, x, 26) = x > 40;
    }
    ls = trace(g, 1, NULL);
    TT_CHECK(ls && ls->n == 4);
    TT_CHECK(td_join(&ls, &jp, &js, NULL) == 0);
    TT_CHECKF(ls->n == 3 && js.joins == 1, "%zu lines, %zu joins", ls->n, js.joins);
    td_lines_free(ls);
    td_grid_u8_free(g);
}


/* A small ring (23 px across) touching a line is cut open at the junction;
 * the joiner keeps it (it is no digit: both ends at the junction, longer
 * than a digit's outline) and closes it. */
static void test_small_ring_touching(void)
{
    td_grid_u8 *g = td_grid_u8_new(100, 60, NULL);
    td_trace_params p = td_trace_defaults();
    td_join_params jp = td_join_defaults(100, 60);
    td_lines *ls = NULL;
    size_t i, k, rings = 0;
    tg_ring(g, 50, 25, 10, 11.6);
    tg_thick_segment(g, 5, 36.5, 95, 36.5, 2.2);
    td_thin_hilditch(g, NULL, NULL);
    p.edge_dist = 0;
    TT_CHECK(td_trace(g, &p, &ls, NULL, NULL) == 0);
    TT_CHECK(ls && td_join(&ls, &jp, NULL, NULL) == 0);
    for (i = 0; ls && i < ls->n; i++) {
        int on = 1;
        for (k = 0; k < ls->v[i].n; k++) {
            double d = hypot(ls->v[i].xy[2 * k] - 50, ls->v[i].xy[2 * k + 1] -
                             25);
            on &= fabs(d - 10.8) < 2.0;
        }
        rings += on && ls->v[i].closed && ls->v[i].n > 20;
    }
    TT_CHECKF(rings == 1, "%zu lines, %zu rings", ls ? ls->n : 0, rings);
    td_lines_free(ls);
    td_grid_u8_free(g);
}

/* Two contours that run into one stretch of ink and part again (crowded
 * slopes): both come in straight, either could go on along the shared
 * stretch, so the join leaves their ends open there instead of guessing
 * (td_join_params.junc_ratio); with the rule off the zone pairs an end
 * with the stretch and the line runs from one contour's side onward. */
static void test_merge_left_open(void)
{
    int k;
    for (k = 0; k < 2; k++) {
        td_grid_u8 *g = td_grid_u8_new(160, 44, NULL);
        td_trace_params p = td_trace_defaults();
        td_join_params jp = td_join_defaults(160, 44);
        td_trace_stats st;
        td_lines *ls = NULL;
        size_t i, j, through = 0;
        int x;
        for (x = 2; x < 158; x++) {
            /* y = 14 and y = 30 outside, meeting at y = 22 over x 60-100 */
            double t = x < 45 ? 0 : x < 60 ? (x - 45) / 15.0
                     : x <= 100 ? 1 : x < 115 ? (115 - x) / 15.0 : 0;
            int a = (int)lround(14 + 8 * t), b = (int)lround(30 - 8 * t);
            TD_AT(g, x, a) = 1;
            TD_AT(g, x, b) = 1;
        }
        td_thin_hilditch(g, NULL, NULL);
        p.edge_dist = 0;
        TT_CHECK(td_trace(g, &p, &ls, &st, NULL) == 0 && st.junctions > 0);
        jp.min_length = 0;
        jp.junc_ratio = k ? 0.0 : jp.junc_ratio;
        TT_CHECK(ls && td_join(&ls, &jp, NULL, NULL) == 0);
        for (i = 0; ls && i < ls->n; i++) {
            int left = 0, right = 0;
            for (j = 0; j < ls->v[i].n; j++) {
                left += ls->v[i].xy[2 * j] < 40.0;
                right += ls->v[i].xy[2 * j] > 120.0;
            }
            through += left > 2 && right > 2;
        }
        if (k == 0)
            TT_CHECKF(through == 0, "%zu lines run through the merge",
                      through);
        else
            TT_CHECKF(through > 0, "rule off: %zu lines through", through);
        td_lines_free(ls);
        td_grid_u8_free(g);
    }
}

/* The default tracer (junctions cut, no border extension) and joiner on
 * g; NULL when either fails. */
static td_lines *cut_join(td_grid_u8 *g)
{
    td_trace_params p = td_trace_defaults();
    td_join_params jp = td_join_defaults(g->w, g->h);
    td_lines *ls = NULL;
    p.edge_dist = 0;
    if (td_trace(g, &p, &ls, NULL, NULL) != 0 ||
        td_join(&ls, &jp, NULL, NULL) != 0) {
        td_lines_free(ls);
        return NULL;
    }
    return ls;
}

/* Two contours that kiss (traced from a real sheet drawn from the Front
 * Range DEM at interval 25): the skeleton is two T junctions joined by a
 * 2-px rung, and the pixels next to a junction touch diagonally, so a
 * tracer stepping to any unvisited neighbour passed the junction by and
 * ran from one contour down the rung onto the other.  No traced line may
 * hold both the upper contour's left end (y 28) and the lower one's right
 * end (y 23), or the lower's left (y 31) and the upper's right (y 20). */
static void test_kiss_corner(void)
{
    /* x 16-35, y 20-31: the upper contour from (16,28) up to J1 (25,24)
       and on north-east; the rung (25,25)-(26,26) down to J2 (26,27);
       the lower contour from (18,31) up to J2 and on east */
    static const char *rows[] = {
        "...............###..", ".............##.....", "...........##.......",
        "..........#........#", "........##......###.", "......##.#....##....",
        "...###....#.##......", ".##.......##........", "#........#..........",
        ".......##...........", ".....##.............", "..###..............."};
    td_grid_u8 *g = td_grid_u8_new(80, 40, NULL);
    td_lines *ls;
    size_t i, k, wrong = 0;
    int x;
    for (i = 0; i < sizeof rows / sizeof rows[0]; i++)
        for (k = 0; rows[i][k]; k++)
            TD_AT(g, k + 16, i + 20) = rows[i][k] == '#';
    for (x = 1; x < 16; x++)
        TD_AT(g, x, 28) = 1;
    for (x = 1; x < 18; x++)
        TD_AT(g, x, 31) = 1;
    for (x = 34; x < 79; x++)
        TD_AT(g, x, 20) = 1;
    for (x = 36; x < 79; x++)
        TD_AT(g, x, 23) = 1;
    ls = cut_join(g);
    TT_CHECK(ls != NULL);
    for (i = 0; ls && i < ls->n; i++) {
        int ul = 0, ur = 0, ll = 0, lr = 0;
        for (k = 0; k < ls->v[i].n; k++) {
            double u = ls->v[i].xy[2 * k], v = ls->v[i].xy[2 * k + 1];
            ul |= u < 10 && fabs(v - 28.5) < 1;
            ll |= u < 10 && fabs(v - 31.5) < 1;
            ur |= u > 70 && fabs(v - 20.5) < 1;
            lr |= u > 70 && fabs(v - 23.5) < 1;
        }
        wrong += (ul && lr) || (ll && ur);
    }
    TT_CHECKF(ls && wrong == 0, "%zu lines, %zu change contour", ls ? ls->n : 0,
              wrong);
    td_lines_free(ls);
    td_grid_u8_free(g);
}

/* A small ring that touches itself (the skeleton of one of the square
 * artefacts of the Elkhorn SRTM DEM, 26 x 22 px: two lobes sharing a
 * wall).  The tracer stops at both contacts, so it comes out as three
 * short pieces, each of them small enough for a digit; together they are
 * more ink than a digit's strokes, and the joiner keeps them
 * (NET_LONG): at least 70 px of line survive. */
static void test_self_touching_ring(void)
{
    static const char *rows[] = {
        "..........##..............", ".........#..#.............",
        "........#....#............", "........#....#............",
        ".......#.....#............", ".....##.....##.....##.....",
        "....#......#..#####..#....", "...#......#...........#...",
        "...#......#............#..", "...#......#...........#...",
        "....#.....#...........#...", "....#......#..........#...",
        "....#......####.......#...", "....#.....#....#......#...",
        "....#.....#....#......#...", "....#.....#....#......#...",
        "....#.....#....#......#...", "....#.....#.....#....#....",
        "....#....#.......####.....", "....#....#................",
        ".....#..#.................", "......##.................."};
    td_grid_u8 *g = td_grid_u8_new(50, 45, NULL);
    td_lines *ls;
    double len = 0;
    size_t i, x, y;
    for (y = 0; y < sizeof rows / sizeof rows[0]; y++)
        for (x = 0; rows[y][x]; x++)
            TD_AT(g, x + 10, y + 10) = rows[y][x] == '#';
    ls = cut_join(g);
    TT_CHECK(ls != NULL);
    for (i = 0; ls && i < ls->n; i++)
        len += td_line_length(&ls->v[i]);
    TT_CHECKF(len >= 70.0, "%zu lines, %.1f px", ls ? ls->n : 0, len);
    td_lines_free(ls);
    td_grid_u8_free(g);
}

/* A contour's hairpin whose apex touches a speck of ink (Elkhorn at
 * interval 20, scanned, at 2066,1732): the apex is a junction, the speck
 * a fragment the joiner removes, and the hairpin's two arms end next to
 * the junction pixel, turning back 120 degrees.  Two ends alone at one
 * junction were one line through it: the joiner joins them (a hairpin)
 * instead of leaving two open ends, which let the faces on either side
 * run into one. */
static void test_hairpin_at_junction(void)
{
    static const int speck[][2] = {{41, 20}, {42, 20}, {43, 19},
                                   {44, 18}, {45, 17}, {45, 16},
                                   {44, 15}, {43, 14}, {42, 14}};
    td_grid_u8 *g = td_grid_u8_new(60, 41, NULL);
    td_lines *ls;
    size_t i, k, through = 0;
    int t;
    for (t = 0; t <= 35; t++) { /* the arms, apex (40,20) */
        TD_AT(g, 40 - t, 20 - (int)lround(t * 20.0 / 35.0)) = 1;
        TD_AT(g, 40 - t, 20 + (int)lround(t * 20.0 / 35.0)) = 1;
    }
    for (t = 0; t < 9; t++) /* the speck, a hook touching the apex */
        TD_AT(g, speck[t][0], speck[t][1]) = 1;
    ls = cut_join(g);
    TT_CHECK(ls != NULL);
    for (i = 0; ls && i < ls->n; i++) {
        int top = 0, bottom = 0;
        for (k = 0; k < ls->v[i].n; k++) {
            top |= ls->v[i].xy[2 * k + 1] < 3;
            bottom |= ls->v[i].xy[2 * k + 1] > 38;
        }
        through += top && bottom;
    }
    TT_CHECKF(ls && through == 1, "%zu lines, %zu through the apex",
              ls ? ls->n : 0, through);
    td_lines_free(ls);
    td_grid_u8_free(g);
}

/* scanner/widecut.c on a hand-made mask: a blob of ink 12 px high from
 * x = 40 to 80 with two lines through it (y = 30 and 36) and a small
 * closed ring (radius 4) in it; lines 2 px wide elsewhere.  Both long
 * lines lose the stretch inside the blob and end on either side of it;
 * the ring stays whole (a small ring is one contour: cutting it would
 * lose a summit); a line alone in a wide stretch of its own ink (no other
 * line inside) stays whole too. */
static void test_wide_cut(void)
{
    td_grid_u8 *g = td_grid_u8_new(120, 80, NULL);
    td_lines *ls = td_lines_new(NULL);
    uint8_t *bits;
    td_line *l;
    size_t i, rings = 0, left = 0, right = 0;
    int x, y, k;
    long nc;
    for (y = 0; y < 80; y++)
        for (x = 0; x < 120; x++)
            TD_AT(g, x, y) = (x >= 40 && x < 80 && y >= 27 && y < 40) ||
                             abs(y - 30) <= 1 || abs(y - 36) <= 1 ||
                             (y >= 60 && y < 72 && x >= 20 && x < 100);
    bits = td_width_pack(g, NULL);
    for (k = 0; k < 3; k++) { /* y = 30, 36, and 66 alone in its ink */
        l = td_lines_add(ls, NULL);
        for (x = 2; x < 118; x++)
            td_line_push(l, x, k == 0 ? 30 : k == 1 ? 36 : 66, NULL);
    }
    l = td_lines_add(ls, NULL);
    for (k = 0; k < 24; k++)
        td_line_push(l, 60 + 4 * cos(k * M_PI / 12),
                     33 + 4 * sin(k * M_PI / 12), NULL);
    l->closed = 1;
    nc = td_wide_cut(bits, 120, 80, ls, 3 * 2.0, NULL);
    for (i = 0; i < ls->n; i++) {
        const td_line *q = &ls->v[i];
        rings += q->closed && q->n == 24;
        if (q->xy[1] == 66)
            TT_CHECKF(q->n == 116, "the line alone in its ink: %zu points",
                      q->n);
        if (q->closed || q->xy[1] == 66)
            continue;
        left += q->xy[2 * (q->n - 1)] < 45 && q->xy[0] == 2;
        right += q->xy[0] > 75 && q->xy[2 * (q->n - 1)] == 117;
    }
    TT_CHECKF(nc == 2 && rings == 1 && left == 2 && right == 2,
              "%ld cut, %zu rings, %zu left and %zu right pieces", nc, rings,
              left, right);
    free(bits);
    td_lines_free(ls);
    td_grid_u8_free(g);
}

/* Four contours 2 px wide, 4 px apart, whose seams (x 30-89) make one
 * blob 14 px across; the first two ribs touch at x 60-61.  With the ribs
 * given, only the two touching lines are cut, each within a few vertices
 * of the contact; the other two run through whole.  Without, all four
 * lose the blob (x 30-89).  A fifth line turns back at x 60 (a hairpin,
 * arms 4 px apart): with the ribs (a sheet where contours crowd) it is
 * cut at its tip, without it stays whole. */
static void test_wide_rib(void)
{
    int pass;
    for (pass = 0; pass < 2; pass++) {
        td_grid_u8 *rg = td_grid_u8_new(120, 80, NULL);
        td_grid_u8 *sg = td_grid_u8_new(120, 80, NULL);
        td_lines *ls = td_lines_new(NULL);
        td_wide_params wp = {3 * 2.0, 0.0, NULL, 0.0, NULL, 0};
        uint8_t *ribs, *seams;
        size_t i, whole = 0, near = 0, hp = 0, tips = 0;
        int x, y, k;
        long nc;
        for (y = 0; y < 80; y++)
            for (x = 0; x < 120; x++) {
                int rib =
                    y >= 30 && y < 46 && (y - 30) % 4 < 2 && x >= 2 && x < 118;
                int touch = y >= 32 && y < 34 && (x == 60 || x == 61);
                TD_AT(rg, x, y) = rib || touch;
                TD_AT(sg, x, y) =
                    rib || touch || (y >= 30 && y < 44 && x >= 30 && x < 90);
            }
        ribs = td_width_pack(rg, NULL);
        seams = td_width_pack(sg, NULL);
        for (k = 0; k < 4; k++) {
            td_line *l = td_lines_add(ls, NULL);
            for (x = 2; x < 118; x++)
                td_line_push(l, x, 30.5 + 4 * k, NULL);
        }
        {
            td_line *l = td_lines_add(ls, NULL); /* the hairpin */
            for (x = 10; x <= 60; x++)
                td_line_push(l, x, 60, NULL);
            for (y = 61; y < 64; y++)
                td_line_push(l, 60, y, NULL);
            for (x = 60; x >= 10; x--)
                td_line_push(l, x, 64, NULL);
        }
        if (pass == 1)
            wp.ribs = ribs, wp.ribw = 2.2 * 2.0, wp.hairpins = 1;
        nc = td_wide_cut_walls(seams, 120, 80, ls, &wp, NULL, NULL);
        for (i = 0; i < ls->n; i++) {
            const td_line *q = &ls->v[i];
            double x0 = q->xy[0], x1 = q->xy[2 * (q->n - 1)];
            if (q->xy[1] >= 60) { /* the hairpin or its pieces */
                hp++;
                tips += fabs(x0 - 60) <= 4 || fabs(x1 - 60) <= 4;
                continue;
            }
            whole += q->n == 116;
            /* a piece ending (or starting) within 8 px of the contact */
            near += (x1 < 60 && x1 >= 52) || (x0 > 61 && x0 <= 69);
        }
        if (pass == 1)
            TT_CHECKF(nc == 3 && whole == 2 && near == 4 && hp == 2 &&
                          tips == 2,
                      "ribs: %ld cut, %zu whole, %zu ends at the contact, "
                      "hairpin in %zu, %zu ending at its tip",
                      nc, whole, near, hp, tips);
        else
            TT_CHECKF(nc == 4 && whole == 0 && hp == 1 && ls->n == 9,
                      "blob whole: %ld cut, %zu whole, %zu lines", nc, whole,
                      ls->n);
        free(ribs), free(seams);
        td_lines_free(ls);
        td_grid_u8_free(rg), td_grid_u8_free(sg);
    }
}

/* An index contour (3 px) and a thin one (2 px) whose inks overlap for 40
 * px: one band 5 px wide, narrower than 3 pens (6 px), so the blob cut
 * leaves it.  The thin contour was traced in two pieces ending inside the
 * band, the index line through it.  With the own-width cut (addw 1.5 px:
 * 3 + 1.5 < 5) the index line loses the band, the thin contour's ends
 * being there; without it, or where the thin contour is traced through
 * the band as well (no end there: two lines side by side), it stays
 * whole. */
static void test_wide_own(void)
{
    int pass;
    for (pass = 0; pass < 3; pass++) {
        td_grid_u8 *g = td_grid_u8_new(120, 60, NULL);
        td_lines *ls = td_lines_new(NULL), *walls = td_lines_new(NULL);
        uint8_t *bits;
        td_line *l;
        size_t i, whole = 0;
        int x, y;
        long nc;
        td_wide_params wp = {0};
        for (y = 0; y < 60; y++)
            for (x = 0; x < 120; x++)
                TD_AT(g, x, y) = (y >= 28 && y <= 30) ||
                                 (x >= 40 && x < 80 ? y >= 31 && y <= 32
                                                    : y >= 33 && y <= 34);
        bits = td_width_pack(g, NULL);
        l = td_lines_add(ls, NULL); /* the index line */
        for (x = 2; x < 118; x++)
            td_line_push(l, x, 29, NULL);
        l->width = 3;
        if (pass == 2) { /* the thin one through the band */
            l = td_lines_add(ls, NULL);
            for (x = 2; x < 118; x++)
                td_line_push(l, x, x >= 40 && x < 80 ? 31.5 : 33.5, NULL);
            l->width = 2;
        } else {
            l = td_lines_add(ls, NULL);
            for (x = 2; x < 40; x++)
                td_line_push(l, x, 33.5, NULL);
            td_line_push(l, 42, 31.5, NULL);
            l->width = 2;
            l = td_lines_add(ls, NULL);
            td_line_push(l, 78, 31.5, NULL);
            for (x = 80; x < 118; x++)
                td_line_push(l, x, 33.5, NULL);
            l->width = 2;
        }
        wp.maxw = 3 * 2.0;
        wp.addw = pass == 0 ? 0 : 1.5;
        nc = td_wide_cut_walls(bits, 120, 60, ls, &wp, walls, NULL);
        for (i = 0; i < ls->n; i++)
            whole += ls->v[i].xy[1] == 29 && ls->v[i].n == 116;
        if (pass == 1)
            TT_CHECKF(nc == 1 && whole == 0 && walls->n == 1,
                      "own-width cut: %ld cut, index line whole: %zu, %zu "
                      "walls",
                      nc, whole, walls->n);
        else
            TT_CHECKF(nc == 0 && whole == 1,
                      "%s: %ld cut, index line whole: %zu",
                      pass ? "side by side" : "addw 0", nc, whole);
        free(bits);
        td_lines_free(ls);
        td_lines_free(walls);
        td_grid_u8_free(g);
    }
}

/* After labelling, a wall goes back as a line where the pieces either side
 * got one height, and stays out where they differ (a line that ran from
 * one contour onto another) or one side has none. */
static void test_walls_restore(void)
{
    static const double piece[5][5] = {/* x0, x1, y, height, has */
                                       {0, 20, 10, 100, 1},
                                       {30, 50, 10, 100, 1},
                                       {0, 20, 20, 110, 1},
                                       {30, 50, 20, 120, 1},
                                       {0, 20, 30, 130, 1}};
    td_lines *ls = td_lines_new(NULL), *walls = td_lines_new(NULL);
    size_t i;
    long nr;
    int k;
    for (k = 0; k < 6; k++) {
        td_line *l = td_lines_add(ls, NULL);
        if (k == 5) { /* beside the last: no height */
            td_line_push(l, 30, 30, NULL);
            td_line_push(l, 50, 30, NULL);
            continue;
        }
        td_line_push(l, piece[k][0], piece[k][2], NULL);
        td_line_push(l, piece[k][1], piece[k][2], NULL);
        l->height = piece[k][3];
        l->has_height = (int)piece[k][4];
        l->hsource = TD_HS_SOLVED;
        l->confidence = 0.5 + 0.1 * k;
    }
    for (k = 0; k < 3; k++) {
        td_line *w = td_lines_add(walls, NULL);
        td_line_push(w, 20, 10 + 10 * k, NULL);
        td_line_push(w, 25, 10 + 10 * k + 1, NULL);
        td_line_push(w, 30, 10 + 10 * k, NULL);
    }
    nr = td_walls_restore(ls, walls, NULL);
    TT_CHECKF(nr == 1 && ls->n == 7, "%ld put back, %zu lines", nr, ls->n);
    for (i = 6; i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        TT_CHECKF(l->has_height && l->height == 100 && l->n == 3 &&
                      l->xy[0] == 20 && l->xy[3] == 11 &&
                      fabs(l->confidence - 0.5) < 1e-9 && l->id == 6,
                  "put back: height %g, %zu points, confidence %g, id %ld",
                  l->height, l->n, l->confidence, l->id);
    }
    td_lines_free(ls);
    td_lines_free(walls);
}

/* A 1-px break in a line with another contour 2 px beside it, starting
 * level with the break: the paper's bridge takes the ring's first pixel
 * counter-clockwise, the neighbour's; ours goes on straight ahead. */
static void test_bridge_ahead(void)
{
    int mode;
    for (mode = TD_BRIDGE_PAPER; mode <= TD_BRIDGE_AHEAD; mode++) {
        td_grid_u8 *g = td_grid_u8_new(40, 70, NULL);
        td_trace_params p = td_trace_defaults();
        td_lines *ls = NULL;
        size_t k, onb = 0, own = 0;
        int y;
        for (y = 5; y < 62; y++) {
            TD_AT(g, 20, y) = y != 31; /* the line, broken at y = 31 */
            TD_AT(g, 18, y) = y >= 31; /* its neighbour, from y = 31 on */
        }
        p.bridge = mode;
        TT_CHECK(td_trace(g, &p, &ls, NULL, NULL) == 0 && ls && ls->n > 0);
        for (k = 0; ls && k < ls->v[0].n; k++) {
            onb += ls->v[0].xy[2 * k] < 19;
            own += ls->v[0].xy[2 * k] > 20 && ls->v[0].xy[2 * k + 1] > 40;
        }
        if (mode == TD_BRIDGE_AHEAD)
            TT_CHECKF(onb == 0 && own > 15, "ahead: %zu px on the neighbour, "
                      "%zu on its own far side", onb, own);
        else
            TT_CHECKF(onb > 0, "paper: %zu px on the neighbour", onb);
        td_lines_free(ls);
        td_grid_u8_free(g);
    }
}

int main(void)
{
    TT_RUN(test_ring_order);
    TT_RUN(test_arch_one_line);
    TT_RUN(test_bridge);
    TT_RUN(test_broken_ring_closes);
    TT_RUN(test_edge);
    TT_RUN(test_every_pixel_once);
    TT_RUN(test_touching_rings);
    TT_RUN(test_touching_rings_cut);
    TT_RUN(test_join);
    TT_RUN(test_small_ring_touching);
    TT_RUN(test_merge_left_open);
    TT_RUN(test_bridge_ahead);
    TT_RUN(test_kiss_corner);
    TT_RUN(test_self_touching_ring);
    TT_RUN(test_hairpin_at_junction);
    TT_RUN(test_wide_cut);
    TT_RUN(test_wide_rib);
    TT_RUN(test_wide_own);
    TT_RUN(test_walls_restore);
    return tt_summary();
}
