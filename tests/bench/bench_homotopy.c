/* bench_homotopy: the homotopy interpolation (interp/homotopy.h) against
 * the scanline and multidir methods on surfaces with a known truth, from
 * the TRUE contour lines (numbers for docs/homotopy.md):
 *  - the generator's valley network (TD_GEN_VALLEYS: a main valley and
 *    four tributaries cut V-shaped into a tilted plane) at 1000 x 1000:
 *    RMSE, the error along the true valley floors, seconds;
 *  - the generator's HILLS sheet at 1000 x 1000 (rings, saddles);
 *  - the valley network at --big N (default 5000): runtime against the
 *    scanline method (a few hundred contours).
 * "homotopy+md" is the homotopy with the multidir method as its fallback
 * (--fallback multidir).
 * Pictures into --dir: hillshade of each DEM with contours, ridge (red),
 * valley (blue) and inflection (green) lines over the homotopy DEM, and
 * the contours coloured by the sign of their curvature.
 *  - --sweep: the epsilon threshold from 0 to 60 degrees on both small
 *    cases (RMSE, valley-floor RMSE, ridge/valley points).
 * Options: --dir DIR --big N --sweep (--topodig is accepted and ignored). */
#define _POSIX_C_SOURCE 200809L
#include "interp/homotopy.h"
#include "interp/interp.h"
#include "samples/gen/gen.h"
#include "src/compare/compare.h"
#include "src/core/core.h"
#include "src/io/io.h"
#include "src/render/render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

/* CPU seconds of the process (all threads): robust against other jobs on
 * a shared machine, where wall time is not. */
static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* The valley network: the generator's VALLEYS terrain (gen.h). */
static td_grid_f32 *network_grid(int S)
{
    td_gen_params gp = td_gen_defaults();
    td_grid_f32 *g = NULL;
    gp.w = gp.h = S;
    gp.terrain = TD_GEN_VALLEYS;
    td_gen_terrain(&gp, &g, NULL);
    return g;
}

/* RMSE of d against t along the true valley floors (every px, 3% of the
 * sheet from its border left out). */
static double floor_rmse(const td_grid_f32 *d, const td_grid_f32 *t)
{
    td_gen_params gp = td_gen_defaults();
    double e = 0, S = t->w, seg[8][4];
    size_t n = 0, i, ns;
    int k;
    gp.w = t->w, gp.h = t->h;
    ns = td_gen_valley_segments(&gp, seg, 8);
    for (i = 0; i < ns; i++) {
        const double *s = seg[i];
        int m = (int)hypot(s[2] - s[0], s[3] - s[1]);
        for (k = 0; k <= m; k++) {
            double x = s[0] + (s[2] - s[0]) * k / m;
            double y = s[1] + (s[3] - s[1]) * k / m;
            int c = (int)x, r = (int)y;
            float v;
            if (x < 0.03 * S || y < 0.03 * S || x > 0.97 * S || y > 0.97 * S)
                continue;
            v = TD_AT(d, c, r);
            if (v == d->nodata)
                continue;
            e += pow(v - TD_AT(t, c, r), 2);
            n++;
        }
    }
    return n ? sqrt(e / n) : NAN;
}

static void picture(const char *dir, const char *name, const td_grid_f32 *d,
                    double iv, const td_rv_path *p, size_t np)
{
    td_render_params rp = td_render_defaults();
    td_image *im = NULL;
    char path[1024];
    size_t i, k;
    rp.interval = iv;
    if (!dir || td_render_hillshade(d, &rp, &im, NULL) != 0)
        return;
    for (i = 0; i < np; i++) {
        static const uint8_t col[3][3] = {{220, 30, 30}, {30, 60, 230},
                                          {40, 170, 60}};
        td_line l;
        memset(&l, 0, sizeof l);
        l.n = p[i].n;
        if (!(l.xy = malloc(2 * l.n * sizeof *l.xy)))
            continue;
        for (k = 0; k < l.n; k++)
            l.xy[2 * k] = p[i].xyz[3 * k], l.xy[2 * k + 1] = p[i].xyz[3 * k + 1];
        td_draw_line(im, &l, col[p[i].kind]);
        free(l.xy);
    }
    snprintf(path, sizeof path, "%s/%s.png", dir, name);
    if (td_png_write(path, im, NULL) == 0)
        printf("   picture %s\n", path);
    td_image_free(im);
}

