/* topodig scan: scanned sheet -> traced contour lines (GeoJSON). */
#include "src/cli/cli.h"

#include "src/core/core.h"
#include "src/io/io.h"
#include "scanner/scan.h"
#include "src/pipeline/pipeline.h"

#include <stdio.h>
#include <string.h>

typedef struct scan_opts {
    const char *in, *out, *debug_dir, *walls;
    int quiet;
    double simplify; /* Douglas-Peucker tolerance of the written lines */
    td_scan_params p;
} scan_opts;

static int ink(const char *a, void *t, td_ctx *cx)
{
    return td_binarise_parse_ink(a, t, cx);
}

static int threshold(const char *a, void *t, td_ctx *cx)
{
    return td_binarise_parse_threshold(a, t, cx);
}

/* --wide-own: auto (a negative value) or PENS in 0..100. */
static int wide_own(const char *a, void *t, td_ctx *cx)
{
    double *v = t;
    if (!strcmp(a, "auto")) {
        *v = -1.0;
        return 0;
    }
    if (td_cli_parse_double(a, 0, 100, v) != 0)
        return td_seterr(cx, TD_EINVAL, "--wide-own: auto or a number of "
                         "pens 0-100, not \"%s\"", a);
    return 0;
}

static int spur(const char *a, void *t, td_ctx *cx)
{
    return td_despur_parse_mode(a, t, cx);
}

