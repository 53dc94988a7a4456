/* labels.c: inline elevation labels cutting the index contours.
 *
 *        gap (20-60 px along the line, erased)
 *   ====|  margin  3 5 0  margin  |====      digits 10-16 px tall, strokes
 *                                            1.5-2 px, along the line
 *
 * Seven-segment digit shapes in a glyph box of 0.55 H x H:
 *
 *      a          a (0,1)-(1,1)    e (0,.5)-(0,0)
 *    f   b        b (1,1)-(1,.5)   f (0,1)-(0,.5)
 *      g          c (1,.5)-(1,0)   g (0,.5)-(1,.5)
 *    e   c        d (0,0)-(1,0)
 *      d
 */
#include "samples/gen/gen_int.h"

#include <ft2build.h>
#include FT_FREETYPE_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const double seg_xy[7][4] = {
    {0, 1, 1, 1}, {1, 1, 1, .5}, {1, .5, 1, 0}, {0, 0, 1, 0},
    {0, .5, 0, 0}, {0, 1, 0, .5}, {0, .5, 1, .5}};
/* segments a..g as bits 0..6 for '0'..'9'; '-' is g alone */
static const unsigned char digit_segs[10] = {0x3f, 0x06, 0x5b, 0x4f, 0x66,
                                             0x6d, 0x7d, 0x07, 0x7f, 0x6f};

/* A line with its cumulative arc length (closing segment included). */
typedef struct arc {
    const td_line *l;
    double *cum; /* cum[k]: arc length at point k; cum[n] closes a ring */
    double len;
} arc;

/* Point at arc length s (wrapped for rings, clamped for open lines). */
static void arc_at(const arc *a, double s, double *x, double *y)
{
    const td_line *l = a->l;
    size_t lo = 0, hi = l->closed ? l->n : l->n - 1, k, k1;
    double t;
    if (l->closed)
        s = fmod(fmod(s, a->len) + a->len, a->len);
    s = s < 0 ? 0 : s > a->len ? a->len : s;
    while (hi - lo > 1) {
        size_t mid = (lo + hi) / 2;
        if (a->cum[mid] <= s)
            lo = mid;
        else
            hi = mid;
    }
    k = lo, k1 = (k + 1) % l->n;
    t = a->cum[k + 1] > a->cum[k] ? (s - a->cum[k]) / (a->cum[k + 1] - a->cum[k]) : 0;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    *x = l->xy[2 * k] + t * (l->xy[2 * k1] - l->xy[2 * k]);
    *y = l->xy[2 * k + 1] + t * (l->xy[2 * k1 + 1] - l->xy[2 * k + 1]);
}

static int arc_make(const td_line *l, arc *a)
{
    size_t k, n = l->n;
    a->l = l;
    if (!(a->cum = malloc((n + 1) * sizeof *a->cum)))
        return TD_ENOMEM;
    a->cum[0] = 0;
    for (k = 1; k <= n; k++) {
        size_t j = k % n;
        a->cum[k] = a->cum[k - 1];
        if (k < n || l->closed)
            a->cum[k] += hypot(l->xy[2 * j] - l->xy[2 * k - 2],
                               l->xy[2 * j + 1] - l->xy[2 * k - 1]);
    }
    a->len = a->cum[n];
    return 0;
}

/* Distance from (px,py) to segment (ax,ay)-(bx,by). */
static double seg_dist(double px, double py, double ax, double ay, double bx,
                       double by)
{
    double dx = bx - ax, dy = by - ay, L2 = dx * dx + dy * dy, t = 0;
    if (L2 > 0)
        t = ((px - ax) * dx + (py - ay) * dy) / L2;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    return hypot(px - ax - t * dx, py - ay - t * dy);
}

/* A label's place: the gap [s0, s1] on a line, its chord and text. */
typedef struct place {
    double s0, s1, x0, y0, x1, y1, H, stroke;
    size_t line;
    int font; /* p->label_font */
    char text[24];
} place;

