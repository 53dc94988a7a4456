/* binarise.c: scan image -> ink mask (ALGORITHMS.md A.1).
 *
 * 1. Ink strength s (u8, high = ink), one image row at a time, written
 *    into the caller's mask: no full-size float, grey or HSV temporary.
 * 2. Threshold s in place: Otsu (with a "no ink" contrast guard), Sauvola
 *    (banded, in the shim) or a fixed level.
 * 3. Remove 8-connected specks smaller than min_speck (bounded fill).
 * 4. Fill pinholes (paper components) smaller than min_hole.
 * The user guide with the brownness score and measurements is
 * docs/binarise.md. */
#include "scanner/binarise.h"

#include "src/io/io.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define LUT_N TD_PALETTE_LUT_N /* table nodes per channel: 0, 8, ..., 256 */
#define LUT_SIZE TD_PALETTE_LUT_SIZE
#define BAND_ROWS 256 /* rows per strength band and progress report */

td_binarise_params td_binarise_defaults(void)
{
    td_binarise_params p;
    memset(&p, 0, sizeof p);
    p.ink = TD_INK_AUTO;
    p.rgb_tol = 60;
    p.thr = TD_THR_OTSU;
    p.thr_value = 128;
    p.sauvola_window = 31;
    p.sauvola_k = 0.2;
    p.min_speck = 8;
    p.min_hole = 8;
    p.split = 24;
    p.local_level = 1;
    p.cores = 0;
    return p;
}

/* ---- option parsing ---------------------------------------------------- */

/* A decimal integer in lo..hi at *s (digits only, no sign); advances *s. */
static int parse_uint(const char **s, long lo, long hi, int *out)
{
    char *end;
    long v;
    if (!isdigit((unsigned char)**s))
        return -1;
    errno = 0;
    v = strtol(*s, &end, 10);
    if (errno != 0 || v < lo || v > hi)
        return -1;
    *s = end;
    *out = (int)v;
    return 0;
}

int td_binarise_parse_ink(const char *s, td_binarise_params *p, td_ctx *cx)
{
    const char *q = s;
    int c[3], tol = p->rgb_tol, i;
    if (!s)
        return td_seterr(cx, TD_EINVAL, "--ink: missing value");
    static const struct {
        const char *name;
        td_ink_kind kind;
    } named[] = {{"auto", TD_INK_AUTO},
                 {"dark", TD_INK_DARK},
                 {"brown", TD_INK_BROWN},
                 {"brown-hue", TD_INK_BROWN_HUE}};
    for (i = 0; i < (int)(sizeof named / sizeof named[0]); i++)
        if (strcmp(s, named[i].name) == 0) {
            p->ink = named[i].kind;
            return 0;
        }
    for (i = 0; i < 3; i++) {
        if (i > 0 && *q++ != ',')
            goto bad;
        if (parse_uint(&q, 0, 255, &c[i]) != 0)
            goto bad;
    }
    if (*q == ':') {
        q++;
        if (parse_uint(&q, 1, 442, &tol) != 0)
            goto bad;
    }
    if (*q != '\0')
        goto bad;
    p->ink = TD_INK_RGB;
    for (i = 0; i < 3; i++)
        p->rgb[i] = (uint8_t)c[i];
    p->rgb_tol = tol;
    return 0;
bad:
    return td_seterr(cx, TD_EINVAL,
                     "--ink '%s': expected auto, dark, brown, brown-hue or "
                     "R,G,B[:tol] "
                     "(R, G, B 0..255, tol 1..442)",
                     s);
}

int td_binarise_parse_threshold(const char *s, td_binarise_params *p,
                                td_ctx *cx)
{
    const char *q = s;
    int v;
    if (!s)
        return td_seterr(cx, TD_EINVAL, "--threshold: missing value");
    if (strcmp(s, "otsu") == 0) {
        p->thr = TD_THR_OTSU;
        return 0;
    }
    if (strcmp(s, "sauvola") == 0) {
        p->thr = TD_THR_SAUVOLA;
        return 0;
    }
    if (parse_uint(&q, 0, 255, &v) != 0 || *q != '\0')
        return td_seterr(cx, TD_EINVAL,
                         "--threshold '%s': expected otsu, sauvola or an "
                         "integer 0..255",
                         s);
    p->thr = TD_THR_FIXED;
    p->thr_value = v;
    return 0;
}

/* ---- brownness ----------------------------------------------------------- */

static double ramp(double v, double lo, double hi)
{
    double t = (v - lo) / (hi - lo);
    return t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
}

/* The exact brownness in 0..255 (float).  Hue H in (-180, 180] degrees so
 * reds sit near 0; weights (docs/binarise.md):
 *   hue   1 on [10, 42], linear to 0 at -5 and at 55   (orange-brown)
 *   sat   C / max(V, 128): 0 at 0.15 (cream paper), 1 at 0.45; the floor of
 *         128 keeps the noisy hue of near-black pixels from counting
 *   value 1 up to V = 0.85 * 255, down to 0.6 at V = 255 (bright paper) */
static double brown_exact(int r, int g, int b)
{
    int mx = r > g ? (r > b ? r : b) : (g > b ? g : b);
    int mn = r < g ? (r < b ? r : b) : (g < b ? g : b);
    double c = mx - mn, h, hw, sw, vw;
    if (mx == mn)
        return 0.0;
    if (mx == r)
        h = 60.0 * (g - b) / c;
    else if (mx == g)
        h = 60.0 * (2.0 + (b - r) / c);
    else
        h = 60.0 * (4.0 + (r - g) / c);
    if (h > 180.0)
        h -= 360.0;
    hw = h < 26.0 ? ramp(h, -5.0, 10.0) : 1.0 - ramp(h, 42.0, 55.0);
    sw = ramp(c / (mx > 128 ? mx : 128), 0.15, 0.45);
    vw = 1.0 - 0.4 * ramp(mx / 255.0, 0.85, 1.0);
    return 255.0 * hw * sw * vw;
}

uint8_t td_binarise_brown_score(uint8_t r, uint8_t g, uint8_t b)
{
    return (uint8_t)lrint(brown_exact(r, g, b));
}

/* Table of brown_exact at the nodes 0, 8, ..., 248, 255 of each channel. */
static void brown_lut_build(uint8_t *lut)
{
    int i, j, k, n = 0;
    for (i = 0; i < LUT_N; i++)
        for (j = 0; j < LUT_N; j++)
            for (k = 0; k < LUT_N; k++) {
                int r = i * 8 > 255 ? 255 : i * 8;
                int g = j * 8 > 255 ? 255 : j * 8;
                int b = k * 8 > 255 ? 255 : k * 8;
                lut[n++] = (uint8_t)lrint(brown_exact(r, g, b));
            }
}

/* ---- ink strength rows --------------------------------------------------- */

typedef struct strength_ctx {
    const td_binarise_params *p;
    const td_image *im;
    uint8_t *lut; /* brown only */
} strength_ctx;

static void row_grey(const uint8_t *px, int w, uint8_t *s)
{
    int x;
    for (x = 0; x < w; x++)
        s[x] = (uint8_t)(255 - px[x]);
}

