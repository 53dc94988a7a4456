/* topodig label: traced lines -> lines with heights (GeoJSON).
 * Automatic heights from known points (scanner/label.h, ours); the paper's
 * way, one typed height per line (001 §2.3), is --heights after editing the
 * --export-csv file. */
#define _GNU_SOURCE
#include "src/cli/cli.h"

#include "src/core/core.h"
#include "src/io/io.h"
#include "scanner/binarise.h"
#include "scanner/label.h"
#include "scanner/ocr.h"
#include "scanner/scan.h"
#include "scanner/width.h"

#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static const char help[] =
    "usage: topodig label LINES.geojson -o LABELLED.geojson\n"
    "                     [--sheet SCAN] [--interval I] [--base B]\n"
    "                     [--known X,Y,H]... [options]\n"
    "\n"
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
    "interval per nesting step, rings rising).\n"
    "\n"
    "options:\n"
    "  -o, --output FILE      the labelled lines (required): .geojson, .gpkg,\n"
    "                         .shp or .dxf; LINES may be any of these too\n"
    "      --sheet SCAN       read the height labels printed on the scan the\n"
    "                         lines were traced from (Tesseract); with them\n"
    "                         --interval may be left out (inferred)\n"
    "      --interval I       contour interval (> 0; required without\n"
    "                         --sheet)\n"
    "      --base B           heights are B + k * I (default 0)\n"
    "      --known X,Y,H      a point on (within 3 px of) a line: its height;\n"
    "                         elsewhere: a spot height (repeatable)\n"
    "      --known-file CSV   x,y,height rows (a header line is skipped)\n"
    "      --depressions X,Y  the ring around X,Y is a depression (repeatable)\n"
    "      --heights CSV      id,height rows: these lines' heights (e.g. an\n"
    "                         edited --export-csv file; an empty height:\n"
    "                         none given)\n"
    "      --export-csv FILE  write id,height of every line\n"
    "      --size WxH         sheet size in px (default: the lines' extent)\n"
    "      --interactive      the paper's way: write a label sheet PNG, then\n"
    "                         ask each line's height on stderr, reading\n"
    "                         answers from stdin: Enter accepts the\n"
    "                         suggestion, a number sets the height (the\n"
    "                         others are re-suggested from it), q keeps the\n"
    "                         rest automatic; end of input accepts the rest\n"
    "      --label-sheet PNG  the label sheet (default LABELLED.geojson.png)\n"
    "      --like SCAN        draw the label sheet over the scan; with\n"
    "                         --index-every, measure the line widths on it\n"
    "                         when the lines carry none\n"
    "      --index-every N    every Nth level (base + k*N*I) is an index\n"
    "                         contour drawn thicker: warn about each line\n"
    "                         whose ink width (the scan's 'width' property)\n"
    "                         disagrees with its height\n"
    "      --thick-ratio R    thick/thin width ratio that tells index lines\n"
    "                         (default 1.3)\n"
    "      --no-missing       tree: a known point one interval off the\n"
    "                         nesting is a contradiction, not a missing\n"
    "                         contour\n"
    "      --labeller L       faces (default) | tree\n"
    "      --debug-dir DIR    write heights.png: the lines coloured by height\n"
    "                         (over --like SCAN when given; thick: known,\n"
    "                         dashed: assumed, grey dots: no height)\n"
    "  -q, --quiet            no summary or warnings\n"
    "  -h, --help             this help\n"
    "\n"
    "Coordinates are scan pixels (column, row).  Summary on stderr:\n"
    "lines labelled, undetermined, warnings, and where the heights came\n"
    "from.  Exit 1 on bad input; known points that contradict each other\n"
    "are a warning naming them and the solver's choice (tree: exit 1).\n";

typedef struct pts {
    td_label_point *v;
    size_t n, cap;
} pts;

typedef struct label_opts {
    const char *debug_dir, *scan;
    const char *in, *out, *csv_out, *sheet, *like;
    int quiet, w, h, interactive, index_every, no_missing, tree;
    double base, interval, thick_ratio;
    pts known;
    double *dep;
    size_t ndep;
} label_opts;

enum { O_INTERVAL = 256, O_BASE, O_KNOWN, O_KNOWNF, O_DEPR, O_HEIGHTS,
       O_EXPORT, O_SIZE, O_INTER, O_SHEET, O_LIKE, O_INDEX, O_THICK,
       O_NOMISS, O_LABELLER, O_DEBUG, O_SCAN };

