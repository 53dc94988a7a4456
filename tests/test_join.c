/* Joining across label gaps (scanner/join.c, stages 0-2): hand-made lines
 * for each rule, and generated sheets whose index contours are cut by
 * inline elevation labels (samples/gen/labels.c): after the scanner every
 * true contour is whole (closed rings closed, one piece each), no traced
 * line follows two contours, and no label-gap join crosses a line. */
#include "tests/tt.h"
#include "tests/util/match.h"
#include "samples/gen/gen.h"
#include "src/core/core.h"
#include "scanner/scan.h"

#include <stdlib.h>
#include <string.h>

#define W 300
#define H 200

/* Append an open line through n points (x,y pairs). */
static void add_line(td_lines *ls, const double *xy, size_t n, int closed)
{
    td_line *l = td_lines_add(ls, NULL);
    size_t k;
    for (k = 0; k < n; k++)
        td_line_push(l, xy[2 * k], xy[2 * k + 1], NULL);
    l->closed = closed;
}

/* A straight line from (x0,y) to (x1,y) with 1-px steps. */
static void add_hline(td_lines *ls, double x0, double x1, double y)
{
    td_line *l = td_lines_add(ls, NULL);
    double x, step = x1 > x0 ? 1 : -1;
    for (x = x0; step > 0 ? x <= x1 : x >= x1; x += step)
        td_line_push(l, x, y, NULL);
}

/* A ring of radius r about (cx,cy) with n points. */
static void add_ring(td_lines *ls, double cx, double cy, double r, int n)
{
    td_line *l = td_lines_add(ls, NULL);
    int k;
    for (k = 0; k < n; k++)
        td_line_push(l, cx + r * cos(2 * M_PI * k / n),
                     cy + r * sin(2 * M_PI * k / n), NULL);
    l->closed = 1;
}

/* A packed other-ink map (W x H, td_join_params.other) with nothing but
 * the box x0..x1, y0..y1 set. */
static void other_box(uint8_t *bits, int x0, int x1, int y0, int y1)
{
    size_t stride = (W + 7) / 8;
    int x, y;
    memset(bits, 0, stride * H);
    for (y = y0; y <= y1; y++)
        for (x = x0; x <= x1; x++)
            bits[(size_t)y * stride + (x >> 3)] |= (uint8_t)(1u << (x & 7));
}

static size_t count_closed(const td_lines *ls)
{
    size_t i, n = 0;
    for (i = 0; i < ls->n; i++)
        n += ls->v[i].closed != 0;
    return n;
}

/* A stream (rows 100-103) crosses two contours 6 px apart (x 100 and
 * 106); on its upper bank the traced line runs down one, turns on a
 * 6-px cap (what the bank's colour fringe leaves) and back up the other:
 * one line carrying two heights.  It is cut at the turn and each arm is
 * joined across the water to its own continuation below (two straight
 * lines); with water_turns off the hairpin stays.  With nothing below
 * the stream (a loop of one contour whose tip touches the water) the
 * cut is undone: the hairpin stays, one line. */
static void test_water_turn(void)
{
    size_t stride = (W + 7) / 8, x, y, i;
    uint8_t *water = calloc(stride * H, 1);
    int k;
    for (y = 100; y <= 103; y++)
        for (x = 0; x < W; x++)
            water[y * stride + x / 8] |= (uint8_t)(1u << (x % 8));
    for (k = 0; k < 3; k++) {
        td_join_params p = td_join_defaults(W, H);
        td_join_stats st;
        td_lines *ls = td_lines_new(NULL);
        td_line *l = td_lines_add(ls, NULL);
        const double cap[] = {101, 97, 102, 98, 103, 98, 104, 98, 105, 97};
        size_t hair = 0, whole = 0;
        double v;
        for (v = 20; v <= 96; v++)
            td_line_push(l, 100, v, NULL);
        for (i = 0; i < 5; i++)
            td_line_push(l, cap[2 * i], cap[2 * i + 1], NULL);
        for (v = 96; v >= 20; v--)
            td_line_push(l, 106, v, NULL);
        for (i = 0; i < (k < 2 ? 2u : 0u); i++) { /* below the stream */
            l = td_lines_add(ls, NULL);
            for (v = 106; v <= 180; v++)
                td_line_push(l, i ? 106 : 100, v, NULL);
        }
        p.water = water;
        p.water_turns = k != 1;
        TT_CHECK(td_join(&ls, &p, &st, NULL) == 0);
        for (i = 0; i < ls->n; i++) {
            const td_line *m = &ls->v[i];
            double x0 = HUGE_VAL, x1 = -HUGE_VAL, y0 = HUGE_VAL, y1 = -HUGE_VAL;
            size_t q;
            for (q = 0; q < m->n; q++) {
                x0 = fmin(x0, m->xy[2 * q]), x1 = fmax(x1, m->xy[2 * q]);
                y0 = fmin(y0, m->xy[2 * q + 1]);
                y1 = fmax(y1, m->xy[2 * q + 1]);
            }
            hair += x1 - x0 > 5 && y1 < 100;
            whole += x1 - x0 <= 4 && y0 <= 20 && y1 >= 180;
        }
        if (k == 0)
            TT_CHECKF(st.water_turns == 1 && hair == 0 && whole == 2 &&
                          ls->n == 2,
                      "%zu turns cut, %zu lines: %zu hairpins, %zu whole",
                      st.water_turns, ls->n, hair, whole);
        else
            TT_CHECKF(
                st.water_turns == 0 && hair == 1 && ls->n == (k == 1 ? 3u : 1u),
                "%s: %zu lines, %zu hairpins",
                k == 1 ? "without the cut" : "nothing below", ls->n, hair);
        td_join_stats_free(&st);
        td_lines_free(ls);
    }
    free(water);
}

/* A 40-px gap along a line is joined; with a line crossing the gap it is
 * not. */
static void test_crossing_rejected(void)
{
    td_join_params p = td_join_defaults(W, H);
    td_join_stats st;
    td_lines *ls = td_lines_new(NULL);
    const double cross[] = {130, 20, 130, 180};
    add_hline(ls, 20, 110, 100);
    add_hline(ls, 150, 260, 100);
    TT_CHECK(td_join(&ls, &p, &st, NULL) == 0);
    TT_CHECKF(ls->n == 1 && st.long_joins == 1, "%zu lines", ls->n);
    td_join_stats_free(&st);
    td_lines_free(ls);

    ls = td_lines_new(NULL);
    add_hline(ls, 20, 110, 100);
    add_hline(ls, 150, 260, 100);
    add_line(ls, cross, 2, 0);
    TT_CHECK(td_join(&ls, &p, &st, NULL) == 0);
    TT_CHECKF(ls->n == 3 && st.joins == 0 && st.ends_open == 6,
              "%zu lines, %zu joins, %zu open ends", ls->n, st.joins,
              st.ends_open);
    td_join_stats_free(&st);
    td_lines_free(ls);

    ls = td_lines_new(NULL); /* the crossing line has a vertex on the join */
    add_hline(ls, 20.5, 110.5, 100.5);
    add_hline(ls, 150.5, 260.5, 100.5);
    {
        const double v[] = {130.5, 20.5, 130.5, 100.5, 130.5, 180.5};
        add_line(ls, v, 3, 0);
    }
    TT_CHECK(td_join(&ls, &p, &st, NULL) == 0);
    TT_CHECKF(ls->n == 3 && st.joins == 0, "%zu lines", ls->n);
    td_join_stats_free(&st);
    td_lines_free(ls);
}

