/* view.c: a DEM in perspective, as paper 001 §2.6 draws its surfaces
 * (ALGORITHMS.md B1 step 5): the grid cut into quad patches of N x N cells
 * (the paper's 3 x 3), each patch's height the mean of its four corners;
 * the patches painted from the farthest to the nearest (hidden surfaces by
 * the painter's order), each flat-shaded by point lights (here at infinity)
 * with the normal from its centre to two of its corners:
 *
 *      NW ------- NE        n = (SE - c) x (NE - c)
 *       |    c    |         shade = ambient + (1 - ambient) sum max(0, n.L)
 *      SW ------- SE
 *
 * Border patches (a corner without data): with two or more corners inside,
 * the others take the mean of those (the paper: the height of the border
 * contour, which a DEM does not know); with fewer, the patch is left out.
 * `wire` draws the patch edges over patches filled with the background,
 * so the painter's order removes the hidden lines too. */
#include "src/render/render.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static const uint8_t BACK[3] = {250, 250, 247};
static const uint8_t WIRE[3] = {40, 40, 40};

/* See render.h. */
td_view_params td_view_defaults(void)
{
    td_view_params p;
    memset(&p, 0, sizeof p);
    p.style = TD_VIEW_SHADED;
    p.drape = TD_DRAPE_HILLSHADE;
    p.azimuth = 200;
    p.elevation = 35;
    p.fov = 40;
    p.distance = 0;
    p.exaggeration = 0;
    p.cellsize = 1;
    p.patch = 3;
    p.nlights = 1;
    p.light[0][0] = 315, p.light[0][1] = 45;
    p.ambient = 0.2;
    p.zbuffer = 0;
    return p;
}

static int valid(const td_grid_f32 *g, float v)
{
    return isfinite(v) && !(g->has_nodata && v == g->nodata);
}

static void cross(const double a[3], const double b[3], double o[3])
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

static void unit(double v[3])
{
    double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (n > 0)
        v[0] /= n, v[1] /= n, v[2] /= n;
}

/* The camera at distance D from t, from azimuth az, elevation el. */
static void place(td_view_camera *cam, const double t[3], double D, double az,
                  double el, double fov, int w, int h)
{
    double up[3] = {0, 0, 1};
    int k;
    cam->c[0] = t[0] + D * sin(az) * cos(el);
    cam->c[1] = t[1] + D * cos(az) * cos(el);
    cam->c[2] = t[2] + D * sin(el);
    for (k = 0; k < 3; k++)
        cam->f[k] = t[k] - cam->c[k];
    unit(cam->f);
    cross(cam->f, up, cam->r);
    unit(cam->r);
    cross(cam->r, cam->f, cam->u);
    cam->focal = (w / 2.0) / tan(fov * M_PI / 360);
    cam->cx = w / 2.0, cam->cy = h / 2.0;
}

static int proj(const td_view_camera *cam, const double P[3], double *px,
                double *py, double *depth);

/* Move the camera in or out until the DEM's box spans 92 % of the picture
 * (its wider way), then shift the picture so the box sits in the middle. */
static void fit(td_view_camera *cam, const td_grid_f32 *dem, const double t[3],
                double D, double az, double el, double fov, int w, int h)
{
    double x0 = 0, x1 = 0, y0 = 0, y1 = 0;
    int it, k;
    for (it = 0; it < 6; it++) {
        double m = 0;
        x0 = y0 = HUGE_VAL, x1 = y1 = -HUGE_VAL;
        place(cam, t, D, az, el, fov, w, h);
        for (k = 0; k < 8; k++) {
            double P[3] = {k & 1 ? dem->w : 0, k & 2 ? -dem->h : 0,
                           k & 4 ? cam->ztop : 0}, px, py;
            if (!proj(cam, P, &px, &py, NULL))
                return;
            x0 = fmin(x0, px), x1 = fmax(x1, px);
            y0 = fmin(y0, py), y1 = fmax(y1, py);
        }
        m = fmax((x1 - x0) / w, (y1 - y0) / h) / 0.92;
        if (fabs(m - 1) < 0.01)
            break;
        D *= 0.3 + 0.7 * m; /* damped: near the camera it is not linear */
    }
    cam->cx += w / 2.0 - 0.5 * (x0 + x1);
    cam->cy += h / 2.0 - 0.5 * (y0 + y1);
}

