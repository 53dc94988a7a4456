/* topodig run: scanned sheet -> DEM in one process (scan, label,
 * interpolate; no temporary files). */
#define _GNU_SOURCE
#include "src/cli/cli.h"

#include "src/io/io.h"
#include "src/core/core.h"
#include "interp/homotopy.h"
#include "interp/interp.h"
#include "scanner/label.h"
#include "scanner/ocr.h"
#include "scanner/scan.h"

#include <errno.h>
#include <getopt.h>
#include <sys/stat.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char help[] =
    "usage: topodig run SCAN -o DEM.tif [--interval I] [--base B]\n"
    "                   [--known X,Y,H]... [--method multidir|scanline|homotopy]\n"
    "                   [--step N]\n"
    "\n"
    "Scan the sheet (as topodig scan), read the height labels printed in\n"
    "the index contours' gaps (Tesseract), give every traced line its\n"
    "height (as topodig label: the labels, known points and index widths\n"
    "solved together) and interpolate the DEM (as topodig interp), all in\n"
    "memory.  With printed labels no option is needed: the interval is\n"
    "inferred from them; --interval, --known, --index-every, --depressions\n"
    "add certainty.  The DEM has the scan's size (or one cell per N x N\n"
    "pixels) and georeferencing; .tif float32 GeoTIFF with nodata, .asc\n"
    "ESRI ASCII grid, .png 16-bit grey.\n"
    "\n"
    "options:\n"
    "  -o, --output FILE     DEM output (required)\n"
    "      --interval I      contour interval (> 0; default: inferred from\n"
    "                        the printed labels)\n"
    "      --base B          heights are B + k * I (default 0)\n"
    "      --known X,Y,H     height H at scan pixel X,Y: a point on a line\n"
    "                        or a spot height (repeatable; needed when the\n"
    "                        sheet has no readable labels)\n"
    "      --labels MODE     read (default): read the printed labels |\n"
    "                        none\n"
    "      --depressions X,Y the ring around X,Y is a depression\n"
    "      --index-every N   every Nth contour is drawn thicker: its width\n"
    "                        decides the slopes the known points leave open\n"
    "      --labeller L      faces (default: one solve over the faces) |\n"
    "                        tree (the containment tree); see topodig label\n"
    "      --ink KIND        auto | dark | brown | brown-hue | R,G,B[:tol]\n"
    "                        (default auto; see topodig scan --help)\n"
    "      --threshold T     otsu | sauvola | N (default otsu)\n"
    "      --method M        multidir (default) | scanline (the paper) |\n"
    "                        homotopy (along ridge/valley lines, 003)\n"
    "      --epsilon DEG     homotopy: turning-angle threshold (default 20)\n"
    "      --fallback M      homotopy: scanline (default) | multidir for the\n"
    "                        cells the homotopy cannot reach\n"
    "      --step N          one DEM cell per N x N pixels (default 1)\n"
    "      --save-lines F    also write the labelled lines the DEM was\n"
    "                        interpolated from (.geojson, .gpkg, .shp or\n"
    "                        .dxf by extension, with height,\n"
    "                        height_source, confidence; within 0.25 px\n"
    "                        of the traced path, as scan writes them)\n"
    "      --debug-dir DIR   write heights.png: every line over the scan\n"
    "                        coloured by its height (thick: known or\n"
    "                        labelled, dashed: assumed, grey dots: no\n"
    "                        height; labels read boxed, refused in grey)\n"
    "                        and labels.geojson (one point per label read:\n"
    "                        text, value, angle, confidence, used, why)\n"
    "      --summit S        extrapolate (default) | flat\n"
    "      --peninsula P     scanline: diagonal (default) | flat\n"
    "      --weight W        multidir: span (default) | prod | span2\n"
    "      --dirs N          multidir: 4 (default) or 2\n"
    "      --nodata V        nodata value (default -9999)\n"
    "      --smooth N        N sweeps of smoothing within the contour bands\n"
    "                        (default 0; ours: removes the creases of the\n"
    "                        linear blend, see docs/interp.md)\n"
    "  -q, --quiet           no progress and no summary\n"
    "  -h, --help            this help\n"
    "\n"
    "Lines the evidence cannot label are left out (counted in the\n"
    "summary).  Summary on stderr: lines, labelled, where the heights came\n"
    "from, cells determined, seconds per stage.\n";

