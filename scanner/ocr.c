/* Reading printed height labels (contract and picture in ocr.h). */
#include "scanner/ocr.h"

#include "scanner/join.h"
#include "scanner/palette.h"
#include "src/core/core.h"

#include <tesseract/capi.h>

#include <ctype.h>
#include <omp.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_STRIP 200 /* px: the strip's longest side */

td_ocr_params td_ocr_defaults(void)
{
    td_ocr_params p;
    p.tessdata = NULL;
    p.min_conf = 0.4;
    p.digit_px = 32.0;
    p.ink = NULL;
    return p;
}

/* A spot height's dot: 5-40 px of ink, at most 7 px across, within 14 px
 * of its text. */
/* A read this confident is taken without trying other thresholds. */
#define SURE_READ 0.9
#define STRIP_EXTRA 40.0 /* px of strip beyond the label's pieces */
/* ... and when digits were read but none sure: the cluster's middle can
 * lie off the label's (Orkhon printed: "1875" cut to "187" and "875" at
 * 40 px) */
#define STRIP_LONG 60.0
#define BIN_LEVEL 0.35 /* the digits binarised: see binarise_digits */

enum { DOT_REACH = 14, DOT_MAX = 7, DOT_MIN_AREA = 5, DOT_MAX_AREA = 40 };

/* Luminance of im at (x, y), bilinear; paper outside.  With lut (the
 * contour ink's strength table, RGB scans): 255 minus the ink's strength,
 * the ink dark on white whatever the background. */
static double lum_at(const td_image *im, const uint8_t *lut, double x, double y)
{
    double fx, fy, v[4];
    long ix, iy;
    int k;
    x -= 0.5, y -= 0.5;
    ix = (long)floor(x), iy = (long)floor(y);
    fx = x - ix, fy = y - iy;
    for (k = 0; k < 4; k++) {
        long X = ix + (k & 1), Y = iy + (k >> 1);
        const uint8_t *q;
        if (X < 0 || Y < 0 || X >= im->w || Y >= im->h) {
            v[k] = 255;
            continue;
        }
        q = im->data + (size_t)Y * im->stride + (size_t)X * im->channels;
        v[k] = im->channels < 3 ? q[0]
               : lut            ? 255 - td_palette_lut_at(lut, q[0], q[1], q[2])
                                : 0.299 * q[0] + 0.587 * q[1] + 0.114 * q[2];
    }
    return (1 - fy) * ((1 - fx) * v[0] + fx * v[1]) +
           fy * ((1 - fx) * v[2] + fx * v[3]);
}

/* Otsu's threshold of n grey values (0..255). */
static double otsu(const double *g, size_t n)
{
    size_t hist[256] = {0}, i, w0 = 0;
    double sum = 0, s0 = 0, best = -1, t = 128;
    for (i = 0; i < n; i++) {
        int b = (int)g[i];
        hist[b < 0 ? 0 : b > 255 ? 255 : b]++;
        sum += g[i];
    }
    for (i = 0; i < 255; i++) {
        double m0, m1, v;
        w0 += hist[i];
        s0 += (double)i * hist[i];
        if (w0 == 0 || w0 == n)
            continue;
        m0 = s0 / w0;
        m1 = (sum - s0) / (n - w0);
        v = (double)w0 * (n - w0) * (m1 - m0) * (m1 - m0);
        if (v > best)
            best = v, t = i + 0.5;
    }
    return t;
}

/* One strip along a gap: grey g (w x h), the ink mask, kept components. */
typedef struct strip {
    double cx, cy, ux, uy; /* centre, chord direction */
    int w, h;
    double *g;
    int *lab; /* component label per px, 0: paper */
    unsigned char *keep;
    double ink, paper;
    int ch[64]; /* kept components' heights */
} strip;

static void strip_free(strip *s)
{
    free(s->g);
    free(s->lab);
    free(s->keep);
}

/* Scan px of strip cell (i, j): along the chord i, across j (down). */
static void strip_xy(const strip *s, double i, double j, double *x, double *y)
{
    double u = i + 0.5 - 0.5 * s->w, v = j + 0.5 - 0.5 * s->h;
    *x = s->cx + u * s->ux - v * s->uy;
    *y = s->cy + u * s->uy + v * s->ux;
}

/* Keep the digits of the kept components (cb: their boxes and labels):
 * a round one much lower than the tallest and beside the others (a spot
 * height's dot, a speck) is no digit, a flat one (a minus sign) is; b gets
 * the digits' box.
 * Returns how many stay. */
static int drop_dots(strip *s, int kept, int cb[64][5], int *b)
{
    int i, n = kept < 64 ? kept : 64, tallest = 0, m = 0;
    int x0 = s->w, x1 = -1; /* the tall components' span */
    for (i = 0; i < n; i++)
        tallest = s->ch[i] > tallest ? s->ch[i] : tallest;
    for (i = 0; i < n; i++)
        if (s->ch[i] >= 0.6 * tallest) {
            x0 = cb[i][0] < x0 ? cb[i][0] : x0;
            x1 = cb[i][2] > x1 ? cb[i][2] : x1;
        }
    b[0] = s->w, b[1] = s->h, b[2] = -1, b[3] = -1;
    for (i = 0; i < n; i++) {
        int wd = cb[i][2] - cb[i][0] + 1, ht = s->ch[i];
        /* beside the digits, not between them (a digit broken by noise
           leaves a low piece among the others) */
        if (ht < 0.6 * tallest && wd < 1.5 * ht &&
            (cb[i][2] < x0 || cb[i][0] > x1)) {
            s->keep[cb[i][4]] = 0;
            continue;
        }
        s->ch[m++] = ht;
        b[0] = cb[i][0] < b[0] ? cb[i][0] : b[0];
        b[1] = cb[i][1] < b[1] ? cb[i][1] : b[1];
        b[2] = cb[i][2] > b[2] ? cb[i][2] : b[2];
        b[3] = cb[i][3] > b[3] ? cb[i][3] : b[3];
    }
    return m + (kept > 64 ? kept - 64 : 0);
}

/* Pieces of ink within PIECE_GAP px of each other, one of them lower
 * than 0.6 of the tallest, are one glyph: a faint digit falls apart at
 * the threshold (a "5" into its bar and its bowl), and alone each piece
 * is too small to keep or taken for a dot beside the digits.  Two tall
 * pieces (two digits side by side) are never one. */
#define PIECE_GAP 2
#define MAX_PIECES 256

static int piece_root(int *par, int a)
{
    while (par[a] != a)
        a = par[a] = par[par[a]];
    return a;
}

/* Grow the 8-connected component of the pixels marked -1 in lab (w x h)
 * from pixel k, labelling it id; q (room for w h) gets its pixels.
 * Returns how many. */
static int flood8(int *lab, int w, int h, int k, int id, int *q)
{
    int qn = 0, qi;
    lab[k] = id;
    q[qn++] = k;
    for (qi = 0; qi < qn; qi++) {
        int x = q[qi] % w, y = q[qi] / w, dx, dy;
        for (dy = -1; dy <= 1; dy++)
            for (dx = -1; dx <= 1; dx++) {
                int X = x + dx, Y = y + dy;
                if (X < 0 || Y < 0 || X >= w || Y >= h || lab[Y * w + X] != -1)
                    continue;
                lab[Y * w + X] = id;
                q[qn++] = Y * w + X;
            }
    }
    return qn;
}

/* The box (x0, y0, x1, y1) of the n pixels q of a w-wide grid; returns
 * whether one lies on its border (h rows). */
static int pixel_box(const int *q, int n, int w, int h, int *b)
{
    int i, edge = 0;
    b[0] = w, b[1] = h, b[2] = -1, b[3] = -1;
    for (i = 0; i < n; i++) {
        int x = q[i] % w, y = q[i] / w;
        b[0] = x < b[0] ? x : b[0], b[2] = x > b[2] ? x : b[2];
        b[1] = y < b[1] ? y : b[1], b[3] = y > b[3] ? y : b[3];
        edge |= x == 0 || y == 0 || x == w - 1 || y == h - 1;
    }
    return edge;
}

