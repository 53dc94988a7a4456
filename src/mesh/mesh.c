/* mesh.c: a DEM as a closed, watertight solid (issue 17; ours).
 *
 *   nodes   a vertex every `step` cells, at the cell centres with data;
 *   top     a quad of four nodes with data: two triangles, counter-
 *           clockwise seen from above,   A ---- B     (A, D, C), (A, C, B)
 *                                        |      |
 *                                        D ---- C
 *   walls   every quad edge u -> v (as the top's triangles run) with no
 *           quad beside it: (v, u, u'), (v, u', v') down to the base
 *           vertices u', v';
 *   base    flat at z = 0: each run of quads along a row one strip,
 *           with corners only where the base's outline turns or a run
 *           above or below starts or ends (base_strips).
 *
 * So every edge belongs to exactly two triangles that run along it in
 * opposite directions, and the solid is closed and faces out, once no
 * two quads touch only at a corner (one of them is then left out). */
#include "src/mesh/mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* See mesh.h. */
td_mesh_params td_mesh_defaults(void)
{
    td_mesh_params p;
    p.step = 1;
    p.exaggeration = 1;
    p.cellsize = 1;
    p.print_size = 0;
    p.base = -1;
    p.max_triangles = 100000000;
    return p;
}

/* See mesh.h. */
void td_mesh_free(td_mesh *m)
{
    if (!m)
        return;
    free(m->v), free(m->uv), free(m->t);
    free(m);
}

static int valid(const td_grid_f32 *g, float v)
{
    return isfinite(v) && !(g->has_nodata && v == g->nodata);
}

/* Where two quads meet only at a corner, leave one out; until none. */
static size_t drop_corner_contacts(uint8_t *in, int qx, int qy)
{
    size_t dropped = 0;
    int changed = 1, i, j;
    while (changed) {
        changed = 0;
        for (j = 1; j < qy; j++)
            for (i = 1; i < qx; i++) {
                uint8_t *nw = &in[(size_t)(j - 1) * qx + i - 1];
                uint8_t *ne = nw + 1, *sw = nw + qx, *se = sw + 1;
                if (*nw && *se && !*ne && !*sw)
                    *se = 0, dropped++, changed = 1;
                else if (*ne && *sw && !*nw && !*se)
                    *sw = 0, dropped++, changed = 1;
            }
    }
    return dropped;
}

typedef struct mbuild mbuild;

/* Where the triangles go: corners as nodes (i, j) on top (t = 1) or on the
 * base (t = 0). */
typedef void (*sink_fn)(mbuild *b, int ai, int aj, int at, int bi, int bj,
                        int bt, int ci, int cj, int ct);

struct mbuild {
    const td_grid_f32 *dem;
    int s, nx, ny, qx, qy;
    uint8_t *in;
    uint8_t *bn;   /* node -> 1: a corner of the base (base_node) */
    uint32_t *id;  /* node -> top vertex, UINT32_MAX: unused */
    uint32_t *bid; /* node -> base vertex (base_node), UINT32_MAX: none */
    td_mesh *m;
    sink_fn put;
    void (*quad)(mbuild *b, int i, int j); /* a top quad at once, or NULL */
    /* the visitor's: positions, its callback, counts */
    double lo, scale, base, cell, ex;
    td_mesh_tri_fn fn;
    void *user;
    td_mesh_info *info;
};

static int quad_in(const mbuild *b, int i, int j)
{
    return i >= 0 && j >= 0 && i < b->qx && j < b->qy &&
           b->in[(size_t)j * b->qx + i];
}

/* The indexed mesh's sink: vertex numbers, appended to m->t. */
static void put_indexed(mbuild *b, int ai, int aj, int at, int bi, int bj,
                        int bt, int ci, int cj, int ct)
{
    uint32_t *t = b->m->t + 3 * b->m->nt++;
    size_t ka = (size_t)aj * b->nx + ai, kb = (size_t)bj * b->nx + bi,
           kc = (size_t)cj * b->nx + ci;
    t[0] = at ? b->id[ka] : b->bid[ka];
    t[1] = bt ? b->id[kb] : b->bid[kb];
    t[2] = ct ? b->id[kc] : b->bid[kc];
}

