/* ridgelink.c: ridge, valley and inflection lines across contours and the
 * branching of ridges into trees (003 §4 last paragraph, §5; ALGORITHMS.md
 * B2 steps 4-5).
 *
 * Adjacent contours: two lines at different heights that bound one band
 * (a region of the containment tree less the regions nested in it, or
 * what lies outside every region): a line and its parent or child, or
 * two siblings.
 * Each ridge (inflection) point links uphill, each valley point downhill,
 * to the nearest point of the same kind on an adjacent contour, when the
 * link
 *   - is at most link_factor x the gap + 4 px long (gap: the point's
 *     distance to that contour), and
 *   - stays inside the band between the two contours (every sample of
 *     the segment, 1.5 px from its ends on, has the band's label), so it
 *     crosses no contour.
 *
 *     z+2   ----*-----        ridge tree: union of the points a link
 *              / \            joins; the lowest contour first, so two
 *     z+1  ---*---*---        ridges meeting at one point above get one
 *             |   |           number (Steps 1-2).  A point with no
 *     z    ---*---*---        partner above is Suspended (Step 3) and
 *                             joins the nearest ridge point above within
 *                             join_factor x the link limit (Step 4).
 *
 * Valleys run the same from the top down: valleys merge downstream. */
#include "interp/homotopy_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Distance from (x,y) to the oriented input polyline of c, or a value
 * >= lim when it is at least lim. */
static double dist_curve(const td_rv_curve *c, double x, double y,
                         double lim)
{
    double best = lim * lim;
    size_t i, m = c->closed ? c->no : c->no - 1;
    if (c->no == 1)
        return hypot(x - c->oxy[0], y - c->oxy[1]);
    for (i = 0; i < m; i++) {
        const double *a = c->oxy + 2 * i, *b = c->oxy + 2 * ((i + 1) % c->no);
        double dx = b[0] - a[0], dy = b[1] - a[1], l2 = dx * dx + dy * dy;
        double t = l2 > 0 ? ((x - a[0]) * dx + (y - a[1]) * dy) / l2 : 0, ex, ey;
        t = t < 0 ? 0 : t > 1 ? 1 : t;
        ex = x - a[0] - t * dx, ey = y - a[1] - t * dy;
        if (ex * ex + ey * ey < best)
            best = ex * ex + ey * ey;
    }
    return sqrt(best);
}

/* The segment a-b inside band `band`: no contour crossed. */
static int band_ok(const int32_t *lab, int w, int h, const td_rv_point *a,
                   const td_rv_point *b, long band)
{
    double len = hypot(b->x - a->x, b->y - a->y), d;
    for (d = 1.5; d < len - 1.5; d += 0.5) {
        double x = a->x + (b->x - a->x) * d / len;
        double y = a->y + (b->y - a->y) * d / len;
        long cx, cy;
        if (!(x >= 0 && y >= 0 && x < w && y < h))
            return 0;
        cx = (long)x, cy = (long)y;
        if (lab[(size_t)cy * w + cx] != band)
            return 0;
    }
    return 1;
}

typedef struct lctx {
    td_ridges *r;
    const td_contain *ct;
    const int32_t *lab;
    int w, h;
    size_t *pstart; /* points of curve c: pstart[c] .. pstart[c+1] */
    long *next;     /* per point: the link leaving it, -1 none */
    size_t lcap;
    size_t *coff, *cidx; /* children of line p: cidx[coff[p+1] ..
                            coff[p+2]); slot 0: the roots (parent -1) */
} lctx;

/* The lines that may bound a band with line l: its parent, its children
 * and its siblings, into out (room for ncurve + 1); returns how many. */
static size_t neighbours(const lctx *L, size_t l, size_t *out)
{
    const long *par = L->ct->parent;
    size_t k = 0, i;
    long p = par[l];
    if (p == -2)
        return 0;
    if (p >= 0)
        out[k++] = (size_t)p;
    for (i = L->coff[l + 1]; i < L->coff[l + 2]; i++)
        out[k++] = L->cidx[i];
    for (i = L->coff[p + 1]; i < L->coff[p + 2]; i++)
        if (L->cidx[i] != l)
            out[k++] = L->cidx[i];
    return k;
}