/* Label 8-connected ink components below t and group them into glyphs
 * (PIECE_GAP); keep the glyphs touching no side of the strip, at least 4
 * px tall, near the middle row.  Returns how many were kept and their box
 * in *b (x0, y0, x1, y1), or 0; -1: no memory. */
static int components(strip *s, double t, int *b)
{
    int n = s->w * s->h, next = 0, kept = 0, i, j, np = 0, tallest = 0;
    int cb[64][5], pb[MAX_PIECES][6], par[MAX_PIECES], tall[MAX_PIECES];
    int *stack = malloc((size_t)n * sizeof *stack), *root = NULL;
    if (!stack)
        return -1;
    for (i = 0; i < n; i++)
        s->lab[i] = s->g[i] < t ? -1 : 0;
    b[0] = s->w, b[1] = s->h, b[2] = -1, b[3] = -1;
    for (i = 0; i < n; i++) {
        int area, edge, bx[4];
        if (s->lab[i] != -1)
            continue;
        area = flood8(s->lab, s->w, s->h, i, ++next, stack);
        edge = pixel_box(stack, area, s->w, s->h, bx);
        if (edge || np == MAX_PIECES)
            continue; /* a line crossing the strip; noise beyond the cap */
        pb[np][0] = bx[0], pb[np][1] = bx[1], pb[np][2] = bx[2];
        pb[np][3] = bx[3], pb[np][4] = next, pb[np][5] = area;
        par[np] = np;
        tallest = bx[3] - bx[1] + 1 > tallest ? bx[3] - bx[1] + 1 : tallest;
        np++;
    }
    free(stack);
    for (i = 0; i < np; i++)
        tall[i] = pb[i][3] - pb[i][1] + 1 >= 0.6 * tallest;
    for (i = 0; i < np; i++) /* a low piece joins what it nearly touches */
        for (j = i + 1; j < np; j++) {
            int ri = piece_root(par, i), rj = piece_root(par, j);
            if (ri == rj || (tall[ri] && tall[rj]) ||
                pb[i][0] > pb[j][2] + PIECE_GAP ||
                pb[j][0] > pb[i][2] + PIECE_GAP ||
                pb[i][1] > pb[j][3] + PIECE_GAP ||
                pb[j][1] > pb[i][3] + PIECE_GAP)
                continue;
            par[rj] = ri;
            tall[ri] |= tall[rj];
            pb[ri][0] = pb[rj][0] < pb[ri][0] ? pb[rj][0] : pb[ri][0];
            pb[ri][1] = pb[rj][1] < pb[ri][1] ? pb[rj][1] : pb[ri][1];
            pb[ri][2] = pb[rj][2] > pb[ri][2] ? pb[rj][2] : pb[ri][2];
            pb[ri][3] = pb[rj][3] > pb[ri][3] ? pb[rj][3] : pb[ri][3];
            pb[ri][5] += pb[rj][5];
        }
    if (np && !(root = calloc((size_t)next + 1, sizeof *root)))
        return -1;
    for (i = 0; i < np; i++) /* each piece's pixels take its glyph's label */
        root[pb[i][4]] = pb[piece_root(par, i)][4];
    for (i = 0; i < n && np; i++)
        if (s->lab[i] > 0 && root[s->lab[i]])
            s->lab[i] = root[s->lab[i]];
    free(root);
    for (i = 0; i < np; i++) {
        const int *g = pb[i];
        if (piece_root(par, i) != i || g[3] - g[1] + 1 < 4 || g[5] < 6 ||
            fabs(0.5 * (g[1] + g[3]) - 0.5 * s->h) > s->h / 4.0)
            continue;
        s->keep[g[4]] = 1;
        if (kept < 64) {
            s->ch[kept] = g[3] - g[1] + 1;
            cb[kept][0] = g[0], cb[kept][1] = g[1], cb[kept][2] = g[2];
            cb[kept][3] = g[3], cb[kept][4] = g[4];
        }
        kept++;
    }
    return drop_dots(s, kept, cb, b);
}

/* A text candidate: where the pieces of one cluster lie. */
typedef struct cand {
    double cx, cy, ux, uy, along, across; /* centre, axis, extents */
} cand;

static int sample_strip(const td_image *im, const uint8_t *lut, const cand *c,
                        double extra, strip *s)
{
    int i, j;
    memset(s, 0, sizeof *s);
    if (c->along < 6)
        return 1;
    s->cx = c->cx, s->cy = c->cy, s->ux = c->ux, s->uy = c->uy;
    s->w = (int)ceil(c->along + extra); /* room for digits not traced */
    s->h = (int)ceil(
        fmin(fmax(fmax(0.9 * c->along, 3.0 * c->across), 24.0), 80.0));
    if (s->w > MAX_STRIP)
        return 1;
    s->g = malloc((size_t)s->w * s->h * sizeof *s->g);
    s->lab = malloc((size_t)s->w * s->h * sizeof *s->lab);
    s->keep = calloc((size_t)s->w * s->h + 1, 1);
    if (!s->g || !s->lab || !s->keep)
        return -1;
    for (j = 0; j < s->h; j++)
        for (i = 0; i < s->w; i++) {
            double x, y;
            strip_xy(s, i, j, &x, &y);
            s->g[j * s->w + i] = lum_at(im, lut, x, y);
        }
    return 0;
}

/* Do the kept components look like a row of digits: 6-40 px tall, most
 * of them about the row's height, the row at least as wide as tall? */
static int text_like(const strip *s, int k, const int *b)
{
    int i, n = k < 64 ? k : 64, tall = 0, H = b[3] - b[1] + 1;
    if (H < 6 || H > 40 || b[2] - b[0] + 1 < H)
        return 0;
    for (i = 0; i < n; i++)
        tall += s->ch[i] >= 0.6 * H;
    return tall >= 2 && tall * 2 >= n; /* labels have two digits or more */
}

/* The kept digits, scaled to about digit_px tall, black on white, 8-bit
 * rows (w x h, stride w) into *img (malloc'ed). */
static int digits_image(const strip *s, const int *b, double digit_px,
                        uint8_t **img, int *w, int *h)
{
    double hd = b[3] - b[1] + 1, f = digit_px / hd, m = 0.4 * hd;
    int W = (int)ceil((b[2] - b[0] + 1 + 2 * m) * f);
    int H = (int)ceil((hd + 2 * m) * f), x, y;
    uint8_t *o;
    if (W < 8 || H < 8 || W > 4000 || !(o = malloc((size_t)W * H)))
        return -1;
    for (y = 0; y < H; y++)
        for (x = 0; x < W; x++) {
            double i = b[0] - m + (x + 0.5) / f - 0.5;
            double j = b[1] - m + (y + 0.5) / f - 0.5;
            int ii = (int)floor(i + 0.5), jj = (int)floor(j + 0.5), dx, dy;
            int near = 0;
            double v = 255, fx, fy;
            for (dy = -1; dy <= 1 && !near; dy++)
                for (dx = -1; dx <= 1 && !near; dx++) {
                    int X = ii + dx, Y = jj + dy;
                    near = X >= 0 && Y >= 0 && X < s->w && Y < s->h &&
                           s->lab[Y * s->w + X] > 0 &&
                           s->keep[s->lab[Y * s->w + X]];
                }
            if (near) {
                int i0 = (int)floor(i), j0 = (int)floor(j);
                i0 = i0 < 0 ? 0 : i0 >= s->w - 1 ? s->w - 2 : i0;
                j0 = j0 < 0 ? 0 : j0 >= s->h - 1 ? s->h - 2 : j0;
                fx = i - i0, fy = j - j0;
                fx = fx < 0 ? 0 : fx > 1 ? 1 : fx;
                fy = fy < 0 ? 0 : fy > 1 ? 1 : fy;
                v = (1 - fy) * ((1 - fx) * s->g[j0 * s->w + i0] +
                                fx * s->g[j0 * s->w + i0 + 1]) +
                    fy * ((1 - fx) * s->g[(j0 + 1) * s->w + i0] +
                          fx * s->g[(j0 + 1) * s->w + i0 + 1]);
                v = (v - s->ink) / (s->paper - s->ink) * 255.0;
                v = v < 0 ? 0 : v > 255 ? 255 : v;
            }
            o[(size_t)y * W + x] = (uint8_t)v;
        }
    *img = o, *w = W, *h = H;
    return 0;
}

