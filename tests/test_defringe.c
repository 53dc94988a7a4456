/* Tests of the colour defringing (scanner/defringe.c): a brown line and a
 * red road printed on cream, the red and blue channels shifted a pixel
 * either way as a misregistered scanner gives them. */
#include "tests/tt.h"

#include "scanner/defringe.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const double CREAM[3] = {245, 235, 210}, BROWN[3] = {160, 90, 40},
                    RED[3] = {205, 50, 40};

/* Cream with a brown line (x = 60 + 0.1 y, 2 px) and a red road (x = 130,
 * 2.2 px), anti-aliased, printed as filters; channel c of the picture lies
 * shift[c] px to the right. */
static td_image *sheet(const double *shift)
{
    td_image *im = td_image_new(200, 120, 3, NULL);
    int x, y, c;
    if (!im)
        return NULL;
    for (y = 0; y < im->h; y++)
        for (x = 0; x < im->w; x++)
            for (c = 0; c < 3; c++) {
                double px = x + 0.5 - shift[c];
                double ab = 1.0 + 0.5 - fabs(px - (60 + 0.1 * y));
                double ar = 1.1 + 0.5 - fabs(px - 130);
                double v = CREAM[c];
                ab = ab < 0 ? 0 : ab > 1 ? 1 : ab;
                ar = ar < 0 ? 0 : ar > 1 ? 1 : ar;
                v *= 1.0 - ab * (1.0 - BROWN[c] / 255.0);
                v *= 1.0 - ar * (1.0 - RED[c] / 255.0);
                im->data[(size_t)y * im->stride + 3 * (size_t)x + c] =
                    (uint8_t)lrint(v);
            }
    return im;
}

/* How far pixel v lies from brown's mixtures with the cream (RGB levels:
 * the residual at the best coverage). */
static double off_brown(const uint8_t *v)
{
    double d[3], dd = 0, t = 0, r = 0;
    int c;
    for (c = 0; c < 3; c++) {
        d[c] = CREAM[c] * (1.0 - BROWN[c] / 255.0);
        dd += d[c] * d[c];
        t += (CREAM[c] - v[c]) * d[c];
    }
    t /= dd;
    for (c = 0; c < 3; c++)
        r += (v[c] - (CREAM[c] - t * d[c])) * (v[c] - (CREAM[c] - t * d[c]));
    return sqrt(r);
}

/* The worst pixel of the brown line (x 40..100, its rows 10..110) off
 * brown's mixtures, among those whose lightness is TD_DEFRINGE_MIN under
 * the cream's or more (lighter ones are left as they are). */
static double worst_off_brown(const td_image *im)
{
    double worst = 0;
    int x, y;
    for (y = 10; y < 110; y++)
        for (x = 40; x < 100; x++) {
            const uint8_t *v = im->data + (size_t)y * im->stride + 3 * x;
            double l = 0.299 * v[0] + 0.587 * v[1] + 0.114 * v[2];
            double lc = 0.299 * CREAM[0] + 0.587 * CREAM[1] + 0.114 * CREAM[2];
            if (l <= (1.0 - TD_DEFRINGE_MIN) * lc)
                worst = fmax(worst, off_brown(v));
        }
    return worst;
}

/* The fringed line's edges are orange on one side and blue on the other,
 * far off brown's mixtures with the paper; defringed, every pixel of it
 * is brown again at some coverage, the road stays red and the paper is
 * left as it was. */
static void test_misregistered_line(void)
{
    static const double none[3] = {0, 0, 0}, fringe[3] = {1.0, 0, -1.0};
    td_image *im = sheet(fringe), *out = NULL, *clean = sheet(none);
    td_defringe_params p = td_defringe_defaults();
    double before, after, ideal;
    int y, same = 1;
    TT_CHECK(im && clean);
    if (!im || !clean)
        goto done;
    out = td_image_new(im->w, im->h, 3, NULL);
    TT_CHECK(out && td_defringe(im, out, &p, NULL) == 0);
    if (!out)
        goto done;
    before = worst_off_brown(im);
    after = worst_off_brown(out);
    ideal = worst_off_brown(clean);
    fprintf(stderr,
            "  off brown's mixtures: fringed %.1f, defringed %.1f, "
            "unfringed %.1f levels\n",
            before, after, ideal);
    TT_CHECK(before > 40);
    TT_CHECK(after < 12);
    for (y = 0; y < im->h; y++) {
        const uint8_t *road = out->data + (size_t)y * out->stride + 3 * 130;
        const uint8_t *a = im->data + (size_t)y * im->stride + 3 * 10;
        const uint8_t *b = out->data + (size_t)y * out->stride + 3 * 10;
        TT_CHECKF(road[0] > road[1] + 100, "road at row %d: %d,%d,%d", y,
                  road[0], road[1], road[2]);
        same &= !memcmp(a, b, 3);
    }
    TT_CHECK(same);
done:
    td_image_free(im);
    td_image_free(out);
    td_image_free(clean);
}

static void test_bad_args(void)
{
    static const double none[3] = {0, 0, 0};
    td_image *im = sheet(none), *grey = td_image_new(200, 120, 1, NULL);
    td_defringe_params p = td_defringe_defaults();
    td_ctx cx;
    td_ctx_init(&cx);
    TT_CHECK(im && grey);
    if (im && grey) {
        TT_CHECK(td_defringe(im, im, &p, &cx) == TD_EINVAL);
        TT_CHECK(td_defringe(im, grey, &p, &cx) == TD_EINVAL);
        p.radius = 9;
        TT_CHECK(td_defringe(im, grey, &p, &cx) == TD_EINVAL);
    }
    td_image_free(im);
    td_image_free(grey);
}

int main(void)
{
    TT_RUN(test_misregistered_line);
    TT_RUN(test_bad_args);
    return tt_summary();
}