/* Two lines side by side (ends 8 px apart sideways over a 40-px gap) are
 * different contours: not joined.  A line bending gently through the gap
 * is. */
static void test_shift_and_bend(void)
{
    td_join_params p = td_join_defaults(W, H);
    td_join_stats st;
    td_lines *ls = td_lines_new(NULL);
    td_line *l;
    double x;
    add_hline(ls, 20, 110, 100);
    add_hline(ls, 150, 260, 108);
    TT_CHECK(td_join(&ls, &p, &st, NULL) == 0);
    TT_CHECKF(ls->n == 2 && st.joins == 0, "%zu lines", ls->n);
    td_join_stats_free(&st);
    td_lines_free(ls);

    ls = td_lines_new(NULL); /* an arc of radius 400 with a gap at its top */
    l = td_lines_add(ls, NULL);
    for (x = -120; x <= -20; x += 1)
        td_line_push(l, 150 + x, 60 + 400 - sqrt(400.0 * 400 - x * x), NULL);
    l = td_lines_add(ls, NULL);
    for (x = 20; x <= 120; x += 1)
        td_line_push(l, 150 + x, 60 + 400 - sqrt(400.0 * 400 - x * x), NULL);
    TT_CHECK(td_join(&ls, &p, &st, NULL) == 0);
    TT_CHECKF(ls->n == 1 && st.long_joins == 1, "%zu lines", ls->n);
    td_join_stats_free(&st);
    td_lines_free(ls);
}

/* Points on a circle about (cx,cy) of radius r, rounded to pixel centres
 * (a traced skeleton), from angle a0 to a1 (degrees), one per px. */
static void add_arc(td_lines *ls, double cx, double cy, double r, double a0,
                    double a1)
{
    td_line *l = td_lines_add(ls, NULL);
    double a, step = (a1 > a0 ? 1 : -1) * 180.0 / (M_PI * r);
    for (a = a0; a1 > a0 ? a <= a1 : a >= a1; a += step) {
        double x = floor(cx + r * cos(a * M_PI / 180)) + 0.5;
        double y = floor(cy + r * sin(a * M_PI / 180)) + 0.5;
        if (l->n == 0 || x != l->xy[2 * l->n - 2] || y != l->xy[2 * l->n - 1])
            td_line_push(l, x, y, NULL);
    }
}

/* A ring of radius 50 (pixel-rounded) cut by a 45-px gap: about 52
 * degrees of turn across it, beyond the straight rule (17 per end); the
 * curve rule joins and closes it, and the join follows the circle within
 * 1 px (the chord's middle is 5 px off).  A straight line whose end lies
 * on the circle's way and points along it does not curve like the ring:
 * not joined to it. */
static void test_curved_gap(void)
{
    td_join_params p = td_join_defaults(W, H);
    td_join_stats st;
    td_lines *ls = td_lines_new(NULL);
    size_t k, far = 0;
    add_arc(ls, 150, 100, 50, -65, 240);
    p.record = 1;
    TT_CHECK(td_join(&ls, &p, &st, NULL) == 0);
    TT_CHECKF(ls->n == 1 && count_closed(ls) == 1 && st.long_joins == 1,
              "%zu lines, %zu label joins", ls->n, st.long_joins);
    TT_CHECK(st.segments && st.segments->n == 1 && st.segments->v[0].n > 5);
    for (k = 0; st.segments && st.segments->n && k < st.segments->v[0].n; k++)
        far += fabs(hypot(st.segments->v[0].xy[2 * k] - 150,
                          st.segments->v[0].xy[2 * k + 1] - 100) - 50) > 1.0;
    TT_CHECKF(far == 0, "%zu join points more than 1 px off the circle", far);
    td_join_stats_free(&st);
    td_lines_free(ls);

    ls = td_lines_new(NULL); /* the arc's end, then a straight line */
    add_arc(ls, 150, 100, 50, -65, 200);
    {
        double a = 240 * M_PI / 180, tx = -sin(a), ty = cos(a);
        double x0 = 150 + 50 * cos(a), y0 = 100 + 50 * sin(a), xy[120];
        for (k = 0; k < 60; k++) /* from the circle's point at 240 deg on */
            xy[2 * k] = x0 + tx * k, xy[2 * k + 1] = y0 + ty * k;
        add_line(ls, xy, 60, 0);
    }
    TT_CHECK(td_join(&ls, &p, &st, NULL) == 0);
    TT_CHECKF(ls->n == 2 && st.long_joins == 0, "%zu lines, %zu joins",
              ls->n, st.long_joins);
    td_join_stats_free(&st);
    td_lines_free(ls);
}

/* A label: a bent digit fragment (a "2") and a digit ring (a "0") in a
 * 44-px gap of a rectangular ring.  The fragment is removed, the gap joined, the ring
 * closed, and the digit ring under the join removed; a tiny true ring
 * elsewhere (a summit, 4 px across) is kept. */
static void test_label_gap(void)
{
    td_join_params p = td_join_defaults(W, H);
    td_join_stats st;
    td_lines *ls = td_lines_new(NULL);
    td_line *l = td_lines_add(ls, NULL);
    const double two[] = {157, 13, 163, 13, 163, 20, 157, 20, 157, 27,
                          163, 27};
    const double corner[][2] = {{260, 20}, {260, 180}, {40, 180}, {40, 20},
                                {128, 20}};
    double x = 172, y = 20;
    int c;
    /* a rectangular ring with a gap from x = 128 to 172 in its top side */
    for (c = 0; c < 5; c++) {
        double dx = corner[c][0] - x, dy = corner[c][1] - y;
        int k, n = (int)fmax(fabs(dx), fabs(dy));
        for (k = 0; k < n; k++)
            td_line_push(l, x + dx * k / n, y + dy * k / n, NULL);
        x = corner[c][0], y = corner[c][1];
    }
    td_line_push(l, x, y, NULL);
    add_line(ls, two, 6, 0);
    /* the digit ring sits on the top of the big ring, inside the gap */
    add_ring(ls, 150, 20, 5, 12);
    add_ring(ls, 150, 100, 2, 6); /* the summit */
    {
        double s[] = {133, 20, 139, 20, 139, 27, 133, 27, 133, 14, 139, 14};
        add_line(ls, s, 6, 0); /* another digit near the gap */
    }
    TT_CHECK(td_join(&ls, &p, &st, NULL) == 0);
    TT_CHECKF(st.fragments == 2 && st.long_joins == 1 && st.glyphs == 1,
              "%zu fragments, %zu label joins, %zu glyphs", st.fragments,
              st.long_joins, st.glyphs);
    TT_CHECKF(ls->n == 2 && count_closed(ls) == 2, "%zu lines, %zu closed",
              ls->n, count_closed(ls));
    TT_CHECK(st.ends_open == 0);
    td_join_stats_free(&st);
    td_lines_free(ls);
}

