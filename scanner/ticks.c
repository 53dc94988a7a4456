/* ticks.c: see ticks.h. */
#include "scanner/ticks.h"
#include "scanner/width.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define RAY_MAX 12.0      /* px: the longest run of ink followed */
#define RAY_STEP 0.25     /* px between the samples of a run */
#define TICK_OVER 1.25    /* px: a tick widens the ink at least this much */
#define TICK_REACH 8.0    /* px: and at most this much */
#define TICK_SIDE 2.0     /* px: paper either side of a tick */
#define TICK_SPACING                                                           \
    13.0 /* pen widths of ring per tick, at least: printed ticks come every \
            8-12 line widths; sharp bends, grid lines and labels make 2-3   \
            "ticks" on rings of any length (docs/scanner.md) */
#define ONE_SIDE 0.75     /* px: a tick widens its side this much more */
#define NARROW 4          /* vertices: a tick is about one pen wide */

/* The ink run from (x, y) along (ux, uy): the distance to its last ink
 * sample, RAY_MAX when the ink goes on (a blot, another line). */
static double ray(const uint8_t *bits, int w, int h, double x, double y,
                  double ux, double uy)
{
    double s = 0.0;
    while (s + RAY_STEP <= RAY_MAX &&
           td_packed_at_pt(bits, w, h, x + (s + RAY_STEP) * ux,
                           y + (s + RAY_STEP) * uy))
        s += RAY_STEP;
    return s + RAY_STEP > RAY_MAX ? RAY_MAX : s;
}

/* The unit normal of ring l at vertex k towards its side 0 (left on the
 * screen, y down), from the chord 5 vertices either side (shorter chords
 * tilt the normal on the steps of a traced line, across its own ink). */
static void normal_at(const td_line *l, size_t k, double *nx, double *ny)
{
    size_t m = l->n, a = (k + m - 5) % m, b = (k + 5) % m;
    double tx = l->xy[2 * b] - l->xy[2 * a];
    double ty = l->xy[2 * b + 1] - l->xy[2 * a + 1], d = sqrt(tx * tx + ty * ty);
    *nx = d > 0 ? ty / d : 0;
    *ny = d > 0 ? -tx / d : 0;
}

/* Whether the ink beyond vertex (x, y) along (nx, ny), at `at` px, is a
 * thin stroke: paper TICK_SIDE px to either side of it (a bend's other
 * arm or a blot is broad). */
static int thin_stroke(const uint8_t *bits, int w, int h, double x, double y,
                       double nx, double ny, double at)
{
    double px = x + at * nx, py = y + at * ny;
    return td_packed_at_pt(bits, w, h, px, py) &&
           !td_packed_at_pt(bits, w, h, px - TICK_SIDE * ny,
                            py + TICK_SIDE * nx) &&
           !td_packed_at_pt(bits, w, h, px + TICK_SIDE * ny,
                            py - TICK_SIDE * nx);
}

/* The median of the 2 WIN + 1 values a[i * stride] of a ring of m
 * vertices about vertex k. */
#define WIN 6
static double local_med(const double *a0, size_t stride, size_t m, size_t k)
{
    double v[2 * WIN + 1];
    size_t j, a;
    for (j = 0; j < 2 * WIN + 1; j++) {
        double x = a0[((k + m + j - WIN) % m) * stride];
        for (a = j; a > 0 && v[a - 1] > x; a--)
            v[a] = v[a - 1];
        v[a] = x;
    }
    return v[WIN];
}

/* Ticks of ring l counted on the mask: runs of at most NARROW vertices
 * where the ink across the line is TICK_OVER..TICK_REACH px wider than
 * about them (the median of the nearby vertices'), the extra ink on one
 * side (the traced centre sits off the ink's middle on diagonals, so the
 * two sides' runs alone do not tell), and a thin stroke there (a bend's
 * other arm or a blot is broad).  r holds 3 numbers per vertex, f 2
 * flags.  cnt[0] the inward ticks, cnt[1] the outward. */