static int push_pt(pts *a, double x, double y, double h, long id, td_ctx *cx)
{
    if (a->n == a->cap) {
        size_t cap = a->cap ? 2 * a->cap : 16;
        td_label_point *v = realloc(a->v, cap * sizeof *v);
        if (!v)
            return td_seterr(cx, TD_ENOMEM, "out of memory");
        a->v = v, a->cap = cap;
    }
    a->v[a->n].x = x, a->v[a->n].y = y, a->v[a->n].height = h;
    a->v[a->n++].id = id;
    return 0;
}

/* "A,B[,C]" with n numbers. */

/* "id," or "id" (spaces allowed): a row without a height; the id in v[0]. */
static int empty_height(const char *line, double *v)
{
    char buf[64];
    size_t n = strcspn(line, ",");
    const char *t = line + n;
    if (n >= sizeof buf)
        return 0;
    if (*t == ',')
        for (t++; *t == ' ' || *t == '\t'; t++)
            ;
    if (*t != '\0')
        return 0;
    memcpy(buf, line, n);
    buf[n] = '\0';
    return td_cli_parse_nums(buf, v, 1) == 0;
}

/* Rows of a CSV file: x,y,height (ids 0) or id,height (ids 1); in id
 * files an empty height is no height (undetermined). */
static int read_csv(const char *path, int ids, pts *a, td_ctx *cx)
{
    FILE *f;
    char line[512];
    long no = 0;
    int rc = 0;
    if (td_check_input(path, cx) != 0)
        return TD_EINVAL;
    f = fopen(path, "r");
    if (!f)
        return td_seterr(cx, TD_EIO, "%s: cannot open (%s)", path,
                         strerror(errno));
    while (rc == 0 && fgets(line, sizeof line, f)) {
        double v[3];
        no++;
        line[strcspn(line, "\r\n")] = '\0';
        if (line[0] == '\0' || line[0] == '#')
            continue;
        if (ids && empty_height(line, v)) {
            if (v[0] < 0 || v[0] != floor(v[0]))
                rc = td_seterr(cx, TD_EINVAL, "%s:%ld: bad id", path, no);
            continue; /* "id," : undetermined, no height given */
        }
        if (td_cli_parse_nums(line, v, ids ? 2 : 3) != 0) {
            if (no == 1 && strpbrk(line, "abcdefghijklmnopqrstuvwxyz"))
                continue; /* a header */
            rc = td_seterr(cx, TD_EINVAL, "%s:%ld: expected %s, got '%.40s'",
                           path, no, ids ? "id,height" : "x,y,height", line);
        } else if (ids && (v[0] < 0 || v[0] != floor(v[0]))) {
            rc = td_seterr(cx, TD_EINVAL, "%s:%ld: bad id", path, no);
        } else {
            rc = ids ? push_pt(a, 0, 0, v[1], (long)v[0], cx)
                     : push_pt(a, v[0], v[1], v[2], -1, cx);
        }
    }
    fclose(f);
    return rc;
}