typedef struct run_opts {
    const char *in, *out, *save_lines, *debug_dir;
    int quiet;
    double interval, base;
    td_label_point *known;
    size_t nknown;
    double *dep;
    size_t ndep;
    int index_every, tree, no_labels;
    td_scan_params sp;
    td_interp_params ip;
} run_opts;

enum { O_INTERVAL = 256, O_BASE, O_KNOWN, O_DEPR, O_INK, O_THR, O_PASS,
       O_INDEX, O_LABELLER, O_SAVE, O_DEBUG, O_LABELS };


static int add_point(run_opts *o, const char *arg, td_ctx *cx)
{
    double v[3];
    td_label_point *k;
    if (td_cli_parse_nums(arg, v, 3) != 0)
        return td_seterr(cx, TD_EINVAL, "--known: '%s' is not X,Y,H", arg);
    if (!(k = realloc(o->known, (o->nknown + 1) * sizeof *k)))
        return td_seterr(cx, TD_ENOMEM, "out of memory");
    o->known = k;
    k[o->nknown].x = v[0];
    k[o->nknown].y = v[1];
    k[o->nknown].height = v[2];
    k[o->nknown++].id = -1;
    return 0;
}

static int add_depression(run_opts *o, const char *arg, td_ctx *cx)
{
    double v[2], *d;
    if (td_cli_parse_nums(arg, v, 2) != 0)
        return td_seterr(cx, TD_EINVAL, "--depressions: '%s' is not X,Y", arg);
    if (!(d = realloc(o->dep, (2 * o->ndep + 2) * sizeof *d)))
        return td_seterr(cx, TD_ENOMEM, "out of memory");
    o->dep = d;
    d[2 * o->ndep] = v[0];
    d[2 * o->ndep++ + 1] = v[1];
    return 0;
}

static int parse_opt(int c, const char *name, const char *arg, run_opts *o,
                     td_ctx *cx)
{
    switch (c) {
    case 'o': o->out = arg; return 0;
    case 'q': o->quiet = 1; return 0;
    case O_SAVE: o->save_lines = arg; return 0;
    case O_LABELS:
        if (strcmp(arg, "read") && strcmp(arg, "none"))
            return td_seterr(cx, TD_EINVAL, "--labels: '%s' is not read or "
                             "none", arg);
        o->no_labels = !strcmp(arg, "none");
        return 0;
    case O_DEBUG: o->debug_dir = arg; return 0;
    case O_KNOWN: return add_point(o, arg, cx);
    case O_DEPR: return add_depression(o, arg, cx);
    case O_INK: return td_binarise_parse_ink(arg, &o->sp.bin, cx);
    case O_THR: return td_binarise_parse_threshold(arg, &o->sp.bin, cx);
    case O_PASS: return td_interp_set(&o->ip, name, arg, cx);
    case O_LABELLER: return td_cli_parse_labeller(arg, &o->tree, cx);
    case O_INDEX: {
        double v;
        if (td_cli_parse_double(arg, 2, 1000, &v) != 0 || v != floor(v))
            return td_seterr(cx, TD_EINVAL, "--index-every: '%s' is not an "
                             "integer in 2..1000", arg);
        o->index_every = (int)v;
        return 0;
    }
    case O_INTERVAL:
    case O_BASE:
        if (td_cli_parse_double(arg, c == O_BASE ? -1e9 : 1e-9, 1e9,
                                c == O_BASE ? &o->base : &o->interval) != 0)
            return td_seterr(cx, TD_EINVAL, "--%s: '%s' is not a %snumber",
                             name, arg, c == O_BASE ? "" : "positive ");
        return 0;
    }
    return td_seterr(cx, TD_EINVAL, "unknown option (see topodig run --help)");
}

