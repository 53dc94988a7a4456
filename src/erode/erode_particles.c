/* erode_particles.c: STEP2-1 of velocity-field erosion, the water particles'
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
#include "src/erode/erode_int.h"

#include <math.h>
#include <omp.h>
#include <string.h>

#define ER_CHUNK 4096 /* cells per work item of a thread */

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

/* The particles in flight, ER_LANES at a time, as structure of arrays.  A
 * round moves every lane once:
 *
 *   lanes_aim    where each lane lands, whether it is done     (vectorised)
 *   lanes_fetch  the last move's sums into acc, the landing
 *                cell's surface record into the lanes          (per lane)
 *   lanes_enter  the next move started where nothing special
 *                happens (selects)                             (vectorised)
 *   lanes_step   walls, stops, drains; a stopped lane gets the
 *                next particle                                 (odd lanes)
 *   lanes_move   the physics of the move                       (vectorised)
 *
 * A thread's lanes are refilled from chunk after chunk of cells until the
 * step's particles are used up.  Lanes do not interact, and the sums are
 * integers, so neither the grouping nor the thread that traces a particle
 * changes a result. */
#define ER_LANES 32
#define ER_ALIGN _Alignas(64)
#if defined(__GNUC__)
#define TD_NOINLINE __attribute__((noinline)) /* its loop on its own */
#else
#define TD_NOINLINE
#endif

typedef struct lanes {
    ER_ALIGN double x[ER_LANES], y[ER_LANES]; /* position, cells */
    ER_ALIGN double vx[ER_LANES], vy[ER_LANES], vz[ER_LANES];
    ER_ALIGN double sp[ER_LANES];  /* |v|, the speed after the last move */
    ER_ALIGN double hsp[ER_LANES]; /* |horizontal part of v| */
    ER_ALIGN double cax[ER_LANES], cay[ER_LANES], caz[ER_LANES]; /* a of c */
    /* this move: where it lands, the acceleration of the cell left (0
     * unless moving), the gradient of the cell entered, the energy */
    ER_ALIGN double nx[ER_LANES], ny[ER_LANES];
    ER_ALIGN double ax[ER_LANES], ay[ER_LANES], az[ER_LANES];
    ER_ALIGN double gx[ER_LANES], gy[ER_LANES];
    /* the sums of the last move in fixed point (ER_FX) */
    ER_ALIGN int64_t svx[ER_LANES], svy[ER_LANES], ssp[ER_LANES], se[ER_LANES];
    ER_ALIGN int32_t c[ER_LANES]; /* cell the particle is in */
    ER_ALIGN int32_t to[ER_LANES]; /* cell it lands in, -1 off the grid */
    ER_ALIGN int32_t k[ER_LANES];  /* moves made */
    ER_ALIGN int32_t done[ER_LANES]; /* max_moves made, or at rest */
    ER_ALIGN int32_t mode[ER_LANES]; /* this move: LN_IDLE, LN_MOVE, LN_WALL */
    ER_ALIGN int32_t live[ER_LANES];
    ER_ALIGN int32_t odd[ER_LANES];  /* live, not moving on (lanes_enter) */
    /* the surface record of the cell landed in (of cell 0 when off the
     * grid), fetched lane by lane for the vectorised lanes_enter */
    ER_ALIGN float fax[ER_LANES], fay[ER_LANES], faz[ER_LANES];
    ER_ALIGN float fgx[ER_LANES], fgy[ER_LANES];
    ER_ALIGN int32_t fwall[ER_LANES];
} lanes;

enum { LN_IDLE = 0, LN_MOVE = 1, LN_WALL = 2 };

typedef struct tracer {
    const er_state *s;
    const td_erode_params *p;
    er_acc *acc;
    double dtc, vstop2, rest2;
    int max_moves;
    long next, end; /* the cells of the thread's current chunk */
    long *chunk;    /* shared by the threads: the next chunk's first cell */
    int64_t mv, dr;
} tracer;

/* Start the particle of the next non-wall cell in lane l, taking the next
 * chunk of ER_CHUNK cells (dynamically, over the threads) when the thread's
 * own is used up; 0 when every cell has its particle.  Lanes thus stay
 * busy up to the end of the step. */