static int parse_opt(int c, const char *arg, label_opts *o, pts *heights,
                     td_ctx *cx)
{
    double v[3];
    switch (c) {
    case 'o': o->out = arg; return 0;
    case 'q': o->quiet = 1; return 0;
    case O_EXPORT: o->csv_out = arg; return 0;
    case O_INTER: o->interactive = 1; return 0;
    case O_SHEET: o->sheet = arg; return 0;
    case O_SCAN: o->scan = arg; return 0;
    case O_LIKE: o->like = arg; return 0;
    case O_DEBUG: o->debug_dir = arg; return 0;
    case O_NOMISS: o->no_missing = 1; return 0;
    case O_LABELLER: return td_cli_parse_labeller(arg, &o->tree, cx);
    case O_INDEX: {
        long n;
        if (td_cli_parse_int(arg, 2, 1000, &n) != 0)
            return td_seterr(cx, TD_EINVAL, "--index-every: '%s' is not an "
                             "integer in 2..1000", arg);
        o->index_every = (int)n;
        return 0;
    }
    case O_THICK:
        if (td_cli_parse_double(arg, 1.01, 100, v) != 0)
            return td_seterr(cx, TD_EINVAL, "--thick-ratio: '%s' is not a "
                             "number in 1.01..100", arg);
        o->thick_ratio = v[0];
        return 0;
    case O_INTERVAL:
    case O_BASE:
        if (td_cli_parse_double(arg, c == O_BASE ? -1e9 : 1e-9, 1e9, v) != 0)
            return td_seterr(cx, TD_EINVAL, "%s: '%s' is not a %snumber",
                             c == O_BASE ? "--base" : "--interval", arg,
                             c == O_BASE ? "" : "positive ");
        *(c == O_BASE ? &o->base : &o->interval) = v[0];
        return 0;
    case O_KNOWN:
        if (td_cli_parse_nums(arg, v, 3) != 0)
            return td_seterr(cx, TD_EINVAL, "--known: '%s' is not X,Y,H", arg);
        return push_pt(&o->known, v[0], v[1], v[2], -1, cx);
    case O_DEPR: {
        double *d;
        if (td_cli_parse_nums(arg, v, 2) != 0)
            return td_seterr(cx, TD_EINVAL, "--depressions: '%s' is not X,Y",
                             arg);
        if (!(d = realloc(o->dep, (2 * o->ndep + 2) * sizeof *d)))
            return td_seterr(cx, TD_ENOMEM, "out of memory");
        o->dep = d;
        d[2 * o->ndep] = v[0], d[2 * o->ndep++ + 1] = v[1];
        return 0;
    }
    case O_KNOWNF: return read_csv(arg, 0, &o->known, cx);
    case O_HEIGHTS: return read_csv(arg, 1, heights, cx);
    case O_SIZE: {
        long w, h;
        char buf[64], *x;
        snprintf(buf, sizeof buf, "%s", arg);
        if (!(x = strchr(buf, 'x')) || (*x = '\0', 0) ||
            td_cli_parse_int(buf, 1, TD_MAX_DIM, &w) != 0 ||
            td_cli_parse_int(x + 1, 1, TD_MAX_DIM, &h) != 0)
            return td_seterr(cx, TD_EINVAL, "--size: '%s' is not WxH", arg);
        o->w = (int)w, o->h = (int)h;
        return 0;
    }
    }
    return td_seterr(cx, TD_EINVAL, "unknown option (see topodig label --help)");
}

/* 0: run, 1: error (printed), 2: --help shown. */
static int parse_args(int argc, char **argv, label_opts *o, pts *heights)
{
    static const struct option lo[] = {
        {"output", 1, 0, 'o'}, {"quiet", 0, 0, 'q'}, {"help", 0, 0, 'h'},
        {"interval", 1, 0, O_INTERVAL}, {"base", 1, 0, O_BASE},
        {"known", 1, 0, O_KNOWN}, {"known-file", 1, 0, O_KNOWNF},
        {"depressions", 1, 0, O_DEPR}, {"heights", 1, 0, O_HEIGHTS},
        {"export-csv", 1, 0, O_EXPORT}, {"size", 1, 0, O_SIZE},
        {"interactive", 0, 0, O_INTER}, {"label-sheet", 1, 0, O_SHEET},
        {"sheet", 1, 0, O_SCAN},
        {"like", 1, 0, O_LIKE}, {"index-every", 1, 0, O_INDEX},
        {"thick-ratio", 1, 0, O_THICK}, {"no-missing", 0, 0, O_NOMISS},
        {"labeller", 1, 0, O_LABELLER}, {"debug-dir", 1, 0, O_DEBUG},
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
        if (c == '?' || c == ':')
            return td_cli_failf("label", "bad or incomplete option '%s' (see "
                                "topodig label --help)", argv[optind - 1]);
        if (parse_opt(c, optarg, o, heights, &cx) != 0)
            return td_cli_fail("label", &cx);
    }
    if (optind != argc - 1)
        return td_cli_failf("label", "expected one LINES.geojson file (see "
                            "topodig label --help)");
    o->in = argv[optind];
    if (!o->out)
        return td_cli_failf("label", "no output: give -o LABELLED.geojson");
    if (td_cli_check_output("label", o->out, o->in) != 0)
        return 1;
    if (!(o->interval > 0) && (!o->scan || o->tree))
        return td_cli_failf("label", "no interval: give --interval I%s",
                            o->scan ? "" : " (or --sheet SCAN to read the "
                            "printed labels)");
    return 0;
}

/* --heights rows: the operator's heights win over the automatic ones;
 * rows off base + k * interval are warned about into checks (may be NULL)
 * and kept. */
