/* Tests of the streams' Vs (scanner/streams.c): printed sheets drawn from
 * a real DEM with the water plate from the terrain's flow (tdgen
 * --streams), each V's uphill side checked against the true surface; a
 * river across straight contours (no V to read); and what the Vs give
 * the labeller. */
#include "tests/tt.h"
#include "tests/util/hsheet.h"
#include "tests/util/match.h"

#include "scanner/binarise.h"
#include "scanner/palette.h"
#include "scanner/scan.h"
#include "scanner/streams.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define VEES_ACC 0.90  /* test_vees_heights: measured 0.979 */
#define VEES_GAIN 0.10 /* measured +0.146 */
#define PAIRS_ACC 0.88 /* test_gap_pairs: measured 0.915 */
#define PAIRS_GAIN 0.06 /* measured +0.099 */

static double at(const td_grid_f32 *g, double x, double y)
{
    long ix = lround(x), iy = lround(y);
    ix = ix < 0 ? 0 : ix >= g->w ? g->w - 1 : ix;
    iy = iy < 0 ? 0 : iy >= g->h ? g->h - 1 : iy;
    return g->data[(size_t)iy * g->stride + (size_t)ix];
}

/* Scan sheet gp, read its Vs; how many, and how many point to the side
 * the true surface dem (the sheet's size) is higher on, 4 px either side
 * of the line. */
static int vees_on(const td_gen_params *gp, size_t *n, size_t *right)
{
    td_image *im = NULL;
    td_grid_f32 *dem = NULL;
    td_scan_result res;
    td_scan_params sp = td_scan_defaults();
    td_vee *v = NULL;
    td_ctx cx;
    size_t i;
    int rc;
    td_ctx_init(&cx);
    memset(&res, 0, sizeof res);
    *n = *right = 0;
    if ((rc = td_gen_sheet(gp, &im, NULL, &dem, &cx)) == 0 &&
        (rc = td_scan(im, &sp, &res, &cx)) == 0)
        rc = td_streams_vees(im, &res.palette, res.lines, res.join.cross_at,
                             res.join.cross_joins, &v, n, &cx);
    TT_CHECKF(rc == 0, "%s", td_errmsg(&cx));
    for (i = 0; rc == 0 && i < *n; i++) {
        const td_line *l = &res.lines->v[v[i].line];
        size_t k, b = 0, a0, a1;
        double bd = HUGE_VAL, tx, ty, t, h0, h1;
        for (k = 0; k < l->n; k++) {
            double d = hypot(l->xy[2 * k] - v[i].x, l->xy[2 * k + 1] - v[i].y);
            if (d < bd)
                bd = d, b = k;
        }
        a0 = b >= 3 ? b - 3 : 0;
        a1 = b + 3 < l->n ? b + 3 : l->n - 1;
        tx = l->xy[2 * a1] - l->xy[2 * a0];
        ty = l->xy[2 * a1 + 1] - l->xy[2 * a0 + 1];
        t = hypot(tx, ty) + 1e-12;
        h0 = at(dem, v[i].x + 4 * ty / t, v[i].y - 4 * tx / t);
        h1 = at(dem, v[i].x - 4 * ty / t, v[i].y + 4 * tx / t);
        *right += (h0 > h1) == (v[i].up == 0);
    }
    free(v);
    td_scan_result_free(&res);
    td_image_free(im);
    td_grid_f32_free(dem);
    return rc;
}

/* *gp: the Orkhon valley printed new (980 x 1800, interval 25) with its
 * streams; the source DEM to free once drawn, or NULL (checked). */
static td_grid_f32 *orkhon_streams(td_gen_params *gp)
{
    td_ctx cx;
    td_grid_f32 *src;
    td_ctx_init(&cx);
    *gp = td_gen_defaults();
    src = td_hsheet_dem_sheet("orkhon_92m.tif", 10, gp, &cx);
    TT_CHECKF(src != NULL, "%s", td_errmsg(&cx));
    if (src) {
        td_hsheet_defects(gp, 4);
        gp->streams = 1;
    }
    return src;
}

