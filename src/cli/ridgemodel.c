/* topodig ridgemodel: ridge lines -> DEM by the ridgeline model (paper
 * 000 §2.1-2.4; src/model/ridgemodel.c), with 2-D trees given heights by
 * Algorithm 2.4 and a file of edits applied by the deletion algorithm
 * chosen (2.2 lists or 2.3 winners). */
#include "src/cli/cli.h"

#include "src/io/io.h"
#include "src/model/model.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct rm_opts {
    const char *in, *out, *like, *nodes_out, *edits;
    int wh[2], quiet;
    long seed;
    double leaf, cell;
    td_ridge_params p;
    td_ridgegen_params g;
} rm_opts;

static int parse_args(int argc, char **argv, rm_opts *o)
{
    const td_opt opts[] = {
        TD_CLI_GRID_OPTS(&o->like, o->wh),
        {"slope", 0, TD_OPT_DOUBLE, &o->p.slope, 0.01, 89.99, .meta = "DEG",
         .help = "the skirts' slope (and, with --leaf-height,\nthe rise "
         "along a tree)"},
        {"smooth", 0, TD_OPT_INT, &o->p.smooth, 0, 1000, .meta = "N",
         .help = "passes of the low-pass filter (3 x 3 mean;\n0: none)"},
        {"cell", 0, TD_OPT_DOUBLE, &o->cell, 1e-9, 1e9, .meta = "M",
         .help = "horizontal size of a cell in the heights'\nunits (default: "
         "from --like's georeferencing,\nelse 1)", .no_default = 1},
        {"base", 0, TD_OPT_DOUBLE, &o->p.base, -1e6, 1e6, .meta = "H",
         .help = "the height the skirts fall to, and of cells\nno skirt "
         "reaches"},
        {"leaf-height", 0, TD_OPT_DOUBLE, &o->leaf, -1e6, 1e6, .meta = "H",
         .help = "2-D ridge trees: every end point gets H,\nevery other "
         "node H + tan(slope) x its\nshortest path to an end point "
         "(Algorithm\n2.4); the lines' own heights are ignored",
         .no_default = 1},
        {"nodes-out", 0, TD_OPT_OUTPUT, &o->nodes_out, .meta = "F.geojson",
         .help = "the tree's nodes with their heights (points)"},
        {"edits", 0, TD_OPT_STRING, &o->edits, .meta = "FILE", .help =
         "apply 'add X0 Y0 Z0 X1 Y1 Z1' and 'delete X0 Y0\nX1 Y1' lines "
         "(map coordinates) after the\nfirst render, in place"},
        {"generate", 0, TD_OPT_INT, &o->g.rounds, 1, 10, .meta = "ROUNDS",
         .help = "recursive ridge generation (Algorithm 2.5):\neach round, "
         "drops every --spacing cells on a\nrandom side of every ridge run "
         "down the DEM\nand their paths become new ridges; the slope\nrises "
         "by --slope-step, the spacing shrinks\nby --spacing-factor",
         .no_default = 1},
        {"seed", 0, TD_OPT_LONG, &o->seed, 0, 2147483647.0, .meta = "N",
         .help = "--generate's random choices"},
        {"spacing", 0, TD_OPT_DOUBLE, &o->g.spacing, 1, 1e6, .meta = "D",
         .help = "--generate: cells between drops, first round"},
        {"spacing-factor", 0, TD_OPT_DOUBLE, &o->g.spacing_factor, 0.01, 1,
         .meta = "F", .help = "--generate: the spacing times F each round"},
        {"slope-step", 0, TD_OPT_DOUBLE, &o->g.slope_step, 0, 60,
         .meta = "DEG", .help = "--generate: the slope's rise each round"},
        {"delete-method", 0, TD_OPT_CHOICE, &o->p.method,
         .choices = "lists|winners", .meta = "M", .help = "how edits delete: "
         "lists (Algorithm 2.2: every\ncell's polygons sorted by height) | "
         "winners\n(2.3: one grid of the winning polygon,\nre-render the "
         "cells it won)"},
        {NULL}};
    const td_cmd c = {
        "ridgemodel", "RIDGES.geojson -o DEM.tif (--like SHEET | --size WxH)\n"
        "                      [--slope DEG] [--smooth N] [--leaf-height H]\n"
        "                      [--generate ROUNDS [--seed N] [--spacing D]]\n"
        "                      [--edits FILE [--delete-method lists|winners]]",
        "A DEM from ridge lines by the ridgeline model (Yaegashi & Chiba,\n"
        "Algorithm 2.1): two skirts sloping away at --slope from every\n"
        "segment, triangles closing the gaps between the skirts at every\n"
        "bend, fork and free end, all z-buffered keeping the highest, then\n"
        "--smooth passes of a low-pass filter.  RIDGES: LineStrings with a\n"
        "height per vertex (3-D coordinates, or a 'heights' list as\n"
        "'topodig ridges' writes them; its valley and inflection lines are\n"
        "skipped), or 2-D trees with --leaf-height.\n"
        "Any vector format GDAL reads; coordinates in the frame of --like\n"
        "(README, Frames).  DEM by extension: .tif float32 GeoTIFF, .asc,\n"
        ".png 16-bit grey.\n",
        "Summary on stderr: segments, nodes, cells, height range, edits and\n"
        "the time per delete, seconds.\n",
        opts, "one RIDGES file", 1, 1, &o->in, &o->out, "DEM.tif", &o->quiet};
    int rc = td_opt_parse(&c, argc, argv);
    if (rc)
        return rc;
    if (!o->like == !o->wh[0])
        return td_cli_failf("ridgemodel", "give the grid: --like SHEET or "
                            "--size WxH (one of them)");
    return 0;
}

