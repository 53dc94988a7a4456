/* erode_flow.c: STEP2-1 of velocity-field erosion, the water particles'
 * velocity field (Fujita, Muraoka, Chiba §2.1).
 *
 * A particle sits on every cell and moves independently:
 *
 *   x(t+dt) = x(t) + v(t) dt           v(t+dt) = v(t) + a(t) dt
 *   |a| = G dh / sqrt(len^2 + dh^2)    toward the lowest steepest neighbour
 *   |v| := alpha |v| + (1 - alpha) |v| (1 - exp(-beta w |v|))   (friction)
 *   v'  = (u . v) u                    u: unit tangent of the surface along v
 *   v' points more upward than v(t)  => collision, e = m dv^2 / 2, m ~ w
 *
 *   neighbours of c (len = cell * 1 or sqrt 2):     profile along v:
 *     NW  N  NE                                         v(t)
 *      W  c  E                          ___        \  /  v' (state A:
 *     SW  S  SE                        /   \__      \/   collision)
 *                                     /       \__ ___/
 *
 * Every visit adds to the cell's water count, velocity sum and energy sum
 * in the tracing thread's own accumulator; the sums are fixed-point
 * integers, so the reduction over threads is exact and order-free. */
#include "erode_int.h"

#include <math.h>
#include <omp.h>
#include <string.h>

#define ER_CHUNK 512 /* cells per work item of a thread */

static const int nb_dx[8] = {1, 1, 0, -1, -1, -1, 0, 1};
static const int nb_dy[8] = {0, 1, 1, 1, 0, -1, -1, -1};

/* Acceleration toward the lowest steepest lower neighbour of (x, y). */
static void accel(const er_state *s, const td_erode_params *p, int x, int y,
                  er_surf *f)
{
    size_t i = (size_t)y * s->w + x;
    double h0 = s->T[i], best = 0, bdh = 0, blen = 1;
    int k, bk = -1;
    for (k = 0; k < 8; k++) {
        int nx = x + nb_dx[k], ny = y + nb_dy[k];
        size_t j;
        double len, dh;
        if (nx < 0 || ny < 0 || nx >= s->w || ny >= s->h)
            continue;
        j = (size_t)ny * s->w + nx;
        if (s->wall[j] || (dh = h0 - s->T[j]) <= 0)
            continue;
        len = p->cell * ((k & 1) ? M_SQRT2 : 1.0);
        if (dh / len > best) {
            best = dh / len;
            bdh = dh;
            blen = len;
            bk = k;
        }
    }
    f->ax = f->ay = f->az = 0;
    if (bk >= 0) {
        double L2 = blen * blen + bdh * bdh, amag = p->gravity * bdh / sqrt(L2);
        double hor = amag * blen / sqrt(L2) / ((bk & 1) ? M_SQRT2 : 1.0);
        f->ax = (float)(hor * nb_dx[bk]);
        f->ay = (float)(hor * nb_dy[bk]);
        f->az = (float)(-amag * bdh / sqrt(L2));
    }
}

/* Height of a neighbour for the gradient, or the centre's when it is off
 * the grid or a wall (one-sided difference). */
static double nbh(const er_state *s, int x, int y, double h0, int *ok)
{
    size_t j;
    if (x < 0 || y < 0 || x >= s->w || y >= s->h)
        return *ok = 0, h0;
    j = (size_t)y * s->w + x;
    if (s->wall[j])
        return *ok = 0, h0;
    return *ok = 1, s->T[j];
}

static void gradient(const er_state *s, const td_erode_params *p, int x,
                     int y, er_surf *f)
{
    double h0 = s->T[(size_t)y * s->w + x], a, b;
    int oa, ob;
    a = nbh(s, x - 1, y, h0, &oa);
    b = nbh(s, x + 1, y, h0, &ob);
    f->gx = (oa + ob) ? (float)((b - a) / (p->cell * (oa + ob))) : 0.0f;
    a = nbh(s, x, y - 1, h0, &oa);
    b = nbh(s, x, y + 1, h0, &ob);
    f->gy = (oa + ob) ? (float)((b - a) / (p->cell * (oa + ob))) : 0.0f;
}