/* 0: run, 1: error (printed), 2: --help shown. */
static int parse_args(int argc, char **argv, scan_opts *o)
{
    td_scan_params *p = &o->p;
    const td_opt opts[] = {
        {"ink", 0, TD_OPT_FUNC, &p->bin, .fn = ink, .meta = "KIND", .help =
         "auto | dark | brown | brown-hue | R,G,B[:tol]\n(default auto: dark "
         "on a grey scan; on a\ncolour scan the sheet's inks are found and\n"
         "the one drawing long thin lines is taken;\nbrown: the same among the "
         "inks near\ncontour brown; brown-hue: a fixed brown\nhue window)"},
        {"threshold", 0, TD_OPT_FUNC, &p->bin, .fn = threshold, .meta = "T",
         .help = "otsu | sauvola | N (0-255) (default otsu)"},
        {"min-speck", 0, TD_OPT_INT, &p->bin.min_speck, 0, 1000000,
         .meta = "N", .help = "remove ink specks under N px"},
        {"min-hole", 0, TD_OPT_INT, &p->bin.min_hole, 0, 1000000, .meta = "N",
         .help = "fill pinholes in the ink under N px"},
        {"seams", 0, TD_OPT_INT, &p->bin.split, 0, 255, .meta = "N", .help =
         "split touching lines (ours): an ink pixel at\nleast N levels "
         "lighter than the ink on both\nsides across the lines is the seam "
         "between\ntwo lines and becomes paper (0: off; otsu\nand fixed "
         "thresholds)"},
        {"detint", 0, TD_OPT_FLAG, &p->detint, .help =
         "colour scans (ours): inks printed over a\ntint (woodland green) "
         "divided by it, so\na red road over the tint reads red, not\n"
         "brown (see docs/binarise.md, 'Inks over\na tint')"},
        {"defringe", 0, TD_OPT_FLAG, &p->defringe, .help =
         "colour scans (ours): each ink pixel first\ntakes the colour of the "
         "ink around it,\ncolour fringes and JPEG's bled colour out\n(for "
         "strongly fringed scans; it can also\nmerge two near inks: see "
         "docs/binarise.md)"},
        {"no-local-level", 0, TD_OPT_OFF, &p->bin.local_level, .help =
         "one Otsu level everywhere (by default, ours,\ntiles where the ink "
         "came out paler than\nthe sheet's threshold lower)"},
        {"no-pale", 0, TD_OPT_OFF, &p->pale, .help =
         "colour scans: no faded lines traced apart\n(by default, ours, thin "
         "ridges of the\ncontour ink's colour too pale for the\nthreshold, "
         "clear of the ink, are traced\non their own and joined by their "
         "ends:\nsee docs/scanner.md, 'Faded lines apart')"},
        {"cores", 0, TD_OPT_FLAG, &p->bin.cores, .help =
         "colour scans, faded print (ours): thin\nridges of the contour "
         "ink's strength\njoined to the ink are ink (more of a faded\n"
         "sheet's lines; the heights may come out\nworse: see "
         "docs/binarise.md)"},
        {"spur", 0, TD_OPT_FUNC, &p->spur, .fn = spur, .meta = "MODE",
         .help = "length | paper | none (default length)"},
        {"spur-max", 0, TD_OPT_DOUBLE, &p->spur.max_len, 0, 10000,
         .meta = "PX", .help = "longest spur, px along the skeleton"},
        {"bridge", 0, TD_OPT_CHOICE, &p->trace.bridge,
         .choices = "none|paper|ahead", .meta = "MODE", .help = "5x5 gap "
         "bridging while tracing: ahead (ours):\nthe ring's pixel most "
         "nearly straight ahead\n(within 50 degrees) | paper: the first "
         "one\ncounter-clockwise | none"},
        {"no-bridge", 0, TD_OPT_OFF, &p->trace.bridge, .help = "the same as "
         "--bridge none"},
        {"junctions", 0, TD_OPT_CHOICE, &p->trace.cut, .choices = "paper|cut",
         .meta = "MODE", .help = "cut (ours): lines stop where contours "
         "touch\nand the joiner pairs the ends there by\ndirection, never "
         "crossing | paper: the\ntracer runs on along the first branch"},
        {"no-join", 0, TD_OPT_OFF, &p->do_join, .help = "do not join line "
         "ends across gaps"},
        {"small-gap", 0, TD_OPT_DOUBLE, &p->join.max_gap, 0, 10000,
         .meta = "PX", .help = "first join stage: longest small gap joined\n"
         "when both ends point across it"},
        {"max-gap", 0, TD_OPT_DOUBLE, &p->join.long_gap, 0, 10000,
         .meta = "PX", .help = "label-gap stage: longest gap joined when the\n"
         "ends continue each other and the join crosses\nno line (<= "
         "--small-gap: off); curved gaps\ntoo when each end curves alike, "
         "the join\nfollowing the curve"},
        {"stream-gap", 0, TD_OPT_DOUBLE, &p->join.cross_gap, 0, 10000,
         .meta = "PX", .help = "colour scans (ours): ends this near on both "
         "sides\nof a stream (the water ink) whose tangents\nmeet on it, "
         "or that face each other across\nit, are joined through it: a "
         "contour the\nstream's ink hides at its V (0: off)"},
        {"no-curves", 0, TD_OPT_OFF, &p->join.curves, .help = "label-gap "
         "stage: straight rule and chords only"},
        {"alone-gaps", 0, TD_OPT_FLAG, &p->join.alone_gaps, .help = "crowded "
         "printed sheets (ours): after the\nother stages join gaps of 3.5-8 "
         "px whose\nends head into them with no other open end\nnear (a "
         "faded contour broken where it\nbends; the DEMs of the crowded "
         "prints\nbetter, of some others worse:\ndocs/scanner.md)"},
        {"no-grid", 0, TD_OPT_OFF, &p->straight.on, .help = "keep long "
         "straight lines (by default the map\ngrid's lines across the sheet "
         "are erased\nfrom the ink, ours: docs/scanner.md)"},
        {"no-flank-cut", 0, TD_OPT_OFF, &p->flank_cut, .help = "colour "
         "scans: keep traced stretches that run\nalong a road or another "
         "ink (by default cut\nout: its edges look like contour ink; ours)"},
        {"no-foreign-cut", 0, TD_OPT_OFF, &p->foreign_cut, .help = "colour "
         "scans: keep short lines whose colour is\nno shade of the contour "
         "ink (by default\ndropped: text, road dashes; ours)"},
        {"no-border-cut", 0, TD_OPT_OFF, &p->border_cut, .help = "keep "
         "lines whole where they turn back at\nthe sheet's border (by "
         "default cut there:\ntwo contours leaving the sheet side by "
         "side,\ntraced as one V; ours)"},
        {"min-length", 0, TD_OPT_DOUBLE, &p->join.min_length, 0, 10000,
         .meta = "PX", .help = "remove open fragments (label digits, text)\n"
         "shorter than PX or fitting in a PX box,\nunless both ends continue "
         "lines (0: off)"},
        {"pieces", 0, TD_OPT_CHOICE, &p->join.keep_pieces,
         .choices = "off|joined|late", .meta = "MODE", .help = "faded or "
         "crowded sheets (ours): the short\npieces the text filter above "
         "would take\nthat continue a longer line (not on a\nroad), lie "
         "between two junctions or were\ntraced from faded ridges: late: "
         "kept as\nlines of their own after the joins (\"piece\":\ntrue; "
         "label gives one the height of the\nline whose end it continues, "
         "when the\nevidence decided that line's) | joined:\nkept and "
         "joined like any line (the\nheights may come out worse) | off: "
         "removed\n(docs/scanner.md)"},
        {"keep-pieces", 0, TD_OPT_FLAG, &p->join.keep_pieces,
         .n = TD_PIECES_JOINED, .help = "the same as --pieces joined"},
        {"ticks", 0, TD_OPT_INT, &p->ticks, 0, 1000, .meta = "N", .help =
         "a ring with at least N ticks on its inside\n(printed maps' "
         "depression contours) is written\nwith depression: true, which "
         "label reads\n(ours; 0: not read)"},
        {"wide-cut", 0, TD_OPT_DOUBLE, &p->wide_cut, 0, 100, .meta = "PENS",
         .help = "end the lines where the ink across them\n(seams between "
         "touching lines included) is\nwider than PENS line widths with "
         "another\nline inside (contours crowding into one\nblob; ours; 0: "
         "off)"},
        {"wide-rib", 0, TD_OPT_DOUBLE, &p->wide_rib, 0, 100, .meta = "PENS",
         .help = "where contours crowd and the seams split\nsuch a blob into "
         "one rib a contour, end\nthem only where their rib is wider than\n"
         "PENS line widths (two ribs touching; ours;\n0: the whole blob)"},
        {"no-hairpin-cut", 0, TD_OPT_OFF, &p->hairpin_cut, .help = "where "
         "contours crowd, do not cut lines\nwhere they turn back sharply (at "
         "a V's tip:\ntwo contours met there, or one contour's\narms touch; "
         "ours)"},
        {"wide-own", 0, TD_OPT_FUNC, &p->wide_own, .fn = wide_own,
         .meta = "PENS", .help = "and where it is wider than the line's own\n"
         "width + PENS line widths with another line\nending there (two "
         "contours' inks overlapping;\nours; 0: off; default auto: 0.75 "
         "where the\nink's edges are crisp, under 0.55 px, else off)"},
        {"simplify", 0, TD_OPT_DOUBLE, &o->simplify, 0, 100, .meta = "PX",
         .help = "write the lines within PX of the traced path\n"
         "(Douglas-Peucker; 0: one vertex per\nskeleton pixel)"},
        {"walls", 0, TD_OPT_OUTPUT, &o->walls, .meta = "WALLS.geojson",
         .help = "also write where lines were cut out of a\nblob of crowded "
         "contours (--wide-cut), for\n`label --walls`: no face runs "
         "through them"},
        {"debug-dir", 0, TD_OPT_STRING, &o->debug_dir, .meta = "DIR", .help =
         "write mask.png, skeleton.png, despurred.png,\noverlay.png "
         "(label-gap joins in magenta, the\npieces kept apart in black), "
         "join.txt;\ncolour scans: palette.png "
         "(the inks\nfound, the one taken framed), ink-K.png, inks.txt,\n"
         "other.png (the other inks' strokes)"},
        {NULL}};
    const td_cmd c = {
        "scan", "SCAN -o LINES.geojson [options]",
        "Binarise a scanned contour sheet, thin the lines (Hilditch), remove\n"
        "spurs, trace every contour (counter-clockwise 3x3 search, 5x5 gap\n"
        "bridging) and write one line per contour: .geojson, .gpkg, .shp or\n"
        ".dxf (3-D polylines), by extension.  SCAN: TIFF/GeoTIFF (1-bit incl.\n"
        "CCITT G4, 8/16-bit grey, palette, RGB; striped or tiled), PNG or\n"
        "JPEG.\n",
        "Summary on stderr: lines, closed, open, edge, bridged gaps, remaining\n"
        "junctions (touching contours, split), merges (places where contours\n"
        "touch) resolved and left open (a line ends there), seconds.\n",
        opts, "one SCAN file", 1, 1, &o->in, &o->out, "LINES.geojson",
        &o->quiet};
    return td_opt_parse(&c, argc, argv);
}