static int parse_args(int argc, char **argv, run_opts *o)
{
    static const struct option lo[] = {
        {"output", 1, 0, 'o'}, {"interval", 1, 0, O_INTERVAL},
        {"base", 1, 0, O_BASE}, {"known", 1, 0, O_KNOWN},
        {"depressions", 1, 0, O_DEPR}, {"ink", 1, 0, O_INK},
        {"index-every", 1, 0, O_INDEX}, {"labeller", 1, 0, O_LABELLER},
        {"save-lines", 1, 0, O_SAVE}, {"debug-dir", 1, 0, O_DEBUG},
        {"labels", 1, 0, O_LABELS},
        {"threshold", 1, 0, O_THR}, {"method", 1, 0, O_PASS},
        {"step", 1, 0, O_PASS}, {"summit", 1, 0, O_PASS},
        {"peninsula", 1, 0, O_PASS}, {"weight", 1, 0, O_PASS},
        {"dirs", 1, 0, O_PASS}, {"nodata", 1, 0, O_PASS},
        {"smooth", 1, 0, O_PASS},
        {"epsilon", 1, 0, O_PASS}, {"fallback", 1, 0, O_PASS},
        {"quiet", 0, 0, 'q'}, {"help", 0, 0, 'h'}, {0, 0, 0, 0}};
    td_ctx cx;
    int c, li = -1;
    td_ctx_init(&cx);
    opterr = 0;
    while ((c = getopt_long(argc, argv, "o:qh", lo, &li)) != -1) {
        if (c == 'h') {
            fputs(help, stdout);
            return 2;
        }
        if (c == '?' || c == ':')
            return td_cli_failf("run", "bad or incomplete option '%s' (see "
                                "topodig run --help)", argv[optind - 1]);
        if (parse_opt(c, li >= 0 ? lo[li].name : "", optarg, o, &cx) != 0)
            return td_cli_fail("run", &cx);
        li = -1;
    }
    if (optind != argc - 1)
        return td_cli_failf("run", "expected one SCAN file (see topodig run "
                            "--help)");
    o->in = argv[optind];
    if (!o->out)
        return td_cli_failf("run", "no output: give -o DEM.tif");
    if (td_cli_check_output("run", o->out, o->in) != 0)
        return 1;
    return 0;
}

typedef struct run_state {
    td_georef geo;
    td_lines *ls;
    td_grid_f32 *dem;
    int w, h;
    size_t traced, dropped;
    double secs[4]; /* read + scan, label, interp, write */
    td_interp_method method;
    int hfallback;
    td_homotopy_stats hs; /* --method homotopy */
    td_label_report rep;
    td_image *scan; /* kept for --debug-dir only */
    td_ocr_read *reads; /* printed labels read */
    size_t nreads;
    double ocr_secs;
    td_palette pal; /* the inks of a colour scan (n = 0: none) */
} run_state;

/* Scan; keeps only the lines (the image and the scanner's grids are freed
 * before interpolation so they never share the peak). */
static int do_scan(const run_opts *o, run_state *s, td_ctx *cx)
{
    td_image *im = NULL;
    td_scan_result res;
    double t0 = td_now();
    int rc;
    memset(&res, 0, sizeof res);
    td_scan_params sp = o->sp;
    if ((rc = td_image_read(o->in, &im, &s->geo, cx)) != 0)
        return rc;
    s->w = im->w;
    s->h = im->h;
    sp.join.record = !o->no_labels; /* where the labels are */
    if ((rc = td_scan(im, &sp, &res, cx)) == 0 && !o->no_labels) {
        double t1 = td_now();
        rc = td_ocr_scan_labels(im, res.lines, &res.join, NULL, NULL, &s->reads,
                                &s->nreads, cx);
        if (rc == 0)
            td_ocr_drop_digits(res.lines, s->reads, s->nreads);
        s->ocr_secs = td_now() - t1;
    }
    if (rc == 0) {
        s->ls = res.lines;
        res.lines = NULL;
        s->traced = s->ls->n;
        s->pal = res.palette;
    }
    td_scan_result_free(&res);
    if (o->debug_dir && rc == 0)
        s->scan = im; /* for heights.png; freed after labelling */
    else
        td_image_free(im);
    s->secs[0] = td_now() - t0;
    return rc;
}

