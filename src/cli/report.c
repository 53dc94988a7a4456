/* topodig report: a sheet -> a one-page PDF handout (the run of topodig
 * run, then src/pipeline/report.c). */
#include "src/cli/run_int.h"

#include "src/render/render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <time.h>

typedef struct rp_opts {
    const char *in, *out, *title;
    int quiet, letter;
    td_cli_run r;
    td_image *sheet; /* the scan with the lines, made in on_labelled */
    double lo, hi;   /* the lines' heights */
    td_ctx *cx;
} rp_opts;

static int parse_args(int argc, char **argv, rp_opts *o)
{
    td_opt opts[TD_CLI_RUN_OPTS + 3];
    size_t n = td_cli_run_opts(opts, &o->r);
    const td_cmd c = {
        "report", "SHEET -o REPORT.pdf [the options of topodig run]\n"
        "                      [--paper a4|letter] [--title T]",
        "A one-page handout of a reconstruction: the sheet with the traced\n"
        "lines coloured by height, the DEM as shaded relief with contours, a\n"
        "3-D view, a cross-section along the longest line through the\n"
        "summit and the figures (area, relief, lines, interval, what was\n"
        "inferred), as PDF (cairo).  The sheet is run as topodig run runs it,\n"
        "with the same options.\n",
        NULL, opts, "one SHEET file", 1, 1, &o->in, &o->out, "REPORT.pdf",
        &o->quiet};
    size_t l;
    int rc;
    opts[n++] = (td_opt){"paper", 0, TD_OPT_CHOICE, &o->letter,
                         .choices = "a4|letter", .help = "the page size"};
    opts[n++] = (td_opt){"title", 0, TD_OPT_STRING, &o->title, .meta = "T",
                         .help = "the title (default: the sheet's name)"};
    opts[n].name = NULL;
    if ((rc = td_opt_parse(&c, argc, argv)) != 0)
        return rc;
    l = strlen(o->out);
    if (l < 4 || strcasecmp(o->out + l - 4, ".pdf"))
        return td_cli_failf("report", "the report is a PDF: give -o "
                            "NAME.pdf");
    return td_cli_interp_check("report", &o->r.p.interp);
}

/* The scan faded and shrunk to at most 1100 px a side (so the lines,
 * drawn 1 px wide, show on the page), every line in the colour of its
 * height (grey: none). */
static int on_labelled(const td_run_result *r, void *user)
{
    rp_opts *o = user;
    int f = 1, w, h, x, y, c;
    td_image *im;
    td_line t;
    size_t i, k;
    while ((r->w + f - 1) / f > 1100 || (r->h + f - 1) / f > 1100)
        f++;
    w = r->w / f > 0 ? r->w / f : 1, h = r->h / f > 0 ? r->h / f : 1;
    o->lo = HUGE_VAL, o->hi = -HUGE_VAL;
    for (i = 0; i < r->lines->n; i++)
        if (r->lines->v[i].has_height) {
            o->lo = fmin(o->lo, r->lines->v[i].height);
            o->hi = fmax(o->hi, r->lines->v[i].height);
        }
    if (!(im = td_image_new(w, h, 3, o->cx)))
        return TD_ENOMEM;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            uint8_t *d = im->data + (size_t)y * im->stride + 3 * (size_t)x;
            const uint8_t *s = r->scan ? r->scan->data +
                                             (size_t)(y * f) * r->scan->stride +
                                             (size_t)(x * f) * r->scan->channels
                                       : NULL;
            for (c = 0; c < 3; c++)
                d[c] = (uint8_t)(s ? 200 + s[r->scan->channels >= 3 ? c : 0] *
                                               55 / 255
                                   : 255);
        }
    for (i = 0; i < r->lines->n; i++) {
        const td_line *l = &r->lines->v[i];
        uint8_t rgb[3] = {150, 150, 150};
        double *xy = malloc(2 * l->n * sizeof *xy + 1);
        if (!xy) {
            td_image_free(im);
            return td_seterr(o->cx, TD_ENOMEM, "out of memory");
        }
        if (l->has_height) {
            double tc[3];
            td_render_ramp(o->hi > o->lo ? (l->height - o->lo) /
                                               (o->hi - o->lo) : 0.5, tc);
            for (c = 0; c < 3; c++) /* darker than the tint, to read */
                rgb[c] = (uint8_t)(200 * tc[c]);
        }
        for (k = 0; k < 2 * l->n; k++)
            xy[k] = l->xy[k] / f;
        t = *l, t.xy = xy;
        td_draw_line(im, &t, rgb);
        free(xy);
    }
    o->sheet = im;
    return 0;
}

