/* topodig scan: scanned sheet -> traced contour lines (GeoJSON). */
#define _GNU_SOURCE
#include "src/cli/cli.h"

#include "src/core/core.h"
#include "src/io/io.h"
#include "scanner/scan.h"

#include <errno.h>
#include <getopt.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

static const char help[] =
    "usage: topodig scan SCAN -o LINES.geojson [options]\n"
    "\n"
    "Binarise a scanned contour sheet, thin the lines (Hilditch), remove\n"
    "spurs, trace every contour (counter-clockwise 3x3 search, 5x5 gap\n"
    "bridging) and write one GeoJSON LineString per contour line.\n"
    "SCAN: TIFF/GeoTIFF (1-bit incl. CCITT G4, 8/16-bit grey, palette, RGB;\n"
    "striped or tiled), PNG or JPEG.\n"
    "\n"
    "options:\n"
    "  -o, --output FILE      the lines (required): .geojson, .gpkg, .shp or\n"
    "                         .dxf (3-D polylines), by extension\n"
    "      --ink KIND         auto | dark | brown | brown-hue | R,G,B[:tol]\n"
    "                         (default auto: dark on a grey scan; on a\n"
    "                         colour scan the sheet's inks are found and\n"
    "                         the one drawing long thin lines is taken;\n"
    "                         brown: the ink found nearest contour brown;\n"
    "                         brown-hue: a fixed brown hue window)\n"
    "      --threshold T      otsu | sauvola | N (0-255)   (default otsu)\n"
    "      --min-speck N      remove ink specks under N px (default 8)\n"
    "      --min-hole N       fill pinholes in the ink under N px (default 8)\n"
    "      --seams N          split touching lines (ours): an ink pixel at\n"
    "                         least N levels lighter than the ink on both\n"
    "                         sides across the lines is the seam between\n"
    "                         two lines and becomes paper (default 24; 0:\n"
    "                         off; otsu and fixed thresholds)\n"
    "      --spur MODE        length | paper | none        (default length)\n"
    "      --spur-max PX      longest spur, px along the skeleton (default 10)\n"
    "      --no-bridge        no 5x5 gap bridging while tracing\n"
    "      --junctions MODE   cut (default, ours): lines stop where\n"
    "                         contours touch and the joiner pairs the ends\n"
    "                         there by direction, never crossing | paper:\n"
    "                         the tracer runs on along the first branch\n"
    "      --no-join          do not join line ends across gaps\n"
    "      --small-gap PX     first join stage: longest small gap joined\n"
    "                         when both ends point across it (default 16)\n"
    "      --max-gap PX       label-gap stage: longest gap joined when the\n"
    "                         ends continue each other and the join crosses\n"
    "                         no line (default 70; <= --small-gap: off);\n"
    "                         curved gaps too when each end curves alike,\n"
    "                         the join following the curve\n"
    "      --no-curves        label-gap stage: straight rule and chords only\n"
    "      --min-length PX    remove open fragments (label digits, text)\n"
    "                         shorter than PX or fitting in a PX box,\n"
    "                         unless both ends continue lines (default 25;\n"
    "                         0: off)\n"
    "      --simplify PX      write the lines within PX of the traced path\n"
    "                         (Douglas-Peucker; default 0.25, 0: one vertex\n"
    "                         per skeleton pixel)\n"
    "      --debug-dir DIR    write mask.png, skeleton.png, despurred.png,\n"
    "                         overlay.png (label-gap joins in magenta) into DIR;\n"
    "                         colour scans: palette.png (the inks found, the\n"
    "                         one taken framed), ink-K.png, inks.txt\n"
    "  -q, --quiet            no progress and no summary\n"
    "  -h, --help             this help\n"
    "\n"
    "Summary on stderr: lines, closed, open, edge, bridged gaps, remaining\n"
    "junctions (touching contours, split), merges (places where contours\n"
    "touch) resolved and left open (a line ends there), seconds.\n"
    "--debug-dir also writes join.txt: gaps joined (label gaps),\n"
    "fragments removed, open ends left, merges.\n";

typedef struct scan_opts {
    const char *in, *out, *debug_dir;
    int quiet;
    double simplify; /* Douglas-Peucker tolerance of the written lines */
    td_scan_params p;
} scan_opts;

