/* Faces by probes (contract and picture in faces.h).
 *
 * The lines' segments are binned in a grid of CELL x CELL px cells (each
 * segment in every cell its bounding box touches); a ray walks the cells it
 * crosses in order (Amanatides & Woo's traversal) and stops at the first
 * cell whose nearest crossing lies inside it. */
#include "scanner/faces.h"

#include "scanner/flank.h"
#include "scanner/width.h"
#include "src/io/io.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define CELL 8 /* the finest cell; coarser when the sheet is large and empty */
#define MAX_CELLS 4000000
#define SIMPLIFY 0.6 /* px: traced staircases simplified before indexing */
#define SKEL_AXIS_R 3 /* px: the skeleton's course where a probe meets it */
#define SKEL_ALONG                                                             \
    0.71 /* ... within 45 degrees of the probe: run along, not crossed */
#define SKEL_MIN_PX 8 /* skeleton pieces of fewer pixels are specks */
#define SKEL_CLEAR                                                             \
    1.6 /* px: a probe's own line's and the line it meets's                    \
           skeleton pixels lie this close to its ends */

struct td_faces {
    const td_lines *ls;
    size_t nw;              /* walls: f->sl->v[ls->n .. ls->n + nw) */
    int w, h, gw, gh, cell; /* cell: side of a grid cell, px */
    uint32_t *start; /* gw * gh + 1 offsets into seg */
    uint32_t *seg;   /* pairs: line index, first vertex index */
    unsigned char *used;
    double *len;      /* per line: its length */
    td_lines *sl;     /* per used line: simplified (Douglas-Peucker,
                         SIMPLIFY px) for the index and the probes */
    size_t *soff;     /* per line: offset of its simplified vertices */
    uint32_t *sorig;  /* per simplified vertex: its vertex in the line */
    size_t *voff;     /* per line: offset of its vertices in vchunk */
    uint32_t *vchunk; /* per vertex: its chunk (segment k: vertex k's) */
    uint32_t *cline;  /* per chunk: its line */
    uint32_t *cfirst; /* per chunk: its first vertex */
    size_t nchunks;
    uint8_t *skel; /* packed bits, w x h: the scanner's skeleton pixels
                      no used line runs within a pixel of
                      (td_faces_set_skeleton), or NULL */
    td_faces_params p;
};

td_faces_params td_faces_defaults(void)
{
    td_faces_params p;
    p.spacing = 4.0;
    p.min_len = 12.0;
    p.chunk_len = 0.0;
    return p;
}

/* Segment k of line l (k + 1 wraps for a closed line's closing segment). */
static void seg_ends(const td_line *l, size_t k, double *a, double *b)
{
    size_t k1 = k + 1 < l->n ? k + 1 : 0;
    a[0] = l->xy[2 * k];
    a[1] = l->xy[2 * k + 1];
    b[0] = l->xy[2 * k1];
    b[1] = l->xy[2 * k1 + 1];
}

static size_t nsegs(const td_line *l)
{
    return l->n < 2 ? 0 : l->closed ? l->n : l->n - 1;
}

static int cell_of(double v, int n, int cell)
{
    long c = (long)floor(v / cell);
    return c < 0 ? 0 : c >= n ? n - 1 : (int)c;
}

/* Calls back for every (cell, line, segment) pair: pass 0 counts, pass 1
 * fills. */
static void bin_segments(td_faces *f, int pass, uint32_t *fill)
{
    size_t i, k;
    for (i = 0; i < f->ls->n + f->nw; i++) {
        const td_line *l = &f->sl->v[i];
        if (i < f->ls->n && !f->used[i])
            continue;
        for (k = 0; k < nsegs(l); k++) {
            double a[2], b[2];
            int x0, x1, y0, y1, cx, cy;
            seg_ends(l, k, a, b);
            x0 = cell_of(a[0] < b[0] ? a[0] : b[0], f->gw, f->cell);
            x1 = cell_of(a[0] < b[0] ? b[0] : a[0], f->gw, f->cell);
            y0 = cell_of(a[1] < b[1] ? a[1] : b[1], f->gh, f->cell);
            y1 = cell_of(a[1] < b[1] ? b[1] : a[1], f->gh, f->cell);
            for (cy = y0; cy <= y1; cy++)
                for (cx = x0; cx <= x1; cx++) {
                    size_t c = (size_t)cy * f->gw + cx;
                    if (pass == 0) {
                        f->start[c + 1]++;
                    } else {
                        uint32_t at = fill[c]++;
                        f->seg[2 * at] = (uint32_t)i;
                        f->seg[2 * at + 1] = (uint32_t)k;
                    }
                }
        }
    }
}