static int launch(tracer *t, lanes *q, int l)
{
    const er_state *s = t->s;
    const er_surf *f;
    long i;
    for (;;) {
        while (t->next < t->end && s->wall[t->next])
            t->next++;
        if (t->next < t->end)
            break;
#pragma omp atomic capture
        {
            i = *t->chunk;
            *t->chunk += ER_CHUNK;
        }
        if (i >= (long)s->n)
            return q->live[l] = 0;
        t->next = i;
        t->end = i + ER_CHUNK < (long)s->n ? i + ER_CHUNK : (long)s->n;
    }
    i = t->next++;
    q->c[l] = (int32_t)i;
    q->x[l] = (double)(i % s->w);
    q->y[l] = (double)(i / s->w);
    q->vx[l] = q->vy[l] = q->vz[l] = q->sp[l] = q->hsp[l] = 0;
    f = &s->surf[i];
    q->cax[l] = f->ax, q->cay[l] = f->ay, q->caz[l] = f->az;
    q->k[l] = 0;
    t->acc[i].n++;
    return q->live[l] = 1;
}

/* Where every lane lands with x += v dt: its nearest cell `to` (-1 off the
 * grid: (int)(x + 0.5) is taken only inside it), and whether the particle
 * is done (max_moves made, or at rest where no neighbour is lower).  No
 * branches: it vectorises. */
TD_CLONES static TD_NOINLINE void lanes_aim(const tracer *t, lanes *q)
{
    const double dtc = t->dtc, vstop2 = t->vstop2, rest2 = t->rest2;
    const double w = t->s->w, h = t->s->h;
    const int32_t iw = t->s->w, maxm = t->max_moves;
    int l;
#pragma omp simd
    for (l = 0; l < ER_LANES; l++) {
        double nx = q->x[l] + q->vx[l] * dtc, ny = q->y[l] + q->vy[l] * dtc;
        double rx = nx + 0.5, ry = ny + 0.5; /* nearest cell, no floor() */
        int in = (nx > -0.5) & (ny > -0.5) & (rx < w) & (ry < h);
        int32_t ix = (int32_t)(in ? rx : 0.0), iy = (int32_t)(in ? ry : 0.0);
        q->nx[l] = nx, q->ny[l] = ny;
        q->to[l] = in ? iy * iw + ix : -1;
        q->done[l] = (q->k[l] >= maxm) |
                     ((q->cax[l] * q->cax[l] + q->cay[l] * q->cay[l] <=
                       rest2) &
                      (q->hsp[l] * q->hsp[l] < vstop2));
    }
}

/* Lane by lane: the sums of the last move (LN_MOVE or LN_WALL) into the
 * tracing thread's accumulator at the cell it landed in, and the surface
 * record of the cell the next move lands in copied into the lanes, plain
 * loads and stores (GCC gathers the 24-byte records for a vectorised loop
 * with one insert per value: slower). */
static void lanes_fetch(tracer *t, lanes *q)
{
    const er_surf *surf = t->s->surf;
    int l;
    for (l = 0; l < ER_LANES; l++) {
        const er_surf *f = &surf[q->to[l] > 0 ? q->to[l] : 0];
        if (q->mode[l] != LN_IDLE) {
            er_acc *a = &t->acc[q->c[l]];
            a->n++;
            a->vx += q->svx[l];
            a->vy += q->svy[l];
            a->sp += q->ssp[l];
            a->e += q->se[l];
        }
        q->fax[l] = f->ax, q->fay[l] = f->ay, q->faz[l] = f->az;
        q->fgx[l] = f->gx, q->fgy[l] = f->gy;
        q->fwall[l] = f->wall;
    }
}

/* Start the next move of every live lane that is not done and lands
 * inside the grid on a cell that is not a wall: LN_MOVE, the acceleration
 * of the cell left (a) and the gradient and acceleration of the cell
 * entered (fetched) taken over; every other lane gets a = 0 and LN_IDLE,
 * and the live ones among them are flagged odd for lanes_step.  No
 * branches: it vectorises. */
