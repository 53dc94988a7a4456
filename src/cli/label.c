/* topodig label: traced lines -> lines with heights (GeoJSON).
 * Automatic heights from known points (scanner/label.h, ours); the paper's
 * way, one typed height per line (001 §2.3), is --heights after editing the
 * --export-csv file. */
#define _GNU_SOURCE
#include "cli.h"

#include "../lines.h"
#include "../../scanner/label.h"

#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char help[] =
    "usage: topodig label LINES.geojson -o LABELLED.geojson --interval I\n"
    "                     [--base B] [--known X,Y,H]... [options]\n"
    "\n"
    "Build the containment tree of the traced lines (lines ending on the\n"
    "sheet border are closed along it, never past the top-left corner) and\n"
    "give every line its height from a few known points and the interval:\n"
    "one interval per nesting step, rings higher than their surroundings\n"
    "unless a known point or a depression mark says otherwise.\n"
    "\n"
    "options:\n"
    "  -o, --output FILE      labelled GeoJSON (required)\n"
    "      --interval I       contour interval (required, > 0)\n"
    "      --base B           heights are B + k * I (default 0)\n"
    "      --known X,Y,H      a point on (within 3 px of) a line: its height;\n"
    "                         elsewhere: a spot height (repeatable)\n"
    "      --known-file CSV   x,y,height rows (a header line is skipped)\n"
    "      --depressions X,Y  the ring around X,Y is a depression (repeatable)\n"
    "      --heights CSV      id,height rows: these lines' heights (e.g. an\n"
    "                         edited --export-csv file)\n"
    "      --export-csv FILE  write id,height of every line\n"
    "      --size WxH         sheet size in px (default: the lines' extent)\n"
    "  -q, --quiet            no summary or warnings\n"
    "  -h, --help             this help\n"
    "\n"
    "Coordinates are scan pixels (column, row).  Summary on stderr:\n"
    "lines labelled, undetermined, warnings.  Exit 1 on bad input or\n"
    "contradictory known points (the message names both and their lines).\n";

typedef struct pts {
    td_label_point *v;
    size_t n, cap;
} pts;

typedef struct label_opts {
    const char *in, *out, *csv_out;
    int quiet, w, h;
    double base, interval;
    pts known;
    double *dep;
    size_t ndep;
} label_opts;

enum { O_INTERVAL = 256, O_BASE, O_KNOWN, O_KNOWNF, O_DEPR, O_HEIGHTS,
       O_EXPORT, O_SIZE };

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
static int parse_nums(const char *s, double *v, int n)
{
    char buf[256], *tok, *save = NULL;
    int k = 0;
    if (strlen(s) >= sizeof buf)
        return -1;
    strcpy(buf, s);
    for (tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        while (*tok == ' ' || *tok == '\t')
            tok++;
        tok[strcspn(tok, " \t\r\n")] = '\0';
        if (k >= n || td_cli_parse_double(tok, -1e12, 1e12, &v[k++]) != 0)
            return -1;
    }
    return k == n ? 0 : -1;
}

