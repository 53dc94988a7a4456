/* topodig run: scan -> label -> interp in one process: the pipeline of
 * src/pipeline/run.c with its files. */
#include "src/cli/run_int.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct run_opts {
    const char *in, *out, *summary_json;
    int quiet;
    td_cli_run r;
    td_ctx *cx;
} run_opts;

static const char about[] =
    "Scan the sheet (as topodig scan), read the height labels printed in\n"
    "the index contours' gaps (Tesseract), give every traced line its\n"
    "height (as topodig label: the labels, known points and index widths\n"
    "solved together) and interpolate the DEM (as topodig interp), all in\n"
    "memory.  With printed labels no option is needed: the interval is\n"
    "inferred from them; --interval, --known, --index-every, --depressions\n"
    "add certainty.  The DEM has the scan's size (or one cell per N x N\n"
    "pixels) and georeferencing; .tif float32 GeoTIFF with nodata, .asc\n"
    "ESRI ASCII grid, .png 16-bit grey.\n";

/* 0: run, 1: error (printed), 2: --help shown. */
static int parse_args(int argc, char **argv, run_opts *o)
{
    td_opt opts[TD_CLI_RUN_OPTS + 2];
    size_t n = td_cli_run_opts(opts, &o->r);
    const td_cmd c = {
        "run", "SCAN -o DEM.tif [--interval I] [--base B]\n"
        "                   [--known X,Y,H]... [--method multidir|scanline|"
        "homotopy]\n                   [--step N]", about,
        "Lines the evidence cannot label are left out (counted in the\n"
        "summary).  Summary on stderr: lines, labelled, where the heights came\n"
        "from, cells determined, seconds per stage.\n",
        opts, "one SCAN file", 1, 1, &o->in, &o->out, "DEM.tif", &o->quiet};
    int rc;
    opts[n++] = (td_opt){"summary-json", 0, TD_OPT_OUTPUT, &o->summary_json,
                         .meta = "F", .help = "also write the summary as one "
                         "JSON object (for\nbatches: lines, heights by "
                         "source, interval,\nlabels, cells, seconds, "
                         "warnings)"};
    opts[n].name = NULL;
    if ((rc = td_opt_parse(&c, argc, argv)) != 0)
        return rc;
    return td_cli_interp_check("run", &o->r.p.interp);
}

/* --save-lines (simplified as scan writes them) and --debug-dir, while
 * every line has its height or null. */
static int on_labelled(const td_run_result *r, void *user)
{
    const run_opts *o = user;
    td_ctx *cx = o->cx;
    int rc = 0;
    if (o->r.save_lines) {
        td_lines *c = td_lines_copy(r->lines, cx);
        rc = !c ? TD_ENOMEM : td_lines_simplify(c, 0.25, cx);
        if (rc == 0)
            rc = td_vector_write_lines(o->r.save_lines, c, &r->geo, cx);
        td_lines_free(c);
    }
    if (rc == 0 && o->r.debug_dir)
        rc = td_pipeline_heights_debug(o->r.debug_dir, r->scan, r->w, r->h,
                                       r->lines, r->reads, r->nreads,
                                       r->vees, r->nvees, &r->geo, cx);
    return rc;
}

/* The labeller refused: --debug-dir still gets the heights picture and
 * labels.geojson, the labels read being what to look at (the error line
 * says what to add).  Nothing else is written. */
