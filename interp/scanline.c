#include "interp/scanline.h"

#include "interp/rasterise.h"

#include <math.h>
#include <stdlib.h>

td_scanline_params td_scanline_defaults(void)
{
    td_scanline_params p;
    p.interval = 0;
    p.summit = 1;
    p.slope_cells = 4;
    p.peninsula = 1;
    return p;
}

typedef struct sl_state {
    td_grid_f32 *g;
    float *dst; /* where spans are written: g->data, or the summit buffer */
    const td_scanline_params *p;
} sl_state;

/* §2.4 ③: z = z1 + (z2 - z1)(x - x1)/(x2 - x1) between two determined
 * cells of different height. */
static void linear_span(const td_span *s, void *user)
{
    sl_state *st = user;
    double dz = (double)s->zb - s->za;
    int k;
    if (s->za == s->zb)
        return;
    for (k = 1; k < s->n; k++)
        st->dst[s->ia + (ptrdiff_t)k * s->di] =
            (float)(s->za + dz * k / s->n);
}

/* §2.5: a gap left along x.  Different heights at its ends (one of them
 * filled by the y pass): linear.  Same height: Fig. 6 (td_interp_tent)
 * with slopes from up to slope_cells determined cells outside P1 and P2,
 * or flat (the paper's "P1 (P2) height") when summit is off or a slope is
 * unknown. */
static void summit_span(const td_span *s, void *user)
{
    sl_state *st = user;
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
        st->dst[s->ia + (ptrdiff_t)k * s->di] = (float)td_interp_tent(
            s->za, s1, s2, k * s->sl, (s->n - k) * s->sl, st->p->interval);
}

/* The summit step reads slopes from determined cells, so its results go to
 * a separate buffer first: one gap's estimate never feeds another's. */
static int summit_pass(td_grid_f32 *g, sl_state *st, td_ctx *cx)
{
    size_t n = (size_t)g->h * g->stride, i;
    float *buf = td_malloc(n * sizeof *buf, cx);
    int rc;
    if (!buf)
        return TD_ENOMEM;
    for (i = 0; i < n; i++)
        buf[i] = NAN;
    st->dst = buf;
    rc = td_interp_walk_gaps(g, TD_DIR_X, summit_span, st, "summit", cx);
    for (i = 0; rc == 0 && i < n; i++)
        if (g->data[i] != g->data[i])
            g->data[i] = buf[i];
    free(buf);
    return rc;
}

int td_scanline_fill(td_grid_f32 *g, const td_scanline_params *p,
                     td_ctx *cx)
{
    sl_state st;
    int rc;
    if (p->summit && !(p->interval > 0))
        return td_seterr(cx, TD_EINVAL, "scanline: the contour interval "
                         "must be > 0");
    st.g = g;
    st.dst = g->data;
    st.p = p;
    if ((rc = td_interp_walk(g, TD_DIR_X, linear_span, &st, "x pass",
                             cx)) != 0 ||
        (rc = td_interp_walk_gaps(g, TD_DIR_Y, linear_span, &st, "y pass",
                                  cx)) != 0)
        return rc;
    if (p->peninsula &&
        ((rc = td_interp_walk_gaps(g, TD_DIR_DIAG, linear_span, &st,
                                   "diagonal pass", cx)) != 0 ||
         (rc = td_interp_walk_gaps(g, TD_DIR_ANTI, linear_span, &st,
                                   "diagonal pass", cx)) != 0))
        return rc;
    return summit_pass(g, &st, cx);
}