/* The wall under the top edge from node u to node v (as the top's
 * triangles run), down to their base vertices. */
static void wall(mbuild *b, int ui, int uj, int vi, int vj, size_t *nwall)
{
    b->put(b, vi, vj, 1, ui, uj, 1, ui, uj, 0);
    b->put(b, vi, vj, 1, ui, uj, 0, vi, vj, 0);
    *nwall += 2;
}

/* The top's quads and their walls; counts into *ntop, *nwall. */
static void emit(mbuild *b, size_t *ntop, size_t *nwall)
{
    int i, j;
    for (j = 0; j < b->qy; j++)
        for (i = 0; i < b->qx; i++) {
            if (!quad_in(b, i, j))
                continue;
            /* A (i, j), B (i+1, j), C (i+1, j+1), D (i, j+1) */
            if (b->quad) {
                b->quad(b, i, j);
            } else {
                b->put(b, i, j, 1, i, j + 1, 1, i + 1, j + 1, 1);
                b->put(b, i, j, 1, i + 1, j + 1, 1, i + 1, j, 1);
            }
            *ntop += 2;
            if (!quad_in(b, i - 1, j))
                wall(b, i, j, i, j + 1, nwall);
            if (!quad_in(b, i, j + 1))
                wall(b, i, j + 1, i + 1, j + 1, nwall);
            if (!quad_in(b, i + 1, j))
                wall(b, i + 1, j + 1, i + 1, j, nwall);
            if (!quad_in(b, i, j - 1))
                wall(b, i + 1, j, i, j, nwall);
        }
}

/* Is node i of line j (between quad rows j - 1 and j) a corner of the
 * base: the end of an open edge along the line, or where a run of quads
 * above or below starts or ends.  Both strips on a line take the same
 * nodes, so their shared edges match. */
static int base_node_of(const mbuild *b, int j, int i)
{
    int nw = quad_in(b, i - 1, j - 1), ne = quad_in(b, i, j - 1),
        sw = quad_in(b, i - 1, j), se = quad_in(b, i, j);
    return nw != sw || ne != se || nw != ne;
}

static int base_node(const mbuild *b, int j, int i)
{
    return b->bn[(size_t)j * b->nx + i];
}

/* A base triangle facing down (clockwise seen from above). */
static void base_tri(mbuild *b, int ax, int ay, int bx, int by, int cx,
                     int cy)
{
    /* x east, y north (= -row): the signed area from above */
    long cr = (long)(bx - ax) * (long)(ay - cy) - (long)(ay - by) * (long)(cx - ax);
    if (cr > 0)
        b->put(b, ax, ay, 0, cx, cy, 0, bx, by, 0);
    else
        b->put(b, ax, ay, 0, bx, by, 0, cx, cy, 0);
}

/* The base, row by row: each run of quads a strip between its two lines,
 * with only the base nodes (base_node) on them, zipped into triangles
 * (each with two corners on one line and one on the other).  A DEM
 * without holes needs about 2 (width + height) triangles.  out: when
 * NULL only counted. */
static size_t base_strips(mbuild *b, int emit_them)
{
    size_t n = 0;
    int j, i0, i1;
    for (j = 0; j < b->qy; j++)
        for (i0 = 0; i0 < b->qx; i0 = i1 + 1) {
            int p, q, pn, qn;
            if (!quad_in(b, i0, j)) {
                i1 = i0;
                continue;
            }
            for (i1 = i0; i1 + 1 < b->qx && quad_in(b, i1 + 1, j); i1++)
                ;
            /* zip line j (top, p) and line j + 1 (bottom, q) */
            for (p = q = i0; p <= i1 || q <= i1;) {
                for (pn = p + 1; pn <= i1 && !base_node(b, j, pn); pn++)
                    ;
                for (qn = q + 1; qn <= i1 && !base_node(b, j + 1, qn); qn++)
                    ;
                if (q > i1 || (p <= i1 && pn <= qn)) {
                    if (emit_them)
                        base_tri(b, p, j, pn, j, q, j + 1);
                    p = pn;
                } else {
                    if (emit_them)
                        base_tri(b, p, j, qn, j + 1, q, j + 1);
                    q = qn;
                }
                n++;
            }
        }
    return n;
}