/* See render.h. */
int td_view_camera_of(const td_grid_f32 *dem, const td_view_params *p,
                      int w, int h, td_view_camera *cam, td_ctx *cx)
{
    double lo = HUGE_VAL, hi = -HUGE_VAL, relief, ext, t[3], half, R, D;
    double az = p->azimuth * M_PI / 180, el = p->elevation * M_PI / 180;
    int x, y;
    if (w < 1 || h < 1 || !(p->fov > 0 && p->fov < 170) ||
        !(p->elevation > -90 && p->elevation < 90) || !(p->cellsize > 0) ||
        p->exaggeration < 0 || p->distance < 0)
        return td_seterr(cx, TD_EINVAL, "view: bad camera (field of view "
                         "0-170, elevation -90..90, cell size > 0)");
    for (y = 0; y < dem->h; y++)
        for (x = 0; x < dem->w; x++)
            if (valid(dem, TD_AT(dem, x, y))) {
                lo = fmin(lo, TD_AT(dem, x, y));
                hi = fmax(hi, TD_AT(dem, x, y));
            }
    if (!(lo <= hi))
        return td_seterr(cx, TD_EINVAL, "view: the DEM has no data");
    relief = hi - lo;
    ext = dem->w > dem->h ? dem->w : dem->h;
    cam->zmin = lo;
    if (p->exaggeration > 0 || !(relief > 0)) {
        cam->zscale = (p->exaggeration > 0 ? p->exaggeration : 1) / p->cellsize;
    } else { /* the true relief, kept within 15-50 % of the longest side */
        double r = relief / p->cellsize / ext;
        r = r < 0.15 ? 0.15 : r > 0.5 ? 0.5 : r;
        cam->zscale = r * ext / relief;
    }
    cam->ztop = relief * cam->zscale;
    t[0] = dem->w / 2.0, t[1] = -dem->h / 2.0, t[2] = cam->ztop / 2;
    R = 0.5 * sqrt((double)dem->w * dem->w + (double)dem->h * dem->h +
                   4 * t[2] * t[2]);
    half = atan(tan(p->fov * M_PI / 360) * (w < h ? 1.0 : (double)h / w));
    D = p->distance > 0 ? p->distance : 1.02 * R / sin(half);
    place(cam, t, D, az, el, p->fov, w, h);
    if (!(p->distance > 0)) /* auto: the box fills the picture */
        fit(cam, dem, t, D, az, el, p->fov, w, h);
    return 0;
}

/* World point -> picture; the depth along the view.  0 behind. */
static int proj(const td_view_camera *cam, const double P[3], double *px,
                double *py, double *depth)
{
    double d[3] = {P[0] - cam->c[0], P[1] - cam->c[1], P[2] - cam->c[2]};
    double zc = d[0] * cam->f[0] + d[1] * cam->f[1] + d[2] * cam->f[2];
    double xc = d[0] * cam->r[0] + d[1] * cam->r[1] + d[2] * cam->r[2];
    double yc = d[0] * cam->u[0] + d[1] * cam->u[1] + d[2] * cam->u[2];
    if (depth)
        *depth = zc;
    if (!(zc > 1e-6))
        return 0;
    *px = cam->cx + cam->focal * xc / zc;
    *py = cam->cy - cam->focal * yc / zc;
    return 1;
}

/* See render.h. */
int td_view_project(const td_view_camera *cam, double col, double row,
                    double z, double *px, double *py)
{
    double P[3] = {col, -row, (z - cam->zmin) * cam->zscale};
    return proj(cam, P, px, py, NULL);
}

/* Fill the triangle a, b, c (picture coordinates): the pixels whose
 * centres lie inside. */