/* Read one image: the number and the confidence, or -1 when the text is
 * not a number.  sec (may be NULL; one entry per character of text) gets
 * each digit's runner-up digit among Tesseract's choices ('\0': none) and
 * secf its confidence over the digit read's (LSTM choices,
 * lstm_choice_mode 2: a faint "8" read "6" keeps its "8" there). */
static int read_number(TessBaseAPI *api, const uint8_t *img, int w, int h,
                       char *text, size_t tlen, double *conf, char *sec,
                       double *secf)
{
    char *t, *p, *q;
    int ok = 1, digits = 0;
    TessBaseAPISetImage(api, img, w, h, 1, w);
    TessBaseAPISetSourceResolution(api, 300);
    if (!(t = TessBaseAPIGetUTF8Text(api)))
        return -1;
    *conf = TessBaseAPIMeanTextConf(api) / 100.0;
    for (p = t, q = text; *p && (size_t)(q - text) + 1 < tlen; p++)
        if (!isspace((unsigned char)*p))
            *q++ = *p;
    *q = '\0';
    TessDeleteText(t);
    for (p = text; *p; p++) {
        ok &= isdigit((unsigned char)*p) || (*p == '-' && p == text);
        digits += isdigit((unsigned char)*p) != 0;
    }
    if (ok && digits > 0 && sec) {
        TessResultIterator *it = TessBaseAPIGetIterator(api);
        size_t k = 0, n = strlen(text);
        memset(sec, 0, n + 1);
        for (; it && k < n; k++) {
            TessChoiceIterator *ci = TessResultIteratorGetChoiceIterator(it);
            double c0 = -1;
            secf[k] = 0;
            do {
                const char *ch = ci ? TessChoiceIteratorGetUTF8Text(ci) : NULL;
                double c = ci ? TessChoiceIteratorConfidence(ci) : 0;
                if (!ch)
                    break;
                if (c0 < 0)
                    c0 = c > 0 ? c : 1e-9;
                else if (ch[0] != text[k] && isdigit((unsigned char)ch[0]) &&
                         !ch[1] && c / c0 > secf[k])
                    sec[k] = ch[0], secf[k] = c / c0;
            } while (ci && TessChoiceIteratorNext(ci));
            TessChoiceIteratorDelete(ci);
            if (!TessResultIteratorNext(it, RIL_SYMBOL))
                k = n; /* fewer symbols than characters: stop */
        }
        TessResultIteratorDelete(it);
    }
    return ok && digits > 0 ? 0 : -1;
}

static int compact_ring(const td_line *l, double side)
{
    double x0 = HUGE_VAL, x1 = -HUGE_VAL, y0 = HUGE_VAL, y1 = -HUGE_VAL;
    size_t k;
    if (!l->closed)
        return 0;
    for (k = 0; k < l->n; k++) { /* most rings are long: out early */
        double x = l->xy[2 * k], y = l->xy[2 * k + 1];
        x0 = x < x0 ? x : x0, x1 = x > x1 ? x : x1;
        y0 = y < y0 ? y : y0, y1 = y > y1 ? y : y1;
        if (x1 - x0 >= side || y1 - y0 >= side)
            return 0;
    }
    return 1;
}

/* End k (0 first, 1 last) of open line l seen from read r: where it is
 * (x, y, from the read's centre) and which way it heads (tx, ty: from 6
 * points back to the end). */
static void end_of_line(const td_line *l, int k, const td_ocr_read *r,
                        double *x, double *y, double *tx, double *ty)
{
    size_t e0 = k ? l->n - 1 : 0, e1 = k ? (l->n > 6 ? l->n - 7 : 0)
                                         : (l->n > 6 ? 6 : l->n - 1);
    *x = l->xy[2 * e0] - r->x, *y = l->xy[2 * e0 + 1] - r->y;
    *tx = l->xy[2 * e0] - l->xy[2 * e1];
    *ty = l->xy[2 * e0 + 1] - l->xy[2 * e1 + 1];
}

/* Where a line bends at its label (printed maps place labels on bends
 * too), its ends meet the text's ends from aside: open ends within one
 * digit height of the text's ends, heading towards the text, the nearest
 * on each side, taken only when there is one on each side (e, end as in
 * lines_of). */
static void near_ends(const td_lines *ls, const td_ocr_read *r, double along,
                      double e[2], long end[2])
{
    double reach = 0.5 * along + r->digit_px, e2[2] = {HUGE_VAL, HUGE_VAL};
    long end2[2] = {-1, -1};
    size_t i;
    int k;
    for (i = 0; ls && i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        if (l->closed || l->n < 2 || l->piece) /* (not the scanner's pieces) */
            continue;
        for (k = 0; k < 2; k++) {
            double x, y, tx, ty, u, d;
            int side;
            end_of_line(l, k, r, &x, &y, &tx, &ty);
            u = x * r->ux + y * r->uy, d = hypot(x, y);
            side = u < 0;
            if (d > reach || fabs(u) < 0.3 * along ||
                tx * -x + ty * -y <= 0)
                continue;
            if (d < e2[side])
                e2[side] = d, end2[side] = (long)i;
        }
    }
    if (end2[0] >= 0 && end2[1] >= 0) /* the line cut on both sides */
        for (k = 0; k < 2; k++)
            e[k] = e2[k], end[k] = end2[k];
}

/* An open line shorter than two digit heights: a stroke of a glyph
 * traced as a line (a contour through a label runs on beyond it). */
static int glyph_piece(const td_line *l, const td_ocr_read *r)
{
    return !l->closed && td_line_length(l) < 2.0 * r->digit_px;
}

/* The lines of a read: the line through the label (within half a digit
 * height of its middle: a neighbour runs beside the text, not through
 * it; on the sheets of bench_heights the next line lies 0.9 digit heights
 * or more from the middle), or a line bending through the label's gap
 * (within half a digit height of both ends of the text and one of its
 * middle: straight text on a curve of radius 48 px left the ring 8 px
 * from its middle), else the lines with an open end at either end of the
 * text (within 24 px beyond it along the text, 0.6 digit heights across,
 * the line's end heading along the text towards it): the nearest on each
 * side; else near_ends. */
static void lines_of(const td_lines *ls, td_ocr_read *r, double along)
{
    size_t i;
    double bd = fmax(2.0, 0.5 * r->digit_px), e[2] = {HUGE_VAL, HUGE_VAL};
    double hx = 0.5 * along * r->ux, hy = 0.5 * along * r->uy;
    long end[2] = {-1, -1};
    int k;
    r->line[0] = r->line[1] = -1;
    for (i = 0; ls && i < ls->n; i++) {
        double d;
        if (compact_ring(&ls->v[i], 25.0) || glyph_piece(&ls->v[i], r) ||
            ls->v[i].piece)
            continue;
        d = td_contain_dist(&ls->v[i], r->x, r->y);
        if (d < bd)
            bd = d, r->line[0] = (long)i;
    }
    if (r->line[0] >= 0)
        return;
    bd = fmax(2.0, 0.5 * r->digit_px);
    for (i = 0; ls && i < ls->n; i++) {
        double d;
        if (compact_ring(&ls->v[i], 25.0) || glyph_piece(&ls->v[i], r) ||
            ls->v[i].piece || td_contain_dist(&ls->v[i], r->x, r->y) > 2 * bd)
            continue;
        d = fmax(td_contain_dist(&ls->v[i], r->x - hx, r->y - hy),
                 td_contain_dist(&ls->v[i], r->x + hx, r->y + hy));
        if (d < bd)
            bd = d, r->line[0] = (long)i;
    }
    if (r->line[0] >= 0)
        return;
    for (i = 0; ls && i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        if (l->closed || l->n < 2 || l->piece) /* (not the scanner's pieces) */
            continue;
        for (k = 0; k < 2; k++) {
            double x, y, tx, ty, tl, u, v;
            int side;
            end_of_line(l, k, r, &x, &y, &tx, &ty);
            tl = hypot(tx, ty), u = x * r->ux + y * r->uy;
            v = fabs(-x * r->uy + y * r->ux);
            side = u < 0;
            /* at one of the text's ends, on its axis, the line's end
             * heading along the axis towards the text */
            if (fabs(u) > 0.5 * along + 24 || v > 0.6 * r->digit_px ||
                !(tl > 0) || tx * -x + ty * -y <= 0 ||
                fabs(tx * r->ux + ty * r->uy) < 0.7 * tl)
                continue;
            if (fabs(u) < e[side])
                e[side] = fabs(u), end[side] = (long)i;
        }
    }
    if (end[0] < 0 && end[1] < 0)
        near_ends(ls, r, along, e, end);
    r->line[0] = end[0] >= 0 ? end[0] : end[1];
    r->line[1] = end[0] >= 0 && end[1] != end[0] ? end[1] : -1;
}