static void row_brown(const uint8_t *lut, const uint8_t *px, int w, uint8_t *s)
{
    int x;
    for (x = 0; x < w; x++, px += 3)
        s[x] = td_palette_lut_at(lut, px[0], px[1], px[2]);
}

static void row_rgb(const td_binarise_params *p, const uint8_t *px, int w,
                    uint8_t *s)
{
    int x, tol2 = p->rgb_tol * p->rgb_tol;
    float inv = 1.0f / (float)p->rgb_tol;
    for (x = 0; x < w; x++, px += 3) {
        int dr = px[0] - p->rgb[0], dg = px[1] - p->rgb[1];
        int db = px[2] - p->rgb[2], d2 = dr * dr + dg * dg + db * db;
        s[x] = d2 >= tol2
                   ? 0
                   : (uint8_t)(255.0f * (1.0f - sqrtf((float)d2) * inv) + 0.5f);
    }
}

/* Dark ink on a colour scan, rows [y0, y0+n): OpenCV's RGB -> grey
 * (BT.601) straight into s, then inverted.  Errors come back without the
 * shim's own progress reports. */
static int dark_rows(const td_image *im, td_grid_u8 *s, int y0, int n,
                     td_ctx *cx)
{
    td_image band = *im;
    td_grid_u8 out = *s;
    td_ctx quiet;
    int x, y;
    td_ctx_init(&quiet);
    band.h = out.h = n;
    band.data = im->data + (size_t)y0 * im->stride;
    out.data = s->data + (size_t)y0 * s->stride;
    if (td_cv_rgb_to_grey(&band, &out, &quiet) != 0)
        return td_seterr(cx, quiet.code, "%s", quiet.msg);
    for (y = 0; y < n; y++) {
        uint8_t *row = out.data + (size_t)y * out.stride;
        for (x = 0; x < out.w; x++)
            row[x] = (uint8_t)(255 - row[x]);
    }
    return 0;
}

/* Ink strength of rows [y0, y0+n) into s. */
static int strength_rows(const strength_ctx *sc, td_grid_u8 *s, int y0, int n,
                         td_ctx *cx)
{
    const td_image *im = sc->im;
    int y;
    if (im->channels == 3 && sc->p->ink == TD_INK_DARK)
        return dark_rows(im, s, y0, n, cx);
    for (y = y0; y < y0 + n; y++) {
        const uint8_t *px = im->data + (size_t)y * im->stride;
        uint8_t *row = s->data + (size_t)y * s->stride;
        if (im->channels == 1)
            row_grey(px, im->w, row);
        else if (sc->lut)
            row_brown(sc->lut, px, im->w, row);
        else
            row_rgb(sc->p, px, im->w, row);
    }
    return 0;
}

/* Four interleaved histograms so runs of one value (paper) do not chain
 * increments of one counter. */
static void hist_row(const uint8_t *s, int w, uint64_t (*h)[256])
{
    int x = 0;
    for (; x + 4 <= w; x += 4) {
        h[0][s[x]]++;
        h[1][s[x + 1]]++;
        h[2][s[x + 2]]++;
        h[3][s[x + 3]]++;
    }
    for (; x < w; x++)
        h[0][s[x]]++;
}

/* Fill s band by band; hist (may be NULL) gets its 256-bin histogram.
 * Progress "binarise" runs from 0 to frac_end. */
#define VETO_R 1
#define VETO_R_TINT 2 /* where td_detint divided a tint out */

/* Word i of row y of a bit grid of W words a row, 0 outside. */
static uint64_t word_at(const uint64_t *r, size_t W, int h, int y, long i)
{
    return y < 0 || y >= h || i < 0 || (size_t)i >= W
               ? 0
               : r[(size_t)y * W + (size_t)i];
}

/* Word i of the 2 x 2 blocks of row y: bit x set when the pixels x and
 * x + 1 of rows y and y + 1 all are. */
static uint64_t block_word(const uint64_t *r, size_t W, int h, int y, long i)
{
    uint64_t a = word_at(r, W, h, y, i), b = word_at(r, W, h, y + 1, i);
    uint64_t a1 = (a >> 1) | (word_at(r, W, h, y, i + 1) << 63);
    uint64_t b1 = (b >> 1) | (word_at(r, W, h, y + 1, i + 1) << 63);
    return a & a1 & b & b1;
}

/* The pixels of im that are another ink's stroke, packed one bit a pixel
 * (rows of (w + 7) / 8 bytes, bit x & 7 of byte x / 8) into *bits
 * (calloc'ed): a pixel the veto table marks (its nearest node) in a 2 x 2
 * block of such pixels, not the one-pixel colour fringe along the contour
 * ink's own edge; *bits NULL when the table marks no colour at all.  The
 * table is read once a pixel, the blocks found 64 pixels at a time.  0 or
 * TD_ENOMEM. */
static int veto_bits(const td_image *im, const uint8_t *veto, uint8_t **bits,
                     td_ctx *cx)
{
    size_t stride = ((size_t)im->w + 7) / 8, W = ((size_t)im->w + 63) / 64,
           n = 0, i;
    uint64_t *raw;
    uint8_t *b;
    int x, y, h = im->h;
    *bits = NULL;
    for (i = 0; i < LUT_SIZE; i++)
        n += veto[i] != 0;
    if (n == 0)
        return 0;
    if (!(raw = td_calloc((size_t)h * W + 1, sizeof *raw, cx)))
        return TD_ENOMEM;
    if (!(b = td_calloc((size_t)h * stride + 1, 1, cx))) {
        free(raw);
        return TD_ENOMEM;
    }
#pragma omp parallel for schedule(static) private(x)
    for (y = 0; y < h; y++) { /* each row its own words */
        const uint8_t *px = im->data + (size_t)y * im->stride;
        uint64_t *row = raw + (size_t)y * W;
        for (x = 0; x < im->w; x++)
            if (veto[td_palette_node(px + 3 * (size_t)x)])
                row[x >> 6] |= (uint64_t)1 << (x & 63);
    }
#pragma omp parallel for schedule(static)
    for (y = 0; y < h; y++) {
        uint8_t *row = b + (size_t)y * stride;
        size_t j, q;
        for (q = 0; q < W; q++) {
            long k = (long)q;
            uint64_t b0 = block_word(raw, W, h, y, k),
                     bp = block_word(raw, W, h, y - 1, k);
            uint64_t b0l = (b0 << 1) | (block_word(raw, W, h, y, k - 1) >> 63);
            uint64_t bpl =
                (bp << 1) | (block_word(raw, W, h, y - 1, k - 1) >> 63);
            uint64_t core = raw[(size_t)y * W + q] & (b0 | b0l | bp | bpl);
            for (j = 0; j < 8 && 8 * q + j < stride; j++)
                row[8 * q + j] = (uint8_t)(core >> (8 * j));
        }
    }
    free(raw);
    *bits = b;
    return 0;
}

/* Where another ink is printed (veto_bits; its packed bits vb), the
 * contour ink's strength is cleared within VETO_R px: a red road's edges
 * over a green tint look like brown over it, and would join the contours
 * it crosses.  With the veto read on the scan with its tints divided out
 * (im; orig: the scan as it is; p->veto_im), within VETO_R_TINT px where
 * the division changed the pixel: the road's blurred edges over the tint
 * stay brown-looking wider (on the printed Front Range sheet they joined
 * two contours across a road at 1 px).  Rows ylo..yhi - 1 of s only. */
