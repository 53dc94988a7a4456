/* effects.c: what makes a rendered sheet look scanned: specks, colour
 * distractors (river, lettering), blur and noise. */
#include "samples/gen/gen.h"
#include "samples/gen/gen_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* True when the box [x0,x1]x[y0,y1] (clipped) has no coverage in lay and
 * is at least `far` px from every break's middle. */
static int box_clear(const uint8_t *lay, int w, int h, int x0, int y0, int x1,
                     int y1, const td_gen_break *br, size_t nbr, double far)
{
    int x, y;
    size_t b;
    if (x0 < 0 || y0 < 0 || x1 >= w || y1 >= h)
        return 0;
    for (y = y0; y <= y1; y++)
        for (x = x0; x <= x1; x++)
            if (lay[(size_t)y * (size_t)w + (size_t)x])
                return 0;
    for (b = 0; b < nbr; b++) {
        double dx = fmax(fmax(x0 - br[b].x, br[b].x - x1 - 1), 0.0);
        double dy = fmax(fmax(y0 - br[b].y, br[b].y - y1 - 1), 0.0);
        if (dx * dx + dy * dy < far * far)
            return 0;
    }
    return 1;
}

/* Grow a 4-connected random blob of n pixels from (0,0) into bx/by. */
static void grow_blob(td_rng *r, int n, int *bx, int *by)
{
    static const int ox[4] = {1, -1, 0, 0}, oy[4] = {0, 0, 1, -1};
    int k = 1, i;
    bx[0] = by[0] = 0;
    while (k < n) {
        int s = (int)td_rng_below(r, (uint64_t)k), d = (int)td_rng_below(r, 4);
        int nx = bx[s] + ox[d], ny = by[s] + oy[d], dup = 0;
        for (i = 0; i < k; i++)
            dup |= bx[i] == nx && by[i] == ny;
        if (!dup) {
            bx[k] = nx;
            by[k] = ny;
            k++;
        }
    }
}

/* Contract in gen_int.h. */
void td_gen_specks(uint8_t *lay, const td_gen_params *p, const td_gen_break *br,
                   size_t nbr)
{
    td_rng r = td_rng_make(p->seed, 5);
    int k, tries, i;
    if (p->w < 16 || p->h < 16)
        return;
    for (k = 0; k < p->specks; k++)
        for (tries = 0; tries < 100; tries++) {
            int bx[6], by[6], n = 1 + (int)td_rng_below(&r, 6);
            int cx = 8 + (int)td_rng_below(&r, (uint64_t)(p->w - 16));
            int cy = 8 + (int)td_rng_below(&r, (uint64_t)(p->h - 16));
            grow_blob(&r, n, bx, by);
            /* blob extent is within 5 px of (cx,cy); keep 4 px clear */
            if (!box_clear(lay, p->w, p->h, cx - 9, cy - 9, cx + 9, cy + 9, br,
                           nbr, 15.0))
                continue;
            for (i = 0; i < n; i++)
                lay[(size_t)(cy + by[i]) * (size_t)p->w +
                    (size_t)(cx + bx[i])] = 255;
            break;
        }
}

/* Contract in gen_int.h. */
void td_gen_composite(td_image *im, const uint8_t *lay, const uint8_t *col)
{
    size_t i, n = (size_t)im->w * (size_t)im->h;
    int c, ch = im->channels;
    for (i = 0; i < n; i++) {
        unsigned a = lay[i];
        if (!a)
            continue;
        for (c = 0; c < ch; c++) {
            uint8_t *v = &im->data[i * (size_t)ch + (size_t)c];
            *v = (uint8_t)((*v * (255u - a) + col[c] * a + 127u) / 255u);
        }
    }
}

/* A wavy river right across the sheet, 2 px wide. */
static void draw_river(uint8_t *lay, const td_gen_params *p, td_rng *r)
{
    double S = p->w < p->h ? p->w : p->h;
    double y0 = p->h * td_rng_range(r, 0.3, 0.7);
    double a1 = 0.05 * S, l1 = 0.6 * p->w, f1 = td_rng_range(r, 0, 2 * TD_PI);
    double a2 = 0.012 * S, l2 = 0.13 * p->w, f2 = td_rng_range(r, 0, 2 * TD_PI);
    double x, px = -8.0, py = 0.0;
    for (x = -8.0; x <= p->w + 8.0; x += 3.0) {
        double y = y0 + a1 * sin(2 * TD_PI * x / l1 + f1) +
                   a2 * sin(2 * TD_PI * x / l2 + f2);
        if (x > -8.0)
            td_gen_draw_seg(lay, p->w, p->h, px, py, x, y, 1.5);
        px = x;
        py = y;
    }
}

