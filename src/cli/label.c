/* topodig label: traced lines -> lines with heights.  Automatic heights
 * (scanner/label.h: the faces solve, ours; the containment tree); the
 * paper's way, one typed height per line (001 §2.3), is --interactive
 * (label_entry.c) or --heights after editing the --export-csv file. */
#include "src/cli/label_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>


static const char about[] =
    "Give every traced line its height from a few known points and the\n"
    "interval.  The default labeller (--labeller faces) finds which lines\n"
    "border one face by probes across the sheet and solves all heights at\n"
    "once (each line one interval between its two faces); the evidence is\n"
    "the known points, the height labels printed on the sheet (--sheet),\n"
    "the index contours' widths (--index-every), and the defaults that\n"
    "rings rise and slopes run on rather than fold back.  Every line gets\n"
    "height_source (known, label, solved, assumed) and confidence\n"
    "(0..1); a line nothing decides keeps a null height and a\n"
    "height_reason.  --labeller tree is the earlier containment tree (one\n"
    "interval per nesting step, rings rising).  LINES and the output:\n"
    ".geojson, .gpkg, .shp or .dxf.\n";

/* 0: run, 1: error (printed), 2: --help shown. */
static int parse_args(int argc, char **argv, label_opts *o)
{
    td_label_params *p = &o->p;
    const td_opt opts[] = {
        {"sheet", 0, TD_OPT_STRING, &o->scan, .meta = "SCAN", .help = "read "
         "the height labels printed on the scan the\nlines were traced from "
         "(Tesseract); with them\n--interval may be left out (inferred)"},
        {"streams", 0, TD_OPT_CHOICE, &o->no_streams, .choices = "read|none",
         .meta = "MODE", .help = "with --sheet, a colour scan: read where "
         "streams\n(the water ink) cross the lines: contours'\nVs point "
         "uphill (ours), or not"},
        {"interval", 0, TD_OPT_DOUBLE, &p->interval, 1e-9, 1e9, .meta = "I",
         .help = "contour interval (required without --sheet)",
         .no_default = 1},
        {"base", 0, TD_OPT_DOUBLE, &p->base, -1e9, 1e9, .meta = "B",
         .help = "heights are B + k * I"},
        {"known", 0, TD_OPT_POINTS, &o->known, .n = 3, .meta = "X,Y,H",
         .help = "a point on (within 3 px of) a line: its height;\n"
         "elsewhere: a spot height (repeatable)"},
        {"walls", 0, TD_OPT_STRING, &o->walls, .meta = "WALLS",
         .help = "where the scan cut lines out of blobs of\ncrowded contours "
         "(`scan --walls`): the faces\ndo not run through them"},
        {"known-file", 0, TD_OPT_STRING, &o->known_file, .meta = "CSV",
         .help = "x,y,height rows (a header line is skipped)"},
        {"depressions", 0, TD_OPT_POINTS, &o->dep, .n = 2, .meta = "X,Y",
         .help = "the ring around X,Y is a depression (repeatable)"},
        {"heights", 0, TD_OPT_STRING, &o->heights, .meta = "CSV", .help =
         "id,height rows: these lines' heights (e.g. an\nedited --export-csv "
         "file; an empty height:\nnone given)"},
        {"export-csv", 0, TD_OPT_OUTPUT, &o->csv_out, .meta = "FILE",
         .help = "write id,height of every line"},
        {"size", 0, TD_OPT_FUNC, &o->w, .fn = td_cli_parse_size, .meta = "WxH",
         .help = "sheet size in px (default: the lines' extent)"},
        {"interactive", 0, TD_OPT_FLAG, &o->interactive, .help = "the paper's "
         "way: write a label sheet PNG, then\nask each line's height on "
         "stderr, reading\nanswers from stdin: Enter accepts the\nsuggestion, "
         "a number sets the height (the\nothers are re-suggested from it), "
         "q keeps the\nrest automatic; end of input accepts the rest"},
        {"label-sheet", 0, TD_OPT_OUTPUT, &o->label_sheet, .meta = "PNG",
         .help = "the label sheet (default LABELLED.png)"},
        {"like", 0, TD_OPT_STRING, &o->like, .meta = "SCAN", .help = "draw "
         "the label sheet over the scan; with\n--index-every, measure the "
         "line widths on it\nwhen the lines carry none"},
        {"index-every", 0, TD_OPT_INT, &p->index_every, 2, 1000, .meta = "N",
         .help = "every Nth level (base + k*N*I) is an index\ncontour drawn "
         "thicker: warn about each line\nwhose ink width (the scan's 'width' "
         "property)\ndisagrees with its height (without it the\nfaces "
         "solve still weighs the widths, at\nthe spacing they fit best)",
         .no_default = 1},
        {"thick-ratio", 0, TD_OPT_DOUBLE, &p->thick_ratio, 1.01, 100,
         .meta = "R", .help = "thick/thin width ratio that tells index lines"},
        {"no-missing", 0, TD_OPT_FLAG, &o->no_missing, .help = "tree: a known "
         "point one interval off the\nnesting is a contradiction, not a "
         "missing\ncontour"},
        {"labeller", 0, TD_OPT_CHOICE, &p->method, .choices = "faces|tree",
         .meta = "L", .help = "faces: one solve | tree: the containment tree"},
        {"search", 0, TD_OPT_INT, &p->search, 0, 64, .meta = "N",
         .help = "faces: also try N forests and a local search\nover every "
         "face edge, keep the cheapest (ours;\nslower; helps where a region "
         "folds the\nwrong way; 8 measured best; 0: off)"},
        {"gap-pairs", 0, TD_OPT_DOUBLE, &p->gap_pairs, 0, 200, .meta = "PX",
         .help = "faces: two free line ends at most PX apart\nthat face each "
         "other are one contour (ours;\nmeasured: see docs/label.md; 0: off;"
         "\ndefault 24 with --sheet in colour, else 0)", .no_default = 1},
        {"debug-dir", 0, TD_OPT_STRING, &o->debug_dir, .meta = "DIR", .help =
         "write heights.png: the lines coloured by height\n(over --like SCAN "
         "when given; thick: known,\ndashed: assumed, grey dots: no height)"},
        {NULL}};
    const td_cmd c = {
        "label", "LINES.geojson -o LABELLED.geojson\n"
        "                     [--sheet SCAN] [--interval I] [--base B]\n"
        "                     [--known X,Y,H]... [options]", about,
        "Coordinates are scan pixels (column, row).  Summary on stderr:\n"
        "lines labelled, undetermined, warnings, and where the heights came\n"
        "from.  Exit 1 on bad input; known points that contradict each other\n"
        "are a warning naming them and the solver's choice (tree: exit 1).\n",
        opts, "one LINES.geojson file", 1, 1, &o->in, &o->out,
        "LABELLED.geojson", &o->quiet};
    int rc = td_opt_parse(&c, argc, argv);
    if (rc == 0 && !(p->interval > 0) && (!o->scan || p->method == TD_LABEL_TREE))
        rc = td_cli_failf("label", "no interval: give --interval I%s",
                          o->scan ? "" : " (or --sheet SCAN to read the "
                          "printed labels)");
    return rc;
}

