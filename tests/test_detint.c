/* Tests of the tint division (scanner/detint.c): cream paper with a green
 * woodland tint in its north-east, brown contours across it and the paper,
 * and red roads, one down the tint, printed as filters (each ink multiplies the
 * light) and blurred as a scanner does, so that the road's blurred edges
 * over the green look like brown. */
#include "tests/tt.h"

#include "scanner/detint.h"
#include "scanner/palette.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const double CREAM[3] = {245, 235, 210}, GREEN[3] = {200, 228, 175},
                    BROWN[3] = {160, 90, 40}, RED[3] = {205, 50, 40};

#define W 240
#define H 200

/* Coverage of a line of half-width hw at distance d (1 px anti-aliased). */
static double cover(double d, double hw)
{
    double a = hw + 0.5 - fabs(d);
    return a < 0 ? 0 : a > 1 ? 1 : a;
}

/* The sheet, blurred over 3 x 3 px as scanned. */
static td_image *sheet(void)
{
    td_image *im = td_image_new(W, H, 3, NULL);
    double *v = malloc((size_t)W * H * 3 * sizeof *v);
    int x, y, c, dx, dy;
    if (!im || !v) {
        td_image_free(im);
        free(v);
        return NULL;
    }
    for (y = 0; y < H; y++)
        for (x = 0; x < W; x++)
            for (c = 0; c < 3; c++) {
                double px = x + 0.5, py = y + 0.5, t = CREAM[c];
                double ag = px > 150 && py < 110 ? 1.0 : 0.0;
                /* five contours east-west; a road north-south at x = 195
                   (over the tint down to y = 110) and one east-west at
                   y = 180 */
                double ab = cover(py - 20, 0.9) + cover(py - 50, 0.9) +
                            cover(py - 80, 0.9) + cover(py - 120, 0.9) +
                            cover(py - 150, 0.9);
                double ar = cover(px - 195, 1.1) + cover(py - 180, 1.1);
                t *= 1.0 - ag * (1.0 - GREEN[c] / 255.0);
                t *= 1.0 - (ab > 1 ? 1 : ab) * (1.0 - BROWN[c] / 255.0);
                t *= 1.0 - (ar > 1 ? 1 : ar) * (1.0 - RED[c] / 255.0);
                v[((size_t)y * W + x) * 3 + c] = t;
            }
    for (y = 0; y < H; y++) /* the scanner's blur */
        for (x = 0; x < W; x++)
            for (c = 0; c < 3; c++) {
                double t = 0;
                int n = 0;
                for (dy = -1; dy <= 1; dy++)
                    for (dx = -1; dx <= 1; dx++)
                        if (x + dx >= 0 && x + dx < W && y + dy >= 0 &&
                            y + dy < H)
                            t += v[((size_t)(y + dy) * W + x + dx) * 3 + c],
                                n++;
                im->data[(size_t)y * im->stride + 3 * (size_t)x + c] =
                    (uint8_t)lrint(t / n);
            }
    free(v);
    return im;
}

static const uint8_t *px(const td_image *im, int x, int y)
{
    return im->data + (size_t)y * im->stride + 3 * (size_t)x;
}

/* The largest difference of one channel of (x0, y0) in a from (x1, y1)
 * in b. */
static int maxdiff(const td_image *a, int x0, int y0, const td_image *b, int x1,
                   int y1)
{
    int c, m = 0;
    for (c = 0; c < 3; c++) {
        int d = abs((int)px(a, x0, y0)[c] - (int)px(b, x1, y1)[c]);
        m = d > m ? d : m;
    }
    return m;
}

/* Divided: the tint's own pixels come out as the paper, the road and the
 * contours over the tint as they are over the paper (the same ink at the
 * same coverage), and the pixels on the paper are left as they were. */
static void test_divided(void)
{
    td_image *im = sheet(), *out = NULL;
    td_palette pal;
    int y, d;
    TT_CHECK(im != NULL);
    if (!im)
        return;
    TT_CHECK(td_palette_find(im, &pal, NULL) == 0);
    TT_CHECK(td_palette_choose(&pal, 1) >= 0);
    TT_CHECK(td_detint_any(&pal));
    out = td_image_new(W, H, 3, NULL);
    TT_CHECK(out && td_detint(im, &pal, TD_DETINT_RADIUS, out, NULL) == 0);
    if (!out) {
        td_image_free(im);
        return;
    }
    /* as scanned, the road over the tint is far from the road over the
       paper (what the palette sees: a darker, browner colour) */
    TT_CHECKF((d = maxdiff(im, 195, 65, im, 195, 135)) > 40, "%d", d);
    TT_CHECKF((d = maxdiff(out, 172, 65, im, 40, 65)) <= 6, "%d", d);
    for (y = 60; y < 75; y++) /* the road's middle over the tint */
        TT_CHECKF((d = maxdiff(out, 195, y, im, 195, 135)) <= 6, "%d", d);
    for (y = 47; y <= 53; y++) /* across a contour over the tint */
        TT_CHECKF((d = maxdiff(out, 172, y, im, 40, y)) <= 6, "%d", d);
    for (y = 40; y < 200; y += 7) /* the paper's side: untouched */
        TT_CHECK(maxdiff(out, 40, y, im, 40, y) == 0);
    td_image_free(out);
    td_image_free(im);
}

/* Bad arguments: a grey image, one image for both, a radius out of range. */
static void test_bad_args(void)
{
    td_image *im = sheet(), *g = td_image_new(W, H, 1, NULL),
             *out = td_image_new(W, H, 3, NULL);
    td_palette pal;
    TT_CHECK(im && g && out);
    if (im && g && out) {
        TT_CHECK(td_palette_find(im, &pal, NULL) == 0);
        TT_CHECK(td_detint(g, &pal, 3, out, NULL) == TD_EINVAL);
        TT_CHECK(td_detint(im, &pal, 3, im, NULL) == TD_EINVAL);
        TT_CHECK(td_detint(im, &pal, 0, out, NULL) == TD_EINVAL);
        TT_CHECK(td_detint(im, &pal, 9, out, NULL) == TD_EINVAL);
    }
    td_image_free(im);
    td_image_free(g);
    td_image_free(out);
}

int main(void)
{
    TT_RUN(test_divided);
    TT_RUN(test_bad_args);
    return tt_summary();
}