#define FONT_FILE "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"
#define DIGIT_EM 0.729 /* DejaVu Sans digit height, in em */
#define ADVANCE 0.87   /* DejaVu Sans digit advance, in digit heights */

/* The text's width in px. */
static double text_width(const place *q)
{
    int nd = (int)strlen(q->text);
    if (q->font)
        return nd * ADVANCE * q->H;
    return nd * 0.55 * q->H + (nd - 1) * 0.4 * q->H;
}

/* Straight within p->label_bend px (default 2.5) over [s0 - 25, s1 + 25]
 * (printed labels sit on smooth stretches; a joiner reads the direction of
 * the line next to the gap). */
static int straight(const arc *a, const place *q, const td_gen_params *p)
{
    double tol = p->label_bend > 0 ? p->label_bend : 2.5;
    double ax, ay, bx, by, s, x, y;
    arc_at(a, q->s0 - 25, &ax, &ay);
    arc_at(a, q->s1 + 25, &bx, &by);
    for (s = q->s0 - 25; s <= q->s1 + 25; s += 2) {
        arc_at(a, s, &x, &y);
        if (seg_dist(x, y, ax, ay, bx, by) > tol)
            return 0;
    }
    return 1;
}

/* Arc distance from s to the gap's middle on line a (wrapped on rings). */
static double arc_off(const arc *a, double s, double mid)
{
    double d = fabs(s - mid);
    return a->l->closed ? fmin(d, a->len - d) : d;
}

/* Whether (x,y) lies in the text's box grown by g px (chord frame). */
static int in_text_box(const place *q, double x, double y, double g)
{
    double dx = q->x1 - q->x0, dy = q->y1 - q->y0, L = hypot(dx, dy);
    double px = x - 0.5 * (q->x0 + q->x1), py = y - 0.5 * (q->y0 + q->y1);
    double tw = text_width(q);
    double u = (px * dx + py * dy) / L, v = (-px * dy + py * dx) / L;
    return fabs(u) <= 0.5 * tw + g && fabs(v) <= 0.5 * q->H + g;
}

/* No other line (nor this one away from the gap) within clear px of the
 * chord, this line outside the gap clear of the text (on a curve it may
 * come back towards it), and the chord at least 12 px inside the sheet. */
static int clear_of(const td_lines *ls, size_t self, const arc *a,
                    const place *q, double clear, const td_gen_params *p)
{
    double mid = 0.5 * (q->s0 + q->s1), half = 0.5 * (q->s1 - q->s0);
    double W = fmax(p->line_width, p->index_width);
    size_t i, k;
    double m = clear + 2;
    if (fmin(q->x0, q->x1) < m || fmin(q->y0, q->y1) < m ||
        fmax(q->x0, q->x1) > p->w - m || fmax(q->y0, q->y1) > p->h - m)
        return 0;
    for (i = 0; i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        for (k = 0; k < l->n; k++) {
            double x = l->xy[2 * k], y = l->xy[2 * k + 1];
            if (i == self && arc_off(a, a->cum[k], mid) > half &&
                in_text_box(q, x, y, W + 2))
                return 0;
            if (i == self && arc_off(a, a->cum[k], mid) < half + clear + 6)
                continue;
            if (seg_dist(x, y, q->x0, q->y0, q->x1, q->y1) < clear)
                return 0;
        }
    }
    return 1;
}

/* The text and sizes for a gap centred at s; 0 when it does not fit. */
static int size_label(td_rng *r, double height, double W, double s,
                      place *q)
{
    double tw, gap;
    snprintf(q->text, sizeof q->text, "%.0f", height);
    q->H = td_rng_range(r, 10.0, 16.0);
    q->stroke = td_rng_range(r, 1.5, 2.0);
    for (;;) {
        tw = text_width(q);
        gap = tw + 2.0 * (7.0 + W);
        if (gap <= 60.0 || q->H <= 10.0)
            break;
        q->H = fmax(10.0, q->H - 1.0);
    }
    if (gap > 60.0)
        return 0;
    gap = fmax(gap, 20.0);
    q->s0 = s - 0.5 * gap;
    q->s1 = s + 0.5 * gap;
    return 1;
}

