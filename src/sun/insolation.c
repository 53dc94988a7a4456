/* insolation.c: daily clear-sky insolation from horizon angles or from a
 * hidden-surface pass per sky viewpoint (paper 000 §3.2).
 *
 * The paper computes a day's insolation as direct light (a parallel
 * projection from the sun with hidden surfaces removed, then Lambert's
 * law) plus diffuse light from the sky hemisphere, and offers two ways to
 * know which part of the sky a cell sees:
 *   - the reference: m viewpoints on the sky hemisphere, one hidden-surface
 *     pass each, O(m n^2)  (td_insol_visibility, hidden_surface below);
 *   - Alg. 3.1: k horizon profiles per cell, O(k n^2)  (horizon.c).
 * Both end as k horizon angles per cell; the day's sum is then the same:
 *
 *   E_day = sum over steps t with the sun up (elevation e_t, azimuth A_t):
 *             dt * [ B(e_t) * max(0, n . s_t) * [e_t > h(A_t)]
 *                    + D(e_t) * V ]
 *
 * with s_t the sun vector (east, north, up), n the cell's unit normal,
 * h(A) the horizon interpolated between the two nearest directions, V the
 * radiative sky-view factor, B and D the clear-sky beam normal and diffuse
 * horizontal irradiance (td_clear_sky). */
#include "src/sun/sun.h"


#include <float.h>
#include <omp.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define DEG (M_PI / 180.0)

td_insol_params td_insol_defaults(void)
{
    td_insol_params p;
    p.latitude = 0.0;
    p.day = 172;
    p.step_minutes = 10.0;
    p.method = TD_INSOL_HORIZON;
    p.directions = 36;
    p.viewpoints = 1024;
    p.cell_size = 1.0;
    p.solar_constant = 1367.0;
    p.transmittance = 0.7;
    p.diffuse_coef = 0.3;
    p.curvature = 0;
    p.earth_radius = 6371000.0;
    return p;
}

/* ---- sun and sky ------------------------------------------------------ */

/* Cooper (1969), as in Duffie & Beckman, Solar Engineering of Thermal
 * Processes, eq. 1.6.1a:  delta = 23.45 deg * sin(360 deg (284 + n) / 365). */
double td_sun_declination(int day)
{
    return 23.45 * sin(2.0 * M_PI * (284.0 + day) / 365.0);
}

/* Hour angle w = 15 deg * (hour - 12) (Duffie & Beckman 1.6); with the
 * latitude phi and declination d the sun vector in (east, north, up) is
 *   east  = -cos d sin w
 *   north =  cos phi sin d - sin phi cos d cos w
 *   up    =  sin phi sin d + cos phi cos d cos w     (= sin elevation,
 * Duffie & Beckman eq. 1.6.5 with the zenith angle).  Morning (w < 0):
 * east > 0, the sun is in the east. */
void td_sun_vector(double lat_deg, int day, double hour, double s[3])
{
    double phi = lat_deg * DEG, d = td_sun_declination(day) * DEG;
    double w = 15.0 * (hour - 12.0) * DEG;
    s[0] = -cos(d) * sin(w);
    s[1] = cos(phi) * sin(d) - sin(phi) * cos(d) * cos(w);
    s[2] = sin(phi) * sin(d) + cos(phi) * cos(d) * cos(w);
}

/* A simple clear-sky model (Campbell & Norman, An Introduction to
 * Environmental Biophysics, 2nd ed., eqs. 11.11-11.13, sea level):
 *   I0   = S (1 + 0.033 cos(2 pi day / 365))    extraterrestrial normal
 *                                               (Duffie & Beckman 1.4.1b)
 *   mair = 1 / sin e                            plane-parallel air mass
 *   B    = I0 tau^mair                          beam, normal to the sun
 *   D    = c (1 - tau^mair) I0 sin e            diffuse on a horizontal
 *                                               surface (Liu & Jordan)
 * with S the solar constant, tau the zenith transmittance, c = 0.3. */
static double extraterrestrial(const td_insol_params *p)
{
    return p->solar_constant * (1.0 + 0.033 * cos(2.0 * M_PI * p->day / 365.0));
}