TD_CLONES static TD_NOINLINE void lanes_enter(const tracer *t, lanes *q)
{
    int l;
#pragma omp simd
    for (l = 0; l < ER_LANES; l++) {
        int32_t to = q->to[l], go = q->live[l] & !q->done[l];
        double gx = q->fgx[l], gy = q->fgy[l];
        double ax = q->fax[l], ay = q->fay[l], az = q->faz[l];
        int32_t mv = go & (to >= 0) & !q->fwall[l];
        q->k[l] += go;
        q->odd[l] = q->live[l] & !mv;
        q->mode[l] = mv ? LN_MOVE : LN_IDLE;
        q->ax[l] = mv ? q->cax[l] : 0.0;
        q->ay[l] = mv ? q->cay[l] : 0.0;
        q->az[l] = mv ? q->caz[l] : 0.0;
        q->x[l] = mv ? q->nx[l] : q->x[l];
        q->y[l] = mv ? q->ny[l] : q->y[l];
        q->c[l] = mv ? to : q->c[l];
        q->gx[l] = mv ? gx : q->gx[l];
        q->gy[l] = mv ? gy : q->gy[l];
        q->cax[l] = mv ? ax : q->cax[l];
        q->cay[l] = mv ? ay : q->cay[l];
        q->caz[l] = mv ? az : q->caz[l];
    }
}

/* One round's memory work: the sums of the last move, then the start of
 * the next (lanes_fetch, lanes_enter), then the odd lanes one by one:
 * LN_WALL (stopped against a wall or closed edge: v = 0 there, gravity
 * acts again), or the particle stopped (done) or drained and the lane gets
 * the next particle, which moves from the next round.  Returns the lanes
 * still live (0: no sums left pending either). */
static int lanes_step(tracer *t, lanes *q)
{
    int l, nlive = 0;
    lanes_fetch(t, q);
    lanes_enter(t, q);
    for (l = 0; l < ER_LANES; l++) {
        if (q->odd[l]) {
            if (!q->done[l] && (q->to[l] >= 0 || t->p->closed_edges)) {
                q->vx[l] = q->vy[l] = q->vz[l] = q->sp[l] = q->hsp[l] = 0;
                q->mode[l] = LN_WALL;
            } else {
                t->dr += !q->done[l]; /* over an open edge: drained */
                t->mv += q->k[l];
                launch(t, q, l);
            }
        }
        nlive += q->live[l];
    }
    return nlive;
}

/* The lanes of a move are taken ER_JAM vectors at a time (lanes l, l +
 * ER_SPAN, l + 2 ER_SPAN, ...), every step of the physics written for all
 * of them before the next step.  A lane's move is one long dependent chain
 * (roots, divisions, the Horner steps of exp); written one lane vector
 * after the other, the processor's scheduler fills with that chain and
 * waits out its latency, while with the chains interleaved it works on
 * ER_JAM of them at once.  Each lane's operations stay the same, in the
 * same order, so the results are the same bits. */
#define ER_JAM 4 /* the unroll count in EACH must be at least this */
#define ER_SPAN (ER_LANES / ER_JAM)
#if defined(__GNUC__)
#define EACH _Pragma("GCC unroll 4") for (j = 0; j < ER_JAM; j++)
#else
#define EACH for (j = 0; j < ER_JAM; j++)
#endif

/* Scratch of one move, lane l + j ER_SPAN at [j][l]: declared outside the
 * loop over l (arrays inside an omp simd loop are kept per lane in memory
 * and stop the vectoriser). */
typedef struct jam {
    double ux[ER_JAM][ER_SPAN], uy[ER_JAM][ER_SPAN], uz[ER_JAM][ER_SPAN];
    double sp[ER_JAM][ER_SPAN], ex[ER_JAM][ER_SPAN], hs[ER_JAM][ER_SPAN];
    double dx[ER_JAM][ER_SPAN], dy[ER_JAM][ER_SPAN], sl[ER_JAM][ER_SPAN];
    double inv[ER_JAM][ER_SPAN];
    double t[ER_JAM][ER_SPAN], r[ER_JAM][ER_SPAN], p[ER_JAM][ER_SPAN];
} jam;