/* Two contours 6 px apart, both broken across the same 40 px (a faded
 * patch of a printed sheet: there each end could be any neighbour's, and
 * most such joins measured on the crowded printed sheets were wrong):
 * left open (4 lines); with gap_room off, joined (2 lines).  One contour
 * broken beside a whole neighbour is joined either way. */
static void test_gaps_side_by_side(void)
{
    int k, both;
    for (both = 0; both < 2; both++)
        for (k = 0; k < 2; k++) {
            td_join_params p = td_join_defaults(W, H);
            td_join_stats st;
            td_lines *ls = td_lines_new(NULL);
            size_t want;
            add_hline(ls, 20, 110, 100);
            add_hline(ls, 150, 260, 100);
            if (both) {
                add_hline(ls, 20, 110, 106);
                add_hline(ls, 150, 260, 106);
            } else
                add_hline(ls, 20, 260, 106);
            if (k == 1)
                p.gap_room = 0;
            TT_CHECK(td_join(&ls, &p, &st, NULL) == 0);
            want = both && k == 0 ? 4 : 2;
            TT_CHECKF(ls->n == want, "%s, gap_room %g: %zu lines (want %zu)",
                      both ? "both broken" : "one broken", p.gap_room, ls->n,
                      want);
            td_join_stats_free(&st);
            td_lines_free(ls);
        }
}

/* Whether some line of ls has points on both rows y0 and y1. */
static int spans_rows(const td_lines *ls, double y0, double y1)
{
    size_t i, k;
    for (i = 0; i < ls->n; i++) {
        int a = 0, b = 0;
        for (k = 0; k < ls->v[i].n; k++)
            a |= ls->v[i].xy[2 * k + 1] == y0,
                b |= ls->v[i].xy[2 * k + 1] == y1;
        if (a && b)
            return 1;
    }
    return 0;
}

/* Two contours 3 px apart where they crowd: contour A at row 100 breaks
 * between x 100 and 115, contour B at row 103 begins at x 104 (its left
 * part lost in a faded patch).  A's end faces B's start 5 px away at 37
 * degrees, a cheaper first-stage pair (cost 14.2) than A's own 15-px
 * break (15): joined, the line runs from contour A onto contour B (to
 * x 200).  That
 * pair steps 3 px sideways and A's end has another candidate (its own
 * continuation) costing under 1.5 times as much: it is left open
 * (gap_ratio, ours), and A is joined whole along its row.  With the rule
 * off the line jumps. */
static void test_sidestep_left_open(void)
{
    int on;
    for (on = 0; on < 2; on++) {
        td_join_params p = td_join_defaults(W, H);
        td_join_stats st;
        td_lines *ls = td_lines_new(NULL);
        size_t i, whole = 0;
        add_hline(ls, 20, 100, 100);
        add_hline(ls, 115, 260, 100);
        add_hline(ls, 104, 200, 103);
        if (!on)
            p.gap_ratio = 0;
        TT_CHECK(td_join(&ls, &p, &st, NULL) == 0);
        for (i = 0; i < ls->n; i++)
            whole += ls->v[i].n >= 2 && ls->v[i].xy[0] == 20 &&
                     ls->v[i].xy[2 * ls->v[i].n - 2] == 260 &&
                     !spans_rows(ls, 100, 103);
        if (on)
            TT_CHECKF(!spans_rows(ls, 100, 103) && whole == 1 &&
                          st.gaps_open == 1,
                      "%zu lines, a line on both contours: %d, %zu ends "
                      "left open",
                      ls->n, spans_rows(ls, 100, 103), st.gaps_open);
        else
            TT_CHECKF(spans_rows(ls, 100, 103),
                      "rule off: %zu lines, none runs onto the other "
                      "contour (the case no longer tests the rule)",
                      ls->n);
        td_join_stats_free(&st);
        td_lines_free(ls);
    }
}

/* Line A (20..100 along y 100), line B starting 12 px straight ahead
 * (112..260), and A's own continuation from (103, 104) down at 53 degrees:
 * the case of the near-end rule. */
static void near_end_lines(td_lines *ls)
{
    double c[2 * 40];
    size_t k;
    for (k = 0; k < 40; k++) {
        c[2 * k] = 103 + 0.6 * (double)k;
        c[2 * k + 1] = 104 + 0.8 * (double)k;
    }
    add_hline(ls, 20, 100, 100);
    add_hline(ls, 112, 260, 100);
    add_line(ls, c, 40, 0);
}

/* A contour turning sharply where its ink broke (docs/scanner.md "A third
 * line's end near the gap"): contour A runs along row 100 to x 100 and
 * goes on down and to the right from (103, 104), 53 degrees off its
 * course, too sharp a turn for a first-stage pair; line B starts on the
 * same row at x 112, 12 px straight ahead.  Joined, A would run onto B.
 * The end of a third line (A's own continuation) lies 5 px from A's end,
 * under half the gap: the pair is left open (gap_near, ours), both ends
 * stay free and no later stage joins them.  With the rule off A runs
 * onto B. */
static void test_near_end_left_open(void)
{
    int on;
    for (on = 0; on < 2; on++) {
        td_join_params p = td_join_defaults(W, H);
        td_join_stats st;
        td_lines *ls = td_lines_new(NULL);
        size_t i, onto = 0;
        near_end_lines(ls);
        if (!on)
            p.gap_near = 0;
        TT_CHECK(td_join(&ls, &p, &st, NULL) == 0);
        for (i = 0; i < ls->n; i++)
            onto += ls->v[i].n >= 2 && ls->v[i].xy[0] == 20 &&
                    ls->v[i].xy[2 * ls->v[i].n - 2] == 260;
        if (on)
            TT_CHECKF(onto == 0 && ls->n == 3 && st.gaps_open == 2,
                      "%zu lines, A run onto B: %zu, %zu ends left open", ls->n,
                      onto, st.gaps_open);
        else
            TT_CHECKF(onto == 1,
                      "rule off: %zu lines, A not run onto B "
                      "(the case no longer tests the rule)",
                      ls->n);
        td_join_stats_free(&st);
        td_lines_free(ls);
    }
}

