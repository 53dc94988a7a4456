/* tdgen: write a synthetic contour sheet, its truth lines and truth DEM.
 *
 *   tdgen -o sheet.png --truth truth.geojson [--dem truth.tif] [options]
 *
 * Errors are one line on stderr and exit status 1. */
#include "src/io/io.h"
#include "samples/gen/gen.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char usage[] =
    "usage: tdgen -o SHEET.png [--truth TRUTH.geojson] [--dem DEM.tif]\n"
    "             [--size W[xH]] [--seed N] [--terrain "
    "hills|cone|plane|ridges|valleys]\n"
    "             [--base B] [--interval I] [--width PX] [--blur SIGMA]\n"
    "             [--noise SD] [--specks N] [--breaks N] [--break-len A,B]\n"
    "             [--index-width PX] [--labels N] [--label-bend PX]\n"
    "             [--spot-heights N] [--hachures]\n"
    "             [--label-font segments|dejavu]\n"
    "             [--colour] [--distractors] [--print [--unfaded]\n"
    "             [--fringe DX[,DY]]] [--streams]\n"
    "             [--dem-in REAL.tif [--scale S]] [--tiff] [-q|--quiet]\n"
    "\n"
    "Writes a synthetic scanned contour sheet (PNG, or grey GeoTIFF with\n"
    "--tiff), its true contour lines (GeoJSON: height, closed, edge) and the\n"
    "true DEM (float32 GeoTIFF).  Defaults: 1000x1000, seed 1, hills, base 0,\n"
    "interval automatic (>= 10, contours >= 6.5 px apart), width 2, no blur,\n"
    "noise, specks or breaks, break length 1,3.  --index-width: draw every\n"
    "5th contour (base + 5k * interval) this wide.  --labels N: up to N\n"
    "inline height labels per index contour cutting the line (one per\n"
    "250 px) where the line stays within --label-bend px (default 2.5) of\n"
    "the label's chord; --label-font dejavu draws them in DejaVu Sans with\n"
    "their tops uphill (as printed maps do), segments (the default) as\n"
    "stroke digits reading left to right.  --spot-heights N: up to N\n"
    "summits and pits marked with a dot and their height beside it.\n"
    "--hachures: depression contours (rings around lower ground) with\n"
    "short ticks on their downhill side, as printed maps draw them.\n"
    "  --colour: brown ink on cream (RGB, PNG only);\n"
    "--distractors adds a blue river and black lettering to a colour\n"
    "sheet.  --print (implies --colour): a printed map as a flatbed scanner\n"
    "gives it: green woodland tint, faded brown contours, red roads (one\n"
    "dashed), blue water, black text and grid over yellowing paper, colour\n"
    "fringing, then --blur/--noise, then JPEG losses; --unfaded: the\n"
    "contours at full strength (a new map); --fringe: the red channel\n"
    "shifted by (DX, DY) px, the blue one by the opposite (default 0.6,0).\n"
    "--streams (implies --colour --distractors): blue streams where the\n"
    "terrain's flow gathers, crossing the contours at their Vs, instead\n"
    "of the random river.\n"
    "--dem-in: draw the sheet from a real DEM (any single-band\n"
    "GeoTIFF or .asc without nodata cells), stretched smoothly (bicubic)\n"
    "to --size, or to S times its size with --scale S (default 8); the\n"
    "interval then keeps contours 6.5 px apart on all but the steepest 2%.\n";

typedef struct opts {
    td_gen_params p;
    const char *out, *truth, *dem, *dem_in;
    double scale;
    int tiff, quiet, sized;
} opts;

static int fail(const char *msg, const char *arg)
{
    fprintf(stderr, "tdgen: %s%s%s\n", msg, arg ? " " : "", arg ? arg : "");
    return 1;
}

static int num(const char *s, double lo, double hi, double *v)
{
    char *end;
    errno = 0;
    *v = strtod(s, &end);
    return errno == 0 && end != s && *end == '\0' && *v >= lo && *v <= hi;
}

static int parse_size(const char *s, td_gen_params *p)
{
    char *end;
    long w = strtol(s, &end, 10), h = w;
    if (end == s)
        return 0;
    if (*end == 'x') {
        const char *t = end + 1;
        h = strtol(t, &end, 10);
        if (end == t)
            return 0;
    }
    if (*end || w < 2 || h < 2 || w > TD_MAX_DIM || h > TD_MAX_DIM)
        return 0;
    p->w = (int)w;
    p->h = (int)h;
    return 1;
}