/* --debug-dir labels.geojson: one point per label read. */
static int write_labels_geojson(const char *path, const run_state *s,
                                td_ctx *cx)
{
    char tmp[4200];
    size_t i;
    FILE *f = td_atomic_open(path, tmp, sizeof tmp, cx);
    if (!f)
        return cx->code;
    char crs[320];
    td_georef_crs_json(&s->geo, crs, sizeof crs);
    fprintf(f, "{\"type\":\"FeatureCollection\",%s,\"features\":[\n", crs);
    for (i = 0; i < s->nreads; i++) {
        const td_ocr_read *r = &s->reads[i];
        double x = r->x, y = r->y;
        td_georef_apply(&s->geo, x, y, &x, &y);
        char ids[64] = "null";
        if (r->line[0] >= 0 && (size_t)r->line[0] < s->ls->n)
            snprintf(ids, sizeof ids, "%ld", s->ls->v[r->line[0]].id);
        fprintf(f, "%s{\"type\":\"Feature\",\"properties\":{\"text\":\"%s\","
                "\"value\":%.10g,\"angle\":%.1f,\"confidence\":%.3f,"
                "\"digit_px\":%.1f,\"line\":%s,\"used\":%s,\"why\":%s%s%s},"
                "\"geometry\":{\"type\":\"Point\",\"coordinates\":[%.3f,"
                "%.3f]}}", i ? ",\n" : "", r->text, r->value,
                atan2(-r->uy, r->ux) * 180.0 / 3.14159265358979323846,
                r->conf, r->digit_px, ids, r->used ? "true" : "false",
                r->why ? "\"" : "", r->why ? r->why : "null",
                r->why ? "\"" : "", x, y);
    }
    fputs("\n]}\n", f);
    return td_atomic_commit(f, tmp, path, cx);
}

/* --save-lines and --debug-dir (heights.png), before the lines without a
 * height are dropped. */
static int write_labelled(const run_opts *o, run_state *s, td_ctx *cx)
{
    int rc = 0;
    if (o->save_lines) { /* simplified as scan writes them (0.25 px) */
        td_lines *c = td_lines_copy(s->ls, cx);
        rc = !c ? TD_ENOMEM : td_lines_simplify(c, 0.25, cx);
        if (rc == 0)
            rc = td_vector_write_lines(o->save_lines, c, &s->geo, cx);
        td_lines_free(c);
        if (rc != 0)
            return rc;
    }
    if (o->debug_dir) {
        td_image *pic = NULL;
        char path[4096];
        if (mkdir(o->debug_dir, 0777) != 0 && errno != EEXIST)
            return td_seterr(cx, TD_EIO, "%s: cannot make the folder: %s",
                             o->debug_dir, strerror(errno));
        snprintf(path, sizeof path, "%s/heights.png", o->debug_dir);
        if ((rc = td_draw_heights(s->scan, s->w, s->h, s->ls, &pic, cx)) ==
            0) {
            td_ocr_draw(pic, s->reads, s->nreads);
            rc = td_png_write(path, pic, cx);
        }
        td_image_free(pic);
        snprintf(path, sizeof path, "%s/labels.geojson", o->debug_dir);
        if (rc == 0)
            rc = write_labels_geojson(path, s, cx);
    }
    td_image_free(s->scan);
    s->scan = NULL;
    return rc;
}

/* Label; lines the known points leave without a height are dropped. */
static int do_label(const run_opts *o, run_state *s, td_ctx *cx)
{
    td_label_params p = td_label_defaults();
    double t0 = td_now();
    size_t i;
    int rc;
    p.method = o->tree ? TD_LABEL_TREE : TD_LABEL_FACES;
    p.labels = s->reads;
    p.nlabels = o->tree ? 0 : s->nreads;
    if (o->nknown == 0 && p.nlabels == 0)
        return td_seterr(cx, TD_EINVAL, "no heights to start from: %s; give "
                         "--known X,Y,H (a point on a contour, or a spot "
                         "height)%s", o->no_labels ? "--labels none"
                         : "no printed height label could be read",
                         o->interval > 0 ? "" : " and --interval I");
    if (!(o->interval > 0) && (o->tree || p.nlabels == 0))
        return td_seterr(cx, TD_EINVAL, "no interval: give --interval I%s",
                         o->tree ? "" : " (no printed labels to infer it "
                         "from)");
    p.base = o->base;
    p.interval = o->interval > 0 ? o->interval : 0;
    p.w = s->w;
    p.h = s->h;
    p.known = o->known;
    p.nknown = o->nknown;
    p.depressions = o->dep;
    p.ndepressions = o->ndep;
    p.index_every = o->index_every;
    if ((rc = td_label_auto(s->ls, &p, &s->rep, cx)) != 0 ||
        (rc = write_labelled(o, s, cx)) != 0)
        return rc;
    s->traced = s->ls->n; /* lines cut where two contours ran as one */
    for (i = s->ls->n; i-- > 0;)
        if (!s->ls->v[i].has_height) {
            td_lines_remove(s->ls, i);
            s->dropped++;
        }
    s->secs[1] = td_now() - t0;
    if (s->ls->n == 0)
        return td_seterr(cx, TD_EINVAL, "no traced line could be labelled "
                         "from the known points");
    return 0;
}