/* A word of 3..7 glyphs, each 2..4 strokes between points of a 3x3
 * lattice in its box (gh px high), drawn at (x,y) top-left. */
static void draw_word(uint8_t *lay, const td_gen_params *p, td_rng *r, int x,
                      int y, int nglyph, double gh)
{
    double gw = 0.6 * gh, step = gw + 0.3 * gh;
    int g, s;
    for (g = 0; g < nglyph; g++) {
        int ns = 2 + (int)td_rng_below(r, 3);
        for (s = 0; s < ns; s++) {
            int a = (int)td_rng_below(r, 9), b = (int)td_rng_below(r, 9);
            if (a == b)
                b = (b + 4) % 9;
            td_gen_draw_seg(lay, p->w, p->h, x + g * step + 0.5 * gw * (a % 3),
                            y + 0.5 * gh * (a / 3),
                            x + g * step + 0.5 * gw * (b % 3),
                            y + 0.5 * gh * (b / 3), 1.3);
        }
    }
}

/* Contract in gen_int.h. */
void td_gen_distractors(td_image *im, const uint8_t *contours, uint8_t *scratch,
                        const td_gen_params *p, const td_gen_break *br,
                        size_t nbr)
{
    static const uint8_t blue[3] = {30, 90, 200}, black[3] = {20, 20, 20};
    td_rng r = td_rng_make(p->seed, 6);
    double S = p->w < p->h ? p->w : p->h, gh = fmax(8.0, S / 70.0);
    int nwords = 4 + (int)((double)p->w * p->h / 250000.0), k, tries;
    draw_river(scratch, p, &r); /* with streams drawn from the terrain
                                   instead, the words stay where they were */
    if (!p->streams)
        td_gen_composite(im, scratch, blue);
    memset(scratch, 0, (size_t)p->w * (size_t)p->h);
    for (k = 0; k < nwords; k++)
        for (tries = 0; tries < 60; tries++) {
            int ng = 3 + (int)td_rng_below(&r, 5);
            int ww = (int)ceil(ng * 0.9 * gh + 2), hh = (int)ceil(gh + 2);
            int x, y;
            if (p->w <= ww + 12 || p->h <= hh + 12)
                return;
            x = 6 + (int)td_rng_below(&r, (uint64_t)(p->w - ww - 12));
            y = 6 + (int)td_rng_below(&r, (uint64_t)(p->h - hh - 12));
            if (!box_clear(contours, p->w, p->h, x - 5, y - 5, x + ww + 5,
                           y + hh + 5, br, nbr, 15.0) ||
                !box_clear(scratch, p->w, p->h, x - 5, y - 5, x + ww + 5,
                           y + hh + 5, NULL, 0, 0.0))
                continue;
            draw_word(scratch, p, &r, x + 1, y + 1, ng, gh);
            break;
        }
    td_gen_composite(im, scratch, black);
}

/* acc[i] += k * src[i]; unrolled by 8 so the compiler's block vectoriser
 * turns it into vector code even at -O2. */
static void axpy(float *acc, const float *src, float k, size_t n)
{
    size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        acc[i] += k * src[i];
        acc[i + 1] += k * src[i + 1];
        acc[i + 2] += k * src[i + 2];
        acc[i + 3] += k * src[i + 3];
        acc[i + 4] += k * src[i + 4];
        acc[i + 5] += k * src[i + 5];
        acc[i + 6] += k * src[i + 6];
        acc[i + 7] += k * src[i + 7];
    }
    for (; i < n; i++)
        acc[i] += k * src[i];
}

/* Horizontal pass of image row y into out (floats, rl of them): the row
 * padded by R clamped pixels each side in pad, then one axpy per tap. */