void er_surface(er_state *s, const td_erode_params *p)
{
    long y;
#pragma omp parallel for num_threads(s->nthreads) schedule(static)
    for (y = 0; y < s->h; y++) {
        int x;
        for (x = 0; x < s->w; x++) {
            size_t i = (size_t)y * s->w + x;
            er_surf *f = &s->surf[i];
            memset(f, 0, sizeof *f);
            f->wall = s->wall[i];
            if (f->wall)
                continue;
            accel(s, p, x, (int)y, f);
            gradient(s, p, x, (int)y, f);
        }
    }
}

typedef struct particle {
    double x, y, vx, vy, vz;
    double sp;  /* |v|, the speed after the last move */
    double hsp; /* |horizontal part of v| */
    size_t c;   /* cell the particle is in */
    int k;      /* moves made */
} particle;

/* Friction, tangent projection and collision at the particle's new cell
 * for the updated velocity u; returns the collision energy (0 if none).
 * |v'| = (u . t) for the unit tangent t, so the new speeds need no root. */
static double project(particle *q, const er_surf *g, double ux, double uy,
                      double uz, const td_erode_params *p)
{
    double sp = sqrt(ux * ux + uy * uy + uz * uz), hs, ih, dx, dy, sl, inv;
    double dot;
    double v0 = q->sp, dv;
    if (sp > 0) {
        double f = p->alpha + (1 - p->alpha) *
                                  (1 - exp(-p->beta * p->water * sp));
        ux *= f, uy *= f, uz *= f, sp *= f;
    }
    hs = sqrt(ux * ux + uy * uy);
    q->vx = q->vy = q->vz = q->sp = q->hsp = 0;
    if (hs <= 0)
        return 0; /* nothing horizontal left: the particle rests */
    ih = 1.0 / hs;
    dx = ux * ih, dy = uy * ih;
    sl = g->gx * dx + g->gy * dy;
    inv = 1.0 / sqrt(1.0 + sl * sl);
    dot = (ux * dx + uy * dy + uz * sl) * inv;
    if (dot > 0) {
        q->sp = dot;
        q->hsp = dot * inv;
        q->vx = q->hsp * dx;
        q->vy = q->hsp * dy;
        q->vz = dot * sl * inv;
    } else {
        dot = 0; /* head-on into the surface: all speed lost */
    }
    if (v0 <= 0 || !(sl * inv * sp > uz + 1e-9 * sp || dot == 0))
        return 0; /* v' not more upward than v(t): no collision */
    dv = sp - dot;
    return 0.5 * p->water * dv * dv;
}

enum { MV_GO = 0, MV_STOP = 1, MV_DRAIN = 2 };

/* One move (one dt) of particle q: x += v dt, v += a dt, then friction,
 * projection and collision in the cell it lands in; the visit is added to
 * acc.  MV_STOP when it rests where no neighbour is lower or has made
 * max_moves moves, MV_DRAIN when it left the grid over an open edge. */
static int move(const er_state *s, const td_erode_params *p, particle *q,
                er_acc *acc, double dtc, double vstop2, int max_moves)
{
    const er_surf *f = &s->surf[q->c];
    double nx = q->x + q->vx * dtc, ny = q->y + q->vy * dtc, e;
    long ix, iy;
    if (q->k >= max_moves)
        return MV_STOP;
    if (f->ax == 0 && f->ay == 0 && q->hsp * q->hsp < vstop2)
        return MV_STOP; /* at rest where no neighbour is lower */
    q->k++;
    ix = nx > -0.5 ? (long)(nx + 0.5) : -1; /* nearest cell, no floor() */
    iy = ny > -0.5 ? (long)(ny + 0.5) : -1;
    if (ix < 0 || iy < 0 || ix >= s->w || iy >= s->h) {
        if (!p->closed_edges)
            return MV_DRAIN;
        ix = -1;
    } else if (s->surf[(size_t)iy * s->w + ix].wall) {
        ix = -1;
    }
    if (ix < 0) { /* against a wall: stop there, gravity acts again */
        q->vx = q->vy = q->vz = q->sp = q->hsp = 0;
    } else {
        double ux = q->vx + f->ax * p->dt, uy = q->vy + f->ay * p->dt,
               uz = q->vz + f->az * p->dt;
        q->x = nx, q->y = ny;
        q->c = (size_t)iy * s->w + ix;
        e = project(q, &s->surf[q->c], ux, uy, uz, p);
        if (e > 0)
            acc[q->c].e += (int64_t)(e * ER_FX);
    }
    acc[q->c].n++;
    acc[q->c].vx += (int64_t)(q->vx * ER_FX);
    acc[q->c].vy += (int64_t)(q->vy * ER_FX);
    acc[q->c].sp += (int64_t)(q->hsp * ER_FX);
    return MV_GO;
}

