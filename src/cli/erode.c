/* topodig erode: DEM -> DEM eroded by the velocity-field model (Fujita,
 * Muraoka, Chiba §2), with the W, E and deposited-sediment fields. */
#define _GNU_SOURCE
#include "src/cli/cli.h"

#include "src/io/io.h"
#include "src/erode/erode.h"
#include "src/model/model.h"

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int td_cmd_erode(int argc, char **argv);

static const char help[] =
    "usage: topodig erode DEM -o ERODED.tif [options]\n"
    "\n"
    "Velocity-field hydraulic erosion (Fujita, Muraoka, Chiba): every step\n"
    "puts a water particle on every cell, traces each one over the terrain,\n"
    "and erodes by flow (Kq Q) and collision (Ke e), carries up to Kc Q^m\n"
    "along the velocity field and deposits the rest.  Open grid edges drain;\n"
    "nodata cells are walls.  DEM: GeoTIFF/TIFF or ESRI ASCII grid.\n"
    "\n"
    "options (defaults in brackets; see docs/erode.md):\n"
    "  -o, --output FILE      eroded DEM (.tif float32 GeoTIFF, .asc, .png)\n"
    "      --steps N          repetitions of the velocity + erosion step [75]\n"
    "      --kq K             flow erosion coefficient, Sq = Kq Q [0.002]\n"
    "      --ke K             collision erosion coefficient, Se = Ke e [0.02]\n"
    "      --kc K             transport capacity, Smax = Kc Q^m [0.05]\n"
    "      --m M              capacity exponent [1]\n"
    "      --alpha A          friction, 0..1 [0.5]\n"
    "      --beta B           friction, > 0 [0.1]\n"
    "      --gravity G        gravity acceleration [1]\n"
    "      --dt T             time step of one particle move [1]\n"
    "      --water W          water per cell (each particle's w, m ~ w) [1]\n"
    "      --c C              Q = C w v [1]\n"
    "      --cell-size S      cell size in height units [the GeoTIFF's pixel\n"
    "                         size, in metres for degrees; else 1]\n"
    "      --max-moves N      moves per particle per step (0: 2 (w+h)) [0]\n"
    "      --v-stop V         a particle with no lower neighbour stops below\n"
    "                         this speed [0.001]\n"
    "      --edges E          open (drain) | closed (walls) [open]\n"
    "      --sediment-route R downhill: along V to a lower neighbour, else\n"
    "                         down the steepest descent | paper: along V,\n"
    "                         also uphill [downhill]\n"
    "      --flow-speed S     v in Q = C w v: mean (speed of the visits) |\n"
    "                         vector (|mean velocity|, the paper's V) [mean]\n"
    "      --deposit D        paper (S_I - Smax settles in the cell) | level\n"
    "                         (no cell dug below its lowest neighbour or\n"
    "                         raised past its feeders; depressions fill and\n"
    "                         spill: resolution-independent) [paper]\n"
    "      --noise A          add white noise of amplitude A (height units)\n"
    "                         to the DEM first, as the paper's start [0]\n"
    "      --seed N           seed of that noise [1]\n"
    "      --threads N        OpenMP threads, 0 = all cores; the result is\n"
    "                         the same bytes for any N [0]\n"
    "      --snapshots K      also write the DEM every K steps as\n"
    "                         OUT-stem_stepNNNN.ext (eroded_step0025.tif)\n"
    "      --out-water FILE   water W of the last step (particle visits * w)\n"
    "      --out-energy FILE  collision energy E of the last step\n"
    "      --out-sediment FILE  total deposited sediment thickness\n"
    "      --mass-log FILE    CSV, one line per step: eroded, deposited,\n"
    "                         carried out of the grid, residual, moves\n"
    "  -q, --quiet            no progress and no summary\n"
    "  -h, --help             this help\n"
    "\n"
    "Summary on stderr: steps, eroded, deposited and outflow volumes, mass\n"
    "residual, particle moves per second, mean path length, seconds.\n";