/* Paint paper over |v| <= R across segment (x0,y0)-(x1,y1), 0 <= u <= L
 * along it (square ends). */
static void erase_rect(td_image *im, double x0, double y0, double x1,
                       double y1, double R, int colour)
{
    static const uint8_t cream[3] = {245, 235, 210};
    double dx = x1 - x0, dy = y1 - y0, L = hypot(dx, dy), ux, uy;
    int x, y, c, ch = im->channels;
    int xa = (int)floor(fmin(x0, x1) - R), xb = (int)ceil(fmax(x0, x1) + R);
    int ya = (int)floor(fmin(y0, y1) - R), yb = (int)ceil(fmax(y0, y1) + R);
    if (!(L > 0))
        return;
    ux = dx / L, uy = dy / L;
    for (y = ya < 0 ? 0 : ya; y <= yb && y < im->h; y++)
        for (x = xa < 0 ? 0 : xa; x <= xb && x < im->w; x++) {
            double px = x + 0.5 - x0, py = y + 0.5 - y0;
            double u = px * ux + py * uy, v = -px * uy + py * ux;
            if (u < 0 || u > L || fabs(v) > R)
                continue;
            for (c = 0; c < ch; c++)
                im->data[((size_t)y * im->w + x) * ch + c] =
                    colour ? cream[c] : 255;
        }
}

/* Erase the line over the gap: |v| <= W/2 + 3.5 across the chord, and
 * across the line itself in 1-px pieces from s0 to s1 (on a curve the
 * line leaves the chord). */
static int erase_gap(td_image *im, const td_line *l, const place *q,
                     double W, int colour)
{
    double R = 0.5 * W + 3.5, s, xa, ya, xb, yb;
    arc a;
    erase_rect(im, q->x0, q->y0, q->x1, q->y1, R, colour);
    if (arc_make(l, &a) != 0)
        return TD_ENOMEM;
    arc_at(&a, q->s0, &xa, &ya);
    for (s = q->s0; s < q->s1; s += 1.0) {
        arc_at(&a, fmin(s + 1.0, q->s1), &xb, &yb);
        erase_rect(im, xa, ya, xb, yb, R, colour);
        xa = xb, ya = yb;
    }
    free(a.cum);
    return 0;
}

/* The reading direction (ux, uy) of the text on the chord: with the real
 * font, its top (the left of the reading direction on the screen) uphill
 * on dem; else left to right. */
static void reading_dir(const place *q, const td_grid_f32 *dem, double *ux,
                        double *uy)
{
    double dx = q->x1 - q->x0, dy = q->y1 - q->y0, L = hypot(dx, dy);
    *ux = dx / L, *uy = dy / L;
    if (dem && q->font) {
        int x = (int)(0.5 * (q->x0 + q->x1)), y = (int)(0.5 * (q->y0 + q->y1));
        int xa = x > 3 ? x - 3 : 0, xb = x + 3 < dem->w ? x + 3 : dem->w - 1;
        int ya = y > 3 ? y - 3 : 0, yb = y + 3 < dem->h ? y + 3 : dem->h - 1;
        double gx, gy;
        x = x < 0 ? 0 : x >= dem->w ? dem->w - 1 : x;
        y = y < 0 ? 0 : y >= dem->h ? dem->h - 1 : y;
        gx = (double)TD_AT(dem, xb, y) - TD_AT(dem, xa, y);
        gy = (double)TD_AT(dem, x, yb) - TD_AT(dem, x, ya);
        if (*uy * gx - *ux * gy < 0) /* up (uy, -ux) against the gradient */
            *ux = -*ux, *uy = -*uy;
        return;
    }
    if (*ux < 0)
        *ux = -*ux, *uy = -*uy;
}

