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
 *   base    under every quad, the top's triangles reversed, at z = 0.
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

/* The wall under the top edge u -> v (top vertex ids; base = + off). */
static void wall(td_mesh *m, uint32_t u, uint32_t v, uint32_t off)
{
    tri(m, v, u, u + off);
    tri(m, v, u + off, v + off);
    m->nwall += 2;
}

static void emit(mbuild *b, uint32_t nvt)
{
    td_mesh *m = b->m;
    int i, j;
    for (j = 0; j < b->qy; j++)
        for (i = 0; i < b->qx; i++) {
            uint32_t A, B, C, D;
            if (!quad_in(b, i, j))
                continue;
            A = b->id[(size_t)j * b->nx + i], B = b->id[(size_t)j * b->nx + i + 1];
            D = b->id[(size_t)(j + 1) * b->nx + i];
            C = b->id[(size_t)(j + 1) * b->nx + i + 1];
            tri(m, A, D, C), tri(m, A, C, B);
            tri(m, A + nvt, C + nvt, D + nvt), tri(m, A + nvt, B + nvt, C + nvt);
            m->ntop += 2, m->nbase += 2;
            if (!quad_in(b, i - 1, j))
                wall(m, A, D, nvt);
            if (!quad_in(b, i, j + 1))
                wall(m, D, C, nvt);
            if (!quad_in(b, i + 1, j))
                wall(m, C, B, nvt);
            if (!quad_in(b, i, j - 1))
                wall(m, B, A, nvt);
        }
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
static int vertices(mbuild *b, const td_mesh_params *p, td_ctx *cx)
{
    const td_grid_f32 *g = b->dem;
    td_mesh *m = b->m;
    double lo = HUGE_VAL, hi = -HUGE_VAL, scale, base, longest;
    uint32_t n = 0, k;
    int i, j;
    for (j = 0; j < b->ny; j++)
        for (i = 0; i < b->nx; i++) {
            int used = quad_in(b, i - 1, j - 1) || quad_in(b, i, j - 1) ||
                       quad_in(b, i - 1, j) || quad_in(b, i, j);
            size_t k2 = (size_t)j * b->nx + i;
            b->id[k2] = used ? n++ : UINT32_MAX;
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
    m->nv = 2 * (size_t)n;
    if (!(m->v = malloc(3 * m->nv * sizeof *m->v)) ||
        !(m->uv = malloc(2 * m->nv * sizeof *m->uv)))
        return td_seterr(cx, TD_ENOMEM, "mesh: out of memory (%zu vertices)",
                         m->nv);
    for (j = 0; j < b->ny; j++)
        for (i = 0; i < b->nx; i++) {
            uint32_t v = b->id[(size_t)j * b->nx + i];
            float *t, *s2;
            if (v == UINT32_MAX)
                continue;
            t = m->v + 3 * (size_t)v, s2 = m->v + 3 * ((size_t)v + n);
            t[0] = s2[0] = (float)(i * b->s * p->cellsize * scale);
            t[1] = s2[1] = (float)(((b->ny - 1 - j) * b->s) * p->cellsize * scale);
            t[2] = (float)((TD_AT(g, i * b->s, j * b->s) - lo) *
                               p->exaggeration * scale + base);
            s2[2] = 0;
            for (k = 0; k < 2; k++) {
                float *uv = m->uv + 2 * ((size_t)v + k * n);
                uv[0] = (float)((i * b->s + 0.5) / g->w);
                uv[1] = (float)(1 - (j * b->s + 0.5) / g->h);
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
    ntri = 4 * nq + 2 * nedge;
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
    emit(&b, (uint32_t)(b.m->nv / 2));
    for (i = 0; i < 3 * b.m->nt; i++) /* nothing left unset */
        if (b.m->t[i] >= b.m->nv) {
            rc = td_seterr(cx, TD_EINVAL, "mesh: internal: vertex out of range");
            goto fail;
        }
    *out = b.m;
    b.m = NULL;
fail:
    td_mesh_free(b.m);
    free(b.in), free(b.id);
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