enum { O_INK = 256, O_THR, O_SPECK, O_HOLE, O_SPUR, O_SPURMAX, O_NOBRIDGE, O_NOJOIN,
       O_MAXGAP, O_DEBUG, O_SMALLGAP, O_MINLEN, O_NOCURVES, O_JUNC, O_SEAMS,
       O_SIMPLIFY };

static int parse_opt(int c, const char *arg, scan_opts *o, td_ctx *cx)
{
    long v;
    double d;
    switch (c) {
    case 'o': o->out = arg; return 0;
    case 'q': o->quiet = 1; return 0;
    case O_INK: return td_binarise_parse_ink(arg, &o->p.bin, cx);
    case O_THR: return td_binarise_parse_threshold(arg, &o->p.bin, cx);
    case O_SPUR: return td_despur_parse_mode(arg, &o->p.spur, cx);
    case O_NOBRIDGE: o->p.trace.bridge = 0; return 0;
    case O_NOJOIN: o->p.do_join = 0; return 0;
    case O_NOCURVES: o->p.join.curves = 0; return 0;
    case O_JUNC:
        if (strcmp(arg, "cut") && strcmp(arg, "paper"))
            return td_seterr(cx, TD_EINVAL, "--junctions: '%s' is not cut "
                             "or paper", arg);
        o->p.trace.cut = !strcmp(arg, "cut");
        return 0;
    case O_DEBUG: o->debug_dir = arg; return 0;
    case O_SEAMS:
        if (td_cli_parse_int(arg, 0, 255, &v) != 0)
            return td_seterr(cx, TD_EINVAL, "--seams: '%s' is not a whole "
                             "number 0..255", arg);
        o->p.bin.split = (int)v;
        return 0;
    case O_SPECK:
    case O_HOLE:
        if (td_cli_parse_int(arg, 0, 1000000, &v) != 0)
            return td_seterr(cx, TD_EINVAL, "%s: '%s' is not a whole number "
                             "0..1000000", c == O_SPECK ? "--min-speck" :
                             "--min-hole", arg);
        if (c == O_SPECK)
            o->p.bin.min_speck = (int)v;
        else
            o->p.bin.min_hole = (int)v;
        return 0;
    case O_SIMPLIFY:
        if (td_cli_parse_double(arg, 0, 100, &o->simplify) != 0)
            return td_seterr(cx, TD_EINVAL, "--simplify: '%s' is not a "
                             "number 0..100 (px)", arg);
        return 0;
    case O_SPURMAX:
    case O_MAXGAP:
    case O_SMALLGAP:
    case O_MINLEN:
        if (td_cli_parse_double(arg, 0, 10000, &d) != 0)
            return td_seterr(cx, TD_EINVAL, "%s: '%s' is not a number 0..10000",
                             c == O_SPURMAX ? "--spur-max" : c == O_MAXGAP ?
                             "--max-gap" : c == O_SMALLGAP ? "--small-gap" :
                             "--min-length", arg);
        if (c == O_SPURMAX)
            o->p.spur.max_len = d;
        else if (c == O_MAXGAP)
            o->p.join.long_gap = d;
        else if (c == O_SMALLGAP)
            o->p.join.max_gap = d;
        else
            o->p.join.min_length = d;
        return 0;
    }
    return td_seterr(cx, TD_EINVAL, "unknown option (see topodig scan --help)");
}