/* The text as a grey raster (0..255 coverage): rows from the top, the
 * baseline at row *base, *tw px wide (the digits' advance). */
static uint8_t *ft_raster(FT_Face face, const place *q, int *rw, int *rh,
                          int *base, double *tw)
{
    int px = (int)lround(q->H / DIGIT_EM), pen = 1, i;
    uint8_t *r;
    if (FT_Set_Pixel_Sizes(face, 0, (FT_UInt)(px > 4 ? px : 4)))
        return NULL;
    *rh = (int)(1.3 * px) + 4;
    *base = px + 2;
    *rw = (int)(strlen(q->text) * 0.8 * px) + 8;
    if (!(r = calloc((size_t)*rw * (size_t)*rh, 1)))
        return NULL;
    for (i = 0; q->text[i]; i++) {
        FT_GlyphSlot g;
        unsigned y, x;
        if (FT_Load_Char(face, (FT_ULong)(unsigned char)q->text[i],
                         FT_LOAD_RENDER))
            continue;
        g = face->glyph;
        for (y = 0; y < g->bitmap.rows; y++)
            for (x = 0; x < g->bitmap.width; x++) {
                int X = pen + g->bitmap_left + (int)x;
                int Y = *base - g->bitmap_top + (int)y;
                if (X >= 0 && Y >= 0 && X < *rw && Y < *rh)
                    r[(size_t)Y * *rw + X] =
                        g->bitmap.buffer[y * (unsigned)g->bitmap.pitch + x];
            }
        pen += (int)(g->advance.x >> 6);
    }
    *tw = pen - 1;
    return r;
}

/* Draw the text with a real font (DejaVu Sans), centred on the chord,
 * reading along (ux, uy). */
static int draw_text_ft(uint8_t *lay, int w, int h, const place *q,
                        FT_Face face, double ux, double uy)
{
    double cx = 0.5 * (q->x0 + q->x1), cy = 0.5 * (q->y0 + q->y1), tw, R;
    int rw, rh, base, x, y;
    uint8_t *r = ft_raster(face, q, &rw, &rh, &base, &tw);
    if (!r)
        return TD_ENOMEM;
    R = 0.5 * tw + q->H + 2;
    for (y = (int)(cy - R); y <= (int)(cy + R); y++)
        for (x = (int)(cx - R); x <= (int)(cx + R); x++) {
            double px = x + 0.5 - cx, py = y + 0.5 - cy;
            double u = px * ux + py * uy, v = px * uy - py * ux; /* v: up */
            double tx = u + 0.5 * tw + 1 - 0.5, ty = base - (v + 0.5 * q->H) - 0.5;
            int ix = (int)floor(tx), iy = (int)floor(ty);
            double fx = tx - ix, fy = ty - iy, c;
            if (x < 0 || y < 0 || x >= w || y >= h || ix < 0 || iy < 0 ||
                ix + 1 >= rw || iy + 1 >= rh)
                continue;
            c = (1 - fy) * ((1 - fx) * r[(size_t)iy * rw + ix] +
                            fx * r[(size_t)iy * rw + ix + 1]) +
                fy * ((1 - fx) * r[(size_t)(iy + 1) * rw + ix] +
                      fx * r[(size_t)(iy + 1) * rw + ix + 1]);
            if (c > lay[(size_t)y * w + x])
                lay[(size_t)y * w + x] = (uint8_t)(c + 0.5);
        }
    free(r);
    return 0;
}

