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

typedef struct mbuild {
    const td_grid_f32 *dem;
    int s, nx, ny, qx, qy;
    uint8_t *in;
    uint32_t *id;  /* node -> top vertex, UINT32_MAX: unused */
    uint32_t *bid; /* node -> base vertex (base_node), UINT32_MAX: none */
    td_mesh *m;
} mbuild;

static int quad_in(const mbuild *b, int i, int j)
{
    return i >= 0 && j >= 0 && i < b->qx && j < b->qy &&
           b->in[(size_t)j * b->qx + i];
}

static void tri(td_mesh *m, uint32_t a, uint32_t b, uint32_t c)
{
    uint32_t *t = m->t + 3 * m->nt++;
    t[0] = a, t[1] = b, t[2] = c;
}

/* The wall under the top edge from node ku to node kv (as the top's
 * triangles run), down to their base vertices. */
static void wall(const mbuild *b, size_t ku, size_t kv)
{
    uint32_t u = b->id[ku], v = b->id[kv], ub = b->bid[ku], vb = b->bid[kv];
    tri(b->m, v, u, ub);
    tri(b->m, v, ub, vb);
    b->m->nwall += 2;
}

static void emit(mbuild *b)
{
    td_mesh *m = b->m;
    int i, j;
    for (j = 0; j < b->qy; j++)
        for (i = 0; i < b->qx; i++) {
            size_t kA = (size_t)j * b->nx + i, kB = kA + 1, kD = kA + b->nx,
                   kC = kD + 1;
            if (!quad_in(b, i, j))
                continue;
            tri(m, b->id[kA], b->id[kD], b->id[kC]);
            tri(m, b->id[kA], b->id[kC], b->id[kB]);
            m->ntop += 2;
            if (!quad_in(b, i - 1, j))
                wall(b, kA, kD);
            if (!quad_in(b, i, j + 1))
                wall(b, kD, kC);
            if (!quad_in(b, i + 1, j))
                wall(b, kC, kB);
            if (!quad_in(b, i, j - 1))
                wall(b, kB, kA);
        }
}

/* Is node i of line j (between quad rows j - 1 and j) a corner of the
 * base: the end of an open edge along the line, or where a run of quads
 * above or below starts or ends.  Both strips on a line take the same
 * nodes, so their shared edges match. */
static int base_node(const mbuild *b, int j, int i)
{
    return quad_in(b, i - 1, j - 1) != quad_in(b, i - 1, j) ||
           quad_in(b, i, j - 1) != quad_in(b, i, j) ||
           quad_in(b, i - 1, j - 1) != quad_in(b, i, j - 1) ||
           quad_in(b, i - 1, j) != quad_in(b, i, j);
}

