/* Tests of the cut along other inks (scanner/flank.c): traced lines over a
 * map of another ink's strokes (a road), as td_binarise_other_ink gives
 * it. */
#include "tests/tt.h"

#include "scanner/flank.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define W 120
#define H 100
#define STRIDE ((W + 7) / 8)

static void put(uint8_t *b, int x, int y)
{
    if (x >= 0 && y >= 0 && x < W && y < H)
        b[y * STRIDE + (x >> 3)] |= (uint8_t)(1u << (x & 7));
}

/* An empty map of the other ink (W x H) and no lines; 0 (checked) when
 * either cannot be had. */
static int fixture(uint8_t **b, td_lines **ls)
{
    *b = calloc(STRIDE * H, 1);
    *ls = td_lines_new(NULL);
    TT_CHECK(*b && *ls);
    return *b && *ls;
}

/* A road along y = 50 from x0 to x1, 2 px wide; dash > 0: on for dash px,
 * off for 2 dash (the patchy map of a thin road's 2 x 2 blocks). */
static void road(uint8_t *b, int x0, int x1, int dash)
{
    int x;
    for (x = x0; x <= x1; x++)
        if (dash == 0 || (x - x0) % (3 * dash) < dash)
            put(b, x, 50), put(b, x, 51);
}

static td_line *line(td_lines *ls, double x0, double y0, double x1, double y1,
                     int steps)
{
    td_line *l = td_lines_add(ls, NULL);
    int k;
    TT_CHECK(l != NULL);
    for (k = 0; l && k <= steps; k++)
        TT_CHECK(td_line_push(l, x0 + (x1 - x0) * k / steps,
                              y0 + (y1 - y0) * k / steps, NULL) == 0);
    return l;
}

/* The x extent of line l. */
static void xrange(const td_line *l, double *lo, double *hi)
{
    size_t k;
    *lo = HUGE_VAL, *hi = -HUGE_VAL;
    for (k = 0; k < l->n; k++)
        *lo = fmin(*lo, l->xy[2 * k]), *hi = fmax(*hi, l->xy[2 * k]);
}

/* A line traced along the road's flank (1 px off it) for 40 px: that
 * stretch goes, the two ends off the road stay as two lines. */
static void test_flank_cut(void)
{
    uint8_t *b;
    td_lines *ls;
    double lo, hi;
    if (!fixture(&b, &ls))
        goto done;
    road(b, 40, 80, 0);
    line(ls, 10, 49, 110, 49, 100)->junc = 3;
    TT_CHECK(td_flank_cut(ls, b, W, H, NULL) == 1);
    TT_CHECKF(ls->n == 2, "%zu pieces", ls->n);
    if (ls->n == 2) {
        xrange(&ls->v[0], &lo, &hi);
        TT_CHECKF(lo == 10 && hi >= 35 && hi < 40, "first piece %g..%g", lo,
                  hi);
        TT_CHECK(ls->v[0].junc == 1); /* its own first end only */
        xrange(&ls->v[1], &lo, &hi);
        TT_CHECKF(hi == 110 && lo > 80 && lo <= 85, "second piece %g..%g", lo,
                  hi);
        TT_CHECK(ls->v[1].junc == 2);
    }
done:
    td_lines_free(ls);
    free(b);
}

/* A contour crossing the road keeps all of it (the joiner bridges the
 * road); so does a line 4 px off the road, beside it. */
static void test_crossing_kept(void)
{
    uint8_t *b;
    td_lines *ls;
    if (!fixture(&b, &ls))
        goto done;
    road(b, 0, W - 1, 0);
    line(ls, 60, 5, 60, 95, 90);
    line(ls, 70, 20, 75, 80, 60); /* crosses at a slant */
    line(ls, 0, 46, 119, 46, 119);
    line(ls, 0, 55, 119, 55, 119);
    TT_CHECK(td_flank_cut(ls, b, W, H, NULL) == 0);
    TT_CHECKF(ls->n == 4 && ls->v[0].n == 91 && ls->v[1].n == 61 &&
                  ls->v[2].n == 120 && ls->v[3].n == 120,
              "%zu lines", ls->n);
done:
    td_lines_free(ls);
    free(b);
}

/* A contour broken by the road whose end hooks along the road's flank for
 * 6 px: the hook goes, the line ends heading at the road (else the joiner
 * pairs the hook's tip, heading along the road, with the next contour's
 * end: a line on the ridges print ran from one contour onto the next so);
 * a line ending at the road's edge, and one ending at a slant, keep every
 * point. */
static void test_hook_trimmed(void)
{
    uint8_t *b;
    td_lines *ls;
    td_line *l;
    int k;
    if (!fixture(&b, &ls))
        goto done;
    road(b, 0, W - 1, 0);
    l = line(ls, 60, 5, 60, 46, 41);
    for (k = 1; l && k <= 6; k++) /* the hook, 2 px off the road */
        TT_CHECK(td_line_push(l, 60 + k, 48, NULL) == 0);
    line(ls, 30, 95, 30, 53, 42);
    line(ls, 90, 95, 80, 53, 42);
    TT_CHECK(td_flank_cut(ls, b, W, H, NULL) == 1);
    TT_CHECKF(ls->n == 3, "%zu lines", ls->n);
    if (ls->n == 3) {
        const td_line *h = &ls->v[0];
        double ex = h->xy[2 * h->n - 2], ey = h->xy[2 * h->n - 1];
        TT_CHECKF(ex == 60 && ey < 48, "the hooked line ends at %g,%g", ex, ey);
        TT_CHECK(ls->v[1].n == 43 && ls->v[2].n == 43);
    }
done:
    td_lines_free(ls);
    free(b);
}