static int do_interp(const run_opts *o, run_state *s, td_ctx *cx)
{
    td_interp_params p = o->ip;
    double t0 = td_now();
    int rc;
    p.interval = s->rep.interval > 0 ? s->rep.interval : o->interval;
    p.hstats = &s->hs;
    if ((rc = td_interp_lines(s->ls, s->w, s->h, &p, &s->dem, cx)) != 0)
        return rc;
    td_lines_free(s->ls);
    s->ls = NULL;
    td_georef_scale(&s->geo, p.step);
    s->secs[2] = td_now() - t0;
    s->method = p.method;
    s->hfallback = p.homotopy.fallback == TD_HM_FALLBACK_MULTIDIR;
    rc = td_dem_write(o->out, s->dem, &s->geo, cx);
    s->secs[3] = td_now() - t0 - s->secs[2];
    return rc;
}

/* The labeller's warnings but the face conflicts (counted in the summary):
 * contradicting known points and labels, the interval inferred. */
static void put_warnings(const td_label_report *rep)
{
    const char *t = rep->text;
    while (t && *t) {
        const char *e = strchr(t, '\n');
        int len = (int)(e ? e - t : (long)strlen(t));
        if (strncmp(t, "lines ", 6) != 0)
            fprintf(stderr, "run: warning: %.*s\n", len, t);
        t = e ? e + 1 : NULL;
    }
}

static void summary(const run_state *s)
{
    size_t n = (size_t)s->dem->w * s->dem->h, i, ok = 0;
    for (i = 0; i < n; i++)
        ok += s->dem->data[i] != s->dem->nodata;
    fprintf(stderr, "run: %zu lines, %zu labelled, %zu left out; %d x %d "
            "cells, %.1f%% determined; read+scan %.2f s, label %.2f s, "
            "interp %.2f s, write %.2f s\n", s->traced,
            s->traced - s->dropped, s->dropped, s->dem->w, s->dem->h,
            100.0 * ok / n, s->secs[0], s->secs[1], s->secs[2], s->secs[3]);
    if (s->pal.n > 0)
        td_cli_print_palette("run", &s->pal);
    td_cli_heights_summary("run", &s->rep);
    if (s->nreads)
        fprintf(stderr, "run: labels: %zu read, %zu used (%.2f s); "
                "interval %g\n", s->nreads, s->rep.labels_used, s->ocr_secs,
                s->rep.interval);
    if (s->method == TD_INTERP_HOMOTOPY)
        fprintf(stderr, "run: homotopy %zu cells in %zu of %zu bands, "
                "%s fallback %zu cells\n", s->hs.cells_homotopy,
                s->hs.bands_homotopy, s->hs.bands,
                s->hfallback ? "multidir" : "scanline", s->hs.cells_fallback);
}

int td_cmd_run(int argc, char **argv)
{
    run_opts o;
    run_state s;
    td_ctx cx;
    td_cli_progress pr;
    int rc;
    memset(&o, 0, sizeof o);
    memset(&s, 0, sizeof s);
    o.sp = td_scan_defaults();
    o.ip = td_interp_defaults();
    if ((rc = parse_args(argc, argv, &o)) != 0) {
        rc = rc == 2 ? 0 : 1;
        goto done;
    }
    td_ctx_init(&cx);
    td_georef_init(&s.geo);
    td_cli_progress_init(&pr, &cx, o.quiet);
    if ((rc = do_scan(&o, &s, &cx)) == 0 &&
        (rc = do_label(&o, &s, &cx)) == 0)
        rc = do_interp(&o, &s, &cx);
    td_cli_progress_done(&pr);
    if (rc == 0 && !o.quiet) {
        put_warnings(&s.rep);
        summary(&s);
    }
    rc = rc == 0 ? 0 : td_cli_fail_on("run", o.in, o.out, &cx);
    td_grid_f32_free(s.dem);
    td_lines_free(s.ls);
    td_label_report_free(&s.rep);
    td_image_free(s.scan);
    free(s.reads);
    td_georef_clear(&s.geo);
done:
    free(o.known);
    free(o.dep);
    return rc;
}
