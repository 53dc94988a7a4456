/* Tests of the cut of short lines in another ink (scanner/foreign.c):
 * lines drawn in colours over a cream sheet whose palette knows only the
 * paper and the contour brown, as a printed map's palette misses a little
 * black text and a faded red road. */
#include "tests/tt.h"

#include "scanner/foreign.h"

#include <stdlib.h>
#include <string.h>

#define W 300
#define H 120

static const uint8_t PAPER[3] = {238, 226, 194}, BROWN[3] = {155, 92, 48},
                     GREY[3] = {120, 112, 100}, PINK[3] = {200, 110, 110};

static td_palette palette(void)
{
    td_palette p;
    memset(&p, 0, sizeof p);
    p.n = 2, p.paper = 0, p.chosen = 1;
    memcpy(p.ink[0].rgb, PAPER, 3), p.ink[0].role = TD_INKROLE_PAPER;
    memcpy(p.ink[1].rgb, BROWN, 3), p.ink[1].role = TD_INKROLE_INK;
    return p;
}

/* A stroke 3 px wide in colour c, its two edge rows (columns) half mixed
 * with the paper, and its traced line: horizontal at row `at` from
 * column a0 to a1, or (vertical) at column `at` from row a0 to a1. */
static void stroke_dir(td_image *im, td_lines *ls, int vertical, int at, int a0,
                       int a1, const uint8_t *c)
{
    td_line *l = td_lines_add(ls, NULL);
    int t, d, k;
    for (t = a0; t <= a1; t++) {
        int x = vertical ? at : t, y = vertical ? t : at;
        for (d = -1; d <= 1; d++) {
            uint8_t *p = im->data +
                         (size_t)(y + (vertical ? 0 : d)) * im->stride +
                         3 * (size_t)(x + (vertical ? d : 0));
            for (k = 0; k < 3; k++)
                p[k] = d ? (uint8_t)((c[k] + PAPER[k]) / 2) : c[k];
        }
        TT_CHECK(l && td_line_push(l, x, y, NULL) == 0);
    }
}

static void stroke(td_image *im, td_lines *ls, int y, int x0, int x1,
                   const uint8_t *c)
{
    stroke_dir(im, ls, 0, y, x0, x1, c);
}

static void vstroke(td_image *im, td_lines *ls, int x, int y0, int y1,
                    const uint8_t *c)
{
    stroke_dir(im, ls, 1, x, y0, y1, c);
}

static td_image *sheet(void)
{
    td_image *im = td_image_new(W, H, 3, NULL);
    int i;
    TT_CHECK(im != NULL);
    for (i = 0; im && i < W * H; i++)
        memcpy(im->data + 3 * (size_t)i, PAPER, 3);
    return im;
}

/* Grey and pink short lines go, and a grey one along another ink's
 * strokes (a road's flank); a brown one, a long grey one and a grey one
 * crossing the other ink (a contour's stretch across a road takes the
 * road's colour) stay. */
static void test_foreign_cut(void)
{
    td_image *im = sheet();
    td_lines *ls = td_lines_new(NULL);
    td_palette pal = palette();
    size_t stride = (W + 7) / 8;
    uint8_t *other = calloc(stride * H, 1);
    long n;
    int x;
    TT_CHECK(im && ls && other);
    if (!im || !ls || !other)
        return;
    stroke(im, ls, 10, 20, 100, BROWN);  /* 0: kept */
    stroke(im, ls, 25, 20, 100, GREY);   /* 1: text, dropped */
    stroke(im, ls, 40, 20, 100, PINK);   /* 2: a road's dash, dropped */
    stroke(im, ls, 55, 20, 290, GREY);   /* 3: long, kept */
    stroke(im, ls, 70, 20, 100, GREY);   /* 4: along the road, dropped */
    vstroke(im, ls, 196, 60, 110, GREY); /* 5: across it, kept */
    for (x = 20; x <= 240; x += 8)       /* the other ink's map: patches */
        other[72 * stride + (x >> 3)] |= (uint8_t)(1u << (x & 7));
    TT_CHECK(td_foreign_residual(im, &pal, &ls->v[0]) < 5);
    TT_CHECK(td_foreign_residual(im, &pal, &ls->v[1]) > TD_FOREIGN_RES);
    TT_CHECK(td_foreign_residual(im, &pal, &ls->v[2]) > TD_FOREIGN_RES);
    TT_CHECK(td_foreign_residual(im, &pal, &ls->v[5]) > TD_FOREIGN_RES);
    n = td_foreign_cut(ls, im, &pal, other, NULL);
    TT_CHECKF(n == 3 && ls->n == 3, "%ld dropped, %zu left", n, ls->n);
    TT_CHECK(ls->n == 3 && ls->v[0].id == 0 && ls->v[1].id == 3 &&
             ls->v[2].id == 5);
    /* grey sheets (no palette) and no lines: nothing to do */
    pal.chosen = -1;
    TT_CHECK(td_foreign_cut(ls, im, &pal, NULL, NULL) == 0 && ls->n == 3);
    free(other);
    td_lines_free(ls);
    td_image_free(im);
}

int main(void)
{
    TT_RUN(test_foreign_cut);
    return tt_summary();
}
