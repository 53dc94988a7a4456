/* Ink width of traced lines (width.h).  At a sample point P with unit
 * normal n, the run is the ink on both sides of P along n:
 *
 *        paper . . . . . . .
 *        ink   ####^#######     run = a + b, stepped in 1/8 px, each
 *        ink   ####P#######     step read from the pixel it falls in
 *        ink   ####v#######
 *        paper . . . . . . .
 */
#include "scanner/width.h"

#include <math.h>
#include <stdlib.h>

#define W_STEP 4     /* vertices (about px) between samples */
#define W_CHORD 3    /* vertices either side for the local direction */
#define W_END 4      /* vertices skipped at an open line's ends */
#define W_MAX 24.0   /* longer runs are not a line's width */
#define W_MIN_RUNS 5
#define W_RES 0.25 /* px: the runs' step */

/* The mask: bytes (a td_grid_u8) or bits (packed rows, bit c & 7 of byte
 * c >> 3 is column c). */
typedef struct wmask {
    int w, h;
    size_t stride;
    const uint8_t *bytes, *bits;
} wmask;

static int ink_at(const wmask *m, double x, double y)
{
    if (m->bits)
        return td_packed_at_pt(m->bits, m->w, m->h, x, y);
    if (!(x >= 0 && y >= 0 && x < m->w && y < m->h))
        return 0;
    return m->bytes[(size_t)(long)y * m->stride + (size_t)(long)x] != 0;
}

/* Distance from (x,y) along (dx,dy) to the first paper, at most W_MAX. */
static double run(const wmask *m, double x, double y, double dx,
                  double dy)
{
    double t;
    for (t = 0.0; t <= W_MAX; t += W_RES)
        if (!ink_at(m, x + t * dx, y + t * dy))
            return t;
    return W_MAX + 1.0;
}

/* Contract in width.h. */
int td_line_normal(const td_line *l, size_t k, size_t chord, double *nx,
                   double *ny)
{
    size_t n = l->n;
    size_t ka = l->closed ? (k + n - chord % n) % n
                          : (k >= chord ? k - chord : 0);
    size_t kb = l->closed ? (k + chord) % n
                          : (k + chord < n ? k + chord : n - 1);
    double dx = l->xy[2 * kb] - l->xy[2 * ka];
    double dy = l->xy[2 * kb + 1] - l->xy[2 * ka + 1];
    double d = sqrt(dx * dx + dy * dy); /* not hypot: see lines.c */
    if (d < 1.0)
        return 0;
    *nx = -dy / d, *ny = dx / d;
    return 1;
}

/* Contract in width.h. */
double td_width_across(const uint8_t *bits, int w, int h, double x, double y,
                       double nx, double ny)
{
    wmask m = {w, h, ((size_t)w + 7) / 8, NULL, bits};
    return run(&m, x, y, nx, ny) + run(&m, x, y, -nx, -ny);
}

/* Contract in width.h. */
double td_width_step_below(double t)
{
    return floor(t / W_RES) * W_RES;
}