/* The edits file: one operation a line ('#' comments, blank lines). */
static int apply_edits(td_ridgemodel *m, const char *path, const td_georef *g,
                       size_t *nadd, size_t *ndel, double *del_secs,
                       td_ctx *cx)
{
    FILE *f;
    char line[512];
    long ln = 0;
    int rc = 0;
    if ((rc = td_check_input(path, cx)) != 0)
        return rc;
    if (!(f = fopen(path, "r")))
        return td_seterr(cx, TD_EIO, "%s: cannot open", path);
    while (rc == 0 && fgets(line, sizeof line, f)) {
        double v[6], x0, y0, x1, y1;
        char op[16], *s = line;
        int n;
        ln++;
        while (isspace((unsigned char)*s))
            s++;
        if (!*s || *s == '#')
            continue;
        if (!strchr(line, '\n') && !feof(f)) {
            rc = td_seterr(cx, TD_EFORMAT, "%s:%ld: line too long", path, ln);
            break;
        }
        n = sscanf(s, "%15s %lf %lf %lf %lf %lf %lf", op, &v[0], &v[1],
                   &v[2], &v[3], &v[4], &v[5]);
        if (!strcmp(op, "add") && n == 7 && isfinite(v[0] + v[1] + v[2] +
                                                     v[3] + v[4] + v[5])) {
            if (td_georef_to_cells(g, v[0], v[1], &x0, &y0) != 0 ||
                td_georef_to_cells(g, v[3], v[4], &x1, &y1) != 0 ||
                td_ridgemodel_add(m, x0, y0, v[2], x1, y1, v[5], cx) < 0)
                rc = td_seterr(cx, cx->code ? cx->code : TD_EINVAL,
                               "%s:%ld: %s", path, ln,
                               cx->msg[0] ? cx->msg : "bad add");
            (*nadd)++;
        } else if (!strcmp(op, "delete") && n == 5 &&
                   isfinite(v[0] + v[1] + v[2] + v[3])) {
            long s2;
            double t0;
            if (td_georef_to_cells(g, v[0], v[1], &x0, &y0) != 0 ||
                td_georef_to_cells(g, v[2], v[3], &x1, &y1) != 0 ||
                (s2 = td_ridgemodel_find(m, x0, y0, x1, y1)) < 0) {
                rc = td_seterr(cx, TD_EINVAL, "%s:%ld: no ridge segment from "
                               "%g,%g to %g,%g", path, ln, v[0], v[1], v[2],
                               v[3]);
                break;
            }
            t0 = td_now();
            rc = td_ridgemodel_delete(m, s2, cx);
            *del_secs += td_now() - t0;
            (*ndel)++;
        } else {
            rc = td_seterr(cx, TD_EFORMAT, "%s:%ld: not 'add X0 Y0 Z0 X1 Y1 "
                           "Z1' or 'delete X0 Y0 X1 Y1'", path, ln);
        }
    }
    fclose(f);
    return rc;
}