static void fill_tri(td_image *im, const double *a, const double *b,
                     const double *c, const uint8_t rgb[3])
{
    const double *v[3] = {a, b, c}, *t;
    int y0, y1, y, x0, x1, x, k;
    if (v[0][1] > v[1][1]) t = v[0], v[0] = v[1], v[1] = t;
    if (v[1][1] > v[2][1]) t = v[1], v[1] = v[2], v[2] = t;
    if (v[0][1] > v[1][1]) t = v[0], v[0] = v[1], v[1] = t;
    y0 = (int)ceil(v[0][1] - 0.5), y1 = (int)floor(v[2][1] - 0.5);
    if (y0 < 0)
        y0 = 0;
    if (y1 > im->h - 1)
        y1 = im->h - 1;
    for (y = y0; y <= y1; y++) {
        double yc = y + 0.5, xa, xb;
        /* the long edge v0-v2 and the short one on this side of v1 */
        xa = v[0][0] + (v[2][0] - v[0][0]) * (v[2][1] > v[0][1]
                                                  ? (yc - v[0][1]) /
                                                        (v[2][1] - v[0][1])
                                                  : 0);
        if (yc < v[1][1])
            xb = v[0][0] + (v[1][0] - v[0][0]) *
                               (v[1][1] > v[0][1]
                                    ? (yc - v[0][1]) / (v[1][1] - v[0][1])
                                    : 0);
        else
            xb = v[1][0] + (v[2][0] - v[1][0]) *
                               (v[2][1] > v[1][1]
                                    ? (yc - v[1][1]) / (v[2][1] - v[1][1])
                                    : 0);
        if (xa > xb) {
            double s = xa;
            xa = xb, xb = s;
        }
        x0 = (int)ceil(xa - 0.5), x1 = (int)floor(xb - 0.5);
        if (x0 < 0)
            x0 = 0;
        if (x1 > im->w - 1)
            x1 = im->w - 1;
        for (x = x0; x <= x1; x++) {
            uint8_t *d = im->data + (size_t)y * im->stride + 3 * (size_t)x;
            for (k = 0; k < 3; k++)
                d[k] = rgb[k];
        }
    }
}

/* A 1-px line a-b (Bresenham over the rounded ends). */
static void line(td_image *im, const double *a, const double *b,
                 const uint8_t rgb[3])
{
    long x0 = lround(a[0] - 0.5), y0 = lround(a[1] - 0.5);
    long x1 = lround(b[0] - 0.5), y1 = lround(b[1] - 0.5);
    long dx = labs(x1 - x0), dy = -labs(y1 - y0), e = dx + dy, e2, n = 0;
    int sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1, k;
    for (;;) {
        if (x0 >= 0 && y0 >= 0 && x0 < im->w && y0 < im->h) {
            uint8_t *d = im->data + (size_t)y0 * im->stride + 3 * (size_t)x0;
            for (k = 0; k < 3; k++)
                d[k] = rgb[k];
        }
        if ((x0 == x1 && y0 == y1) || ++n > 100000)
            break;
        e2 = 2 * e;
        if (e2 >= dy)
            e += dy, x0 += sx;
        if (e2 <= dx)
            e += dx, y0 += sy;
    }
}

/* The triangle a, b, c with depths da, db, dc through the depth buffer:
 * each pixel centre inside takes rgb where it is nearer than what is
 * there (1/depth interpolated, as perspective keeps it linear). */
static void fill_tri_z(td_image *im, float *zb, const double *a,
                       const double *b, const double *c, double da,
                       double db, double dc, const uint8_t rgb[3])
{
    double area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    int x0 = (int)floor(fmin(a[0], fmin(b[0], c[0])));
    int x1 = (int)ceil(fmax(a[0], fmax(b[0], c[0])));
    int y0 = (int)floor(fmin(a[1], fmin(b[1], c[1])));
    int y1 = (int)ceil(fmax(a[1], fmax(b[1], c[1]))), x, y, k;
    if (!(fabs(area) > 1e-12))
        return;
    x0 = x0 < 0 ? 0 : x0, y0 = y0 < 0 ? 0 : y0;
    x1 = x1 > im->w - 1 ? im->w - 1 : x1, y1 = y1 > im->h - 1 ? im->h - 1 : y1;
    for (y = y0; y <= y1; y++)
        for (x = x0; x <= x1; x++) {
            double px = x + 0.5, py = y + 0.5, w0, w1, w2, d;
            float *z = zb + (size_t)y * im->w + x;
            w0 = ((b[0] - px) * (c[1] - py) - (b[1] - py) * (c[0] - px)) / area;
            w1 = ((c[0] - px) * (a[1] - py) - (c[1] - py) * (a[0] - px)) / area;
            w2 = 1 - w0 - w1;
            if (w0 < -1e-12 || w1 < -1e-12 || w2 < -1e-12)
                continue;
            d = 1.0 / (w0 / da + w1 / db + w2 / dc);
            if (!(d < *z))
                continue;
            *z = (float)d;
            for (k = 0; k < 3; k++)
                im->data[(size_t)y * im->stride + 3 * (size_t)x + k] = rgb[k];
        }
}

/* A 1-px line a-b drawn where it is not behind the depth buffer (a
 * thousandth of slack for the patch it edges). */
