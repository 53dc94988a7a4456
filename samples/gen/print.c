/* print.c: a colour sheet as it comes from a flatbed scanner (tdgen
 * --print): the plates of a printed topographic map over ageing paper,
 * then the scanner's defects.
 *
 * Plates, printed one over another (inks are filters: each multiplies the
 * light, coverage a of ink colour k turns v into v (1 - a (1 - k/255))):
 *   green woodland tint in smooth blobs (about a quarter of the sheet);
 *   brown contours (160,90,40), faded to 55-100 % in smooth patches
 *     (--unfaded: at full strength, a new map);
 *   red roads (205,50,40): one solid, one dashed, 2.2 px, crossing the
 *     sheet (their hue is close to the brown);
 *   blue water (a river), black lettering and a black 1-px grid.
 * Scan: the paper yellows and darkens smoothly (0.93-1.0 per channel),
 * the red and blue channels are misregistered by +-fringe px (0.6 px
 * horizontally by default: colour fringing), then blur, noise and JPEG (quality
 * 75). */
#include "samples/gen/gen.h"
#include "samples/gen/gen_int.h"

#include "src/io/io.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A smooth random field in about [-1, 1]: six plane waves with
 * wavelengths lam_lo..lam_hi px in random directions. */
typedef struct field {
    double kx[6], ky[6], ph[6];
} field;

static field field_make(td_rng *r, double lam_lo, double lam_hi)
{
    field f;
    int i;
    for (i = 0; i < 6; i++) {
        double a = td_rng_range(r, 0, 2 * TD_PI);
        double k = 2 * TD_PI / td_rng_range(r, lam_lo, lam_hi);
        f.kx[i] = k * cos(a);
        f.ky[i] = k * sin(a);
        f.ph[i] = td_rng_range(r, 0, 2 * TD_PI);
    }
    return f;
}

static double field_at(const field *f, double x, double y)
{
    double s = 0;
    int i;
    for (i = 0; i < 6; i++)
        s += cos(f->kx[i] * x + f->ky[i] * y + f->ph[i]);
    return s / 2.45; /* sd of the sum is sqrt(3) */
}

/* Contract in gen_int.h. */
void td_gen_overprint(td_image *im, const uint8_t *lay, const uint8_t *col)
{
    size_t i, n = (size_t)im->w * (size_t)im->h;
    int c;
    for (i = 0; i < n; i++) {
        unsigned a = lay[i];
        if (!a)
            continue;
        for (c = 0; c < 3; c++) {
            uint8_t *v = &im->data[3 * i + (size_t)c];
            unsigned t = 255u * 255u - a * (255u - col[c]);
            *v = (uint8_t)((*v * t + 255u * 255u / 2) / (255u * 255u));
        }
    }
}

/* A road from one side of the sheet to the other, wavy; dashed when dash
 * > 0 (dash px drawn, dash / 2 left out). */
static void draw_road(uint8_t *lay, const td_gen_params *p, td_rng *r,
                      double dash)
{
    double S = p->w < p->h ? p->w : p->h, L, ux, uy, t, run = 0;
    double x0, y0, x1, y1, a1 = 0.04 * S, f1 = td_rng_range(r, 0, 2 * TD_PI);
    double px = 0, py = 0;
    int horiz = td_rng_below(r, 2) == 0, first = 1;
    if (horiz) {
        x0 = -5, x1 = p->w + 5;
        y0 = p->h * td_rng_range(r, 0.15, 0.85);
        y1 = p->h * td_rng_range(r, 0.15, 0.85);
    } else {
        y0 = -5, y1 = p->h + 5;
        x0 = p->w * td_rng_range(r, 0.15, 0.85);
        x1 = p->w * td_rng_range(r, 0.15, 0.85);
    }
    L = hypot(x1 - x0, y1 - y0);
    ux = (x1 - x0) / L, uy = (y1 - y0) / L;
    for (t = 0; t <= L; t += 2.0) {
        double off = a1 * sin(2 * TD_PI * t / (0.7 * L) + f1);
        double x = x0 + ux * t - uy * off, y = y0 + uy * t + ux * off;
        if (!first && (dash <= 0 || fmod(run, 1.5 * dash) < dash))
            td_gen_draw_seg(lay, p->w, p->h, px, py, x, y, 2.2);
        if (!first)
            run += hypot(x - px, y - py);
        first = 0;
        px = x, py = y;
    }
}