/* Start the particle of the next non-wall cell of [*next, end) in q;
 * 0 when the range is used up. */
static int launch(const er_state *s, particle *q, long *next, long end,
                  er_acc *acc)
{
    while (*next < end && s->wall[*next])
        (*next)++;
    if (*next >= end)
        return 0;
    memset(q, 0, sizeof *q);
    q->c = (size_t)*next;
    q->x = (double)(q->c % s->w);
    q->y = (double)(q->c / s->w);
    acc[q->c].n++;
    (*next)++;
    return 1;
}

/* Trace the particles of cells [lo, hi) ER_LANES at a time, one move of
 * each in turn: the moves of different particles do not depend on each
 * other, so the processor overlaps their long chains of roots, exp and
 * divisions.  Adds the moves and drained particles to *mv, *dr. */
#define ER_LANES 4
static void trace_range(const er_state *s, const td_erode_params *p,
                        long lo, long hi, int max_moves, er_acc *acc,
                        int64_t *mv, int64_t *dr)
{
    particle q[ER_LANES];
    int live[ER_LANES], l, nlive = 0;
    double dtc = p->dt / p->cell, vstop2 = p->v_stop * p->v_stop;
    long next = lo;
    for (l = 0; l < ER_LANES; l++)
        nlive += live[l] = launch(s, &q[l], &next, hi, acc);
    while (nlive > 0)
        for (l = 0; l < ER_LANES; l++) {
            int r;
            if (!live[l] || (r = move(s, p, &q[l], acc, dtc, vstop2,
                                      max_moves)) == MV_GO)
                continue;
            *mv += q[l].k;
            *dr += r == MV_DRAIN;
            if (!(live[l] = launch(s, &q[l], &next, hi, acc)))
                nlive--;
        }
}

/* Add every thread's accumulator into acc[0..n), over cells in parallel. */
static void reduce(er_state *s)
{
    long i, n = (long)s->n;
    int t;
    if (s->nthreads < 2)
        return;
#pragma omp parallel for num_threads(s->nthreads) schedule(static) private(t)
    for (i = 0; i < n; i++)
        for (t = 1; t < s->nthreads; t++) {
            const er_acc *b = &s->acc[(size_t)t * s->n + i];
            s->acc[i].n += b->n;
            s->acc[i].vx += b->vx;
            s->acc[i].vy += b->vy;
            s->acc[i].sp += b->sp;
            s->acc[i].e += b->e;
        }
}

void er_velocity_field(er_state *s, const td_erode_params *p, int64_t *moves,
                       int64_t *drained)
{
    int max_moves = p->max_moves > 0 ? p->max_moves : 2 * (s->w + s->h);
    int64_t mv = 0, dr = 0;
    long z, nz = (long)(s->n * (size_t)s->nthreads);
    /* all slots zeroed first: OpenMP may start fewer threads than asked */
#pragma omp parallel for num_threads(s->nthreads) schedule(static)
    for (z = 0; z < nz; z++)
        memset(&s->acc[z], 0, sizeof *s->acc);
#pragma omp parallel num_threads(s->nthreads) reduction(+ : mv, dr)
    {
        er_acc *acc = s->acc + (size_t)omp_get_thread_num() * s->n;
        long i, n = (long)s->n;
#pragma omp for schedule(dynamic, 1)
        for (i = 0; i < n; i += ER_CHUNK)
            trace_range(s, p, i, i + ER_CHUNK < n ? i + ER_CHUNK : n,
                        max_moves, acc, &mv, &dr);
    }
    reduce(s);
    *moves = mv;
    *drained = dr;
}