typedef struct erode_opts {
    const char *in, *out, *water, *energy, *sediment, *mass_log;
    int quiet, cell_given;
    double noise;
    long seed;
    td_erode_params p;
    /* filled while running */
    const td_georef *geo;
    td_erode_step_stats *log;
    int nlog;
    td_ctx *cx;
} erode_opts;

enum { O_STEPS = 256, O_KQ, O_KE, O_KC, O_M, O_ALPHA, O_BETA, O_G, O_DT,
       O_WATER, O_C, O_CELL, O_MAXMOVES, O_VSTOP, O_EDGES, O_NOISE, O_SEED,
       O_THREADS, O_SNAP, O_OWATER, O_OENERGY, O_OSED, O_MASSLOG, O_ROUTE,
       O_SPEED, O_DEPOSIT };

/* A word option: arg must be one of the two words; *dst = 0 or 1. */
static int word_opt(const char *name, const char *arg, const char *w0,
                    const char *w1, int *dst, td_ctx *cx)
{
    if (strcmp(arg, w0) && strcmp(arg, w1))
        return td_seterr(cx, TD_EINVAL, "%s: '%s' is not %s or %s", name,
                         arg, w0, w1);
    *dst = !strcmp(arg, w1);
    return 0;
}

/* Real-valued options: option code, name, lo, hi, target offset. */
static int real_opt(int c, const char *arg, erode_opts *o, td_ctx *cx)
{
    static const struct { int c; const char *name; double lo, hi; } t[] = {
        {O_KQ, "--kq", 0, 1e6}, {O_KE, "--ke", 0, 1e6}, {O_KC, "--kc", 0, 1e9},
        {O_M, "--m", 1e-6, 10}, {O_ALPHA, "--alpha", 0, 1},
        {O_BETA, "--beta", 1e-12, 1e9}, {O_G, "--gravity", 1e-12, 1e9},
        {O_DT, "--dt", 1e-9, 1e6}, {O_WATER, "--water", 1e-12, 1e9},
        {O_C, "--c", 1e-12, 1e9}, {O_CELL, "--cell-size", 1e-9, 1e9},
        {O_VSTOP, "--v-stop", 0, 1e9}, {O_NOISE, "--noise", 0, 1e9}};
    double *dst[] = {&o->p.kq, &o->p.ke, &o->p.kc, &o->p.m, &o->p.alpha,
                     &o->p.beta, &o->p.gravity, &o->p.dt, &o->p.water,
                     &o->p.c, &o->p.cell, &o->p.v_stop, &o->noise};
    size_t k;
    for (k = 0; k < sizeof t / sizeof *t; k++)
        if (t[k].c == c) {
            if (td_cli_parse_double(arg, t[k].lo, t[k].hi, dst[k]) != 0)
                return td_seterr(cx, TD_EINVAL, "%s: '%s' is not a number "
                                 "in %g..%g", t[k].name, arg, t[k].lo,
                                 t[k].hi);
            return 0;
        }
    return td_seterr(cx, TD_EINVAL, "unknown option (see topodig erode "
                     "--help)");
}

static int int_opt(const char *name, const char *arg, long lo, long hi,
                   long *v, td_ctx *cx)
{
    if (td_cli_parse_int(arg, lo, hi, v) != 0)
        return td_seterr(cx, TD_EINVAL, "%s: '%s' is not a whole number "
                         "%ld..%ld", name, arg, lo, hi);
    return 0;
}