/* Douglas-Peucker keep flags for the vertices of l (first and last kept);
 * stack of size n. */
static void dp_keep(const td_line *l, unsigned char *keep, size_t *stack)
{
    size_t sp = 0;
    keep[0] = keep[l->n - 1] = 1;
    stack[sp++] = 0;
    stack[sp++] = l->n - 1;
    while (sp >= 2) {
        size_t b = stack[--sp], a = stack[--sp], k, far = a;
        double ax = l->xy[2 * a], ay = l->xy[2 * a + 1];
        double dx = l->xy[2 * b] - ax, dy = l->xy[2 * b + 1] - ay;
        double L = sqrt(dx * dx + dy * dy), best = SIMPLIFY;
        for (k = a + 1; k < b; k++) {
            double px = l->xy[2 * k] - ax, py = l->xy[2 * k + 1] - ay;
            double d =
                L > 0 ? fabs(px * dy - py * dx) / L : sqrt(px * px + py * py);
            if (d > best)
                best = d, far = k;
        }
        if (far != a) {
            keep[far] = 1;
            stack[sp++] = a, stack[sp++] = far;
            stack[sp++] = far, stack[sp++] = b;
        }
    }
}

/* The simplified lines and their vertices' places in the lines: the
 * keep flags of every used line on threads (a stack per thread), the lines
 * made from them in order. */
static int simplify_all(td_faces *f, td_ctx *cx)
{
    size_t i, k, nmax = 2, tot = 0, nv = f->voff[f->ls->n];
    unsigned char *keep;
    long li;
    int oom = 0;
    for (i = 0; i < f->ls->n; i++)
        nmax = f->ls->v[i].n > nmax ? f->ls->v[i].n : nmax;
    if (!(f->sl = td_lines_new(cx)) ||
        !(f->soff = td_calloc(f->ls->n + 1, sizeof *f->soff, cx)) ||
        !(f->sorig = td_malloc((nv + 1) * sizeof *f->sorig, cx)) ||
        !(keep = td_calloc(nv + 1, 1, cx)))
        return TD_ENOMEM;
#pragma omp parallel
    {
        size_t *stack = malloc(2 * nmax * sizeof *stack);
        if (!stack) {
#pragma omp atomic write
            oom = 1;
        }
#pragma omp for schedule(dynamic, 16)
        for (li = 0; li < (long)f->ls->n; li++)
            if (stack && f->used[li])
                dp_keep(&f->ls->v[li], keep + f->voff[li], stack);
        free(stack);
    }
    if (oom) {
        free(keep);
        return td_seterr(cx, TD_ENOMEM, "faces: out of memory");
    }
    for (i = 0; i < f->ls->n; i++) {
        const td_line *l = &f->ls->v[i];
        td_line *o = td_lines_add(f->sl, cx);
        f->soff[i] = tot;
        if (!o)
            break;
        o->closed = l->closed;
        if (!f->used[i])
            continue;
        for (k = 0; k < l->n; k++)
            if (keep[f->voff[i] + k]) {
                if (td_line_push(o, l->xy[2 * k], l->xy[2 * k + 1], cx) != 0)
                    break;
                f->sorig[tot++] = (uint32_t)k;
            }
    }
    f->soff[f->ls->n] = tot;
    free(keep);
    return i < f->ls->n ? TD_ENOMEM : 0;
}

/* Cut every used line into chunks of about p.chunk_len px of arc (one
 * chunk per line when chunk_len <= 0). */