/* Draw the text centred on the chord, reading along (ux, uy). */
static void draw_text(uint8_t *lay, int w, int h, const place *q, double ux,
                      double uy)
{
    double cx = 0.5 * (q->x0 + q->x1),
           cy = 0.5 * (q->y0 + q->y1), gw = 0.55 * q->H, tw, r;
    int nd = (int)strlen(q->text), g, s;
    tw = nd * gw + (nd - 1) * 0.4 * q->H;
    r = 0.5 * q->stroke + 0.5;
    for (g = 0; g < nd; g++) {
        char ch = q->text[g];
        unsigned m = ch == '-' ? 0x40 : ch >= '0' && ch <= '9' ? digit_segs[ch - '0'] : 0;
        double ox = -0.5 * tw + g * (gw + 0.4 * q->H);
        for (s = 0; s < 7; s++) {
            double pt[2][2];
            int e;
            if (!(m >> s & 1))
                continue;
            for (e = 0; e < 2; e++) {
                double gx = ox + seg_xy[s][2 * e] * gw;
                double gy = (seg_xy[s][2 * e + 1] - 0.5) * q->H; /* up */
                pt[e][0] = cx + gx * ux + gy * uy;
                pt[e][1] = cy + gx * uy - gy * ux;
            }
            td_gen_draw_seg(lay, w, h, pt[0][0], pt[0][1], pt[1][0], pt[1][1], r);
        }
    }
}

static int is_index(double height, const td_gen_params *p, double interval)
{
    double k = floor((height - p->base) / interval + 0.5);
    return fabs(fmod(k, 5.0)) < 0.5;
}

/* Up to p->labels places on line i, kept 80 px from earlier ones. */
static int place_on_line(const td_lines *ls, size_t i, const td_gen_params *p,
                         double interval, td_rng *r, place **pl, size_t *np,
                         size_t *cap)
{
    arc a;
    size_t j, nl, t, k;
    const td_line *l = &ls->v[i];
    if (!l->has_height || !is_index(l->height, p, interval) || l->n < 8)
        return 0;
    if (arc_make(l, &a) != 0)
        return TD_ENOMEM;
    nl = (size_t)(a.len / 250.0);
    nl = nl > (size_t)p->labels ? (size_t)p->labels : nl;
    for (j = 0; j < nl; j++)
        for (t = 0; t < 8; t++) {
            double s = (j + td_rng_range(r, 0.15, 0.85)) * a.len / nl;
            place q;
            int far = 1;
            q.font = p->label_font;
            if (!size_label(r, l->height, td_gen_width_of(l, p, interval), s,
                            &q) ||
                (!l->closed && (q.s0 < 50 || q.s1 > a.len - 50)))
                continue;
            arc_at(&a, q.s0, &q.x0, &q.y0);
            arc_at(&a, q.s1, &q.x1, &q.y1);
            for (k = 0; k < *np; k++)
                far &= hypot((*pl)[k].x0 - q.x0, (*pl)[k].y0 - q.y0) > 80;
            if (!far || !straight(&a, &q, p) ||
                !clear_of(ls, i, &a, &q,
                          0.5 * q.H + td_gen_width_of(l, p, interval) + 4, p))
                continue;
            if (*np == *cap) {
                place *v = realloc(*pl, (*cap = *cap ? 2 * *cap : 32) * sizeof *v);
                if (!v) {
                    free(a.cum);
                    return TD_ENOMEM;
                }
                *pl = v;
            }
            q.line = i;
            (*pl)[(*np)++] = q;
            break;
        }
    free(a.cum);
    return 0;
}

/* Contract in gen.h. */
int td_gen_labels(const td_lines *truth, const td_gen_params *p,
                  double interval, td_image *im, size_t *nplaced, td_ctx *cx)
{
    return td_gen_labels_dem(truth, p, interval, NULL, im, NULL, nplaced, cx);
}

static int open_font(FT_Library *lib, FT_Face *face, td_ctx *cx)
{
    if (FT_Init_FreeType(lib))
        return td_seterr(cx, TD_ENOMEM, "labels: FreeType did not start");
    if (FT_New_Face(*lib, FONT_FILE, 0, face)) {
        FT_Done_FreeType(*lib);
        *lib = NULL;
        return td_seterr(cx, TD_EIO, "labels: %s: cannot open the font "
                         "(install fonts-dejavu-core)", FONT_FILE);
    }
    return 0;
}