/* Count the quads and their open edges. */
static void count(const mbuild *b, size_t *nq, size_t *nedge)
{
    int i, j;
    *nq = *nedge = 0;
    for (j = 0; j < b->qy; j++)
        for (i = 0; i < b->qx; i++)
            if (quad_in(b, i, j)) {
                (*nq)++;
                *nedge += !quad_in(b, i - 1, j) + !quad_in(b, i + 1, j) +
                          !quad_in(b, i, j - 1) + !quad_in(b, i, j + 1);
            }
}

static int node_used(const mbuild *b, int i, int j)
{
    return quad_in(b, i - 1, j - 1) || quad_in(b, i, j - 1) ||
           quad_in(b, i - 1, j) || quad_in(b, i, j);
}

/* The output's frame: the lowest used node's height (lo), the scale
 * (print size) and the base's thickness; *hi the highest. */
static void frame(mbuild *b, const td_mesh_params *p, double *hi)
{
    double lo = HUGE_VAL, longest;
    int i, j;
    *hi = -HUGE_VAL;
    for (j = 0; j < b->ny; j++)
        for (i = 0; i < b->nx; i++)
            if (node_used(b, i, j)) {
                float z = TD_AT(b->dem, i * b->s, j * b->s);
                lo = fmin(lo, z), *hi = fmax(*hi, z);
            }
    longest = fmax(b->qx, b->qy) * (double)b->s * p->cellsize;
    b->scale = p->print_size > 0 && longest > 0 ? p->print_size / longest : 1;
    b->base = p->base >= 0 ? p->base
                           : fmax(0.1 * (*hi - lo) * p->exaggeration * b->scale,
                                  1e-3 * longest * b->scale);
    b->lo = lo;
    b->cell = p->cellsize;
    b->ex = p->exaggeration;
}

/* Node (i, j)'s position, top (z = its height) or base (z = 0). */
static void place(const mbuild *b, int i, int j, int top, float *v)
{
    v[0] = (float)(i * b->s * b->cell * b->scale);
    v[1] = (float)((b->ny - 1 - j) * b->s * b->cell * b->scale);
    v[2] = top ? (float)((TD_AT(b->dem, i * b->s, j * b->s) - b->lo) * b->ex *
                             b->scale + b->base)
               : 0.0f;
}

/* Vertices: the nodes of quads on top, then the base's nodes. */
static int vertices(mbuild *b, td_ctx *cx)
{
    td_mesh *m = b->m;
    uint32_t n = 0, nb = 0;
    size_t k;
    int i, j;
    for (j = 0; j < b->ny; j++)
        for (i = 0; i < b->nx; i++) {
            int used = node_used(b, i, j);
            k = (size_t)j * b->nx + i;
            b->id[k] = used ? n++ : UINT32_MAX;
            b->bid[k] = used && base_node(b, j, i) ? nb++ : UINT32_MAX;
        }
    m->nv = (size_t)n + nb;
    if (!(m->v = malloc(3 * m->nv * sizeof *m->v)) ||
        !(m->uv = malloc(2 * m->nv * sizeof *m->uv)))
        return td_seterr(cx, TD_ENOMEM, "mesh: out of memory (%zu vertices)",
                         m->nv);
    for (j = 0; j < b->ny; j++)
        for (i = 0; i < b->nx; i++) {
            float uv[2];
            k = (size_t)j * b->nx + i;
            uv[0] = (float)((i * b->s + 0.5) / b->dem->w);
            uv[1] = (float)(1 - (j * b->s + 0.5) / b->dem->h);
            if (b->id[k] != UINT32_MAX) {
                place(b, i, j, 1, m->v + 3 * (size_t)b->id[k]);
                memcpy(m->uv + 2 * (size_t)b->id[k], uv, sizeof uv);
            }
            if (b->bid[k] != UINT32_MAX) {
                b->bid[k] += n; /* after the top's */
                place(b, i, j, 0, m->v + 3 * (size_t)b->bid[k]);
                memcpy(m->uv + 2 * (size_t)b->bid[k], uv, sizeof uv);
            }
        }
    return 0;
}