static int make_chunks(td_faces *f, td_ctx *cx)
{
    size_t i, k, nv = 0, nc = 0;
    for (i = 0; i < f->ls->n; i++) {
        f->voff[i] = nv;
        nv += f->ls->v[i].n;
        if (f->used[i]) {
            double len = f->len[i];
            size_t m = f->p.chunk_len > 0
                           ? (size_t)floor(len / f->p.chunk_len + 0.5)
                           : 1;
            nc += m ? m : 1;
        }
    }
    f->voff[f->ls->n] = nv;
    if (nc >= UINT32_MAX / 4)
        return td_seterr(cx, TD_ENOMEM, "faces: too many chunks");
    if (!(f->vchunk = td_malloc((nv + 1) * sizeof *f->vchunk, cx)) ||
        !(f->cline = td_malloc((nc + 1) * sizeof *f->cline, cx)) ||
        !(f->cfirst = td_malloc((nc + 1) * sizeof *f->cfirst, cx)))
        return TD_ENOMEM;
    nc = 0;
    for (i = 0; i < f->ls->n; i++) {
        const td_line *l = &f->ls->v[i];
        double len, s = 0;
        size_t m, c0 = nc;
        if (!f->used[i])
            continue;
        len = f->len[i];
        m = f->p.chunk_len > 0 ? (size_t)floor(len / f->p.chunk_len + 0.5) : 1;
        m = m ? m : 1;
        for (k = 0; k < m; k++) {
            f->cline[nc + k] = (uint32_t)i;
            f->cfirst[nc + k] = UINT32_MAX;
        }
        for (k = 0; k < l->n; k++) {
            size_t c;
            if (k > 0)
                s += sqrt((l->xy[2 * k] - l->xy[2 * k - 2]) *
                              (l->xy[2 * k] - l->xy[2 * k - 2]) +
                          (l->xy[2 * k + 1] - l->xy[2 * k - 1]) *
                              (l->xy[2 * k + 1] - l->xy[2 * k - 1]));
            c = (size_t)(s / len * m);
            c = c < m ? c : m - 1;
            f->vchunk[f->voff[i] + k] = (uint32_t)(c0 + c);
            if (f->cfirst[c0 + c] == UINT32_MAX)
                f->cfirst[c0 + c] = (uint32_t)k;
        }
        for (k = 0; k < m; k++) /* a chunk no vertex fell in: empty */
            if (f->cfirst[c0 + k] == UINT32_MAX)
                f->cfirst[c0 + k] = k ? f->cfirst[c0 + k - 1] : 0;
        nc += m;
    }
    f->nchunks = nc;
    return 0;
}

/* Contract in faces.h. */
td_faces *td_faces_new(const td_lines *ls, int w, int h,
                       const td_faces_params *p, td_ctx *cx)
{
    return td_faces_new_walls(ls, NULL, w, h, p, cx);
}

/* The walls appended to f->sl after the lines, as they are. */
static int add_walls(td_faces *f, const td_lines *walls, td_ctx *cx)
{
    size_t i, k;
    for (i = 0; walls && i < walls->n; i++) {
        const td_line *l = &walls->v[i];
        td_line *o;
        if (l->n < 2)
            continue;
        if (!(o = td_lines_add(f->sl, cx)))
            return TD_ENOMEM;
        for (k = 0; k < l->n; k++)
            if (td_line_push(o, l->xy[2 * k], l->xy[2 * k + 1], cx) != 0)
                return TD_ENOMEM;
        o->closed = 0;
        f->nw++;
    }
    return 0;
}