/* The hook of the ridges print at 1233,746 (a contour crossing a road top
 * to bottom, its right piece's tip turned up the road's flank): the other
 * ink's map has a gap where the contour crosses, so only the tip's first
 * 3 px lie beside the road and the corner, 2.8 px further on, does not.
 * The hook still goes, up to its corner; a piece that comes to the road
 * square, at the same place, keeps every point, and so does an end that
 * turns off another stroke (a stream, y = 90) across it instead of along
 * it (Orkhon new print, 910,992: the joiner took the bend's loss for a
 * free end and joined it to the next contour). */
static void test_hook_past_the_gap(void)
{
    static const double hook[][2] = {{63, 40}, {63, 41}, {63, 42}, {63, 43},
                                     {64, 44}, {65, 45}, {66, 46}};
    uint8_t *b;
    td_lines *ls;
    td_line *l;
    int k;
    if (!fixture(&b, &ls))
        goto done;
    for (k = 0; k < H; k++) /* the road down x = 60..61, its map cut at the
                               crossing */
        if (k < 42 || k >= 50)
            put(b, 60, k), put(b, 61, k);
    l = td_lines_add(ls, NULL);
    TT_CHECK(l != NULL);
    for (k = 0; l && k < 7; k++)
        TT_CHECK(td_line_push(l, hook[k][0], hook[k][1], NULL) == 0);
    for (k = 67; l && k <= 110; k++)
        TT_CHECK(td_line_push(l, k, 46, NULL) == 0);
    line(ls, 64, 60, 110, 60, 46); /* square to the road */
    for (k = 0; k <= 40; k++)      /* the stream */
        put(b, k, 90), put(b, k, 91);
    l = line(ls, 20, 88, 21, 88, 1); /* beside it, then off across it */
    for (k = 87; l && k >= 85; k--)
        TT_CHECK(td_line_push(l, 21, k, NULL) == 0);
    for (k = 22; l && k <= 30; k++)
        TT_CHECK(td_line_push(l, k, 85, NULL) == 0);
    TT_CHECK(td_flank_cut(ls, b, W, H, NULL) == 1);
    TT_CHECKF(ls->n == 3, "%zu lines", ls->n);
    if (ls->n == 3) {
        TT_CHECKF(ls->v[0].xy[0] >= 64 && ls->v[0].xy[1] >= 44 &&
                      ls->v[0].xy[2 * ls->v[0].n - 2] == 110,
                  "the hooked piece starts at %g,%g", ls->v[0].xy[0],
                  ls->v[0].xy[1]);
        TT_CHECK(ls->v[1].n == 47 && ls->v[1].xy[0] == 64);
        TT_CHECKF(ls->v[2].n == 14 && ls->v[2].xy[0] == 20,
                  "the end off the stream: %zu points from %g", ls->v[2].n,
                  ls->v[2].xy[0]);
    }
done:
    td_lines_free(ls);
    free(b);
}

/* A dashed map of the road (the 2 x 2 blocks of a thin road come and go)
 * still cuts the flank; a ring with a side along the road opens there. */
static void test_patchy_and_ring(void)
{
    uint8_t *b;
    td_lines *ls;
    td_line *r;
    double lo, hi;
    int k;
    if (!fixture(&b, &ls))
        goto done;
    road(b, 20, 100, 3);
    r = td_lines_add(ls, NULL);
    TT_CHECK(r != NULL);
    /* a rectangle 30..90 x 49..80, its top side along the road */
    for (k = 30; r && k < 90; k++)
        td_line_push(r, k, 49, NULL);
    for (k = 49; r && k < 80; k++)
        td_line_push(r, 90, k, NULL);
    for (k = 90; r && k > 30; k--)
        td_line_push(r, k, 80, NULL);
    for (k = 80; r && k > 49; k--)
        td_line_push(r, 30, k, NULL);
    if (r)
        r->closed = 1;
    TT_CHECK(td_flank_cut(ls, b, W, H, NULL) == 1);
    TT_CHECKF(ls->n == 1 && !ls->v[0].closed, "%zu lines, closed %d", ls->n,
              ls->n ? ls->v[0].closed : -1);
    if (ls->n == 1) {
        xrange(&ls->v[0], &lo, &hi);
        TT_CHECK(lo == 30 && hi == 90);
        /* its ends are the rectangle's corners' side of the road */
        TT_CHECKF(ls->v[0].xy[1] >= 52 && ls->v[0].xy[2 * ls->v[0].n - 1] >= 52,
                  "ends at y %g, %g", ls->v[0].xy[1],
                  ls->v[0].xy[2 * ls->v[0].n - 1]);
    }
    TT_CHECK(td_flank_cut(ls, NULL, W, H, NULL) == 0);
done:
    td_lines_free(ls);
    free(b);
}

int main(void)
{
    TT_RUN(test_flank_cut);
    TT_RUN(test_crossing_kept);
    TT_RUN(test_hook_trimmed);
    TT_RUN(test_hook_past_the_gap);
    TT_RUN(test_patchy_and_ring);
    return tt_summary();
}