void td_clear_sky(const td_insol_params *p, double sin_el, double *beam,
                  double *diffuse)
{
    double i0, t;
    if (!(sin_el > 0.0)) {
        *beam = *diffuse = 0.0;
        return;
    }
    i0 = extraterrestrial(p);
    t = pow(p->transmittance, 1.0 / sin_el);
    *beam = i0 * t;
    *diffuse = p->diffuse_coef * (1.0 - t) * i0 * sin_el;
}

/* ---- results ----------------------------------------------------------- */

void td_insol_result_free(td_insol_result *r)
{
    int i;
    if (!r)
        return;
    td_grid_f32_free(r->total);
    td_grid_f32_free(r->direct);
    td_grid_f32_free(r->diffuse);
    td_grid_f32_free(r->skyview);
    for (i = 0; r->horizons && i < r->k; i++)
        td_grid_f32_free(r->horizons[i]);
    free(r->horizons);
    free(r);
}

static td_grid_f32 *new_like(const td_grid_f32 *dem, td_ctx *cx)
{
    td_grid_f32 *g = td_grid_f32_new(dem->w, dem->h, cx);
    if (g) {
        g->has_nodata = 1;
        g->nodata = dem->has_nodata ? dem->nodata : -9999.0f;
    }
    return g;
}

/* A result with every grid and k horizon bands allocated (zero). */
static td_insol_result *result_new(const td_grid_f32 *dem, int k, td_ctx *cx)
{
    td_insol_result *r = td_calloc(1, sizeof *r, cx);
    int i;
    if (!r)
        return NULL;
    r->k = k;
    if (!(r->horizons = td_calloc((size_t)k, sizeof *r->horizons, cx)))
        goto fail;
    if (!(r->total = new_like(dem, cx)) || !(r->direct = new_like(dem, cx)) ||
        !(r->diffuse = new_like(dem, cx)) || !(r->skyview = new_like(dem, cx)))
        goto fail;
    for (i = 0; i < k; i++)
        if (!(r->horizons[i] = new_like(dem, cx)))
            goto fail;
    return r;
fail:
    td_insol_result_free(r);
    return NULL;
}

static int is_nod(const td_grid_f32 *g, float v)
{
    return isnan(v) || (g->has_nodata && v == g->nodata);
}

/* ---- horizons and sky view ------------------------------------------- */

/* See insolation.h.  Band i is at azimuth i * 360 / k; between bands the
 * angle is interpolated linearly in azimuth. */
double td_insol_horizon_at(td_grid_f32 *const *bands, int k, size_t at,
                           double az_deg)
{
    double f = fmod(az_deg, 360.0) / 360.0 * k, t;
    int i0, i1;
    if (f < 0)
        f += k;
    i0 = (int)floor(f);
    t = f - i0;
    i0 = i0 % k;
    i1 = (i0 + 1) % k;
    return (1.0 - t) * bands[i0]->data[at] + t * bands[i1]->data[at];
}

/* Radiative sky-view factor of a horizontal surface from k horizon angles
 * h_i (Dozier & Frew 1990, eq. for a horizontal surface; e.g. Zaksek et
 * al. 2011):  V = (1/2pi) * integral over azimuth of cos^2 h  ~
 * (1/k) sum_i cos^2 h_i.  Open flat ground: V = 1. */
static void skyview_from_horizons(const td_grid_f32 *dem, td_insol_result *r)
{
    int y;
#pragma omp parallel for schedule(static)
    for (y = 0; y < dem->h; y++) {
        int x, i;
        for (x = 0; x < dem->w; x++) {
            size_t at = (size_t)y * (size_t)dem->w + (size_t)x;
            double v = 0.0;
            if (is_nod(dem, TD_AT(dem, x, y))) {
                r->skyview->data[at] = r->skyview->nodata;
                continue;
            }
            for (i = 0; i < r->k; i++) {
                double c = cos(r->horizons[i]->data[at] * DEG);
                v += c * c;
            }
            r->skyview->data[at] = (float)(v / r->k);
        }
    }
}

static int horizon_method(const td_grid_f32 *dem, const td_insol_params *p,
                          td_insol_result *r, td_ctx *cx)
{
    td_horizon_params hp = td_horizon_defaults();
    int rc;
    hp.directions = p->directions;
    hp.cell_size = p->cell_size;
    hp.curvature = p->curvature;
    hp.earth_radius = p->earth_radius;
    if ((rc = td_horizon_sweep(dem, &hp, r->horizons, cx)) != 0)
        return rc;
    skyview_from_horizons(dem, r);
    return 0;
}