/* The same case with a stream (water bits, td_join_params.water) across
 * the gap between the break and the third line's start: a contour's V at
 * a stream has its ends askew and its neighbours' near, yet the chord over
 * the water is no surer than one on dry paper, so the near-end rule holds
 * there too (the break stays open rather than run onto the other line;
 * docs/scanner.md, "Chords over the water"). */
static void test_near_end_over_water(void)
{
    static uint8_t water[(W + 7) / 8 * H + 1];
    td_join_params p = td_join_defaults(W, H);
    td_join_stats st;
    td_lines *ls = td_lines_new(NULL);
    size_t i, onto = 0;
    near_end_lines(ls);
    other_box(water, 104, 108, 80, 120); /* a stream across the gap */
    p.water = water;
    TT_CHECK(td_join(&ls, &p, &st, NULL) == 0);
    for (i = 0; i < ls->n; i++)
        onto += ls->v[i].n >= 2 && ls->v[i].xy[0] == 20 &&
                ls->v[i].xy[2 * ls->v[i].n - 2] == 260;
    TT_CHECKF(onto == 0 && ls->n == 3,
              "%zu lines, A run onto B across the water: %zu", ls->n, onto);
    td_join_stats_free(&st);
    td_lines_free(ls);
}

/* --alone-gaps (td_join_params.alone_gaps): a line whose ink broke where
 * it bends 85 degrees, its ends 5 px apart, the gap 50 degrees off the
 * first piece's course and 35 off the second's (stage 1's 40-degree limit
 * refuses the pair), nothing else near: joined into one line with the
 * option, two lines without; with a third line's end 8 px from the break
 * (within twice the gap) it stays open even with the option. */
static void test_alone_gap(void)
{
    int k;
    for (k = 0; k < 3; k++) {
        td_join_params p = td_join_defaults(W, H);
        td_join_stats st;
        td_lines *ls = td_lines_new(NULL);
        double c[2 * 60];
        size_t j, whole = 0;
        for (j = 0; j < 60; j++) { /* 5 px from (100, 100) at 50 degrees,
                                      on at 85 */
            c[2 * j] = 100 + 5 * cos(50 * M_PI / 180) +
                       (double)j * cos(85 * M_PI / 180);
            c[2 * j + 1] = 100 + 5 * sin(50 * M_PI / 180) +
                           (double)j * sin(85 * M_PI / 180);
        }
        add_hline(ls, 20, 100, 100);
        add_line(ls, c, 60, 0);
        if (k == 2) /* a third line starting 8 px above the break */
            add_hline(ls, 102, 160, 92);
        p.alone_gaps = k > 0;
        TT_CHECK(td_join(&ls, &p, &st, NULL) == 0);
        for (j = 0; j < ls->n; j++)
            whole += ls->v[j].n >= 2 && ls->v[j].xy[0] == 20 &&
                     fabs(ls->v[j].xy[2 * ls->v[j].n - 2] - c[118]) < 1e-9;
        if (k == 1)
            TT_CHECKF(whole == 1 && st.alone_joins == 1,
                      "option on: %zu lines, whole %zu, %zu alone joins", ls->n,
                      whole, st.alone_joins);
        else
            TT_CHECKF(whole == 0 && st.alone_joins == 0,
                      "case %d: %zu lines, whole %zu, %zu alone joins", k,
                      ls->n, whole, st.alone_joins);
        td_join_stats_free(&st);
        td_lines_free(ls);
    }
}

/* A 30-px gap between two pieces of one line is a label gap on paper
 * (joined); the same gap under a road (another ink, td_join_params.other,
 * along the gap) is a contour hidden under it, and stays open: its ends
 * could be any two of the contours the road runs along.  A road crossing
 * the gap (a 4-px band across it) does not stop the join. */
static void test_gap_under_other_ink(void)
{
    static uint8_t bits[(W + 7) / 8 * H + 1];
    int k;
    for (k = 0; k < 3; k++) {
        td_join_params p = td_join_defaults(W, H);
        td_join_stats st;
        td_lines *ls = td_lines_new(NULL);
        add_hline(ls, 20, 130, 100);
        add_hline(ls, 160, 280, 100);
        if (k == 1) /* a road along the gap */
            other_box(bits, 125, 165, 97, 103);
        else /* across it */
            other_box(bits, 143, 146, 97, 103);
        p.other = k ? bits : NULL;
        TT_CHECK(td_join(&ls, &p, &st, NULL) == 0);
        TT_CHECKF((k == 1) == (ls->n == 2),
                  "case %d: %zu lines, %zu label "
                  "joins",
                  k, ls->n, st.long_joins);
        td_join_stats_free(&st);
        td_lines_free(ls);
    }
}

/* A short piece of a contour between two small breaks is not a fragment:
 * it continues the lines on both sides. */
static void test_short_piece_kept(void)
{
    td_join_params p = td_join_defaults(W, H);
    td_join_stats st;
    td_lines *ls = td_lines_new(NULL);
    add_hline(ls, 20, 100, 100);
    add_hline(ls, 106, 120, 100);
    add_hline(ls, 126, 260, 100);
    TT_CHECK(td_join(&ls, &p, &st, NULL) == 0);
    TT_CHECKF(ls->n == 1 && st.fragments == 0 && st.joins == 2,
              "%zu lines, %zu fragments", ls->n, st.fragments);
    TT_CHECKF(ls->n == 1 && td_line_length(&ls->v[0]) > 235, "length %g",
              ls->n ? td_line_length(&ls->v[0]) : 0.0);
    td_join_stats_free(&st);
    td_lines_free(ls);
}

/* A contour that bends sharply beside its label gap, cut off from the
 * rest of its line at a thin neck (Orkhon 50 scanned, the 1500 line at
 * 920,1600): the hook is compact (a 19 x 15 px box, under min_length)
 * but 40 px long, one of its ends continues the line across a 4 px
 * break, and the other ends in the label gap.  It is the line's, not a
 * digit: kept and joined (before: removed as a fragment, the line ended
 * 30 px short of its gap and the DEM there came out 80 m off). */