static void line_z(td_image *im, const float *zb, const double *a,
                   const double *b, double da, double db, const uint8_t rgb[3])
{
    double L = fmax(fabs(b[0] - a[0]), fabs(b[1] - a[1]));
    int n = (int)ceil(L), i, k;
    for (i = 0; i <= n; i++) {
        double t = n ? (double)i / n : 0;
        int x = (int)floor(a[0] + (b[0] - a[0]) * t);
        int y = (int)floor(a[1] + (b[1] - a[1]) * t);
        double d = 1.0 / ((1 - t) / da + t / db);
        if (x < 0 || y < 0 || x >= im->w || y >= im->h ||
            d > zb[(size_t)y * im->w + x] * 1.001)
            continue;
        for (k = 0; k < 3; k++)
            im->data[(size_t)y * im->stride + 3 * (size_t)x + k] = rgb[k];
    }
}

typedef struct patch {
    float depth;
    uint32_t x, y; /* its NW corner (cells) */
} patch;

static int farthest_first(const void *a, const void *b)
{
    float u = ((const patch *)a)->depth, v = ((const patch *)b)->depth;
    return (u < v) - (u > v);
}

/* The patch's four corners (world), NW, NE, SE, SW; 0 when fewer than
 * two have data. */
static int corners(const td_grid_f32 *dem, const td_view_camera *cam, int x,
                   int y, int n, double P[4][3])
{
    static const int dx[4] = {0, 1, 1, 0}, dy[4] = {0, 0, 1, 1};
    double sum = 0;
    int k, have = 0, ok[4];
    for (k = 0; k < 4; k++) {
        int cx = x + dx[k] * n, cy = y + dy[k] * n;
        float v;
        if (cx > dem->w - 1)
            cx = dem->w - 1;
        if (cy > dem->h - 1)
            cy = dem->h - 1;
        v = TD_AT(dem, cx, cy);
        P[k][0] = cx + 0.5, P[k][1] = -(cy + 0.5);
        ok[k] = valid(dem, v);
        if (ok[k]) {
            P[k][2] = (v - cam->zmin) * cam->zscale;
            sum += P[k][2], have++;
        }
    }
    if (have < 2)
        return 0;
    for (k = 0; k < 4; k++)
        if (!ok[k])
            P[k][2] = sum / have;
    return 1;
}

/* The patch's colour: drape x shade (Lambert, lights at infinity). */
static void colour(const td_grid_f32 *dem, const td_image *drape,
                   const td_view_params *p, double top, double P[4][3], int x,
                   int y, uint8_t rgb[3])
{
    double c[3], a[3], b[3], nrm[3], shade = 0, base[3] = {1, 1, 1};
    int k, l;
    for (k = 0; k < 3; k++) {
        c[k] = 0.25 * (P[0][k] + P[1][k] + P[2][k] + P[3][k]);
        a[k] = P[2][k] - c[k], b[k] = P[1][k] - c[k];
    }
    cross(a, b, nrm);
    unit(nrm);
    for (l = 0; l < p->nlights; l++) {
        double az = p->light[l][0] * M_PI / 180;
        double al = p->light[l][1] * M_PI / 180;
        double L[3] = {sin(az) * cos(al), cos(az) * cos(al), sin(al)};
        shade += fmax(0, nrm[0] * L[0] + nrm[1] * L[1] + nrm[2] * L[2]);
    }
    shade = p->ambient + (1 - p->ambient) * fmin(shade, 1);
    if (p->drape == TD_DRAPE_TINT) {
        td_render_ramp(top > 0 ? c[2] / top : 0, base);
    } else if (p->drape == TD_DRAPE_IMAGE && drape) {
        int ix = (int)((x + 0.5 * p->patch) * drape->w / dem->w);
        int iy = (int)((y + 0.5 * p->patch) * drape->h / dem->h);
        const uint8_t *s;
        ix = ix < 0 ? 0 : ix >= drape->w ? drape->w - 1 : ix;
        iy = iy < 0 ? 0 : iy >= drape->h ? drape->h - 1 : iy;
        s = drape->data + (size_t)iy * drape->stride +
            (size_t)ix * drape->channels;
        for (k = 0; k < 3; k++)
            base[k] = s[drape->channels >= 3 ? k : 0] / 255.0;
    }
    for (k = 0; k < 3; k++)
        rgb[k] = (uint8_t)lround(fmin(255, 255 * base[k] * shade));
}