td_faces *td_faces_new_walls(const td_lines *ls, const td_lines *walls, int w,
                             int h, const td_faces_params *p, td_ctx *cx)
{
    td_faces *f;
    uint32_t *fill = NULL;
    size_t i, nc;
    if (w < 1 || h < 1) {
        td_seterr(cx, TD_EINVAL, "faces: bad sheet size %d x %d", w, h);
        return NULL;
    }
    if (!(f = td_calloc(1, sizeof *f, cx)))
        return NULL;
    f->ls = ls;
    f->w = w;
    f->h = h;
    f->p = p ? *p : td_faces_defaults();
    /* memory follows the lines, not the sheet's claimed size: cells grow
       until there are at most max(MAX_CELLS, 16 per vertex) */
    {
        size_t nv = 0, cap;
        for (i = 0; i < ls->n; i++)
            nv += ls->v[i].n;
        cap = nv < MAX_CELLS / 16 ? MAX_CELLS : 16 * nv;
        for (f->cell = CELL;
             ((size_t)w / f->cell + 1) * ((size_t)h / f->cell + 1) > cap &&
             f->cell < (1 << 20);
             f->cell *= 2)
            ;
    }
    f->gw = (int)(((size_t)w + f->cell - 1) / f->cell);
    f->gh = (int)(((size_t)h + f->cell - 1) / f->cell);
    nc = (size_t)f->gw * f->gh;
    if (!(f->used = td_calloc(ls->n + 1, 1, cx)) ||
        !(f->len = td_calloc(ls->n + 1, sizeof *f->len, cx)) ||
        !(f->voff = td_calloc(ls->n + 1, sizeof *f->voff, cx)) ||
        !(f->start = td_calloc(nc + 1, sizeof *f->start, cx)))
        goto fail;
#pragma omp parallel for schedule(dynamic, 64)
    for (i = 0; i < ls->n; i++) {
        f->len[i] = td_line_length(&ls->v[i]);
        f->used[i] =
            ls->v[i].n >= 2 && f->len[i] >= f->p.min_len && !ls->v[i].piece;
    }
    if (make_chunks(f, cx) != 0 || simplify_all(f, cx) != 0 ||
        add_walls(f, walls, cx) != 0)
        goto fail;
    bin_segments(f, 0, NULL);
    for (i = 0; i < nc; i++) {
        if (f->start[i + 1] > UINT32_MAX / 2 - f->start[i]) {
            td_seterr(cx, TD_ENOMEM, "faces: too many segments");
            goto fail;
        }
        f->start[i + 1] += f->start[i];
    }
    if (!(f->seg =
              td_malloc(2 * (size_t)f->start[nc] * sizeof *f->seg + 8, cx)) ||
        !(fill = td_malloc(nc * sizeof *fill, cx)))
        goto fail;
    memcpy(fill, f->start, nc * sizeof *fill);
    bin_segments(f, 1, fill);
    free(fill);
    return f;
fail:
    free(fill);
    td_faces_free(f);
    return NULL;
}

void td_faces_free(td_faces *f)
{
    if (!f)
        return;
    free(f->start);
    free(f->seg);
    free(f->used);
    free(f->skel);
    free(f->len);
    td_lines_free(f->sl);
    free(f->soff);
    free(f->sorig);
    free(f->voff);
    free(f->vchunk);
    free(f->cline);
    free(f->cfirst);
    free(f);
}

int td_faces_used(const td_faces *f, size_t i)
{
    return i < f->ls->n && f->used[i];
}

double td_faces_line_length(const td_faces *f, size_t i)
{
    return i < f->ls->n ? f->len[i] : 0.0;
}

size_t td_faces_nchunks(const td_faces *f)
{
    return f->nchunks;
}

size_t td_faces_chunk_line(const td_faces *f, size_t c)
{
    return f->cline[c];
}

size_t td_faces_chunk_first(const td_faces *f, size_t c)
{
    return f->cfirst[c];
}

long td_faces_chunk_at(const td_faces *f, size_t i, size_t k)
{
    if (!td_faces_used(f, i) || k >= f->ls->v[i].n)
        return -1;
    return (long)f->vchunk[f->voff[i] + k];
}

/* The nearest crossing of the ray with the segments of cell c beyond t0:
 * updates *best (distance) and *node. */
static void test_cell(const td_faces *f, size_t c, const double *o,
                      const double *d, long skip, double skip_t, double *best,
                      long *node)
{
    uint32_t s;
    for (s = f->start[c]; s < f->start[c + 1]; s++) {
        uint32_t li = f->seg[2 * s], k = f->seg[2 * s + 1];
        double a[2], b[2], S[2], q[2], den, t, u;
        seg_ends(&f->sl->v[li], k, a, b);
        S[0] = b[0] - a[0];
        S[1] = b[1] - a[1];
        den = d[0] * S[1] - d[1] * S[0];
        if (fabs(den) < 1e-12)
            continue; /* parallel: the neighbouring segments decide */
        q[0] = a[0] - o[0];
        q[1] = a[1] - o[1];
        t = (q[0] * S[1] - q[1] * S[0]) / den;
        u = (q[0] * d[1] - q[1] * d[0]) / den;
        if (u < 0 || u > 1 || t <= 1e-9 || t >= *best)
            continue;
        if ((long)li == skip && t < skip_t)
            continue;
        *best = t;
        if (li >= f->ls->n) { /* a wall: stops the ray, no side */
            *node = -1;
            continue;
        }
        /* side 0 (left on screen) when the start is left of the segment */
        *node = 2 * (long)f->vchunk[f->voff[li] + f->sorig[f->soff[li] + k]] +
                ((S[0] * -q[1] - S[1] * -q[0]) < 0 ? 0 : 1);
    }
}