/* One summary line (its format is kept stable: scripts read it). */
static void summary(const td_scan_result *r, double secs)
{
    const td_trace_stats *t = &r->trace;
    size_t closed = 0, edge = 0, i, n = r->lines->n;
    for (i = 0; i < n; i++) {
        closed += r->lines->v[i].closed != 0;
        edge += r->lines->v[i].edge != 0;
    }
    fprintf(stderr,
            "scan: %zu lines, %zu closed, %zu open, %zu edge, %zu bridged "
            "gaps, %zu remaining junctions, %zu merges resolved, %zu left "
            "open, %.2f s\n",
            n, closed, n - closed, edge, t->bridged + r->join.joins,
            t->junctions, r->join.merges - r->join.merges_open,
            r->join.merges_open, secs);
    if (r->palette.n > 0)
        td_cli_print_palette("scan", &r->palette);
    if (r->wide_cuts > 0 && r->wide_own > 0)
        fprintf(stderr, "scan: %zu line%s ended where contours crowd into one "
                "blob of ink or their inks overlap (crisp ink: edges %.2f "
                "px)\n", r->wide_cuts, r->wide_cuts == 1 ? "" : "s", r->edge);
    else if (r->wide_cuts > 0)
        fprintf(stderr, "scan: %zu line%s ended where contours crowd into one "
                "blob of ink\n", r->wide_cuts, r->wide_cuts == 1 ? "" : "s");
    if (r->join.gaps_open > 0)
        fprintf(stderr, "scan: %zu line end%s left open where a neighbour's "
                "end was as near (joined, the line would step onto the next "
                "contour)\n", r->join.gaps_open,
                r->join.gaps_open == 1 ? "" : "s");
    if (r->join.late_pieces > 0)
        fprintf(stderr, "scan: %zu short piece%s of contour kept as line%s of "
                "%s own, not joined (\"piece\": true; --pieces off: "
                "removed)\n", r->join.late_pieces,
                r->join.late_pieces == 1 ? "" : "s",
                r->join.late_pieces == 1 ? "" : "s",
                r->join.late_pieces == 1 ? "its" : "their");
    if (r->pale > 0)
        fprintf(stderr, "scan: %zu faded piece%s of contour traced apart from "
                "the ink (--no-pale: without)\n", r->pale,
                r->pale == 1 ? "" : "s");
    if (r->foreign > 0)
        fprintf(stderr,
                "scan: %zu short line%s in another ink's colour dropped (text, "
                "road dashes)\n",
                r->foreign, r->foreign == 1 ? "" : "s");
    if (r->join.road_pieces > 0)
        fprintf(stderr,
                "scan: %zu straight piece%s lined up along a road "
                "removed (the road cut at every contour it crosses)\n",
                r->join.road_pieces, r->join.road_pieces == 1 ? "" : "s");
    if (r->border_cuts > 0)
        fprintf(stderr, "scan: %zu line%s cut where %s turned back at the "
                "sheet's border (two contours leaving it, traced as one)\n",
                r->border_cuts, r->border_cuts == 1 ? "" : "s",
                r->border_cuts == 1 ? "it" : "they");
    if (r->flank_cuts > 0)
        fprintf(stderr, "scan: %zu stretch%s along roads or other inks cut "
                "out (their flanks look like contour ink)\n", r->flank_cuts,
                r->flank_cuts == 1 ? "" : "es");
    if (r->join.alone_joins > 0)
        fprintf(stderr, "scan: %zu short gap%s with no other line end near "
                "joined (--alone-gaps)\n", r->join.alone_joins,
                r->join.alone_joins == 1 ? "" : "s");
    if (r->join.cross_joins > 0)
        fprintf(stderr, "scan: %zu gap%s where streams hide a contour "
                "joined across the water\n", r->join.cross_joins,
                r->join.cross_joins == 1 ? "" : "s");
    if (r->join.water_turns > 0)
        fprintf(stderr, "scan: %zu line%s cut where %s turned back at a "
                "stream (two contours linked by its bank)\n",
                r->join.water_turns, r->join.water_turns == 1 ? "" : "s",
                r->join.water_turns == 1 ? "it" : "they");
    if (r->depressions > 0)
        fprintf(stderr, "scan: %zu ring%s read as depression%s (ticks "
                "inside)\n", r->depressions, r->depressions == 1 ? "" : "s",
                r->depressions == 1 ? "" : "s");
}