/* Smooth the strip's grey with the 3 x 3 binomial kernel: the noise of a
 * scan breaks faint digits into specks at any threshold. */
static int smooth_strip(strip *s)
{
    int w = s->w, h = s->h, i, j;
    double *t = malloc((size_t)w * h * sizeof *t);
    if (!t)
        return -1;
    for (j = 0; j < h; j++)
        for (i = 0; i < w; i++) {
            double a = 0, wt = 0;
            int di, dj;
            for (dj = -1; dj <= 1; dj++)
                for (di = -1; di <= 1; di++) {
                    int x = i + di, y = j + dj;
                    double k = (2 - abs(di)) * (2 - abs(dj));
                    if (x < 0 || y < 0 || x >= w || y >= h)
                        continue;
                    a += k * s->g[y * w + x], wt += k;
                }
            t[j * w + i] = a / wt;
        }
    free(s->g);
    s->g = t;
    return 0;
}

/* Drop the alternative of r reading value. */
static void drop_alt(td_ocr_read *r, double value)
{
    int k;
    for (k = 0; k < TD_OCR_ALTS && r->alt[k].conf > 0; k++)
        if (r->alt[k].value == value) {
            memmove(&r->alt[k], &r->alt[k + 1],
                    (size_t)(TD_OCR_ALTS - 1 - k) * sizeof r->alt[0]);
            memset(&r->alt[TD_OCR_ALTS - 1], 0, sizeof r->alt[0]);
            return;
        }
}

/* Another number read for r (turn: the way round, from the strip's
 * direction): one alternative per value at its best confidence, most
 * confident first, the least dropped when full. */
static void add_alt(td_ocr_read *r, double value, double conf, int turn)
{
    int k;
    if (value == r->value)
        return;
    for (k = 0; k < TD_OCR_ALTS && r->alt[k].conf > 0; k++)
        if (r->alt[k].value == value) {
            if (conf <= r->alt[k].conf)
                return;
            drop_alt(r, value);
            break;
        }
    for (k = 0; k < TD_OCR_ALTS && r->alt[k].conf >= conf; k++)
        ;
    if (k == TD_OCR_ALTS)
        return;
    memmove(&r->alt[k + 1], &r->alt[k],
            (size_t)(TD_OCR_ALTS - 1 - k) * sizeof r->alt[0]);
    r->alt[k].value = value, r->alt[k].conf = conf, r->alt[k].turned = turn;
}

/* Reverse the n pixels of img: the picture turned half round. */
static void turn_round(uint8_t *img, size_t n)
{
    size_t i;
    for (i = 0; i < n / 2; i++) {
        uint8_t v = img[i];
        img[i] = img[n - 1 - i];
        img[n - 1 - i] = v;
    }
}

/* Black and white at BIN_LEVEL of the way from the darkest pixel (the
 * digits' own ink, lighter than a contour's on colour sheets) to white:
 * the strokes' cores.  Tesseract reads a faint, blurred grey "2" as "7"
 * and "2250" as "7250" at confidence 0.9; their cores it reads right
 * (binarised halfway, "2500" became "2300" as often). */
static void binarise_digits(uint8_t *img, size_t n)
{
    size_t i;
    int m = 255, t;
    for (i = 0; i < n; i++)
        m = img[i] < m ? img[i] : m;
    t = (int)(m + BIN_LEVEL * (255 - m));
    for (i = 0; i < n; i++)
        img[i] = img[i] < t ? 0 : 255;
}

/* How many of the kept glyphs are digit-tall (text_like's count). */
static int tall_glyphs(const strip *s, int k, const int *b)
{
    int i, n = k < 64 ? k : 64, tall = 0, H = b[3] - b[1] + 1;
    for (i = 0; i < n; i++)
        tall += s->ch[i] >= 0.6 * H;
    return tall;
}

/* Whether text a holds text b and more ("1625" holds "16"). */
static int extends(const char *a, const char *b)
{
    return b[0] && strlen(a) > strlen(b) && strstr(a, b) != NULL;
}

#define EXTEND_CONF 0.5

/* Read the digits kept at threshold t (both ways round, as sampled and
 * binarised) into *r: the most confident number read is the read, the
 * others its alternatives (turned from the strip's direction: *turn0 is
 * the read's).  A number with fewer digits than the glyphs kept has left
 * some out: its confidence is scaled by the share read (every read of one
 * digit or two on the benchmark sheets, 33, was wrong; of three or four
 * digits 3 in 527).  A read that holds the read so far and more ("1625"
 * after "16": the luminance cut "25" off at the tint's edge) takes its
 * place when its confidence is EXTEND_CONF or more, whatever the other's,
 * and a part of the read so far never does.  1: nothing better read, -1:
 * no memory. */
static int read_at(TessBaseAPI *api, strip *s, double t,
                   const td_ocr_params *p, td_ocr_read *r, double *best,
                   int *turn0)
{
    int b[4], w, h, turn, var, k, rc = 1, cur = 0, bin = 0, glyphs, read0 = 0;
    uint8_t *img = NULL;
    memset(s->keep, 0, (size_t)s->w * s->h + 1);
    if ((k = components(s, t, b)) < 0)
        return -1;
    if (k == 0 || !text_like(s, k, b))
        return 1;
    glyphs = tall_glyphs(s, k, b);
    if (digits_image(s, b, p->digit_px, &img, &w, &h) != 0)
        return 1;
    for (var = 0; var < 2; var++)
        for (turn = 0; turn < 2; turn++) {
            char text[24], sec[24];
            double conf, secf[24];
            size_t q;
            if (var == 1 && read0 && turn != *turn0)
                continue;    /* the cores: only the way the text reads (when
                                the grey digits told it) */
            if (turn != cur) /* half round: reverse the pixels */
                turn_round(img, (size_t)w * h), cur = turn;
            if (var == 1 && !bin)
                binarise_digits(img, (size_t)w * h), bin = 1;
            if (read_number(api, img, w, h, text, sizeof text, &conf, sec,
                            secf) != 0)
                continue;
            read0 |= var == 0;
            if ((int)strlen(text) < glyphs) /* glyphs left out */
                conf *= (double)strlen(text) / glyphs;
            for (q = 0; text[q]; q++) /* one digit read otherwise */
                if (sec[q]) {
                    char t2[24];
                    memcpy(t2, text, sizeof t2);
                    t2[q] = sec[q];
                    add_alt(r, atof(t2), conf * secf[q], turn);
                }
            if ((conf <= *best &&
                 !(extends(text, r->text) && conf >= EXTEND_CONF)) ||
                (*best >= 0 && extends(r->text, text) &&
                 r->conf >= EXTEND_CONF)) {
                /* read worse than the best so far, or a part of it */
                add_alt(r, atof(text), conf, turn);
                continue;
            }
            if (*best >= 0) /* the best so far becomes an alternative */
                add_alt(r, r->value, r->conf, *turn0);
            drop_alt(r, atof(text));
            *best = conf;
            *turn0 = turn;
            strip_xy(s, 0.5 * (b[0] + b[2]), 0.5 * (b[1] + b[3]), &r->x,
                     &r->y);
            r->ux = turn ? -s->ux : s->ux, r->uy = turn ? -s->uy : s->uy;
            r->digit_px = b[3] - b[1] + 1;
            r->len = b[2] - b[0] + 1;
            r->value = atof(text);
            r->conf = conf;
            snprintf(r->text, sizeof r->text, "%s", text);
            rc = 0;
        }
    free(img);
    return rc;
}