/* Contract in faces.h. */
long td_faces_ray(const td_faces *f, double x, double y, double dx, double dy,
                  long skip, double skip_t, double *t)
{
    double o[2] = {x, y}, d[2], len = sqrt(dx * dx + dy * dy), best = INFINITY;
    double tmx, tmy, tdx, tdy;
    long node = -1;
    int cx, cy, sx, sy;
    if (!(len > 0) || !(x >= 0 && x <= f->w && y >= 0 && y <= f->h))
        return -1;
    d[0] = dx / len;
    d[1] = dy / len;
    cx = cell_of(x, f->gw, f->cell);
    cy = cell_of(y, f->gh, f->cell);
    sx = d[0] > 0 ? 1 : -1;
    sy = d[1] > 0 ? 1 : -1;
    tdx = d[0] != 0 ? f->cell / fabs(d[0]) : INFINITY;
    tdy = d[1] != 0 ? f->cell / fabs(d[1]) : INFINITY;
    tmx = d[0] != 0 ? ((cx + (sx > 0)) * (double)f->cell - x) / d[0] : INFINITY;
    tmy = d[1] != 0 ? ((cy + (sy > 0)) * (double)f->cell - y) / d[1] : INFINITY;
    for (;;) {
        double texit = fmin(tmx, tmy);
        test_cell(f, (size_t)cy * f->gw + cx, o, d, skip, skip_t, &best, &node);
        if (best <= texit)
            break;
        if (tmx < tmy) {
            cx += sx;
            tmx += tdx;
        } else {
            cy += sy;
            tmy += tdy;
        }
        if (cx < 0 || cy < 0 || cx >= f->gw || cy >= f->gh)
            break;
    }
    if (node >= 0 && t)
        *t = best;
    return node;
}

/* Contract in faces.h. */
int td_faces_near(const td_faces *f, double x, double y, double r, long skip,
                  long *nodes, double *dist, int max)
{
    int x0 = cell_of(x - r, f->gw, f->cell),
        x1 = cell_of(x + r, f->gw, f->cell);
    int y0 = cell_of(y - r, f->gh, f->cell),
        y1 = cell_of(y + r, f->gh, f->cell);
    int cx, cy, n = 0, j;
    for (cy = y0; cy <= y1; cy++)
        for (cx = x0; cx <= x1; cx++) {
            size_t c = (size_t)cy * f->gw + cx;
            uint32_t s;
            for (s = f->start[c]; s < f->start[c + 1]; s++) {
                uint32_t li = f->seg[2 * s], k = f->seg[2 * s + 1];
                double a[2], b[2], S[2], q[2], L2, t, d;
                long node;
                if ((long)li == skip || li >= f->ls->n)
                    continue;
                seg_ends(&f->sl->v[li], k, a, b);
                S[0] = b[0] - a[0], S[1] = b[1] - a[1];
                q[0] = x - a[0], q[1] = y - a[1];
                L2 = S[0] * S[0] + S[1] * S[1];
                t = L2 > 0 ? (q[0] * S[0] + q[1] * S[1]) / L2 : 0;
                t = t < 0 ? 0 : t > 1 ? 1 : t;
                d = hypot(q[0] - t * S[0], q[1] - t * S[1]);
                if (!(d <= r))
                    continue;
                node =
                    2 * (long)
                            f->vchunk[f->voff[li] + f->sorig[f->soff[li] + k]] +
                    ((S[0] * q[1] - S[1] * q[0]) < 0 ? 0 : 1);
                for (j = 0; j < n; j++)
                    if (f->cline[nodes[j] / 2] == li)
                        break;
                if (j < n && d >= dist[j])
                    continue;
                if (j == n) {
                    if (n == max)
                        continue;
                    n++;
                }
                nodes[j] = node, dist[j] = d;
            }
        }
    return n;
}

