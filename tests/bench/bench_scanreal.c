/* bench_scanreal: the scanner on sheets drawn from real DEMs (issue 14's
 * measures): recall and precision within 2 px of the true contours, the
 * share of traced length on its own contour, and the traced lines that run
 * onto another contour for more than 20 px, for clean, scanned, colour,
 * printed and printed-new (tdgen --print --unfaded) sheets: the paper's
 * junctions, ours without the seam split, and the
 * default (ours with it); then the same on the generator's 800 px cone,
 * whose rings both roads of the printed kinds cross.  Numbers for
 * docs/scanner.md and docs/binarise.md (the options measured: --ink brown,
 * the hue window, --no-grid, every junction paired, --detint, the pieces
 * kept joined or late, --alone-gaps).  --levels: instead, the colour
 * kinds with their levels mapped as other scanners give them (eight
 * gdal_translate -scale ranges and two colour balances), the defaults'
 * recall and precision on each (the palette's sensitivity,
 * docs/binarise.md).
 *
 *   bench_scanreal [--dems DIR] [--only NAME] [--log] [--out DIR]
 *                  [--levels] */
#include "samples/gen/gen.h"
#include "scanner/scan.h"
#include "src/io/io.h"
#include "tests/util/bench.h"
#include "tests/util/hsheet.h"
#include "tests/util/match.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* One sheet's defect kind (td_hsheet_defects) over gp: every variant's
 * row; with out, the default's sheet, truth and lines written there. */
static void one_kind(const char *name, td_gen_params gp, int kind, int logit,
                     const char *out, td_ctx *cx)
{
    td_image *im = NULL;
    td_lines *truth = NULL;
    char path[512];
    int v;
    td_hsheet_defects(&gp, kind);
    if (td_gen_sheet(&gp, &im, &truth, NULL, cx) != 0) {
        printf("%-12s %-7s generate failed: %s\n", name, td_defect_names[kind],
               td_errmsg(cx));
        td_ctx_clear(cx);
        return;
    }
    for (v = 0; v < 11; v++) {
        /* paper junctions, cut without seams, the default; colour:
           --ink brown, and the first brown selection (hue window);
           the default without the grid-line removal; the default
           pairing every junction zone's ends (no ambiguity rule);
           colour: --detint; --keep-pieces; --pieces late; --alone-gaps */
        static const char *const vname[11] = {
            "paper",     "cut,noseam", "default",   "ink brown",
            "brown-hue", "nogrid",     "junc any",  "detint",
            "keep pcs",  "pcs late",   "alone gaps"};
        int paper = v == 0;
        td_scan_params sp = td_scan_defaults();
        td_scan_result res;
        td_scanscore sc;
        struct timespec t0, t1;
        if (((v >= 3 && v <= 4) || v == 7) && kind < 2)
            continue;
        if (v == 7)
            sp.detint = 1;
        if (v == 8)
            sp.join.keep_pieces = TD_PIECES_JOINED;
        if (v == 9)
            sp.join.keep_pieces = TD_PIECES_LATE;
        if (v == 10)
            sp.join.alone_gaps = 1;
        if (v == 5)
            sp.straight.on = 0;
        if (v == 6)
            sp.join.junc_ratio = 0; /* every zone paired */
        if (v == 3)
            sp.bin.ink = TD_INK_BROWN;
        if (v == 4)
            sp.bin.ink = TD_INK_BROWN_HUE;
        sp.trace.cut = !paper;
        if (v == 1)
            sp.bin.split = 0;
        clock_gettime(CLOCK_MONOTONIC, &t0);
        if (td_scan(im, &sp, &res, cx) != 0) {
            printf("%-12s %-7s scan failed: %s\n", name, td_defect_names[kind],
                   td_errmsg(cx));
            td_ctx_clear(cx);
            continue;
        }
        clock_gettime(CLOCK_MONOTONIC, &t1);
        if (logit)
            printf("-- %s %s %s\n", name, td_defect_names[kind], vname[v]);
        td_match_scan(truth, res.lines, im->w, im->h, 2.0, 20.0, &sc,
                      logit ? stdout : NULL);
        printf("%-12s %-7s %-10s %6ld %6ld %6.3f %6.3f %6.3f %6.3f "
               "%6.2f\n",
               name, td_defect_names[kind], vname[v], sc.n_truth, sc.n_traced,
               sc.recall, sc.precision, sc.own,
               (double)sc.n_jump / (double)(sc.n_traced + !sc.n_traced),
               (double)(t1.tv_sec - t0.tv_sec) +
                   1e-9 * (double)(t1.tv_nsec - t0.tv_nsec));
        fflush(stdout);
        if (out && v == 2) {
            snprintf(path, sizeof path, "%s/%s_%s.png", out, name,
                     td_defect_names[kind]);
            if (td_png_write(path, im, cx) != 0)
                td_ctx_clear(cx);
            snprintf(path, sizeof path, "%s/%s_%s_truth.geojson", out, name,
                     td_defect_names[kind]);
            if (td_geojson_write_lines(path, truth, NULL, cx) != 0)
                td_ctx_clear(cx);
            snprintf(path, sizeof path, "%s/%s_%s_lines.geojson", out, name,
                     td_defect_names[kind]);
            if (td_geojson_write_lines(path, res.lines, NULL, cx) != 0)
                td_ctx_clear(cx);
        }
        td_scan_result_free(&res);
    }
    td_image_free(im);
    td_lines_free(truth);
}