/* Undo open_font (either may be NULL). */
static void close_font(FT_Library lib, FT_Face face)
{
    if (face)
        FT_Done_Face(face);
    if (lib)
        FT_Done_FreeType(lib);
}

/* Contract in gen.h. */
int td_gen_labels_dem(const td_lines *truth, const td_gen_params *p,
                      double interval, const td_grid_f32 *dem, td_image *im,
                      double **out, size_t *nout, td_ctx *cx)
{
    static const uint8_t brown[3] = {160, 90, 40}, black[3] = {0, 0, 0};
    td_rng r = td_rng_make(p->seed, 8);
    place *pl = NULL;
    size_t np = 0, cap = 0, i;
    uint8_t *lay = NULL;
    FT_Library lib = NULL;
    FT_Face face = NULL;
    int rc = TD_ENOMEM;
    if (out)
        *out = NULL;
    if (nout)
        *nout = 0;
    if (p->labels <= 0 || !(interval > 0))
        return 0;
    if (p->label_font && (rc = open_font(&lib, &face, cx)) != 0)
        return rc;
    rc = TD_ENOMEM;
    for (i = 0; i < truth->n; i++)
        if (place_on_line(truth, i, p, interval, &r, &pl, &np, &cap) != 0)
            goto fail;
    if (!(lay = td_calloc((size_t)im->w * (size_t)im->h, 1, cx)) ||
        (out && !(*out = malloc((6 * np + 1) * sizeof **out))))
        goto fail;
    for (i = 0; i < np; i++) {
        double ux, uy;
        if (erase_gap(im, &truth->v[pl[i].line], &pl[i],
                      fmax(p->line_width, p->index_width),
                      im->channels == 3) != 0)
            goto fail;
        reading_dir(&pl[i], dem, &ux, &uy);
        if (face) {
            if (draw_text_ft(lay, im->w, im->h, &pl[i], face, ux, uy) != 0)
                goto fail;
        } else {
            draw_text(lay, im->w, im->h, &pl[i], ux, uy);
        }
        if (out) {
            double *o = *out + 6 * i;
            o[0] = 0.5 * (pl[i].x0 + pl[i].x1);
            o[1] = 0.5 * (pl[i].y0 + pl[i].y1);
            o[2] = ux, o[3] = uy, o[4] = pl[i].H;
            o[5] = truth->v[pl[i].line].height;
        }
    }
    td_gen_composite(im, lay, im->channels == 3 ? brown : black);
    if (nout)
        *nout = np;
    rc = 0;
fail:
    if (rc) {
        td_seterr(cx, TD_ENOMEM, "labels: out of memory");
        if (out) {
            free(*out);
            *out = NULL;
        }
    }
    close_font(lib, face);
    free(pl);
    free(lay);
    return rc;
}

/* ---- spot heights ---------------------------------------------------- */

enum { SPOT_WIN = 20, SPOT_RING = 30, SPOT_EDGE = 40, SPOT_APART = 120 };

typedef struct spot {
    int x, y;
    double z;
    int sg; /* 1 summit, -1 pit */
} spot;

/* Summits first, the highest first; then pits, the lowest first. */
static int spot_cmp(const void *a, const void *b)
{
    const spot *p = a, *q = b;
    double za = p->sg * p->z, zb = q->sg * q->z;
    if (p->sg != q->sg)
        return p->sg > q->sg ? -1 : 1;
    return za < zb ? 1 : za > zb ? -1 : 0;
}

/* Whether (x, y) is the highest (sg 1) or lowest (sg -1) cell within
 * SPOT_WIN and at least drop above (below) the lowest (highest) of 16
 * points SPOT_RING away. */
