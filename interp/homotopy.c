/* homotopy.c: patch-wise interpolation between two adjacent contours
 * along the ridge, valley and inflection links (003 §3, §4 last
 * paragraph; ALGORITHMS.md B2 step 6).
 *
 * For a band between an outer contour f (region p) and the one contour g
 * nested in it (region c, another height), the links between them give
 * anchor pairs (s_f, s_g) of arc lengths.  The anchors kept are the
 * longest subsequence that is monotone (cyclically, on rings), so no two
 * correspondences cross; U maps s_f to s_g piecewise linearly between
 * consecutive anchors (open lines: their ends are anchors too).  The
 * homotopy
 *
 *     F(s, t) = (1 - t) f(s) + t g(U(s)),   z(s, t) = (1 - t) z_f + t z_g
 *
 *      f(s_k)    f(s_k+1)      is sampled about every 3 cells along both
 *        *--------*            curves; each quad of consecutive samples
 *        |      / |            is two triangles, scan-converted with
 *        |    /   |            barycentric z into the band's cells only
 *        |  /     |            (cells whose label is p).
 *        *--------*
 *      g(U(s_k)) g(U(s_k+1))
 *
 * Also an open line around one ring (open_ends) and, in part, branching
 * faces (fill_branching).  Not handled here (the fallback method fills
 * them, counted): the saddle parts of branching faces, faces holding
 * lines of different heights, the regions inside the innermost contours
 * (summits, pits) and outside the outermost, lines that bound no region. */
#include "interp/homotopy_int.h"

#include "interp/multidir.h"
#include "interp/scanline.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

td_homotopy_params td_homotopy_defaults(void)
{
    td_homotopy_params p;
    p.spacing = 2;
    p.smooth = 3;
    p.epsilon = 20;
    p.link_factor = 3;
    p.join_factor = 2;
    p.fallback = TD_HM_FALLBACK_SCANLINE;
    return p;
}

typedef struct anchor {
    double f, g;
    size_t curve; /* branching faces: the inner line g is on */
} anchor;

typedef struct band {
    td_grid_f32 *g;
    const int32_t *lab;
    long id;
    double step, zf, zg;
    size_t filled;
} band;

static long ifloor(double x)
{
    long i = (long)x;
    return i - (x < (double)i);
}

static long iceil(double x)
{
    long i = (long)x;
    return i + (x > (double)i);
}

/* Scan-convert triangle (x,y,z)[3] (cell units) into the band's NaN
 * cells: vertices sorted by y, each row's span between the long edge
 * (top to bottom) and the short edge it meets; z from the triangle's
 * plane z = z0 + zx (x - x0) + zy (y - y0) (barycentric interpolation). */