static void blur_row(const td_image *im, int y, float *pad, float *out,
                     const float *k, int R)
{
    const uint8_t *src = im->data + (size_t)y * im->stride;
    int ch = im->channels, x, c, t;
    size_t rl = (size_t)im->w * (size_t)ch;
    for (x = -R; x < im->w + R; x++) {
        int xx = x < 0 ? 0 : (x >= im->w ? im->w - 1 : x);
        for (c = 0; c < ch; c++)
            pad[(size_t)(x + R) * ch + c] = src[(size_t)xx * ch + c];
    }
    memset(out, 0, rl * sizeof *out);
    for (t = 0; t <= 2 * R; t++)
        axpy(out, pad + (size_t)t * ch, k[t], rl);
}

static uint8_t clamp_u8(float v)
{
    return (uint8_t)(v <= 0.0f ? 0 : (v >= 255.0f ? 255 : (int)(v + 0.5f)));
}

/* Contract in gen_int.h.  Rows are blurred horizontally into a ring of
 * 2R+1 float rows just before the vertical pass needs them, so the image
 * is rewritten in place with memory of about 2R+3 rows. */
int td_gen_blur(td_image *im, double sigma, td_ctx *cx)
{
    int R = (int)ceil(3.0 * sigma), t, y, nk;
    size_t rl = (size_t)im->w * (size_t)im->channels, x;
    float *k = NULL, *acc = NULL, *pad = NULL, *ring = NULL, sum = 0.0f;
    int rc = TD_ENOMEM;
    R = R < 1 ? 1 : R;
    nk = 2 * R + 1;
    if (!(k = td_malloc((size_t)nk * sizeof *k, cx)) ||
        !(acc = td_malloc(rl * sizeof *acc, cx)) ||
        !(pad =
              td_malloc((rl + (size_t)nk * im->channels) * sizeof *pad, cx)) ||
        !(ring = td_malloc((size_t)nk * rl * sizeof *ring, cx)))
        goto fail;
    for (t = -R; t <= R; t++)
        sum += k[t + R] = (float)exp(-0.5 * t * t / (sigma * sigma));
    for (t = 0; t < nk; t++)
        k[t] /= sum;
    for (y = 0; y < R && y < im->h; y++)
        blur_row(im, y, pad, ring + (size_t)y * rl, k, R);
    for (y = 0; y < im->h; y++) {
        uint8_t *dst = im->data + (size_t)y * im->stride;
        if (y + R < im->h) /* row y+R is still unmodified in the image */
            blur_row(im, y + R, pad, ring + (size_t)((y + R) % nk) * rl, k, R);
        memset(acc, 0, rl * sizeof *acc);
        for (t = -R; t <= R; t++) {
            int yy = y + t;
            yy = yy < 0 ? 0 : (yy >= im->h ? im->h - 1 : yy);
            axpy(acc, ring + (size_t)(yy % nk) * rl, k[t + R], rl);
        }
        for (x = 0; x < rl; x++)
            dst[x] = clamp_u8(acc[x]);
    }
    rc = 0;
fail:
    free(k);
    free(acc);
    free(pad);
    free(ring);
    return rc;
}

/* Inverse of the standard normal CDF by bisection on erfc (table set-up
 * only). */
static double normal_quantile(double p)
{
    double lo = -10.0, hi = 10.0;
    int it;
    for (it = 0; it < 80; it++) {
        double mid = 0.5 * (lo + hi);
        if (0.5 * erfc(-mid / sqrt(2.0)) < p)
            lo = mid;
        else
            hi = mid;
    }
    return 0.5 * (lo + hi);
}

/* Contract in gen_int.h.  Each deviate is one of 4096 normal quantiles
 * (at (i + 0.5) / 4096, so |z| <= 3.5) picked by 12 random bits: five per
 * 64-bit draw, much faster than exact deviates on 10^8 pixels and
 * indistinguishable from them for scan noise. */
void td_gen_noise(td_image *im, double sd, unsigned seed)
{
    td_rng r = td_rng_make(seed, 7);
    size_t rl = (size_t)im->w * (size_t)im->channels, x;
    float tab[4096];
    uint64_t bits = 0;
    int left = 0, y, i;
    for (i = 0; i < 4096; i++)
        tab[i] = (float)(sd * normal_quantile((i + 0.5) / 4096.0));
    for (y = 0; y < im->h; y++) {
        uint8_t *row = im->data + (size_t)y * im->stride;
        for (x = 0; x < rl; x++) {
            if (!left) {
                bits = td_rng_u64(&r);
                left = 5;
            }
            row[x] = clamp_u8(row[x] + tab[bits & 4095]);
            bits >>= 12;
            left--;
        }
    }
}
