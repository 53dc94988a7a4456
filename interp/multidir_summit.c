/* multidir_summit.c: phase 2 of the multidir method (the summit phase) in
 * one pass down the rows.
 *
 * Phase 2 fills the cells phase 1 left undetermined: along each of the
 * four directions a run of them between two determined cells A and B
 * (n steps apart) gets a linear estimate when A and B differ, else the
 * paper's tent (§2.5 Fig. 6) with the slopes at A and B read outwards on
 * the phase-1 grid; a cell blends its directions' estimates, x, y,
 * diagonal, anti-diagonal in that order.  Walking each direction over
 * the runs (until 2026-12-05) added them into an 8-byte sum per
 * undetermined cell, down columns for three of the four directions:
 * scattered writes into hundreds of MB (288 MB on the 10000^2 benchmark
 * sheet).  Here the rows are swept top to bottom with one row of sums:
 *
 *     bottom-up pass: for every run of undetermined cells along y, diag,
 *       anti that starts below a determined cell, its steps n to the
 *       determined cell after it (0: it leaves the grid), in the order
 *       the sweep meets the run starts;
 *     top-down sweep: per line the open run (A, n, the step k, its
 *       linear step or tent slopes); per row the x runs, then each
 *       crossing direction, into the row's sums; the blend.
 *
 * Two threads: the bottom-up pass per direction, and in the sweep x and
 * y on one thread, the diagonals on the other, each direction into its
 * own rows of sums, added per cell in the walk's order; the diagonals'
 * thread runs up to SM_RING rows ahead of the blend instead of meeting
 * the other at two barriers a row (the sweep of the 10000^2 benchmark
 * 0.43-0.55 -> 0.39-0.47 s on two threads, each busy for 0.44 s of it;
 * 0.84 s on one thread; the same bytes).
 *
 * The slopes at A read up to slope_cells rows above the row being swept,
 * so the blended rows go into g slope_cells + 2 rows behind (a ring of
 * rows): every read sees the phase-1 grid.  The float operations are the
 * walk's (multidir.c's linear_span and add, rasterise.c's tent), in the
 * same order per cell: the same bytes. */
#include "interp/multidir_int.h"

#include "interp/interp_int.h"
#include "interp/rasterise.h"

#include <math.h>
#include <omp.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

enum { SV = 3 }; /* the directions crossing rows: y, diag, anti */

/* Rows of sums in flight: the diagonals' thread may run this many rows
 * ahead of the blend. */
enum { SM_RING = 64 };

static const int sm_dc[SV] = {0, 1, -1};

/* The open run of one scan line. */
typedef struct sm_line {
    int k, n;       /* steps from A so far; the run's steps (0: none) */
    int ca, ra;     /* A */
    float z, dz, w; /* linear: the running estimate, its step, weight */
    float za;
    double s1, s2; /* tent: the slopes at A and B */
    int tent;
} sm_line;

typedef struct sm_state {
    td_grid_f32 *g;
    const td_multidir_params *p;
    const td_nan_runs *nr;
    size_t nl;      /* lines per crossing direction (w + h - 1) */
    int nv;         /* crossing directions: 1 (y; ndir 2) or 3 */
    int *ends;      /* bottom-up: per line, the row of the determined cell
                       after the run (-1: the run leaves the grid) */
    int *steps[SV]; /* per direction, the run starts' n in the sweep's
                       order */
    size_t nsteps[SV], cap[SV];
    size_t *row_at[SV]; /* per direction and row: its first entry */
} sm_state;

/* A row's sums: of x and y (the first thread), of diag, of anti (the
 * second), added in that order per cell as the walk added them. */
typedef struct sm_sums {
    float *bz, *bw;
} sm_sums;

/* Scan line of cell (c, r) in crossing direction j (as multidir_sweep.c
 * and the walk index them: y col, diag col - row + h - 1, anti col +
 * row). */