static void tri(band *b, const double *v)
{
    const double *p[3] = {v, v + 3, v + 6}, *t;
    double det, zx, zy, ya, yb, yc, sl, s1, s2;
    long r, r0, r1;
    if (p[0][1] > p[1][1])
        t = p[0], p[0] = p[1], p[1] = t;
    if (p[1][1] > p[2][1])
        t = p[1], p[1] = p[2], p[2] = t;
    if (p[0][1] > p[1][1])
        t = p[0], p[0] = p[1], p[1] = t;
    det = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) -
          (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
    if (det > -1e-12 && det < 1e-12)
        return;
    zx = ((p[1][2] - p[0][2]) * (p[2][1] - p[0][1]) -
          (p[2][2] - p[0][2]) * (p[1][1] - p[0][1])) / det;
    zy = ((p[2][2] - p[0][2]) * (p[1][0] - p[0][0]) -
          (p[1][2] - p[0][2]) * (p[2][0] - p[0][0])) / det;
    ya = p[0][1], yb = p[1][1], yc = p[2][1];
    sl = (p[2][0] - p[0][0]) / (yc - ya); /* dx/dy of the three edges */
    s1 = yb > ya ? (p[1][0] - p[0][0]) / (yb - ya) : 0;
    s2 = yc > yb ? (p[2][0] - p[1][0]) / (yc - yb) : 0;
    if (yc < 0 || ya > b->g->h) /* (clamped before any cast to long) */
        return;
    r0 = ya < 0 ? 0 : iceil(ya - 0.5);
    r1 = yc > b->g->h ? b->g->h - 1 : ifloor(yc - 0.5);
    for (r = r0; r <= r1; r++) {
        double y = r + 0.5, xl, xr, zrow;
        long c, c1;
        float *row = b->g->data + (size_t)r * b->g->stride;
        const int32_t *lab = b->lab + (size_t)r * b->g->w;
        xl = p[0][0] + (y - ya) * sl;
        xr = y < yb ? p[0][0] + (y - ya) * s1 : p[1][0] + (y - yb) * s2;
        if (xl > xr)
            zrow = xl, xl = xr, xr = zrow;
        if (!(xr >= 0 && xl <= b->g->w)) /* also NaN */
            continue;
        c = xl < 0 ? 0 : iceil(xl - 0.5 - 1e-9);
        c1 = xr > b->g->w ? b->g->w - 1 : ifloor(xr - 0.5 + 1e-9);
        zrow = p[0][2] + zy * (y - ya) + zx * (0.5 - p[0][0]);
        for (; c <= c1; c++)
            if (row[c] != row[c] && lab[c] == b->id) {
                row[c] = (float)(zrow + zx * c);
                b->filled++;
            }
    }
}

/* The strip between f on [sf, sf+df] and g on [sg, sg+dg]. */
static void strip(band *b, const td_rv_curve *f, const td_rv_curve *g,
                  double sf, double df, double sg, double dg)
{
    long n = (long)ceil((df > dg ? df : dg) / b->step / 3), k;
    double v[12], q[12];
    size_t hf = 0, hg = 0;
    if (n < 1)
        n = 1;
    for (k = 0; k <= n; k++) {
        double t = (double)k / n;
        hm_curve_at_hint(f, sf + df * t, &q[0], &q[1], &hf);
        hm_curve_at_hint(g, sg + dg * t, &q[3], &q[4], &hg);
        q[0] /= b->step, q[1] /= b->step, q[3] /= b->step, q[4] /= b->step;
        q[2] = b->zf, q[5] = b->zg;
        if (k > 0) { /* v: f_k-1, g_k-1, f_k, g_k */
            double t1[9] = {v[0], v[1], v[2], q[0], q[1], q[2], v[3], v[4], v[5]};
            double t2[9] = {q[0], q[1], q[2], q[3], q[4], q[5], v[3], v[4], v[5]};
            tri(b, t1);
            tri(b, t2);
        }
        memcpy(v, q, 6 * sizeof *q);
    }
}

static int cmp_anchor(const void *x, const void *y)
{
    double a = ((const anchor *)x)->f, b = ((const anchor *)y)->f;
    return (a > b) - (a < b);
}

/* Longest chain of anchors v[0..n) (sorted by f) with g non-decreasing,
 * on a ring (lg > 0) unwrapped from and rooted at v[start]; written to
 * out (when not NULL) in f order from start; returns its length.
 * prev, len: n scratch entries.  O(n^2). */
static size_t monotone(const anchor *v, size_t n, size_t start, double lg,
                       long *prev, size_t *len, anchor *out)
{
    size_t i, j, best = 0, m = 0;
    long k;
#define UG(i) (lg > 0 ? fmod(v[(start + (i)) % n].g - v[start].g + 2 * lg, lg) \
                      : v[i].g)
    for (i = 0; i < n; i++) {
        len[i] = lg > 0 && i > 0 ? 0 : 1, prev[i] = -1;
        for (j = 0; j < i; j++)
            if (len[j] > 0 && UG(j) <= UG(i) && len[j] + 1 > len[i])
                len[i] = len[j] + 1, prev[i] = (long)j;
        if (len[i] > len[best])
            best = i;
    }