/* exp(x) for the friction, in place on z->ex[j][l] for every j, on its
 * own so that a loop over lanes can vectorise it.  x = -beta w |u| <= 0
 * (beta, w > 0).  x = k ln 2 + r with |r| <= ln 2 / 2 (Cody-Waite,
 * two-part ln 2), exp(r) by its Taylor series to r^13 (error below 2e-16),
 * 2^k put into the exponent bits; below x = -40 the result is 0 instead
 * (exp(-40) = 4e-18 < 2^-54, so 1 - exp(x) is 1.0 in double either way),
 * selected after the polynomial so that no branch splits the lanes' chains.
 * At most 1 ulp from glibc's exp (6% of 20 M random arguments differ); the
 * same bits on every machine (plain IEEE operations, no fused multiply-add
 * in ISO C mode).  The ER_JAM arguments go through each step together. */
static inline void er_exp(jam *z, int l)
{
    static const double c[14] = {
        1.0 / 6227020800.0, 1.0 / 479001600.0, 1.0 / 39916800.0,
        1.0 / 3628800.0,    1.0 / 362880.0,    1.0 / 40320.0,
        1.0 / 5040.0,       1.0 / 720.0,       1.0 / 120.0,
        1.0 / 24.0,         1.0 / 6.0,         0.5,
        1.0,                1.0};
    const double ln2hi = 6.93147180369123816490e-01;
    const double ln2lo = 1.90821492927058770002e-10;
    const double rnd = 6755399441055744.0; /* 1.5 * 2^52 */
    int j, i;
    EACH {
        double x = z->ex[j][l], kd;
        z->t[j][l] = x * 1.44269504088896338700e+00 + rnd; /* k: low bits */
        kd = z->t[j][l] - rnd;                   /* k = round(x / ln 2) */
        z->r[j][l] = (x - kd * ln2hi) - kd * ln2lo;
        z->p[j][l] = c[0];
    }
#if defined(__GNUC__)
#pragma GCC unroll 13
#endif
    for (i = 1; i < 14; i++)
        EACH z->p[j][l] = c[i] + z->r[j][l] * z->p[j][l];
    EACH {
        int64_t bits;
        double t;
        memcpy(&bits, &z->t[j][l], sizeof bits); /* 0x4338... + k */
        bits = (int64_t)((uint64_t)(bits + 1023) << 52);
        memcpy(&t, &bits, sizeof t); /* 2^k, k in [-58, 0] if x >= -40 */
        z->ex[j][l] = z->ex[j][l] < -40.0 ? 0.0 : z->p[j][l] * t;
    }
}

/* One move's physics for every lane, for the acceleration a = (ax, ay,
 * az) of the cell left and the gradient (gx, gy) of the cell entered:
 * u = v + a dt, friction, tangent projection and collision; the energy
 * into e (0 if none).  |v'| = (u . t) for the unit tangent t, so the new
 * speeds need no root.  A lane where nothing horizontal is left (hs = 0)
 * rests (v = 0, e = 0); head-on into the surface (u . t <= 0) all speed
 * is lost.  Lanes not moving have a = v = 0 and so end at rest.
 *
 * Every value is computed, then selected with ?: on doubles: no branches
 * and no trapping operation under a condition, so the loop vectorises;
 * hs > 0 and dot > 0 as in the scalar form. */