/* A printed map of the Orkhon valley (new, 980 x 1800, interval 25) with
 * its streams: 33 Vs read (2026-12-04), all pointing uphill (51 with
 * the ones at the joins across the water, all right too).  With the
 * sides swapped none would be right; with the two-sided water check
 * taken out, stray water-coloured pixels on the contours' edges pass. */
static void test_vees_real(void)
{
    td_gen_params gp;
    td_grid_f32 *src = orkhon_streams(&gp);
    size_t n, right;
    if (!src)
        return;
    if (vees_on(&gp, &n, &right) == 0)
        TT_CHECKF(n >= 25 && right >= n - n / 20,
                  "Orkhon new print with streams: %zu Vs, %zu right", n, right);
    td_grid_f32_free(src);
}

/* A blue river across straight contours (a plane, tdgen --colour
 * --distractors): it crosses them everywhere and bends none. */
static void test_no_vee_on_straight(void)
{
    td_gen_params gp = td_gen_defaults();
    size_t n, right;
    gp.terrain = TD_GEN_PLANE;
    gp.w = gp.h = 800;
    gp.colour = gp.distractors = 1;
    if (vees_on(&gp, &n, &right) == 0)
        TT_CHECKF(n == 0, "a river across straight contours: %zu Vs", n);
    gp.colour = gp.distractors = 0; /* grey: no water ink */
    gp.terrain = TD_GEN_HILLS;
    if (vees_on(&gp, &n, &right) == 0)
        TT_CHECKF(n == 0, "a grey sheet: %zu Vs", n);
}

/* The labeller with the Vs and the joins across the water, against
 * neither: the crowded Front Range map (interval 20) in colour with its
 * streams, three known points and the index widths: 0.833 without
 * either, 0.979 with both (7 Vs read; 2026-12-04, session 16).  This test used
 * the Front Range map at its own interval printed (0.768 / 0.950, session 12)
 * until the tracer stopped stepping round junctions (scanner.md, "Corners of
 * junctions"): that sheet no longer needs them (0.965 / 0.953).  Right evidence
 * moves the heights both ways (the forest's fragility, docs/label.md); over all
 * the streams sheets the Vs and joins gain 18 rows and lose 8 (bench_heights
 * --streams). */
static void test_vees_heights(void)
{
    td_hsheet hs[2];
    td_ctx cx;
    int k;
    for (k = 0; k < 2; k++) {
        td_grid_f32 *src;
        memset(&hs[k], 0, sizeof hs[k]);
        td_ctx_init(&cx);
        src = td_hsheet_dem_sheet("frontrange_srtm3.tif", 10, &hs[k].gp, &cx);
        TT_CHECKF(src != NULL, "%s", td_errmsg(&cx));
        if (!src)
            return;
        hs[k].gp.interval = 20;
        td_hsheet_defects(&hs[k].gp, 2);
        hs[k].gp.streams = 1;
        hs[k].nknown = 3;
        hs[k].index_every = 5;
        hs[k].no_vees = hs[k].no_stream_joins = k == 1;
        TT_CHECKF(td_hsheet_run(&hs[k], NULL, &cx) == 0, "%s", td_errmsg(&cx));
        td_grid_f32_free(src);
    }
    TT_CHECKF(
        hs[0].rep.vees >= 5 && hs[1].rep.vees == 0 &&
            hs[0].score.accuracy >= VEES_ACC &&
            hs[0].score.accuracy >= hs[1].score.accuracy + VEES_GAIN,
        "crowded Front Range colour with streams, 3 known + widths: %zu Vs, "
        "accuracy %.3f, without the Vs and joins %.3f",
        hs[0].rep.vees, hs[0].score.accuracy, hs[1].score.accuracy);
    td_label_report_free(&hs[0].rep);
    td_label_report_free(&hs[1].rep);
}