#undef UG
    for (k = (long)best; k >= 0; k = prev[k])
        m++;
    if (out)
        for (k = (long)best, j = m; k >= 0; k = prev[k])
            out[--j] = v[lg > 0 ? (start + (size_t)k) % n : (size_t)k];
    return m;
}

/* The links between curves cf and cg as anchors (joins left out).
 * *out has room for 3 more. */
static int band_anchors(const td_ridges *r, size_t cf, size_t cg,
                        anchor **out, size_t *n, td_ctx *cx)
{
    size_t i, k = 0;
    anchor *v = td_malloc((r->nlink + 3) * sizeof *v, cx);
    if (!v)
        return TD_ENOMEM;
    for (i = 0; i < r->nlink; i++) {
        const td_rv_point *a = &r->pt[r->link[i].a], *b = &r->pt[r->link[i].b];
        if (r->link[i].join)
            continue;
        if (a->curve == cf && b->curve == cg)
            v[k].f = a->s, v[k++].g = b->s;
        else if (a->curve == cg && b->curve == cf)
            v[k].f = b->s, v[k++].g = a->s;
    }
    *out = v, *n = k;
    return 0;
}

/* Arc length on g of the sample nearest f at arc length sf. */
static double nearest_on(const td_rv_curve *f, double sf, const td_rv_curve *g)
{
    double x, y, best = INFINITY, s = 0;
    size_t i;
    hm_curve_at(f, sf, &x, &y);
    for (i = 0; i < g->n; i++) {
        double d = hypot(g->x[i] - x, g->y[i] - y);
        if (d < best)
            best = d, s = g->s[i];
    }
    return s;
}

/* An open line f around a ring g (a hill in the region of a line that
 * leaves the sheet): the strips between the anchors as usual; the ring's
 * rest goes to the two ends of f, split in proportion to their lengths,
 * so both ends of f meet at one point of the ring. */
static void open_ends(band *b, const td_rv_curve *f, const td_rv_curve *g,
                      const anchor *ch, size_t m)
{
    double cov = 0, l1 = ch[0].f, l2 = f->len - ch[m - 1].f, rest, r1;
    size_t j;
    for (j = 0; j + 1 < m; j++)
        cov += fmod(ch[j + 1].g - ch[j].g + 2 * g->len, g->len);
    rest = g->len - cov;
    if (rest < 0 || l1 + l2 <= 0)
        return;
    r1 = rest * l1 / (l1 + l2);
    strip(b, f, g, 0, l1, ch[0].g - r1, r1);
    strip(b, f, g, ch[m - 1].f, l2, ch[m - 1].g, rest - r1);
}

/* The correspondence U between curve cf (outer) and cg, strip by strip. */
static int fill_band(band *b, const td_ridges *r, size_t cf, size_t cg,
                     td_ctx *cx)
{
    const td_rv_curve *f = &r->curve[cf], *g = &r->curve[cg];
    anchor *v = NULL, *ch = NULL;
    long *prev = NULL;
    size_t n, m, j, *len = NULL, st, best = 0, bm = 0;
    int rc;
    int mixed = !f->closed && g->closed, ring = f->closed || mixed;
    if ((rc = band_anchors(r, cf, cg, &v, &n, cx)) != 0)
        return rc;
    if (!ring) {
        v[n].f = 0, v[n++].g = 0;
        v[n].f = f->len, v[n++].g = g->len;
    } else if (n == 0)
        v[n].f = f->len / 2, v[n].g = nearest_on(f, f->len / 2, g), n++;
    qsort(v, n, sizeof *v, cmp_anchor);
    rc = TD_ENOMEM;
    if (!(ch = td_malloc(n * sizeof *ch, cx)) ||
        !(prev = td_malloc(n * sizeof *prev, cx)) ||
        !(len = td_malloc(n * sizeof *len, cx)))
        goto fail;
    for (st = 0; st < (f->closed ? n : 1); st++)
        if ((m = monotone(v, n, st, ring ? g->len : 0, prev, len, NULL)) > bm)
            bm = m, best = st;
    m = monotone(v, n, best, ring ? g->len : 0, prev, len, ch);
    for (j = 0; j + (f->closed ? 0 : 1) < m; j++) {
        const anchor *a = &ch[j], *e = &ch[(j + 1) % m];
        double df = e->f - a->f, dg = e->g - a->g;
        if (f->closed)
            df = m == 1 ? f->len : fmod(df + 2 * f->len, f->len);
        if (ring)
            dg = m == 1 && f->closed ? g->len : fmod(dg + 2 * g->len, g->len);
        strip(b, f, g, a->f, df, a->g, dg);
    }
    if (mixed)
        open_ends(b, f, g, ch, m);
    rc = 0;
fail:
    free(v);
    free(ch);
    free(prev);
    free(len);
    return rc;
}

