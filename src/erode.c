/* erode.c: velocity-field hydraulic erosion, the driver and STEP2-2
 * (Fujita, Muraoka, Chiba §2 and §2.2; ALGORITHMS.md C1).
 *
 *   STEP0  arrays T (height), W (water), V (velocity), E (collision energy)
 *   STEP1  T := the initial terrain
 *   STEP2  repeat `steps` times:
 *     2-1  velocity field W, V, E from independent particles (erode_flow.c)
 *     2-2  erosion, transport, deposition on every cell:
 *            Q = C w v,  Sq = Kq Q,  Se = Ke e       (T lowered by Sq + Se)
 *            Smax = Kc Q^m
 *            S_I = Sq + Se + sum of S_0 from upstream neighbours
 *            S_I > Smax: deposit S_I - Smax, pass Smax on along V
 *            else:       pass S_I on along V
 *
 *   "along V": to the 8-neighbour the cell's mean velocity points at
 *       (sectors of 45 degrees):       \ | /
 *                                     -- c --> V
 *                                      / | \
 *
 * The sediment is passed on within the step, upstream cells first (a
 * topological order of the receiver graph); sediment that would go round a
 * loop of receivers, against a wall or into a cell with no flow settles
 * where it is.  Over an open edge it leaves the grid (outflow).  Every
 * transfer is booked, so eroded = deposited + outflow to rounding. */
#include "erode_int.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

td_erode_params td_erode_defaults(void)
{
    td_erode_params p;
    memset(&p, 0, sizeof p);
    p.steps = 75;
    p.kq = 2e-3;
    p.ke = 0.02;
    p.kc = 0.05;
    p.m = 1.0;
    p.alpha = 0.5;
    p.beta = 0.1;
    p.gravity = 1.0;
    p.dt = 1.0;
    p.water = 1.0;
    p.c = 1.0;
    p.cell = 1.0;
    p.v_stop = 1e-3;
    return p;
}

int td_erode_check(const td_erode_params *p, td_ctx *cx)
{
#define NEED(cond, what)                                                     \
    if (!(cond))                                                             \
        return td_seterr(cx, TD_EINVAL, "erode: %s", what)
    NEED(p->steps >= 0, "steps must be >= 0");
    NEED(p->kq >= 0 && isfinite(p->kq), "Kq must be >= 0");
    NEED(p->ke >= 0 && isfinite(p->ke), "Ke must be >= 0");
    NEED(p->kc >= 0 && isfinite(p->kc), "Kc must be >= 0");
    NEED(p->m > 0 && p->m <= 10, "m must be in (0, 10]");
    NEED(p->alpha >= 0 && p->alpha <= 1, "alpha must be in [0, 1]");
    NEED(p->beta > 0 && isfinite(p->beta), "beta must be > 0");
    NEED(p->gravity > 0 && isfinite(p->gravity), "gravity must be > 0");
    NEED(p->dt > 0 && isfinite(p->dt), "dt must be > 0");
    NEED(p->water > 0 && isfinite(p->water), "water per cell must be > 0");
    NEED(p->c > 0 && isfinite(p->c), "C must be > 0");
    NEED(p->cell > 0 && isfinite(p->cell), "cell size must be > 0");
    NEED(p->max_moves >= 0, "max moves must be >= 0");
    NEED(p->v_stop >= 0 && isfinite(p->v_stop), "v_stop must be >= 0");
    NEED(p->threads >= 0 && p->threads <= 1024, "threads must be 0..1024");
    NEED(p->snapshot_every >= 0, "snapshot interval must be >= 0");
#undef NEED
    return 0;
}

static void state_free(er_state *s)
{
    free(s->T);
    free(s->wall);
    free(s->surf);
    free(s->acc);
    free(s->sq);
    free(s->se);
    free(s->smax);
    free(s->sin);
    free(s->dep);
    free(s->dep_total);
    free(s->recv);
    free(s->indeg);
    free(s->queue);
    memset(s, 0, sizeof *s);
}