/* Contract in faces.h. */
int td_faces_around(const td_faces *f, double x, double y, long nodes[16])
{
    int k, hits = 0;
    for (k = 0; k < 16; k++) {
        double a = k * (3.14159265358979323846 / 8);
        nodes[k] = td_faces_ray(f, x, y, cos(a), sin(a), -1, 0, NULL);
        hits += nodes[k] >= 0;
    }
    return hits;
}

typedef struct hit {
    uint32_t a, b;
    float x, y, hx, hy, w;
    uint32_t step; /* untraced ink crossed (td_face_edge.step) */
} hit;

/* Contract in faces.h. */
int td_faces_set_skeleton(td_faces *f, const uint8_t *bits, td_ctx *cx)
{
    size_t row = ((size_t)f->w + 7) / 8;
    td_grid_u8 *g;
    uint8_t *own;
    int x, y, rc;
    free(f->skel);
    f->skel = NULL;
    if (!bits)
        return 0;
    if (!(own = td_malloc(row * (size_t)f->h + 1, cx)))
        return TD_ENOMEM;
    memcpy(own, bits, row * (size_t)f->h);
    /* the used lines' own pixels, and their neighbours, out */
    td_packed_lines(own, f->w, f->h, f->ls, f->used, 1, 0);
    /* then the specks (pieces under SKEL_MIN_PX), on a byte a pixel */
    if (!(g = td_grid_u8_new(f->w, f->h, cx))) {
        free(own);
        return TD_ENOMEM;
    }
#pragma omp parallel for private(x) schedule(static)
    for (y = 0; y < f->h; y++)
        for (x = 0; x < f->w; x++)
            g->data[(size_t)y * g->stride + (size_t)x] =
                (uint8_t)td_packed_at(own, f->w, f->h, x, y);
    free(own);
    if ((rc = td_cv_remove_specks(g, SKEL_MIN_PX, NULL, cx)) == 0 &&
        !(f->skel = td_width_pack(g, cx)))
        rc = TD_ENOMEM;
    td_grid_u8_free(g);
    return rc;
}

/* Whether the probe from (x,y) along unit d crosses a skeleton pixel
 * between t0 and t1: the pixels the segment passes through, in order
 * (Amanatides & Woo), so a diagonal line of 8-connected pixels is never
 * slipped through. */
static int skel_crossed(const td_faces *f, double x, double y, const double *d,
                        double t0, double t1)
{
    double px = x + d[0] * t0, py = y + d[1] * t0, tmx, tmy, tdx, tdy, t = t0;
    int cx = (int)floor(px), cy = (int)floor(py);
    int sx = d[0] > 0 ? 1 : -1, sy = d[1] > 0 ? 1 : -1;
    tdx = d[0] != 0 ? 1.0 / fabs(d[0]) : INFINITY;
    tdy = d[1] != 0 ? 1.0 / fabs(d[1]) : INFINITY;
    tmx = d[0] != 0 ? t0 + ((cx + (sx > 0)) - px) / d[0] : INFINITY;
    tmy = d[1] != 0 ? t0 + ((cy + (sy > 0)) - py) / d[1] : INFINITY;
    while (t < t1) {
        double ux = 0, uy = 0;
        if (cx >= 0 && cy >= 0 && cx < f->w && cy < f->h &&
            td_packed_at(f->skel, f->w, f->h, cx, cy) &&
            (td_flank_axis(f->skel, f->w, f->h, cx + 0.5, cy + 0.5, SKEL_AXIS_R,
                           1, &ux, &uy) < 3 ||
             fabs(ux * d[0] + uy * d[1]) < SKEL_ALONG))
            return 1; /* crossed, not run along (a road's flank) */
        if (tmx < tmy) {
            t = tmx;
            cx += sx;
            tmx += tdx;
        } else {
            t = tmy;
            cy += sy;
            tmy += tdy;
        }
    }
    return 0;
}

/* By node pair, then place (so the merged order is the same for any
 * number of threads). */
