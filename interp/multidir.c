#include "interp/multidir.h"
#include "interp/interp_int.h"
#include "interp/multidir_int.h"

#include "interp/rasterise.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

td_multidir_params td_multidir_defaults(void)
{
    td_multidir_params p;
    p.interval = 0;
    p.summit = 1;
    p.slope_cells = 4;
    p.ndir = 4;
    p.weight = TD_MULTIDIR_SPAN;
    return p;
}

/* Per cell: sum of w*z and of w, side by side (one cache line holds
 * both for 8 cells). */
typedef struct md_sum {
    float wz, w;
} md_sum;

typedef struct md_state {
    const td_grid_f32 *g;
    md_sum *sum;      /* per cell, or (nr set) per undetermined cell */
    const td_multidir_params *p;
    const td_nan_runs *nr; /* phase 2: sum holds only the runs' cells */
    size_t *base;     /* phase 2: the first slot of each run */
} md_state;

/* The sums of cell (c, r): phase 2 keeps them only for the cells phase 1
 * left undetermined (a few percent of the grid), found by the row's runs
 * (c is in one of them: phase 2's spans run over them only). */
static md_sum *slot(const md_state *st, int c, int r, size_t i)
{
    size_t lo, hi;
    if (!st->nr)
        return &st->sum[i];
    lo = st->nr->off[r], hi = st->nr->off[r + 1];
    while (hi - lo > 1) { /* the last run starting at or before c */
        size_t mid = lo + (hi - lo) / 2;
        if (st->nr->run[mid][0] <= c)
            lo = mid;
        else
            hi = mid;
    }
    return &st->sum[st->base[lo] + (size_t)(c - st->nr->run[lo][0])];
}

static double weight(td_multidir_weight m, double d1, double d2)
{
    switch (m) {
    case TD_MULTIDIR_SPAN: return 1.0 / (d1 + d2);
    case TD_MULTIDIR_SPAN2: return 1.0 / ((d1 + d2) * (d1 + d2));
    default: return 1.0 / (d1 * d2);
    }
}

float td_multidir_span_weight(td_multidir_weight m, int n, double sl)
{
    return (float)weight(m, sl, (n - 1) * sl);
}

static void add(md_state *st, const td_span *s, int k, double z)
{
    size_t i = s->ia + (ptrdiff_t)k * s->di;
    double w = weight(st->p->weight, k * s->sl, (s->n - k) * s->sl);
    md_sum *p = slot(st, s->ca + k * s->dc, s->ra + k * s->dr, i);
    p->wz += (float)(w * z);
    p->w += (float)w;
}

/* One line's linear estimate between two contour cells of different
 * height, added to every cell between them with its weight (the hot loop:
 * the span weights need no division per cell). */
static void linear_span(const td_span *s, void *user)
{
    md_state *st = user;
    float dz = (s->zb - s->za) / (float)s->n, z = s->za, w;
    md_sum *p = st->sum + s->ia;
    int k;
    if (s->za == s->zb)
        return;
    if (st->p->weight == TD_MULTIDIR_PROD) {
        for (k = 1; k < s->n; k++)
            add(st, s, k, s->za + dz * k);
        return;
    }
    w = td_multidir_span_weight(st->p->weight, s->n, s->sl);
    if (st->nr) { /* phase 2: the same operations, into the runs' slots */
        for (k = 1; k < s->n; k++) {
            md_sum *q = slot(st, s->ca + k * s->dc, s->ra + k * s->dr, 0);
            z += dz;
            q->wz += w * z;
            q->w += w;
        }
        return;
    }
    for (k = 1; k < s->n; k++) {
        p += s->di;
        z += dz;
        p->wz += w * z;
        p->w += w;
    }
}

/* Second phase, on the grid filled by the first: a gap between two
 * determined cells.  Same height: §2.5 Fig. 6 along this line
 * (td_interp_tent), flat when summit is off or a slope is unknown;
 * different heights: linear. */
static void summit_span(const td_span *s, void *user)
{
    md_state *st = user;
    double s1 = 0, s2 = 0;
    int k;
    if (s->za != s->zb) {
        linear_span(s, user);
        return;
    }
    if (st->p->summit &&
        (td_interp_slope(st->g, s, 0, st->p->slope_cells, &s1) != 0 ||
         td_interp_slope(st->g, s, 1, st->p->slope_cells, &s2) != 0))
        s1 = s2 = 0;
    for (k = 1; k < s->n; k++)
        add(st, s, k, td_interp_tent(s->za, s1, s2, k * s->sl,
                                     (s->n - k) * s->sl, st->p->interval));
}

