/* test_view.c: perspective views (src/render/view.c, paper 001 §2.6):
 * where a known pyramid lands in the picture against the perspective
 * formula written out here; hidden surfaces (a tall block in front hides
 * a low one behind it); flat shading by Lambert's law on planes facing
 * the light and facing away. */
#include "tests/tt.h"
#include "src/render/render.h"

#include <stdlib.h>
#include <string.h>

static td_grid_f32 *grid(int w, int h)
{
    td_grid_f32 *g = td_grid_f32_new(w, h, NULL);
    g->has_nodata = 1, g->nodata = -9999;
    return g;
}

static const uint8_t *pix(const td_image *im, int x, int y)
{
    return im->data + (size_t)y * im->stride + 3 * (size_t)x;
}

static int is_back(const td_image *im, int x, int y)
{
    const uint8_t *p = pix(im, x, y);
    return p[0] == 250 && p[1] == 250 && p[2] == 247;
}

/* The camera written out independently: standing at azimuth az (clockwise
 * from north), elevation el, distance D from the point t; world x east,
 * y north, z up; focal length from the horizontal field of view. */
static void expect(const double t[3], double D, double az_deg, double el_deg,
                   double fov_deg, int W, int H, double X, double Y, double Z,
                   double *px, double *py)
{
    double az = az_deg * M_PI / 180, el = el_deg * M_PI / 180;
    double c[3] = {t[0] + D * sin(az) * cos(el), t[1] + D * cos(az) * cos(el),
                   t[2] + D * sin(el)};
    /* forward: towards t; right: forward x up; up: right x forward */
    double f[3] = {-sin(az) * cos(el), -cos(az) * cos(el), -sin(el)};
    double r[3] = {f[1], -f[0], 0}, u[3], d[3] = {X - c[0], Y - c[1], Z - c[2]};
    double n = hypot(r[0], r[1]), focal = W / 2.0 / tan(fov_deg * M_PI / 360);
    r[0] /= n, r[1] /= n;
    u[0] = r[1] * f[2] - r[2] * f[1];
    u[1] = r[2] * f[0] - r[0] * f[2];
    u[2] = r[0] * f[1] - r[1] * f[0];
    *px = W / 2.0 + focal * (d[0] * r[0] + d[1] * r[1] + d[2] * r[2]) /
                        (d[0] * f[0] + d[1] * f[1] + d[2] * f[2]);
    *py = H / 2.0 - focal * (d[0] * u[0] + d[1] * u[1] + d[2] * u[2]) /
                        (d[0] * f[0] + d[1] * f[1] + d[2] * f[2]);
}

/* A pyramid 100 x 100 cells, apex 50 high at the centre, seen from the
 * south-west, drawn as a wire mesh: the apex and the base corners where
 * the formula says. */