/* ---- the hidden-surface reference ------------------------------------ */

/* One viewpoint's parallel projection.  With the view direction
 * d = (cos e sin A, cos e cos A, sin e) (towards the sky point), screen
 * axes u = (cos A, -sin A, 0) and v = (-sin e sin A, -sin e cos A, cos e),
 * a ground point P = (X, Y, Z) = (x cs, -y cs, z) has screen coordinates
 * (P.u / pu, P.v / pv) in pixels and depth P.d (larger = nearer the sky):
 *
 *            sky point
 *               \  d          the z-buffer keeps, per screen pixel, the
 *        screen  \            largest depth of the terrain drawn there;
 *        ---+---+-\--         a cell sees the sky point iff its own depth
 *            ridge \   P      is not below the buffer at its pixel
 *         ___/\__   \ /       (minus a tolerance for the pixel size).
 */
typedef struct zbuf {
    double *su, *sv, *dp;   /* per cell: screen x, y (pixels), depth */
    float *buf;             /* W x H depths, -FLT_MAX where empty */
    size_t cap;
    int W, H;
} zbuf;

static void zb_free(zbuf *zb)
{
    free(zb->su);
    free(zb->buf);
    memset(zb, 0, sizeof *zb);
}

static int zb_init(zbuf *zb, size_t n, td_ctx *cx)
{
    memset(zb, 0, sizeof *zb);
    if (!(zb->su = td_malloc(3 * n * sizeof(double), cx)))
        return TD_ENOMEM;
    zb->sv = zb->su + n;
    zb->dp = zb->sv + n;
    return 0;
}

/* Project every cell; choose the pixel pitch: pu = cs / 2 across, pv =
 * cs sin(e) / 2 up the screen (about half a cell along the azimuth),
 * coarser when needed to keep H <= 4 max(w, h); size the buffer. */
static int zb_project(const td_grid_f32 *dem, double cs, double az,
                      double el, zbuf *zb, td_ctx *cx)
{
    double sa = sin(az * DEG), ca = cos(az * DEG), se = sin(el * DEG);
    double ce = cos(el * DEG), u0 = DBL_MAX, u1 = -DBL_MAX, v0 = DBL_MAX;
    double v1 = -DBL_MAX, pu = 0.5 * cs, pv, lim;
    size_t i, n = (size_t)dem->w * (size_t)dem->h, cells;
    int x, y;
    for (y = 0; y < dem->h; y++)
        for (x = 0; x < dem->w; x++) {
            double X = x * cs, Y = -y * cs, Z = TD_AT(dem, x, y);
            i = (size_t)y * dem->w + x;
            if (is_nod(dem, (float)Z)) {
                zb->su[i] = NAN;
                continue;
            }
            zb->su[i] = X * ca - Y * sa;
            zb->sv[i] = -(X * sa + Y * ca) * se + Z * ce;
            zb->dp[i] = (X * sa + Y * ca) * ce + Z * se;
            u0 = fmin(u0, zb->su[i]); u1 = fmax(u1, zb->su[i]);
            v0 = fmin(v0, zb->sv[i]); v1 = fmax(v1, zb->sv[i]);
        }
    zb->W = zb->H = 0;
    if (u0 > u1)
        return 0; /* no valid cell */
    pv = 0.5 * cs * se;
    lim = (v1 - v0) / (4.0 * (dem->w > dem->h ? dem->w : dem->h));
    pv = pv < lim ? lim : pv;
    for (i = 0; i < n; i++) {
        zb->su[i] = (zb->su[i] - u0) / pu;
        zb->sv[i] = (zb->sv[i] - v0) / pv;
    }
    if (!((u1 - u0) / pu <= 1e9) || !((v1 - v0) / pv <= 1e9))
        return td_seterr(cx, TD_ETOOBIG, "hidden-surface: z-buffer too big "
                         "(heights not finite, or too far apart)");
    zb->W = (int)floor((u1 - u0) / pu) + 2;
    zb->H = (int)floor((v1 - v0) / pv) + 2;
    if (td_mul2((size_t)zb->W, (size_t)zb->H, &cells) != 0 ||
        cells > TD_MAX_PIXELS)
        return td_seterr(cx, TD_ETOOBIG, "hidden-surface: z-buffer too big");
    if (cells > zb->cap) {
        free(zb->buf);
        zb->cap = 0;
        if (!(zb->buf = td_malloc(cells * sizeof(float), cx)))
            return TD_ENOMEM;
        zb->cap = cells;
    }
    for (i = 0; i < cells; i++)
        zb->buf[i] = -FLT_MAX;
    return 0;
}