static int apply_heights(td_lines *ls, const pts *hs, td_label_report *checks,
                         const td_label_params *p, td_ctx *cx)
{
    size_t i, j;
    for (j = 0; j < hs->n; j++) {
        for (i = 0; i < ls->n && ls->v[i].id != hs->v[j].id; i++)
            ;
        if (i == ls->n)
            return td_seterr(cx, TD_EINVAL, "--heights: no line has id %ld",
                             hs->v[j].id);
        ls->v[i].has_height = 1;
        ls->v[i].height = hs->v[j].height;
        if (checks) {
            double k = (hs->v[j].height - p->base) / p->interval, x, y;
            if (fabs(k - floor(k + 0.5)) <= 1e-6)
                continue;
            td_label_where(&ls->v[i], &x, &y);
            td_label_warn(checks, "--heights: height %g of line %ld (near "
                          "%.0f,%.0f) is not base %g + a multiple of %g; "
                          "kept", hs->v[j].height, hs->v[j].id, x, y,
                          p->base, p->interval);
        }
    }
    return 0;
}

/* id,height rows (empty height when undetermined), written atomically. */
static int export_csv(const char *path, const td_lines *ls, td_ctx *cx)
{
    char tmp[4200];
    FILE *f;
    size_t i;
    int bad;
    snprintf(tmp, sizeof tmp, "%s.tmp%ld", path, (long)getpid());
    if (!(f = fopen(tmp, "w")))
        return td_seterr(cx, TD_EIO, "%s: cannot write (%s)", path,
                         strerror(errno));
    fputs("id,height\n", f);
    for (i = 0; i < ls->n; i++) {
        if (ls->v[i].has_height)
            fprintf(f, "%ld,%.10g\n", ls->v[i].id, ls->v[i].height);
        else
            fprintf(f, "%ld,\n", ls->v[i].id);
    }
    bad = ferror(f);
    if (fclose(f) != 0 || bad || rename(tmp, path) != 0) {
        remove(tmp);
        return td_seterr(cx, TD_EIO, "%s: cannot write", path);
    }
    return 0;
}

/* Each line of a report's text as "label: warning: ...". */
static void put_warnings(const char *text)
{
    while (text && *text) {
        size_t n = strcspn(text, "\n");
        fprintf(stderr, "label: warning: %.*s\n", (int)n, text);
        text += n + (text[n] == '\n');
    }
}

/* Whether id is among the points' ids. */
static int has_id(const pts *a, long id)
{
    size_t j;
    for (j = 0; j < a->n; j++)
        if (a->v[j].id == id)
            return 1;
    return 0;
}

/* The lines whose up/down is only assumed (a note, not a warning); lines
 * given by --heights or answered in --interactive are not guesses. */
static void put_assumed(td_label_report *rep, const pts *heights,
                        const pts *seen)
{
    size_t i, m = 0;
    for (i = 0; i < rep->assumed; i++)
        if (!has_id(heights, rep->assumed_ids[i]) &&
            !has_id(seen, rep->assumed_ids[i]))
            rep->assumed_ids[m++] = rep->assumed_ids[i];
    rep->assumed = m;
    if (rep->assumed == 0)
        return;
    fprintf(stderr, "label: note: %zu lines are higher or lower than their "
            "surroundings by assumption only (no two known points or "
            "--depressions fix it; rings taken as rising), ids ",
            rep->assumed);
    for (i = 0; i < rep->assumed && i < 20; i++)
        fprintf(stderr, "%s%ld", i ? "," : "", rep->assumed_ids[i]);
    fputs(rep->assumed > 20 ? ",...\n" : "\n", stderr);
}

static void summary(const td_lines *ls, td_label_report *rep,
                    const td_label_report *checks, const pts *heights,
                    const pts *seen, size_t more)
{
    size_t i, lab = 0, shown = 0;
    for (i = 0; i < ls->n; i++)
        lab += ls->v[i].has_height != 0;
    put_warnings(rep->text);
    put_warnings(checks->text);
    put_assumed(rep, heights, seen);
    fprintf(stderr, "label: %zu lines, %zu labelled, %zu undetermined, %zu "
            "warnings", ls->n, lab, ls->n - lab,
            rep->warnings + checks->warnings + more);
    for (i = 0; i < ls->n && shown < 20; i++)
        if (!ls->v[i].has_height)
            fprintf(stderr, "%s%ld", shown++ ? "," : " (undetermined ids: ",
                    ls->v[i].id);
    fputs(shown ? (shown < ls->n - lab ? ",...)\n" : ")\n") : "\n", stderr);
    td_cli_heights_summary("label", rep);
}

/* --sheet SCAN: scan it again for where the labels are, read them, tie
 * them to the given lines. */