/* Read the label in one gap, sampled through lut (lum_at), into *r
 * against the best read so far (*best, its way round *turn0); 1: nothing
 * better read, -1: no memory.  The digits are cut from the strip at
 * Otsu's threshold.  When that reads nothing sure (confidence under
 * SURE_READ), faint or blurred print is tried too: Otsu's rule, pulled
 * towards the paper by the few ink pixels, merges blurred digits into one
 * blob, and the lighter label ink of a colour sheet falls apart at it;
 * halfway between ink and paper and a third of the way from paper, on the
 * strip smoothed against the noise.  The most confident read wins. */
static int read_strip(TessBaseAPI *api, const td_image *im, const uint8_t *lut,
                      double extra, const cand *gap, const td_ocr_params *p,
                      td_ocr_read *r, double *best, int *turn0)
{
    strip s;
    int rc, k, any;
    double t[4];
    size_t i, n;
    if ((rc = sample_strip(im, lut, gap, extra, &s)) != 0)
        goto done;
    n = (size_t)s.w * s.h;
    s.ink = 255, s.paper = 0;
    for (i = 0; i < n; i++) { /* ink and paper levels: darkest, lightest */
        s.ink = s.g[i] < s.ink ? s.g[i] : s.ink;
        s.paper = s.g[i] > s.paper ? s.g[i] : s.paper;
    }
    rc = 1;
    if (s.paper - s.ink < 40)
        goto done;
    t[0] = otsu(s.g, n);
    if ((any = read_at(api, &s, t[0], p, r, best, turn0)) < 0 ||
        *best >= SURE_READ) {
        rc = any;
        goto done;
    }
    if (smooth_strip(&s) != 0) {
        rc = -1;
        goto done;
    }
    t[1] = 0.5 * (s.ink + s.paper);
    t[2] = s.paper - 0.3 * (s.paper - s.ink);
    t[3] = s.paper - 0.15 * (s.paper - s.ink); /* the ink's strength only */
    for (k = 1; k < (lut ? 4 : 3); k++) {
        int q = read_at(api, &s, t[k], p, r, best, turn0);
        if (q < 0) {
            any = -1;
            break;
        }
        any &= q;
    }
    rc = any;
done:
    strip_free(&s);
    return rc;
}

/* Read the label in one gap into *r (read_strip): on a colour scan whose
 * contour ink is known (lut), in the ink's strength first (a tint, the
 * light box knocked out of it and a road are paper there: in the
 * luminance the tint joined the end digits of a label on its edge, and
 * "1875" came out "875"), then, when that read nothing sure, in the
 * luminance; with digits read but none sure, both once more in a strip
 * STRIP_LONG beyond the label's pieces, and then in one centred on the
 * digits read (the pieces were the label's last digit, and the rest lay
 * beyond the strip).  1: nothing read, -1: no memory. */
static int read_gap(TessBaseAPI *api, const td_image *im, const uint8_t *lut,
                    const cand *gap, const td_ocr_params *p, td_ocr_read *r)
{
    const uint8_t *way[2] = {lut, NULL}; /* the ink's strength, luminance */
    int rc, k, pass, turn0 = 0, nway = lut ? 2 : 1;
    double best = -1;
    cand c2;
    memset(r, 0, sizeof *r);
    rc = read_strip(api, im, way[0], STRIP_EXTRA, gap, p, r, &best, &turn0);
    for (pass = 1; pass < 4 && rc >= 0 && best < SURE_READ; pass++) {
        int q;
        if (pass % 2 >= nway || (pass >= 2 && best < 0))
            continue;
        q = read_strip(api, im, way[pass % 2],
                       pass < 2 ? STRIP_EXTRA : STRIP_LONG, gap, p, r, &best,
                       &turn0);
        rc = q < 0 ? q : rc & q;
    }
    c2 = *gap; /* centred on the digits read */
    c2.cx = r->x, c2.cy = r->y, c2.along = fmax(r->len, 6.0);
    for (pass = 0; pass < nway && rc >= 0 && best >= 0 && best < SURE_READ;
         pass++) {
        int q = read_strip(api, im, way[pass], STRIP_LONG, &c2, p, r, &best,
                           &turn0);
        rc = q < 0 ? q : rc & q;
    }
    for (k = 0; k < TD_OCR_ALTS; k++) /* turned from the read's way */
        r->alt[k].turned = r->alt[k].conf > 0 && r->alt[k].turned != turn0;
    return rc;
}

static size_t ufind(size_t *uf, size_t a)
{
    while (uf[a] != a)
        a = uf[a] = uf[uf[a]];
    return a;
}

/* Pieces near each other (boxes within 6 px) form one candidate: its
 * centre, main axis (of the points' scatter) and extents.  The pieces from
 * pale on (pale_pieces) cluster only with one another, and a cluster of
 * them within PALE_NEAR px of the box of another candidate at least half
 * as long is that candidate's (its pale digits would move the strip off
 * the label read there).
 * *out (free()), returns how many, or -1 (no memory). */