static int parse_terrain(const char *s, td_gen_params *p)
{
    static const char *names[5] = {"hills", "cone", "plane", "ridges",
                                   "valleys"};
    static const td_gen_terrain_kind kinds[5] = {TD_GEN_HILLS, TD_GEN_CONE,
                                                 TD_GEN_PLANE, TD_GEN_RIDGES,
                                                 TD_GEN_VALLEYS};
    int k;
    for (k = 0; k < 5; k++)
        if (strcmp(s, names[k]) == 0) {
            p->terrain = kinds[k];
            return 1;
        }
    return 0;
}

static int parse_break_len(const char *v, td_gen_params *p)
{
    char buf[64], *comma;
    double a, b;
    if (strlen(v) >= sizeof buf)
        return 0;
    strcpy(buf, v);
    if (!(comma = strchr(buf, ',')))
        return 0;
    *comma = '\0';
    if (!num(buf, 0, 1000, &a) || !num(comma + 1, a, 1000, &b))
        return 0;
    p->break_min = a;
    p->break_max = b;
    return 1;
}

/* --fringe DX[,DY]: each within 3 px. */
static int parse_fringe(const char *v, td_gen_params *p)
{
    char buf[64], *comma;
    double a, b = 0;
    if (strlen(v) >= sizeof buf)
        return 0;
    strcpy(buf, v);
    if ((comma = strchr(buf, ',')) != NULL) {
        *comma = '\0';
        if (!num(comma + 1, -3, 3, &b))
            return 0;
    }
    if (!num(buf, -3, 3, &a))
        return 0;
    p->fringe[0] = a;
    p->fringe[1] = b;
    return 1;
}

/* One option with a value: 0 ok, 1 bad value, 2 unknown option. */
static int value_opt(const char *o, const char *v, opts *op)
{
    td_gen_params *p = &op->p;
    double seed = p->seed, specks = p->specks, breaks = p->breaks,
           labels = p->labels, spots = p->spots;
    const struct {
        const char *name;
        double lo, hi, *dst;
    } nums[] = {
        {"--seed", 0, 4294967295.0, &seed},
        {"--base", -1e6, 1e6, &p->base},
        {"--interval", 1e-3, 1e6, &p->interval},
        {"--width", 0.5, 50, &p->line_width},
        {"--blur", 0, 50, &p->blur},
        {"--noise", 0, 255, &p->noise},
        {"--specks", 0, 1e7, &specks},
        {"--breaks", 0, 1e7, &breaks},
        {"--index-width", 0, 50, &p->index_width},
        {"--labels", 0, 1000, &labels},
        {"--spot-heights", 0, 10000, &spots},
        {"--label-bend", 0, 1000, &p->label_bend},
        {"--scale", 0.01, 1000, &op->scale},
    };
    size_t i;
    for (i = 0; i < sizeof nums / sizeof nums[0]; i++)
        if (!strcmp(o, nums[i].name)) {
            if (!num(v, nums[i].lo, nums[i].hi, nums[i].dst))
                return 1;
            p->seed = (unsigned)seed;
            p->specks = (int)specks;
            p->breaks = (int)breaks;
            p->labels = (int)labels;
            p->spots = (int)spots;
            return 0;
        }
    if (!strcmp(o, "-o"))
        op->out = v;
    else if (!strcmp(o, "--truth"))
        op->truth = v;
    else if (!strcmp(o, "--dem"))
        op->dem = v;
    else if (!strcmp(o, "--label-font")) {
        if (strcmp(v, "segments") && strcmp(v, "dejavu"))
            return 1;
        p->label_font = !strcmp(v, "dejavu");
    } else if (!strcmp(o, "--dem-in"))
        op->dem_in = v;
    else if (!strcmp(o, "--size"))
        return !(op->sized = parse_size(v, p));
    else if (!strcmp(o, "--terrain"))
        return !parse_terrain(v, p);
    else if (!strcmp(o, "--break-len"))
        return !parse_break_len(v, p);
    else if (!strcmp(o, "--fringe"))
        return !parse_fringe(v, p);
    else
        return 2;
    return 0;
}