static int parse_opt(int c, const char *arg, erode_opts *o, td_ctx *cx)
{
    long v = 0;
    int rc = 0;
    switch (c) {
    case 'o': o->out = arg; return 0;
    case 'q': o->quiet = 1; return 0;
    case O_OWATER: o->water = arg; return 0;
    case O_OENERGY: o->energy = arg; return 0;
    case O_OSED: o->sediment = arg; return 0;
    case O_MASSLOG: o->mass_log = arg; return 0;
    case O_EDGES:
        return word_opt("--edges", arg, "open", "closed", &o->p.closed_edges,
                        cx);
    case O_ROUTE:
        return word_opt("--sediment-route", arg, "downhill", "paper",
                        &o->p.route, cx);
    case O_SPEED:
        return word_opt("--flow-speed", arg, "mean", "vector", &o->p.speed,
                        cx);
    case O_DEPOSIT:
        return word_opt("--deposit", arg, "paper", "level", &o->p.deposit,
                        cx);
    case O_CELL:
        o->cell_given = 1;
        break;
    case O_STEPS: rc = int_opt("--steps", arg, 0, 1000000, &v, cx);
        o->p.steps = (int)v; return rc;
    case O_MAXMOVES: rc = int_opt("--max-moves", arg, 0, 100000000, &v, cx);
        o->p.max_moves = (int)v; return rc;
    case O_THREADS: rc = int_opt("--threads", arg, 0, 1024, &v, cx);
        o->p.threads = (int)v; return rc;
    case O_SNAP: rc = int_opt("--snapshots", arg, 0, 1000000, &v, cx);
        o->p.snapshot_every = (int)v; return rc;
    case O_SEED: return int_opt("--seed", arg, 0, 2147483647L, &o->seed, cx);
    }
    return real_opt(c, arg, o, cx);
}

/* 0: run, 1: error (printed), 2: --help shown. */
static int parse_args(int argc, char **argv, erode_opts *o)
{
    static const struct option lo[] = {
        {"output", 1, 0, 'o'}, {"quiet", 0, 0, 'q'}, {"help", 0, 0, 'h'},
        {"steps", 1, 0, O_STEPS}, {"kq", 1, 0, O_KQ}, {"ke", 1, 0, O_KE},
        {"kc", 1, 0, O_KC}, {"m", 1, 0, O_M}, {"alpha", 1, 0, O_ALPHA},
        {"beta", 1, 0, O_BETA}, {"gravity", 1, 0, O_G}, {"dt", 1, 0, O_DT},
        {"water", 1, 0, O_WATER}, {"c", 1, 0, O_C},
        {"cell-size", 1, 0, O_CELL}, {"max-moves", 1, 0, O_MAXMOVES},
        {"v-stop", 1, 0, O_VSTOP}, {"edges", 1, 0, O_EDGES},
        {"noise", 1, 0, O_NOISE}, {"seed", 1, 0, O_SEED},
        {"threads", 1, 0, O_THREADS}, {"snapshots", 1, 0, O_SNAP},
        {"out-water", 1, 0, O_OWATER}, {"out-energy", 1, 0, O_OENERGY},
        {"out-sediment", 1, 0, O_OSED}, {"mass-log", 1, 0, O_MASSLOG},
        {"sediment-route", 1, 0, O_ROUTE}, {"flow-speed", 1, 0, O_SPEED},
        {"deposit", 1, 0, O_DEPOSIT},
        {0, 0, 0, 0}};
    td_ctx cx;
    int c;
    td_ctx_init(&cx);
    opterr = 0;
    optind = 1;
    while ((c = getopt_long(argc, argv, "o:qh", lo, NULL)) != -1) {
        if (c == 'h') {
            fputs(help, stdout);
            return 2;
        }
        if (c == '?' || c == ':')
            return td_cli_failf("erode", "bad or incomplete option '%s' (see "
                                "topodig erode --help)", argv[optind - 1]);
        if (parse_opt(c, optarg, o, &cx) != 0)
            return td_cli_fail("erode", &cx);
    }
    if (optind != argc - 1)
        return td_cli_failf("erode", "expected one DEM file (see topodig "
                            "erode --help)");
    o->in = argv[optind];
    if (!o->out)
        return td_cli_failf("erode", "no output: give -o ERODED.tif");
    if (td_cli_check_output("erode", o->out, o->in) != 0)
        return 1;
    return 0;
}