static int state_alloc(er_state *s, const td_grid_f32 *in, int nthreads,
                       td_ctx *cx)
{
    size_t n = (size_t)in->w * in->h, y, x;
    memset(s, 0, sizeof *s);
    s->w = in->w, s->h = in->h, s->n = n, s->nthreads = nthreads;
    if (n > (size_t)INT32_MAX / 2)
        return td_seterr(cx, TD_ETOOBIG, "erode: %d x %d cells is too many",
                         in->w, in->h);
    if (!(s->T = td_malloc(n * sizeof *s->T, cx)) ||
        !(s->wall = td_calloc(n, 1, cx)) ||
        !(s->surf = td_malloc(n * sizeof *s->surf, cx)) ||
        !(s->acc = td_calloc(n * (size_t)nthreads, sizeof *s->acc, cx)) ||
        !(s->sq = td_calloc(n, sizeof(double), cx)) ||
        !(s->se = td_calloc(n, sizeof(double), cx)) ||
        !(s->smax = td_calloc(n, sizeof(double), cx)) ||
        !(s->sin = td_calloc(n, sizeof(double), cx)) ||
        !(s->dep = td_calloc(n, sizeof(double), cx)) ||
        !(s->dep_total = td_calloc(n, sizeof(double), cx)) ||
        !(s->recv = td_calloc(n, sizeof(int32_t), cx)) ||
        !(s->indeg = td_calloc(n, sizeof(int32_t), cx)) ||
        !(s->queue = td_calloc(n, sizeof(int32_t), cx)))
        return TD_ENOMEM;
    for (y = 0; y < (size_t)s->h; y++)
        for (x = 0; x < (size_t)s->w; x++) {
            float v = in->data[y * in->stride + x];
            int nd = !isfinite(v) || (in->has_nodata && v == in->nodata);
            s->wall[y * s->w + x] = (uint8_t)nd;
            s->T[y * s->w + x] = nd ? 0.0 : v;
        }
    return 0;
}

/* Neighbour (ox, oy) of cell i: its index, -2 off an open edge, -1 none. */
static int32_t neighbour(const er_state *s, const td_erode_params *p,
                         size_t i, int ox, int oy)
{
    long x = (long)(i % s->w) + ox, y = (long)(i / s->w) + oy;
    if (!ox && !oy)
        return -1;
    if (x < 0 || y < 0 || x >= s->w || y >= s->h)
        return p->closed_edges ? -1 : -2;
    if (s->wall[(size_t)y * s->w + x])
        return -1;
    return (int32_t)((size_t)y * s->w + x);
}

/* The receiver of a cell's sediment: the neighbour V points at (sectors of
 * 45 degrees).  Sediment does not climb: when that neighbour is not lower,
 * the lowest steepest neighbour (the direction of a) receives it, and with
 * no lower neighbour the sediment settles. */
static int32_t receiver(const er_state *s, const td_erode_params *p,
                        size_t i, double vx, double vy)
{
    const double t = 0.41421356237309503; /* tan 22.5 degrees */
    const er_surf *f = &s->surf[i];
    int ox = fabs(vx) > t * fabs(vy) ? (vx > 0 ? 1 : -1) : 0;
    int oy = fabs(vy) > t * fabs(vx) ? (vy > 0 ? 1 : -1) : 0;
    int32_t r = neighbour(s, p, i, ox, oy);
    if (r == -2 || (r >= 0 && s->T[r] < s->T[i]))
        return r;
    ox = f->ax > 0 ? 1 : f->ax < 0 ? -1 : 0;
    oy = f->ay > 0 ? 1 : f->ay < 0 ? -1 : 0;
    return neighbour(s, p, i, ox, oy);
}

/* Q, Sq, Se, Smax and the receiver of every cell from the gathered sums. */
static void cell_rates(er_state *s, const td_erode_params *p)
{
    long i, n = (long)s->n;
#pragma omp parallel for num_threads(s->nthreads) schedule(static)
    for (i = 0; i < n; i++) {
        const er_acc *a = &s->acc[i];
        double vx, vy, q;
        s->sq[i] = s->se[i] = s->smax[i] = 0;
        s->recv[i] = -1;
        if (s->wall[i] || a->n == 0)
            continue;
        vx = (double)a->vx / ER_FX / (double)a->n;
        vy = (double)a->vy / ER_FX / (double)a->n;
        /* v_ij: the mean speed of the visiting particles (their mean
         * vector gives only the direction: particles swinging across a
         * valley floor would cancel) */
        q = p->c * p->water * (double)a->sp / ER_FX;
        s->sq[i] = p->kq * q;
        s->se[i] = p->ke * ((double)a->e / ER_FX);
        s->smax[i] = q > 0 ? p->kc * pow(q, p->m) : 0.0;
        s->recv[i] = receiver(s, p, i, vx, vy);
    }
}