static int cmp_hit(const void *pa, const void *pb)
{
    const hit *a = pa, *b = pb;
    if (a->a != b->a)
        return a->a < b->a ? -1 : 1;
    if (a->b != b->b)
        return a->b < b->b ? -1 : 1;
    if (a->step != b->step)
        return a->step < b->step ? -1 : 1;
    if (a->y != b->y)
        return a->y < b->y ? -1 : 1;
    return (a->x > b->x) - (a->x < b->x);
}

#define MAX_PROBES 256 /* per side of a line: longer lines probe sparser */

static int push_hit(hit **hv, size_t *nh, size_t *cap, uint32_t me, uint32_t m,
                    double x, double y, double hx, double hy, float w,
                    uint32_t step)
{
    if (*nh == *cap) {
        size_t nc = *cap ? 2 * *cap : 4096;
        hit *v = realloc(*hv, nc * sizeof *v);
        if (!v)
            return TD_ENOMEM;
        *hv = v;
        *cap = nc;
    }
    (*hv)[*nh].a = me < m ? me : m;
    (*hv)[*nh].b = me < m ? m : me;
    (*hv)[*nh].x = (float)x;
    (*hv)[*nh].y = (float)y;
    (*hv)[*nh].hx = (float)hx;
    (*hv)[*nh].hy = (float)hy;
    (*hv)[*nh].step = step;
    (*hv)[(*nh)++].w = w;
    return 0;
}

/* Merge the hits from `from` on in hv that share a node pair (sorted
 * first), summing their weights; *nh shrinks. */
static void merge_hits(hit *hv, size_t from, size_t *nh)
{
    size_t k, m = from;
    if (*nh - from < 2)
        return;
    qsort(hv + from, *nh - from, sizeof *hv, cmp_hit);
    for (k = from; k < *nh; k++) {
        if (m > from && hv[m - 1].a == hv[k].a && hv[m - 1].b == hv[k].b &&
            hv[m - 1].step == hv[k].step) {
            hv[m - 1].w += hv[k].w;
            continue;
        }
        hv[m++] = hv[k];
    }
    *nh = m;
}

/* Probes of line i into hits (grown as needed): every sp px along its
 * simplified shape, square to the segment they start on; the line's hits
 * are merged per node pair before the next line's. */
static int probe_line(const td_faces *f, size_t i, hit **hv, size_t *nh,
                      size_t *cap)
{
    size_t from = *nh;
    const td_line *l = &f->sl->v[i];
    double sp = fmax(f->p.spacing, f->len[i] / MAX_PROBES);
    double next = 0.5 * sp, s = 0;
    float w = (float)(sp / f->p.spacing); /* weight: px shared / spacing */
    size_t k;
    for (k = 0; k < nsegs(l); k++) {
        double a[2], b[2], tx, ty, L, n[2];
        uint32_t cme = f->vchunk[f->voff[i] + f->sorig[f->soff[i] + k]];
        seg_ends(l, k, a, b);
        tx = b[0] - a[0], ty = b[1] - a[1];
        L = sqrt(tx * tx + ty * ty);
        if (!(L > 0))
            continue;
        n[0] = ty / L, n[1] = -tx / L; /* side 0: left on the screen */
        for (; next <= s + L; next += sp) {
            double x = a[0] + (next - s) / L * tx,
                   y = a[1] + (next - s) / L * ty;
            int side;
            for (side = 0; side < 2; side++) {
                double sg = side ? -1.0 : 1.0, t = 0;
                long m = td_faces_ray(f, x, y, sg * n[0], sg * n[1], (long)i,
                                      1.5, &t);
                uint32_t me = 2 * cme + (uint32_t)side;
                double dd[2] = {sg * n[0], sg * n[1]};
                uint32_t step;
                if (m < 0 || (uint32_t)m / 2 == me / 2)
                    continue; /* the border, or this chunk again */
                step = f->skel && t > 2 * SKEL_CLEAR &&
                       skel_crossed(f, x, y, dd, SKEL_CLEAR, t - SKEL_CLEAR);
                if (push_hit(hv, nh, cap, me, (uint32_t)m, x, y, x + dd[0] * t,
                             y + dd[1] * t, w, step) != 0)
                    return TD_ENOMEM;
            }
        }
        s += L;
    }
    merge_hits(*hv, from, nh);
    return 0;
}