/* Children lists (CSR) of the containment tree. */
static int children(lctx *L, td_ctx *cx)
{
    const long *par = L->ct->parent;
    size_t n = L->r->ncurve, i, *fill;
    if (!(L->coff = td_calloc(n + 3, sizeof *L->coff, cx)) ||
        !(L->cidx = td_malloc((n + 1) * sizeof *L->cidx, cx)) ||
        !(fill = td_malloc((n + 3) * sizeof *fill, cx)))
        return TD_ENOMEM;
    for (i = 0; i < n; i++)
        if (par[i] >= -1)
            L->coff[par[i] + 2]++;
    for (i = 1; i < n + 3; i++)
        L->coff[i] += L->coff[i - 1];
    memcpy(fill, L->coff, (n + 3) * sizeof *fill);
    for (i = 0; i < n; i++)
        if (par[i] >= -1)
            L->cidx[fill[par[i] + 1]++] = i;
    free(fill);
    return 0;
}

static int add_link(lctx *L, size_t a, size_t b, int join, td_ctx *cx)
{
    td_ridges *r = L->r;
    if (r->nlink == L->lcap) {
        size_t nc = L->lcap * 2 + 64;
        void *t = realloc(r->link, nc * sizeof *r->link);
        if (!t)
            return td_seterr(cx, TD_ENOMEM, "out of memory");
        r->link = t, L->lcap = nc;
    }
    r->link[r->nlink].a = a, r->link[r->nlink].b = b;
    r->link[r->nlink].kind = r->pt[a].kind, r->link[r->nlink].join = join;
    L->next[a] = (long)r->nlink++;
    return 0;
}

/* The band lines l and m both bound (the parent's region for a parent
 * and child, the common parent's for two siblings, -1 outside every
 * region), or -2 when they bound none together. */
static long common_band(const long *par, size_t l, size_t m)
{
    if (par[l] == (long)m)
        return (long)m;
    if (par[m] == (long)l)
        return (long)l;
    if (par[l] == par[m] && par[l] != -2)
        return par[l];
    return -2;
}

/* Is line m adjacent to line l in direction dir (+1 up, -1 down)? */
static int adjacent(const lctx *L, size_t l, size_t m, int dir)
{
    const td_ridges *r = L->r;
    double dz = r->curve[m].z - r->curve[l].z;
    if (m == l || dz * dir <= 0 || r->curve[m].orient == 0)
        return 0;
    return common_band(L->ct->parent, l, m) != -2;
}

/* The best partner of point a on the adjacent lines (dir), -1 none;
 * strict: the link rules, else the Suspended join (no band test).  nb:
 * scratch for the neighbour list. */
static long partner(const lctx *L, size_t a, int dir, int strict,
                    const td_homotopy_params *p, size_t *nb)
{
    const td_ridges *r = L->r;
    const td_rv_point *pa = &r->pt[a];
    size_t l = pa->curve, j, k, nn = neighbours(L, l, nb);
    double gap = INFINITY, lim, best = INFINITY;
    long bi = -1;
    for (j = 0; j < nn; j++)
        if (adjacent(L, l, nb[j], dir))
            gap = dist_curve(&r->curve[nb[j]], pa->x, pa->y, gap);
    if (!isfinite(gap))
        return -1;
    lim = p->link_factor * gap + 4;
    if (!strict)
        lim *= p->join_factor;
    for (j = 0; j < nn; j++) {
        size_t m = nb[j];
        long band = common_band(L->ct->parent, l, m);
        if (!adjacent(L, l, m, dir))
            continue;
        for (k = L->pstart[m]; k < L->pstart[m + 1]; k++) {
            const td_rv_point *pb = &r->pt[k];
            double d = hypot(pb->x - pa->x, pb->y - pa->y);
            if (pb->kind != pa->kind || d > lim || d >= best)
                continue;
            if (strict && !band_ok(L->lab, L->w, L->h, pa, pb, band))
                continue;
            best = d, bi = (long)k;
        }
    }
    return bi;
}

/* Does the line of point a have an adjacent line in direction dir? */
static int has_next(const lctx *L, size_t a, int dir, size_t *nb)
{
    size_t l = L->r->pt[a].curve, j, nn = neighbours(L, l, nb);
    for (j = 0; j < nn; j++)
        if (adjacent(L, l, nb[j], dir))
            return 1;
    return 0;
}