/* The quads with data (corner-only contacts dropped), the triangle count
 * and the checks; b->in allocated (the caller frees it). */
static int prepare(mbuild *b, const td_grid_f32 *dem, const td_mesh_params *p,
                   size_t *ntri, size_t *dropped, td_ctx *cx)
{
    size_t nq, nedge;
    int x, y;
    if (p->step < 1 || !(p->exaggeration > 0) || !(p->cellsize > 0) ||
        p->print_size < 0)
        return td_seterr(cx, TD_EINVAL, "mesh: bad parameters (step >= 1, "
                         "exaggeration and cell size > 0)");
    b->dem = dem, b->s = p->step;
    b->nx = (dem->w - 1) / p->step + 1, b->ny = (dem->h - 1) / p->step + 1;
    b->qx = b->nx - 1, b->qy = b->ny - 1;
    if (b->qx < 1 || b->qy < 1)
        return td_seterr(cx, TD_EINVAL, "mesh: a DEM of %d x %d cells at step "
                         "%d has no quad (2 x 2 vertices needed)", dem->w,
                         dem->h, p->step);
    if (!(b->in = malloc((size_t)b->qx * b->qy)))
        return td_seterr(cx, TD_ENOMEM, "mesh: out of memory");
    for (y = 0; y < b->qy; y++)
        for (x = 0; x < b->qx; x++) {
            int s = p->step;
            b->in[(size_t)y * b->qx + x] =
                valid(dem, TD_AT(dem, x * s, y * s)) &&
                valid(dem, TD_AT(dem, (x + 1) * s, y * s)) &&
                valid(dem, TD_AT(dem, x * s, (y + 1) * s)) &&
                valid(dem, TD_AT(dem, (x + 1) * s, (y + 1) * s));
        }
    *dropped = drop_corner_contacts(b->in, b->qx, b->qy);
    if (!(b->bn = malloc((size_t)b->nx * b->ny)))
        return td_seterr(cx, TD_ENOMEM, "mesh: out of memory");
    for (y = 0; y < b->ny; y++)
        for (x = 0; x < b->nx; x++)
            b->bn[(size_t)y * b->nx + x] = (uint8_t)base_node_of(b, y, x);
    count(b, &nq, &nedge);
    if (nq == 0)
        return td_seterr(cx, TD_EINVAL, "mesh: no 2 x 2 vertices with data");
    *ntri = 2 * nq + 2 * nedge + base_strips(b, 0);
    if (*ntri > p->max_triangles) {
        int s = p->step;
        while ((double)*ntri * p->step * p->step / ((double)s * s) >
               (double)p->max_triangles)
            s++;
        return td_seterr(cx, TD_EINVAL, "mesh: %zu triangles, more than %zu; "
                         "give --step %d or more", *ntri, p->max_triangles, s);
    }
    return 0;
}

/* See mesh.h. */
int td_mesh_build(const td_grid_f32 *dem, const td_mesh_params *p,
                  td_mesh **out, td_ctx *cx)
{
    mbuild b;
    size_t ntri, i, dropped = 0;
    double hi;
    int rc;
    *out = NULL;
    memset(&b, 0, sizeof b);
    if ((rc = prepare(&b, dem, p, &ntri, &dropped, cx)) != 0)
        goto fail;
    if (!(b.id = malloc((size_t)b.nx * b.ny * sizeof *b.id)) ||
        !(b.bid = malloc((size_t)b.nx * b.ny * sizeof *b.bid)) ||
        !(b.m = calloc(1, sizeof *b.m))) {
        rc = td_seterr(cx, TD_ENOMEM, "mesh: out of memory");
        goto fail;
    }
    b.m->dropped = dropped;
    frame(&b, p, &hi);
    b.m->volume_scale = b.scale;
    if ((rc = vertices(&b, cx)) != 0)
        goto fail;
    if (!(b.m->t = malloc(3 * ntri * sizeof *b.m->t))) {
        rc = td_seterr(cx, TD_ENOMEM, "mesh: out of memory (%zu triangles)",
                       ntri);
        goto fail;
    }
    b.put = put_indexed;
    emit(&b, &b.m->ntop, &b.m->nwall);
    b.m->nbase = base_strips(&b, 1);
    for (i = 0; i < 3 * b.m->nt; i++) /* nothing left unset */
        if (b.m->t[i] >= b.m->nv) {
            rc = td_seterr(cx, TD_EINVAL, "mesh: internal: vertex out of range");
            goto fail;
        }
    *out = b.m;
    b.m = NULL;
fail:
    td_mesh_free(b.m);
    free(b.in), free(b.bn), free(b.id), free(b.bid);
    return rc;
}