static int read_sheet_labels(const label_opts *o, const td_lines *ls,
                             td_ocr_read **reads, size_t *n, td_ctx *cx)
{
    td_image *im = NULL;
    td_scan_params sp = td_scan_defaults();
    td_scan_result res;
    int rc;
    memset(&res, 0, sizeof res);
    if ((rc = td_image_read(o->scan, &im, NULL, cx)) != 0)
        return rc;
    sp.join.record = 1;
    sp.measure_width = 0;
    if ((rc = td_scan(im, &sp, &res, cx)) == 0)
        rc = td_ocr_scan_labels(im, res.lines, &res.join, ls, NULL, reads, n,
                                cx);
    td_scan_result_free(&res);
    td_image_free(im);
    return rc;
}

/* --debug-dir: heights.png over the --like scan (or white). */
static int write_heights_png(const label_opts *o, const td_lines *ls,
                             td_ctx *cx)
{
    td_image *scan = NULL, *pic = NULL;
    char path[4096];
    int rc;
    if (mkdir(o->debug_dir, 0777) != 0 && errno != EEXIST)
        return td_seterr(cx, TD_EIO, "%s: cannot make the folder: %s",
                         o->debug_dir, strerror(errno));
    snprintf(path, sizeof path, "%s/heights.png", o->debug_dir);
    if (o->like && (rc = td_image_read(o->like, &scan, NULL, cx)) != 0)
        return rc;
    if ((rc = td_draw_heights(scan, o->w, o->h, ls, &pic, cx)) == 0)
        rc = td_png_write(path, pic, cx);
    td_image_free(pic);
    td_image_free(scan);
    return rc;
}

/* ---- --interactive: the paper's way (001 §2.3, one height per line) ---- */

/* 3x5 digits, rows top to bottom, 3 bits per row (4 = left column). */
static const unsigned char font3x5[10][5] = {
    {7, 5, 5, 5, 7}, {2, 6, 2, 2, 7}, {7, 1, 7, 4, 7}, {7, 1, 7, 1, 7},
    {5, 5, 7, 1, 1}, {7, 4, 7, 1, 7}, {7, 4, 7, 5, 7}, {7, 1, 1, 1, 1},
    {7, 5, 7, 5, 7}, {7, 5, 7, 1, 7}};

static void put_px(td_image *im, int x, int y, const uint8_t c[3])
{
    uint8_t *p;
    if (x < 0 || y < 0 || x >= im->w || y >= im->h)
        return;
    p = im->data + ((size_t)y * im->w + x) * 3;
    p[0] = c[0], p[1] = c[1], p[2] = c[2];
}

/* The id in 2x-scaled 3x5 digits centred at (cx,cy) on a white box with
 * a border in the line's colour. */
static void draw_id(td_image *im, double cx, double cy, long id,
                    const uint8_t c[3])
{
    static const uint8_t white[3] = {255, 255, 255};
    char t[24];
    int n = snprintf(t, sizeof t, "%ld", id), bw = n * 8 + 2, bh = 14;
    int x0 = (int)cx - bw / 2, y0 = (int)cy - bh / 2, x, y, g;
    for (y = -1; y <= bh; y++)
        for (x = -1; x <= bw; x++)
            put_px(im, x0 + x, y0 + y,
                   y < 0 || x < 0 || y == bh || x == bw ? c : white);
    for (g = 0; g < n; g++)
        for (y = 0; y < 10; y++)
            for (x = 0; x < 6; x++)
                if (t[g] >= '0' && t[g] <= '9' &&
                    font3x5[t[g] - '0'][y / 2] >> (2 - x / 2) & 1)
                    put_px(im, x0 + 2 + 8 * g + x, y0 + 2 + y, c);
}

/* The point at fraction f of l's length. */
static void line_at(const td_line *l, double f, double *x, double *y)
{
    double want = f * td_line_length(l), s = 0;
    size_t k;
    *x = l->n ? l->xy[0] : 0, *y = l->n ? l->xy[1] : 0;
    for (k = 1; k < l->n; k++) {
        double d = hypot(l->xy[2 * k] - l->xy[2 * k - 2],
                         l->xy[2 * k + 1] - l->xy[2 * k - 1]);
        if (s + d >= want) {
            *x = l->xy[2 * k], *y = l->xy[2 * k + 1];
            return;
        }
        s += d;
    }
}

/* Where line i's id goes: near its middle, or the first of eight places
 * along it whose box (bw x 16 px) overlaps no earlier id box (xy[2j]). */