/* A base triangle facing down (clockwise seen from above). */
static void base_tri(mbuild *b, int ax, int ay, int bx, int by, int cx,
                     int cy)
{
    td_mesh *m = b->m;
    uint32_t A = b->bid[(size_t)ay * b->nx + ax];
    uint32_t B = b->bid[(size_t)by * b->nx + bx];
    uint32_t C = b->bid[(size_t)cy * b->nx + cx];
    /* x east, y north (= -row): the signed area from above */
    long cr = (long)(bx - ax) * (long)(ay - cy) - (long)(ay - by) * (long)(cx - ax);
    if (cr > 0)
        tri(m, A, C, B);
    else
        tri(m, A, B, C);
    m->nbase++;
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

/* Vertices: the nodes of quads, top then base. */
/* Node (i, j)'s position, top (z = its height) or base (z = 0). */
static void place(const mbuild *b, const td_mesh_params *p, int i, int j,
                  double lo, double scale, double base, int top, float *v,
                  float *uv)
{
    v[0] = (float)(i * b->s * p->cellsize * scale);
    v[1] = (float)((b->ny - 1 - j) * b->s * p->cellsize * scale);
    v[2] = top ? (float)((TD_AT(b->dem, i * b->s, j * b->s) - lo) *
                             p->exaggeration * scale + base)
               : 0.0f;
    uv[0] = (float)((i * b->s + 0.5) / b->dem->w);
    uv[1] = (float)(1 - (j * b->s + 0.5) / b->dem->h);
}

/* Vertices: the nodes of quads on top, then the base's nodes. */
static int vertices(mbuild *b, const td_mesh_params *p, td_ctx *cx)
{
    const td_grid_f32 *g = b->dem;
    td_mesh *m = b->m;
    double lo = HUGE_VAL, hi = -HUGE_VAL, scale, base, longest;
    uint32_t n = 0, nb = 0;
    size_t k;
    int i, j;
    for (j = 0; j < b->ny; j++)
        for (i = 0; i < b->nx; i++) {
            int used = quad_in(b, i - 1, j - 1) || quad_in(b, i, j - 1) ||
                       quad_in(b, i - 1, j) || quad_in(b, i, j);
            k = (size_t)j * b->nx + i;
            b->id[k] = used ? n++ : UINT32_MAX;
            b->bid[k] = used && base_node(b, j, i) ? nb++ : UINT32_MAX;
            if (used) {
                float z = TD_AT(g, i * b->s, j * b->s);
                lo = fmin(lo, z), hi = fmax(hi, z);
            }
        }
    longest = fmax(b->qx, b->qy) * (double)b->s * p->cellsize;
    scale = p->print_size > 0 && longest > 0 ? p->print_size / longest : 1;
    base = p->base >= 0 ? p->base
                        : fmax(0.1 * (hi - lo) * p->exaggeration * scale,
                               1e-3 * longest * scale);
    m->volume_scale = scale;
    m->nv = (size_t)n + nb;
    if (!(m->v = malloc(3 * m->nv * sizeof *m->v)) ||
        !(m->uv = malloc(2 * m->nv * sizeof *m->uv)))
        return td_seterr(cx, TD_ENOMEM, "mesh: out of memory (%zu vertices)",
                         m->nv);
    for (j = 0; j < b->ny; j++)
        for (i = 0; i < b->nx; i++) {
            k = (size_t)j * b->nx + i;
            if (b->id[k] != UINT32_MAX)
                place(b, p, i, j, lo, scale, base, 1, m->v + 3 * (size_t)b->id[k],
                      m->uv + 2 * (size_t)b->id[k]);
            if (b->bid[k] != UINT32_MAX) {
                b->bid[k] += n; /* after the top's */
                place(b, p, i, j, lo, scale, base, 0,
                      m->v + 3 * (size_t)b->bid[k], m->uv + 2 * (size_t)b->bid[k]);
            }
        }
    return 0;
}

/* See mesh.h. */
int td_mesh_build(const td_grid_f32 *dem, const td_mesh_params *p,
                  td_mesh **out, td_ctx *cx)
{
    mbuild b;
    size_t nq, nedge, ntri, i;
    int x, y, rc = 0;
    *out = NULL;
    if (p->step < 1 || !(p->exaggeration > 0) || !(p->cellsize > 0) ||
        p->print_size < 0)
        return td_seterr(cx, TD_EINVAL, "mesh: bad parameters (step >= 1, "
                         "exaggeration and cell size > 0)");
    memset(&b, 0, sizeof b);
    b.dem = dem, b.s = p->step;
    b.nx = (dem->w - 1) / p->step + 1, b.ny = (dem->h - 1) / p->step + 1;
    b.qx = b.nx - 1, b.qy = b.ny - 1;
    if (b.qx < 1 || b.qy < 1)
        return td_seterr(cx, TD_EINVAL, "mesh: a DEM of %d x %d cells at step "
                         "%d has no quad (2 x 2 vertices needed)", dem->w,
                         dem->h, p->step);
    if (!(b.in = malloc((size_t)b.qx * b.qy)) ||
        !(b.id = malloc((size_t)b.nx * b.ny * sizeof *b.id)) ||
        !(b.bid = malloc((size_t)b.nx * b.ny * sizeof *b.bid)) ||
        !(b.m = calloc(1, sizeof *b.m))) {
        rc = td_seterr(cx, TD_ENOMEM, "mesh: out of memory");
        goto fail;
    }
    for (y = 0; y < b.qy; y++)
        for (x = 0; x < b.qx; x++) {
            int s = p->step;
            b.in[(size_t)y * b.qx + x] =
                valid(dem, TD_AT(dem, x * s, y * s)) &&
                valid(dem, TD_AT(dem, (x + 1) * s, y * s)) &&
                valid(dem, TD_AT(dem, x * s, (y + 1) * s)) &&
                valid(dem, TD_AT(dem, (x + 1) * s, (y + 1) * s));
        }
    b.m->dropped = drop_corner_contacts(b.in, b.qx, b.qy);
    count(&b, &nq, &nedge);
    if (nq == 0) {
        rc = td_seterr(cx, TD_EINVAL, "mesh: no 2 x 2 vertices with data");
        goto fail;
    }
    ntri = 2 * nq + 2 * nedge + base_strips(&b, 0);
    if (ntri > p->max_triangles) {
        int s = p->step;
        while ((double)ntri * p->step * p->step / ((double)s * s) >
               (double)p->max_triangles)
            s++;
        rc = td_seterr(cx, TD_EINVAL, "mesh: %zu triangles, more than %zu; "
                       "give --step %d or more", ntri, p->max_triangles, s);
        goto fail;
    }
    if ((rc = vertices(&b, p, cx)) != 0)
        goto fail;
    if (!(b.m->t = malloc(3 * ntri * sizeof *b.m->t))) {
        rc = td_seterr(cx, TD_ENOMEM, "mesh: out of memory (%zu triangles)",
                       ntri);
        goto fail;
    }
    emit(&b);
    base_strips(&b, 1);
    for (i = 0; i < 3 * b.m->nt; i++) /* nothing left unset */
        if (b.m->t[i] >= b.m->nv) {
            rc = td_seterr(cx, TD_EINVAL, "mesh: internal: vertex out of range");
            goto fail;
        }
    *out = b.m;
    b.m = NULL;
fail:
    td_mesh_free(b.m);
    free(b.in), free(b.id), free(b.bid);
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