/* The nodes as GeoJSON points with their heights, atomically. */
static int write_nodes(const char *path, const td_ridgemodel *m,
                       const td_georef *g, td_ctx *cx)
{
    size_t n = td_ridgemodel_nodes(m, NULL, 0), i, tl = strlen(path) + 32;
    double *v = malloc((3 * n + 1) * sizeof *v);
    char *tmp = malloc(tl), crs[256];
    FILE *f;
    int rc;
    if (!v || !tmp) {
        free(v), free(tmp);
        return td_seterr(cx, TD_ENOMEM, "out of memory");
    }
    td_ridgemodel_nodes(m, v, n);
    if (!(f = td_atomic_open(path, tmp, tl, cx))) {
        free(v), free(tmp);
        return cx->code ? cx->code : TD_EIO;
    }
    td_georef_crs_json(g, crs, sizeof crs);
    fprintf(f, "{\"type\": \"FeatureCollection\", %s, \"features\": [\n", crs);
    for (i = 0; i < n; i++) {
        double X, Y;
        td_georef_apply(g, v[3 * i], v[3 * i + 1], &X, &Y);
        fprintf(f, "%s{\"type\": \"Feature\", \"properties\": {\"id\": %zu, "
                "\"height\": %.10g}, \"geometry\": {\"type\": \"Point\", "
                "\"coordinates\": [%.10g, %.10g, %.10g]}}",
                i ? ",\n" : "", i, v[3 * i + 2], X, Y, v[3 * i + 2]);
    }
    fputs("\n]}\n", f);
    rc = td_atomic_commit(f, tmp, path, cx);
    free(v), free(tmp);
    return rc;
}

/* Every line's segments into the model: heights per vertex, or NaN for
 * the tree pass.  Lines that all lie off the w x h grid are refused (a
 * file in another frame would give a flat DEM). */
static int add_lines(td_ridgemodel *m, const td_lines *ls, const double *z,
                     int tree, int w, int h, const char *path, size_t *nseg,
                     td_ctx *cx)
{
    size_t i, k, off = 0, on = 0;
    for (i = 0; i < ls->n; i++)
        for (k = 0; k < ls->v[i].n; k++) {
            double x = ls->v[i].xy[2 * k], y = ls->v[i].xy[2 * k + 1];
            on += x >= 0 && y >= 0 && x <= w && y <= h;
        }
    if (on == 0)
        return td_seterr(cx, TD_EINVAL, "%s: no ridge line lies on the %d x "
                         "%d grid (coordinates in another frame than the "
                         "grid's?)", path, w, h);
    for (i = 0; i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        for (k = 0; k < l->n; k++)
            if (!tree && !isfinite(z[off + k]))
                return td_seterr(cx, TD_EINVAL, "%s: line %zu has a vertex "
                                 "without a height (give 3-D coordinates or a "
                                 "'heights' list, or --leaf-height H for 2-D "
                                 "trees)", path, i);
        for (k = 0; k + 1 < l->n; k++) {
            if (td_ridgemodel_add(m, l->xy[2 * k], l->xy[2 * k + 1],
                                  tree ? NAN : z[off + k], l->xy[2 * k + 2],
                                  l->xy[2 * k + 3],
                                  tree ? NAN : z[off + k + 1], cx) < 0)
                return cx->code ? cx->code : TD_EINVAL;
            (*nseg)++;
        }
        off += l->n;
    }
    return 0;
}

/* Algorithm 2.5 on the model's segments: *m replaced by a model of them
 * and the generated ones at the final round's slope. */
static int generate(td_ridgemodel **m, rm_opts *o, int w, int h,
                    size_t *nseg, td_ctx *cx)
{
    size_t n = td_ridgemodel_segments(*m, NULL, 0), i;
    double *v = malloc((6 * n + 6) * sizeof *v), slope;
    td_ridge_params q = o->p;
    int rc;
    if (!v)
        return td_seterr(cx, TD_ENOMEM, "out of memory");
    td_ridgemodel_segments(*m, v, n);
    o->g.seed = (uint64_t)o->seed;
    if ((rc = td_ridgegen(&v, &n, w, h, &o->p, &o->g, &slope, cx)) != 0) {
        free(v);
        return rc;
    }
    td_ridgemodel_free(*m);
    q.slope = slope;
    if (!(*m = td_ridgemodel_new(w, h, &q, cx))) {
        free(v);
        return cx->code ? cx->code : TD_ENOMEM;
    }
    for (i = 0; i < n; i++)
        if (td_ridgemodel_add(*m, v[6 * i], v[6 * i + 1], v[6 * i + 2],
                              v[6 * i + 3], v[6 * i + 4], v[6 * i + 5],
                              cx) < 0) {
            free(v);
            return cx->code ? cx->code : TD_EINVAL;
        }
    free(v);
    *nseg = n;
    o->p.slope = slope;
    return 0;
}