TD_CLONES static TD_NOINLINE void lanes_move(const tracer *t, lanes *q)
{
    const double alpha = t->p->alpha, water = t->p->water, dt = t->p->dt;
    const double bw = -t->p->beta * t->p->water;
    const double one = 1.0, zero = 0.0;
    jam z;
    int l;
#pragma omp simd
    for (l = 0; l < ER_SPAN; l++) {
        int j;
        EACH {
            int m = l + j * ER_SPAN;
            double ux = q->vx[m] + q->ax[m] * dt;
            double uy = q->vy[m] + q->ay[m] * dt;
            double uz = q->vz[m] + q->az[m] * dt;
            double sp = sqrt(ux * ux + uy * uy + uz * uz);
            z.ux[j][l] = ux, z.uy[j][l] = uy, z.uz[j][l] = uz;
            z.sp[j][l] = sp;
            z.ex[j][l] = bw * sp;
        }
        er_exp(&z, l);
        EACH {
            double fr = alpha + (1 - alpha) * (1 - z.ex[j][l]);
            double f = z.sp[j][l] > 0 ? fr : 1.0;
            double ux = z.ux[j][l] * f, uy = z.uy[j][l] * f;
            z.ux[j][l] = ux, z.uy[j][l] = uy;
            z.uz[j][l] *= f, z.sp[j][l] *= f;
            z.hs[j][l] = sqrt(ux * ux + uy * uy);
        }
        EACH {
            int m = l + j * ER_SPAN;
            double hs = z.hs[j][l], ih = one / (hs > 0 ? hs : one);
            double dx = z.ux[j][l] * ih, dy = z.uy[j][l] * ih;
            double sl = q->gx[m] * dx + q->gy[m] * dy;
            z.dx[j][l] = dx, z.dy[j][l] = dy, z.sl[j][l] = sl;
            z.inv[j][l] = one / sqrt(one + sl * sl);
        }
        EACH {
            int m = l + j * ER_SPAN;
            double ux = z.ux[j][l], uy = z.uy[j][l], uz = z.uz[j][l];
            double sp = z.sp[j][l], dx = z.dx[j][l], dy = z.dy[j][l];
            double sl = z.sl[j][l], inv = z.inv[j][l];
            double dot, hsp, dv, e, vx, vy, vz;
            int go = z.hs[j][l] > 0;
            dot = (ux * dx + uy * dy + uz * sl) * inv;
            hsp = dot * inv;
            vx = hsp * dx, vy = hsp * dy, vz = dot * sl * inv;
            dv = sp - (dot > 0 ? dot : zero);
            e = 0.5 * water * dv * dv;
            e = sl * inv * sp > uz + 1e-9 * sp ? e : dot > 0 ? zero : e;
            e = q->sp[m] > 0 ? e : zero; /* v(t) = 0: no collision */
            e = go ? e : zero;
            q->sp[m] = go ? (dot > 0 ? dot : zero) : zero;
            q->hsp[m] = go ? (dot > 0 ? hsp : zero) : zero;
            q->vx[m] = go ? (dot > 0 ? vx : zero) : zero;
            q->vy[m] = go ? (dot > 0 ? vy : zero) : zero;
            q->vz[m] = go ? (dot > 0 ? vz : zero) : zero;
            q->svx[m] = (int64_t)(q->vx[m] * ER_FX);
            q->svy[m] = (int64_t)(q->vy[m] * ER_FX);
            q->ssp[m] = (int64_t)(q->hsp[m] * ER_FX);
            q->se[m] = e > 0 ? (int64_t)(e * ER_FX) : 0;
        }
    }
}

/* Trace particles ER_LANES at a time, one move of each lane per round,
 * from the chunks of cells taken through *chunk until every particle has
 * stopped or drained.  Adds the moves and drained particles to *mv, *dr. */
TD_CLONES static void trace(const er_state *s, const td_erode_params *p,
                  int max_moves, long *chunk, er_acc *acc, int64_t *mv,
                  int64_t *dr)
{
    static const lanes zero;
    lanes q = zero;
    tracer t;
    int l;
    t.s = s, t.p = p, t.acc = acc;
    t.dtc = p->dt / p->cell;
    t.vstop2 = p->v_stop * p->v_stop;
    t.rest2 = p->rest_accel * p->rest_accel; /* 0: a == 0 only */
    t.max_moves = max_moves;
    t.next = t.end = 0;
    t.chunk = chunk;
    t.mv = t.dr = 0;
    for (l = 0; l < ER_LANES; l++)
        launch(&t, &q, l);
    for (;;) { /* a round: one move of every lane */
        lanes_aim(&t, &q);
        if (lanes_step(&t, &q) == 0)
            break; /* no sums left pending either */
        lanes_move(&t, &q);
    }
    *mv += t.mv;
    *dr += t.dr;
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
    long z, nz = (long)(s->n * (size_t)s->nthreads), chunk = 0;
    /* all slots zeroed first: OpenMP may start fewer threads than asked */
#pragma omp parallel for num_threads(s->nthreads) schedule(static)
    for (z = 0; z < nz; z++)
        memset(&s->acc[z], 0, sizeof *s->acc);
#pragma omp parallel num_threads(s->nthreads) reduction(+ : mv, dr)
    trace(s, p, max_moves, &chunk,
          s->acc + (size_t)omp_get_thread_num() * s->n, &mv, &dr);
    reduce(s);
    *moves = mv;
    *drained = dr;
}