static size_t line_of(const td_grid_f32 *g, int j, int c, int r)
{
    return j == 0   ? (size_t)c
           : j == 1 ? (size_t)(c - r + g->h - 1)
                    : (size_t)(c + r);
}

static int is_set(const td_grid_f32 *g, int c, int r)
{
    float v = TD_AT(g, c, r);
    return v == v;
}

/* Whether the undetermined cell (c, r) starts a run along j: the cell
 * before it on the line is in the grid and determined. */
static int starts(const td_grid_f32 *g, int j, int c, int r)
{
    int pc = c - sm_dc[j];
    return r > 0 && pc >= 0 && pc < g->w && is_set(g, pc, r - 1);
}

static int push_step(sm_state *s, int j, int n)
{
    if (s->nsteps[j] == s->cap[j]) {
        size_t cap = s->cap[j] + s->cap[j] / 2 + 4096;
        int *v = cap < SIZE_MAX / sizeof *v
                     ? realloc(s->steps[j], cap * sizeof *v)
                     : NULL;
        if (!v)
            return TD_ENOMEM;
        s->steps[j] = v;
        s->cap[j] = cap;
    }
    s->steps[j][s->nsteps[j]++] = n;
    return 0;
}

/* Bottom-up along crossing direction j: the runs' lengths.  Row r's run
 * starts (its cells left to right) are stored in that order from
 * row_at[j][r]; rows are stored bottom first, so row_at runs backwards.
 * 0 or TD_ENOMEM. */
static int lookahead(sm_state *s, int j)
{
    const td_grid_f32 *g = s->g;
    const td_nan_runs *nr = s->nr;
    int r, c, *end = s->ends + (size_t)j * s->nl;
    size_t i, l;
    for (l = 0; l < s->nl; l++)
        end[l] = -1;
    for (r = g->h - 1; r >= 0; r--) {
        s->row_at[j][r] = s->nsteps[j];
        for (i = nr->off[r]; i < nr->off[r + 1]; i++)
            for (c = nr->run[i][0]; c < nr->run[i][1]; c++) {
                int nc = c + sm_dc[j];
                l = line_of(g, j, c, r);
                if (r + 1 >= g->h || nc < 0 || nc >= g->w)
                    end[l] = -1;
                else if (is_set(g, nc, r + 1))
                    end[l] = r + 1;
                /* else: the run goes on below, end[l] as it is */
                if (starts(g, j, c, r) &&
                    push_step(s, j, end[l] >= 0 ? end[l] - (r - 1) : 0) != 0)
                    return TD_ENOMEM;
            }
    }
    return 0;
}

/* One cell's estimate z, k steps into a span of n, with its own weight
 * (multidir.c's add()). */
static void add_est(const sm_state *s, sm_sums *b, int c, double z, int k,
                    int n, double sl)
{
    double w = td_multidir_cell_weight(s->p->weight, k * sl, (n - k) * sl);
    b->bz[c] += (float)(w * z);
    b->bw[c] += (float)w;
}

/* Slopes at the two ends of span sp (summit_span's rule). */
static void slopes(const sm_state *s, const td_span *sp, double *s1, double *s2)
{
    *s1 = *s2 = 0;
    if (s->p->summit &&
        (td_interp_slope(s->g, sp, 0, s->p->slope_cells, s1) != 0 ||
         td_interp_slope(s->g, sp, 1, s->p->slope_cells, s2) != 0))
        *s1 = *s2 = 0;
}