static void id_place(const td_lines *ls, size_t i, const double *xy,
                     double *x, double *y)
{
    static const double f[8] = {.5, .25, .75, .125, .375, .625, .875, 0};
    char t[24];
    double bw = 8.0 * snprintf(t, sizeof t, "%ld", ls->v[i].id) + 4;
    size_t j;
    int k;
    for (k = 0; k < 8; k++) {
        int clash = 0;
        line_at(&ls->v[i], f[k], x, y);
        for (j = 0; j < i && !clash; j++)
            clash = fabs(xy[2 * j] - *x) < bw + 6 &&
                    fabs(xy[2 * j + 1] - *y) < 18;
        if (!clash)
            return;
    }
    line_at(&ls->v[i], 0.5, x, y);
}

/* Id places of every line (x,y pairs in *out, caller frees). */
static int id_places(const td_lines *ls, double **out, td_ctx *cx)
{
    size_t i;
    if (!(*out = malloc((2 * ls->n + 2) * sizeof **out)))
        return td_seterr(cx, TD_ENOMEM, "out of memory");
    for (i = 0; i < ls->n; i++)
        id_place(ls, i, *out, &(*out)[2 * i], &(*out)[2 * i + 1]);
    return 0;
}

/* The label sheet: every line in its own colour with its id near its
 * middle, on white (w x h) or over the scan (--like). */
static int write_sheet(const label_opts *o, const td_lines *ls,
                       const double *idxy, td_ctx *cx)
{
    char path[4200];
    td_image *scan = NULL, *im = NULL;
    size_t i;
    int rc;
    if (o->sheet)
        snprintf(path, sizeof path, "%s", o->sheet);
    else
        snprintf(path, sizeof path, "%s.png", o->out);
    if (o->like) {
        if ((rc = td_image_read(o->like, &scan, NULL, cx)) != 0 ||
            (rc = td_draw_overlay(scan, ls, &im, cx)) != 0)
            goto fail;
    } else {
        rc = TD_ENOMEM;
        if (!(im = td_image_new(o->w, o->h, 3, cx)))
            goto fail;
        memset(im->data, 255, (size_t)o->w * o->h * 3);
        for (i = 0; i < ls->n; i++) {
            uint8_t c[3];
            td_draw_colour(i, c);
            td_draw_line(im, &ls->v[i], c);
        }
    }
    for (i = 0; i < ls->n; i++) {
        uint8_t c[3];
        td_draw_colour(i, c);
        draw_id(im, idxy[2 * i], idxy[2 * i + 1], ls->v[i].id, c);
    }
    rc = td_png_write(path, im, cx);
    if (rc == 0)
        fprintf(stderr, "label: label sheet %s\n", path);
fail:
    td_image_free(scan);
    td_image_free(im);
    return rc;
}

/* Re-suggest every height from the known points plus the typed ones.  On
 * failure (the typed heights contradict) the heights are left as they were
 * and a warning is printed. */
static void repropagate(td_lines *ls, td_label_params *p, const pts *typed,
                        const pts *known, const pts *heights,
                        td_label_report *rep, size_t *warnings)
{
    td_label_point *all = NULL;
    double *saved = malloc((ls->n + 1) * 2 * sizeof *saved);
    td_label_report r2;
    td_ctx cx;
    size_t i;
    td_ctx_init(&cx);
    memset(&r2, 0, sizeof r2);
    all = malloc((known->n + typed->n + 1) * sizeof *all);
    if (!saved || !all)
        goto done;
    for (i = 0; i < ls->n; i++)
        saved[2 * i] = ls->v[i].has_height, saved[2 * i + 1] = ls->v[i].height;
    if (known->n)
        memcpy(all, known->v, known->n * sizeof *all);
    if (typed->n)
        memcpy(all + known->n, typed->v, typed->n * sizeof *all);
    p->known = all, p->nknown = known->n + typed->n;
    if (td_label_auto(ls, p, &r2, &cx) != 0 ||
        apply_heights(ls, heights, NULL, p, &cx) != 0) {
        fprintf(stderr, "label: warning: %s; heights not re-suggested\n",
                td_errmsg(&cx));
        (*warnings)++;
        for (i = 0; i < ls->n; i++)
            ls->v[i].has_height = (int)saved[2 * i],
            ls->v[i].height = saved[2 * i + 1];
        td_label_report_free(&r2);
    } else {
        td_label_report_free(rep);
        *rep = r2;
    }
done:
    p->known = known->v, p->nknown = known->n;
    free(all);
    free(saved);
}