#define PALE_NEAR 10.0
static long clusters(const td_lines *pc, size_t pale, cand **out)
{
    size_t n = pc->n, i, j, k, m = 0, mk = 0;
    size_t *uf = malloc((n + 1) * sizeof *uf);
    double *box = malloc((4 * n + 1) * sizeof *box);
    cand *c = calloc(n + 1, sizeof *c);
    unsigned char *light = calloc(n + 1, 1); /* per candidate: pale */
    if (!uf || !box || !c || !light) {
        free(uf), free(box), free(c), free(light);
        return -1;
    }
    for (i = 0; i < n; i++) {
        const td_line *l = &pc->v[i];
        uf[i] = i;
        box[4 * i] = box[4 * i + 1] = HUGE_VAL;
        box[4 * i + 2] = box[4 * i + 3] = -HUGE_VAL;
        for (k = 0; k < l->n; k++) {
            box[4 * i] = fmin(box[4 * i], l->xy[2 * k]);
            box[4 * i + 1] = fmin(box[4 * i + 1], l->xy[2 * k + 1]);
            box[4 * i + 2] = fmax(box[4 * i + 2], l->xy[2 * k]);
            box[4 * i + 3] = fmax(box[4 * i + 3], l->xy[2 * k + 1]);
        }
    }
    for (i = 0; i < n; i++)
        for (j = i + 1; j < n; j++)
            if (pc->v[i].n && pc->v[j].n && (i >= pale) == (j >= pale) &&
                box[4 * i] - 6 <= box[4 * j + 2] &&
                box[4 * j] - 6 <= box[4 * i + 2] &&
                box[4 * i + 1] - 6 <= box[4 * j + 3] &&
                box[4 * j + 1] - 6 <= box[4 * i + 3])
                uf[ufind(uf, i)] = ufind(uf, j);
    for (i = 0; i < n; i++) {
        double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0, cnt = 0, a, b;
        double lo = HUGE_VAL, hi = -HUGE_VAL, lo2 = HUGE_VAL, hi2 = -HUGE_VAL;
        if (ufind(uf, i) != i)
            continue;
        for (j = 0; j < n; j++)
            for (k = 0; ufind(uf, j) == i && k < pc->v[j].n; k++) {
                double x = pc->v[j].xy[2 * k], y = pc->v[j].xy[2 * k + 1];
                sx += x, sy += y, sxx += x * x, syy += y * y, sxy += x * y;
                cnt++;
            }
        if (cnt < 2)
            continue;
        c[m].cx = sx / cnt, c[m].cy = sy / cnt;
        a = sxx / cnt - c[m].cx * c[m].cx - (syy / cnt - c[m].cy * c[m].cy);
        b = 2 * (sxy / cnt - c[m].cx * c[m].cy);
        c[m].ux = cos(0.5 * atan2(b, a)), c[m].uy = sin(0.5 * atan2(b, a));
        for (j = 0; j < n; j++)
            for (k = 0; ufind(uf, j) == i && k < pc->v[j].n; k++) {
                double x = pc->v[j].xy[2 * k] - c[m].cx;
                double y = pc->v[j].xy[2 * k + 1] - c[m].cy;
                double u = x * c[m].ux + y * c[m].uy;
                double v = -x * c[m].uy + y * c[m].ux;
                lo = fmin(lo, u), hi = fmax(hi, u);
                lo2 = fmin(lo2, v), hi2 = fmax(hi2, v);
            }
        c[m].cx += 0.5 * (lo + hi) * c[m].ux - 0.5 * (lo2 + hi2) * c[m].uy;
        c[m].cy += 0.5 * (lo + hi) * c[m].uy + 0.5 * (lo2 + hi2) * c[m].ux;
        c[m].along = hi - lo;
        c[m].across = hi2 - lo2;
        light[m] = i >= pale;
        for (j = k = 0; light[m] && j < n; j++)
            k += ufind(uf, j) == i;
        if (light[m] && k < 2)
            continue; /* one pale piece alone: no label has one digit */
        m++;
    }
    for (i = 0; i < m; i++) { /* pale clusters beside a candidate: out */
        int near = 0;
        for (j = 0; j < m && light[i] && !near; j++) {
            double dx = c[i].cx - c[j].cx, dy = c[i].cy - c[j].cy;
            near = !light[j] && c[j].along >= 0.5 * c[i].along &&
                   fabs(dx * c[j].ux + dy * c[j].uy) <=
                       0.5 * c[j].along + PALE_NEAR &&
                   fabs(-dx * c[j].uy + dy * c[j].ux) <=
                       0.5 * c[j].across + PALE_NEAR;
        }
        if (!near)
            c[mk++] = c[i];
    }
    free(uf);
    free(box);
    free(light);
    *out = c;
    return (long)mk;
}

/* A Tesseract reader for one line of digits, or NULL (no memory, or
 * the English model missing). */
static TessBaseAPI *digit_reader(const td_ocr_params *p)
{
    TessBaseAPI *api = TessBaseAPICreate();
    if (!api)
        return NULL;
    TessBaseAPISetVariable(api, "debug_file", "/dev/null");
    if (TessBaseAPIInit3(api, p->tessdata, "eng") != 0) {
        TessBaseAPIDelete(api);
        return NULL;
    }
    TessBaseAPISetPageSegMode(api, PSM_SINGLE_LINE);
    TessBaseAPISetVariable(api, "tessedit_do_invert", "0");
    TessBaseAPISetVariable(api, "tessedit_char_whitelist", "0123456789-");
    TessBaseAPISetVariable(api, "lstm_choice_mode", "2");
    return api;
}

static void reader_free(TessBaseAPI *api)
{
    if (api) {
        TessBaseAPIEnd(api);
        TessBaseAPIDelete(api);
    }
}

/* A label per OCR_PER_THREAD candidates or more before a second reader
 * (each loads the model, ~0.1 s) is started. */
#define OCR_PER_THREAD 8

/* Contract in ocr.h.  The candidates are read on up to
 * omp_get_max_threads() threads, each with its own reader, taking the
 * next candidate from a shared counter; each read depends on its
 * candidate alone, so the reads (and their order, kept by candidate) are
 * the same for any thread count.  Tesseract's own OpenMP regions run on
 * one thread inside ours: for these small pictures they only waited on
 * each other (15 labels 1.24 s -> 0.32 s on one thread of ours). */
static int read_labels(const td_image *im, const td_lines *ls,
                       const td_lines *pieces, size_t pale,
                       const td_ocr_params *p, td_ocr_read **out, size_t *n,
                       td_ctx *cx)
{
    td_ocr_params d = td_ocr_defaults();
    TessBaseAPI *api;
    td_ocr_read *v = NULL;
    signed char *st = NULL; /* per candidate: read_gap's answer */
    uint8_t *lut = NULL;    /* the contour ink's strength (p->ink) */
    cand *cs = NULL;
    long nc, next = 0, done = 0;
    int levels, nth, stop = 0;
    size_t i, m = 0;
    *out = NULL;
    *n = 0;
    if (!p)
        p = &d;
    if (!pieces || pieces->n == 0)
        return 0;
    if ((nc = clusters(pieces, pale, &cs)) < 0 ||
        !(v = td_calloc((size_t)nc + 1, sizeof *v, cx)) ||
        !(st = td_calloc((size_t)nc + 1, 1, cx))) {
        free(cs);
        free(v);
        return td_seterr(cx, TD_ENOMEM, "labels: out of memory");
    }
    if (nc == 0) { /* nothing to read: no reader started (0.1 s) */
        free(cs), free(v), free(st);
        return 0;
    }
    if (p->ink && p->ink->n > 0 && p->ink->chosen >= 0 && im->channels == 3) {
        if (!(lut = td_malloc(TD_PALETTE_LUT_SIZE, cx))) {
            free(cs), free(v), free(st);
            return TD_ENOMEM;
        }
        td_palette_lut(p->ink, lut);
    }
    if (!(api = digit_reader(p))) {
        free(lut);
        free(v);
        free(st);
        free(cs);
        return td_seterr(cx, TD_EIO,
                         "labels: Tesseract did not start or its English "
                         "model (eng.traineddata) was not found%s%s: "
                         "install tesseract-ocr-eng",
                         p->tessdata ? " in " : "",
                         p->tessdata ? p->tessdata : "");
    }
    nth = omp_get_max_threads();
    nth = nth > 1 + nc / OCR_PER_THREAD ? (int)(1 + nc / OCR_PER_THREAD) : nth;
    nth = nth < 1 ? 1 : nth;
    levels = omp_get_max_active_levels();
    omp_set_max_active_levels(nth > 1 ? 1 : 0);
#pragma omp parallel num_threads(nth)
    {
        TessBaseAPI *mine = omp_get_thread_num() == 0 ? api : digit_reader(p);
        long k;
        for (;;) {
            int halt;
#pragma omp atomic capture
            k = next++;
#pragma omp atomic read
            halt = stop;
            if (!mine || k >= nc || halt)
                break;
            st[k] = (signed char)read_gap(mine, im, lut, &cs[k], p, &v[k]);
            if (st[k] < 0) {
#pragma omp atomic write
                stop = -1;
            }
#pragma omp atomic update
            done++;
            if (omp_get_thread_num() == 0 && (k & 15) == 0) {
                long dn;
#pragma omp atomic read
                dn = done;
                if (td_progress(cx, "labels", (double)dn / (double)nc) != 0) {
#pragma omp atomic write
                    stop = -2;
                }
            }
        }
        if (mine != api)
            reader_free(mine);
    }
    omp_set_max_active_levels(levels);
    reader_free(api);
    free(lut);
    for (i = 0; i < (size_t)nc && !stop; i++) /* in candidate order */
        if (st[i] == 0 && v[i].conf >= p->min_conf) {
            if (m != i)
                v[m] = v[i];
            lines_of(ls, &v[m], fmax(cs[i].along, v[m].len));
            m++;
        }
    free(cs);
    free(st);
    if (stop == -1) {
        free(v);
        return td_seterr(cx, TD_ENOMEM, "labels: out of memory");
    }
    if (stop == -2) {
        free(v);
        return TD_ECANCEL;
    }
    *out = v;
    *n = m;
    return 0;
}