/* The hints from the options and their files into o->p. */
static int hints(label_opts *o, td_ctx *cx)
{
    double *v = NULL;
    size_t n = 0, i;
    int rc = 0;
    for (i = 0; rc == 0 && i < o->known.n; i++)
        rc = td_pts_push(&o->pts, o->known.v[3 * i], o->known.v[3 * i + 1],
                         o->known.v[3 * i + 2], -1, cx);
    if (rc == 0 && o->known_file &&
        (rc = td_csv_read_rows(o->known_file, 3, 0, &v, &n, cx)) == 0)
        for (i = 0; rc == 0 && i < n; i++)
            rc = td_pts_push(&o->pts, v[3 * i], v[3 * i + 1], v[3 * i + 2],
                             -1, cx);
    free(v);
    if (rc == 0 && o->heights)
        rc = td_csv_read_rows(o->heights, 2, 1, &o->rows, &o->nrows, cx);
    o->p.known = o->pts.v, o->p.nknown = o->pts.n;
    o->p.depressions = o->dep.v, o->p.ndepressions = o->dep.n;
    o->p.missing = !o->no_missing;
    return rc;
}

/* The labeller refused (its error stands): --debug-dir still
 * gets the heights picture and labels.geojson, every line without a
 * height (td_label_auto), to show what was read. */
static void refused_debug(const label_opts *o, const td_lines *ls,
                          const td_ocr_read *reads, size_t nreads)
{
    td_ctx dc;
    td_ctx_init(&dc);
    if (td_pipeline_heights_debug(o->debug_dir, NULL, o->w, o->h, ls, reads,
                                  nreads, o->p.vees, o->p.nvees, NULL,
                                  &dc) != 0)
        fprintf(stderr, "label: %s\n", td_errmsg(&dc));
}