/* The x runs of row r into bz, bw (summit_span on each). */
static void row_x(const sm_state *s, sm_sums *b, int r)
{
    const td_grid_f32 *g = s->g;
    const float *row = g->data + (size_t)r * g->stride;
    size_t i;
    for (i = s->nr->off[r]; i < s->nr->off[r + 1]; i++) {
        int c0 = s->nr->run[i][0], c1 = s->nr->run[i][1], n, k, a;
        float za, zb;
        if (c0 < 1 || c1 >= g->w)
            continue;
        n = c1 - c0 + 1, a = c0 - 1;
        za = row[a], zb = row[c1];
        if (za != zb && s->p->weight == TD_MULTIDIR_PROD) {
            float dz = (zb - za) / (float)n;
            for (k = 1; k < n; k++)
                add_est(s, b, a + k, za + dz * k, k, n, 1.0);
        } else if (za != zb) {
            float dz = (zb - za) / (float)n, z = za,
                  w = td_multidir_span_weight(s->p->weight, n, 1.0);
            for (k = 1; k < n; k++) {
                z += dz;
                b->bz[a + k] += w * z;
                b->bw[a + k] += w;
            }
        } else {
            td_span sp;
            double s1, s2;
            memset(&sp, 0, sizeof sp);
            sp.ca = a, sp.ra = r, sp.dc = 1, sp.dr = 0, sp.n = n;
            sp.sl = 1.0, sp.za = za, sp.zb = zb;
            slopes(s, &sp, &s1, &s2);
            for (k = 1; k < n; k++)
                add_est(s, b, a + k,
                        td_interp_tent(za, s1, s2, k, n - k, s->p->interval), k,
                        n, 1.0);
        }
    }
}

/* Open line l's run at the undetermined cell (c, r) along j, n steps from
 * A (the cell before it) to B; n 0: none. */
static void open_run(const sm_state *s, sm_line *L, int j, int c, int r, int n)
{
    const td_grid_f32 *g = s->g;
    double sl = j ? sqrt(2.0) : 1.0;
    L->n = n, L->k = 0;
    if (n < 2)
        return;
    L->ca = c - sm_dc[j], L->ra = r - 1;
    L->za = TD_AT(g, L->ca, L->ra);
    {
        float zb = TD_AT(g, L->ca + n * sm_dc[j], L->ra + n);
        L->tent = L->za == zb;
        if (!L->tent) {
            L->dz = (zb - L->za) / (float)n;
            L->z = L->za;
            L->w = td_multidir_span_weight(s->p->weight, n, sl);
        } else {
            td_span sp;
            memset(&sp, 0, sizeof sp);
            sp.ca = L->ca, sp.ra = L->ra, sp.dc = sm_dc[j], sp.dr = 1;
            sp.n = n, sp.sl = sl, sp.za = L->za, sp.zb = zb;
            slopes(s, &sp, &L->s1, &L->s2);
        }
    }
}

/* Row r along crossing direction j into b: each line's run steps one
 * cell down; runs start below their A. */
static void row_cross(const sm_state *s, sm_line *lj, int j, sm_sums *b, int r)
{
    const td_grid_f32 *g = s->g;
    double sl = j ? sqrt(2.0) : 1.0;
    size_t i, at = s->row_at[j][r];
    int c;
    for (i = s->nr->off[r]; i < s->nr->off[r + 1]; i++)
        for (c = s->nr->run[i][0]; c < s->nr->run[i][1]; c++) {
            sm_line *L = lj + line_of(g, j, c, r);
            int k;
            if (starts(g, j, c, r))
                open_run(s, L, j, c, r, s->steps[j][at++]);
            else if (r == 0 || c - sm_dc[j] < 0 || c - sm_dc[j] >= g->w)
                L->n = 0; /* begins at the grid's edge: no run */
            if (L->n < 2)
                continue;
            k = ++L->k;
            if (!L->tent && s->p->weight == TD_MULTIDIR_PROD)
                add_est(s, b, c, L->za + L->dz * k, k, L->n, sl);
            else if (!L->tent) {
                L->z += L->dz;
                b->bz[c] += L->w * L->z;
                b->bw[c] += L->w;
            } else
                add_est(s, b, c,
                        td_interp_tent(L->za, L->s1, L->s2, k * sl,
                                       (L->n - k) * sl, s->p->interval),
                        k, L->n, sl);
        }
}