/* Draw triangle (a, b, c) (cell indices) into the z-buffer: every pixel
 * centre inside it (edges included) keeps the larger of its depth and the
 * triangle's depth there (barycentric interpolation). */
static void zb_triangle(zbuf *zb, size_t a, size_t b, size_t c)
{
    double x0 = zb->su[a], y0 = zb->sv[a], x1 = zb->su[b], y1 = zb->sv[b];
    double x2 = zb->su[c], y2 = zb->sv[c];
    double area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0);
    int i, j, ia, ib, ja, jb;
    if (isnan(x0) || isnan(x1) || isnan(x2) || fabs(area) < 1e-12)
        return;
    ia = (int)ceil(fmin(x0, fmin(x1, x2)) - 1e-9);
    ib = (int)floor(fmax(x0, fmax(x1, x2)) + 1e-9);
    ja = (int)ceil(fmin(y0, fmin(y1, y2)) - 1e-9);
    jb = (int)floor(fmax(y0, fmax(y1, y2)) + 1e-9);
    ib = ib < zb->W - 1 ? ib : zb->W - 1;
    jb = jb < zb->H - 1 ? jb : zb->H - 1;
    for (j = ja < 0 ? 0 : ja; j <= jb; j++)
        for (i = ia < 0 ? 0 : ia; i <= ib; i++) {
            double w0 = ((x1 - i) * (y2 - j) - (x2 - i) * (y1 - j)) / area;
            double w1 = ((x2 - i) * (y0 - j) - (x0 - i) * (y2 - j)) / area;
            double w2 = 1.0 - w0 - w1, d;
            float *o = zb->buf + (size_t)j * zb->W + i;
            if (w0 < -1e-9 || w1 < -1e-9 || w2 < -1e-9)
                continue;
            d = w0 * zb->dp[a] + w1 * zb->dp[b] + w2 * zb->dp[c];
            if (d > *o)
                *o = (float)d;
        }
}

/* Cell i sees the sky point when its depth is not below the buffer at its
 * nearest pixel by more than the depth its own surface can change over
 * that distance (<= 0.71 px): the steepest depth rise per pixel towards
 * any of its 8 neighbours, a pixel's worth, plus the float buffer's
 * rounding. */
static int zb_sees(const td_grid_f32 *dem, const zbuf *zb, int x, int y)
{
    size_t i = (size_t)y * dem->w + x;
    double g = 0.0, d = zb->dp[i];
    int dx, dy, px = (int)floor(zb->su[i] + 0.5), py = (int)floor(zb->sv[i] + 0.5);
    for (dy = -1; dy <= 1; dy++)
        for (dx = -1; dx <= 1; dx++) {
            size_t q;
            double s;
            if ((!dx && !dy) || x + dx < 0 || x + dx >= dem->w || y + dy < 0 ||
                y + dy >= dem->h)
                continue;
            q = (size_t)(y + dy) * dem->w + (size_t)(x + dx);
            if (isnan(zb->su[q]))
                continue;
            s = hypot(zb->su[q] - zb->su[i], zb->sv[q] - zb->sv[i]);
            s = (zb->dp[q] - d) / (s > 0.5 ? s : 0.5);
            g = s > g ? s : g;
        }
    /* the buffer is float: allow its rounding too */
    return d >= zb->buf[(size_t)py * zb->W + px] - g -
                    4.0 * FLT_EPSILON * (1.0 + fabs(d));
}

/* One viewpoint into vis using the workspace zb. */
static int zb_pass(const td_grid_f32 *dem, double cs, double az, double el,
                   zbuf *zb, td_grid_u8 *vis, td_ctx *cx)
{
    int x, y, rc;
    if ((rc = zb_project(dem, cs, az, el, zb, cx)) != 0)
        return rc;
    for (y = 0; y + 1 < dem->h; y++)
        for (x = 0; x + 1 < dem->w; x++) {
            size_t a = (size_t)y * dem->w + x, b = a + 1, c = a + dem->w;
            zb_triangle(zb, a, b, c + 1);   /*  a - b      two triangles  */
            zb_triangle(zb, a, c + 1, c);   /*  | \ |      per 2x2 cells  */
        }                                   /*  c - c+1                   */
    for (y = 0; y < dem->h; y++)
        for (x = 0; x < dem->w; x++) {
            size_t i = (size_t)y * dem->w + x;
            TD_AT(vis, x, y) = (uint8_t)(!isnan(zb->su[i]) &&
                                         zb_sees(dem, zb, x, y));
        }
    return 0;
}