/* See render.h. */
int td_view_render(const td_grid_f32 *dem, const td_image *drape,
                   const td_view_params *p, td_image *out, td_ctx *cx)
{
    td_view_camera cam;
    patch *ps;
    float *zb = NULL;
    size_t np = 0, cap, i;
    int rc, x, y, n = p->patch, k;
    if (out->channels != 3 || n < 1 || n > 1000 || p->nlights < 0 ||
        p->nlights > TD_VIEW_MAX_LIGHTS || !(p->ambient >= 0 && p->ambient <= 1))
        return td_seterr(cx, TD_EINVAL, "view: bad parameters (patch 1-1000, "
                         "0-%d lights, ambient 0-1)", TD_VIEW_MAX_LIGHTS);
    if (dem->w < 2 || dem->h < 2)
        return td_seterr(cx, TD_EINVAL, "view: a DEM of %d x %d cells; at "
                         "least 2 x 2 needed", dem->w, dem->h);
    if (p->drape == TD_DRAPE_IMAGE && !drape)
        return td_seterr(cx, TD_EINVAL, "view: no image to drape");
    if ((rc = td_view_camera_of(dem, p, out->w, out->h, &cam, cx)) != 0)
        return rc;
    cap = (size_t)((dem->w + n - 1) / n) * (size_t)((dem->h + n - 1) / n);
    if (!(ps = malloc((cap ? cap : 1) * sizeof *ps)))
        return td_seterr(cx, TD_ENOMEM, "view: out of memory (%zu patches)",
                         cap);
    for (y = 0; y + 1 < dem->h; y += n)
        for (x = 0; x + 1 < dem->w; x += n) {
            double P[4][3], c[3], px, py, d;
            if (!corners(dem, &cam, x, y, n, P))
                continue;
            for (k = 0; k < 3; k++)
                c[k] = 0.25 * (P[0][k] + P[1][k] + P[2][k] + P[3][k]);
            if (!proj(&cam, c, &px, &py, &d))
                continue;
            ps[np].depth = (float)d, ps[np].x = (uint32_t)x;
            ps[np].y = (uint32_t)y, np++;
        }
    if (p->zbuffer) {
        size_t npx = (size_t)out->w * out->h;
        if (!(zb = malloc(npx * sizeof *zb))) {
            free(ps);
            return td_seterr(cx, TD_ENOMEM, "view: out of memory");
        }
        for (i = 0; i < npx; i++)
            zb[i] = INFINITY;
    } else {
        qsort(ps, np, sizeof *ps, farthest_first); /* the paper's order */
    }
    for (y = 0; y < out->h; y++)
        for (x = 0; x < out->w; x++)
            memcpy(out->data + (size_t)y * out->stride + 3 * (size_t)x, BACK,
                   3);
    for (i = 0; i < np; i++) {
        double P[4][3], S[4][2], D[4];
        uint8_t rgb[3];
        int ok = 1;
        corners(dem, &cam, (int)ps[i].x, (int)ps[i].y, n, P);
        for (k = 0; k < 4; k++)
            ok &= proj(&cam, P[k], &S[k][0], &S[k][1], &D[k]);
        if (!ok)
            continue;
        if (p->style == TD_VIEW_WIRE)
            memcpy(rgb, BACK, 3);
        else
            colour(dem, drape, p, cam.ztop, P, (int)ps[i].x, (int)ps[i].y, rgb);
        if (zb) {
            fill_tri_z(out, zb, S[0], S[1], S[2], D[0], D[1], D[2], rgb);
            fill_tri_z(out, zb, S[0], S[2], S[3], D[0], D[2], D[3], rgb);
        } else {
            fill_tri(out, S[0], S[1], S[2], rgb);
            fill_tri(out, S[0], S[2], S[3], rgb);
        }
        for (k = 0; !zb && p->style != TD_VIEW_SHADED && k < 4; k++)
            line(out, S[k], S[(k + 1) % 4], WIRE);
    }
    for (i = 0; zb && p->style != TD_VIEW_SHADED && i < np; i++) {
        double P[4][3], S[4][2], D[4]; /* edges after all the fills */
        int ok = 1;
        corners(dem, &cam, (int)ps[i].x, (int)ps[i].y, n, P);
        for (k = 0; k < 4; k++)
            ok &= proj(&cam, P[k], &S[k][0], &S[k][1], &D[k]);
        for (k = 0; ok && k < 4; k++)
            line_z(out, zb, S[k], S[(k + 1) % 4], D[k], D[(k + 1) % 4], WIRE);
    }
    free(ps);
    free(zb);
    return 0;
}