/* Zero b over row r's undetermined cells. */
static void sums_clear(const td_nan_runs *nr, sm_sums *b, int r)
{
    size_t i;
    int c;
    for (i = nr->off[r]; i < nr->off[r + 1]; i++)
        for (c = nr->run[i][0]; c < nr->run[i][1]; c++)
            b->bz[c] = b->bw[c] = 0;
}

/* The share of row r for thread t of nt: x and y (t 0), diag and anti
 * (t 1; both when nt is 1), each crossing direction into its own sums. */
static void row_part(const sm_state *s, sm_line *lines, sm_sums *b, int t,
                     int nt, int r)
{
    int j;
    if (t == 0) {
        sums_clear(s->nr, &b[0], r);
        row_x(s, &b[0], r);
        row_cross(s, lines, 0, &b[0], r);
    }
    if (t == 1 || nt == 1)
        for (j = 1; j < s->nv; j++) {
            sums_clear(s->nr, &b[j], r);
            row_cross(s, lines + (size_t)j * s->nl, j, &b[j], r);
        }
}

/* Row r's blend into out: x + y, then + diag, + anti (a direction with no
 * run there adds 0, which leaves a sum of x and y as it is: such a sum
 * is never -0). */
static void row_blend(const sm_state *s, const sm_sums *b, float *out, int r)
{
    size_t i;
    int c;
    for (i = s->nr->off[r]; i < s->nr->off[r + 1]; i++)
        for (c = s->nr->run[i][0]; c < s->nr->run[i][1]; c++) {
            float z = b[0].bz[c], w = b[0].bw[c];
            if (s->nv == SV) {
                z = (z + b[1].bz[c]) + b[2].bz[c];
                w = (w + b[1].bw[c]) + b[2].bw[c];
            }
            out[c] = w > 0 ? z / w : NAN;
        }
}

/* Row r's blends (ring) into g's undetermined cells. */
static void row_put(const sm_state *s, const float *done, int r)
{
    float *row = s->g->data + (size_t)r * s->g->stride;
    size_t i;
    int c;
    for (i = s->nr->off[r]; i < s->nr->off[r + 1]; i++)
        for (c = s->nr->run[i][0]; c < s->nr->run[i][1]; c++)
            if (done[c] == done[c])
                row[c] = done[c];
}

/* The sums of row r: slot r % SM_RING of each direction's ring. */
static void sums_slot(const sm_sums *ring, sm_sums *v, size_t w, int r)
{
    size_t o = (size_t)(r % SM_RING) * w;
    int j;
    for (j = 0; j < SV; j++)
        v[j].bz = ring[j].bz + o, v[j].bw = ring[j].bw + o;
}

/* Wait until *a reaches at least v (or *stop is set); spins a while,
 * then yields the core. */
static void wait_for(atomic_int *a, int v, atomic_int *stop)
{
    unsigned spins = 0;
    while (atomic_load_explicit(a, memory_order_acquire) < v &&
           !atomic_load_explicit(stop, memory_order_relaxed))
        if (++spins > 256)
            sched_yield();
}

/* The top-down sweep.  Thread 0 sums x and y into row r's slot, waits
 * until thread 1 has summed the diagonals of row r, blends the row into
 * the ring and writes row r - D back; thread 1 sums the diagonals up to
 * SM_RING rows ahead of the blend (its slot must be blended first).
 * Thread 1 reads g no higher than row r1 - 1 - slope_cells while thread 0
 * writes rows below r0 - D with r0 <= r1: every read sees phase 1's
 * grid, as in one thread.  0, or the cancel code. */