static void test_pyramid(void)
{
    enum { N = 101, W = 800, H = 600 };
    td_grid_f32 *g = grid(N, N);
    td_image *im = td_image_new(W, H, 3, NULL);
    td_view_params p = td_view_defaults();
    td_view_camera cam;
    double t[3] = {N / 2.0, -N / 2.0, 25}, ax, ay, x0 = 1e9, x1 = -1e9, y1 = -1e9;
    int x, y, k, top = H, left = W, right = -1, bottom = -1;
    for (y = 0; y < N; y++)
        for (x = 0; x < N; x++)
            TD_AT(g, x, y) = (float)(50 - fmax(fabs(x - 50.0), fabs(y - 50.0)));
    p.azimuth = 210, p.elevation = 30, p.fov = 40, p.distance = 300;
    p.exaggeration = 1, p.patch = 1;
    p.style = TD_VIEW_WIRE; /* the edges run through the corners' pixels */
    TT_CHECK(td_view_camera_of(g, &p, W, H, &cam, NULL) == 0);
    TT_CHECK(td_view_project(&cam, 50.5, 50.5, 50, &ax, &ay));
    {
        double ex, ey;
        expect(t, 300, 210, 30, 40, W, H, 50.5, -50.5, 50, &ex, &ey);
        TT_NEAR(ax, ex, 1e-6);
        TT_NEAR(ay, ey, 1e-6);
    }
    for (k = 0; k < 4; k++) { /* the base corners (cell centres) */
        double ex, ey;
        expect(t, 300, 210, 30, 40, W, H, k & 1 ? 100.5 : 0.5,
               k & 2 ? -100.5 : -0.5, 0, &ex, &ey);
        x0 = fmin(x0, ex), x1 = fmax(x1, ex), y1 = fmax(y1, ey);
    }
    TT_CHECK(td_view_render(g, NULL, &p, im, NULL) == 0);
    for (y = 0; y < H; y++)
        for (x = 0; x < W; x++)
            if (!is_back(im, x, y)) {
                top = y < top ? y : top, bottom = y > bottom ? y : bottom;
                left = x < left ? x : left, right = x > right ? x : right;
            }
    /* the extreme drawn pixels: the corners', within a pixel */
    TT_CHECKF(fabs(top + 0.5 - ay) <= 1.0, "apex at y %g, top pixel %d", ay,
              top);
    TT_CHECKF(fabs(left + 0.5 - x0) <= 1.0 && fabs(right + 0.5 - x1) <= 1.0,
              "base corners x %g..%g, drawn %d..%d", x0, x1, left, right);
    TT_CHECKF(fabs(bottom + 0.5 - y1) <= 1.0, "nearest corner y %g, drawn %d",
              y1, bottom);
    td_image_free(im);
    td_grid_f32_free(g);
}

/* Flat ground with a low block far off (draped green) and a tall block in
 * front of it (draped red), seen from the south, low: where the low
 * block's top would be, the tall block is drawn (red); without the tall
 * block the low one shows there (green). */
static void hidden(int zbuffer)
{
    enum { N = 100, W = 600, H = 400 };
    td_grid_f32 *g = grid(N, N);
    td_image *im = td_image_new(W, H, 3, NULL), *dr = td_image_new(N, N, 3, NULL);
    td_view_params p = td_view_defaults();
    td_view_camera cam;
    const uint8_t *c;
    double px, py;
    int x, y, pass;
    p.azimuth = 180, p.elevation = 12, p.fov = 40, p.distance = 250;
    p.exaggeration = 1, p.patch = 1, p.drape = TD_DRAPE_IMAGE;
    p.ambient = 1; /* colours as draped */
    p.zbuffer = zbuffer;
    for (pass = 0; pass < 2; pass++) {
        for (y = 0; y < N; y++)
            for (x = 0; x < N; x++) {
                int low = y >= 20 && y < 30 && x >= 40 && x < 60;
                int tall = pass == 0 && y >= 60 && y < 75 && x >= 30 && x < 70;
                uint8_t *d = dr->data + (size_t)y * dr->stride + 3 * (size_t)x;
                TD_AT(g, x, y) = (float)(tall ? 40 : low ? 10 : 0);
                d[0] = tall ? 255 : low ? 0 : 255;
                d[1] = tall ? 0 : 255;
                d[2] = tall ? 0 : low ? 0 : 255;
            }
        TT_CHECK(td_view_render(g, dr, &p, im, NULL) == 0);
        TT_CHECK(td_view_camera_of(g, &p, W, H, &cam, NULL) == 0);
        TT_CHECK(td_view_project(&cam, 50, 25, 10, &px, &py));
        c = pix(im, (int)px, (int)py);
        if (pass == 0)
            TT_CHECKF(c[0] == 255 && c[1] == 0, "behind the tall block (%s): "
                      "%d %d %d, not its red", zbuffer ? "z-buffer" : "painter",
                      c[0], c[1], c[2]);
        else
            TT_CHECKF(c[0] == 0 && c[1] == 255, "the low block alone: %d %d "
                      "%d, not its green", c[0], c[1], c[2]);
    }
    td_image_free(im), td_image_free(dr);
    td_grid_f32_free(g);
}

static void test_hidden(void)
{
    hidden(0);
    hidden(1);
}

/* The z-buffer and the paper's order draw a hill alike: the same colour
 * on 99 % of the pixels (they differ only where patches overlap by a
 * pixel's centre at their shared edges). */