/* See insolation.h. */
int td_insol_visibility(const td_grid_f32 *dem, double cell_size,
                        double az_deg, double el_deg, td_grid_u8 *vis,
                        td_ctx *cx)
{
    zbuf zb;
    int rc;
    if (!dem || !dem->data || !vis || !vis->data || vis->w != dem->w ||
        vis->h != dem->h)
        return td_seterr(cx, TD_EINVAL, "hidden-surface: missing grid or "
                         "sizes differ");
    if (!(cell_size > 0.0) || !(el_deg > 0.0 && el_deg <= 90.0) ||
        !isfinite(az_deg))
        return td_seterr(cx, TD_EINVAL, "hidden-surface: bad cell size or "
                         "direction");
    if ((rc = td_check_dims(dem->w, dem->h, "hidden-surface: DEM", cx)) != 0)
        return rc;
    if ((rc = zb_init(&zb, (size_t)dem->w * dem->h, cx)) != 0)
        return rc;
    rc = zb_pass(dem, cell_size, az_deg, el_deg, &zb, vis, cx);
    zb_free(&zb);
    return rc;
}

/* The viewpoint grid for m viewpoints: ke elevation rings of width
 * 90/ke degrees (viewpoints at the ring centres) by ka azimuths, ka ~ 4 ke
 * so that both spacings are about equal; m is rounded to ka * ke. */
static void viewpoint_grid(int m, int *ka, int *ke)
{
    *ke = (int)floor(sqrt(m / 4.0) + 0.5);
    *ke = *ke < 1 ? 1 : *ke;
    *ka = (int)floor((double)m / *ke + 0.5);
    *ka = *ka < 4 ? 4 : *ka;
}

/* All rings of azimuth band a, from the top down: a cell's horizon is
 * estimated as the top of the highest ring whose centre it does not see
 * ((j + 1) * 90 / ke; 0 when it sees every ring), the boundary between
 * its hidden and visible viewpoints.  A height field's visibility is
 * monotone in elevation, so cos^2 of that angle is exactly the radiative
 * weight of the visible rings (skyview_from_horizons). */
static int hs_azimuth(const td_grid_f32 *dem, double cs, double az, int ke,
                      zbuf *zb, td_grid_u8 *vis, td_grid_f32 *band,
                      td_ctx *cx)
{
    int j, x, y, rc;
    for (y = 0; y < dem->h; y++)
        for (x = 0; x < dem->w; x++)
            band->data[(size_t)y * band->w + x] =
                is_nod(dem, TD_AT(dem, x, y)) ? band->nodata : 0.0f;
    for (j = ke - 1; j >= 0; j--) {
        float top = (float)((j + 1) * 90.0 / ke);
        if ((rc = zb_pass(dem, cs, az, (j + 0.5) * 90.0 / ke, zb, vis,
                          cx)) != 0)
            return rc;
        for (y = 0; y < dem->h; y++)
            for (x = 0; x < dem->w; x++) {
                float *o = band->data + (size_t)y * band->w + x;
                if (!TD_AT(vis, x, y) && *o == 0.0f &&
                    !is_nod(dem, TD_AT(dem, x, y)))
                    *o = top;
            }
    }
    return 0;
}

/* The reference method: ka * ke hidden-surface passes, azimuths shared
 * out to threads (each with its own z-buffer), progress between rounds. */
