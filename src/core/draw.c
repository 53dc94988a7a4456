#include "src/core/core.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

void td_draw_colour(size_t i, uint8_t rgb[3])
{
    double h = fmod(0.13 + 0.618033988749895 * (double)i, 1.0) * 6.0;
    double f = h - floor(h), v = 0.85, s = 0.9;
    double p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
    double r, g, b;
    switch ((int)h) {
    case 0: r = v; g = t; b = p; break;
    case 1: r = q; g = v; b = p; break;
    case 2: r = p; g = v; b = t; break;
    case 3: r = p; g = q; b = v; break;
    case 4: r = t; g = p; b = v; break;
    default: r = v; g = p; b = q; break;
    }
    rgb[0] = (uint8_t)(r * 255);
    rgb[1] = (uint8_t)(g * 255);
    rgb[2] = (uint8_t)(b * 255);
}

static void put(td_image *im, long x, long y, const uint8_t rgb[3])
{
    uint8_t *p;
    if (x < 0 || y < 0 || x >= im->w || y >= im->h)
        return;
    p = im->data + (size_t)y * im->stride + (size_t)x * 3;
    p[0] = rgb[0];
    p[1] = rgb[1];
    p[2] = rgb[2];
}

/* Bresenham between pixel centres (x,y in pixel units, centre at +0.5). */
static void segment(td_image *im, double x0, double y0, double x1, double y1,
                    const uint8_t rgb[3])
{
    long ax = (long)floor(x0), ay = (long)floor(y0);
    long bx = (long)floor(x1), by = (long)floor(y1);
    long dx = labs(bx - ax), dy = -labs(by - ay);
    long sx = ax < bx ? 1 : -1, sy = ay < by ? 1 : -1, err = dx + dy;
    for (;;) {
        long e2;
        put(im, ax, ay, rgb);
        if (ax == bx && ay == by)
            break;
        e2 = 2 * err;
        if (e2 >= dy) {
            err += dy;
            ax += sx;
        }
        if (e2 <= dx) {
            err += dx;
            ay += sy;
        }
    }
}

void td_draw_line(td_image *im, const td_line *l, const uint8_t rgb[3])
{
    size_t i;
    if (l->n == 1)
        put(im, (long)l->xy[0], (long)l->xy[1], rgb);
    for (i = 1; i < l->n; i++)
        segment(im, l->xy[2 * i - 2], l->xy[2 * i - 1], l->xy[2 * i],
                l->xy[2 * i + 1], rgb);
    if (l->closed && l->n > 2)
        segment(im, l->xy[2 * l->n - 2], l->xy[2 * l->n - 1], l->xy[0],
                l->xy[1], rgb);
}

/* A red 3x3 box around an open end that is not on the sheet border. */
static void mark_end(td_image *im, double x, double y)
{
    static const uint8_t red[3] = {230, 0, 0};
    long cx = (long)floor(x), cy = (long)floor(y), dx, dy;
    if (cx <= 0 || cy <= 0 || cx >= im->w - 1 || cy >= im->h - 1)
        return;
    for (dy = -1; dy <= 1; dy++)
        for (dx = -1; dx <= 1; dx++)
            if (dx || dy)
                put(im, cx + dx, cy + dy, red);
}

int td_draw_overlay(const td_image *scan, const td_lines *ls, td_image **out,
                    td_ctx *cx)
{
    td_image *im = td_image_new(scan->w, scan->h, 3, cx);
    int x, y, c;
    size_t i;
    *out = NULL;
    if (!im)
        return cx ? cx->code : TD_ENOMEM;
    for (y = 0; y < scan->h; y++) {
        const uint8_t *s = scan->data + (size_t)y * scan->stride;
        uint8_t *d = im->data + (size_t)y * im->stride;
        for (x = 0; x < scan->w; x++)
            for (c = 0; c < 3; c++) {
                int v = s[scan->channels == 3 ? 3 * x + c : x];
                d[3 * x + c] = (uint8_t)(255 - (255 - v) * 2 / 5);
            }
    }
    for (i = 0; i < ls->n; i++) {
        uint8_t rgb[3];
        td_draw_colour(i, rgb);
        td_draw_line(im, &ls->v[i], rgb);
    }
    for (i = 0; i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        if (l->closed || l->n == 0)
            continue;
        mark_end(im, l->xy[0], l->xy[1]);
        mark_end(im, l->xy[2 * l->n - 2], l->xy[2 * l->n - 1]);
    }
    *out = im;
    return 0;
}