/* The level mappings of --levels: per channel v -> lo + v (hi - lo) /
 * 255 (gdal_translate -scale 0 255 lo hi), clamped. */
static const struct {
    const char *name;
    int lo[3], hi[3];
} level_maps[10] = {{"0..255", {0, 0, 0}, {255, 255, 255}},
                    {"-2..253", {-2, -2, -2}, {253, 253, 253}},
                    {"2..257", {2, 2, 2}, {257, 257, 257}},
                    {"1..256", {1, 1, 1}, {256, 256, 256}},
                    {"-4..251", {-4, -4, -4}, {251, 251, 251}},
                    {"0..250", {0, 0, 0}, {250, 250, 250}},
                    {"5..255", {5, 5, 5}, {255, 255, 255}},
                    {"0..260", {0, 0, 0}, {260, 260, 260}},
                    {"R+3,B-3", {3, 0, -3}, {258, 255, 252}},
                    {"R-3,G+2", {-3, 2, 0}, {252, 257, 255}}};

/* One colour kind under every level mapping: a row each, then the
 * worst and mean recall. */
static void levels_kind(const char *name, td_gen_params gp, int kind,
                        td_ctx *cx)
{
    td_image *im = NULL, *sh = NULL;
    td_lines *truth = NULL;
    double lo = 1, sum = 0;
    int m, n = 0;
    td_hsheet_defects(&gp, kind);
    if (td_gen_sheet(&gp, &im, &truth, NULL, cx) != 0 ||
        !(sh = td_image_new(im->w, im->h, 3, cx))) {
        printf("%-12s %-7s generate failed: %s\n", name, td_defect_names[kind],
               td_errmsg(cx));
        td_ctx_clear(cx);
        td_image_free(im);
        td_lines_free(truth);
        return;
    }
    for (m = 0; m < 10; m++) {
        td_scan_params sp = td_scan_defaults();
        td_scan_result res;
        td_scanscore sc;
        td_hsheet_levels(im, sh, level_maps[m].lo, level_maps[m].hi);
        if (td_scan(sh, &sp, &res, cx) != 0) {
            printf("%-12s %-7s %-10s scan failed: %s\n", name,
                   td_defect_names[kind], level_maps[m].name, td_errmsg(cx));
            td_ctx_clear(cx);
            continue;
        }
        td_match_scan(truth, res.lines, im->w, im->h, 2.0, 20.0, &sc, NULL);
        printf("%-12s %-7s %-10s %6ld %6ld %6.3f %6.3f\n", name,
               td_defect_names[kind], level_maps[m].name, sc.n_truth,
               sc.n_traced, sc.recall, sc.precision);
        fflush(stdout);
        lo = sc.recall < lo ? sc.recall : lo;
        sum += sc.recall, n++;
        td_scan_result_free(&res);
    }
    printf("%-12s %-7s %-10s recall worst %.3f mean %.3f\n", name,
           td_defect_names[kind], "(all)", lo, n ? sum / n : 0);
    td_image_free(sh);
    td_image_free(im);
    td_lines_free(truth);
}