/* A branching face (003 §5, last paragraph): the outer line f holds
 * several lines.  Each link from f to one of them is an anchor; between
 * two anchors next to each other along f that go to the same inner line
 * the strip is filled as in a two-line band (when both stretches are
 * under half their lines: a longer one would wrap the wrong way round).
 * Stretches of f between anchors to different lines face the saddle
 * between them and are left to the fallback.  Only faces whose inner
 * lines share one height other than f's: with a pit and a summit inside,
 * or a line at f's own height, the surface is not monotone between f and
 * a nested line. */
static int fill_branching(band *b, const td_ridges *r, size_t cf,
                          td_ctx *cx)
{
    const td_rv_curve *f = &r->curve[cf];
    anchor *v = td_malloc((r->nlink + 1) * sizeof *v, cx);
    size_t i, n = 0;
    if (!v)
        return TD_ENOMEM;
    for (i = 0; i < r->nlink; i++) {
        const td_rv_point *a = &r->pt[r->link[i].a], *e = &r->pt[r->link[i].b];
        if (r->link[i].join)
            continue;
        if (e->curve == cf)
            a = e, e = &r->pt[r->link[i].a];
        else if (a->curve != cf)
            continue;
        if (r->cparent[e->curve] != (long)cf || r->curve[e->curve].z == f->z)
            continue;
        v[n].f = a->s, v[n].g = e->s, v[n++].curve = e->curve;
    }
    qsort(v, n, sizeof *v, cmp_anchor);
    for (i = 0; i + (f->closed ? 0 : 1) < n && n > 1; i++) {
        const anchor *a = &v[i], *e = &v[(i + 1) % n];
        const td_rv_curve *g = &r->curve[a->curve];
        double df = e->f - a->f, dg = e->g - a->g;
        if (e->curve != a->curve)
            continue;
        if (f->closed)
            df = fmod(df + 2 * f->len, f->len);
        if (g->closed)
            dg = fmod(dg + 2 * g->len, g->len);
        if (df > f->len / 2 || dg < 0 || dg > g->len / 2)
            continue;
        b->zg = g->z;
        strip(b, f, g, a->f, df, a->g, dg);
    }
    free(v);
    return 0;
}

/* Do all lines nested in line b lie at one height other than b's (a
 * proper branching face, so the surface in it runs between two heights)? */
static int one_side(const td_ridges *r, size_t b)
{
    size_t i;
    double zc = NAN;
    for (i = 0; i < r->ncurve; i++) {
        if (r->cparent[i] != (long)b)
            continue;
        if (r->curve[i].z == r->curve[b].z || (zc == zc && r->curve[i].z != zc))
            return 0;
        zc = r->curve[i].z;
    }
    return zc == zc;
}

/* The two lines bounding band b (a region, or -1: outside every region)
 * when exactly two do: the region's own line first.  0 when not. */