/* One answer: 0 accepted (Enter), 1 a height in *v, 2 stop (q), 3 not
 * understood, 4 end of input. */
static int read_answer(FILE *in, double *v)
{
    char buf[256], *s;
    if (!fgets(buf, sizeof buf, in))
        return 4;
    if (!isatty(fileno(in)))
        fputs(buf[strcspn(buf, "\n")] ? buf : "\n", stderr);
    for (s = buf; *s == ' ' || *s == '\t'; s++)
        ;
    s[strcspn(s, " \t\r\n")] = '\0';
    if (*s == '\0')
        return 0;
    if (!strcmp(s, "q") || !strcmp(s, "quit"))
        return 2;
    return td_cli_parse_double(s, -1e9, 1e9, v) == 0 ? 1 : 3;
}

/* Ask each line's height in id order (the paper's operator), re-suggesting
 * the others after each typed height.  Returns the number of warnings;
 * *asked gets the number of lines answered (accepted or typed). */
static size_t interact(td_lines *ls, td_label_params *p, const pts *known,
                       const pts *heights, const double *idxy,
                       td_label_report *rep, FILE *in, size_t *asked)
{
    pts typed = {NULL, 0, 0};
    size_t i, warnings = 0;
    for (i = 0; i < ls->n; i++) {
        *asked = i; /* lines before i were answered */
        td_line *l = &ls->v[i];
        double x = idxy[2 * i], y = idxy[2 * i + 1], v, k;
        char sug[64] = "?";
        int a;
        if (l->has_height)
            snprintf(sug, sizeof sug, "%.10g", l->height);
        fprintf(stderr, "line %ld (%s, near %.0f,%.0f) height [%s]: ", l->id,
                l->closed ? "closed" : "open", x, y, sug);
        a = read_answer(in, &v);
        if (a == 2 || a == 4) {
            if (a == 4)
                fputc('\n', stderr);
            break;
        }
        *asked = i + 1;
        if (a == 3) {
            fprintf(stderr, "  a height, Enter to accept, q to stop\n");
            i--;
            continue;
        }
        if (a == 0 || (l->has_height && v == l->height))
            continue;
        k = (v - p->base) / p->interval;
        if (fabs(k - floor(k + 0.5)) > 1e-6) {
            fprintf(stderr, "label: warning: height %g for line %ld is not "
                    "base %g + a multiple of %g\n", v, l->id, p->base,
                    p->interval);
            warnings++;
        }
        if (push_pt(&typed, 0, 0, v, l->id, NULL) != 0)
            break;
        l->has_height = 1, l->height = v;
        repropagate(ls, p, &typed, known, heights, rep, &warnings);
        l = &ls->v[i];
        l->has_height = 1, l->height = v; /* the operator's word stands */
    }
    free(typed.v);
    return warnings;
}

/* Warn about lines that cross (one line each, before the summary);
 * returns the number of warnings, or -1 (out of memory). */
static long warn_crossings(const td_lines *ls, int quiet, td_ctx *cx)
{
    td_crossing *v = NULL;
    size_t n = 0, i;
    if (td_contain_crossings(ls, &v, &n, cx) != 0)
        return -1;
    for (i = 0; i < n && !quiet; i++)
        fprintf(stderr, "label: warning: lines %ld and %ld cross at "
                "(%.1f,%.1f)\n", v[i].a, v[i].b, v[i].x, v[i].y);
    free(v);
    return (long)n;
}

/* Widths for --index-every from the scan (--like) when the lines carry
 * none (a GeoJSON not written by topodig scan): binarised with the
 * scanner's defaults. */
static int widths_from_scan(const char *scan, td_lines *ls, td_ctx *cx)
{
    td_image *im = NULL;
    td_grid_u8 *m = NULL;
    td_binarise_params bp = td_binarise_defaults();
    size_t i;
    int rc;
    for (i = 0; i < ls->n; i++)
        if (ls->v[i].width > 0)
            return 0;
    if ((rc = td_image_read(scan, &im, NULL, cx)) != 0)
        goto fail;
    rc = TD_ENOMEM;
    if (!(m = td_grid_u8_new(im->w, im->h, cx)))
        goto fail;
    if ((rc = td_binarise(im, &bp, m, cx)) == 0)
        rc = td_line_widths(m, ls, cx);
fail:
    td_image_free(im);
    td_grid_u8_free(m);
    return rc;
}