/* A flag option: 1 when o was one. */
static int flag_opt(const char *o, opts *op)
{
    if (!strcmp(o, "--colour") || !strcmp(o, "--color"))
        op->p.colour = 1;
    else if (!strcmp(o, "--distractors"))
        op->p.distractors = 1;
    else if (!strcmp(o, "--print"))
        op->p.colour = op->p.distractors = op->p.print = 1;
    else if (!strcmp(o, "--unfaded"))
        op->p.unfaded = 1;
    else if (!strcmp(o, "--hachures"))
        op->p.hachures = 1;
    else if (!strcmp(o, "--streams"))
        op->p.colour = op->p.distractors = op->p.streams = 1;
    else if (!strcmp(o, "--tiff"))
        op->tiff = 1;
    else if (!strcmp(o, "--quiet") || !strcmp(o, "-q"))
        op->quiet = 1;
    else
        return 0;
    return 1;
}

/* Returns -1 to go on, else the exit status. */
static int parse(int argc, char **argv, opts *op)
{
    int i;
    for (i = 1; i < argc; i++) {
        const char *a = argv[i];
        int rc;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(usage, stdout);
            return 0;
        }
        if (flag_opt(a, op))
            continue;
        if (a[0] != '-')
            return fail("unexpected argument", a);
        if (i + 1 >= argc)
            return fail("missing value after", a);
        rc = value_opt(a, argv[i + 1], op);
        if (rc == 2)
            return fail("unknown option (see --help):", a);
        if (rc == 1) {
            fprintf(stderr, "tdgen: bad value for %s: %s\n", a, argv[i + 1]);
            return 1;
        }
        i++;
    }
    if (!op->out)
        return fail("missing -o SHEET (see --help)", NULL);
    if (op->tiff && op->p.colour)
        return fail("--tiff writes grey sheets only (no RGB TIFF writer); "
                    "use PNG for --colour",
                    NULL);
    return -1;
}

static int write_sheet(const opts *op, const td_image *im, td_ctx *cx)
{
    td_grid_u8 g;
    if (!op->tiff)
        return td_png_write(op->out, im, cx);
    g.w = im->w;
    g.h = im->h;
    g.stride = im->stride;
    g.data = im->data;
    return td_geotiff_write_u8(op->out, &g, NULL, cx);
}

/* --dem-in: read the source DEM and size the sheet from it. */
static int load_dem_in(opts *op, td_grid_f32 **src, td_ctx *cx)
{
    td_georef geo;
    int rc;
    td_georef_init(&geo);
    rc = td_dem_read(op->dem_in, src, &geo, cx);
    td_georef_clear(&geo);
    if (rc)
        return rc;
    op->p.terrain = TD_GEN_DEM;
    op->p.dem_in = *src;
    if (!op->sized) {
        double s = op->scale > 0 ? op->scale : 8.0;
        double w = (*src)->w * s, h = (*src)->h * s;
        if (w < 2 || h < 2 || w > TD_MAX_DIM || h > TD_MAX_DIM)
            return td_seterr(cx, TD_EINVAL, "--scale %g: sheet %.0f x %.0f "
                             "out of range", s, w, h);
        op->p.w = (int)(w + 0.5);
        op->p.h = (int)(h + 0.5);
    }
    return 0;
}

int main(int argc, char **argv)
{
    opts op;
    td_ctx cx;
    td_image *im = NULL;
    td_lines *ls = NULL;
    td_grid_f32 *dem = NULL, *src = NULL;
    double t0;
    int rc;
    memset(&op, 0, sizeof op);
    op.p = td_gen_defaults();
    if ((rc = parse(argc, argv, &op)) >= 0)
        return rc;
    td_ctx_init(&cx);
    t0 = td_now();
    rc = op.dem_in ? load_dem_in(&op, &src, &cx) : 0;
    if (!rc)
        rc = td_gen_sheet(&op.p, &im, &ls, &dem, &cx);
    if (!rc)
        rc = write_sheet(&op, im, &cx);
    if (!rc && op.truth)
        rc = td_geojson_write_lines(op.truth, ls, NULL, &cx);
    if (!rc && op.dem)
        rc = td_geotiff_write_f32(op.dem, dem, NULL, &cx);
    if (!rc && !op.quiet)
        fprintf(stderr,
                "tdgen: %dx%d sheet, interval %g, %zu truth lines, "
                "%.1f s\n",
                op.p.w, op.p.h, td_gen_auto_interval(&op.p, dem), ls->n,
                td_now() - t0);
    td_image_free(im);
    td_lines_free(ls);
    td_grid_f32_free(dem);
    td_grid_f32_free(src);
    if (rc)
        return fail(td_errmsg(&cx), NULL);
    return 0;
}