/* Settle or pass on the sediment of cell i (S_I = Sq + Se + inflow). */
static void settle(er_state *s, size_t i, int pass_on, td_erode_step_stats *st)
{
    double si = s->sq[i] + s->se[i] + s->sin[i], pass, dep;
    int32_t r = s->recv[i];
    st->eroded_flow += s->sq[i];
    st->eroded_coll += s->se[i];
    pass = si > s->smax[i] ? s->smax[i] : si;
    dep = si - pass;
    if (!pass_on || r == -1) {
        dep = si;
        pass = 0;
    } else if (r == -2) {
        st->outflow += pass;
    } else {
        s->sin[r] += pass;
    }
    s->dep[i] = dep;
    st->deposited += dep;
}

/* Pass the sediment on, upstream cells first (Kahn's order over the
 * receiver graph, ties in index order); cells on receiver loops keep all. */
static void transport(er_state *s, td_erode_step_stats *st)
{
    size_t i, head = 0, tail = 0;
    memset(s->indeg, 0, s->n * sizeof *s->indeg);
    for (i = 0; i < s->n; i++) {
        s->sin[i] = 0;
        if (s->recv[i] >= 0)
            s->indeg[s->recv[i]]++;
    }
    for (i = 0; i < s->n; i++)
        if (!s->wall[i] && s->indeg[i] == 0)
            s->queue[tail++] = (int32_t)i;
    while (head < tail) {
        size_t c = (size_t)s->queue[head++];
        int32_t r = s->recv[c];
        settle(s, c, 1, st);
        if (r >= 0 && --s->indeg[r] == 0)
            s->queue[tail++] = r;
    }
    for (i = 0; i < s->n; i++)
        if (!s->wall[i] && s->indeg[i] > 0) {
            s->indeg[i] = 0;
            settle(s, i, 0, st);
        }
}

/* T := T - Sq - Se + deposit; the step's volumes in height * area. */
static void apply(er_state *s, const td_erode_params *p,
                  td_erode_step_stats *st)
{
    long i, n = (long)s->n;
    double area = p->cell * p->cell;
#pragma omp parallel for num_threads(s->nthreads) schedule(static)
    for (i = 0; i < n; i++) {
        if (s->wall[i])
            continue;
        s->T[i] += s->dep[i] - s->sq[i] - s->se[i];
        s->dep_total[i] += s->dep[i];
    }
    st->eroded_flow *= area;
    st->eroded_coll *= area;
    st->eroded = st->eroded_flow + st->eroded_coll;
    st->deposited *= area;
    st->outflow *= area;
}

/* Copy a double field (or visits * water) into a float grid, nodata kept. */
static void export_field(const er_state *s, const td_grid_f32 *in,
                         const double *v, double per_visit, td_grid_f32 *g)
{
    size_t x, y;
    if (!g)
        return;
    g->nodata = in->nodata;
    g->has_nodata = in->has_nodata;
    for (y = 0; y < (size_t)s->h; y++)
        for (x = 0; x < (size_t)s->w; x++) {
            size_t i = y * s->w + x;
            double val = v ? v[i] : per_visit < 0
                                        ? (double)s->acc[i].e / ER_FX
                                        : per_visit * (double)s->acc[i].n;
            g->data[y * g->stride + x] =
                s->wall[i] ? (in->has_nodata ? in->nodata : NAN) : (float)val;
        }
}

static void accumulate(td_erode_stats *st, const td_erode_step_stats *ss)
{
    td_erode_step_stats *t = &st->total;
    double r = ss->eroded > 0
                   ? fabs(ss->eroded - ss->deposited - ss->outflow) / ss->eroded
                   : 0.0;
    t->step = ss->step;
    t->eroded += ss->eroded;
    t->eroded_flow += ss->eroded_flow;
    t->eroded_coll += ss->eroded_coll;
    t->deposited += ss->deposited;
    t->outflow += ss->outflow;
    t->moves += ss->moves;
    t->particles += ss->particles;
    t->drained += ss->drained;
    if (r > st->max_residual)
        st->max_residual = r;
}