static long uf_find(long *u, long i)
{
    while (u[i] != i)
        i = u[i] = u[u[i]];
    return i;
}

/* Tree ids: the union of linked points (the paper's renumbering),
 * numbered 0.. per kind. */
static int number_trees(td_ridges *r, td_ctx *cx)
{
    long *u = td_malloc((r->npt + 1) * sizeof *u, cx), *id = NULL;
    size_t i;
    if (!u || !(id = td_malloc((r->npt + 1) * sizeof *id, cx))) {
        free(u);
        return TD_ENOMEM;
    }
    for (i = 0; i < r->npt; i++)
        u[i] = (long)i, id[i] = -1;
    for (i = 0; i < r->nlink; i++) {
        long a = uf_find(u, (long)r->link[i].a), b = uf_find(u, (long)r->link[i].b);
        if (a != b)
            u[a > b ? a : b] = a < b ? a : b;
    }
    r->nridge = r->nvalley = 0;
    for (i = 0; i < r->npt; i++) {
        long root = uf_find(u, (long)i);
        td_rv_point *q = &r->pt[i];
        if (q->kind == TD_RV_INFLECT)
            continue;
        if (id[root] < 0)
            id[root] = q->kind == TD_RV_RIDGE ? r->nridge++ : r->nvalley++;
        q->tree = id[root];
    }
    free(u);
    free(id);
    return 0;
}

/* Points in processing order: uphill for ridges and inflections,
 * downhill for valleys, each kind from its own end (003 §5 Step 0). */
static int link_all(lctx *L, const td_homotopy_params *p, td_ctx *cx)
{
    td_ridges *r = L->r;
    size_t i, *nb = td_malloc((r->ncurve + 1) * sizeof *nb, cx);
    td_dkey *ord = td_malloc((r->npt + 1) * sizeof *ord, cx);
    int rc = 0;
    if (!ord || !nb) {
        free(ord);
        free(nb);
        return TD_ENOMEM;
    }
    for (i = 0; i < r->npt; i++) {
        ord[i].i = i;
        ord[i].key = r->pt[i].kind == TD_RV_VALLEY ? -r->pt[i].z : r->pt[i].z;
    }
    qsort(ord, r->npt, sizeof *ord, td_dkey_cmp);
    for (i = 0; i < r->npt && rc == 0; i++) {
        size_t a = ord[i].i;
        int dir = r->pt[a].kind == TD_RV_VALLEY ? -1 : 1;
        long b = partner(L, a, dir, 1, p, nb);
        if (b < 0 && r->pt[a].kind != TD_RV_INFLECT &&
            has_next(L, a, dir, nb)) {
            b = partner(L, a, dir, 0, p, nb); /* Suspended: Step 4 */
            if (b < 0)
                r->suspended++;
            else
                rc = add_link(L, a, (size_t)b, 1, cx);
        } else if (b >= 0)
            rc = add_link(L, a, (size_t)b, 0, cx);
    }
    free(ord);
    free(nb);
    return rc;
}

int hm_link(td_ridges *r, const td_contain *ct, const int32_t *lab, int w,
            int h, const td_homotopy_params *p, td_ctx *cx)
{
    lctx L;
    size_t i;
    int rc = TD_ENOMEM;
    memset(&L, 0, sizeof L);
    L.r = r, L.ct = ct, L.lab = lab, L.w = w, L.h = h;
    if (!(L.pstart = td_calloc(r->ncurve + 2, sizeof *L.pstart, cx)) ||
        !(L.next = td_malloc((r->npt + 1) * sizeof *L.next, cx)))
        goto fail;
    for (i = 0; i < r->npt; i++) /* points are stored curve by curve */
        L.pstart[r->pt[i].curve + 1] = i + 1;
    for (i = 1; i <= r->ncurve; i++)
        if (L.pstart[i] < L.pstart[i - 1])
            L.pstart[i] = L.pstart[i - 1];
    for (i = 0; i < r->npt; i++)
        L.next[i] = -1;
    if ((rc = children(&L, cx)) == 0 && (rc = link_all(&L, p, cx)) == 0)
        rc = number_trees(r, cx);
fail:
    free(L.pstart);
    free(L.next);
    free(L.coff);
    free(L.cidx);
    return rc;
}