/* 0: run, 1: error (printed), 2: --help shown. */
static int parse_args(int argc, char **argv, scan_opts *o)
{
    static const struct option lo[] = {
        {"output", 1, 0, 'o'}, {"quiet", 0, 0, 'q'}, {"help", 0, 0, 'h'},
        {"ink", 1, 0, O_INK}, {"threshold", 1, 0, O_THR},
        {"min-speck", 1, 0, O_SPECK}, {"min-hole", 1, 0, O_HOLE}, {"spur", 1, 0, O_SPUR},
        {"spur-max", 1, 0, O_SPURMAX}, {"no-bridge", 0, 0, O_NOBRIDGE},
        {"no-join", 0, 0, O_NOJOIN}, {"max-gap", 1, 0, O_MAXGAP},
        {"debug-dir", 1, 0, O_DEBUG}, {"small-gap", 1, 0, O_SMALLGAP},
        {"min-length", 1, 0, O_MINLEN}, {"no-curves", 0, 0, O_NOCURVES},
        {"junctions", 1, 0, O_JUNC}, {"seams", 1, 0, O_SEAMS},
        {"simplify", 1, 0, O_SIMPLIFY},
        {0, 0, 0, 0}};
    td_ctx cx;
    int c;
    td_ctx_init(&cx);
    opterr = 0;
    while ((c = getopt_long(argc, argv, "o:qh", lo, NULL)) != -1) {
        if (c == 'h') {
            fputs(help, stdout);
            return 2;
        }
        if (c == '?' || c == ':') {
            td_cli_failf("scan", "bad or incomplete option '%s' (see topodig "
                         "scan --help)", argv[optind - 1]);
            return 1;
        }
        if (parse_opt(c, optarg, o, &cx) != 0)
            return td_cli_fail("scan", &cx);
    }
    if (optind != argc - 1)
        return td_cli_failf("scan", "expected one SCAN file (see topodig scan "
                            "--help)");
    o->in = argv[optind];
    if (!o->out)
        return td_cli_failf("scan", "no output: give -o LINES.geojson");
    if (td_cli_check_output("scan", o->out, o->in) != 0)
        return 1;
    return 0;
}

/* The join's statistics, one "name value" per line. */
static int write_join_report(const char *path, const td_join_stats *j,
                             td_ctx *cx)
{
    FILE *f = fopen(path, "w");
    int bad;
    if (!f)
        return td_seterr(cx, TD_EIO, "%s: cannot write (%s)", path,
                         strerror(errno));
    fprintf(f, "joins %zu\nlabel_gap_joins %zu\nclosures %zu\n"
            "fragments_removed %zu\nglyph_rings_removed %zu\nends_open %zu\n"
            "merges %zu\nmerges_left_open %zu\n",
            j->joins, j->long_joins, j->closures, j->fragments, j->glyphs,
            j->ends_open, j->merges, j->merges_open);
    bad = ferror(f);
    if (fclose(f) != 0 || bad)
        return td_seterr(cx, TD_EIO, "%s: cannot write", path);
    return 0;
}

static void fill(td_image *im, int x0, int y0, int w, int h,
                 const uint8_t *rgb)
{
    int x, y;
    for (y = y0; y < y0 + h && y < im->h; y++)
        for (x = x0; x < x0 + w && x < im->w; x++)
            memcpy(im->data + (size_t)y * im->stride + 3 * (size_t)x, rgb, 3);
}

/* palette.png: one row per colour found: its swatch (framed black when it
 * is the contour ink, grey when it is contour ink too, hatched when it is
 * a tint) and a bar as long as its share of the sheet (500 px = 100 %);
 * ink-K.png: the pixels each colour K explains; inks.txt: the numbers. */