/* The contours coloured by the sign of kappa: red convex, blue concave. */
static void curvature_picture(const char *dir, const td_ridges *r, int w,
                              int h)
{
    td_image *im = td_image_new(w, h, 3, NULL);
    char path[1024];
    size_t i, k;
    if (!dir || !im)
        return;
    memset(im->data, 255, im->stride * h);
    for (i = 0; i < r->ncurve; i++) {
        const td_rv_curve *c = &r->curve[i];
        for (k = 0; c->orient && k + 1 < c->n + (size_t)c->closed; k++) {
            double xy[4] = {c->x[k], c->y[k], c->x[(k + 1) % c->n],
                            c->y[(k + 1) % c->n]};
            uint8_t red[3] = {210, 40, 40}, blue[3] = {40, 70, 220};
            td_line l;
            memset(&l, 0, sizeof l);
            l.xy = xy, l.n = 2;
            td_draw_line(im, &l, c->kappa[k] >= 0 ? red : blue);
        }
    }
    snprintf(path, sizeof path, "%s/homotopy_curvature.png", dir);
    if (td_png_write(path, im, NULL) == 0)
        printf("   picture %s\n", path);
    td_image_free(im);
}

static double g_epsilon = -1; /* bench option: homotopy epsilon */

/* One method: DEM, seconds, RMSE, valley-floor RMSE (network only). */
static td_grid_f32 *run(const td_lines *ls, const td_grid_f32 *t, int m,
                        int network_case, td_homotopy_stats *hs,
                        const char *label)
{
    td_interp_params p = td_interp_defaults();
    td_grid_f32 *d = NULL;
    td_compare_stats cs;
    double t0 = td_now(), c0 = cpu_now(), secs, cpu;
    p.method = m == 3 ? TD_INTERP_HOMOTOPY : (td_interp_method)m;
    p.homotopy.fallback = m == 3 ? TD_HM_FALLBACK_MULTIDIR : TD_HM_FALLBACK_SCANLINE;
    p.hstats = hs;
    if (g_epsilon >= 0)
        p.homotopy.epsilon = g_epsilon;
    if (td_interp_lines(ls, t->w, t->h, &p, &d, NULL) != 0) {
        printf("   %-10s failed\n", label);
        return NULL;
    }
    secs = td_now() - t0;
    cpu = cpu_now() - c0;
    td_compare_grids(d, t, &cs, NULL);
    printf("   %-16s rmse %7.3f  mae %7.3f  max %7.2f  coverage %.4f", label,
           cs.rmse, cs.mae, cs.max_abs, cs.coverage);
    if (network_case)
        printf("  valley floor rmse %7.3f", floor_rmse(d, t));
    printf("  %6.2f s (cpu %.2f s)\n", secs, cpu);
    return d;
}