/* The figures block. */
static int facts(const rp_opts *o, const td_run_result *r, double cell,
                 int metres, char lines[8][200])
{
    const td_label_report *rep = &r->rep;
    size_t n = (size_t)r->dem->w * r->dem->h, i, ok = 0;
    double lo = HUGE_VAL, hi = -HUGE_VAL;
    const char *base = strrchr(o->in, '/') ? strrchr(o->in, '/') + 1 : o->in;
    static const char *const meth[3] = {"scanline (the paper's)",
                                        "multi-directional (default)",
                                        "homotopy (along ridges/valleys)"};
    for (i = 0; i < n; i++)
        if (r->dem->data[i] != r->dem->nodata) {
            ok++;
            lo = fmin(lo, r->dem->data[i]), hi = fmax(hi, r->dem->data[i]);
        }
    snprintf(lines[0], 200, "Sheet: %s, %d x %d pixels; DEM %d x %d cells "
             "(%.1f %% determined)%s", base, r->w, r->h, r->dem->w,
             r->dem->h, 100.0 * ok / n, metres ? "" : ", in the pixel frame");
    if (metres)
        snprintf(lines[1], 200, "Area: %.4g km2 (cells of %.3g m)",
                 ok * cell * cell / 1e6, cell);
    else
        snprintf(lines[1], 200, "Area: %zu cells (no georeferencing: no "
                 "ground size)", ok);
    snprintf(lines[2], 200, "Relief: %.6g to %.6g (%.6g)", lo, hi, hi - lo);
    snprintf(lines[3], 200, "Lines: %zu traced, %zu labelled (%zu from "
             "printed labels, %zu known points, %zu solved, %zu assumed), "
             "%zu left out", r->traced, r->traced - r->dropped,
             rep->by_source[TD_HS_LABEL], rep->by_source[TD_HS_KNOWN],
             rep->by_source[TD_HS_SOLVED], rep->by_source[TD_HS_ASSUMED],
             r->dropped);
    snprintf(lines[4], 200, "Interval: %g, %s; heights base %g + k x %g",
             rep->interval, o->r.p.label.interval > 0
                 ? "given"
                 : "inferred from the printed labels",
             o->r.p.label.base, rep->interval);
    snprintf(lines[5], 200, "Labels: %zu read, %zu agreeing with the "
             "solution", r->nreads, rep->labels_used);
    snprintf(lines[6], 200, "Interpolation: %s",
             meth[o->r.p.interp.method <= 2 ? o->r.p.interp.method : 1]);
    {
        time_t now = time(NULL);
        char d[32];
        strftime(d, sizeof d, "%Y-%m-%d", gmtime(&now));
        snprintf(lines[7], 200, "Made with topodig on %s", d);
    }
    return 8;
}

int td_cmd_report(int argc, char **argv)
{
    rp_opts o;
    td_run_result r;
    td_ctx cx;
    td_cli_progress pr;
    td_report_input in;
    char fl[8][200], sub[256];
    const char *fp[8];
    double cell;
    int rc, geographic = 0, k;
    memset(&o, 0, sizeof o);
    memset(&r, 0, sizeof r);
    memset(&in, 0, sizeof in);
    td_cli_run_init(&o.r);
    o.cx = &cx;
    if ((rc = parse_args(argc, argv, &o)) != 0 ||
        (rc = td_cli_run_hints(&o.r, "report")) != 0) {
        rc = rc == 2 ? 0 : 1;
        goto done;
    }
    o.r.p.keep_scan = 1;
    o.r.p.on_labelled = on_labelled;
    o.r.p.user = &o;
    td_ctx_init(&cx);
    td_cli_progress_init(&pr, &cx, o.quiet);
    rc = td_pipeline_run(o.in, &o.r.p, &r, &cx);
    td_cli_progress_done(&pr);
    if (rc == 0) {
        cell = td_georef_cell_size(&r.geo, r.dem->w, r.dem->h, &geographic);
        k = facts(&o, &r, cell > 0 ? cell : 1, cell > 0, fl);
        for (int i = 0; i < k; i++)
            fp[i] = fl[i];
        snprintf(sub, sizeof sub, "A DEM reconstructed from a scanned "
                 "contour sheet: %zu lines, interval %g", r.traced,
                 r.rep.interval);
        in.title = o.title ? o.title
                           : (strrchr(o.in, '/') ? strrchr(o.in, '/') + 1
                                                 : o.in);
        in.subtitle = sub;
        in.sheet = o.sheet;
        in.dem = r.dem;
        in.cell = cell > 0 ? cell : 1;
        in.unit = cell > 0 ? "m" : "cells";
        in.interval = r.rep.interval;
        in.base = o.r.p.label.base;
        in.facts = fp;
        in.nfacts = (size_t)k;
        in.letter = o.letter;
        rc = td_pipeline_report(o.out, &in, &cx);
    }
    if (rc == 0 && !o.quiet)
        fprintf(stderr, "report: %s: one page (%s), %zu lines, interval %g\n",
                o.out, o.letter ? "Letter" : "A4", r.traced, r.rep.interval);
    rc = rc == 0 ? 0 : td_cli_fail_on("report", o.in, o.out, &cx);
    td_run_result_free(&r);
done:
    td_image_free(o.sheet);
    td_cli_run_free(&o.r);
    return rc;
}