static int band_pair(const td_ridges *r, const size_t *nchild,
                     const long *first, long b, size_t *f, size_t *g)
{
    size_t i;
    if (b >= 0 && nchild[b] == 1) {
        *f = (size_t)b, *g = (size_t)first[b];
        return 1;
    }
    if (b >= 0 || nchild[r->ncurve] != 2)
        return 0;
    *f = (size_t)first[r->ncurve];
    for (i = *f + 1; i < r->ncurve; i++)
        if (r->cparent[i] == -1)
            break;
    *g = i;
    return 1;
}

/* Bands between exactly two lines of different heights and of one kind
 * (ring around ring, open line beside open line). */
static int fill_bands(td_grid_f32 *g, const td_ridges *r, const int32_t *lab,
                      double step, td_homotopy_stats *st, td_ctx *cx)
{
    size_t nc = r->ncurve, i, f, k;
    size_t *nchild = td_calloc(nc + 1, sizeof *nchild, cx);
    long *first = td_malloc((nc + 1) * sizeof *first, cx), b;
    band bd;
    int rc = 0;
    if (!nchild || !first) {
        free(nchild);
        free(first);
        return TD_ENOMEM;
    }
    for (i = 0; i <= nc; i++)
        first[i] = -1;
    for (i = 0; i < nc; i++) { /* slot nc: outside every region */
        long pp = r->cparent[i] == -1 ? (long)nc : r->cparent[i];
        if (pp < 0)
            continue;
        if (nchild[pp]++ == 0)
            first[pp] = (long)i;
    }
    for (b = -1; b < (long)nc && rc == 0; b++) {
        const td_rv_curve *cf, *cg;
        st->bands += b < 0 || nchild[b] > 0;
        if (b >= 0 && nchild[b] >= 2 && r->curve[b].orient &&
            one_side(r, (size_t)b)) {
            memset(&bd, 0, sizeof bd);
            bd.g = g, bd.lab = lab, bd.id = b, bd.step = step;
            bd.zf = r->curve[b].z;
            rc = fill_branching(&bd, r, (size_t)b, cx);
            st->cells_homotopy += bd.filled;
            st->bands_branching += bd.filled > 0;
            continue;
        }
        if (!band_pair(r, nchild, first, b, &f, &k))
            continue;
        cf = &r->curve[f], cg = &r->curve[k];
        if (cf->z == cg->z || !cf->orient || !cg->orient ||
            (cf->closed && !cg->closed) || (b < 0 && cf->closed != cg->closed) ||
            (b < 0 && cf->closed) || cf->n < 2 || cg->n < 2)
            continue;
        memset(&bd, 0, sizeof bd);
        bd.g = g, bd.lab = lab, bd.id = b, bd.step = step;
        bd.zf = cf->z, bd.zg = cg->z;
        rc = fill_band(&bd, r, f, k, cx);
        st->cells_homotopy += bd.filled;
        st->bands_homotopy++;
        if (rc == 0 && (b & 63) == 63)
            rc = td_progress(cx, "homotopy", (double)b / nc);
    }
    free(nchild);
    free(first);
    return rc;
}

/* The cells the homotopy left take the scanline method's heights,
 * interpolated from the contours alone (sl), so a band filled in part
 * does not feed the scanline's spans and summit slopes. */
static void fallback(td_grid_f32 *g, const td_grid_f32 *sl,
                     td_homotopy_stats *st)
{
    size_t r, c;
    for (r = 0; r < (size_t)g->h; r++) {
        float *row = g->data + r * g->stride;
        const float *srow = sl->data + r * sl->stride;
        for (c = 0; c < (size_t)g->w; c++) {
            if (row[c] == row[c])
                continue;
            row[c] = srow[c];
            if (srow[c] == srow[c])
                st->cells_fallback++;
            else
                st->cells_none++;
        }
    }
}

static size_t count_nan(const td_grid_f32 *g)
{
    size_t n = 0, r, c;
    for (r = 0; r < (size_t)g->h; r++)
        for (c = 0; c < (size_t)g->w; c++)
            n += g->data[r * g->stride + c] != g->data[r * g->stride + c];
    return n;
}