int td_cmd_scan(int argc, char **argv)
{
    scan_opts o;
    td_ctx cx;
    td_cli_progress pr;
    td_image *im = NULL;
    td_georef geo;
    td_scan_result res;
    double t0 = td_now();
    int rc;
    memset(&o, 0, sizeof o);
    memset(&res, 0, sizeof res);
    o.p = td_scan_defaults();
    o.simplify = 0.25;
    if ((rc = parse_args(argc, argv, &o)) != 0)
        return rc == 2 ? 0 : 1;
    td_ctx_init(&cx);
    td_georef_init(&geo);
    td_cli_progress_init(&pr, &cx, o.quiet);
    o.p.keep_debug = o.debug_dir != NULL;
    rc = td_image_read(o.in, &im, &geo, &cx);
    if (rc == 0 && (rc = td_scan(im, &o.p, &res, &cx)) != 0 && cx.msg[0] &&
        !strstr(cx.msg, o.in)) {
        char m[sizeof cx.msg + 64];
        snprintf(m, sizeof m, "%.60s: %s", o.in, cx.msg);
        memcpy(cx.msg, m, sizeof cx.msg - 1);
        cx.msg[sizeof cx.msg - 1] = '\0';
    }
    /* the debug pictures first: when they fail, the output (new or old)
       is left as it was */
    if (rc == 0 && o.debug_dir)
        rc = td_pipeline_scan_debug(o.debug_dir, im, &res, &cx);
    if (rc == 0)
        rc = td_lines_simplify(res.lines, o.simplify, &cx);
    if (rc == 0 && o.walls) { /* none cut (or --wide-cut 0): no feature */
        td_lines *none = res.walls ? NULL : td_lines_new(&cx);
        rc = res.walls || none
                 ? td_vector_write_lines(o.walls, res.walls ? res.walls : none,
                                         &geo, &cx)
                 : TD_ENOMEM;
        td_lines_free(none);
    }
    if (rc == 0)
        rc = td_vector_write_lines(o.out, res.lines, &geo, &cx);
    td_cli_progress_done(&pr);
    if (rc == 0 && !o.quiet)
        summary(&res, td_now() - t0);
    td_scan_result_free(&res);
    td_image_free(im);
    td_georef_clear(&geo);
    return rc == 0 ? 0 : td_cli_fail("scan", &cx);
}