static int write_palette(const char *dir, const td_image *im,
                         const td_palette *pal, td_ctx *cx)
{
    static const uint8_t white[3] = {255, 255, 255}, black[3] = {0, 0, 0},
                         grey[3] = {150, 150, 150};
    static const char *const role[3] = {"paper", "tint", "ink"};
    char path[4096];
    td_image *pic = td_image_new(580, 50 * pal->n + 10, 3, cx);
    td_grid_u8 *lbl = NULL;
    FILE *f;
    int i, rc = 0, x, y;
    if (!pic)
        return TD_ENOMEM;
    fill(pic, 0, 0, pic->w, pic->h, white);
    for (i = 0; i < pal->n; i++) {
        const td_ink *k = &pal->ink[i];
        int y0 = 10 + 50 * i;
        if (i == pal->chosen || (pal->also >> i & 1u))
            fill(pic, 7, y0 - 3, 46, 46, i == pal->chosen ? black : grey);
        fill(pic, 10, y0, 40, 40, k->rgb);
        if (k->role == TD_INKROLE_TINT)
            for (y = 0; y < 40; y++)
                for (x = 0; x < 40; x++)
                    if ((x + y) % 8 == 0)
                        fill(pic, 10 + x, y0 + y, 1, 1, white);
        fill(pic, 70, y0 + 12, 2 + (int)(500.0 * k->share), 16, k->rgb);
    }
    snprintf(path, sizeof path, "%s/palette.png", dir);
    rc = td_png_write(path, pic, cx);
    td_image_free(pic);
    if (rc != 0)
        return rc;
    if (!(lbl = td_grid_u8_new(im->w, im->h, cx)))
        return TD_ENOMEM;
    if ((rc = td_palette_label(pal, im, lbl, cx)) != 0)
        goto done;
    for (i = 0; i < pal->n && rc == 0; i++) {
        td_grid_u8 *m;
        if (i == pal->paper)
            continue;
        if (!(m = td_grid_u8_new(im->w, im->h, cx))) {
            rc = TD_ENOMEM;
            break;
        }
        for (y = 0; y < im->h; y++)
            for (x = 0; x < im->w; x++)
                TD_AT(m, x, y) = TD_AT(lbl, x, y) == i;
        snprintf(path, sizeof path, "%s/ink-%d.png", dir, i);
        rc = td_png_write_u8(path, m, 1, cx);
        td_grid_u8_free(m);
    }
    snprintf(path, sizeof path, "%s/inks.txt", dir);
    if (rc == 0 && !(f = fopen(path, "w")))
        rc = td_seterr(cx, TD_EIO, "%s: cannot write (%s)", path,
                       strerror(errno));
    if (rc == 0) {
        int bad;
        fprintf(f, "# index role rgb share width_px long_stroke_px_per_Mpx "
                   "contour\n");
        for (i = 0; i < pal->n; i++)
            fprintf(f, "%d %s #%02x%02x%02x %.4f %.2f %.0f %s\n", i,
                    role[pal->ink[i].role], pal->ink[i].rgb[0],
                    pal->ink[i].rgb[1], pal->ink[i].rgb[2],
                    pal->ink[i].share, pal->ink[i].width,
                    pal->ink[i].line_len,
                    i == pal->chosen             ? "taken"
                    : (pal->also >> i & 1u) ? "also"
                                                 : "-");
        bad = ferror(f);
        if (fclose(f) != 0 || bad)
            rc = td_seterr(cx, TD_EIO, "%s: cannot write", path);
    }
done:
    td_grid_u8_free(lbl);
    return rc;
}

static int write_debug(const scan_opts *o, const td_image *im,
                       const td_scan_result *r, td_ctx *cx)
{
    char path[4096];
    td_image *ov = NULL;
    int rc;
    if (mkdir(o->debug_dir, 0777) != 0 && errno != EEXIST)
        return td_seterr(cx, TD_EIO, "%s: cannot create folder (%s)",
                         o->debug_dir, strerror(errno));
#define DPATH(name) (snprintf(path, sizeof path, "%s/%s", o->debug_dir, name), path)
    if ((rc = td_png_write_u8(DPATH("mask.png"), r->mask, 1, cx)) != 0 ||
        (rc = td_png_write_u8(DPATH("skeleton.png"), r->skeleton, 1, cx)) != 0 ||
        (rc = td_png_write_u8(DPATH("despurred.png"), r->despurred, 1, cx)) != 0 ||
        (rc = td_draw_overlay(im, r->lines, &ov, cx)) != 0)
        return rc;
    if (r->join.segments) { /* label-gap joins, magenta */
        static const uint8_t magenta[3] = {230, 0, 230};
        size_t i;
        for (i = 0; i < r->join.segments->n; i++)
            td_draw_line(ov, &r->join.segments->v[i], magenta);
    }
    rc = td_png_write(DPATH("overlay.png"), ov, cx);
    if (rc == 0)
        rc = write_join_report(DPATH("join.txt"), &r->join, cx);
    if (rc == 0 && r->palette.n > 0)
        rc = write_palette(o->debug_dir, im, &r->palette, cx);
#undef DPATH
    td_image_free(ov);
    return rc;
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
        rc = write_debug(&o, im, &res, &cx);
    if (rc == 0)
        rc = td_lines_simplify(res.lines, o.simplify, &cx);
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