static void veto_row(const td_image *im, const td_image *orig,
                     const uint8_t *vb, td_grid_u8 *s, int y, int ylo, int yhi)
{
    const uint8_t *bits = vb + (size_t)y * (((size_t)im->w + 7) / 8);
    int x, yy, xx;
    for (x = 0; x < im->w; x++) {
        int r = VETO_R;
        if (!(bits[x >> 3] >> (x & 7) & 1)) {
            if (!bits[x >> 3])
                x |= 7; /* the next byte */
            continue;
        }
        if (orig &&
            memcmp(im->data + (size_t)y * im->stride + 3 * (size_t)x,
                   orig->data + (size_t)y * orig->stride + 3 * (size_t)x,
                   3) != 0)
            r = VETO_R_TINT;
        for (yy = y - r; yy <= y + r; yy++) {
            uint8_t *row;
            if (yy < ylo || yy >= yhi)
                continue;
            row = s->data + (size_t)yy * s->stride;
            for (xx = x - r; xx <= x + r; xx++)
                if (xx >= 0 && xx < im->w)
                    row[xx] = 0;
        }
    }
}

static int strength_pass(const td_image *im, const td_binarise_params *p,
                         td_grid_u8 *s, uint64_t *hist, double frac_end,
                         td_palette *pal, uint8_t **other, td_ctx *cx)
{
    strength_ctx sc = {p, im, NULL};
    uint8_t *veto = NULL, *vb = NULL;
    int b, nb, rc = 0;
    int vr = p->veto_im ? VETO_R_TINT : VETO_R;
    if (im->channels == 3 &&
        (p->ink == TD_INK_BROWN_HUE || p->ink == TD_INK_BROWN ||
         p->ink == TD_INK_AUTO)) {
        sc.lut = td_malloc(LUT_SIZE, cx);
        if (!sc.lut)
            return TD_ENOMEM;
        if (p->ink == TD_INK_BROWN_HUE) {
            brown_lut_build(sc.lut);
        } else {
            if (p->palette)
                *pal = *p->palette;
            else if ((rc = td_palette_find(im, pal, cx)) != 0)
                goto fail;
            if (p->palette
                    ? pal->chosen < 0
                    : td_palette_choose(pal, p->ink == TD_INK_BROWN) < 0) {
                rc = td_seterr(cx, TD_EFORMAT,
                               "no ink found: the colour scan is paper "
                               "and tints only (try --ink dark)");
                goto fail;
            }
            td_palette_lut(pal, sc.lut);
            if (!(veto = td_malloc(LUT_SIZE, cx))) {
                rc = TD_ENOMEM;
                goto fail;
            }
            td_palette_veto_lut(pal, veto);
        }
    }
    /* in bands on threads: the strength, then the veto (each band
       clears its own rows about the vetoed pixels of its rows and vr
       beyond), then the histogram; the serial pass's bytes (each step a
       function of the rows before it); 10000^2 grey sheet 0.35 -> 0.2 s
       (most of it the kernel clearing the mask's fresh pages) */
    nb = (im->h + BAND_ROWS - 1) / BAND_ROWS;
#pragma omp parallel for schedule(dynamic)
    for (b = 0; b < nb; b++) {
        int y0 = b * BAND_ROWS,
            n = im->h - y0 < BAND_ROWS ? im->h - y0 : BAND_ROWS;
        td_ctx q;
        td_ctx_init(&q);
        if (strength_rows(&sc, s, y0, n, &q) != 0) {
#pragma omp critical(strength_error)
            if (rc == 0)
                rc = td_seterr(cx, q.code, "%s", q.msg);
        }
    }
    if (rc != 0 || (rc = td_progress(cx, "binarise", 0.5 * frac_end)) != 0)
        goto fail;
    if (veto &&
        (rc = veto_bits(p->veto_im ? p->veto_im : im, veto, &vb, cx)) != 0)
        goto fail;
    if (vb) {
#pragma omp parallel for schedule(dynamic)
        for (b = 0; b < nb; b++) {
            int y0 = b * BAND_ROWS,
                y1 = im->h - y0 < BAND_ROWS ? im->h : y0 + BAND_ROWS, v;
            for (v = y0 - vr > 0 ? y0 - vr : 0;
                 v < (y1 + vr < im->h ? y1 + vr : im->h); v++)
                veto_row(p->veto_im ? p->veto_im : im, p->veto_im ? im : NULL,
                         vb, s, v, y0, y1);
        }
    }
    if (hist) {
        memset(hist, 0, 256 * sizeof *hist);
#pragma omp parallel
        {
            uint64_t h4[4][256];
            int v, k;
            memset(h4, 0, sizeof h4);
#pragma omp for schedule(static)
            for (v = 0; v < im->h; v++)
                hist_row(s->data + (size_t)v * s->stride, im->w, h4);
#pragma omp critical(strength_hist)
            for (k = 0; k < 256; k++)
                hist[k] += h4[0][k] + h4[1][k] + h4[2][k] + h4[3][k];
        }
    }
    rc = td_progress(cx, "binarise", frac_end);
fail:
    free(sc.lut);
    free(veto);
    if (rc == 0 && other)
        *other = vb;
    else
        free(vb);
    return rc;
}

/* ---- checks -------------------------------------------------------------- */

static int check_image(const td_image *im, const td_binarise_params *p,
                       const td_grid_u8 *out, td_ctx *cx)
{
    if (!im || !im->data || (im->channels != 1 && im->channels != 3) ||
        im->w <= 0 || im->h <= 0 ||
        im->stride < (size_t)im->w * (size_t)im->channels)
        return td_seterr(cx, TD_EINVAL, "binarise: invalid image");
    if (!out || !out->data || out->w != im->w || out->h != im->h ||
        out->stride < (size_t)out->w)
        return td_seterr(cx, TD_EINVAL, "binarise: mask must be a %d x %d grid",
                         im->w, im->h);
    if (p->veto_im && (p->veto_im->w != im->w || p->veto_im->h != im->h ||
                       p->veto_im->channels != 3 || im->channels != 3 ||
                       p->veto_im->stride < 3 * (size_t)im->w))
        return td_seterr(cx, TD_EINVAL,
                         "binarise: the veto image must be RGB, %d x %d", im->w,
                         im->h);
    if (im->channels == 1 &&
        (p->ink == TD_INK_BROWN || p->ink == TD_INK_BROWN_HUE))
        return td_seterr(cx, TD_EINVAL, "--ink brown needs a colour scan");
    if (im->channels == 1 && p->ink == TD_INK_RGB)
        return td_seterr(cx, TD_EINVAL, "--ink R,G,B needs a colour scan");
    if (p->ink == TD_INK_RGB && (p->rgb_tol < 1 || p->rgb_tol > 442))
        return td_seterr(cx, TD_EINVAL, "--ink: tolerance %d (1..442)",
                         p->rgb_tol);
    return 0;
}