/* The joiner's stage 3 on the same map: contours the streams' ink hides
 * at their Vs joined across the water.  Measured 2026-12-04 (docs/
 * scanner.md, "Contours under streams"): 473 -> 420 lines (53 joins), the
 * traced length on its own contour 0.973 both; every stage-3 join on
 * seven sheets checked against the truth, 188 of 188 on one contour.  A
 * join across two contours would show as a jump. */
static void test_stream_joins(void)
{
    td_gen_params gp;
    td_image *im = NULL;
    td_lines *tl = NULL;
    td_scan_result res[2];
    td_scanscore sc[2];
    td_ctx cx;
    td_grid_f32 *src = orkhon_streams(&gp);
    int k, ok = 1;
    td_ctx_init(&cx);
    memset(res, 0, sizeof res);
    if (!src)
        return;
    ok = td_gen_sheet(&gp, &im, &tl, NULL, &cx) == 0;
    for (k = 0; ok && k < 2; k++) {
        td_scan_params sp = td_scan_defaults();
        sp.join.cross_gap = k == 0 ? 16.0 : 0.0;
        ok = td_scan(im, &sp, &res[k], &cx) == 0 &&
             td_match_scan(tl, res[k].lines, im->w, im->h, 2.0, 20.0, &sc[k],
                           NULL) == 0;
    }
    TT_CHECKF(ok, "%s", td_errmsg(&cx));
    if (ok)
        TT_CHECKF(res[0].join.cross_joins >= 20 &&
                      res[1].join.cross_joins == 0 &&
                      res[0].lines->n + 10 <= res[1].lines->n &&
                      sc[0].own >= sc[1].own - 0.002 &&
                      sc[0].n_jump <= sc[1].n_jump + 2,
                  "stream joins %zu: %zu lines (%zu without), own %.4f "
                  "(%.4f), %ld jumps (%ld)",
                  res[0].join.cross_joins, res[0].lines->n, res[1].lines->n,
                  sc[0].own, sc[1].own, sc[0].n_jump, sc[1].n_jump);
    for (k = 0; k < 2; k++)
        td_scan_result_free(&res[k]);
    td_image_free(im);
    td_lines_free(tl);
    td_grid_f32_free(src);
}

/* Whether a bit of the packed mask (w x h) is set within CUT_R px of (x,
 * y) (a square): a 3 px road then cuts a line over about 10 px, as the
 * scanner leaves it (the road, the palette's veto ring, the thinned ends
 * drawn back). */
#define CUT_R 3
static int covered(const uint8_t *bits, int w, int h, double x, double y)
{
    size_t stride = ((size_t)w + 7) / 8;
    long X = lround(x), Y = lround(y), u, v;
    for (v = Y - CUT_R; v <= Y + CUT_R; v++)
        for (u = X - CUT_R; u <= X + CUT_R; u++)
            if (u >= 0 && v >= 0 && u < w && v < h &&
                (bits[(size_t)v * stride + (size_t)u / 8] >> (u % 8)) & 1)
                return 1;
    return 0;
}

/* The true lines of the Orkhon map with streams, cut wherever another
 * ink (the road, the streams, the black text) covers them as the
 * scanner's palette sees it (CUT_R), and labelled with 3 known points and
 * the index widths, with the free-end pairs (24 px: the labeller's default
 * on a colour scan) and without (its default on a grey one).
 * Measured 2026-12-04 (docs/label.md, "Free ends that continue each
 * other"): 0.915 of the length right with them, 0.816 without (723
 * pieces of 191 lines; cut within 1 or 2 px both gave 0.95: the probes
 * through narrow gaps tie the pieces). */
