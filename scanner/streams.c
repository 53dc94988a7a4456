/* streams.c: the Vs where streams cross the contours (streams.h). */
#include "scanner/streams.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define WATER_B (-8.0) /* CIELAB b* of a water ink at most this */
#define WATER_A 0.4    /* coverage of the water ink for a water pixel */
#define VEE_RUN 12.0   /* px: a longer wet stretch runs along the line */
#define VEE_APEX 2.0   /* px: the bend's offset 8 px either side, at least */
#define VEE_SURE 4.0   /* ... and this much counts in full */
#define WET_R 8        /* px: about a crossing, ... */
#define WET_MIN 8      /* ... at least this many water pixels */
#define SKIP_R 4.0     /* px from a join across the water */
#define SIDE_LO 3.0    /* water on both sides this far ... */
#define SIDE_HI 10.0   /* ... to this far (px) */

/* See streams.h. */
unsigned td_streams_water_inks(const td_palette *pal)
{
    unsigned set = 0;
    int i;
    for (i = 0; i < pal->n; i++) {
        const td_ink *k = &pal->ink[i];
        if (k->role == TD_INKROLE_INK && i != pal->chosen &&
            !(pal->also >> i & 1u) && k->lab[2] <= WATER_B &&
            -k->lab[2] >= fabs(k->lab[1]))
            set |= 1u << i;
    }
    return set;
}

typedef struct wet {
    const td_image *im;
    const uint8_t *tab; /* per table node: 1 water */
} wet;

static int wet_px(const wet *w, int x, int y)
{
    if (x < 0 || y < 0 || x >= w->im->w || y >= w->im->h)
        return 0;
    return w->tab[td_palette_node(w->im->data + (size_t)y * w->im->stride +
                                  3 * (size_t)x)];
}

/* Water within r px of (x, y). */
static int wet_near(const wet *w, double x, double y, int r)
{
    int cx = (int)lround(x), cy = (int)lround(y), dx, dy;
    for (dy = -r; dy <= r; dy++)
        for (dx = -r; dx <= r; dx++)
            if (dx * dx + dy * dy <= r * r && wet_px(w, cx + dx, cy + dy))
                return 1;
    return 0;
}

/* Point at arclength s along line l from vertex k (s < 0: backwards);
 * closed lines wrap.  0 when the line ends first. */
static int walk(const td_line *l, size_t k, double s, double *x, double *y)
{
    size_t n = l->closed ? l->n - 1 : l->n, i = k, steps = 0;
    double left = fabs(s);
    int dir = s < 0 ? -1 : 1;
    if (n < 2)
        return 0;
    while (steps++ < n) {
        size_t j;
        double dx, dy, d;
        if (dir > 0)
            j = i + 1 < n ? i + 1 : (l->closed ? 0 : n);
        else
            j = i > 0 ? i - 1 : (l->closed ? n - 1 : n);
        if (j == n)
            return 0;
        dx = l->xy[2 * j] - l->xy[2 * i];
        dy = l->xy[2 * j + 1] - l->xy[2 * i + 1];
        d = hypot(dx, dy);
        if (d >= left) {
            double f = d > 0 ? left / d : 0;
            *x = l->xy[2 * i] + f * dx;
            *y = l->xy[2 * i + 1] + f * dy;
            return 1;
        }
        left -= d;
        i = j;
    }
    return 0;
}

/* Water on both sides of the line at (x, y): pixels SIDE_LO-SIDE_HI px
 * across it (along (nx, ny) and against it), no farther along the line
 * than 1.2 times across (a stream meeting the line at 40 deg or more). */
static int wet_sides(const wet *w, double x, double y, double nx, double ny)
{
    int r = (int)SIDE_HI, cx = (int)lround(x), cy = (int)lround(y), dx, dy;
    int side = 0;
    for (dy = -r; dy <= r; dy++)
        for (dx = -r; dx <= r; dx++) {
            double ex = cx + dx - x, ey = cy + dy - y;
            double dn = ex * nx + ey * ny, dt = fabs(ex * ny - ey * nx);
            if (fabs(dn) < SIDE_LO || fabs(dn) > SIDE_HI ||
                dt > 1.2 * fabs(dn) || !wet_px(w, cx + dx, cy + dy))
                continue;
            side |= dn > 0 ? 1 : 2;
        }
    return side == 3;
}

