/* erode.c: velocity-field hydraulic erosion, the driver and STEP2-2
 * (Fujita, Muraoka, Chiba §2 and §2.2; ALGORITHMS.md C1).
 *
 *   STEP0  arrays T (height), W (water), V (velocity), E (collision energy)
 *   STEP1  T := the initial terrain
 *   STEP2  repeat `steps` times:
 *     2-1  velocity field W, V, E from independent particles (erode_particles.c)
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
#include "src/erode/erode_int.h"

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
    p.rest_accel = 0;
    return p;
}

td_erode_params td_erode_rescale(const td_erode_params *p, double cell)
{
    td_erode_params q = *p;
    double s = cell / p->cell;
    q.cell = cell;
    q.dt = p->dt * s;
    q.water = p->water * s * s;
    q.alpha = 1.0 - (1.0 - p->alpha) * s;
    q.beta = p->beta / (s * s);
    q.c = p->c / s;
    q.kc = p->kc / s;
    q.ke = p->ke / (s * s);
    if (p->max_moves > 0)
        q.max_moves = (int)ceil(p->max_moves / s);
    return q;
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
    NEED(p->rest_accel >= 0 && isfinite(p->rest_accel),
         "rest_accel must be >= 0");
    NEED(p->route == TD_ERODE_ROUTE_DOWNHILL ||
         p->route == TD_ERODE_ROUTE_PAPER, "unknown sediment route");
    NEED(p->speed == TD_ERODE_SPEED_MEAN || p->speed == TD_ERODE_SPEED_VECTOR,
         "unknown flow speed");
    NEED(p->deposit == TD_ERODE_DEPOSIT_PAPER ||
         p->deposit == TD_ERODE_DEPOSIT_LEVEL, "unknown deposition rule");
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
    free(s->snd);
    free(s->fill);
    free(s->ord);
    free(s->par);
    free(s->heap);
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
        !(s->snd = td_calloc(n, sizeof(double), cx)) ||
        !(s->fill = td_calloc(n, sizeof(double), cx)) ||
        !(s->ord = td_calloc(n, sizeof(int32_t), cx)) ||
        !(s->par = td_calloc(n, sizeof(int32_t), cx)) ||
        !(s->heap = td_calloc(n, sizeof(int32_t), cx)) ||
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
 * 45 degrees).  TD_ERODE_ROUTE_DOWNHILL: sediment does not climb: when that
 * neighbour is not lower, the lowest steepest neighbour (the direction of
 * a) receives it, and with no lower neighbour the sediment settles; the
 * receiver graph then has no loops (heights fall along it).
 * TD_ERODE_ROUTE_PAPER: the neighbour V points at, whatever its height. */
static int32_t receiver(const er_state *s, const td_erode_params *p,
                        size_t i, double vx, double vy)
{
    const double t = 0.41421356237309503; /* tan 22.5 degrees */
    const er_surf *f = &s->surf[i];
    int ox = fabs(vx) > t * fabs(vy) ? (vx > 0 ? 1 : -1) : 0;
    int oy = fabs(vy) > t * fabs(vx) ? (vy > 0 ? 1 : -1) : 0;
    int32_t r = neighbour(s, p, i, ox, oy);
    if (p->route == TD_ERODE_ROUTE_PAPER || r == -2 ||
        (r >= 0 && s->T[r] < s->T[i]))
        return r;
    if (f->ax == 0 && f->ay == 0) /* a pit: with LEVEL, over the rim */
        return p->deposit == TD_ERODE_DEPOSIT_LEVEL ? r : -1;
    ox = f->ax > 0 ? 1 : f->ax < 0 ? -1 : 0;
    oy = f->ay > 0 ? 1 : f->ay < 0 ? -1 : 0;
    return neighbour(s, p, i, ox, oy);
}

/* Heap of cells keyed by (fill height, index): a strict order, so the
 * flood is the same on every run. */
static int flood_less(const er_state *s, int32_t a, int32_t b)
{
    return s->fill[a] < s->fill[b] || (s->fill[a] == s->fill[b] && a < b);
}

static void heap_push(er_state *s, size_t *nh, int32_t c)
{
    size_t k = (*nh)++;
    while (k > 0 && flood_less(s, c, s->heap[(k - 1) / 2])) {
        s->heap[k] = s->heap[(k - 1) / 2];
        k = (k - 1) / 2;
    }
    s->heap[k] = c;
}

static int32_t heap_pop(er_state *s, size_t *nh)
{
    int32_t top = s->heap[0], last = s->heap[--*nh];
    size_t k = 0, n = *nh;
    for (;;) {
        size_t c = 2 * k + 1;
        if (c >= n)
            break;
        if (c + 1 < n && flood_less(s, s->heap[c + 1], s->heap[c]))
            c++;
        if (!flood_less(s, s->heap[c], last))
            break;
        s->heap[k] = s->heap[c];
        k = c;
    }
    if (n > 0)
        s->heap[k] = last;
    return top;
}