int td_cmd_ridgemodel(int argc, char **argv)
{
    rm_opts o;
    td_ctx cx;
    td_cli_progress pr;
    td_georef geo;
    td_lines *ls = NULL;
    double *z = NULL, t0 = td_now(), del_secs = 0, lo = HUGE_VAL,
           hi = -HUGE_VAL;
    td_ridgemodel *m = NULL;
    td_grid_f32 *dem = NULL;
    size_t nseg = 0, nadd = 0, ndel = 0, i;
    int rc, w, h;
    memset(&o, 0, sizeof o);
    o.p = td_ridge_defaults();
    o.g = td_ridgegen_defaults();
    o.g.rounds = 0;
    o.seed = (long)o.g.seed;
    o.leaf = NAN;
    if ((rc = parse_args(argc, argv, &o)) != 0)
        return rc == 2 ? 0 : 1;
    td_ctx_init(&cx);
    td_georef_init(&geo);
    td_cli_progress_init(&pr, &cx, o.quiet);
    if ((rc = td_cli_grid(o.like, o.wh, &w, &h, &geo, &o.cell, &cx)) != 0)
        goto fail;
    o.p.cell = o.cell;
    if ((rc = td_vector_read_lines_z(o.in, &geo, "ridge", &ls, &z, NULL, NULL,
                                     &cx)) != 0)
        goto fail;
    if (ls->n == 0) {
        rc = td_seterr(&cx, TD_EINVAL, "%s: no lines", o.in);
        goto fail;
    }
    if (!(m = td_ridgemodel_new(w, h, &o.p, &cx))) {
        rc = cx.code;
        goto fail;
    }
    if ((rc = add_lines(m, ls, z, isfinite(o.leaf), w, h, o.in, &nseg, &cx)) != 0 ||
        (isfinite(o.leaf) &&
         (rc = td_ridgemodel_tree_heights(m, o.leaf, &cx)) != 0))
        goto fail;
    if (o.g.rounds > 0 && (rc = generate(&m, &o, w, h, &nseg, &cx)) != 0)
        goto fail;
    if ((rc = td_ridgemodel_render(m, &cx)) != 0)
        goto fail;
    if (o.edits && (rc = apply_edits(m, o.edits, &geo, &nadd, &ndel,
                                     &del_secs, &cx)) != 0)
        goto fail;
    if (!(dem = td_ridgemodel_dem(m, &cx))) {
        rc = cx.code;
        goto fail;
    }
    if ((rc = td_dem_write(o.out, dem, &geo, &cx)) != 0)
        goto fail;
    if (o.nodes_out && (rc = write_nodes(o.nodes_out, m, &geo, &cx)) != 0)
        goto fail;
    td_cli_progress_done(&pr);
    for (i = 0; i < (size_t)w * h; i++) {
        lo = dem->data[i] < lo ? dem->data[i] : lo;
        hi = dem->data[i] > hi ? dem->data[i] : hi;
    }
    if (!o.quiet) {
        fprintf(stderr, "ridgemodel: %zu segments, %zu nodes, %d x %d cells, "
                "heights %.6g to %.6g", nseg, td_ridgemodel_nodes(m, NULL, 0),
                w, h, lo, hi);
        if (o.g.rounds > 0)
            fprintf(stderr, "; %d rounds generated, final slope %g", o.g.rounds,
                    o.p.slope);
        if (o.edits)
            fprintf(stderr, "; edits: %zu added, %zu deleted (%s, %.3g ms "
                    "per delete)", nadd, ndel,
                    o.p.method == TD_RM_LISTS ? "lists" : "winners",
                    ndel ? 1e3 * del_secs / ndel : 0.0);
        fprintf(stderr, "; %.2f s\n", td_now() - t0);
    }
fail:
    td_cli_progress_done(&pr);
    td_grid_f32_free(dem);
    td_ridgemodel_free(m);
    td_lines_free(ls);
    free(z);
    td_georef_clear(&geo);
    return rc == 0 ? 0 : td_cli_fail_on("ridgemodel", o.in, o.out, &cx);
}