/* Water pixels within WET_R px of (x, y). */
static int wet_count(const wet *w, double x, double y)
{
    int X = (int)lround(x), Y = (int)lround(y), dx, dy, n = 0;
    for (dy = -WET_R; dy <= WET_R; dy++)
        for (dx = -WET_R; dx <= WET_R; dx++)
            n +=
                dx * dx + dy * dy <= WET_R * WET_R && wet_px(w, X + dx, Y + dy);
    return n;
}

/* The V at vertex k of line li, if the stream goes through there. */
static int vee_at(const wet *w, const td_lines *ls, size_t li, size_t k,
                  td_vee *v)
{
    static const double arm[3] = {8.0, 16.0, 24.0};
    const td_line *l = &ls->v[li];
    double px = l->xy[2 * k], py = l->xy[2 * k + 1], ax, ay, bx, by;
    double tx, ty, t, nx, ny, off[3];
    int j, m = 0;
    if (!walk(l, k, -3.0, &ax, &ay) || !walk(l, k, 3.0, &bx, &by))
        return 0;
    tx = bx - ax, ty = by - ay, t = hypot(tx, ty);
    if (t < 1e-9)
        return 0;
    nx = ty / t, ny = -tx / t; /* side 0 */
    if (wet_count(w, px, py) < WET_MIN || !wet_sides(w, px, py, nx, ny))
        return 0;
    for (j = 0; j < 3; j++) { /* the offsets, side 0 positive */
        if (!walk(l, k, -arm[j], &ax, &ay) || !walk(l, k, arm[j], &bx, &by))
            break;
        off[j] = (px - 0.5 * (ax + bx)) * nx + (py - 0.5 * (ay + by)) * ny;
        m++;
    }
    if (m < 2 || fabs(off[0]) < VEE_APEX || off[0] * off[1] <= 0 ||
        fabs(off[1]) < fabs(off[0]) || (m == 3 && off[1] * off[2] <= 0))
        return 0;
    v->x = px, v->y = py;
    v->line = (long)li;
    v->up = off[0] > 0 ? 0 : 1;
    v->ux = off[0] > 0 ? nx : -nx;
    v->uy = off[0] > 0 ? ny : -ny;
    v->conf = fmin(1.0, fabs(off[0]) / VEE_SURE);
    return 1;
}

/* The Vs of line li: every wet stretch short enough to be a crossing. */
static int line_vees(const wet *w, const td_lines *ls, size_t li, uint8_t *wv,
                     td_vee **out, size_t *n, size_t *cap)
{
    const td_line *l = &ls->v[li];
    size_t k = 0, N = l->n;
    for (k = 0; k < N; k++)
        wv[k] = (uint8_t)wet_near(w, l->xy[2 * k], l->xy[2 * k + 1], 2);
    k = 0;
    while (k < N) {
        size_t a = k, b, mid;
        double len = 0.0;
        if (!wv[k]) {
            k++;
            continue;
        }
        for (b = a; b + 1 < N && wv[b + 1]; b++)
            len += hypot(l->xy[2 * b + 2] - l->xy[2 * b],
                         l->xy[2 * b + 3] - l->xy[2 * b + 1]);
        k = b + 1;
        if (len > VEE_RUN || (l->closed && (a == 0 || b + 1 == N)))
            continue; /* along the line, or wrapping: not read */
        mid = a;
        {
            double half = 0.5 * len, s = 0.0;
            while (mid < b && s < half) {
                s += hypot(l->xy[2 * mid + 2] - l->xy[2 * mid],
                           l->xy[2 * mid + 3] - l->xy[2 * mid + 1]);
                mid++;
            }
        }
        if (*n == *cap) {
            size_t nc = *cap ? 2 * *cap : 64;
            td_vee *t = realloc(*out, nc * sizeof *t);
            if (!t)
                return TD_ENOMEM;
            *out = t, *cap = nc;
        }
        *n += (size_t)vee_at(w, ls, li, mid, &(*out)[*n]);
    }
    return 0;
}

/* The table of pal's water into *out (per td_palette_node): 1 where a
 * water ink explains the colour at coverage >= WATER_A; NULL when pal has
 * no water ink.  0 or TD_ENOMEM. */
