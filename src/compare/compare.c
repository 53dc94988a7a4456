#include "src/compare/compare.h"

#include <math.h>
#include <string.h>

static int valid(const td_grid_f32 *g, float v)
{
    return isfinite(v) && !(g->has_nodata && v == g->nodata);
}

static int same_size(const td_grid_f32 *a, const td_grid_f32 *b, td_ctx *cx)
{
    if (a->w != b->w || a->h != b->h)
        return td_seterr(cx, TD_EINVAL, "the grids differ in size (%d x %d "
                         "and %d x %d)", a->w, a->h, b->w, b->h);
    return 0;
}

int td_compare_grids(const td_grid_f32 *a, const td_grid_f32 *b,
                     td_compare_stats *st, td_ctx *cx)
{
    double s = 0, s2 = 0, sa = 0;
    int x, y;
    memset(st, 0, sizeof *st);
    st->max_x = st->max_y = -1;
    st->min_b = INFINITY;
    st->max_b = -INFINITY;
    if (same_size(a, b, cx) != 0)
        return TD_EINVAL;
    for (y = 0; y < a->h; y++) {
        const float *ra = a->data + (size_t)y * a->stride;
        const float *rb = b->data + (size_t)y * b->stride;
        for (x = 0; x < a->w; x++) {
            int va = valid(a, ra[x]), vb = valid(b, rb[x]);
            double d;
            st->n_a += va;
            st->n_b += vb;
            if (vb) {
                st->min_b = fmin(st->min_b, rb[x]);
                st->max_b = fmax(st->max_b, rb[x]);
            }
            if (!va || !vb)
                continue;
            d = (double)ra[x] - rb[x];
            st->n_both++;
            s += d;
            s2 += d * d;
            sa += fabs(d);
            if (fabs(d) > st->max_abs || st->max_x < 0) {
                st->max_abs = fabs(d);
                st->max_x = x;
                st->max_y = y;
            }
        }
    }
    if (st->n_b == 0)
        st->min_b = st->max_b = 0;
    if (st->n_both) {
        st->bias = s / st->n_both;
        st->rmse = sqrt(s2 / st->n_both);
        st->mae = sa / st->n_both;
    }
    st->coverage = st->n_b ? (double)st->n_both / st->n_b : 0;
    return 0;
}

/* blue (-1) - white (0) - red (+1) */
static void diverging(double t, uint8_t *p)
{
    double u = fmin(1.0, fabs(t));
    uint8_t fade = (uint8_t)lround(255 * (1 - u));
    if (t >= 0) {
        p[0] = 255;
        p[1] = p[2] = fade;
    } else {
        p[0] = p[1] = fade;
        p[2] = 255;
    }
}

int td_compare_diff_image(const td_grid_f32 *a, const td_grid_f32 *b,
                          double range, td_image **out, td_ctx *cx)
{
    td_compare_stats st;
    td_image *im;
    int x, y, rc;
    *out = NULL;
    if ((rc = td_compare_grids(a, b, &st, cx)) != 0)
        return rc;
    if (range <= 0)
        range = fmax(3 * st.rmse, 1e-6);
    if (!(im = td_image_new(a->w, a->h, 3, cx)))
        return TD_ENOMEM;
    for (y = 0; y < a->h; y++) {
        const float *ra = a->data + (size_t)y * a->stride;
        const float *rb = b->data + (size_t)y * b->stride;
        uint8_t *p = im->data + (size_t)y * im->stride;
        for (x = 0; x < a->w; x++, p += 3) {
            int va = valid(a, ra[x]), vb = valid(b, rb[x]);
            if (va && vb)
                diverging(((double)ra[x] - rb[x]) / range, p);
            else
                p[0] = p[1] = p[2] = va ? 200 : vb ? 90 : 0;
        }
    }
    *out = im;
    return 0;
}