static void test_hook_kept(void)
{
    td_join_params p = td_join_defaults(W, H);
    td_join_stats st;
    td_lines *ls = td_lines_new(NULL);
    td_line *l;
    int k;
    add_hline(ls, 20, 150, 100);
    l = td_lines_add(ls, NULL);
    for (k = 154; k < 162; k++) /* on along the line, then round */
        td_line_push(l, k, 100, NULL);
    for (k = 0; k <= 12; k++)
        td_line_push(l, 162 + 7 * sin(M_PI * k / 12),
                     107 - 7 * cos(M_PI * k / 12), NULL);
    for (k = 161; k >= 150; k--) /* back west, into the gap */
        td_line_push(l, k, 114, NULL);
    TT_CHECK(td_join(&ls, &p, &st, NULL) == 0);
    TT_CHECKF(ls->n == 1 && st.fragments == 0 &&
                  td_line_length(&ls->v[0]) > 170,
              "%zu lines, %zu fragments, length %g", ls->n, st.fragments,
              ls->n ? td_line_length(&ls->v[0]) : 0.0);
    td_join_stats_free(&st);
    td_lines_free(ls);
}

/* A stretch of contour curled round a small summit, open at both ends
 * where the faded ink broke (a U 16 px across and 22 high, 53 px long: a
 * compact piece, as a label's digits are) with no line near its ends:
 * kept as contour (td_join_params.curl_keep), not taken as text.  A
 * label "20" beside it, its "2" as long (32 px, 7 x 14) and curled, still
 * goes: a glyph has its label's other glyphs beside it.  With the rule
 * off the U goes too. */
static void test_curl_kept(void)
{
    int off;
    for (off = 0; off < 2; off++) {
        td_join_params p = td_join_defaults(W, H);
        td_join_stats st;
        td_lines *ls = td_lines_new(NULL);
        td_line *l = td_lines_add(ls, NULL);
        const double two[] = {217, 93,  223, 93,  223, 100,
                              217, 100, 217, 107, 223, 107};
        int k;
        double len;
        for (k = 0; k <= 14; k++) /* down the left arm */
            td_line_push(l, 100, 86 + k, NULL);
        for (k = 1; k < 12; k++) /* round the bottom */
            td_line_push(l, 108 - 8 * cos(M_PI * k / 12),
                         100 + 8 * sin(M_PI * k / 12), NULL);
        for (k = 0; k <= 14; k++) /* up the right arm */
            td_line_push(l, 116, 100 - k, NULL);
        len = td_line_length(l);
        add_line(ls, two, 6, 0);
        add_ring(ls, 232, 100, 5, 12); /* the label's "0" */
        add_hline(ls, 20, 280, 160);
        if (off)
            p.curl_keep = 0;
        TT_CHECK(td_join(&ls, &p, &st, NULL) == 0);
        TT_CHECKF(len > 2 * p.min_length, "the U is %g px", len);
        if (!off)
            TT_CHECKF(ls->n == 2 && st.curls == 1 && st.fragments == 1 &&
                          st.glyphs == 1,
                      "%zu lines, %zu curls kept, %zu fragments, %zu glyphs",
                      ls->n, st.curls, st.fragments, st.glyphs);
        else
            TT_CHECKF(ls->n == 1 && st.curls == 0 && st.fragments == 2,
                      "off: %zu lines, %zu curls kept, %zu fragments", ls->n,
                      st.curls, st.fragments);
        td_join_stats_free(&st);
        td_lines_free(ls);
    }
}

/* A straight road the mask took with the contours, cut at every contour
 * it crosses: four 36-px pieces lined up at x = 150, each gap holding a
 * contour.  The pieces go (each would be a "contour" stepping from one
 * level to the next) and the three contours stay whole; the same pieces
 * with nothing in their gaps (a contour broken where its ink faded) stay
 * and are joined. */
static void test_road_chain(void)
{
    int crossed;
    for (crossed = 1; crossed >= 0; crossed--) {
        td_join_params p = td_join_defaults(W, H);
        td_join_stats st;
        td_lines *ls = td_lines_new(NULL);
        size_t i, contours = 0, on_road = 0;
        double y0;
        if (crossed) {
            add_hline(ls, 20, 280, 60);
            add_hline(ls, 20, 280, 100);
            add_hline(ls, 20, 280, 140);
        }
        for (y0 = 22; y0 < 180; y0 += 40) {
            td_line *l = td_lines_add(ls, NULL);
            double y;
            for (y = y0; y <= y0 + 36; y++)
                td_line_push(l, 150 + (y - 100) * 0.05, y, NULL);
        }
        TT_CHECK(td_join(&ls, &p, &st, NULL) == 0);
        for (i = 0; i < ls->n; i++) {
            const td_line *l = &ls->v[i];
            if (l->xy[1] == l->xy[2 * l->n - 1] && td_line_length(l) > 250)
                contours++;
            else if (fabs(l->xy[0] - 150) < 4)
                on_road++;
        }
        if (crossed)
            TT_CHECKF(st.road_pieces == 4 && contours == 3 && on_road == 0,
                      "crossed: %zu road pieces removed, %zu whole contours, "
                      "%zu lines on the road",
                      st.road_pieces, contours, on_road);
        else
            TT_CHECKF(st.road_pieces == 0 && on_road >= 1,
                      "empty gaps: %zu removed, %zu lines left on the road",
                      st.road_pieces, on_road);
        td_join_stats_free(&st);
        td_lines_free(ls);
    }
}

/* A faded contour printed in dashes: short straight pieces 20 px apart
 * (too far for the small-gap stage) are contour, not text: they stay and
 * the label-gap stage joins them; the "1" of a label, as straight, goes
 * with the curled "2" beside it. */
static void test_faded_pieces(void)
{
    td_join_params p = td_join_defaults(W, H);
    td_join_stats st;
    td_lines *ls = td_lines_new(NULL);
    const double two[] = {157, 73, 163, 73, 163, 80, 157, 80, 157, 87,
                          163, 87};
    const double one[] = {150, 73, 150, 87};
    double x;
    size_t i, kept = 0;
    for (x = 20; x + 18 <= 280; x += 38) /* 18-px pieces, 20-px gaps */
        add_hline(ls, x, x + 18, 140);
    add_line(ls, two, 6, 0);
    add_line(ls, one, 2, 0);
    TT_CHECK(td_join(&ls, &p, &st, NULL) == 0);
    for (i = 0; i < ls->n; i++)
        if (ls->v[i].xy[1] == 140)
            kept += (size_t)td_line_length(&ls->v[i]);
    /* kept, and joined across the gaps into one line (stage 2) */
    TT_CHECKF(kept >= 240 && ls->n == 1 && st.fragments == 2,
              "%zu px of the faded line kept, %zu lines, %zu fragments "
              "removed",
              kept, ls->n, st.fragments);
    td_join_stats_free(&st);
    td_lines_free(ls);
    /* the rule off: every short piece goes */
    ls = td_lines_new(NULL);
    for (x = 20; x + 18 <= 280; x += 38)
        add_hline(ls, x, x + 18, 140);
    p.straight_keep = 0;
    TT_CHECK(td_join(&ls, &p, &st, NULL) == 0);
    TT_CHECKF(ls->n == 0, "%zu lines", ls->n);
    td_join_stats_free(&st);
    td_lines_free(ls);
}