static int water_table(const td_palette *pal, uint8_t **out, td_ctx *cx)
{
    const int N = TD_PALETTE_LUT_N;
    unsigned water = td_streams_water_inks(pal);
    uint8_t *tab;
    int r, g, b;
    *out = NULL;
    if (!water)
        return 0;
    if (!(tab = td_calloc(TD_PALETTE_LUT_SIZE, 1, cx)))
        return TD_ENOMEM;
    for (r = 0; r < N; r++)
        for (g = 0; g < N; g++)
            for (b = 0; b < N; b++) {
                double a = 0.0;
                int k = td_palette_classify(pal, r * 8 > 255 ? 255 : r * 8,
                                            g * 8 > 255 ? 255 : g * 8,
                                            b * 8 > 255 ? 255 : b * 8, &a);
                tab[(r * N + g) * N + b] =
                    k >= 0 && (water >> k & 1u) && a >= WATER_A;
            }
    *out = tab;
    return 0;
}

/* See streams.h. */
int td_streams_water_bits(const td_image *im, const td_palette *pal,
                          uint8_t **bits, td_ctx *cx)
{
    size_t stride = ((size_t)im->w + 7) / 8;
    uint8_t *tab, *b;
    int x, y, rc;
    *bits = NULL;
    if (im->channels != 3 || !pal || pal->n == 0)
        return 0;
    if ((rc = water_table(pal, &tab, cx)) != 0 || !tab)
        return rc;
    if (!(b = td_calloc((size_t)im->h * stride + 1, 1, cx))) {
        free(tab);
        return TD_ENOMEM;
    }
#pragma omp parallel for schedule(static) private(x)
    for (y = 0; y < im->h; y++) { /* each row its own bytes */
        const uint8_t *px = im->data + (size_t)y * im->stride;
        uint8_t *row = b + (size_t)y * stride;
        for (x = 0; x < im->w; x++, px += 3)
            if (tab[td_palette_node(px)])
                row[x >> 3] |= (uint8_t)(1u << (x & 7));
    }
    free(tab);
    *bits = b;
    return 0;
}

/* See streams.h. */
int td_streams_vees(const td_image *im, const td_palette *pal,
                    const td_lines *ls, const double *skip, size_t nskip,
                    td_vee **out, size_t *n, td_ctx *cx)
{
    uint8_t *tab = NULL, *wv = NULL;
    size_t i, cap = 0, maxn = 1;
    int rc = 0;
    wet w;
    *out = NULL;
    *n = 0;
    if (im->channels != 3 || !pal || pal->n == 0)
        return 0;
    if ((rc = water_table(pal, &tab, cx)) != 0 || !tab)
        return rc;
    for (i = 0; i < ls->n; i++)
        maxn = ls->v[i].n > maxn ? ls->v[i].n : maxn;
    if (!(wv = td_calloc(maxn, 1, cx))) {
        free(tab);
        return TD_ENOMEM;
    }
    w.im = im;
    w.tab = tab;
    for (i = 0; i < ls->n && rc == 0; i++)
        rc = line_vees(&w, ls, i, wv, out, n, &cap);
    if (rc == 0 && nskip) { /* not at the joiner's joins across the water */
        size_t k, j, m = 0;
        for (k = 0; k < *n; k++) {
            for (j = 0; j < nskip; j++)
                if (hypot((*out)[k].x - skip[2 * j],
                          (*out)[k].y - skip[2 * j + 1]) <= SKIP_R)
                    break;
            if (j == nskip)
                (*out)[m++] = (*out)[k];
        }
        *n = m;
    }
    free(tab);
    free(wv);
    if (rc) {
        free(*out);
        *out = NULL;
        *n = 0;
        return td_seterr(cx, TD_ENOMEM, "out of memory");
    }
    return 0;
}

/* See streams.h. */
void td_streams_draw(td_image *im, const td_vee *v, size_t n)
{
    static const uint8_t blue[3] = {0, 60, 255};
    double xy[10];
    td_line l;
    size_t i;
    memset(&l, 0, sizeof l);
    l.xy = xy;
    l.n = 5;
    for (i = 0; i < n; i++) {
        double x1 = v[i].x + 9 * v[i].ux, y1 = v[i].y + 9 * v[i].uy;
        xy[0] = v[i].x, xy[1] = v[i].y, xy[2] = x1, xy[3] = y1;
        xy[4] = x1 - 4 * v[i].ux + 3 * v[i].uy; /* the head */
        xy[5] = y1 - 4 * v[i].uy - 3 * v[i].ux;
        xy[6] = x1, xy[7] = y1;
        xy[8] = x1 - 4 * v[i].ux - 3 * v[i].uy;
        xy[9] = y1 - 4 * v[i].uy + 3 * v[i].ux;
        td_draw_line(im, &l, blue);
    }
}