static int check_params(const td_binarise_params *p, td_ctx *cx)
{
    if (p->thr == TD_THR_FIXED && (p->thr_value < 0 || p->thr_value > 255))
        return td_seterr(cx, TD_EINVAL, "--threshold %d (0..255)",
                         p->thr_value);
    if (p->thr == TD_THR_SAUVOLA &&
        (p->sauvola_window < 3 || p->sauvola_window > 181 ||
         p->sauvola_window % 2 == 0 ||
         !(p->sauvola_k > 0.0 && p->sauvola_k <= 1.0)))
        return td_seterr(cx, TD_EINVAL,
                         "sauvola: window %d (odd, 3..181), k %g (0..1]",
                         p->sauvola_window, p->sauvola_k);
    if (p->min_speck < 0)
        return td_seterr(cx, TD_EINVAL, "--min-speck %d (>= 0)", p->min_speck);
    return 0;
}

int td_binarise_strength(const td_image *im, const td_binarise_params *p,
                         td_grid_u8 *s, td_ctx *cx)
{
    td_palette pal;
    int rc = check_image(im, p, s, cx);
    return rc != 0 ? rc : strength_pass(im, p, s, NULL, 1.0, &pal, NULL, cx);
}

/* ---- thresholds ---------------------------------------------------------- */

/* Otsu's level on the histogram, refusing sheets without ink: when the two
 * classes' means are closer than TD_BINARISE_MIN_CONTRAST, Otsu has split
 * paper noise (or a smooth shading), not ink from paper. */
static int otsu_level(const uint64_t *hist, int *t, td_ctx *cx)
{
    double n0 = 0, s0 = 0, n1 = 0, s1 = 0, sep;
    int i, rc = td_cv_otsu_hist(hist, t, cx);
    if (rc != 0)
        return rc;
    for (i = 0; i < 256; i++) {
        if (i <= *t) {
            n0 += (double)hist[i];
            s0 += (double)hist[i] * i;
        } else {
            n1 += (double)hist[i];
            s1 += (double)hist[i] * i;
        }
    }
    sep = n0 > 0 && n1 > 0 ? s1 / n1 - s0 / n0 : 0.0;
    if (sep < TD_BINARISE_MIN_CONTRAST)
        return td_seterr(cx, TD_EFORMAT,
                         "no ink found (is --ink right?): ink and paper "
                         "differ by %.0f levels, fewer than %d",
                         sep, TD_BINARISE_MIN_CONTRAST);
    return 0;
}

/* ---- the local ink level (ours) ------------------------------------------
 *
 * Printed sheets fade unevenly: where the contour ink came out pale, its
 * lines' cores are as weak as the flanks of the dark lines elsewhere and
 * a global level keeps only broken threads of them.  Per tile of
 * LOCAL_TILE px, the ink level L is the LOCAL_PCT percentile of the
 * strengths over t/2 (the cores of the tile's strongest lines); where it
 * is under the sheet's (the same percentile over every tile), the tile
 * thresholds at t L / L_sheet, down to LOCAL_MIN t; tiles with fewer than
 * LOCAL_COUNT such pixels, and every tile where the ink is as strong as
 * the sheet's, keep t.  Thresholds are interpolated bilinearly between
 * tile centres.  A sheet printed evenly keeps t everywhere (no map). */
#define LOCAL_TILE 64
#define LOCAL_PCT 0.98
#define LOCAL_MIN 0.4
#define LOCAL_COUNT 32
#define LOCAL_BINS 64

typedef struct level_map {
    int tw, th; /* tiles across and down */
    float *f;   /* per tile: the share of t it thresholds at, <= 1 */
} level_map;

static int pct_bin(const uint32_t *h, double pct, uint64_t n)
{
    uint64_t acc = 0;
    int b;
    for (b = 0; b < LOCAL_BINS - 1; b++)
        if ((acc += h[b]) >= pct * (double)n)
            break;
    return b;
}

/* The level map of strength image m at level t; lm->f NULL when every
 * tile keeps t. */
static int level_map_make(const td_grid_u8 *m, int t, level_map *lm, td_ctx *cx)
{
    int tw = (m->w + LOCAL_TILE - 1) / LOCAL_TILE,
        th = (m->h + LOCAL_TILE - 1) / LOCAL_TILE, j, any = 0, lo = t / 2;
    size_t nt = (size_t)tw * th, k;
    uint32_t *h = td_calloc(nt * LOCAL_BINS + 1, sizeof *h, cx);
    uint32_t all[LOCAL_BINS];
    uint64_t nall = 0;
    double lg;
    lm->tw = tw, lm->th = th, lm->f = NULL;
    if (!h)
        return TD_ENOMEM;
#pragma omp parallel for schedule(dynamic, 1)
    for (j = 0; j < th; j++) {
        int y, x;
        for (y = j * LOCAL_TILE; y < m->h && y < (j + 1) * LOCAL_TILE; y++) {
            const uint8_t *row = m->data + (size_t)y * m->stride;
            uint32_t *hr = h + (size_t)j * tw * LOCAL_BINS;
            for (x = 0; x < m->w; x++)
                if (row[x] > lo)
                    hr[(size_t)(x / LOCAL_TILE) * LOCAL_BINS + (row[x] >> 2)]++;
        }
    }
    memset(all, 0, sizeof all);
    for (k = 0; k < nt; k++) {
        int b;
        for (b = 0; b < LOCAL_BINS; b++)
            all[b] += h[k * LOCAL_BINS + b], nall += h[k * LOCAL_BINS + b];
    }
    lg = 4.0 * pct_bin(all, LOCAL_PCT, nall) + 2.0;
    if (nall == 0 || !(lm->f = td_malloc(nt * sizeof *lm->f, cx))) {
        free(h);
        return nall == 0 ? 0 : TD_ENOMEM;
    }
    for (k = 0; k < nt; k++) {
        const uint32_t *hk = h + k * LOCAL_BINS;
        uint64_t n = 0;
        int b;
        double f = 1.0;
        for (b = 0; b < LOCAL_BINS; b++)
            n += hk[b];
        if (n >= LOCAL_COUNT)
            f = fmin(1.0, fmax(LOCAL_MIN,
                               (4.0 * pct_bin(hk, LOCAL_PCT, n) + 2.0) / lg));
        lm->f[k] = (float)f;
        any |= f < 1.0;
    }
    free(h);
    if (!any) {
        free(lm->f);
        lm->f = NULL;
    }
    return 0;
}

/* Row y's thresholds into tr (w ints, lm->f set): t times the map's
 * share, interpolated between tile centres (never above t).  Along the
 * row the share moves linearly from one tile centre to the next. */