/* Undetermined cells with some weight take the blend; the sums are
 * cleared for the next phase.  Only the sums of undetermined cells are
 * read. */
static void combine(td_grid_f32 *g, md_state *st)
{
    size_t n = (size_t)g->h * g->stride, i;
    for (i = 0; i < n; i++) {
        if (g->data[i] == g->data[i])
            continue;
        if (st->sum[i].w > 0)
            g->data[i] = st->sum[i].wz / st->sum[i].w;
        st->sum[i].wz = st->sum[i].w = 0;
    }
}

/* Phase 1 for the prod weight (one division per cell): the span walker,
 * one direction after the other, into st->sum. */
static int phase1_walk(td_grid_f32 *g, md_state *st, td_ctx *cx)
{
    int d, rc = 0;
    for (d = 0; d < st->p->ndir && rc == 0; d++)
        rc = td_interp_walk(g, d, linear_span, st, "interpolate", cx);
    if (rc == 0)
        combine(g, st);
    return rc;
}

/* Phase 2 walks only over the runs of cells phase 1 left undetermined
 * (found once: the walks write the sums, not g) and blends them; the sums
 * are kept for those cells only (8 bytes each, not 8 per grid cell).  Each
 * direction's lines are walked on threads (td_interp_walk_runs): a cell
 * gets its directions' sums in order, the same bytes on any thread count. */
static int phase2(td_grid_f32 *g, md_state *st, td_ctx *cx)
{
    td_nan_runs nr;
    md_sum *sum = NULL;
    size_t *base = NULL, i, k, cells = 0;
    int d, rc, r, c;
    memset(&nr, 0, sizeof nr);
    rc = td_nan_runs_find(g, &nr, cx);
    if (rc == 0 && !(base = td_malloc((nr.n + 1) * sizeof *base, cx)))
        rc = TD_ENOMEM;
    for (i = 0; rc == 0 && i < nr.n; i++) {
        base[i] = cells;
        cells += (size_t)(nr.run[i][1] - nr.run[i][0]);
    }
    if (rc == 0 && !(sum = td_calloc(cells + 1, sizeof *sum, cx)))
        rc = TD_ENOMEM;
    st->sum = sum, st->nr = &nr, st->base = base;
    for (d = 0; d < st->p->ndir && rc == 0; d++)
        rc = td_interp_walk_runs(g, &nr, d, summit_span, st, "summit", cx);
    for (r = 0; r < g->h && rc == 0; r++)
        for (i = nr.off[r]; i < nr.off[r + 1]; i++)
            for (c = nr.run[i][0]; c < nr.run[i][1]; c++) {
                const md_sum *q = &sum[base[i] + (size_t)(c - nr.run[i][0])];
                k = (size_t)r * g->stride + (size_t)c;
                if (q->w > 0)
                    g->data[k] = q->wz / q->w;
            }
    st->sum = NULL, st->nr = NULL, st->base = NULL;
    free(sum), free(base);
    td_nan_runs_free(&nr);
    return rc;
}

int td_multidir_fill(td_grid_f32 *g, const td_multidir_params *p,
                     td_ctx *cx)
{
    size_t n = (size_t)g->h * g->stride;
    md_state st;
    int rc;
    if (p->summit && !(p->interval > 0))
        return td_seterr(cx, TD_EINVAL, "multidir: the contour interval "
                         "must be > 0");
    if (p->ndir != 2 && p->ndir != 4)
        return td_seterr(cx, TD_EINVAL, "multidir: 2 or 4 directions");
    memset(&st, 0, sizeof st);
    st.g = g;
    st.p = p;
    if (p->weight != TD_MULTIDIR_PROD) {
        if ((rc = td_multidir_sweep(g, p, "interpolate", cx)) != 0)
            return rc;
    } else { /* the walk's sums, per cell */
        if (!(st.sum = td_calloc(n, sizeof *st.sum, cx)))
            return TD_ENOMEM;
        rc = phase1_walk(g, &st, cx);
        free(st.sum);
        st.sum = NULL;
        if (rc != 0)
            return rc;
    }
    return phase2(g, &st, cx);
}