/* One STEP2: velocity field, rates, transport, update. */
static void one_step(er_state *s, const td_erode_params *p,
                     td_erode_step_stats *ss)
{
    int64_t moves = 0, drained = 0;
    size_t i, np = 0;
    er_surface(s, p);
    er_velocity_field(s, p, &moves, &drained);
    cell_rates(s, p);
    transport(s, ss);
    apply(s, p, ss);
    for (i = 0; i < s->n; i++)
        np += !s->wall[i];
    ss->moves = (double)moves;
    ss->drained = (double)drained;
    ss->particles = (double)np;
}

/* The current terrain into `out` (float), nodata kept. */
static void export_dem(const er_state *s, const td_grid_f32 *in,
                       td_grid_f32 *out)
{
    export_field(s, in, s->T, 0, out);
}

static int check_grid(const td_grid_f32 *in, const td_grid_f32 *g,
                      const char *what, td_ctx *cx)
{
    if (g && (g->w != in->w || g->h != in->h || !g->data ||
              g->stride < (size_t)g->w))
        return td_seterr(cx, TD_EINVAL, "erode: %s grid is %d x %d, the DEM "
                         "%d x %d", what, g->w, g->h, in->w, in->h);
    if (g && g->data == in->data)
        return td_seterr(cx, TD_EINVAL, "erode: %s may not alias the input",
                         what);
    return 0;
}

static int check_args(const td_grid_f32 *in, const td_erode_params *p,
                      td_grid_f32 *out, const td_erode_fields *f, td_ctx *cx)
{
    int rc;
    if (!in || !in->data || !p || !out)
        return td_seterr(cx, TD_EINVAL, "erode: missing input or output");
    if ((rc = td_check_dims(in->w, in->h, "erode: DEM", cx)) != 0 ||
        (rc = td_erode_check(p, cx)) != 0 ||
        (rc = check_grid(in, out, "output", cx)) != 0)
        return rc;
    if (f && ((rc = check_grid(in, f->water, "water", cx)) != 0 ||
              (rc = check_grid(in, f->energy, "energy", cx)) != 0 ||
              (rc = check_grid(in, f->sediment, "sediment", cx)) != 0))
        return rc;
    return 0;
}

int td_erode_run(const td_grid_f32 *in, const td_erode_params *p,
                 td_grid_f32 *out, td_erode_fields *fields,
                 td_erode_stats *st, td_ctx *cx)
{
    er_state s;
    td_erode_stats tot;
    int rc, k, nt;
    memset(&s, 0, sizeof s);
    memset(&tot, 0, sizeof tot);
    if ((rc = check_args(in, p, out, fields, cx)) != 0)
        return rc;
    nt = p->threads > 0 ? p->threads : omp_get_max_threads();
    if ((rc = state_alloc(&s, in, nt < 1 ? 1 : nt, cx)) != 0)
        goto fail;
    for (k = 1; k <= p->steps; k++) {
        td_erode_step_stats ss;
        int snap = p->snapshot_every > 0 && k % p->snapshot_every == 0;
        memset(&ss, 0, sizeof ss);
        ss.step = k;
        one_step(&s, p, &ss);
        accumulate(&tot, &ss);
        if (snap)
            export_dem(&s, in, out);
        if (p->on_step && p->on_step(&ss, snap ? out : NULL, p->user) != 0) {
            rc = td_seterr(cx, TD_ECANCEL, "erode: stopped at step %d", k);
            goto fail;
        }
        if ((rc = td_progress(cx, "erode", (double)k / p->steps)) != 0)
            goto fail;
    }
    export_dem(&s, in, out);
    if (fields) {
        export_field(&s, in, NULL, p->water, fields->water);
        export_field(&s, in, NULL, -1, fields->energy);
        export_field(&s, in, s.dep_total, 0, fields->sediment);
    }
    tot.residual = tot.total.eroded > 0
                       ? fabs(tot.total.eroded - tot.total.deposited -
                              tot.total.outflow) / tot.total.eroded
                       : 0.0;
    tot.path_mean = tot.total.particles > 0
                        ? tot.total.moves / tot.total.particles : 0.0;
    if (st)
        *st = tot;
fail:
    state_free(&s);
    return rc;
}