static int hidden_surface(const td_grid_f32 *dem, const td_insol_params *p,
                          td_insol_result *r, td_ctx *cx)
{
    int nth = omp_get_max_threads(), t, a0, rc = 0, *trc = NULL;
    zbuf *zb = td_calloc((size_t)nth, sizeof *zb, cx);
    td_grid_u8 **vis = td_calloc((size_t)nth, sizeof *vis, cx);
    td_ctx *tcx = td_calloc((size_t)nth, sizeof *tcx, cx);
    trc = td_calloc((size_t)nth, sizeof *trc, cx);
    if (!zb || !vis || !tcx || !trc) {
        rc = TD_ENOMEM;
        goto fail;
    }
    for (t = 0; t < nth; t++) {
        td_ctx_init(&tcx[t]);
        if ((rc = zb_init(&zb[t], (size_t)dem->w * dem->h, cx)) != 0 ||
            !(vis[t] = td_grid_u8_new(dem->w, dem->h, cx))) {
            rc = rc ? rc : TD_ENOMEM;
            goto fail;
        }
    }
    for (a0 = 0; a0 < r->az_count && rc == 0; a0 += nth) {
#pragma omp parallel for num_threads(nth) schedule(static, 1)
        for (t = 0; t < nth; t++) {
            int a = a0 + t;
            if (a < r->az_count)
                trc[t] = hs_azimuth(dem, p->cell_size, 360.0 * a / r->az_count,
                                    r->el_count, &zb[t], vis[t],
                                    r->horizons[a], &tcx[t]);
        }
        for (t = 0; t < nth && rc == 0; t++)
            if ((rc = trc[t]) != 0)
                td_seterr(cx, rc, "%s", td_errmsg(&tcx[t]));
        if (rc == 0)
            rc = td_progress(cx, "hidden-surface",
                             fmin(1.0, (double)(a0 + nth) / r->az_count));
    }
    if (rc == 0)
        skyview_from_horizons(dem, r);
fail:
    for (t = 0; zb && vis && t < nth; t++) {
        zb_free(&zb[t]);
        td_grid_u8_free(vis[t]);
    }
    free(zb);
    free(vis);
    free(tcx);
    free(trc);
    return rc;
}

/* ---- the day's sum ---------------------------------------------------- */

/* One time step with the sun up. */
typedef struct sunstep {
    double s[3];        /* sun vector (east, north, up) */
    double beam, diff;  /* W/m^2: beam normal, diffuse horizontal */
    double el;          /* elevation, degrees */
    double az;          /* azimuth, degrees clockwise from north */
    int i0, i1;         /* the two horizon bands around az ... */
    double t;           /* ... and the weight of i1 (td_insol_horizon_at) */
} sunstep;

/* The day cut into N = ceil(1440 / step_minutes) equal steps of solar time,
 * each taken at its midpoint (midpoint rule); only steps with the sun up
 * are kept.  *dt_h is the step in hours.  Returns the count or -1. */
static int sun_steps(const td_insol_params *p, sunstep **out, double *dt_h,
                     td_ctx *cx)
{
    int n = (int)ceil(1440.0 / p->step_minutes - 1e-9), k, ns = 0;
    sunstep *st = td_calloc((size_t)n, sizeof *st, cx);
    if (!st)
        return -1;
    *dt_h = 24.0 / n;
    for (k = 0; k < n; k++) {
        sunstep *q = &st[ns];
        td_sun_vector(p->latitude, p->day, (k + 0.5) * *dt_h, q->s);
        if (q->s[2] <= 0.0)
            continue;
        td_clear_sky(p, q->s[2], &q->beam, &q->diff);
        q->el = asin(q->s[2] > 1.0 ? 1.0 : q->s[2]) / DEG;
        q->az = atan2(q->s[0], q->s[1]) / DEG;
        q->az += q->az < 0 ? 360.0 : 0.0;
        ns++;
    }
    *out = st;
    return ns;
}

/* dz per ground unit from cell (x, y) towards (x + dx, y + dy): the
 * central difference (z+ - z-) / (2 cs), one-sided where a neighbour is
 * off the grid or nodata, 0 when both are. */
static double slope_along(const td_grid_f32 *dem, int x, int y, int dx,
                          int dy, double cs)
{
    double z0 = TD_AT(dem, x, y), zp = NAN, zm = NAN;
    int xp = x + dx, yp = y + dy, xm = x - dx, ym = y - dy;
    if (xp >= 0 && xp < dem->w && yp >= 0 && yp < dem->h &&
        !is_nod(dem, TD_AT(dem, xp, yp)))
        zp = TD_AT(dem, xp, yp);
    if (xm >= 0 && xm < dem->w && ym >= 0 && ym < dem->h &&
        !is_nod(dem, TD_AT(dem, xm, ym)))
        zm = TD_AT(dem, xm, ym);
    if (!isnan(zp) && !isnan(zm))
        return (zp - zm) / (2.0 * cs);
    if (!isnan(zp))
        return (zp - z0) / cs;
    if (!isnan(zm))
        return (z0 - zm) / cs;
    return 0.0;
}