static void test_gap_pairs(void)
{
    td_gen_params gp;
    td_image *im = NULL;
    td_lines *tl = NULL, *cut[2] = {NULL, NULL};
    td_grid_f32 *dem = NULL, *src = orkhon_streams(&gp);
    td_palette pal;
    uint8_t *bits = NULL;
    double *truth = NULL, acc[2] = {0, 0}, I = 0;
    size_t i, k, n = 0;
    td_ctx cx;
    int r, ok;
    if (!src)
        return;
    td_ctx_init(&cx);
    ok = td_gen_sheet(&gp, &im, &tl, &dem, &cx) == 0 &&
         td_palette_find(im, &pal, &cx) == 0 &&
         td_palette_choose(&pal, 1) >= 0 &&
         td_binarise_other_ink(im, &pal, &bits, &cx) == 0 && bits &&
         (truth = malloc((2 * tl->n * 64 + 1) * sizeof *truth)) != NULL;
    TT_CHECKF(ok, "%s", td_errmsg(&cx));
    if (ok)
        I = td_gen_auto_interval(&gp, dem);
    for (r = 0; ok && r < 2; r++) {
        ok = (cut[r] = td_lines_new(&cx)) != NULL;
        for (i = 0; ok && i < tl->n; i++) {
            const td_line *l = &tl->v[i];
            double q = (l->height - gp.base) / I / 5;
            td_line *c = NULL;
            for (k = 0; ok && k < l->n; k++) {
                double x = l->xy[2 * k], y = l->xy[2 * k + 1];
                if (covered(bits, im->w, im->h, x, y)) {
                    c = NULL;
                    continue;
                }
                if (!c) {
                    ok = (c = td_lines_add(cut[r], &cx)) != NULL;
                    if (!ok)
                        break;
                    c->width = fabs(q - floor(q + 0.5)) < 1e-6 ? 3.2 : 1.8;
                    if (r == 0)
                        truth[n++] = l->height;
                }
                ok = td_line_push(c, x, y, &cx) == 0;
            }
        }
    }
    for (r = 0; ok && r < 2; r++) {
        td_label_params lp = td_label_defaults();
        td_label_report rep;
        td_label_point kp[3];
        double tot = 0, right = 0;
        memset(&rep, 0, sizeof rep);
        lp.interval = I;
        lp.base = gp.base;
        lp.index_every = 5;
        lp.w = im->w, lp.h = im->h;
        lp.nknown = (size_t)td_hsheet_pick_known(tl, I, 3, kp);
        lp.known = kp;
        lp.colour = r == 0; /* the default: pairs on a colour scan only */
        ok = td_label_auto(cut[r], &lp, &rep, &cx) == 0;
        for (i = 0; ok && i < cut[r]->n; i++) {
            double L = td_line_length(&cut[r]->v[i]);
            tot += L;
            right += cut[r]->v[i].has_height &&
                             fabs(cut[r]->v[i].height - truth[i]) < 1e-6
                         ? L
                         : 0;
        }
        acc[r] = tot > 0 ? right / tot : 0;
        td_label_report_free(&rep);
    }
    TT_CHECKF(ok, "%s", td_errmsg(&cx));
    if (ok)
        TT_CHECKF(cut[0]->n > tl->n + 100 && acc[0] >= PAIRS_ACC &&
                      acc[0] >= acc[1] + PAIRS_GAIN,
                  "true lines cut into %zu pieces (of %zu): %.3f right with "
                  "the free-end pairs (colour default), %.3f without (grey)",
                  cut[0]->n, tl->n, acc[0], acc[1]);
    td_lines_free(cut[0]);
    td_lines_free(cut[1]);
    free(truth);
    free(bits);
    td_image_free(im);
    td_lines_free(tl);
    td_grid_f32_free(dem);
    td_grid_f32_free(src);
}

int main(void)
{
    TT_RUN(test_vees_real);
    TT_RUN(test_no_vee_on_straight);
    TT_RUN(test_stream_joins);
    TT_RUN(test_vees_heights);
    TT_RUN(test_gap_pairs);
    return tt_summary();
}