static int on_refused(const td_run_result *r, void *user)
{
    const run_opts *o = user;
    td_ctx dc;
    if (!o->r.debug_dir)
        return 0;
    td_ctx_init(&dc);
    if (td_pipeline_heights_debug(o->r.debug_dir, r->scan, r->w, r->h, r->lines,
                                  r->reads, r->nreads, r->vees, r->nvees,
                                  &r->geo, &dc) != 0)
        fprintf(stderr, "run: %s\n", td_errmsg(&dc));
    return 0;
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

static void summary(const td_run_result *s, const td_run_params *p,
                    double write_secs)
{
    size_t n = (size_t)s->dem->w * s->dem->h, ok = n - s->undetermined;
    fprintf(stderr, "run: %zu lines, %zu labelled, %zu left out; %d x %d "
            "cells, %.1f%% determined; read+scan %.2f s, label %.2f s, "
            "interp %.2f s, write %.2f s\n", s->traced,
            s->traced - s->dropped, s->dropped, s->dem->w, s->dem->h,
            100.0 * ok / n, s->secs[0], s->secs[1], s->secs[2], write_secs);
    if (s->pal.n > 0)
        td_cli_print_palette("run", &s->pal);
    td_cli_heights_summary("run", &s->rep);
    if (s->nreads)
        fprintf(stderr,
                "run: labels: %zu read, %zu used (%.2f s); "
                "interval %g; %zu label gaps closed\n",
                s->nreads, s->rep.labels_used, s->ocr_secs, s->rep.interval,
                s->rep.gaps_closed);
    if (s->walls_back)
        fprintf(stderr, "run: %zu stretch%s cut where contours crowd put "
                "back (both sides one height)\n", s->walls_back,
                s->walls_back == 1 ? "" : "es");
    td_cli_bridged_summary("run", s->breaks_closed, s->bridge,
                           s->rep.spacing);
    if (s->ncross)
        fprintf(stderr, "run: warning: %zu pairs of lines cross (contours "
                "do not): a trace jumped between contours there\n",
                s->ncross);
    if (p->interp.method == TD_INTERP_HOMOTOPY)
        fprintf(stderr, "run: homotopy %zu cells in %zu of %zu bands, "
                "%s fallback %zu cells\n", s->hs.cells_homotopy,
                s->hs.bands_homotopy, s->hs.bands,
                p->interp.homotopy.fallback == TD_HM_FALLBACK_MULTIDIR
                    ? "multidir" : "scanline", s->hs.cells_fallback);
}

/* --summary-json: the summary as one object, atomically. */
static int write_summary_json(const char *path, const td_run_result *s,
                              double write_secs, td_ctx *cx)
{
    const td_label_report *rep = &s->rep;
    size_t n = (size_t)s->dem->w * s->dem->h, i, ok = 0, tl = strlen(path) + 32;
    char *tmp = malloc(tl);
    const char *t = rep->text;
    FILE *f;
    int first = 1;
    if (!tmp)
        return td_seterr(cx, TD_ENOMEM, "out of memory");
    for (i = 0; i < n; i++)
        ok += s->dem->data[i] != s->dem->nodata;
    if (!(f = td_atomic_open(path, tmp, tl, cx))) {
        free(tmp);
        return cx->code ? cx->code : TD_EIO;
    }
    fprintf(f, "{\"lines\": %zu, \"labelled\": %zu, \"left_out\": %zu, "
            "\"by_source\": {\"known\": %zu, \"label\": %zu, \"solved\": "
            "%zu, \"assumed\": %zu}, \"interval\": %.10g, \"labels_read\": "
            "%zu, \"labels_used\": %zu, \"cells\": %zu, \"determined\": "
            "%.6f, \"seconds\": {\"scan\": %.3f, \"label\": %.3f, "
            "\"interp\": %.3f, \"write\": %.3f}, \"warnings\": [",
            s->traced, s->traced - s->dropped, s->dropped,
            rep->by_source[TD_HS_KNOWN], rep->by_source[TD_HS_LABEL],
            rep->by_source[TD_HS_SOLVED], rep->by_source[TD_HS_ASSUMED],
            rep->interval, s->nreads, rep->labels_used, n,
            n ? (double)ok / n : 0.0, s->secs[0], s->secs[1], s->secs[2],
            write_secs);
    while (t && *t) { /* the labeller's warnings but the face conflicts */
        const char *e = strchr(t, '\n');
        size_t len = e ? (size_t)(e - t) : strlen(t);
        if (strncmp(t, "lines ", 6) != 0) {
            fputs(first ? "\"" : ", \"", f);
            td_cli_json_str(f, t, len);
            fputc('"', f);
            first = 0;
        }
        t = e ? e + 1 : NULL;
    }
    fputs("]}\n", f);
    first = td_atomic_commit(f, tmp, path, cx);
    free(tmp);
    return first;
}

int td_cmd_run(int argc, char **argv)
{
    run_opts o;
    td_run_result r;
    td_ctx cx;
    td_cli_progress pr;
    double t0;
    int rc;
    memset(&o, 0, sizeof o);
    memset(&r, 0, sizeof r);
    td_cli_run_init(&o.r);
    o.cx = &cx;
    if ((rc = parse_args(argc, argv, &o)) != 0 ||
        (rc = td_cli_run_hints(&o.r, "run")) != 0) {
        rc = rc == 2 ? 0 : 1;
        goto done;
    }
    o.r.p.keep_scan = o.r.debug_dir != NULL;
    o.r.p.on_labelled = on_labelled;
    o.r.p.on_refused = on_refused;
    o.r.p.user = &o;
    td_ctx_init(&cx);
    td_cli_progress_init(&pr, &cx, o.quiet);
    rc = td_pipeline_run(o.in, &o.r.p, &r, &cx);
    t0 = td_now();
    if (rc == 0)
        rc = td_dem_write(o.out, r.dem, &r.geo, &cx);
    if (rc == 0 && o.summary_json)
        rc = write_summary_json(o.summary_json, &r, td_now() - t0, &cx);
    td_cli_progress_done(&pr);
    if (rc == 0 && !o.quiet) {
        put_warnings(&r.rep);
        put_warnings(&r.checks);
        summary(&r, &o.r.p, td_now() - t0);
    }
    rc = rc == 0 ? 0 : td_cli_fail_on("run", o.in, o.out, &cx);
    td_run_result_free(&r);
done:
    td_cli_run_free(&o.r);
    return rc;
}
