/* tin.c: the surface of the straight-skeleton model as paper 004 §3 makes
 * it: the contours (shrunk outlines) have few corners, so each is drawn as
 * a closed B-spline with its corners as control points; the points on
 * those curves, the key outline and the summits are Delaunay-triangulated
 * (the paper wrote its own in Visual Basic; here OpenCV's Subdiv2D through
 * the shim), and the triangles give the DEM.  A B-spline runs inside its
 * control polygon, so the contours come out rounder and a little smaller
 * than the shrunk outlines: that is the paper's smoothing. */
#include "src/model/model.h"
#include "src/model/model_int.h"
#include "src/io/io.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct pts {
    double *xy, *h;
    size_t n, cap;
} pts;

static int put(pts *p, double x, double y, double h, td_ctx *cx)
{
    if (p->n == p->cap) {
        size_t nc = p->cap ? 2 * p->cap : 1024;
        double *a = realloc(p->xy, 2 * nc * sizeof *a), *b;
        if (!a)
            return td_seterr(cx, TD_ENOMEM, "tin: out of memory");
        p->xy = a;
        if (!(b = realloc(p->h, nc * sizeof *b)))
            return td_seterr(cx, TD_ENOMEM, "tin: out of memory");
        p->h = b, p->cap = nc;
    }
    p->xy[2 * p->n] = x, p->xy[2 * p->n + 1] = y, p->h[p->n++] = h;
    return 0;
}

/* Ring l (m corners) as a closed uniform cubic B-spline, every spacing. */
static int bspline(pts *p, const td_line *l, double spacing, td_ctx *cx)
{
    size_t m = l->n, i;
    int rc = 0;
    for (i = 0; i < m && rc == 0; i++) {
        const double *a = l->xy + 2 * ((i + m - 1) % m), *b = l->xy + 2 * i;
        const double *c = l->xy + 2 * ((i + 1) % m);
        const double *d = l->xy + 2 * ((i + 2) % m);
        int k, steps = (int)ceil(hypot(c[0] - b[0], c[1] - b[1]) / spacing);
        steps = steps < 1 ? 1 : steps > 10000 ? 10000 : steps;
        for (k = 0; k < steps && rc == 0; k++) {
            double u = (double)k / steps, u2 = u * u, u3 = u2 * u;
            double w0 = (1 - u) * (1 - u) * (1 - u) / 6;
            double w1 = (3 * u3 - 6 * u2 + 4) / 6;
            double w2 = (-3 * u3 + 3 * u2 + 3 * u + 1) / 6, w3 = u3 / 6;
            rc = put(p, w0 * a[0] + w1 * b[0] + w2 * c[0] + w3 * d[0],
                     w0 * a[1] + w1 * b[1] + w2 * c[1] + w3 * d[1],
                     l->height, cx);
        }
    }
    return rc;
}

int td_skeleton_tin(const double *outline, size_t n, double base,
                    const td_lines *rings, const td_lines *peaks,
                    double spacing, td_grid_f32 *dem, td_ctx *cx)
{
    pts p;
    int32_t *tri = NULL;
    size_t nt = 0, i, k;
    int rc = 0;
    memset(&p, 0, sizeof p);
    if (!(spacing > 0) || n < 3)
        return td_seterr(cx, TD_EINVAL, "tin: bad outline or spacing");
    for (i = 0; i < n && rc == 0; i++) { /* the outline, densified */
        const double *a = outline + 2 * i, *b = outline + 2 * ((i + 1) % n);
        int steps = (int)ceil(hypot(b[0] - a[0], b[1] - a[1]) / spacing);
        steps = steps < 1 ? 1 : steps > 100000 ? 100000 : steps;
        for (k = 0; k < (size_t)steps && rc == 0; k++)
            rc = put(&p, a[0] + (b[0] - a[0]) * k / steps,
                     a[1] + (b[1] - a[1]) * k / steps, base, cx);
    }
    for (i = 0; rings && i < rings->n && rc == 0; i++)
        if (rings->v[i].n >= 3)
            rc = bspline(&p, &rings->v[i], spacing, cx);
    for (i = 0; peaks && i < peaks->n && rc == 0; i++)
        if (peaks->v[i].n >= 1)
            rc = put(&p, peaks->v[i].xy[0], peaks->v[i].xy[1],
                     peaks->v[i].height, cx);
    if (rc == 0)
        rc = td_cv_delaunay(p.xy, p.n, &tri, &nt, cx);
    for (i = 0; i < nt && rc == 0; i++) {
        const int32_t *t = tri + 3 * i;
        double x[3], y[3], h[3], det;
        int row, r0, r1, c0, c1, col, j;
        for (j = 0; j < 3; j++)
            x[j] = p.xy[2 * t[j]], y[j] = p.xy[2 * t[j] + 1], h[j] = p.h[t[j]];
        det = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
        if (fabs(det) < 1e-12)
            continue;
        r0 = (int)floor(fmin(y[0], fmin(y[1], y[2])));
        r1 = (int)ceil(fmax(y[0], fmax(y[1], y[2])));
        r0 = r0 < 0 ? 0 : r0, r1 = r1 >= dem->h ? dem->h - 1 : r1;
        for (row = r0; row <= r1; row++) {
            if (!td_convex_span(x, y, 3, row, 0, dem->w - 1, &c0, &c1))
                continue;
            for (col = c0; col <= c1; col++) {
                float *z = &dem->data[(size_t)row * dem->w + col];
                double px = col + 0.5 - x[0], py = row + 0.5 - y[0];
                double l1 = (px * (y[2] - y[0]) - py * (x[2] - x[0])) / det;
                double l2 = (py * (x[1] - x[0]) - px * (y[1] - y[0])) / det;
                if (dem->has_nodata && *z == dem->nodata)
                    continue; /* outside the outline */
                *z = (float)(h[0] + l1 * (h[1] - h[0]) + l2 * (h[2] - h[0]));
            }
        }
    }
    free(tri);
    free(p.xy);
    free(p.h);
    return rc;
}