/* Flood cells outward from the seeds already in the heap: every cell gets
 * its pop rank ord, the neighbour it was reached from (par) and the height
 * of the water that would stand on it (fill = max(T, fill of par)). */
static void flood_from(er_state *s, size_t *nh, int32_t *rank)
{
    while (*nh > 0) {
        int32_t c = heap_pop(s, nh);
        long cx = c % s->w, cy = c / s->w, dx, dy;
        s->ord[c] = (*rank)++;
        for (dy = -1; dy <= 1; dy++)
            for (dx = -1; dx <= 1; dx++) {
                long x = cx + dx, y = cy + dy;
                int32_t j;
                if (x < 0 || y < 0 || x >= s->w || y >= s->h)
                    continue;
                j = (int32_t)(y * s->w + x);
                if (s->wall[j] || s->par[j] != -3)
                    continue;
                s->par[j] = c;
                s->fill[j] = s->T[j] > s->fill[c] ? s->T[j] : s->fill[c];
                heap_push(s, nh, j);
            }
    }
}

/* Priority flood (depression filling): seeds are the border cells with
 * open edges (their sediment leaves the grid), then the lowest cell left
 * of every region not reached (a closed basin: its sediment settles).
 * Sediment routed along par falls in fill order and fills depressions up
 * to their spill level before it spills over the rim. */
static void flood(er_state *s, const td_erode_params *p)
{
    size_t i, nh = 0;
    int32_t rank = 0;
    for (i = 0; i < s->n; i++) {
        long x = (long)(i % s->w), y = (long)(i / s->w);
        s->par[i] = -3; /* not reached */
        if (s->wall[i] || p->closed_edges ||
            !(x == 0 || y == 0 || x == s->w - 1 || y == s->h - 1))
            continue;
        s->par[i] = -2;
        s->fill[i] = s->T[i];
        heap_push(s, &nh, (int32_t)i);
    }
    flood_from(s, &nh, &rank);
    for (;;) {
        int32_t lo = -1;
        for (i = 0; i < s->n; i++)
            if (!s->wall[i] && s->par[i] == -3 &&
                (lo < 0 || s->T[i] < s->T[lo]))
                lo = (int32_t)i;
        if (lo < 0)
            break;
        s->par[lo] = -1;
        s->fill[lo] = s->T[lo];
        heap_push(s, &nh, lo);
        flood_from(s, &nh, &rank);
    }
}

/* TD_ERODE_DEPOSIT_LEVEL: keep a receiver only when it comes earlier in
 * the flood order (so the receiver graph has no loops), else send the
 * sediment to the flood parent (out of a depression over its rim). */
static void level_receivers(er_state *s)
{
    size_t i;
    for (i = 0; i < s->n; i++) {
        int32_t r = s->recv[i];
        if (s->wall[i])
            continue;
        if (r == -1 || (r >= 0 && s->ord[r] > s->ord[i]))
            s->recv[i] = s->par[i];
    }
}

/* Height of cell c once this step's erosion and deposits are applied. */
static double new_height(const er_state *s, int32_t c)
{
    return s->T[c] - s->sq[c] - s->se[c] + s->dep[c];
}

/* TD_ERODE_DEPOSIT_LEVEL: what settles in the sink of a closed region (a
 * basin with no outlet) spreads as a level layer over the cells around
 * it, taken in flood order while their heights rise and stay below the
 * level (a lake filling up): volume kept exactly, no one-cell spike. */
static void lake(er_state *s, int32_t sink)
{
    double x = s->dep[sink], hsum = 0, top = -HUGE_VAL, level;
    int32_t k, k0 = s->ord[sink], m = 0;
    s->dep[sink] = 0;
    for (k = k0; k < (int32_t)s->n; k++) {
        int32_t c = s->heap[k];
        double h;
        if (c < 0 || (k > k0 && s->par[c] == -1))
            break; /* end of the flood, or of this region */
        h = new_height(s, c);
        if (m > 0 && (h < top || h >= (x + hsum) / m))
            break;
        top = h;
        hsum += h;
        m++;
    }
    level = (x + hsum) / m;
    for (k = k0; k < k0 + m; k++)
        s->dep[s->heap[k]] += level - new_height(s, s->heap[k]);
}

static void lakes(er_state *s, const td_erode_params *p)
{
    size_t i;
    if (p->deposit != TD_ERODE_DEPOSIT_LEVEL)
        return;
    for (i = 0; i < s->n; i++)
        s->heap[i] = -1;
    for (i = 0; i < s->n; i++)
        if (!s->wall[i])
            s->heap[s->ord[i]] = (int32_t)i; /* cells by flood rank */
    for (i = 0; i < s->n; i++)
        if (!s->wall[i] && s->par[i] == -1 && s->dep[i] > 0)
            lake(s, (int32_t)i);
}