/* Unit normal (east, north, up) of cell (x, y).  North is towards row 0:
 *
 *             (x, y-1)           n = (-dz/dE, -dz/dN, 1) / |...|
 *   (x-1, y)  (x, y)  (x+1, y)   dz/dE from columns x-1 .. x+1,
 *             (x, y+1)           dz/dN from rows y+1 (south) .. y-1. */
static void cell_normal(const td_grid_f32 *dem, int x, int y, double cs,
                        double n[3])
{
    double ge = slope_along(dem, x, y, 1, 0, cs);
    double gn = slope_along(dem, x, y, 0, -1, cs);
    double l = sqrt(ge * ge + gn * gn + 1.0);
    n[0] = -ge / l;
    n[1] = -gn / l;
    n[2] = 1.0 / l;
}

/* Where td_insol_horizon_at finds azimuth az among k bands. */
static void band_pair(int k, double az, sunstep *st)
{
    double f = fmod(az, 360.0) / 360.0 * k;
    if (f < 0)
        f += k;
    st->i0 = (int)floor(f);
    st->t = f - st->i0;
    st->i0 %= k;
    st->i1 = (st->i0 + 1) % k;
}

/* Direct beam of row y over the day (W/m^2 summed over steps) into dir:
 * Lambert on the cell normal n (3 per cell), where the sun is above the
 * cell's horizon in its azimuth (interpolated between the two nearest
 * horizon directions, as td_insol_horizon_at).  One pass per sun step
 * over the row, so each step reads two band rows in order. */
static void row_direct(const td_insol_result *r, int y, int w,
                       const double *n, const sunstep *st, int ns,
                       double *dir)
{
    int k, x;
    for (x = 0; x < w; x++)
        dir[x] = 0.0;
    for (k = 0; k < ns; k++) {
        const float *b0 = r->horizons[st[k].i0]->data + (size_t)y * w;
        const float *b1 = r->horizons[st[k].i1]->data + (size_t)y * w;
        double t = st[k].t, el = st[k].el, beam = st[k].beam;
        double s0 = st[k].s[0], s1 = st[k].s[1], s2 = st[k].s[2];
        for (x = 0; x < w; x++) {
            double c = n[3 * x] * s0 + n[3 * x + 1] * s1 + n[3 * x + 2] * s2;
            double h = (1.0 - t) * b0[x] + t * b1[x];
            dir[x] += c > 0.0 && el > h ? beam * c : 0.0;
        }
    }
}

/* Rows y0..y1-1 of direct, diffuse and total (Wh/m^2); buf: 4 w doubles
 * of scratch per thread. */
static void integrate_rows(const td_grid_f32 *dem, double cs,
                           td_insol_result *r, const sunstep *st, int ns,
                           double dt_h, double diff_sum, int y0, int y1,
                           double *buf)
{
    int y;
#pragma omp parallel for schedule(dynamic, 4)
    for (y = y0; y < y1; y++) {
        double *n = buf + 4 * (size_t)dem->w * omp_get_thread_num();
        double *dir = n + 3 * (size_t)dem->w;
        int x;
        for (x = 0; x < dem->w; x++)
            if (is_nod(dem, TD_AT(dem, x, y)))
                n[3 * x] = n[3 * x + 1] = n[3 * x + 2] = 0.0;
            else
                cell_normal(dem, x, y, cs, n + 3 * x);
        row_direct(r, y, dem->w, n, st, ns, dir);
        for (x = 0; x < dem->w; x++) {
            size_t at = (size_t)y * dem->w + x;
            double dif = diff_sum * dt_h * r->skyview->data[at];
            if (is_nod(dem, TD_AT(dem, x, y))) {
                r->direct->data[at] = r->direct->nodata;
                r->diffuse->data[at] = r->diffuse->nodata;
                r->total->data[at] = r->total->nodata;
                continue;
            }
            r->direct->data[at] = (float)(dir[x] * dt_h);
            r->diffuse->data[at] = (float)dif;
            r->total->data[at] = (float)(dir[x] * dt_h + dif);
        }
    }
}