/* Contract in faces.h. */
int td_faces_edges(const td_faces *f, td_face_edge **out, size_t *n, td_ctx *cx)
{
    hit *hv = NULL;
    td_face_edge *e = NULL;
    size_t nh = 0, i, m = 0;
    int fail = 0;
    *out = NULL;
    *n = 0;
    /* probes on threads, each into its own list, then put together */
#pragma omp parallel reduction(| : fail)
    {
        hit *mine = NULL;
        size_t nm = 0, cm = 0;
        long j;
#pragma omp for schedule(dynamic, 16) nowait
        for (j = 0; j < (long)f->ls->n; j++)
            if (!fail && f->used[j])
                fail |= probe_line(f, (size_t)j, &mine, &nm, &cm) != 0;
#pragma omp critical
        {
            hit *t = nm ? realloc(hv, (nh + nm) * sizeof *t) : hv;
            if (nm && !t) {
                fail = 1;
            } else if (nm) {
                memcpy(t + nh, mine, nm * sizeof *t);
                hv = t;
                nh += nm;
            }
        }
        free(mine);
    }
    if (fail) {
        free(hv);
        return td_seterr(cx, TD_ENOMEM, "faces: out of memory");
    }
    if (nh > 1)
        qsort(hv, nh, sizeof *hv, cmp_hit);
    if (nh && !(e = td_malloc(nh * sizeof *e, cx))) {
        free(hv);
        return TD_ENOMEM;
    }
    for (i = 0; i < nh; i++) {
        if (m > 0 && e[m - 1].a == hv[i].a && e[m - 1].b == hv[i].b &&
            e[m - 1].step == hv[i].step) {
            e[m - 1].w += hv[i].w;
            continue;
        }
        e[m].a = hv[i].a;
        e[m].b = hv[i].b;
        e[m].w = hv[i].w;
        e[m].step = hv[i].step;
        e[m].x = hv[i].x;
        e[m].y = hv[i].y;
        e[m].hx = hv[i].hx;
        e[m++].hy = hv[i].hy;
    }
    free(hv);
    *out = e;
    *n = m;
    return 0;
}

/* Contract in faces.h. */
int td_faces_untraced_between(const td_faces *f, double x0, double y0,
                              double x1, double y1, double clear)
{
    double d[2] = {x1 - x0, y1 - y0}, L = hypot(d[0], d[1]);
    if (!f->skel || !(L > 2 * clear))
        return 0;
    d[0] /= L, d[1] /= L;
    return skel_crossed(f, x0, y0, d, clear, L - clear);
}

/* Contract in faces.h. */
int td_faces_spacing(const td_face_edge *e, size_t n, double *spacing,
                     td_ctx *cx)
{
    double *v = td_malloc((2 * n + 2) * sizeof *v, cx), tw = 0, acc = 0;
    size_t i;
    *spacing = 0;
    if (!v)
        return TD_ENOMEM;
    for (i = 0; i < n; i++) { /* (length, weight) pairs, by length */
        v[2 * i] = hypot(e[i].hx - e[i].x, e[i].hy - e[i].y);
        v[2 * i + 1] = e[i].w;
        tw += e[i].w;
    }
    qsort(v, n, 2 * sizeof *v, td_cmp_double); /* by length */
    for (i = 0; i < n && acc < tw / 2; i++)
        acc += v[2 * i + 1], *spacing = v[2 * i];
    free(v);
    return 0;
}

/* Contract in faces.h. */
int td_lines_spacing(const td_lines *ls, int w, int h, double *spacing,
                     td_ctx *cx)
{
    td_faces_params fp = td_faces_defaults();
    td_faces *f;
    td_face_edge *e = NULL;
    size_t n = 0;
    int rc;
    *spacing = 0;
    if (!(f = td_faces_new(ls, w, h, &fp, cx)))
        return cx->code ? cx->code : TD_ENOMEM;
    if ((rc = td_faces_edges(f, &e, &n, cx)) == 0)
        rc = td_faces_spacing(e, n, spacing, cx);
    free(e);
    td_faces_free(f);
    return rc;
}