/* How far cell i stands above its lowest neighbour (0 in a pit): with
 * TD_ERODE_DEPOSIT_LEVEL flow and collision never dig a cell below it. */
static double above_lowest(const er_state *s, size_t i)
{
    long x0 = (long)(i % s->w), y0 = (long)(i / s->w), dx, dy;
    double lo = s->T[i];
    for (dy = -1; dy <= 1; dy++)
        for (dx = -1; dx <= 1; dx++) {
            long x = x0 + dx, y = y0 + dy;
            size_t j = (size_t)y * s->w + x;
            if (x >= 0 && y >= 0 && x < s->w && y < s->h && !s->wall[j] &&
                s->T[j] < lo)
                lo = s->T[j];
        }
    return s->T[i] - lo;
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
        q = p->speed == TD_ERODE_SPEED_VECTOR
                ? p->c * p->water * (double)a->n * sqrt(vx * vx + vy * vy)
                : p->c * p->water * (double)a->sp / ER_FX;
        s->sq[i] = p->kq * q;
        s->se[i] = p->ke * ((double)a->e / ER_FX);
        s->smax[i] = q > 0 ? p->kc * pow(q, p->m) : 0.0;
        if (p->deposit == TD_ERODE_DEPOSIT_LEVEL &&
            s->sq[i] + s->se[i] > 0) {
            double room = above_lowest(s, i), e = s->sq[i] + s->se[i];
            if (e > room) {
                s->sq[i] *= room / e;
                s->se[i] *= room / e;
            }
        }
        s->recv[i] = receiver(s, p, i, vx, vy);
    }
}

/* Settle or pass on the sediment of cell i (S_I = Sq + Se + inflow).
 * TD_ERODE_DEPOSIT_LEVEL: a cell that receives sediment rises at most
 * half-way to the lowest cell that sent it some; the excess passes on. */
static void settle(er_state *s, const td_erode_params *p, size_t i,
                   int pass_on, td_erode_step_stats *st)
{
    double si = s->sq[i] + s->se[i] + s->sin[i], pass, dep;
    double low = s->T[i] - s->sq[i] - s->se[i]; /* height once eroded */
    int32_t r = s->recv[i];
    st->eroded_flow += s->sq[i];
    st->eroded_coll += s->se[i];
    pass = si > s->smax[i] ? s->smax[i] : si;
    dep = si - pass;
    if (!pass_on || r == -1) {
        dep = si;
        pass = 0;
    } else if (p->deposit == TD_ERODE_DEPOSIT_LEVEL && dep > 0) {
        double room = 0.5 * (s->snd[i] - low);
        room = room > s->fill[i] - low ? room : s->fill[i] - low;
        room = room > 0 ? room : 0;
        if (dep > room) {
            pass += dep - room;
            dep = room;
        }
    }
    if (pass_on && r == -2) {
        st->outflow += pass;
    } else if (pass_on && r >= 0) {
        s->sin[r] += pass;
        if (low + dep < s->snd[r])
            s->snd[r] = low + dep;
    }
    s->dep[i] = dep;
    st->deposited += dep;
}

/* Pass the sediment on, upstream cells first (Kahn's order over the
 * receiver graph, ties in index order); cells on receiver loops keep all. */
static void transport(er_state *s, const td_erode_params *p,
                      td_erode_step_stats *st)
{
    size_t i, head = 0, tail = 0;
    memset(s->indeg, 0, s->n * sizeof *s->indeg);
    for (i = 0; i < s->n; i++) {
        s->sin[i] = 0;
        s->snd[i] = HUGE_VAL;
        if (s->recv[i] >= 0)
            s->indeg[s->recv[i]]++;
    }
    for (i = 0; i < s->n; i++)
        if (!s->wall[i] && s->indeg[i] == 0)
            s->queue[tail++] = (int32_t)i;
    while (head < tail) {
        size_t c = (size_t)s->queue[head++];
        int32_t r = s->recv[c];
        settle(s, p, c, 1, st);
        if (r >= 0 && --s->indeg[r] == 0)
            s->queue[tail++] = r;
    }
    for (i = 0; i < s->n; i++)
        if (!s->wall[i] && s->indeg[i] > 0) {
            s->indeg[i] = 0;
            settle(s, p, i, 0, st);
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
    if (p->deposit == TD_ERODE_DEPOSIT_LEVEL) {
        flood(s, p);
        level_receivers(s);
    }
    transport(s, p, ss);
    lakes(s, p);
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
