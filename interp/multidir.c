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
    md_sum *sum; /* per cell (phase 1 of the prod weight) */
    const td_multidir_params *p;
} md_state;

/* See multidir_int.h. */
double td_multidir_cell_weight(td_multidir_weight m, double d1, double d2)
{
    switch (m) {
    case TD_MULTIDIR_SPAN: return 1.0 / (d1 + d2);
    case TD_MULTIDIR_SPAN2: return 1.0 / ((d1 + d2) * (d1 + d2));
    default: return 1.0 / (d1 * d2);
    }
}

float td_multidir_span_weight(td_multidir_weight m, int n, double sl)
{
    return (float)td_multidir_cell_weight(m, sl, (n - 1) * sl);
}

static void add(md_state *st, const td_span *s, int k, double z)
{
    size_t i = s->ia + (ptrdiff_t)k * s->di;
    double w =
        td_multidir_cell_weight(st->p->weight, k * s->sl, (s->n - k) * s->sl);
    md_sum *p = &st->sum[i];
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
    for (k = 1; k < s->n; k++) {
        p += s->di;
        z += dz;
        p->wz += w * z;
        p->w += w;
    }
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
    return td_multidir_summit(g, p, "summit", cx);
}