static void one_case(const char *name, td_grid_f32 *t, double iv,
                     int network_case, const char *dir, int pictures)
{
    static const char *const names[4] = {"scanline", "multidir", "homotopy",
                                         "homotopy+md"};
    td_lines *ls = NULL;
    td_homotopy_stats hs;
    int m;
    memset(&hs, 0, sizeof hs);
    if (td_gen_contours(t, 0, iv, &ls, NULL) != 0)
        return;
    printf("%s: %d x %d, interval %g m, %zu contours\n", name, t->w, t->h,
           iv, ls->n);
    for (m = 0; m < 4; m++) {
        td_grid_f32 *d = run(ls, t, m, network_case, m == 2 ? &hs : NULL,
                             names[m]);
        if (d && pictures && m < 3) {
            char pn[128];
            td_ridges *r = NULL;
            td_rv_path *p = NULL;
            size_t np = 0;
            td_homotopy_params hp = td_homotopy_defaults();
            if (m == 2 && td_ridges_find(ls, t->w, t->h, &hp, &r, NULL) == 0 &&
                td_ridges_paths(r, &p, &np, NULL) == 0 && network_case)
                curvature_picture(dir, r, t->w, t->h);
            snprintf(pn, sizeof pn, "homotopy_%s_%s", name, names[m]);
            picture(dir, pn, d, iv, p, np);
            td_rv_paths_free(p, np);
            td_ridges_free(r);
        }
        td_grid_f32_free(d);
    }
    printf("   homotopy: %zu of %zu bands, %zu cells homotopy, %zu fallback,"
           " %zu ridge / %zu valley points, %zu links\n", hs.bands_homotopy,
           hs.bands, hs.cells_homotopy, hs.cells_fallback, hs.ridge_points,
           hs.valley_points, hs.links);
    td_lines_free(ls);
}

/* Epsilon against accuracy: homotopy only. */
static void sweep(void)
{
    static const double eps[] = {0, 5, 10, 20, 30, 45, 60};
    td_gen_params gp = td_gen_defaults();
    td_grid_f32 *t[2] = {network_grid(1000), NULL};
    td_lines *ls[2] = {NULL, NULL};
    size_t e;
    int k;
    td_gen_terrain(&gp, &t[1], NULL);
    td_gen_contours(t[0], 0, 5, &ls[0], NULL);
    td_gen_contours(t[1], 0, td_gen_auto_interval(&gp, t[1]), &ls[1], NULL);
    for (e = 0; e < sizeof eps / sizeof *eps; e++)
        for (k = 0; k < 2; k++) {
            td_homotopy_stats hs;
            td_grid_f32 *d;
            char lab[64];
            memset(&hs, 0, sizeof hs);
            g_epsilon = eps[e];
            snprintf(lab, sizeof lab, "eps %2.0f %s", eps[e],
                     k ? "hills" : "network");
            d = run(ls[k], t[k], TD_INTERP_HOMOTOPY, k == 0, &hs, lab);
            printf("      %zu ridge, %zu valley points, %zu links\n",
                   hs.ridge_points, hs.valley_points, hs.links);
            td_grid_f32_free(d);
        }
    for (k = 0; k < 2; k++) {
        td_lines_free(ls[k]);
        td_grid_f32_free(t[k]);
    }
    g_epsilon = -1;
}

int main(int argc, char **argv)
{
    const char *dir = NULL;
    int big = 5000, i;
    td_grid_f32 *t = NULL;
    td_gen_params gp = td_gen_defaults();
    for (i = 1; i + 1 < argc; i++) {
        if (!strcmp(argv[i], "--dir"))
            dir = argv[++i];
        else if (!strcmp(argv[i], "--big"))
            big = atoi(argv[++i]);
    }
    for (i = 1; i < argc; i++)
        if (!strcmp(argv[i], "--sweep")) {
            sweep();
            return 0;
        }
    if (dir)
        mkdir(dir, 0777);
    t = network_grid(1000);
    one_case("network", t, 5, 1, dir, 1);
    td_grid_f32_free(t);
    t = NULL;
    if (td_gen_terrain(&gp, &t, NULL) == 0)
        one_case("hills", t, td_gen_auto_interval(&gp, t), 0, dir, 1);
    td_grid_f32_free(t);
    t = NULL;
    if (big > 0 && (t = network_grid(big)) != NULL)
        one_case("network_big", t, 10, 1, dir, 0);
    td_grid_f32_free(t);
    return 0;
}