static int is_summit(const td_grid_f32 *g, int x, int y, double drop, int sg)
{
    double z = sg * TD_AT(g, x, y), lo = z;
    int dx, dy, k;
    for (dy = -SPOT_WIN; dy <= SPOT_WIN; dy++)
        for (dx = -SPOT_WIN; dx <= SPOT_WIN; dx++) {
            double v = sg * TD_AT(g, x + dx, y + dy);
            if ((dx || dy) && (v > z || (v == z && (dy < 0 || (dy == 0 && dx < 0)))))
                return 0;
        }
    for (k = 0; k < 16; k++) {
        double a = k * M_PI / 8;
        int px = x + (int)lround(SPOT_RING * cos(a));
        int py = y + (int)lround(SPOT_RING * sin(a));
        lo = fmin(lo, sg * TD_AT(g, px, py));
    }
    return z - lo >= drop;
}

/* Summits and pits (summits first), SPOT_APART from each other; at most
 * max. */
static int find_summits(const td_grid_f32 *g, double drop, int max,
                        spot **out, size_t *n)
{
    size_t cap = 64, m = 0, i, k;
    spot *v = malloc(cap * sizeof *v);
    int x, y;
    *out = NULL;
    *n = 0;
    if (!v)
        return TD_ENOMEM;
    for (y = SPOT_EDGE; y < g->h - SPOT_EDGE; y++)
        for (x = SPOT_EDGE; x < g->w - SPOT_EDGE; x++) {
            int sg = is_summit(g, x, y, drop, 1) ? 1
                     : is_summit(g, x, y, drop, -1) ? -1 : 0;
            if (!sg)
                continue;
            if (m == cap) {
                spot *nv = realloc(v, (cap *= 2) * sizeof *nv);
                if (!nv) {
                    free(v);
                    return TD_ENOMEM;
                }
                v = nv;
            }
            v[m++] = (spot){x, y, TD_AT(g, x, y), sg};
        }
    qsort(v, m, sizeof *v, spot_cmp);
    for (i = 0; i < m && (int)*n < max; i++) {
        int far = 1;
        for (k = 0; k < *n && far; k++)
            far = hypot(v[k].x - v[i].x, v[k].y - v[i].y) >= SPOT_APART;
        if (far)
            v[(*n)++] = v[i];
    }
    *out = v;
    return 0;
}

/* Dark pixels of im in the box of q's text (its chord +- H/2 + 2). */
static long ink_under(const td_image *im, const place *q)
{
    int x, y, c, ch = im->channels;
    long n = 0;
    double R = 0.5 * q->H + 2;
    for (y = (int)(fmin(q->y0, q->y1) - R); y <= (int)(fmax(q->y0, q->y1) + R); y++)
        for (x = (int)(fmin(q->x0, q->x1)); x <= (int)(fmax(q->x0, q->x1)); x++) {
            int sum = 0;
            if (x < 0 || y < 0 || x >= im->w || y >= im->h)
                return 1L << 30; /* off the sheet */
            for (c = 0; c < ch; c++)
                sum += im->data[((size_t)y * im->w + x) * ch + c];
            n += sum < 160 * ch;
        }
    return n;
}

/* The text's place beside the dot at (x, y): right, left, above, below,
 * whichever covers the least ink; returns that ink (pixels). */
static long spot_place(const td_image *im, int x, int y, place *q)
{
    static const int side[4][2] = {{1, 0}, {-1, 0}, {0, -1}, {0, 1}};
    double tw = text_width(q), best = -1, bx0 = 0, by = 0;
    int k;
    for (k = 0; k < 4; k++) {
        double cx = x + 0.5 + side[k][0] * (0.5 * tw + 8),
               cy = y + 0.5 + side[k][1] * (0.5 * q->H + 8);
        long ink;
        q->x0 = cx - 0.5 * tw, q->x1 = cx + 0.5 * tw, q->y0 = q->y1 = cy;
        ink = ink_under(im, q);
        if (best < 0 || ink < best)
            best = (double)ink, bx0 = q->x0, by = cy;
    }
    q->x0 = bx0, q->x1 = bx0 + tw, q->y0 = q->y1 = by;
    return (long)best;
}