/* OUT-stem_stepNNNN.ext */
static void snapshot_path(const char *out, int step, char *buf, size_t n)
{
    const char *slash = strrchr(out, '/'), *dot = strrchr(out, '.');
    if (!dot || (slash && dot < slash))
        dot = out + strlen(out);
    snprintf(buf, n, "%.*s_step%04d%s", (int)(dot - out), out, step, dot);
}

static int on_step(const td_erode_step_stats *s, const td_grid_f32 *dem,
                   void *user)
{
    erode_opts *o = user;
    if (o->mass_log) {
        td_erode_step_stats *l = realloc(o->log, (size_t)(o->nlog + 1) *
                                                     sizeof *l);
        if (!l)
            return td_seterr(o->cx, TD_ENOMEM, "out of memory"), 1;
        o->log = l;
        o->log[o->nlog++] = *s;
    }
    if (dem) {
        char path[4096];
        snapshot_path(o->out, s->step, path, sizeof path);
        if (td_dem_write(path, dem, o->geo, o->cx) != 0)
            return 1;
    }
    return 0;
}

static int write_mass_log(const erode_opts *o, td_ctx *cx)
{
    char tmp[4200];
    FILE *f;
    int k;
    if (strlen(o->mass_log) > 4000)
        return td_seterr(cx, TD_EINVAL, "--mass-log: path too long");
    if (!(f = td_atomic_open(o->mass_log, tmp, sizeof tmp, cx)))
        return TD_EIO;
    fputs("step,eroded,eroded_flow,eroded_collision,deposited,outflow,"
          "residual,moves,particles,drained\n", f);
    for (k = 0; k < o->nlog; k++) {
        const td_erode_step_stats *s = &o->log[k];
        double r = s->eroded > 0 ? (s->eroded - s->deposited - s->outflow) /
                                       s->eroded : 0.0;
        fprintf(f, "%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.3g,%.0f,%.0f,%.0f\n",
                s->step, s->eroded, s->eroded_flow, s->eroded_coll,
                s->deposited, s->outflow, r, s->moves, s->particles,
                s->drained);
    }
    return td_atomic_commit(f, tmp, o->mass_log, cx);
}

static int write_outputs(const erode_opts *o, const td_grid_f32 *out,
                         const td_erode_fields *f, const td_georef *geo,
                         td_ctx *cx)
{
    /* the secondary outputs first: when one fails, the main output (new
       or old) is left as it was */
    int rc = 0;
    if (o->water)
        rc = td_dem_write(o->water, f->water, geo, cx);
    if (rc == 0 && o->energy)
        rc = td_dem_write(o->energy, f->energy, geo, cx);
    if (rc == 0 && o->sediment)
        rc = td_dem_write(o->sediment, f->sediment, geo, cx);
    if (rc == 0 && o->mass_log)
        rc = write_mass_log(o, cx);
    if (rc == 0)
        rc = td_dem_write(o->out, out, geo, cx);
    return rc;
}

static void summary(const td_erode_stats *st, double secs)
{
    const td_erode_step_stats *t = &st->total;
    fprintf(stderr,
            "erode: %d steps, eroded %.6g, deposited %.6g, outflow %.6g, "
            "residual %.2g, %.4g particle moves (%.3g M/s), mean path %.1f "
            "moves, %.2f s\n",
            t->step, t->eroded, t->deposited, t->outflow, st->residual,
            t->moves, secs > 0 ? t->moves / secs / 1e6 : 0.0, st->path_mean,
            secs);
}

/* Without --cell-size: the pixel size of the DEM's georeferencing, the
 * mean of |gt[1]| and |gt[5]| (square cells expected); for a geographic
 * CRS (GTModelTypeGeoKey 2, degrees) converted to metres at the DEM's
 * centre latitude (heights are then taken to be metres). */