/* A hypsometric ramp: t in [0,1] from low (blue-green) to high (brown,
 * then white). */
static void ramp(double t, uint8_t rgb[3])
{
    static const double k[5][3] = {{20, 90, 190},  {30, 150, 70},
                                   {200, 190, 40}, {150, 80, 20},
                                   {120, 60, 120}};
    double f;
    int i;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    i = t >= 1 ? 3 : (int)(t * 4);
    f = t * 4 - i;
    rgb[0] = (uint8_t)(k[i][0] + f * (k[i + 1][0] - k[i][0]));
    rgb[1] = (uint8_t)(k[i][1] + f * (k[i + 1][1] - k[i][1]));
    rgb[2] = (uint8_t)(k[i][2] + f * (k[i + 1][2] - k[i][2]));
}

/* Line l drawn with dashes (on, off px along the arc; off 0: solid) and
 * `thick` (1 or 3 px wide). */
static void dashed(td_image *im, const td_line *l, const uint8_t rgb[3],
                   double on, double off, int thick)
{
    size_t i, n = l->closed && l->n > 2 ? l->n + 1 : l->n;
    double s = 0;
    for (i = 1; i < n; i++) {
        const double *a = l->xy + 2 * (i - 1), *b = l->xy + 2 * (i % l->n);
        double len = hypot(b[0] - a[0], b[1] - a[1]);
        int dx, dy;
        if (off <= 0 || fmod(s, on + off) < on)
            for (dy = -(thick > 1); dy <= (thick > 1); dy++)
                for (dx = -(thick > 1); dx <= (thick > 1); dx++)
                    segment(im, a[0] + dx, a[1] + dy, b[0] + dx, b[1] + dy,
                            rgb);
        s += len;
    }
}

int td_draw_heights(const td_image *scan, int w, int h, const td_lines *ls,
                    td_image **out, td_ctx *cx)
{
    static const uint8_t grey[3] = {150, 150, 150};
    td_image *im = td_image_new(scan ? scan->w : w, scan ? scan->h : h, 3, cx);
    double lo = HUGE_VAL, hi = -HUGE_VAL;
    size_t i;
    int x, y, c;
    *out = NULL;
    if (!im)
        return cx ? cx->code : TD_ENOMEM;
    for (y = 0; y < im->h; y++) {
        uint8_t *d = im->data + (size_t)y * im->stride;
        const uint8_t *s = scan ? scan->data + (size_t)y * scan->stride : NULL;
        for (x = 0; x < im->w; x++)
            for (c = 0; c < 3; c++)
                d[3 * x + c] = s ? (uint8_t)(255 - (255 - s[scan->channels == 3
                                                                ? 3 * x + c
                                                                : x]) /
                                                       5)
                                 : 255;
    }
    for (i = 0; i < ls->n; i++)
        if (ls->v[i].has_height) {
            lo = fmin(lo, ls->v[i].height);
            hi = fmax(hi, ls->v[i].height);
        }
    for (i = 0; i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        uint8_t rgb[3];
        if (!l->has_height) {
            dashed(im, l, grey, 2, 3, 1);
            continue;
        }
        ramp(hi > lo ? (l->height - lo) / (hi - lo) : 0.5, rgb);
        if (l->hsource == TD_HS_ASSUMED)
            dashed(im, l, rgb, 6, 4, 1);
        else
            dashed(im, l, rgb, 1, 0, l->hsource == TD_HS_KNOWN ||
                                          l->hsource == TD_HS_LABEL ? 3 : 1);
    }
    *out = im;
    return 0;
}

/* ---- line ids: the label sheet of the paper's operator entry ---- */

/* 3x5 digits, rows top to bottom, 3 bits per row (4 = left column). */
static const unsigned char font3x5[10][5] = {
    {7, 5, 5, 5, 7}, {2, 6, 2, 2, 7}, {7, 1, 7, 4, 7}, {7, 1, 7, 1, 7},
    {5, 5, 7, 1, 1}, {7, 4, 7, 1, 7}, {7, 4, 7, 5, 7}, {7, 1, 1, 1, 1},
    {7, 5, 7, 5, 7}, {7, 5, 7, 1, 7}};