static int cmp_d(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The vertices a line is sampled at: lo, lo + step, ... below hi (every
 * W_STEP-th or sparser, at most max; W_END skipped at an open line's
 * ends). */
static void sample_span(const td_line *l, size_t max, size_t *lo, size_t *hi,
                        size_t *step)
{
    size_t n = l->n;
    *lo = l->closed ? 0 : W_END;
    *hi = l->closed ? n : (n > W_END ? n - W_END : 0);
    *step = *hi > *lo ? (*hi - *lo) / max + 1 : 1;
    *step = *step < W_STEP ? W_STEP : *step;
}

/* The median of v[0..n-1] (sorted in place), 0 with fewer than
 * W_MIN_RUNS. */
static double median_of(double *v, size_t n)
{
    if (n < W_MIN_RUNS)
        return 0.0;
    qsort(v, n, sizeof *v, cmp_d);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* The median run of one line, 0 when fewer than W_MIN_RUNS.  Traced lines
 * have a vertex per pixel step (1 to 1.41 px), so samples are taken at
 * every W_STEP-th vertex and the chord spans W_CHORD vertices each way
 * (skipping W_END vertices at an open line's ends); no arc lengths. */
static double line_width(const wmask *m, const td_line *l, double *runs,
                         size_t maxruns)
{
    size_t k, nr = 0, lo, hi, step;
    sample_span(l, maxruns, &lo, &hi, &step);
    for (k = lo; k < hi && nr < maxruns; k += step) {
        double x = l->xy[2 * k], y = l->xy[2 * k + 1], nx, ny, r;
        if (!td_line_normal(l, k, W_CHORD, &nx, &ny) || !ink_at(m, x, y))
            continue;
        r = run(m, x, y, nx, ny) + run(m, x, y, -nx, -ny);
        if (r <= W_MAX)
            runs[nr++] = r;
    }
    return median_of(runs, nr);
}

/* Every line's width (only_unset: of the lines whose width is 0); lines
 * on threads (each alone). */
static int widths(const wmask *mask, td_lines *ls, int only_unset, td_ctx *cx)
{
    long n = (long)ls->n;
    int fail = 0;
#pragma omp parallel reduction(| : fail)
    {
        size_t maxruns = 512;
        double *runs = malloc(maxruns * sizeof *runs);
        long i;
        fail |= !runs;
#pragma omp for schedule(dynamic, 16)
        for (i = 0; i < n; i++) {
            td_line *l = &ls->v[i];
            if (runs && !(only_unset && l->width > 0))
                l->width = l->n < 2 ? 0.0 : line_width(mask, l, runs, maxruns);
        }
        free(runs);
    }
    return fail ? td_seterr(cx, TD_ENOMEM, "widths: out of memory") : 0;
}

/* Contract in width.h. */
/* Whether l is at least len px long (open: its arc; closed: with the
 * closing segment), walking only as far as it needs to. */
static int long_enough(const td_line *l, double len)
{
    double s = 0;
    size_t i;
    for (i = 1; i < l->n && s < len; i++) {
        double dx = l->xy[2 * i] - l->xy[2 * i - 2];
        double dy = l->xy[2 * i + 1] - l->xy[2 * i - 1];
        s += sqrt(dx * dx + dy * dy);
    }
    return s >= len || td_line_length(l) >= len;
}

double td_pen_width(const td_lines *ls, td_ctx *cx)
{
    double *v = td_malloc((ls->n + 1) * sizeof *v, cx), med = 0;
    size_t i, n = 0;
    if (!v)
        return -1;
    for (i = 0; i < ls->n; i++)
        if (ls->v[i].width > 0 && long_enough(&ls->v[i], 30))
            v[n++] = ls->v[i].width;
    if (n) {
        qsort(v, n, sizeof *v, cmp_d);
        med = v[n / 2];
    }
    free(v);
    return med;
}

/* Contract in width.h. */
int td_line_widths(const td_grid_u8 *mask, td_lines *ls, td_ctx *cx)
{
    wmask m = {mask->w, mask->h, mask->stride, mask->data, NULL};
    return widths(&m, ls, 0, cx);
}

/* Contract in width.h. */
uint8_t *td_width_pack(const td_grid_u8 *mask, td_ctx *cx)
{
    size_t bs = ((size_t)mask->w + 7) / 8;
    uint8_t *bits = td_calloc((size_t)mask->h * bs + 1, 1, cx);
    long r;
    if (!bits)
        return NULL;
#pragma omp parallel for schedule(static)
    for (r = 0; r < (long)mask->h; r++) {
        const uint8_t *src = mask->data + (size_t)r * mask->stride;
        uint8_t *dst = bits + (size_t)r * bs;
        size_t w8 = (size_t)mask->w / 8 * 8, c;
        for (c = 0; c < w8; c += 8) /* eight pixels a byte, no branch */
            dst[c >> 3] = (uint8_t)((src[c] != 0) | (src[c + 1] != 0) << 1 |
                                    (src[c + 2] != 0) << 2 |
                                    (src[c + 3] != 0) << 3 |
                                    (src[c + 4] != 0) << 4 |
                                    (src[c + 5] != 0) << 5 |
                                    (src[c + 6] != 0) << 6 |
                                    (src[c + 7] != 0) << 7);
        for (; c < (size_t)mask->w; c++)
            dst[c >> 3] |= (uint8_t)((src[c] != 0) << (c & 7));
    }
    return bits;
}

/* Contract in width.h. */
int td_line_widths_packed(const uint8_t *bits, int w, int h, td_lines *ls,
                          td_ctx *cx)
{
    wmask m = {w, h, ((size_t)w + 7) / 8, NULL, bits};
    return widths(&m, ls, 0, cx);
}

/* Contract in width.h. */
int td_line_widths_packed_unset(const uint8_t *bits, int w, int h, td_lines *ls,
                                td_ctx *cx)
{
    wmask m = {w, h, ((size_t)w + 7) / 8, NULL, bits};
    return widths(&m, ls, 1, cx);
}

/* The darkness (paper minus the channel) at (x, y), nearest pixel. */
static int dark_at(const td_image *im, int c, int paper, double x, double y)
{
    long xi = lround(x - 0.5), yi = lround(y - 0.5);
    int v;
    if (xi < 0 || yi < 0 || xi >= im->w || yi >= im->h)
        return 0;
    v = im->data[(size_t)yi * im->stride + (size_t)xi * im->channels + c];
    return paper > v ? paper - v : 0;
}

/* The median darkness of one line's middle, 0 when too few samples. */
static double line_dark(const td_image *im, int c, int paper, const td_line *l,
                        double *v, size_t maxv)
{
    size_t k, nv = 0, lo, hi, step;
    sample_span(l, maxv, &lo, &hi, &step);
    for (k = lo; k < hi && nv < maxv; k += step) {
        double x = l->xy[2 * k], y = l->xy[2 * k + 1], nx, ny, t;
        int best = 0;
        if (!td_line_normal(l, k, W_CHORD, &nx, &ny))
            continue;
        for (t = -TD_DARK_REACH; t <= TD_DARK_REACH + 1e-9; t += W_RES) {
            int d = dark_at(im, c, paper, x + t * nx, y + t * ny);
            best = d > best ? d : best;
        }
        v[nv++] = best;
    }
    return median_of(v, nv) / paper;
}

/* Contract in width.h. */
int td_line_darkness(const td_image *im, td_lines *ls, td_ctx *cx)
{
    long hist[256] = {0}, n = 0, acc = 0, i;
    int c, paper, step, x, y, fail = 0;
    if (!im || !im->data || (im->channels != 1 && im->channels != 3))
        return td_seterr(cx, TD_EINVAL, "darkness: not a grey or RGB image");
    c = im->channels == 3 ? 1 : 0;
    step = (int)fmax(1.0, floor(sqrt((double)im->w * im->h / 250000.0)));
    for (y = step / 2; y < im->h; y += step)
        for (x = step / 2; x < im->w; x += step, n++)
            hist[im->data[(size_t)y * im->stride + (size_t)x * im->channels +
                          c]]++;
    for (paper = 0; paper < 256 && (acc += hist[paper]) * 2 < n; paper++)
        ;
    if (paper < 1)
        paper = 1;
    n = (long)ls->n;
#pragma omp parallel reduction(| : fail)
    {
        size_t maxv = 512;
        double *v = malloc(maxv * sizeof *v);
        fail |= !v;
#pragma omp for schedule(dynamic, 16)
        for (i = 0; i < n; i++) {
            td_line *l = &ls->v[i];
            if (v)
                l->ink = l->n < 2 ? 0.0 : line_dark(im, c, paper, l, v, maxv);
        }
        free(v);
    }
    return fail ? td_seterr(cx, TD_ENOMEM, "darkness: out of memory") : 0;
}

/* Contract in width.h. */
int td_lines_inked(const td_lines *ls)
{
    size_t i, n = 0, dark = 0;
    for (i = 0; i < ls->n; i++)
        if (ls->v[i].width > 0)
            n++, dark += ls->v[i].ink > 0;
    return n > 0 && dark >= 0.9 * (double)n;
}

/* Contract in width.h. */
void td_packed_lines(uint8_t *bits, int w, int h, const td_lines *ls,
                     const unsigned char *only, int grow, int set)
{
    size_t row = ((size_t)w + 7) / 8, i, k;
    for (i = 0; i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        if ((only && !only[i]) || l->n == 0)
            continue;
        for (k = 0; k < l->n + (l->closed && l->n > 2); k++) {
            const double *a = l->xy + 2 * (k ? k - 1 : 0),
                         *b = l->xy + 2 * (k % l->n);
            int j,
                m = (int)ceil(2 * fmax(fabs(b[0] - a[0]), fabs(b[1] - a[1])));
            for (j = 0; j <= m; j++) {
                double t = m ? (double)j / m : 0;
                int cx = (int)floor(a[0] + (b[0] - a[0]) * t),
                    cy = (int)floor(a[1] + (b[1] - a[1]) * t), u, v;
                for (v = cy - grow; v <= cy + grow; v++)
                    for (u = cx - grow; u <= cx + grow; u++) {
                        uint8_t *p, bit = (uint8_t)(1u << (u & 7));
                        if (u < 0 || v < 0 || u >= w || v >= h)
                            continue;
                        p = bits + (size_t)v * row + (size_t)u / 8;
                        *p = set ? (uint8_t)(*p | bit) : (uint8_t)(*p & ~bit);
                    }
            }
        }
    }
}