/* Label ls and write every output, the secondary ones first: when one
 * fails, the main output (new or old) is left as it was. */
static int label(label_opts *o, td_lines *ls, const td_georef *frame,
                 td_label_report *rep, td_label_report *checks,
                 td_pts *seen, size_t *more, td_ctx *cx)
{
    td_ocr_read *reads = NULL;
    td_vee *vees = NULL;
    size_t nreads = 0, nvees = 0;
    long ncross;
    int rc = 0;
    if (o->scan && o->p.method != TD_LABEL_TREE)
        rc = td_pipeline_sheet_labels(o->scan, ls, &reads, &nreads,
                                      o->no_streams ? NULL : &vees, &nvees,
                                      &o->p.colour, cx);
    o->p.labels = reads, o->p.nlabels = nreads;
    o->p.vees = vees, o->p.nvees = nvees;
    o->p.w = o->w, o->p.h = o->h;
    if (rc == 0 && (ncross = td_label_warn_crossings(ls, o->quiet, cx)) < 0)
        rc = TD_ENOMEM;
    if (rc == 0 && (rc = td_label_auto(ls, &o->p, rep, cx)) == TD_EINVAL &&
        o->debug_dir)
        refused_debug(o, ls, reads, nreads);
    if (rc == 0) {
        *more += (size_t)ncross;
        if (!(o->p.interval > 0))
            o->p.interval = rep->interval;
        rc = td_pipeline_apply_heights(ls, o->rows, o->nrows, checks, &o->p,
                                       cx);
    }
    if (rc == 0 && o->interactive)
        rc = td_label_entry(o, ls, rep, seen, more, cx);
    if (rc == 0 && o->p.index_every > 0 && o->like)
        rc = td_pipeline_scan_widths(o->like, ls, cx);
    if (rc == 0)
        rc = td_label_check_index(ls, &o->p, checks, cx);
    if (rc == 0 && o->csv_out)
        rc = td_csv_write_heights(o->csv_out, ls, cx);
    if (rc == 0 && o->debug_dir)
        rc = td_pipeline_heights_debug(o->debug_dir, NULL, o->w, o->h, ls,
                                       reads, nreads, vees, nvees, NULL, cx);
    if (rc == 0)
        rc = td_vector_write_lines(o->out, ls, frame->valid ? frame : NULL,
                                   cx);
    free(reads);
    free(vees);
    o->p.vees = NULL, o->p.nvees = 0;
    return rc;
}

int td_cmd_label(int argc, char **argv)
{
    label_opts o;
    td_pts seen = {NULL, 0, 0};
    td_ctx cx;
    td_lines *ls = NULL, *walls = NULL;
    td_label_report rep, checks;
    td_georef frame;
    size_t more = 0;
    int rc;
    memset(&o, 0, sizeof o);
    memset(&rep, 0, sizeof rep);
    memset(&checks, 0, sizeof checks);
    o.p = td_label_defaults();
    td_georef_init(&frame);
    td_ctx_init(&cx);
    if ((rc = parse_args(argc, argv, &o)) != 0)
        goto done;
    if (o.scan && !o.like)
        o.like = o.scan; /* widths and pictures from the same scan */
    /* the lines come back in pixel units, and go out in their own frame */
    if ((rc = hints(&o, &cx)) != 0 ||
        (rc = td_vector_read_lines(o.in, NULL, &ls, NULL, &frame, &cx)) != 0 ||
        (o.walls && (rc = td_vector_read_lines(o.walls, NULL, &walls, NULL,
                                               NULL, &cx)) != 0) ||
        (o.w == 0 && (rc = td_lines_extent(ls, &o.w, &o.h, &cx)) != 0) ||
        ((o.p.walls = walls), 0) ||
        (rc = label(&o, ls, &frame, &rep, &checks, &seen, &more, &cx)) != 0)
        rc = td_cli_fail("label", &cx);
    else if (!o.quiet)
        td_label_summary(ls, &rep, &checks, &o, &seen, more);
done:
    td_georef_clear(&frame);
    td_label_report_free(&rep);
    td_label_report_free(&checks);
    td_lines_free(ls);
    td_lines_free(walls);
    td_opt_points_free(&o.known);
    td_opt_points_free(&o.dep);
    free(o.pts.v);
    free(o.rows);
    free(seen.v);
    return rc == 2 ? 0 : rc;
}