/* Rows of a CSV file: x,y,height (ids 0) or id,height (ids 1). */
static int read_csv(const char *path, int ids, pts *a, td_ctx *cx)
{
    FILE *f = fopen(path, "r");
    char line[512];
    long no = 0;
    int rc = 0;
    if (!f)
        return td_seterr(cx, TD_EIO, "%s: cannot open (%s)", path,
                         strerror(errno));
    while (rc == 0 && fgets(line, sizeof line, f)) {
        double v[3];
        no++;
        line[strcspn(line, "\r\n")] = '\0';
        if (line[0] == '\0' || line[0] == '#')
            continue;
        if (parse_nums(line, v, ids ? 2 : 3) != 0) {
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
    case O_INTERVAL:
    case O_BASE:
        if (td_cli_parse_double(arg, c == O_BASE ? -1e9 : 1e-9, 1e9, v) != 0)
            return td_seterr(cx, TD_EINVAL, "%s: '%s' is not a %snumber",
                             c == O_BASE ? "--base" : "--interval", arg,
                             c == O_BASE ? "" : "positive ");
        *(c == O_BASE ? &o->base : &o->interval) = v[0];
        return 0;
    case O_KNOWN:
        if (parse_nums(arg, v, 3) != 0)
            return td_seterr(cx, TD_EINVAL, "--known: '%s' is not X,Y,H", arg);
        return push_pt(&o->known, v[0], v[1], v[2], -1, cx);
    case O_DEPR: {
        double *d;
        if (parse_nums(arg, v, 2) != 0)
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
        {"export-csv", 1, 0, O_EXPORT}, {"size", 1, 0, O_SIZE}, {0, 0, 0, 0}};
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
    if (!(o->interval > 0))
        return td_cli_failf("label", "no interval: give --interval I");
    return 0;
}

/* The sheet size when --size is not given: the lines' extent (traced
 * lines ending on the border reach the border pixels' centres). */
static void extent(const td_lines *ls, int *w, int *h)
{
    double mx = 1, my = 1;
    size_t i, k;
    for (i = 0; i < ls->n; i++)
        for (k = 0; k < ls->v[i].n; k++) {
            mx = fmax(mx, ls->v[i].xy[2 * k]);
            my = fmax(my, ls->v[i].xy[2 * k + 1]);
        }
    *w = (int)ceil(mx + 0.5 - 1e-9);
    *h = (int)ceil(my + 0.5 - 1e-9);
}

/* --heights rows: the operator's heights win over the automatic ones. */
static int apply_heights(td_lines *ls, const pts *hs, td_ctx *cx)
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

static void summary(const td_lines *ls, const td_label_report *rep)
{
    size_t i, lab = 0, shown = 0;
    for (i = 0; i < ls->n; i++)
        lab += ls->v[i].has_height != 0;
    if (rep->text)
        fputs(rep->text, stderr);
    fprintf(stderr, "label: %zu lines, %zu labelled, %zu undetermined, %zu "
            "warnings", ls->n, lab, ls->n - lab, rep->warnings);
    for (i = 0; i < ls->n && shown < 20; i++)
        if (!ls->v[i].has_height)
            fprintf(stderr, "%s%ld", shown++ ? "," : " (undetermined ids: ",
                    ls->v[i].id);
    fputs(shown ? (shown < ls->n - lab ? ",...)\n" : ")\n") : "\n", stderr);
}

int td_cmd_label(int argc, char **argv)
{
    label_opts o;
    pts heights;
    td_ctx cx;
    td_lines *ls = NULL;
    td_label_report rep;
    td_label_params p = td_label_defaults();
    int rc;
    memset(&o, 0, sizeof o);
    memset(&heights, 0, sizeof heights);
    memset(&rep, 0, sizeof rep);
    td_ctx_init(&cx);
    if ((rc = parse_args(argc, argv, &o, &heights)) != 0)
        goto done;
    if ((rc = td_geojson_read_lines(o.in, NULL, &ls, NULL, &cx)) != 0)
        goto fail;
    if (o.w == 0)
        extent(ls, &o.w, &o.h);
    p.base = o.base, p.interval = o.interval, p.w = o.w, p.h = o.h;
    p.known = o.known.v, p.nknown = o.known.n;
    p.depressions = o.dep, p.ndepressions = o.ndep;
    if ((rc = td_label_auto(ls, &p, &rep, &cx)) != 0 ||
        (rc = apply_heights(ls, &heights, &cx)) != 0 ||
        (rc = td_geojson_write_lines(o.out, ls, NULL, &cx)) != 0 ||
        (o.csv_out && (rc = export_csv(o.csv_out, ls, &cx)) != 0))
        goto fail;
    if (!o.quiet)
        summary(ls, &rep);
fail:
    if (rc)
        rc = td_cli_fail("label", &cx);
done:
    td_label_report_free(&rep);
    td_lines_free(ls);
    free(o.known.v);
    free(o.dep);
    free(heights.v);
    return rc == 2 ? 0 : rc;
}