static void level_row(const level_map *lm, int t, int y, int w, int *tr)
{
    const int T = LOCAL_TILE, h0 = LOCAL_TILE / 2;
    double gy = (y + 0.5) / T - 0.5, wy, f0, f1, step;
    int j0, j1, i, x = 0;
    gy = gy < 0 ? 0 : gy > lm->th - 1 ? lm->th - 1 : gy;
    j0 = (int)gy, j1 = j0 + 1 < lm->th ? j0 + 1 : j0, wy = gy - j0;
#define ROWF(i)                                                                \
    (lm->f[(size_t)j0 * lm->tw + (i)] * (1 - wy) +                             \
     lm->f[(size_t)j1 * lm->tw + (i)] * wy)
    f0 = ROWF(0);
    for (; x < w && x < h0; x++) /* before the first centre */
        tr[x] = (int)(t * f0 + 0.5);
    for (i = 0; i + 1 < lm->tw; i++) { /* from centre i to centre i + 1 */
        f1 = ROWF(i + 1);
        step = (f1 - f0) / T;
        for (; x < w && x < (i + 1) * T + h0; x++)
            tr[x] = (int)(t * (f0 + step * (x - i * T - h0 + 0.5)) + 0.5);
        f0 = f1;
    }
    for (; x < w; x++) /* after the last */
        tr[x] = (int)(t * f0 + 0.5);
#undef ROWF
    for (x = 0; x < w; x++)
        tr[x] = tr[x] > t ? t : tr[x];
}

static int apply_level(td_grid_u8 *m, int t, const level_map *lm, td_ctx *cx)
{
    int x, y;
    int *tr = NULL;
    if (lm->f && !(tr = td_malloc((size_t)m->w * sizeof *tr, cx)))
        return TD_ENOMEM;
    for (y = 0; y < m->h; y++) {
        uint8_t *row = m->data + (size_t)y * m->stride;
        if (tr) {
            level_row(lm, t, y, m->w, tr);
            for (x = 0; x < m->w; x++)
                row[x] = row[x] > tr[x];
        } else
            for (x = 0; x < m->w; x++)
                row[x] = row[x] > t;
    }
    free(tr);
    return 0;
}

/* ---- split touching lines (ours) ---------------------------------------- */

#define SPLIT_R 2 /* rows kept above and below the row being thresholded */

/* Is the strength at c (over ink level t, under the ink's core level hi) a
 * seam of the ink between two lines: along one of four directions d, each
 * side within 2 px is at least margin stronger while the next pixel on
 * each side is not margin or more weaker (a seam is a dip, not the flank
 * of a thin line whose neighbours 2 px off are darker: on a crisp sheet
 * with contours 3 px apart every flank pixel passed the first test and
 * whole lines were split away), and d lies within 45
 * degrees of the ink's normal there (the structure tensor of the strength
 * gradients over 3 x 3 px: lines run across a seam, while a dip of noise
 * or aliasing inside one thin line has the line's ink on both sides along
 * the line).  rows[k] is row y + k - SPLIT_R of the strength (NULL off the
 * sheet). */
static int is_valley(const uint8_t *const *rows, int w, int x, int t, int hi,
                     int margin)
{
    static const int dir[4][3] = {/* dx, dy, and cos 2a, sin 2a of d */
                                  {1, 0, 1},
                                  {0, 1, -1},
                                  {1, 1, 2},
                                  {1, -1, -2}};
    int c = rows[SPLIT_R][x], need = c + margin, k;
    long jxx = 0, jxy = 0, jyy = 0;
    if (c <= t || c >= hi || x < 2 || x + 2 >= w || !rows[0] ||
        !rows[2 * SPLIT_R])
        return 0;
    for (k = 0; k < 4; k++) {
        int dx = dir[k][0], dy = dir[k][1], side, ok = 1;
        for (side = -1; side <= 1 && ok; side += 2) {
            int a = rows[SPLIT_R + side * dy][x + side * dx];
            int b = rows[SPLIT_R + 2 * side * dy][x + 2 * side * dx];
            ok = (a > b ? a : b) >= need && a >= c - margin;
        }
        if (!ok)
            continue;
        if (jxx == 0 && jyy == 0) {
            int i, j;
            for (j = -1; j <= 1; j++)
                for (i = -1; i <= 1; i++) {
                    long gx = rows[SPLIT_R + j][x + i + 1] -
                              rows[SPLIT_R + j][x + i - 1];
                    long gy = rows[SPLIT_R + j + 1][x + i] -
                              rows[SPLIT_R + j - 1][x + i];
                    jxx += gx * gx;
                    jxy += gx * gy;
                    jyy += gy * gy;
                }
        }
        /* cos 2(angle(d) - angle(normal)) >= 0, times the tensor's size */
        if (dir[k][2] == 1 ? jxx - jyy >= 0
            : dir[k][2] == -1 ? jyy - jxx >= 0
            : dir[k][2] == 2  ? jxy >= 0
                              : jxy <= 0)
            return 1;
    }
    return 0;
}

/* Ink at column x of row k (0 .. 2 SPLIT_R) of rows, at level t. */
static int ink_at(const uint8_t *const *rows, int w, int k, int x, int t)
{
    return k >= 0 && k <= 2 * SPLIT_R && rows[k] && x >= 0 && x < w &&
           rows[k][x] > t;
}

/* Whether the ink pixel at (row k, column x) is inside a line that does
 * not need the pixel at (ek, ex): at least two other ink neighbours, in one
 * 8-connected piece round it (Yokoi's 8-connectivity number of its ring,
 * (ek, ex) left out, is 1), so removing it keeps them connected; one
 * such neighbour would make it the end of a chain (a thin diagonal line
 * steps corner to corner too). */
static int simple_without(const uint8_t *const *rows, int w, int k, int x,
                          int ek, int ex, int t)
{
    static const int ring[8][2] = {{0, 1},  {-1, 1}, {-1, 0}, {-1, -1},
                                   {0, -1}, {1, -1}, {1, 0},  {1, 1}};
    int b[8], i, nc = 0, cnt = 0;
    for (i = 0; i < 8; i++) {
        int kk = k + ring[i][0], xx = x + ring[i][1];
        int n = !(kk == ek && xx == ex) && ink_at(rows, w, kk, xx, t);
        b[i] = !n;
        cnt += n;
    }
    for (i = 0; i < 8; i += 2)
        nc += b[i] - b[i] * b[(i + 1) & 7] * b[(i + 2) & 7];
    return cnt >= 2 && cnt < 8 && nc == 1;
}

/* Whether the ink pixel at column x of the middle row touches another
 * ink pixel only diagonally across a light corner, and is the one of the
 * two to cut.  Two crisp lines a pixel apart meet corner to corner where
 * their paper gap steps diagonally: the two pixels beside the contact are
 * paper and the contact is ink, but the mean of the four strengths (the
 * level at the shared corner) is under t, so the ink does not run across
 * it.  When both lie inside their lines (simple_without), the weaker goes
 * (the upper one at a tie). */
static int light_contact(const uint8_t *const *rows, int w, int x, int t)
{
    int c = SPLIT_R, dy, dx;
    if (!ink_at(rows, w, c, x, t))
        return 0;
    for (dy = -1; dy <= 1; dy += 2)
        for (dx = -1; dx <= 1; dx += 2) {
            int sp, sq, pfirst;
            if (!ink_at(rows, w, c + dy, x + dx, t) ||
                ink_at(rows, w, c, x + dx, t) ||
                ink_at(rows, w, c + dy, x, t))
                continue;
            sp = rows[c][x];
            sq = rows[c + dy][x + dx];
            if (sp + sq + rows[c][x + dx] + rows[c + dy][x] > 4 * t)
                continue;
            pfirst = sp < sq || (sp == sq && dy > 0);
            if (simple_without(rows, w, c, x, c + dy, x + dx, t) &&
                simple_without(rows, w, c + dy, x + dx, c, x, t) && pfirst)
                return 1;
        }
    return 0;
}