/* Contract in ocr.h. */
int td_ocr_labels(const td_image *im, const td_lines *ls,
                  const td_lines *pieces, const td_ocr_params *p,
                  td_ocr_read **out, size_t *n, td_ctx *cx)
{
    return read_labels(im, ls, pieces, pieces ? pieces->n : 0, p, out, n, cx);
}

/* Pale digits.  A label printed lighter than its line (a new print's
 * thin type, a faded one) is not in the mask: the joiner sees no text
 * and leaves its gap open, and no piece marks it.  Around every open end
 * of a line inside the sheet (a window of PALE_R px each way) the pieces
 * of the contour ink (its strength by the palette's table: colour scans)
 * at PALE_LEVEL or more are found (8-connected); those that fit
 * in the window, are digit-sized (PALE_MIN .. PALE_MAX px on their longer
 * side, 3 or more on the shorter, 10 px or more) and paler than the
 * traced ink (no pixel at PALE_TOP) go into pc as their pixels' centres;
 * clusters() then makes a row of them one candidate.  done (1 bit per
 * pixel) keeps a piece seen from two ends from going in twice. */
#define PALE_R 40
#define PALE_LEVEL 44
#define PALE_TOP 200
#define PALE_MIN 7
#define PALE_MAX 32
enum { PALE_W = 2 * PALE_R + 1 };

typedef struct pale_ws {
    const td_image *im;
    const uint8_t *lut;
    uint8_t v[PALE_W * PALE_W];
    int lab[PALE_W * PALE_W], q[PALE_W * PALE_W];
    uint8_t *done;
    size_t stride;
} pale_ws;

/* The contour ink's strength at (X, Y) by the table's nearest node
 * (enough for a threshold; RGB). */
static int pale_strength(const pale_ws *ws, int X, int Y)
{
    const td_image *im = ws->im;
    return ws->lut[td_palette_node(im->data + (size_t)Y * im->stride +
                                   (size_t)X * 3)];
}

/* The pieces in the window at (x0, y0) from its pixel k: grown into
 * ws->q (returns the count); *keep when it is a pale digit. */
static int pale_grow(pale_ws *ws, int x0, int y0, int k, int id, int *keep)
{
    int qn = flood8(ws->lab, PALE_W, PALE_W, k, id, ws->q), qi, b[4];
    int edge = pixel_box(ws->q, qn, PALE_W, PALE_W, b), top = 0, bw, bh;
    for (qi = 0; qi < qn; qi++)
        top = ws->v[ws->q[qi]] > top ? ws->v[ws->q[qi]] : top;
    bw = b[2] - b[0] + 1, bh = b[3] - b[1] + 1;
    *keep = !edge && top < PALE_TOP && qn >= 10 &&
            (bw > bh ? bw : bh) >= PALE_MIN &&
            (bw > bh ? bw : bh) <= PALE_MAX && (bw < bh ? bw : bh) >= 3;
    if (*keep) { /* not seen from another end */
        int X = x0 + ws->q[0] % PALE_W, Y = y0 + ws->q[0] / PALE_W;
        *keep =
            !(ws->done[(size_t)Y * ws->stride + (size_t)(X >> 3)] >> (X & 7) &
              1u);
    }
    return qn;
}

static int pale_window(pale_ws *ws, int ex, int ey, td_lines *pc, td_ctx *cx)
{
    const td_image *im = ws->im;
    int x0 = ex - PALE_R, y0 = ey - PALE_R, x, y, id = 0;
    for (y = 0; y < PALE_W; y++)
        for (x = 0; x < PALE_W; x++) {
            int X = x0 + x, Y = y0 + y, k = y * PALE_W + x;
            ws->v[k] = X < 0 || Y < 0 || X >= im->w || Y >= im->h
                           ? 0
                           : (uint8_t)pale_strength(ws, X, Y);
            ws->lab[k] = ws->v[k] >= PALE_LEVEL ? -1 : 0;
        }
    for (x = 0; x < PALE_W * PALE_W; x++) {
        int keep, qn, qi;
        td_line *g;
        if (ws->lab[x] != -1)
            continue;
        qn = pale_grow(ws, x0, y0, x, ++id, &keep);
        if (!keep)
            continue;
        if (!(g = td_lines_add(pc, cx)))
            return TD_ENOMEM;
        for (qi = 0; qi < qn; qi++) {
            int X = x0 + ws->q[qi] % PALE_W, Y = y0 + ws->q[qi] / PALE_W;
            ws->done[(size_t)Y * ws->stride + (size_t)(X >> 3)] |=
                (uint8_t)(1u << (X & 7));
            if (td_line_push(g, X + 0.5, Y + 0.5, cx) != 0)
                return TD_ENOMEM;
        }
    }
    return 0;
}

static int pale_pieces(const td_image *im, const uint8_t *lut,
                       const td_lines *ls, td_lines *pc, td_ctx *cx)
{
    pale_ws *ws = td_malloc(sizeof *ws, cx);
    size_t i;
    int rc = 0;
    if (!ws)
        return TD_ENOMEM;
    ws->im = im, ws->lut = lut;
    ws->stride = ((size_t)im->w + 7) / 8;
    if (!(ws->done = td_calloc((size_t)im->h * ws->stride + 1, 1, cx))) {
        free(ws);
        return TD_ENOMEM;
    }
    for (i = 0; i < ls->n && !rc; i++) {
        const td_line *l = &ls->v[i];
        int e;
        if (l->closed || l->n < 2 || l->piece) /* (not the scanner's pieces) */
            continue;
        for (e = 0; e < 2 && !rc; e++) {
            size_t k = e ? l->n - 1 : 0;
            int ex = (int)floor(l->xy[2 * k]),
                ey = (int)floor(l->xy[2 * k + 1]);
            if (ex >= 3 && ey >= 3 && ex < im->w - 3 && ey < im->h - 3)
                rc = pale_window(ws, ex, ey, pc, cx);
        }
    }
    free(ws->done);
    free(ws);
    return rc;
}

/* Contract in ocr.h. */
int td_ocr_scan_labels(const td_image *im, const td_lines *ls,
                       const td_join_stats *join, const td_lines *assoc,
                       const td_ocr_params *p, td_ocr_read **out, size_t *n,
                       td_ctx *cx)
{
    td_lines *pc = td_lines_new(cx);
    size_t i, pale;
    int rc = 0;
    *out = NULL;
    *n = 0;
    if (!pc)
        return TD_ENOMEM;
    for (i = 0; join && join->segments && i < join->segments->n && !rc; i++)
        rc = td_lines_append_copy(pc, &join->segments->v[i], cx);
    for (i = 0; join && join->text && i < join->text->n && !rc; i++)
        rc = td_lines_append_copy(pc, &join->text->v[i], cx);
    for (i = 0; i < ls->n && !rc; i++)
        if (compact_ring(&ls->v[i], 25.0))
            rc = td_lines_append_copy(pc, &ls->v[i], cx);
    pale = pc->n;
    if (!rc && p && p->ink && p->ink->n > 0 && p->ink->chosen >= 0 &&
        im->channels == 3) { /* colour scans: new prints' pale type */
        uint8_t *lut = td_malloc(TD_PALETTE_LUT_SIZE, cx);
        if (!lut)
            rc = TD_ENOMEM;
        else
            td_palette_lut(p->ink, lut), rc = pale_pieces(im, lut, ls, pc, cx);
        free(lut);
    }
    if (!rc)
        rc = read_labels(im, assoc ? assoc : ls, pc, pale, p, out, n, cx);
    if (!rc)
        td_ocr_find_spots(im, *out, *n);
    td_lines_free(pc);
    return rc;
}

/* The region around read r: the text box grown by 14 px, in the text's
 * frame; a pixel's (u, v) along and across the text. */