static int sweep(const sm_state *s, sm_line *lines, const sm_sums *b,
                 float *ring, int D, const char *stage, td_ctx *cx)
{
    const td_grid_f32 *g = s->g;
    size_t w = (size_t)g->w;
    atomic_int done0, done1, stop;
    atomic_init(&done0, 0), atomic_init(&done1, 0), atomic_init(&stop, 0);
#pragma omp parallel num_threads(2)
    {
        int t = omp_get_thread_num(), nt = omp_get_num_threads(), r;
        sm_sums v[SV];
        for (r = 0; r < g->h; r++) {
            if (t == 1) {
                wait_for(&done0, r - SM_RING + 1, &stop);
                if (atomic_load_explicit(&stop, memory_order_relaxed))
                    break;
                sums_slot(b, v, w, r);
                row_part(s, lines, v, 1, nt, r);
                atomic_store_explicit(&done1, r + 1, memory_order_release);
                continue;
            }
            sums_slot(b, v, w, r);
            row_part(s, lines, v, 0, nt, r);
            if (nt > 1)
                wait_for(&done1, r + 1, &stop);
            if (r >= D)
                row_put(s, ring + (size_t)((r - D) % D) * w, r - D);
            row_blend(s, v, ring + (size_t)(r % D) * w, r);
            atomic_store_explicit(&done0, r + 1, memory_order_release);
            if (stage && (r & 1023) == 1023 &&
                td_progress(cx, stage, (double)r / g->h) != 0) {
                atomic_store(&stop, 1);
                break;
            }
        }
    }
    if (atomic_load(&stop))
        return cx && cx->code ? cx->code : TD_ECANCEL;
    return 0;
}

/* See multidir_int.h. */
int td_multidir_summit(td_grid_f32 *g, const td_multidir_params *p,
                       const char *stage, td_ctx *cx)
{
    td_nan_runs nr;
    sm_state s;
    sm_sums b[SV];
    sm_line *lines = NULL;
    float *ring = NULL;
    int D = (p->slope_cells > 0 ? p->slope_cells : 0) + 2, r, j, rc;
    int fail = 0;
    size_t w = (size_t)g->w;
    memset(&nr, 0, sizeof nr);
    memset(&s, 0, sizeof s);
    memset(b, 0, sizeof b);
    s.g = g, s.p = p, s.nr = &nr;
    s.nl = (size_t)g->w + (size_t)g->h - 1;
    s.nv = p->ndir == 2 ? 1 : SV;
    if ((rc = td_nan_runs_find(g, &nr, cx)) != 0 || nr.n == 0)
        goto done; /* or nothing left undetermined */
    rc = TD_ENOMEM;
    if (!(s.ends = td_malloc(SV * s.nl * sizeof *s.ends, cx)) ||
        !(lines = td_calloc(SV * s.nl, sizeof *lines, cx)) ||
        !(ring = td_malloc((size_t)D * w * sizeof *ring, cx)))
        goto done;
    for (j = 0; j < SV; j++)
        if (!(s.row_at[j] =
                  td_malloc(((size_t)g->h + 1) * sizeof *s.row_at[j], cx)) ||
            !(b[j].bz = td_calloc(SM_RING * w, sizeof *b[j].bz, cx)) ||
            !(b[j].bw = td_calloc(SM_RING * w, sizeof *b[j].bw, cx)))
            goto done;
#pragma omp parallel for schedule(dynamic, 1) reduction(| : fail)
    for (j = 0; j < s.nv; j++)
        fail |= lookahead(&s, j) != 0;
    if (fail) {
        rc = td_seterr(cx, TD_ENOMEM, "multidir: out of memory");
        goto done;
    }
    free(s.ends);
    s.ends = NULL;
    if ((rc = sweep(&s, lines, b, ring, D, stage, cx)) != 0)
        goto done;
    for (r = g->h - D > 0 ? g->h - D : 0; r < g->h; r++)
        row_put(&s, ring + (size_t)(r % D) * w, r);
    rc = 0;
done:
    free(s.ends);
    for (j = 0; j < SV; j++)
        free(s.steps[j]), free(s.row_at[j]), free(b[j].bz), free(b[j].bw);
    free(lines);
    free(ring);
    td_nan_runs_free(&nr);
    return rc;
}