/* The visitor's sink: positions to the caller's function. */
static void put_visit(mbuild *b, int ai, int aj, int at, int bi, int bj,
                      int bt, int ci, int cj, int ct)
{
    float a[3], v[3], c[3];
    place(b, ai, aj, at, a);
    place(b, bi, bj, bt, v);
    place(b, ci, cj, ct, c);
    b->fn(b->user, a, v, c);
}

/* The visitor's top quad: four corners placed once, (A, D, C), (A, C, B). */
static void quad_visit(mbuild *b, int i, int j)
{
    float A[3], B[3], C[3], D[3];
    place(b, i, j, 1, A);
    place(b, i + 1, j, 1, B);
    place(b, i + 1, j + 1, 1, C);
    place(b, i, j + 1, 1, D);
    b->fn(b->user, A, D, C);
    b->fn(b->user, A, C, B);
}

/* See mesh.h. */
int td_mesh_visit(const td_grid_f32 *dem, const td_mesh_params *p,
                  td_mesh_info *info, td_mesh_tri_fn fn, void *user,
                  td_ctx *cx)
{
    mbuild b;
    size_t ntri, dropped = 0;
    double hi;
    int rc, i, j;
    memset(&b, 0, sizeof b);
    memset(info, 0, sizeof *info);
    if ((rc = prepare(&b, dem, p, &ntri, &dropped, cx)) != 0)
        goto fail;
    frame(&b, p, &hi);
    info->nt = ntri;
    info->dropped = dropped;
    info->volume_scale = b.scale;
    {
        int i0 = b.nx, i1 = -1, j0 = b.ny, j1 = -1;
        for (j = 0; j < b.ny; j++) /* distinct vertices, as td_mesh_build */
            for (i = 0; i < b.nx; i++)
                if (node_used(&b, i, j)) {
                    info->nv += 1 + (size_t)base_node(&b, j, i);
                    i0 = i < i0 ? i : i0, i1 = i > i1 ? i : i1;
                    j0 = j < j0 ? j : j0, j1 = j > j1 ? j : j1;
                }
        info->lo[0] = i0 * b.s * b.cell * b.scale;
        info->hi[0] = i1 * b.s * b.cell * b.scale;
        info->lo[1] = (b.ny - 1 - j1) * b.s * b.cell * b.scale;
        info->hi[1] = (b.ny - 1 - j0) * b.s * b.cell * b.scale;
        info->lo[2] = 0;
        info->hi[2] = (hi - b.lo) * b.ex * b.scale + b.base;
    }
    if (fn) {
        b.put = put_visit, b.quad = quad_visit, b.fn = fn, b.user = user;
        emit(&b, &info->ntop, &info->nwall);
        info->nbase = base_strips(&b, 1);
    }
fail:
    free(b.in), free(b.bn);
    return rc;
}

/* See mesh.h. */
double td_mesh_volume(const td_mesh *m)
{
    double v = 0;
    size_t i;
    for (i = 0; i < m->nt; i++) {
        const float *a = m->v + 3 * (size_t)m->t[3 * i];
        const float *b = m->v + 3 * (size_t)m->t[3 * i + 1];
        const float *c = m->v + 3 * (size_t)m->t[3 * i + 2];
        v += (double)a[0] * ((double)b[1] * c[2] - (double)b[2] * c[1]) -
             (double)a[1] * ((double)b[0] * c[2] - (double)b[2] * c[0]) +
             (double)a[2] * ((double)b[0] * c[1] - (double)b[1] * c[0]);
    }
    return v / 6;
}