/* The fallback method on sl (the contours alone). */
static int fill_fallback(td_grid_f32 *sl, int method,
                         const td_scanline_params *sp, td_ctx *cx)
{
    td_multidir_params mp = td_multidir_defaults();
    if (method != TD_HM_FALLBACK_MULTIDIR)
        return td_scanline_fill(sl, sp, cx);
    mp.interval = sp->interval;
    mp.summit = sp->summit;
    return td_multidir_fill(sl, &mp, cx);
}

/* The homotopy into g and the fallback method into a copy of g (the
 * contours alone), side by side; then the fallback cells from the copy. */
static int fill_both(td_grid_f32 *g, const td_ridges *r, const int32_t *clab,
                     int step, int method, const td_scanline_params *sp,
                     td_homotopy_stats *st, td_ctx *cx)
{
    td_grid_f32 *sl = td_grid_f32_new(g->w, g->h, cx);
    td_ctx cx2;
    size_t i;
    int rc = 0, rc2 = 0;
    if (!sl)
        return TD_ENOMEM;
    for (i = 0; i < (size_t)g->h; i++)
        memcpy(sl->data + i * sl->stride, g->data + i * g->stride,
               (size_t)g->w * sizeof *g->data);
    td_ctx_init(&cx2);
#pragma omp parallel sections num_threads(2)
    { /* independent grids: the homotopy into g, the fallback into sl */
#pragma omp section
        rc = fill_bands(g, r, clab, step, st, cx);
#pragma omp section
        rc2 = fill_fallback(sl, method, sp, &cx2);
    }
    if (rc == 0 && rc2 != 0)
        rc = td_seterr(cx, rc2, "%s", td_errmsg(&cx2));
    if (rc == 0)
        fallback(g, sl, st);
    td_grid_f32_free(sl);
    return rc;
}

int td_homotopy_fill(td_grid_f32 *g, const td_lines *ls, int w, int h,
                     int step, const td_homotopy_params *p, double interval,
                     int summit, int peninsula, td_homotopy_stats *st,
                     td_ctx *cx)
{
    td_homotopy_stats s0;
    td_scanline_params sp = td_scanline_defaults();
    td_contain ct;
    td_ridges *r = NULL;
    int32_t *lab = NULL, *clab = NULL;
    size_t i, ncell = (size_t)g->w * g->h;
    int rc = TD_ENOMEM;
    memset(&ct, 0, sizeof ct);
    st = st ? st : &s0;
    memset(st, 0, sizeof *st);
    if (step < 1 || (rc = td_check_dims(w, h, "scan", cx)) != 0)
        return step < 1 ? td_seterr(cx, TD_EINVAL, "step must be >= 1") : rc;
    if (!(lab = td_malloc((size_t)w * h * sizeof *lab, cx)))
        return TD_ENOMEM;
    if ((rc = hm_find(ls, w, h, p, &r, &ct, lab, cx)) != 0)
        goto fail;
    clab = lab;
    if (step != 1 || g->w != w || g->h != h) {
        rc = TD_ENOMEM;
        if (!(clab = td_malloc(ncell * sizeof *clab, cx)) ||
            (rc = hm_label(&ct, g->w, g->h, step, clab, cx)) != 0)
            goto fail;
    }
    for (i = 0; i < r->npt; i++) {
        st->ridge_points += r->pt[i].kind == TD_RV_RIDGE;
        st->valley_points += r->pt[i].kind == TD_RV_VALLEY;
    }
    st->links = r->nlink;
    st->cells_line = ncell - count_nan(g);
    sp.interval = interval;
    sp.summit = summit;
    sp.peninsula = peninsula;
    rc = fill_both(g, r, clab, step, p->fallback, &sp, st, cx);
fail:
    if (clab != lab)
        free(clab);
    free(lab);
    td_contain_free(&ct);
    td_ridges_free(r);
    return rc;
}