/* Whether im has dark pixels within r of (x, y). */
static int ink_near(const td_image *im, int x, int y, int r)
{
    int dx, dy, c, ch = im->channels;
    for (dy = -r; dy <= r; dy++)
        for (dx = -r; dx <= r; dx++) {
            int px = x + dx, py = y + dy, sum = 0;
            if (px < 0 || py < 0 || px >= im->w || py >= im->h)
                continue;
            for (c = 0; c < ch; c++)
                sum += im->data[((size_t)py * im->w + px) * ch + c];
            if (sum < 160 * ch)
                return 1;
        }
    return 0;
}

/* A filled dot of radius r at (x + 0.5, y + 0.5) into lay. */
static void draw_dot(uint8_t *lay, int w, int h, int x, int y, double r)
{
    int dx, dy, R = (int)ceil(r) + 1;
    for (dy = -R; dy <= R; dy++)
        for (dx = -R; dx <= R; dx++) {
            double d = hypot(dx, dy), c = fmin(1.0, fmax(0.0, r + 0.5 - d));
            int px = x + dx, py = y + dy;
            if (px < 0 || py < 0 || px >= w || py >= h || c <= 0)
                continue;
            if (255 * c > lay[(size_t)py * w + px])
                lay[(size_t)py * w + px] = (uint8_t)(255 * c + 0.5);
        }
}

/* Contract in gen.h. */
int td_gen_spots(const td_gen_params *p, const td_grid_f32 *dem,
                 td_image *im, double **out, size_t *nout, td_ctx *cx)
{
    static const uint8_t brown[3] = {160, 90, 40}, black[3] = {0, 0, 0};
    spot *s = NULL;
    size_t n = 0, i, drawn = 0;
    uint8_t *lay = NULL;
    FT_Library lib = NULL;
    FT_Face face = NULL;
    double interval = td_gen_auto_interval(p, dem);
    int rc;
    if (out)
        *out = NULL;
    if (nout)
        *nout = 0;
    if (p->spots <= 0)
        return 0;
    if (!dem || dem->w != im->w || dem->h != im->h)
        return td_seterr(cx, TD_EINVAL, "spot heights: the surface is not "
                         "the sheet's size");
    if (p->label_font && (rc = open_font(&lib, &face, cx)) != 0)
        return rc;
    rc = TD_ENOMEM;
    if (find_summits(dem, 0.5 * interval, p->spots, &s, &n) != 0 ||
        !(lay = td_calloc((size_t)im->w * im->h, 1, cx)) ||
        (out && !(*out = malloc((3 * n + 1) * sizeof **out))))
        goto fail;
    for (i = 0; i < n; i++) {
        place q;
        memset(&q, 0, sizeof q);
        q.font = p->label_font;
        q.H = 10.0;
        q.stroke = 1.4;
        snprintf(q.text, sizeof q.text, "%ld", lround(s[i].z));
        if (spot_place(im, s[i].x, s[i].y, &q) > 0 ||
            ink_near(im, s[i].x, s[i].y, 4))
            continue; /* no clear place: cartographers leave it out */
        draw_dot(lay, im->w, im->h, s[i].x, s[i].y, 2.0);
        if (face) {
            if (draw_text_ft(lay, im->w, im->h, &q, face, 1.0, 0.0) != 0)
                goto fail;
        } else {
            draw_text(lay, im->w, im->h, &q, 1.0, 0.0);
        }
        if (out) {
            (*out)[3 * drawn] = s[i].x + 0.5;
            (*out)[3 * drawn + 1] = s[i].y + 0.5;
            (*out)[3 * drawn + 2] = s[i].z;
        }
        drawn++;
    }
    td_gen_composite(im, lay, im->channels == 3 ? brown : black);
    if (nout)
        *nout = drawn;
    rc = 0;
fail:
    if (rc) {
        td_seterr(cx, TD_ENOMEM, "spot heights: out of memory");
        if (out) {
            free(*out);
            *out = NULL;
        }
    }
    close_font(lib, face);
    free(s);
    free(lay);
    return rc;
}