/* Threshold at t as apply_level, but ink pixels in a valley (is_valley)
 * become 2, and then (the mask is 8-connected ink) every diagonal contact
 * across a valley is cut too, so two lines whose blurred ink runs together
 * with a lighter seam between them stay apart.  Leaves 0/1.
 *
 * In SPLIT_BANDS bands of rows on threads, with the bytes of one pass down
 * the rows: each band reads the rows beside it as they were before
 * (copies of each band edge's SPLIT_R rows either side, taken first), and
 * the diagonal pass of a band's last row reads the next band's first row
 * as the threshold left it (a copy taken between the two passes). */
#define SPLIT_BANDS 16

typedef struct split_band {
    const td_grid_u8 *m;
    int y0, y1;          /* the band's rows */
    const uint8_t *above; /* rows y0 - R .. y0 - 1 before the pass */
    const uint8_t *below; /* rows y1 .. y1 + R - 1 before the pass */
} split_band;

/* Row y of the strength as it was before the threshold, for band b. */
static const uint8_t *split_row(const split_band *b, int y)
{
    if (y < b->y0)
        return b->above + (size_t)(y - (b->y0 - SPLIT_R)) * b->m->w;
    if (y >= b->y1)
        return b->below + (size_t)(y - b->y1) * b->m->w;
    return b->m->data + (size_t)y * b->m->stride;
}

/* The first pass over band b: 2 in a valley, else ink above t. */
static void split_threshold(const split_band *b, uint8_t *ring, int t, int hi,
                            int margin, const level_map *lm, int *tr)
{
    const td_grid_u8 *m = b->m;
    const uint8_t *rows[2 * SPLIT_R + 1];
    int x, y, k, n = 2 * SPLIT_R + 1;
    for (y = b->y0 - SPLIT_R; y < b->y0 + SPLIT_R; y++)
        if (y >= 0 && y < m->h)
            memcpy(ring + (size_t)(((y % n) + n) % n) * m->w, split_row(b, y),
                   (size_t)m->w);
    for (y = b->y0; y < b->y1; y++) {
        uint8_t *row = m->data + (size_t)y * m->stride;
        if (y + SPLIT_R < m->h)
            memcpy(ring + (size_t)((y + SPLIT_R) % n) * m->w,
                   split_row(b, y + SPLIT_R), (size_t)m->w);
        for (k = 0; k < n; k++) {
            int yy = y + k - SPLIT_R;
            rows[k] = yy < 0 || yy >= m->h ? NULL
                                            : ring + (size_t)(yy % n) * m->w;
        }
        if (tr) {
            level_row(lm, t, y, m->w, tr);
            for (x = 0; x < m->w; x++)
                row[x] = is_valley(rows, m->w, x, tr[x], hi, margin) ? 2
                         : light_contact(rows, m->w, x, tr[x])       ? 3
                                                      : rows[SPLIT_R][x] > tr[x];
        } else
            for (x = 0; x < m->w; x++)
                row[x] = is_valley(rows, m->w, x, t, hi, margin) ? 2
                         : light_contact(rows, m->w, x, t)       ? 3
                                                          : rows[SPLIT_R][x] > t;
    }
}

/* The second pass over band b (rows y0 .. y1 - 1 against the row below;
 * next: row y1 as the first pass left it), then 0/1. */
static void split_diagonals(const split_band *b, const uint8_t *next)
{
    const td_grid_u8 *m = b->m;
    int x, y;
    for (y = b->y0; y < b->y1 && y + 1 < m->h; y++) {
        uint8_t *a = m->data + (size_t)y * m->stride;
        const uint8_t *bb = y + 1 < b->y1 ? a + m->stride : next;
        for (x = 0; x + 1 < m->w; x++) {
            if (a[x] == 1 && bb[x + 1] == 1 && a[x + 1] != 1 && bb[x] != 1 &&
                (a[x + 1] == 2 || bb[x] == 2))
                a[x] = 2;
            else if (a[x + 1] == 1 && bb[x] == 1 && a[x] != 1 &&
                     bb[x + 1] != 1 && (a[x] == 2 || bb[x + 1] == 2))
                a[x + 1] = 2;
        }
    }
}

/* Band j of nb over m; saved holds per band edge its rows either side
 * (edge bytes) and the edge row after the threshold (w bytes). */
static split_band band_of(td_grid_u8 *m, int j, int nb, uint8_t *saved,
                          size_t edge, size_t w)
{
    split_band b;
    b.m = m;
    b.y0 = (int)((long)j * m->h / nb);
    b.y1 = (int)((long)(j + 1) * m->h / nb);
    b.above = saved + (size_t)j * (edge + w);
    b.below = j + 1 < nb ? saved + (size_t)(j + 1) * (edge + w) + SPLIT_R * w
                         : NULL; /* past the sheet: never read */
    return b;
}

static int apply_level_split(td_grid_u8 *m, int t, int hi, int margin,
                             const level_map *lm, uint8_t *seams, td_ctx *cx)
{
    int nb = m->h >= 64 * SPLIT_BANDS ? SPLIT_BANDS : 1, k, fail = 0, y, x;
    size_t w = (size_t)m->w, edge = 2 * SPLIT_R * w;
    /* per band edge k (1..nb-1): SPLIT_R rows either side as they are, then
     * the edge row after the threshold */
    uint8_t *saved = td_malloc((size_t)nb * (edge + w) + 1, cx);
    if (!saved)
        return TD_ENOMEM;
    for (k = 1; k < nb; k++) {
        int e = (int)((long)k * m->h / nb), r;
        for (r = 0; r < 2 * SPLIT_R; r++)
            if (e - SPLIT_R + r >= 0 && e - SPLIT_R + r < m->h)
                memcpy(saved + (size_t)k * (edge + w) + (size_t)r * w,
                       m->data + (size_t)(e - SPLIT_R + r) * m->stride, w);
    }
#pragma omp parallel reduction(| : fail)
    {
        uint8_t *ring = malloc((size_t)(2 * SPLIT_R + 1) * w);
        int *tr = lm->f ? malloc(w * sizeof *tr) : NULL;
        int j;
        fail |= !ring || (lm->f && !tr);
#pragma omp for schedule(dynamic, 1)
        for (j = 0; j < nb; j++) {
            split_band b = band_of(m, j, nb, saved, edge, w);
            if (ring && (tr || !lm->f))
                split_threshold(&b, ring, t, hi, margin, lm, tr);
            if (ring && j > 0) /* this band's first row, thresholded */
                memcpy(saved + (size_t)j * (edge + w) + edge,
                       m->data + (size_t)b.y0 * m->stride, w);
        }
#pragma omp for schedule(dynamic, 1)
        for (j = 0; j < nb; j++) {
            split_band b = band_of(m, j, nb, saved, edge, w);
            if (ring) /* the next band's first row as the threshold left it */
                split_diagonals(&b, b.below ? b.below - SPLIT_R * w + edge
                                            : NULL);
        }
        free(ring);
        free(tr);
    }
    free(saved);
    if (fail)
        return td_seterr(cx, TD_ENOMEM, "binarise: out of memory");
#pragma omp parallel for schedule(static) private(x)
    for (y = 0; y < m->h; y++) {
        uint8_t *row = m->data + (size_t)y * m->stride;
        uint8_t *sb =
            seams ? seams + (size_t)y * (((size_t)m->w + 7) / 8) : NULL;
        for (x = 0; x < m->w; x++) {
            if (sb && row[x] == 2)
                sb[x >> 3] |= (uint8_t)(1u << (x & 7));
            row[x] = row[x] == 1;
        }
    }
    return 0;
}