/* A contour broken four times in a row where its ink faded on a winding
 * stretch (bench_heights' printed Elkhorn 20 sheet): three short curved
 * pieces (a 6-px bump each, under min_length, too bent for straight_keep)
 * between two long lines, 3-px breaks.  Each piece pairs only with its
 * neighbours, yet the chain runs from one long line's end to the
 * other's: the pieces stay and the line comes out whole.  With the rule
 * off (chains 0) they went as text and the line stayed in two. */
static void test_broken_chain(void)
{
    int chains;
    for (chains = 1; chains >= 0; chains--) {
        td_join_params p = td_join_defaults(W, H);
        td_join_stats st;
        td_lines *ls = td_lines_new(NULL);
        double x0;
        p.chains = chains;
        add_hline(ls, 20, 100, 100);
        for (x0 = 103; x0 < 150; x0 += 17) { /* 14-px bumps, 3-px breaks */
            td_line *l = td_lines_add(ls, NULL);
            double x;
            for (x = x0; x <= x0 + 14; x += 0.5)
                td_line_push(l, x, 100 - 3 * (1 - cos(M_PI * (x - x0) / 7)),
                             NULL);
        }
        add_hline(ls, 154, 260, 100);
        TT_CHECK(td_join(&ls, &p, &st, NULL) == 0);
        if (chains)
            TT_CHECKF(ls->n == 1 && st.fragments == 0,
                      "chains: %zu lines, %zu fragments removed", ls->n,
                      st.fragments);
        else
            TT_CHECKF(st.fragments == 3, "no chains: %zu fragments removed",
                      st.fragments);
        td_join_stats_free(&st);
        td_lines_free(ls);
    }
}

/* A line broken at a skeleton junction where a small loop hangs (the
 * traced pieces of bench_heights' scanned Elkhorn 20 sheet at 1582,200,
 * moved): the west line's end, a 22-px piece on to the east line and the
 * loop's two ends all at the junction.  The loop pairs with the west
 * line's end and with the piece, whose other end continues the east
 * line; but ends at junctions do not chain: the loop goes, as before, and
 * the line comes out whole (with the loop kept it took the west line's
 * join and the line stayed in two, the region beyond one interval off). */
static void test_chain_not_at_junction(void)
{
    const double piece[] = {166.5, 91.5, 165.5, 91.5, 164.5, 90.5, 163.5, 89.5,
                            162.5, 89.5, 161.5, 88.5, 160.5, 88.5, 159.5, 88.5,
                            158.5, 88.5, 157.5, 89.5, 156.5, 89.5, 155.5, 90.5,
                            154.5, 91.5, 153.5, 92.5, 152.5, 93.5, 151.5, 94.5,
                            151.5, 95.5, 150.5, 96.5, 151.5, 97.5};
    const double loop[] = {
        152.5, 101.5, 153.5, 102.5, 154.5, 102.5, 155.5, 101.5, 156.5, 101.5,
        157.5, 100.5, 158.5, 99.5,  158.5, 98.5,  158.5, 97.5,  158.5, 96.5,
        157.5, 95.5,  156.5, 95.5,  155.5, 96.5,  154.5, 97.5,  153.5, 98.5};
    const double west[] = {
        128.5, 105.5, 129.5, 104.5, 130.5, 104.5, 131.5, 104.5, 132.5, 104.5,
        133.5, 104.5, 134.5, 103.5, 135.5, 103.5, 136.5, 103.5, 137.5, 103.5,
        138.5, 103.5, 139.5, 103.5, 140.5, 103.5, 141.5, 102.5, 142.5, 102.5,
        143.5, 101.5, 144.5, 101.5, 145.5, 101.5, 146.5, 101.5, 147.5, 100.5,
        148.5, 100.5, 149.5, 100.5, 150.5, 100.5};
    td_join_params p = td_join_defaults(W, H);
    td_join_stats st;
    td_lines *ls = td_lines_new(NULL);
    td_line *l = td_lines_add(ls, NULL);
    size_t k;
    for (k = 30; k < 128; k++) /* the west line, straight, then as traced */
        td_line_push(l, k + 0.5, 105.5, NULL);
    for (k = 0; k < sizeof west / sizeof *west / 2; k++)
        td_line_push(l, west[2 * k], west[2 * k + 1], NULL);
    l->junc = 2;
    add_line(ls, piece, sizeof piece / sizeof *piece / 2, 0);
    ls->v[1].junc = 2;
    add_line(ls, loop, sizeof loop / sizeof *loop / 2, 0);
    ls->v[2].junc = 3;
    add_hline(ls, 169.5, 280.5, 91.5);
    TT_CHECK(td_join(&ls, &p, &st, NULL) == 0);
    TT_CHECKF(ls->n == 1 && td_line_length(&ls->v[0]) > 180,
              "%zu lines, %zu fragments removed, first %g px", ls->n,
              st.fragments, ls->n ? td_line_length(&ls->v[0]) : 0.0);
    td_join_stats_free(&st);
    td_lines_free(ls);
}

/* A 14-px bump (too bent for straight_keep: a digit could curl so)
 * from x0 along y. */
static td_line *add_bump(td_lines *ls, double x0, double y)
{
    td_line *l = td_lines_add(ls, NULL);
    double x;
    for (x = x0; x <= x0 + 14; x += 0.5)
        td_line_push(l, x, y - 3 * (1 - cos(M_PI * (x - x0) / 7)), NULL);
    return l;
}

/* keep_pieces (ours, off by default): short pieces the text filter takes
 * on faded sheets, 448 of whose 463 lie on contours on the printed
 * Front Range 25 sheet (docs/scanner.md, "Pieces the text filter
 * takes").  A bent 14-px piece 3 px beyond a long line's end, its other
 * end free (the line faded there), goes by default and stays with
 * TD_PIECES_JOINED (joined on) or TD_PIECES_LATE (set aside in st.late,
 * unjoined and marked td_line.piece, the long line as without it, for
 * td_scan to put back after its cuts), unless half of it lies on another
 * ink (a road's dash whose end meets a contour's).  A piece traced from
 * faded ridges (td_line.pale) with nothing near stays.  (A pinched finger:
 * test_scan.c, test_short_pinch.  The third rule, junction pieces from
 * 10 px, is measured on bench_scanreal's "keep pcs" rows.) */