/* After the heights are final: the interval check of --heights rows and
 * typed heights is done where they come in; here the index widths. */
static int final_checks(const label_opts *o, td_lines *ls,
                        const td_label_params *p, td_label_report *checks,
                        td_ctx *cx)
{
    int rc = 0;
    if (o->index_every > 0 && o->like)
        rc = widths_from_scan(o->like, ls, cx);
    if (rc == 0)
        rc = td_label_check_index(ls, p, checks, cx);
    return rc;
}

int td_cmd_label(int argc, char **argv)
{
    label_opts o;
    pts heights, seen = {NULL, 0, 0};
    td_ctx cx;
    td_lines *ls = NULL;
    td_label_report rep, checks;
    td_georef frame;
    td_label_params p = td_label_defaults();
    td_ocr_read *reads = NULL;
    size_t nreads = 0;
    double *idxy = NULL;
    size_t more = 0;
    long ncross = 0;
    int rc;
    memset(&o, 0, sizeof o);
    memset(&heights, 0, sizeof heights);
    memset(&rep, 0, sizeof rep);
    memset(&checks, 0, sizeof checks);
    td_georef_init(&frame);
    td_ctx_init(&cx);
    if ((rc = parse_args(argc, argv, &o, &heights)) != 0)
        goto done;
    /* the lines come back in pixel units, and go out in their own frame */
    if ((rc = td_vector_read_lines(o.in, NULL, &ls, NULL, &frame, &cx)) != 0)
        goto fail;
    if (o.scan && !o.tree &&
        (rc = read_sheet_labels(&o, ls, &reads, &nreads, &cx)) != 0)
        goto fail;
    if (o.scan && !o.like)
        o.like = o.scan; /* widths and pictures from the same scan */
    if (o.w == 0 && (rc = td_lines_extent(ls, &o.w, &o.h, &cx)) != 0)
        goto fail;
    p.base = o.base, p.interval = o.interval, p.w = o.w, p.h = o.h;
    p.known = o.known.v, p.nknown = o.known.n;
    p.depressions = o.dep, p.ndepressions = o.ndep;
    p.index_every = o.index_every, p.missing = !o.no_missing;
    p.method = o.tree ? TD_LABEL_TREE : TD_LABEL_FACES;
    p.labels = reads;
    p.nlabels = nreads;
    if (o.thick_ratio > 0)
        p.thick_ratio = o.thick_ratio;
    if ((ncross = warn_crossings(ls, o.quiet, &cx)) < 0) {
        rc = TD_ENOMEM;
        goto fail;
    }
    if ((rc = td_label_auto(ls, &p, &rep, &cx)) != 0 ||
        (!(p.interval > 0) && (p.interval = rep.interval, 0)) ||
        (rc = apply_heights(ls, &heights, &checks, &p, &cx)) != 0 ||
        (o.interactive && (rc = id_places(ls, &idxy, &cx)) != 0) ||
        (o.interactive && (rc = write_sheet(&o, ls, idxy, &cx)) != 0))
        goto fail;
    if (o.interactive) {
        size_t asked = 0, i;
        more += interact(ls, &p, &o.known, &heights, idxy, &rep, stdin,
                         &asked);
        for (i = 0; i < asked && rc == 0; i++) /* seen: not "assumed" */
            rc = push_pt(&seen, 0, 0, ls->v[i].height, ls->v[i].id, &cx);
        if (rc != 0)
            goto fail;
    }
    more += (size_t)ncross;
    /* the secondary outputs first: when one fails, the main output (new
       or old) is left as it was */
    if ((rc = final_checks(&o, ls, &p, &checks, &cx)) != 0 ||
        (o.csv_out && (rc = export_csv(o.csv_out, ls, &cx)) != 0) ||
        (o.debug_dir && (rc = write_heights_png(&o, ls, &cx)) != 0) ||
        (rc = td_vector_write_lines(o.out, ls, frame.valid ? &frame : NULL,
                                    &cx)) != 0)
        goto fail;
    if (!o.quiet)
        summary(ls, &rep, &checks, &heights, &seen, more);
fail:
    if (rc)
        rc = td_cli_fail("label", &cx);
done:
    td_georef_clear(&frame);
    td_label_report_free(&rep);
    td_label_report_free(&checks);
    td_lines_free(ls);
    free(idxy);
    free(reads);
    free(o.known.v);
    free(o.dep);
    free(heights.v);
    free(seen.v);
    return rc == 2 ? 0 : rc;
}