static void put_px(td_image *im, int x, int y, const uint8_t c[3])
{
    uint8_t *p;
    if (x < 0 || y < 0 || x >= im->w || y >= im->h)
        return;
    p = im->data + ((size_t)y * im->w + x) * 3;
    p[0] = c[0], p[1] = c[1], p[2] = c[2];
}

/* See core.h. */
void td_draw_text(td_image *im, int x0, int y0, const char *t, int scale,
                  const uint8_t c[3])
{
    int g, x, y;
    for (g = 0; t[g]; g++)
        for (y = 0; y < 5 * scale; y++)
            for (x = 0; x < 3 * scale; x++) {
                int on = 0;
                if (t[g] >= '0' && t[g] <= '9')
                    on = font3x5[t[g] - '0'][y / scale] >> (2 - x / scale) & 1;
                else if (t[g] == '-')
                    on = y / scale == 2;
                else if (t[g] == '.')
                    on = y / scale == 4 && x / scale == 1;
                if (on)
                    put_px(im, x0 + (4 * scale) * g + x, y0 + y, c);
            }
}

/* The id in 2x-scaled 3x5 digits centred at (cx,cy) on a white box with
 * a border in the line's colour. */
static void draw_id(td_image *im, double cx, double cy, long id,
                    const uint8_t c[3])
{
    static const uint8_t white[3] = {255, 255, 255};
    char t[24];
    int n = snprintf(t, sizeof t, "%ld", id), bw = n * 8 + 2, bh = 14;
    int x0 = (int)cx - bw / 2, y0 = (int)cy - bh / 2, x, y, g;
    for (y = -1; y <= bh; y++)
        for (x = -1; x <= bw; x++)
            put_px(im, x0 + x, y0 + y,
                   y < 0 || x < 0 || y == bh || x == bw ? c : white);
    for (g = 0; g < n; g++)
        for (y = 0; y < 10; y++)
            for (x = 0; x < 6; x++)
                if (t[g] >= '0' && t[g] <= '9' &&
                    font3x5[t[g] - '0'][y / 2] >> (2 - x / 2) & 1)
                    put_px(im, x0 + 2 + 8 * g + x, y0 + 2 + y, c);
}

/* The point at fraction f of l's length. */
static void line_at(const td_line *l, double f, double *x, double *y)
{
    double want = f * td_line_length(l), s = 0;
    size_t k;
    *x = l->n ? l->xy[0] : 0, *y = l->n ? l->xy[1] : 0;
    for (k = 1; k < l->n; k++) {
        double d = hypot(l->xy[2 * k] - l->xy[2 * k - 2],
                         l->xy[2 * k + 1] - l->xy[2 * k - 1]);
        if (s + d >= want) {
            *x = l->xy[2 * k], *y = l->xy[2 * k + 1];
            return;
        }
        s += d;
    }
}

/* Where line i's id goes: near its middle, or the first of eight places
 * along it whose box (bw x 16 px) overlaps no earlier id box (xy[2j]). */
static void id_place(const td_lines *ls, size_t i, const double *xy,
                     double *x, double *y)
{
    static const double f[8] = {.5, .25, .75, .125, .375, .625, .875, 0};
    char t[24];
    double bw = 8.0 * snprintf(t, sizeof t, "%ld", ls->v[i].id) + 4;
    size_t j;
    int k;
    for (k = 0; k < 8; k++) {
        int clash = 0;
        line_at(&ls->v[i], f[k], x, y);
        for (j = 0; j < i && !clash; j++)
            clash = fabs(xy[2 * j] - *x) < bw + 6 &&
                    fabs(xy[2 * j + 1] - *y) < 18;
        if (!clash)
            return;
    }
    line_at(&ls->v[i], 0.5, x, y);
}

/* See core.h. */
int td_line_id_places(const td_lines *ls, double **out, td_ctx *cx)
{
    size_t i;
    if (!(*out = malloc((2 * ls->n + 2) * sizeof **out)))
        return td_seterr(cx, TD_ENOMEM, "out of memory");
    for (i = 0; i < ls->n; i++)
        id_place(ls, i, *out, &(*out)[2 * i], &(*out)[2 * i + 1]);
    return 0;
}

/* See core.h. */
void td_draw_ids(td_image *im, const td_lines *ls, const double *xy)
{
    size_t i;
    for (i = 0; i < ls->n; i++) {
        uint8_t c[3];
        td_draw_colour(i, c);
        draw_id(im, xy[2 * i], xy[2 * i + 1], ls->v[i].id, c);
    }
}