static void test_keep_pieces(void)
{
    static uint8_t bits[(W + 7) / 8 * H + 1];
    int keep, road;
    for (keep = 0; keep < 3; keep++)
        for (road = 0; road < 2; road++) {
            td_join_params p = td_join_defaults(W, H);
            td_join_stats st;
            td_lines *ls = td_lines_new(NULL);
            int kept, aside;
            p.keep_pieces = keep;
            add_hline(ls, 20, 100, 100);
            add_bump(ls, 103, 100);
            other_box(bits, 101, 119, 92, 102);
            p.other = road ? bits : NULL;
            TT_CHECK(td_join(&ls, &p, &st, NULL) == 0);
            kept = ls->n == 1 && td_line_length(&ls->v[0]) > 95;
            aside = st.late && st.late->n == 1 && st.late->v[0].piece &&
                    td_line_length(&st.late->v[0]) > 14;
            TT_CHECKF(kept == (keep == TD_PIECES_JOINED && !road) &&
                          ls->n == 1 && !ls->v[0].piece &&
                          aside == (keep == TD_PIECES_LATE && !road),
                      "keep %d road %d: %zu lines, first %g px, %zu "
                      "fragments, %zu set aside",
                      keep, road, ls->n,
                      ls->n ? td_line_length(&ls->v[0]) : 0.0, st.fragments,
                      st.late_pieces);
            td_join_stats_free(&st);
            td_lines_free(ls);
        }
    for (keep = 0; keep < 3; keep++) { /* a faded ridge's piece */
        td_join_params p = td_join_defaults(W, H);
        td_join_stats st;
        td_lines *ls = td_lines_new(NULL);
        p.keep_pieces = keep;
        add_hline(ls, 20, 100, 40);
        add_bump(ls, 150, 140)->pale = 1;
        TT_CHECK(td_join(&ls, &p, &st, NULL) == 0);
        TT_CHECKF(ls->n == (size_t)(1 + (keep == TD_PIECES_JOINED)) &&
                      (keep != TD_PIECES_LATE ||
                       (st.late && st.late->n == 1 && st.late->v[0].piece)),
                  "keep %d: pale piece, %zu lines", keep, ls->n);
        td_join_stats_free(&st);
        td_lines_free(ls);
    }
}

/* Number of proper crossings between segment ab and the lines. */
static int seg_crossings(const double *a, const double *b, const td_lines *ls)
{
    size_t i, k;
    int n = 0;
    for (i = 0; i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        size_t nseg = l->n < 2 ? 0 : l->closed ? l->n : l->n - 1;
        for (k = 0; k < nseg; k++) {
            const double *c = l->xy + 2 * k, *d = l->xy + 2 * ((k + 1) % l->n);
            double o1 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            double o2 = (b[0] - a[0]) * (d[1] - a[1]) - (b[1] - a[1]) * (d[0] - a[0]);
            double o3 = (d[0] - c[0]) * (a[1] - c[1]) - (d[1] - c[1]) * (a[0] - c[0]);
            double o4 = (d[0] - c[0]) * (b[1] - c[1]) - (d[1] - c[1]) * (b[0] - c[0]);
            n += o1 * o2 < 0 && o3 * o4 < 0;
        }
    }
    return n;
}

/* Number of proper crossings between the pieces of join path s and the
 * lines. */
static int crossings(const td_line *s, const td_lines *ls)
{
    size_t j;
    int n = 0;
    for (j = 0; j + 1 < s->n; j++)
        n += seg_crossings(s->xy + 2 * j, s->xy + 2 * j + 2, ls);
    return n;
}

/* Two contours 8 px apart cut by a 10-px road, each end bent towards the
 * other contour's end across it (the ink's blur at the cut): the two
 * cheapest small-gap joins would cross, an X of two lines each carrying
 * two heights.  Contours never cross, and neither do joins: the second
 * is refused, and no two lines cross.  (The ends lie 4 px apart, under
 * half the gap: the near-end rule, gap_near, would leave all four open;
 * it is off here so that the crossing check is what is tested.) */
static void test_joins_never_cross(void)
{
    td_join_params p = td_join_defaults(W, H);
    td_join_stats st;
    td_lines *ls = td_lines_new(NULL);
    const double a[] = {40, 90, 84, 90, 92, 96, 100, 102};
    const double b[] = {40, 118, 84, 118, 92, 112, 100, 106};
    const double c[] = {110, 102, 118, 96, 126, 90, 170, 90};
    const double d[] = {110, 106, 118, 112, 126, 118, 170, 118};
    size_t i;
    int n = 0;
    add_line(ls, a, 4, 0);
    add_line(ls, b, 4, 0);
    add_line(ls, c, 4, 0);
    add_line(ls, d, 4, 0);
    p.gap_near = 0;
    TT_CHECK(td_join(&ls, &p, &st, NULL) == 0);
    for (i = 0; i < ls->n; i++)
        n += crossings(&ls->v[i], ls);
    TT_CHECKF(n == 0 && st.joins >= 1, "%d crossings, %zu joins, %zu lines", n,
              st.joins, ls->n);
    td_join_stats_free(&st);
    td_lines_free(ls);
}

/* Scan a labelled sheet with and without the label-gap stage. */
static void labelled_sheet(unsigned seed, int w, int h, double lw,
                           double noise, int breaks)
{
    td_gen_params gp = td_gen_defaults();
    td_scan_params sp = td_scan_defaults();
    td_image *im = NULL;
    td_lines *truth = NULL;
    td_scan_result res;
    td_match_report r;
    td_ctx cx;
    size_t j;
    int bad = 0;
    td_ctx_init(&cx);
    gp.w = w, gp.h = h, gp.seed = seed, gp.line_width = lw, gp.labels = 3;
    gp.noise = noise, gp.blur = noise > 0 ? 0.7 : 0, gp.breaks = breaks;
    gp.break_max = 4;
    TT_CHECK(td_gen_sheet(&gp, &im, &truth, NULL, &cx) == 0);
    if (!im)
        return;
    sp.join.record = 1;
    TT_CHECK(td_scan(im, &sp, &res, &cx) == 0);
    TT_CHECK(td_match_lines(truth, res.lines, w, h, NULL, &r, stderr) == 0);
    TT_CHECKF(td_match_ok(&r) && r.n_split == 0 && r.n_mixed == 0,
              "seed %u: %ld of %ld matched, %ld split, %ld mixed", seed,
              r.n_matched, r.n_truth, r.n_split, r.n_mixed);
    TT_CHECKF(res.join.long_joins >= 2 && res.join.ends_open == 0,
              "seed %u: %zu label joins, %zu open ends", seed,
              res.join.long_joins, res.join.ends_open);
    for (j = 0; res.join.segments && j < res.join.segments->n; j++)
        bad += crossings(&res.join.segments->v[j], res.lines) > 0;
    TT_CHECKF(bad == 0, "seed %u: %d joins cross a line", seed, bad);
    td_scan_result_free(&res);

    sp.join.long_gap = 0; /* without stage 2 the labels leave lines cut */
    TT_CHECK(td_scan(im, &sp, &res, &cx) == 0);
    TT_CHECK(td_match_lines(truth, res.lines, w, h, NULL, &r, NULL) == 0);
    TT_CHECKF(r.n_split > 0 || r.n_matched < r.n_truth,
              "seed %u: labels cut nothing", seed);
    td_scan_result_free(&res);
    td_lines_free(truth);
    td_image_free(im);
}