static int integrate(const td_grid_f32 *dem, const td_insol_params *p,
                     td_insol_result *r, td_ctx *cx)
{
    sunstep *st = NULL;
    double dt_h, diff_sum = 0.0, *buf;
    int ns = sun_steps(p, &st, &dt_h, cx), k, y, rc = 0;
    if (ns < 0)
        return TD_ENOMEM;
    buf = td_malloc(sizeof(double) * 4 * (size_t)dem->w *
                    (size_t)omp_get_max_threads(), cx);
    if (!buf) {
        free(st);
        return TD_ENOMEM;
    }
    for (k = 0; k < ns; k++) {
        diff_sum += st[k].diff;
        band_pair(r->k, st[k].az, &st[k]);
    }
    for (y = 0; y < dem->h && rc == 0; y += 64) {
        int y1 = y + 64 < dem->h ? y + 64 : dem->h;
        integrate_rows(dem, p->cell_size, r, st, ns, dt_h, diff_sum, y, y1,
                       buf);
        rc = td_progress(cx, "insolation", (double)y1 / dem->h);
    }
    free(buf);
    free(st);
    return rc;
}

static int check_params(const td_grid_f32 *dem, const td_insol_params *p,
                        td_ctx *cx)
{
    if (!dem || !dem->data || !p)
        return td_seterr(cx, TD_EINVAL, "insolation: missing DEM");
    if (!(p->latitude >= -90.0 && p->latitude <= 90.0))
        return td_seterr(cx, TD_EINVAL, "insolation: latitude %g is not in "
                         "-90..90", p->latitude);
    if (p->day < 1 || p->day > 366)
        return td_seterr(cx, TD_EINVAL, "insolation: day %d is not in "
                         "1..366", p->day);
    if (!(p->step_minutes >= 0.1 && p->step_minutes <= 720.0))
        return td_seterr(cx, TD_EINVAL, "insolation: time step must be "
                         "0.1..720 minutes");
    if (!(p->cell_size > 0.0) || !isfinite(p->cell_size))
        return td_seterr(cx, TD_EINVAL, "insolation: cell size must be > 0");
    if (p->method == TD_INSOL_HORIZON &&
        (p->directions < 1 || p->directions > 3600))
        return td_seterr(cx, TD_EINVAL, "insolation: directions must be "
                         "1..3600");
    if (p->method == TD_INSOL_HIDDEN_SURFACE &&
        (p->viewpoints < 4 || p->viewpoints > 1000000))
        return td_seterr(cx, TD_EINVAL, "insolation: viewpoints must be "
                         "4..1000000");
    if (!(p->transmittance > 0.0 && p->transmittance <= 1.0) ||
        !(p->solar_constant > 0.0) || !(p->diffuse_coef >= 0.0))
        return td_seterr(cx, TD_EINVAL, "insolation: bad clear-sky "
                         "parameters");
    if (p->curvature && p->method != TD_INSOL_HORIZON)
        return td_seterr(cx, TD_EINVAL, "insolation: Earth curvature needs "
                         "the horizon method");
    if (p->curvature && !(p->earth_radius > 0.0))
        return td_seterr(cx, TD_EINVAL, "insolation: earth radius must be "
                         "> 0");
    return td_check_dims(dem->w, dem->h, "insolation: DEM", cx);
}

/* See insolation.h. */
int td_insolation_run(const td_grid_f32 *dem, const td_insol_params *p,
                      td_insol_result **out, td_ctx *cx)
{
    td_insol_result *r = NULL;
    int rc, ka = 0, ke = 0;
    if (out)
        *out = NULL;
    if (!out)
        return td_seterr(cx, TD_EINVAL, "insolation: no result pointer");
    if ((rc = check_params(dem, p, cx)) != 0)
        return rc;
    if (p->method == TD_INSOL_HIDDEN_SURFACE)
        viewpoint_grid(p->viewpoints, &ka, &ke);
    if (!(r = result_new(dem, ka ? ka : p->directions, cx)))
        return TD_ENOMEM;
    r->az_count = ka;
    r->el_count = ke;
    rc = ka ? hidden_surface(dem, p, r, cx) : horizon_method(dem, p, r, cx);
    if (rc == 0)
        rc = integrate(dem, p, r, cx);
    if (rc != 0) {
        td_insol_result_free(r);
        return rc;
    }
    *out = r;
    return 0;
}