static void profile_ticks(const uint8_t *bits, int w, int h, const td_line *l,
                          double *r, uint8_t *f, size_t *cnt)
{
    size_t m = l->n, k, side;
    int inner = td_line_signed_area(l) > 0 ? 1 : 0;
    double *wd = r + 2 * m;
    for (k = 0; k < m; k++) {
        double x = l->xy[2 * k], y = l->xy[2 * k + 1], nx, ny, r0, r1;
        normal_at(l, k, &nx, &ny);
        r0 = ray(bits, w, h, x, y, nx, ny);
        r1 = ray(bits, w, h, x, y, -nx, -ny);
        r[2 * k + (inner == 0 ? 0 : 1)] = r0; /* [0] inward, [1] outward */
        r[2 * k + (inner == 0 ? 1 : 0)] = r1;
        wd[k] = r0 + r1;
    }
    memset(f, 0, 2 * m);
    for (k = 0; k < m; k++) {
        double base, nx, ny, e[2];
        size_t j, below = 0, q = (k + m - WIN) % m;
        /* the cheap test first, most fail it: the median (the WIN + 1st
           smallest) + TICK_OVER is at most wd[k] exactly when WIN + 1 of
           the window's values are (v + TICK_OVER rounds monotonically) */
        for (j = 0; j < 2 * WIN + 1; j++, q = q + 1 == m ? 0 : q + 1)
            below += wd[q] + TICK_OVER <= wd[k];
        if (below < WIN + 1)
            continue;
        base = local_med(wd, 1, m, k);
        if (wd[k] < base + TICK_OVER || wd[k] > base + TICK_REACH)
            continue;
        /* the side that widened: its run against its own runs about it
         * (the traced centre sits off the ink's middle, more so on
         * diagonals and where blur widens both sides) */
        e[0] = r[2 * k] - local_med(r, 2, m, k);
        e[1] = r[2 * k + 1] - local_med(r + 1, 2, m, k);
        side = e[0] >= e[1] ? 0 : 1;
        if (e[side] < ONE_SIDE + e[1 - side])
            continue;
        normal_at(l, k, &nx, &ny); /* towards the line's side 0, which
                                      is the inside when inner == 0 */
        if ((side == 0) != (inner == 0))
            nx = -nx, ny = -ny;
        f[2 * k + side] = (uint8_t)thin_stroke(bits, w, h, l->xy[2 * k],
                                               l->xy[2 * k + 1], nx, ny,
                                               r[2 * k + side] - 0.5);
    }
    for (side = 0; side < 2; side++) {
        size_t start = m, run = 0, j;
        for (k = 0; k < m && start == m; k++)
            if (!f[2 * k + side])
                start = k; /* walk the ring from a vertex off any tick */
        for (j = 1; start < m && j <= m; j++) {
            if (f[2 * ((start + j) % m) + side]) {
                run++;
                continue;
            }
            if (run > 0 && run <= NARROW)
                cnt[side]++;
            run = 0;
        }
    }
}

long td_ticks_mark(td_lines *ls, const uint8_t *bits, int w, int h,
                   int min_in, td_ctx *cx)
{
    size_t mx = 0, i;
    long marked = 0;
    int fail = 0;
    double pen = td_pen_width(ls, cx);
    if (pen < 0)
        return TD_ENOMEM;
    pen = fmax(pen, 1.5);
    for (i = 0; i < ls->n; i++)
        if (ls->v[i].closed && ls->v[i].n > mx)
            mx = ls->v[i].n;
#pragma omp parallel reduction(+ : marked) reduction(| : fail)
    { /* rings on threads, each with its own profile buffers */
        double *r = malloc(3 * mx * sizeof *r + 1);
        uint8_t *f = malloc(2 * mx + 1);
        size_t j;
        fail |= !r || !f;
#pragma omp for schedule(dynamic, 16)
        for (j = 0; j < ls->n; j++) {
            td_line *l = &ls->v[j];
            size_t c[2] = {0, 0};
            double per, half;
            l->depression = 0;
            if (!r || !f || !l->closed || l->n < 12)
                continue;
            per = td_line_length(l);
            half = 2.0 * fabs(td_line_signed_area(l)) / fmax(per, 1.0);
            /* a ring too narrow inside for a tick to show (the mean
             * half-width 2 area / perimeter) */
            if (half < pen + 2.0)
                continue;
            profile_ticks(bits, w, h, l, r, f, c);
            /* printed ticks come every few line widths: a long ring with
             * a few bumps inside is noise, not a depression */
            l->depression = c[0] >= (size_t)min_in &&
                            (double)c[0] >= per / (TICK_SPACING * pen) &&
                            c[0] > 2 * c[1];
            marked += l->depression;
        }
        free(r);
        free(f);
    }
    if (fail)
        return td_seterr(cx, TD_ENOMEM, "ticks: out of memory");
    return marked;
}