/* A dot beside read r: see td_ocr_find_spots. */
static int find_dot(const td_image *im, const td_ocr_read *r, double *dx,
                    double *dy)
{
    double hu = 0.5 * r->len + DOT_REACH, hv = 0.5 * r->digit_px + DOT_REACH;
    double R = hypot(hu, hv), best = 1e30, t;
    int x0 = (int)floor(r->x - R), y0 = (int)floor(r->y - R);
    int W = (int)ceil(2 * R) + 1, x, y, found = 0;
    uint8_t *m = calloc((size_t)W * W, 1);
    int *st = malloc((size_t)W * W * sizeof *st);
    if (!m || !st || W > 400) {
        free(m);
        free(st);
        return 0;
    }
    /* dark: below the middle of paper (255) and the digits' ink */
    t = 150.0;
    for (y = 0; y < W; y++)
        for (x = 0; x < W; x++) {
            double px = x0 + x + 0.5 - r->x, py = y0 + y + 0.5 - r->y;
            double u = px * r->ux + py * r->uy, v = -px * r->uy + py * r->ux;
            if (fabs(u) > hu || fabs(v) > hv) { /* out of reach, dark: 2 */
                m[(size_t)y * W + x] =
                    lum_at(im, NULL, x0 + x + 0.5, y0 + y + 0.5) < t ? 2 : 0;
                continue;
            }
            m[(size_t)y * W + x] =
                fabs(u) <= 0.5 * r->len && fabs(v) <= 0.4 * r->digit_px
                    ? 3 /* the text's core */
                : lum_at(im, NULL, x0 + x + 0.5, y0 + y + 0.5) < t ? 1
                                                                   : 0;
        }
    for (y = 0; y < W; y++)
        for (x = 0; x < W; x++) {
            int n = 0, top = 0, bx0 = x, bx1 = x, by0 = y, by1 = y, edge = 0;
            double sx = 0, sy = 0;
            if (m[(size_t)y * W + x] != 1)
                continue;
            m[(size_t)y * W + x] = 4;
            st[top++] = y * W + x;
            while (top) {
                int q = st[--top], qx = q % W, qy = q / W, ax, ay;
                n++, sx += qx, sy += qy;
                bx0 = qx < bx0 ? qx : bx0, bx1 = qx > bx1 ? qx : bx1;
                by0 = qy < by0 ? qy : by0, by1 = qy > by1 ? qy : by1;
                for (ay = qy - 1; ay <= qy + 1; ay++)
                    for (ax = qx - 1; ax <= qx + 1; ax++) {
                        uint8_t *v;
                        if (ax < 0 || ay < 0 || ax >= W || ay >= W) {
                            edge = 1;
                            continue;
                        }
                        v = &m[(size_t)ay * W + ax];
                        /* touches the text (a digit) or runs out of
                           reach (a line) */
                        edge |= *v == 3 || *v == 2;
                        if (*v == 1) {
                            *v = 4;
                            st[top++] = ay * W + ax;
                        }
                    }
            }
            if (edge || n < DOT_MIN_AREA || n > DOT_MAX_AREA ||
                bx1 - bx0 + 1 > DOT_MAX || by1 - by0 + 1 > DOT_MAX ||
                n < 0.5 * (bx1 - bx0 + 1) * (by1 - by0 + 1))
                continue;
            sx = x0 + sx / n + 0.5, sy = y0 + sy / n + 0.5;
            if (hypot(sx - r->x, sy - r->y) < best) {
                best = hypot(sx - r->x, sy - r->y);
                *dx = sx, *dy = sy;
                found = 1;
            }
        }
    free(m);
    free(st);
    return found;
}

/* Contract in ocr.h. */
size_t td_ocr_find_spots(const td_image *im, td_ocr_read *r, size_t n)
{
    size_t i, m = 0;
    for (i = 0; i < n; i++) {
        r[i].spot = 0;
        if (r[i].line[0] >= 0 || r[i].line[1] >= 0 ||
            !find_dot(im, &r[i], &r[i].sx, &r[i].sy))
            continue;
        r[i].spot = 1;
        m++;
    }
    return m;
}

/* Contract in ocr.h. */
size_t td_ocr_drop_digits(td_lines *ls, td_ocr_read *r, size_t n)
{
    size_t i, j, k, m = 0;
    for (i = ls->n; i-- > 0;) {
        const td_line *l = &ls->v[i];
        int in = 0;
        if (!compact_ring(l, 25.0))
            continue;
        for (j = 0; j < n && !in; j++) {
            /* inside the read's box (a digit), or within 5 px of a spot
               height's dot (the dot traced as a tiny ring) */
            int inbox = 1, atdot = r[j].spot;
            for (k = 0; k < l->n && (inbox || atdot); k++) {
                double x = l->xy[2 * k] - r[j].x, y = l->xy[2 * k + 1] - r[j].y;
                inbox = inbox &&
                        fabs(x * r[j].ux + y * r[j].uy) <= 0.5 * r[j].len + 3 &&
                        fabs(-x * r[j].uy + y * r[j].ux) <=
                            0.5 * r[j].digit_px + 3;
                atdot = atdot && hypot(l->xy[2 * k] - r[j].sx,
                                       l->xy[2 * k + 1] - r[j].sy) <= 5.0;
            }
            in = inbox || atdot;
        }
        if (in) { /* the reads' line indexes follow the removal */
            td_lines_remove(ls, i);
            for (j = 0; j < n; j++) {
                int e;
                for (e = 0; e < 2; e++)
                    if (r[j].line[e] == (long)i)
                        r[j].line[e] = -1;
                    else if (r[j].line[e] > (long)i)
                        r[j].line[e]--;
            }
            m++;
        }
    }
    return m;
}

/* Line i is removed: the reads' indexes follow. */
static void reads_follow(td_ocr_read *r, size_t n, size_t i)
{
    size_t j;
    int e;
    for (j = 0; j < n; j++)
        for (e = 0; e < 2; e++)
            if (r[j].line[e] == (long)i)
                r[j].line[e] = -1;
            else if (r[j].line[e] > (long)i)
                r[j].line[e]--;
}

/* Contract in ocr.h. */
size_t td_ocr_drop_dots(td_lines *ls, const td_lines *text, td_ocr_read *r,
                        size_t n)
{
    size_t i, j, k, m = 0;
    for (i = ls->n; text && i-- > 0;) {
        const td_line *l = &ls->v[i];
        double b[4], cx, cy;
        int near = 0;
        if (!l->closed || l->n == 0)
            continue;
        td_line_box(l, b);
        if (b[2] - b[0] > DOT_MAX + 2 || b[3] - b[1] > DOT_MAX + 2)
            continue;
        cx = 0.5 * (b[0] + b[2]), cy = 0.5 * (b[1] + b[3]);
        for (j = 0; j < text->n && !near; j++)
            for (k = 0; k < text->v[j].n && !near; k++)
                near = hypot(text->v[j].xy[2 * k] - cx,
                             text->v[j].xy[2 * k + 1] - cy) <= DOT_REACH;
        if (!near)
            continue;
        td_lines_remove(ls, i);
        reads_follow(r, n, i);
        m++;
    }
    return m;
}

/* Contract in ocr.h. */
void td_ocr_draw(td_image *im, const td_ocr_read *r, size_t n)
{
    static const uint8_t used[3] = {0, 40, 160}, refused[3] = {140, 140, 140};
    double xy[8];
    td_line box;
    size_t i;
    int k;
    memset(&box, 0, sizeof box);
    box.xy = xy, box.n = 4, box.closed = 1;
    for (i = 0; i < n; i++) {
        double hu = 0.5 * r[i].len + 3, hv = 0.5 * r[i].digit_px + 3;
        for (k = 0; k < 4; k++) {
            double u = (k == 1 || k == 2) ? hu : -hu, v = k >= 2 ? hv : -hv;
            xy[2 * k] = r[i].x + u * r[i].ux - v * r[i].uy;
            xy[2 * k + 1] = r[i].y + u * r[i].uy + v * r[i].ux;
        }
        td_draw_line(im, &box, r[i].used ? used : refused);
    }
}