static int any_ink(const td_grid_u8 *m)
{
    int y;
    for (y = 0; y < m->h; y++)
        if (memchr(m->data + (size_t)y * m->stride, 1, (size_t)m->w))
            return 1;
    return 0;
}

/* Shim calls report their own stage names; while one runs, its progress is
 * mapped onto [a, b] of stage "binarise". */
typedef struct remap {
    td_progress_fn fn;
    void *user;
    double a, b;
} remap;

static int remap_cb(const char *stage, double frac, void *user)
{
    const remap *r = user;
    (void)stage;
    return r->fn("binarise", r->a + (r->b - r->a) * frac, r->user);
}

static void remap_begin(td_ctx *cx, remap *r, double a, double b)
{
    r->fn = cx ? cx->progress : NULL;
    r->user = cx ? cx->progress_user : NULL;
    r->a = a;
    r->b = b;
    if (r->fn) {
        cx->progress = remap_cb;
        cx->progress_user = r;
    }
}

static void remap_end(td_ctx *cx, const remap *r)
{
    if (r->fn) {
        cx->progress = r->fn;
        cx->progress_user = r->user;
    }
}

/* The seam margin: at least min, and at least 3 noise deviations of the
 * sheet, so noise alone makes no seam.  The noise is measured on the paper
 * (pairs of horizontal neighbours both under t, every 4th row): the median
 * of |difference| is 0.954 sigma for Gaussian noise. */
static int split_margin(const td_grid_u8 *m, int t, int min)
{
    uint64_t h[256] = {0}, n = 0, acc = 0;
    int x, y, med;
    for (y = 0; y < m->h; y += 4) {
        const uint8_t *row = m->data + (size_t)y * m->stride;
        for (x = 0; x + 1 < m->w; x++)
            if (row[x] <= t && row[x + 1] <= t) {
                h[abs(row[x] - row[x + 1])]++;
                n++;
            }
    }
    for (med = 0; med < 255 && (acc += h[med]) * 2 < n; med++)
        ;
    return (int)fmax(min, 3.0 * med / 0.954);
}

/* The share of half-tone strengths to ink at level t (contract in
 * binarise.h). */
static double halftone_share(const uint64_t *hist, int t)
{
    double np = 0, sp = 0, ni = 0, si = 0, mid = 0, pap, ink;
    int i;
    for (i = 0; i < 256; i++) {
        if (i <= t)
            np += (double)hist[i], sp += (double)hist[i] * i;
        else
            ni += (double)hist[i], si += (double)hist[i] * i;
    }
    if (np <= 0 || ni <= 0)
        return -1;
    pap = sp / np;
    ink = si / ni;
    for (i = 0; i < 256; i++)
        if (i >= pap + 0.25 * (ink - pap) && i <= pap + 0.75 * (ink - pap))
            mid += (double)hist[i];
    return mid / ni;
}

/* ---- faded line cores (ours; colour scans, with the local level) -------
 * Where the print faded, a contour's core is a thin ridge of strength
 * (30-70 over a paper of 0) that the level passes only in broken threads.
 * A pixel is a core when along one of four directions it is at least as
 * strong as both neighbours and CORE_MARGIN stronger than both pixels 2 px
 * off (a ridge up to 3 px wide; a line's flank, the gap between two
 * touching lines and the paper's noise are not), and at least CORE_LOW t.
 * Cores 8-connected to the thresholded ink, directly or through other
 * cores, are ink (hysteresis along the line into the faded patch); the
 * seams the split cut stay open. */
#define CORE_LOW 0.4
#define CORE_MARGIN 10
#define CORE_DROP 0.4

static int core_at(const uint8_t *const *r, int w, int x, int lo)
{
    static const int d[4][2] = {{1, 0}, {0, 1}, {1, 1}, {1, -1}};
    int s = r[2][x], k, m;
    if (s < lo || x < 2 || x >= w - 2)
        return 0;
    m = (int)(CORE_DROP * s) > CORE_MARGIN ? (int)(CORE_DROP * s) : CORE_MARGIN;
    for (k = 0; k < 4; k++) {
        int dx = d[k][0], dy = d[k][1];
        int a1 = r[2 - dy][x - dx], b1 = r[2 + dy][x + dx];
        int a2 = r[2 - 2 * dy][x - 2 * dx], b2 = r[2 + 2 * dy][x + 2 * dx];
        if (s >= a1 && s >= b1 && s >= a2 + m && s >= b2 + m)
            return 1;
    }
    return 0;
}

/* The cores of strength image m at level t, in the tiles the level map
 * lowers (lm; none when it lowers none), as packed bits (rows of (w + 7)
 * / 8 bytes), or NULL when out of memory. */
static uint8_t *cores_find(const td_grid_u8 *m, int t, const level_map *lm,
                           td_ctx *cx)
{
    size_t stride = ((size_t)m->w + 7) / 8;
    uint8_t *bits = td_calloc(stride * (size_t)m->h + 1, 1, cx);
    int y, lo = (int)(CORE_LOW * t + 0.5);
    if (!bits)
        return NULL;
#pragma omp parallel for schedule(static)
    for (y = 2; y < m->h - 2; y++) {
        const uint8_t *r[5];
        const float *fr = lm->f + (size_t)(y / LOCAL_TILE) * lm->tw;
        uint8_t *b = bits + (size_t)y * stride;
        int k, x;
        for (k = 0; k < 5; k++)
            r[k] = m->data + (size_t)(y - 2 + k) * m->stride;
        for (x = 2; x < m->w - 2; x++)
            if (fr[x / LOCAL_TILE] < 1.0f && core_at(r, m->w, x, lo))
                b[x >> 3] |= (uint8_t)(1u << (x & 7));
    }
    return bits;
}

#define BIT(b, st, x, y) (((b)[(size_t)(y) * (st) + ((x) >> 3)] >> ((x)&7)) & 1)

/* Push pixel index at onto the stack (*st, *n of *cap); 0 or TD_ENOMEM. */
static int push_px(size_t **st, size_t *n, size_t *cap, size_t at)
{
    if (*n == *cap) {
        size_t *q = realloc(*st, 2 * *cap * sizeof *q);
        if (!q)
            return TD_ENOMEM;
        *st = q, *cap *= 2;
    }
    (*st)[(*n)++] = at;
    return 0;
}

/* Mask m (0/1) grown into the cores 8-connected to it (not into seams):
 * every core beside the ink becomes ink, then the cores beside those. */