static void cell_from_georef(erode_opts *o, const td_georef *geo,
                             const td_grid_f32 *in)
{
    const double deg = 111319.49; /* metres per degree on the equator */
    double sx, sy;
    int model = 0;
    if (o->cell_given || !geo->valid || geo->pixel)
        return;
    sx = fabs(geo->gt[1]);
    sy = fabs(geo->gt[5]);
    if (!(sx > 0) || !(sy > 0) || !isfinite(sx) || !isfinite(sy))
        return;
    if (td_georef_geokey(geo, 1024, &model) && model == 2) {
        double X, lat;
        td_georef_apply(geo, 0.5 * in->w, 0.5 * in->h, &X, &lat);
        sx *= deg * cos(lat * M_PI / 180.0);
        sy *= deg;
    }
    o->p.cell = 0.5 * (sx + sy);
    if (!o->quiet)
        fprintf(stderr, "erode: cell size %.6g from the georeferencing%s\n",
                o->p.cell, model == 2 ? " (degrees -> metres)" : "");
}

/* Allocate out and the requested fields with in's size and nodata. */
static int alloc_grids(const erode_opts *o, const td_grid_f32 *in,
                       td_grid_f32 **out, td_erode_fields *f, td_ctx *cx)
{
    if (!(*out = td_grid_f32_new(in->w, in->h, cx)) ||
        (o->water && !(f->water = td_grid_f32_new(in->w, in->h, cx))) ||
        (o->energy && !(f->energy = td_grid_f32_new(in->w, in->h, cx))) ||
        (o->sediment && !(f->sediment = td_grid_f32_new(in->w, in->h, cx))))
        return TD_ENOMEM;
    (*out)->nodata = in->nodata;
    (*out)->has_nodata = in->has_nodata;
    return 0;
}

int td_cmd_erode(int argc, char **argv)
{
    erode_opts o;
    td_ctx cx;
    td_cli_progress pr;
    td_grid_f32 *in = NULL, *out = NULL;
    td_erode_fields f = {NULL, NULL, NULL};
    td_erode_stats st;
    td_georef geo;
    double t0 = td_now();
    int rc;
    memset(&o, 0, sizeof o);
    o.p = td_erode_defaults();
    o.seed = 1;
    if ((rc = parse_args(argc, argv, &o)) != 0)
        return rc == 2 ? 0 : 1;
    td_ctx_init(&cx);
    td_georef_init(&geo);
    if ((rc = td_erode_check(&o.p, &cx)) != 0)
        return td_cli_fail("erode", &cx);
    td_cli_progress_init(&pr, &cx, o.quiet);
    o.geo = &geo;
    o.cx = &cx;
    o.p.on_step = on_step;
    o.p.user = &o;
    rc = td_dem_read(o.in, &in, &geo, &cx);
    if (rc == 0) {
        cell_from_georef(&o, &geo, in);
        rc = alloc_grids(&o, in, &out, &f, &cx);
    }
    if (rc == 0 && o.noise > 0)
        rc = td_terrain_noise(in, o.noise, (uint64_t)o.seed, &cx);
    if (rc == 0)
        rc = td_erode_run(in, &o.p, out, &f, &st, &cx);
    if (rc == 0)
        rc = write_outputs(&o, out, &f, &geo, &cx);
    td_cli_progress_done(&pr);
    if (rc == 0 && !o.quiet)
        summary(&st, td_now() - t0);
    td_grid_f32_free(in);
    td_grid_f32_free(out);
    td_grid_f32_free(f.water);
    td_grid_f32_free(f.energy);
    td_grid_f32_free(f.sediment);
    td_georef_clear(&geo);
    free(o.log);
    return rc == 0 ? 0 : td_cli_fail_on("erode", o.in, o.out, &cx);
}