static void test_labelled_sheets(void)
{
    labelled_sheet(1, 1000, 800, 2.5, 0, 0);
    labelled_sheet(2, 1000, 800, 2.0, 0, 0);
    labelled_sheet(3, 1000, 800, 3.0, 0, 0);
}

static void test_labelled_noisy(void)
{
    labelled_sheet(11, 1200, 1000, 3.0, 8, 15);
    labelled_sheet(13, 1200, 1000, 3.0, 8, 15);
}

/* Scan a sheet; joins and whole contours summed into *whole, *joins. */
static void scan_count(const td_gen_params *gp, int curves, long *whole,
                       long *total, size_t *joins, size_t *false_joins)
{
    td_scan_params sp = td_scan_defaults();
    td_image *im = NULL;
    td_lines *truth = NULL;
    td_scan_result res;
    td_match_report r;
    size_t j;
    sp.join.record = 1, sp.join.curves = curves;
    TT_CHECK(td_gen_sheet(gp, &im, &truth, NULL, NULL) == 0);
    TT_CHECK(im && td_scan(im, &sp, &res, NULL) == 0);
    if (!im)
        return;
    TT_CHECK(td_match_lines(truth, res.lines, gp->w, gp->h, NULL, &r, NULL) == 0);
    *whole += r.n_matched, *total += r.n_truth;
    *joins += res.join.long_joins;
    for (j = 0; res.join.segments && j < res.join.segments->n; j++) {
        const td_line *s = &res.join.segments->v[j]; /* ends on one contour */
        size_t i, ia = 0, ib = 0;
        double da = 1e9, db = 1e9;
        for (i = 0; i < truth->n; i++) {
            double a = td_contain_dist(&truth->v[i], s->xy[0], s->xy[1]);
            double b = td_contain_dist(&truth->v[i], s->xy[2 * s->n - 2],
                                       s->xy[2 * s->n - 1]);
            if (a < da)
                da = a, ia = i;
            if (b < db)
                db = b, ib = i;
        }
        *false_joins += ia != ib || da > 3 || db > 3;
        TT_CHECK(crossings(s, res.lines) == 0);
    }
    TT_CHECK(r.n_mixed == 0);
    td_scan_result_free(&res);
    td_lines_free(truth);
    td_image_free(im);
}

/* Labels on curved stretches (within 15 px of their chord) and breaks of
 * 20-60 px anywhere: the curve rule joins more (docs/scanner.md has the
 * numbers) and no join links two contours or crosses a line. */
static void test_curved_sheets(void)
{
    td_gen_params gp = td_gen_defaults();
    long whole[2] = {0, 0}, total = 0;
    size_t joins[2] = {0, 0}, bad = 0, c;
    unsigned seed;
    for (c = 0; c < 2; c++)
        for (seed = 1; seed <= 5; seed++) {
            gp = td_gen_defaults();
            gp.w = 1000, gp.h = 800, gp.seed = seed, gp.line_width = 2.5;
            gp.labels = 3, gp.label_bend = 15;
            scan_count(&gp, (int)c, &whole[c], &total, &joins[c], &bad);
        }
    TT_CHECKF(whole[1] >= 138 && total == 2 * 142 && whole[0] <= 132 &&
              joins[1] >= joins[0] + 10, "labels: %ld / %ld whole with "
              "curves, %ld without; %zu / %zu joins", whole[1], total / 2,
              whole[0], joins[1], joins[0]);
    joins[0] = joins[1] = 0;
    for (c = 0; c < 2; c++)
        for (seed = 1; seed <= 3; seed++) {
            gp = td_gen_defaults();
            gp.seed = seed, gp.breaks = 20, gp.break_min = 20;
            gp.break_max = 60;
            scan_count(&gp, (int)c, &whole[c], &total, &joins[c], &bad);
        }
    TT_CHECKF(joins[1] >= 55 && joins[0] <= 48, "breaks: %zu of 60 joined "
              "with curves, %zu without", joins[1], joins[0]);
    TT_CHECKF(bad == 0, "%zu joins between two contours", bad);
}

/* The default sheet (labels off) is unchanged: no label drawn. */
static void test_labels_off(void)
{
    td_gen_params gp = td_gen_defaults();
    td_image *a = NULL, *b = NULL;
    td_lines *truth = NULL;
    size_t n = 1;
    gp.w = 400, gp.h = 300;
    TT_CHECK(gp.labels == 0);
    TT_CHECK(td_gen_sheet(&gp, &a, &truth, NULL, NULL) == 0);
    TT_CHECK(td_gen_render(truth, &gp, &b, NULL) == 0);
    TT_CHECK(a && b && memcmp(a->data, b->data, (size_t)400 * 300) == 0);
    TT_CHECK(b && td_gen_labels(truth, &gp, 20, b, &n, NULL) == 0 && n == 0);
    td_image_free(a);
    td_image_free(b);
    td_lines_free(truth);
}

int main(void)
{
    TT_RUN(test_crossing_rejected);
    TT_RUN(test_shift_and_bend);
    TT_RUN(test_curved_gap);
    TT_RUN(test_water_turn);
    TT_RUN(test_label_gap);
    TT_RUN(test_gaps_side_by_side);
    TT_RUN(test_sidestep_left_open);
    TT_RUN(test_near_end_left_open);
    TT_RUN(test_near_end_over_water);
    TT_RUN(test_alone_gap);
    TT_RUN(test_gap_under_other_ink);
    TT_RUN(test_short_piece_kept);
    TT_RUN(test_hook_kept);
    TT_RUN(test_curl_kept);
    TT_RUN(test_road_chain);
    TT_RUN(test_faded_pieces);
    TT_RUN(test_broken_chain);
    TT_RUN(test_chain_not_at_junction);
    TT_RUN(test_keep_pieces);
    TT_RUN(test_joins_never_cross);
    TT_RUN(test_labels_off);
    TT_RUN(test_labelled_sheets);
    TT_RUN(test_labelled_noisy);
    TT_RUN(test_curved_sheets);
    return tt_summary();
}