static int cores_grow(td_grid_u8 *m, const uint8_t *cores, const uint8_t *seams,
                      td_ctx *cx)
{
    size_t stride = ((size_t)m->w + 7) / 8, n = 0, cap = 4096, w = (size_t)m->w;
    size_t *stack = td_malloc(cap * sizeof *stack, cx);
    int x, y, rc = 0;
    if (!stack)
        return TD_ENOMEM;
    for (y = 0; y < m->h && rc == 0; y++) /* seeds: cores beside the ink */
        for (x = 0; x < m->w && rc == 0; x++) {
            int u, v, any = 0;
            if (!BIT(cores, stride, x, y) ||
                m->data[(size_t)y * m->stride + x] ||
                (seams && BIT(seams, stride, x, y)))
                continue;
            for (v = y - 1; v <= y + 1 && !any; v++)
                for (u = x - 1; u <= x + 1 && !any; u++)
                    any = u >= 0 && v >= 0 && u < m->w && v < m->h &&
                          m->data[(size_t)v * m->stride + u] == 1;
            if (any) {
                m->data[(size_t)y * m->stride + x] = 2; /* ink after the scan */
                rc = push_px(&stack, &n, &cap, (size_t)y * w + (size_t)x);
            }
        }
    for (x = 0; x < (int)n; x++) /* the seeds became ink */
        m->data[(stack[x] / w) * m->stride + stack[x] % w] = 1;
    while (n > 0 && rc == 0) {
        size_t at = stack[--n];
        int x0 = (int)(at % w), y0 = (int)(at / w), u, v;
        for (v = y0 - 1; v <= y0 + 1 && rc == 0; v++)
            for (u = x0 - 1; u <= x0 + 1 && rc == 0; u++) {
                uint8_t *px;
                if (u < 0 || v < 0 || u >= m->w || v >= m->h ||
                    !BIT(cores, stride, u, v) ||
                    (seams && BIT(seams, stride, u, v)))
                    continue;
                px = m->data + (size_t)v * m->stride + u;
                if (*px)
                    continue;
                *px = 1;
                rc = push_px(&stack, &n, &cap, (size_t)v * w + (size_t)u);
            }
    }
    free(stack);
    return rc ? td_seterr(cx, TD_ENOMEM, "binarise: out of memory") : 0;
}
#undef BIT

/* Threshold the strength image held in m, in place. */
static int threshold(td_grid_u8 *m, const td_binarise_params *p,
                     const uint64_t *hist, int local, uint8_t *seams,
                     double *halftone, uint8_t **cores_out, td_ctx *cx)
{
    remap r;
    level_map lm = {0, 0, NULL};
    uint8_t *cores = NULL;
    int t, rc;
    if (p->thr == TD_THR_SAUVOLA) {
        remap_begin(cx, &r, 0.4, 0.8);
        rc = td_cv_sauvola(m, p->sauvola_window, p->sauvola_k, m, cx);
        remap_end(cx, &r);
        return rc;
    }
    t = p->thr_value;
    if (p->thr == TD_THR_OTSU && (rc = otsu_level(hist, &t, cx)) != 0)
        return rc;
    if (halftone)
        *halftone = halftone_share(hist, t);
    if (p->thr == TD_THR_OTSU && local &&
        (rc = level_map_make(m, t, &lm, cx)) != 0)
        return rc;
    if (lm.f && p->cores && !(cores = cores_find(m, t, &lm, cx))) {
        free(lm.f);
        return TD_ENOMEM;
    }
    if (p->split > 0) {
        /* the ink's core level: its mean */
        double n = 0, sum = 0;
        int i;
        for (i = t + 1; i < 256; i++)
            n += (double)hist[i], sum += (double)hist[i] * i;
        rc = apply_level_split(m, t, n > 0 ? (int)(sum / n) : 256,
                               split_margin(m, t, p->split), &lm, seams, cx);
    } else
        rc = apply_level(m, t, &lm, cx);
    free(lm.f);
    if (rc == 0)
        *cores_out = cores;
    else
        free(cores);
    return rc;
}

int td_binarise(const td_image *im, const td_binarise_params *p,
                td_grid_u8 *mask, td_ctx *cx)
{
    return td_binarise_pal(im, p, mask, NULL, cx);
}

int td_binarise_pal(const td_image *im, const td_binarise_params *p,
                    td_grid_u8 *mask, td_palette *pal_out, td_ctx *cx)
{
    return td_binarise_seams(im, p, mask, pal_out, NULL, NULL, NULL, cx);
}

int td_binarise_seams(const td_image *im, const td_binarise_params *p,
                      td_grid_u8 *mask, td_palette *pal_out, uint8_t *seams,
                      double *halftone, uint8_t **other, td_ctx *cx)
{
    uint64_t hist[256];
    td_palette pal;
    uint8_t *cores = NULL;
    remap r;
    int rc;
    memset(&pal, 0, sizeof pal);
    if (halftone)
        *halftone = -1;
    if (pal_out)
        memset(pal_out, 0, sizeof *pal_out);
    if (other)
        *other = NULL;
    if ((rc = check_image(im, p, mask, cx)) != 0 ||
        (rc = check_params(p, cx)) != 0)
        goto fail;
    rc = strength_pass(im, p, mask, hist, 0.4, &pal, other, cx);
    if (pal_out)
        *pal_out = pal;
    /* the local ink level on the palette's contour ink (printed colour
       sheets fade unevenly; on grey scans it broke the rough test sheet
       and a pinched contour) */
    if (rc != 0 ||
        (rc = threshold(mask, p, hist,
                        p->local_level && im->channels == 3 &&
                            (p->ink == TD_INK_AUTO || p->ink == TD_INK_BROWN),
                        seams, halftone, &cores, cx)) != 0)
        goto fail;
    if (p->min_speck > 1) {
        remap_begin(cx, &r, 0.8, 0.9);
        rc = td_cv_remove_specks(mask, p->min_speck, NULL, cx);
        remap_end(cx, &r);
        if (rc != 0)
            goto fail;
    }
    /* the faded cores grow from the ink the specks' removal left (a speck
       of a black glyph's rim would grow round the glyph) */
    if (cores && (rc = cores_grow(mask, cores, seams, cx)) != 0)
        goto fail;
    if (p->min_hole > 1) {
        remap_begin(cx, &r, 0.9, 1.0);
        rc = td_cv_fill_holes(mask, p->min_hole, NULL, cx);
        remap_end(cx, &r);
        if (rc != 0)
            goto fail;
    }
    if (!any_ink(mask)) {
        rc = td_seterr(cx, TD_EFORMAT, "no ink found (is --ink right?)");
        goto fail;
    }
    rc = td_progress(cx, "binarise", 1.0);
fail:
    free(cores);
    if (rc != 0 && other) {
        free(*other);
        *other = NULL;
    }
    return rc;
}

/* Contract in binarise.h. */
int td_binarise_other_ink(const td_image *im, const td_palette *pal,
                          uint8_t **bits, td_ctx *cx)
{
    uint8_t *veto;
    int rc;
    *bits = NULL;
    if (!pal || pal->n == 0 || pal->chosen < 0 || im->channels != 3)
        return 0;
    if (!(veto = td_malloc(LUT_SIZE, cx)))
        return TD_ENOMEM;
    td_palette_veto_lut(pal, veto);
    rc = veto_bits(im, veto, bits, cx);
    free(veto);
    return rc;
}