static void test_zbuffer_as_painter(void)
{
    enum { N = 120, W = 400, H = 300 };
    td_grid_f32 *g = grid(N, N);
    td_image *a = td_image_new(W, H, 3, NULL), *b = td_image_new(W, H, 3, NULL);
    td_view_params p = td_view_defaults();
    long same = 0;
    int x, y;
    for (y = 0; y < N; y++)
        for (x = 0; x < N; x++)
            TD_AT(g, x, y) = (float)(30 * exp(-((x - 60) * (x - 60) +
                                                (y - 55) * (y - 55)) / 900.0) +
                                     8 * sin(x / 9.0) * cos(y / 7.0));
    TT_CHECK(td_view_render(g, NULL, &p, a, NULL) == 0);
    p.zbuffer = 1;
    TT_CHECK(td_view_render(g, NULL, &p, b, NULL) == 0);
    for (y = 0; y < H; y++)
        for (x = 0; x < W; x++)
            same += !memcmp(pix(a, x, y), pix(b, x, y), 3);
    TT_CHECKF(same >= 0.99 * W * H, "%ld of %d pixels alike", same, W * H);
    td_image_free(a), td_image_free(b);
    td_grid_f32_free(g);
}

/* Planes sloping 30 degrees, the light from the south 45 degrees up:
 * facing it (rising to the north) the normal is 15 degrees off the
 * light, facing away 75; grey = 255 (ambient + (1 - ambient) cos). */
static void test_lambert(void)
{
    enum { N = 60, W = 200, H = 200 };
    double want[2], s = tan(30 * M_PI / 180);
    int k, x, y;
    want[0] = 255 * (0.2 + 0.8 * cos(15 * M_PI / 180));
    want[1] = 255 * (0.2 + 0.8 * cos(75 * M_PI / 180));
    for (k = 0; k < 2; k++) {
        td_grid_f32 *g = grid(N, N);
        td_image *im = td_image_new(W, H, 3, NULL);
        td_view_params p = td_view_defaults();
        const uint8_t *c;
        for (y = 0; y < N; y++)
            for (x = 0; x < N; x++)
                TD_AT(g, x, y) = (float)(s * (k == 0 ? N - y : y));
        p.azimuth = 180, p.elevation = 60, p.distance = 200;
        p.exaggeration = 1, p.patch = 3, p.ambient = 0.2;
        p.light[0][0] = 180, p.light[0][1] = 45;
        TT_CHECK(td_view_render(g, NULL, &p, im, NULL) == 0);
        c = pix(im, W / 2, H / 2);
        TT_CHECKF(fabs(c[0] - want[k]) <= 2 && c[0] == c[1] && c[1] == c[2],
                  "%s the light: grey %d, Lambert %g", k ? "away from" :
                  "facing", c[0], want[k]);
        td_image_free(im);
        td_grid_f32_free(g);
    }
}

static void test_bad(void)
{
    td_grid_f32 *g = grid(10, 10), *one = grid(1, 30);
    td_image *im = td_image_new(50, 50, 3, NULL);
    td_view_params p = td_view_defaults();
    td_ctx cx;
    int i;
    td_ctx_init(&cx);
    for (i = 0; i < 100; i++)
        g->data[i] = -9999;
    TT_CHECK(td_view_render(g, NULL, &p, im, &cx) == TD_EINVAL);
    TT_CHECKF(strstr(td_errmsg(&cx), "no data") != NULL, "%s", td_errmsg(&cx));
    TT_CHECK(td_view_render(one, NULL, &p, im, &cx) == TD_EINVAL);
    p.drape = TD_DRAPE_IMAGE;
    g->data[0] = 1;
    TT_CHECK(td_view_render(g, NULL, &p, im, &cx) == TD_EINVAL);
    td_image_free(im);
    td_grid_f32_free(g), td_grid_f32_free(one);
}

int main(void)
{
    TT_RUN(test_pyramid);
    TT_RUN(test_hidden);
    TT_RUN(test_zbuffer_as_painter);
    TT_RUN(test_lambert);
    TT_RUN(test_bad);
    return tt_summary();
}
