/* topodig erode: DEM -> DEM eroded by the velocity-field model (Fujita,
 * Muraoka, Chiba §2), with the W, E and deposited-sediment fields. */
#include "src/cli/cli.h"

#include "src/io/io.h"
#include "src/erode/erode.h"
#include "src/model/model.h"
#include "src/pipeline/pipeline.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct erode_opts {
    const char *in;
    td_erode_files f;
    int quiet, seed, map_units, deposit;
    double noise, rest;
    td_erode_params p;
} erode_opts;

/* 0: run, 1: error (printed), 2: --help shown. */
static int parse_args(int argc, char **argv, erode_opts *o)
{
    td_erode_params *p = &o->p;
    const td_opt opts[] = {
        {"steps", 0, TD_OPT_INT, &p->steps, 0, 1000000, .meta = "N",
         .help = "repetitions of the velocity + erosion step"},
        {"kq", 0, TD_OPT_DOUBLE, &p->kq, 0, 1e6, .meta = "K",
         .help = "flow erosion coefficient, Sq = Kq Q"},
        {"ke", 0, TD_OPT_DOUBLE, &p->ke, 0, 1e6, .meta = "K",
         .help = "collision erosion coefficient, Se = Ke e"},
        {"kc", 0, TD_OPT_DOUBLE, &p->kc, 0, 1e9, .meta = "K",
         .help = "transport capacity, Smax = Kc Q^m"},
        {"m", 0, TD_OPT_DOUBLE, &p->m, 1e-6, 10, .meta = "M",
         .help = "capacity exponent"},
        {"alpha", 0, TD_OPT_DOUBLE, &p->alpha, 0, 1, .meta = "A",
         .help = "friction, 0..1"},
        {"beta", 0, TD_OPT_DOUBLE, &p->beta, 1e-12, 1e9, .meta = "B",
         .help = "friction, > 0"},
        {"gravity", 0, TD_OPT_DOUBLE, &p->gravity, 1e-12, 1e9, .meta = "G",
         .help = "gravity acceleration"},
        {"dt", 0, TD_OPT_DOUBLE, &p->dt, 1e-9, 1e6, .meta = "T",
         .help = "time step of one particle move"},
        {"water", 0, TD_OPT_DOUBLE, &p->water, 1e-12, 1e9, .meta = "W",
         .help = "water per cell (each particle's w, m ~ w)"},
        {"c", 0, TD_OPT_DOUBLE, &p->c, 1e-12, 1e9, .meta = "C",
         .help = "Q = C w v"},
        {"units", 0, TD_OPT_CHOICE, &o->map_units, .choices = "cells|map",
         .meta = "U", .help = "cells: the model runs on the heights in cell\n"
         "units (divided by the cell size; the\nparameters are the paper's, "
         "for cell 1), the\noutput back in the DEM's units | map: the\n"
         "parameters in the DEM's units with its cell\nsize (slow on real "
         "DEMs: docs/erode.md)"},
        {"cell-size", 0, TD_OPT_DOUBLE, &p->cell, 1e-9, 1e9, .meta = "S",
         .help = "cell size in height units (default: from the\n"
         "georeferencing, in metres for degrees; else 1)", .no_default = 1},
        {"max-moves", 0, TD_OPT_INT, &p->max_moves, 0, 100000000, .meta = "N",
         .help = "moves per particle per step (0: 2 (w+h))"},
        {"rest-accel", 0, TD_OPT_DOUBLE, &o->rest, -1, 1e9, .meta = "A",
         .help = "ours: a particle slower than --v-stop also\nrests where "
         "the slope accelerates it less than\nA (it would creep for "
         "thousands of moves);\n0: only where no neighbour is lower (the\n"
         "paper); default: --v-stop on a georeferenced\nDEM, else 0",
         .no_default = 1},
        {"v-stop", 0, TD_OPT_DOUBLE, &p->v_stop, 0, 1e9, .meta = "V",
         .help = "a particle with no lower neighbour stops below\nthis speed"},
        {"edges", 0, TD_OPT_CHOICE, &p->closed_edges, .choices = "open|closed",
         .meta = "E", .help = "open (drain) | closed (walls)"},
        {"sediment-route", 0, TD_OPT_CHOICE, &p->route, .meta = "R",
         .choices = "downhill|paper", .help = "downhill: along V to a lower "
         "neighbour, else\ndown the steepest descent | paper: along V,\n"
         "also uphill"},
        {"flow-speed", 0, TD_OPT_CHOICE, &p->speed, .choices = "mean|vector",
         .meta = "S", .help = "v in Q = C w v: mean (speed of the visits) |\n"
         "vector (|mean velocity|, the paper's V)"},
        {"deposit", 0, TD_OPT_CHOICE, &o->deposit, .choices =
         "auto|paper|level", .meta = "D", .help = "paper (S_I - Smax settles "
         "in the cell) | level\n(no cell dug below its lowest neighbour or\n"
         "raised past its feeders; depressions fill and\nspill: resolution-"
         "independent) | auto: level\non a georeferenced DEM (a real one: "
         "the\npaper's rule piles single cells hundreds of\nmetres high "
         "there), else paper"},
        {"noise", 0, TD_OPT_DOUBLE, &o->noise, 0, 1e9, .meta = "A",
         .help = "add white noise of amplitude A (height units)\nto the DEM "
         "first, as the paper's start"},
        {"seed", 0, TD_OPT_INT, &o->seed, 0, 2147483647.0, .meta = "N",
         .help = "seed of that noise"},
        {"threads", 0, TD_OPT_INT, &p->threads, 0, 1024, .meta = "N",
         .help = "OpenMP threads, 0 = all cores; the result is\nthe same "
         "bytes for any N"},
        {"snapshots", 0, TD_OPT_INT, &p->snapshot_every, 0, 1000000,
         .meta = "K", .help = "also write the DEM every K steps as\n"
         "OUT-stem_stepNNNN.ext (eroded_step0025.tif)"},
        {"out-water", 0, TD_OPT_OUTPUT, &o->f.water, .meta = "FILE",
         .help = "water W of the last step (particle visits * w)"},
        {"out-energy", 0, TD_OPT_OUTPUT, &o->f.energy, .meta = "FILE",
         .help = "collision energy E of the last step"},
        {"out-sediment", 0, TD_OPT_OUTPUT, &o->f.sediment, .meta = "FILE",
         .help = "total deposited sediment thickness"},
        {"mass-log", 0, TD_OPT_OUTPUT, &o->f.mass_log, .meta = "FILE",
         .help = "CSV, one line per step: eroded, deposited,\ncarried out "
         "of the grid, residual, moves"},
        {NULL}};
    const td_cmd c = {
        "erode", "DEM -o ERODED.tif [options]",
        "Velocity-field hydraulic erosion (Fujita, Muraoka, Chiba): every step\n"
        "puts a water particle on every cell, traces each one over the terrain,\n"
        "and erodes by flow (Kq Q) and collision (Ke e), carries up to Kc Q^m\n"
        "along the velocity field and deposits the rest.  Open grid edges drain;\n"
        "nodata cells are walls.  DEM: GeoTIFF/TIFF or ESRI ASCII grid; the\n"
        "output .tif float32 GeoTIFF, .asc or .png (docs/erode.md).\n",
        "Summary on stderr: steps, eroded, deposited and outflow volumes, mass\n"
        "residual, particle moves per second, mean path length, seconds.\n",
        opts, "one DEM file", 1, 1, &o->in, &o->f.out, "ERODED.tif",
        &o->quiet};
    return td_opt_parse(&c, argc, argv);
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

int td_cmd_erode(int argc, char **argv)
{
    erode_opts o;
    td_ctx cx;
    td_cli_progress pr;
    td_grid_f32 *in = NULL;
    td_erode_stats st;
    td_georef geo;
    double t0 = td_now();
    int rc, deg = 0;
    memset(&o, 0, sizeof o);
    o.p = td_erode_defaults();
    o.p.cell = 0; /* unless given: from the georeferencing, else 1 */
    o.seed = 1;
    o.rest = -1; /* unless given: v_stop on a georeferenced DEM, else 0 */
    if ((rc = parse_args(argc, argv, &o)) != 0)
        return rc == 2 ? 0 : 1;
    td_ctx_init(&cx);
    td_georef_init(&geo);
    td_cli_progress_init(&pr, &cx, o.quiet);
    rc = td_dem_read(o.in, &in, &geo, &cx);
    if (rc == 0 && !(o.p.cell > 0)) {
        o.p.cell = td_georef_cell_size(&geo, in->w, in->h, &deg);
        if (o.p.cell > 0 && !o.quiet)
            fprintf(stderr, "erode: cell size %.6g from the georeferencing%s"
                    "\n", o.p.cell, deg ? " (degrees -> metres)" : "");
        if (!(o.p.cell > 0))
            o.p.cell = 1.0;
    }
    if (rc == 0) {
        int real = geo.valid && !geo.pixel;
        o.p.deposit = o.deposit == 1   ? TD_ERODE_DEPOSIT_PAPER
                      : o.deposit == 2 ? TD_ERODE_DEPOSIT_LEVEL
                      : real           ? TD_ERODE_DEPOSIT_LEVEL
                                       : TD_ERODE_DEPOSIT_PAPER;
        if (o.deposit == 0 && real && !o.quiet)
            fprintf(stderr, "erode: --deposit level on a georeferenced DEM "
                    "(--deposit paper for the paper's rule)\n");
        o.p.rest_accel = o.rest >= 0 ? o.rest : real ? o.p.v_stop : 0;
        if (o.rest < 0 && real && !o.quiet)
            fprintf(stderr, "erode: --rest-accel %g on a georeferenced DEM "
                    "(0 for the paper's rest rule)\n", o.p.rest_accel);
    }
    if (rc == 0 && !o.map_units && o.p.cell != 1) {
        if (!o.quiet)
            fprintf(stderr, "erode: the model runs in cell units (heights / "
                    "%.6g; --units map to run in the DEM's)\n", o.p.cell);
        o.f.cell_units = o.p.cell;
        o.p.cell = 1;
    }
    if (rc == 0)
        rc = td_erode_check(&o.p, &cx);
    if (rc == 0 && o.noise > 0)
        rc = td_terrain_noise(in, o.noise, (uint64_t)o.seed, &cx);
    if (rc == 0)
        rc = td_pipeline_erode(in, &geo, &o.p, &o.f, &st, &cx);
    td_cli_progress_done(&pr);
    if (rc == 0 && !o.quiet)
        summary(&st, td_now() - t0);
    td_grid_f32_free(in);
    td_georef_clear(&geo);
    return rc == 0 ? 0 : td_cli_fail_on("erode", o.in, o.f.out, &cx);
}
