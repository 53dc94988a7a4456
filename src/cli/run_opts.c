/* run_opts.c: the option table of topodig run, which topodig report takes
 * as it is (run_int.h). */
#include "src/cli/run_int.h"

#include <stdlib.h>
#include <string.h>

static int ink(const char *a, void *t, td_ctx *cx)
{
    return td_binarise_parse_ink(a, t, cx);
}

static int threshold(const char *a, void *t, td_ctx *cx)
{
    return td_binarise_parse_threshold(a, t, cx);
}

/* See run_int.h. */
void td_cli_run_init(td_cli_run *r)
{
    memset(r, 0, sizeof *r);
    r->p = td_run_defaults();
}

/* See run_int.h. */
size_t td_cli_run_opts(td_opt *v, td_cli_run *r)
{
    td_label_params *lp = &r->p.label;
    const td_opt o[TD_CLI_RUN_OPTS - TD_CLI_INTERP_OPTS] = {
        {"interval", 0, TD_OPT_DOUBLE, &lp->interval, 1e-9, 1e9, .meta = "I",
         .help = "contour interval (default: inferred from\nthe printed "
         "labels)", .no_default = 1},
        {"base", 0, TD_OPT_DOUBLE, &lp->base, -1e9, 1e9, .meta = "B",
         .help = "heights are B + k * I"},
        {"known", 0, TD_OPT_POINTS, &r->known, .n = 3, .meta = "X,Y,H",
         .help = "height H at scan pixel X,Y: a point on a line\nor a spot "
         "height (repeatable; needed when the\nsheet has no readable labels)"},
        {"labels", 0, TD_OPT_CHOICE, &r->no_labels, .choices = "read|none",
         .meta = "MODE", .help = "read the printed labels, or not"},
        {"streams", 0, TD_OPT_CHOICE, &r->no_streams, .choices = "read|none",
         .meta = "MODE", .help = "colour scans: read where streams (the\n"
         "water ink) cross the lines: contours' Vs\npoint uphill (ours), "
         "or not"},
        {"depressions", 0, TD_OPT_POINTS, &r->dep, .n = 2, .meta = "X,Y",
         .help = "the ring around X,Y is a depression"},
        {"index-every", 0, TD_OPT_INT, &lp->index_every, 2, 1000, .meta = "N",
         .help = "every Nth contour is drawn thicker: its width\ndecides the "
         "slopes the known points leave open\n(default: the spacing the "
         "widths fit best,\n5, 4, 10 or 2; none without thicker lines)",
         .no_default = 1},
        {"labeller", 0, TD_OPT_CHOICE, &lp->method, .choices = "faces|tree",
         .meta = "L", .help = "faces: one solve over the faces | tree: the\n"
         "containment tree; see topodig label"},
        {"search", 0, TD_OPT_INT, &lp->search, 0, 64, .meta = "N",
         .help = "faces: also try N forests and a local search\nover every "
         "face edge, keep the cheapest (ours;\nslower; helps where a region "
         "folds the\nwrong way; 8 measured best; 0: off)"},
        {"gap-pairs", 0, TD_OPT_DOUBLE, &lp->gap_pairs, 0, 200, .meta = "PX",
         .help = "faces: two free line ends at most PX apart\nthat face each "
         "other are one contour (ours;\nmeasured: see docs/label.md; 0: off;"
         "\ndefault 24 on a colour scan, else 0)", .no_default = 1},
        {"steps", 0, TD_OPT_FLAG, &r->p.steps, .help = "faces: a probe across "
         "contour ink no line\nwas traced on is a step of one level or\nmore, "
         "not one face (ours; measured: see\ndocs/label.md)"},
        {"ink", 0, TD_OPT_FUNC, &r->p.scan.bin, .fn = ink, .meta = "KIND",
         .help = "auto | dark | brown | brown-hue | R,G,B[:tol]\n(default "
         "auto; see topodig scan --help)"},
        {"detint", 0, TD_OPT_FLAG, &r->p.scan.detint, .help =
         "colour scans: inks over a tint divided by\nit (ours; see topodig "
         "scan --help)"},
        {"no-pale", 0, TD_OPT_OFF, &r->p.scan.pale, .help =
         "colour scans: no faded lines traced apart\n(ours; see topodig scan "
         "--help)"},
        {"defringe", 0, TD_OPT_FLAG, &r->p.scan.defringe, .help =
         "colour scans: colour fringes out before the\ninks are found "
         "(ours; see topodig scan --help)"},
        {"pieces", 0, TD_OPT_CHOICE, &r->p.scan.join.keep_pieces,
         .choices = "off|joined|late", .meta = "MODE", .help = "the short "
         "pieces of contour the text\nfilter takes (ours; see topodig scan "
         "--help)"},
        {"alone-gaps", 0, TD_OPT_FLAG, &r->p.scan.join.alone_gaps, .help =
         "crowded printed sheets: short gaps with no\nother line end near "
         "joined (ours; see\ntopodig scan --help)"},
        {"threshold", 0, TD_OPT_FUNC, &r->p.scan.bin, .fn = threshold,
         .meta = "T", .help = "otsu | sauvola | N (default otsu)"},
        {"bridge", 0, TD_OPT_DOUBLE, &r->p.bridge, 0, 1e6, .meta = "PX",
         .help = "join lines of one height across breaks\nbetween their "
         "ends up to PX long (ours;\n0: off; default 5 times the spacing "
         "of\nthe contours, 48 to 160)", .no_default = 1},
        {"save-lines", 0, TD_OPT_OUTPUT, &r->save_lines, .meta = "F", .help =
         "also write the labelled lines the DEM was\ninterpolated from "
         "(.geojson, .gpkg, .shp or\n.dxf by extension, with height,\n"
         "height_source, confidence; within 0.25 px\nof the traced path, as "
         "scan writes them)"},
        {"debug-dir", 0, TD_OPT_STRING, &r->debug_dir, .meta = "DIR", .help =
         "write heights.png: every line over the scan\ncoloured by its "
         "height (thick: known or\nlabelled, dashed: assumed, grey dots: no\n"
         "height; labels read boxed, refused in grey)\nand labels.geojson "
         "(one point per label read:\ntext, value, angle, confidence, used, "
         "why)"}};
    const size_t n = sizeof o / sizeof o[0];
    memcpy(v, o, sizeof o);
    return n + td_cli_interp_opts(v + n, &r->p.interp);
}

/* See run_int.h. */
int td_cli_run_hints(td_cli_run *r, const char *cmd)
{
    td_label_point *k = calloc(r->known.n + 1, sizeof *k);
    size_t i;
    if (!k)
        return td_cli_failf(cmd, "out of memory");
    for (i = 0; i < r->known.n; i++) {
        k[i].x = r->known.v[3 * i];
        k[i].y = r->known.v[3 * i + 1];
        k[i].height = r->known.v[3 * i + 2];
        k[i].id = -1;
    }
    r->p.label.known = k;
    r->p.label.nknown = r->known.n;
    r->p.label.depressions = r->dep.v;
    r->p.label.ndepressions = r->dep.n;
    r->p.read_labels = !r->no_labels;
    r->p.read_streams = !r->no_streams;
    return 0;
}

/* See run_int.h. */
void td_cli_run_free(td_cli_run *r)
{
    free((void *)r->p.label.known);
    r->p.label.known = NULL;
    td_opt_points_free(&r->known);
    td_opt_points_free(&r->dep);
}