static const char usage[] =
    "usage: bench_scanreal [--dems DIR] [--only NAME] [--log] [--out DIR] "
    "[--levels]\n";

int main(int argc, char **argv)
{
    const char *dir = "tests/data/dems", *only = NULL, *out = NULL;
    int logit = 0, levels = 0, a;
    size_t c;
    for (a = 1; a < argc; a++) {
        if (!strcmp(argv[a], "--dems") && a + 1 < argc)
            dir = argv[++a];
        else if (!strcmp(argv[a], "--only") && a + 1 < argc)
            only = argv[++a];
        else if (!strcmp(argv[a], "--out") && a + 1 < argc)
            out = argv[++a];
        else if (!strcmp(argv[a], "--log"))
            logit = 1;
        else if (!strcmp(argv[a], "--levels"))
            levels = 1;
        else if ((!strcmp(argv[a], "--topodig") || !strcmp(argv[a], "--dir")) &&
                 a + 1 < argc)
            a++; /* make bench's common options */
        else
            return td_bench_usage("bench_scanreal", argv[a], usage);
    }
    if (out && td_bench_outdir("bench_scanreal", out) != 0)
        return 1;
    if (levels)
        printf("%-12s %-7s %-10s %6s %6s %6s %6s\n", "sheet", "scan", "levels",
               "truth", "traced", "recall", "prec");
    else
        printf("%-12s %-7s %-10s %6s %6s %6s %6s %6s %6s %6s\n", "sheet",
               "scan", "junctions", "truth", "traced", "recall", "prec", "own",
               "jumps", "secs");
    for (c = 0; c < sizeof td_real_sheets / sizeof td_real_sheets[0]; c++) {
        const td_real_sheet *k = &td_real_sheets[c];
        td_grid_f32 *src = NULL;
        td_ctx cx;
        int kind;
        char path[512];
        if (only && strcmp(only, k->name))
            continue;
        td_ctx_init(&cx);
        snprintf(path, sizeof path, "%s/%s", dir, k->dem);
        if (td_hsheet_load_dem(path, &src, &cx) != 0) {
            printf("%-12s (skipped: %s)\n", k->name, td_errmsg(&cx));
            continue;
        }
        for (kind = 0; kind < 5; kind++) {
            td_gen_params gp = td_gen_defaults();
            gp.terrain = TD_GEN_DEM;
            gp.dem_in = src;
            gp.interval = k->interval;
            gp.w = (int)(src->w * k->scale);
            gp.h = (int)(src->h * k->scale);
            if (levels && kind >= 2)
                levels_kind(k->name, gp, kind, &cx);
            else if (!levels)
                one_kind(k->name, gp, kind, logit, out, &cx);
        }
        td_grid_f32_free(src);
    }
    if (!levels && (!only || !strcmp(only, "cone"))) {
        /* the generator's cone, 800 px: every ring crossed by both roads
           (the printed kinds), contours 7 px apart */
        td_ctx cx;
        int kind;
        td_ctx_init(&cx);
        for (kind = 0; kind < 5; kind++) {
            td_gen_params gp = td_gen_defaults();
            gp.terrain = TD_GEN_CONE;
            gp.w = gp.h = 800;
            one_kind("cone", gp, kind, logit, out, &cx);
        }
    }
    return 0;
}