/* Contract in gen_int.h. */
int td_gen_print_plates(td_image *im, const uint8_t *contours,
                        const td_gen_params *p, const td_gen_break *br,
                        size_t nbr, td_ctx *cx)
{
    static const uint8_t green[3] = {200, 228, 175}, brown[3] = {160, 90, 40},
                         red[3] = {205, 50, 40}, black[3] = {25, 25, 25};
    size_t n = (size_t)p->w * (size_t)p->h, i;
    double S = p->w < p->h ? p->w : p->h;
    td_rng r = td_rng_make(p->seed, 7);
    field wood = field_make(&r, 0.25 * S, 0.7 * S);
    field fade = field_make(&r, 0.1 * S, 0.3 * S);
    uint8_t *lay = td_calloc(n, 1, cx);
    int x, y;
    if (!lay)
        return TD_ENOMEM;
    for (i = 0; i < n; i++) {
        im->data[3 * i] = 245;
        im->data[3 * i + 1] = 235;
        im->data[3 * i + 2] = 210;
    }
    for (y = 0; y < p->h; y++) /* woodland: the field over 0.55, soft edge */
        for (x = 0; x < p->w; x++) {
            double v = (field_at(&wood, x, y) - 0.55) * 0.02 * S;
            lay[(size_t)y * p->w + x] =
                (uint8_t)(255.0 * (v < 0 ? 0 : v > 1 ? 1 : v));
        }
    td_gen_overprint(im, lay, green);
    for (y = 0; y < p->h; y++) /* contours, faded in patches */
        for (x = 0; x < p->w; x++) {
            size_t k = (size_t)y * p->w + x;
            double f = 0.775 + 0.225 * field_at(&fade, x, y);
            f = p->unfaded ? 1.0 : f < 0.55 ? 0.55 : f > 1 ? 1 : f;
            lay[k] = (uint8_t)(contours[k] * f + 0.5);
        }
    td_gen_overprint(im, lay, brown);
    memset(lay, 0, n);
    draw_road(lay, p, &r, 0.0);
    draw_road(lay, p, &r, 14.0);
    td_gen_overprint(im, lay, red);
    memset(lay, 0, n);
    for (i = 1; i <= 2; i++) { /* the grid */
        td_gen_draw_seg(lay, p->w, p->h, p->w * i / 3.0, -2, p->w * i / 3.0,
                        p->h + 2, 0.6);
        td_gen_draw_seg(lay, p->w, p->h, -2, p->h * i / 3.0, p->w + 2,
                        p->h * i / 3.0, 0.6);
    }
    td_gen_overprint(im, lay, black);
    memset(lay, 0, n);
    td_gen_distractors(im, contours, lay, p, br, nbr);
    free(lay);
    return 0;
}

/* Shift n samples v[0], v[step], ... by d samples (linear interpolation,
 * ends held). */
static void shift_line(uint8_t *v, size_t step, int n, double d, uint8_t *tmp)
{
    int i;
    if (d == 0.0)
        return;
    for (i = 0; i < n; i++)
        tmp[i] = v[(size_t)i * step];
    for (i = 0; i < n; i++) {
        double s = i - d;
        int i0 = (int)floor(s);
        double f = s - i0;
        int a = i0 < 0 ? 0 : i0 >= n ? n - 1 : i0;
        int b = i0 + 1 < 0 ? 0 : i0 + 1 >= n ? n - 1 : i0 + 1;
        v[(size_t)i * step] = (uint8_t)(tmp[a] * (1 - f) + tmp[b] * f + 0.5);
    }
}

/* Shift channel c of im by (dx, dy) px. */
static void shift_channel(td_image *im, int c, double dx, double dy,
                          uint8_t *tmp)
{
    int i;
    for (i = 0; i < im->h; i++)
        shift_line(im->data + (size_t)i * im->stride + c, 3, im->w, dx, tmp);
    for (i = 0; i < im->w; i++)
        shift_line(im->data + 3 * (size_t)i + c, im->stride, im->h, dy, tmp);
}

/* Contract in gen_int.h. */
int td_gen_scan_effects(td_image *im, const td_gen_params *p, td_ctx *cx)
{
    int rc;
    if (p->print && im->channels == 3) {
        double S = p->w < p->h ? p->w : p->h;
        td_rng r = td_rng_make(p->seed, 8);
        field age = field_make(&r, 0.3 * S, 0.9 * S);
        uint8_t *tmp = td_malloc((size_t)(im->w > im->h ? im->w : im->h), cx);
        int x, y;
        if (!tmp)
            return TD_ENOMEM;
        for (y = 0; y < im->h; y++) {
            uint8_t *row = im->data + (size_t)y * im->stride;
            for (x = 0; x < im->w; x++) {
                double a = 0.5 + 0.5 * field_at(&age, x, y);
                double k[3] = {1.0 - 0.035 * a, 1.0 - 0.045 * a,
                               1.0 - 0.09 * a}; /* yellowing */
                int c;
                for (c = 0; c < 3; c++)
                    row[3 * x + c] = (uint8_t)(row[3 * x + c] * k[c] + 0.5);
            }
        }
        shift_channel(im, 0, p->fringe[0], p->fringe[1], tmp);
        shift_channel(im, 2, -p->fringe[0], -p->fringe[1], tmp);
        free(tmp);
    }
    if (p->blur > 0.0 && (rc = td_gen_blur(im, p->blur, cx)) != 0)
        return rc;
    if (p->noise > 0.0)
        td_gen_noise(im, p->noise, p->seed);
    if (p->print && (rc = td_cv_jpeg_roundtrip(im, 75, cx)) != 0)
        return rc;
    return 0;
}
