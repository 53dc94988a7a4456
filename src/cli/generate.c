/* topodig generate: synthetic terrains; `mound` is the initial terrain of
 * the velocity-field erosion paper (Fujita, Muraoka, Chiba §3, Fig. 2a). */
#include "src/cli/cli.h"

#include "src/io/io.h"
#include "src/model/model.h"

#include <stdio.h>
#include <string.h>

typedef struct gen_opts {
    const char *kind, *out;
    int quiet, size, w, h, seed;
    double relief;
    td_mound_params p;
} gen_opts;

/* 0: run, 1: error (printed), 2: --help shown. */
static int parse_args(int argc, char **argv, gen_opts *o)
{
    const td_opt opts[] = {
        {"size", 0, TD_OPT_INT, &o->size, 1, 65536, .meta = "N",
         .help = "N x N cells"},
        {"width", 0, TD_OPT_INT, &o->w, 1, 65536, .meta = "W",
         .help = "a W x H grid instead (with --height-cells)", .no_default = 1},
        {"height-cells", 0, TD_OPT_INT, &o->h, 1, 65536, .meta = "H",
         .help = "the grid's height in cells", .no_default = 1},
        {"relief", 0, TD_OPT_DOUBLE, &o->relief, 0, 1e9, .meta = "H",
         .help = "mound height at the centre (default size / 8)",
         .no_default = 1},
        {"radius", 0, TD_OPT_DOUBLE, &o->p.radius, 1e-9, 1e9, .meta = "F",
         .help = "mound radius, fraction of half the side"},
        {"noise", 0, TD_OPT_DOUBLE, &o->p.noise, 0, 1e9, .meta = "A",
         .help = "white-noise amplitude, fraction of the relief\n(uniform "
         "in [-A, A] * relief)"},
        {"seed", 0, TD_OPT_INT, &o->seed, 0, 2147483647, .meta = "N",
         .help = "noise seed"},
        {NULL}};
    const td_cmd c = {
        "generate", "mound -o MOUND.tif [options]",
        "mound: a central mound, height H (1 - (r/R)^2)^2, plus uniform white\n"
        "noise, the initial terrain of the velocity-field erosion paper; run\n"
        "`topodig erode MOUND.tif -o ERODED.tif --snapshots 25` next.\n"
        "The same options give the same bytes.  The DEM: .tif float32\n"
        "GeoTIFF, .asc or .png.\n",
        NULL, opts, "the terrain kind 'mound'", 1, 1, &o->kind, &o->out,
        "MOUND.tif", &o->quiet};
    int rc = td_opt_parse(&c, argc, argv);
    if (rc == 0 && strcmp(o->kind, "mound") != 0)
        rc = td_cli_failf("generate", "expected the terrain kind 'mound' "
                          "(see topodig generate --help)");
    return rc;
}

int td_cmd_generate(int argc, char **argv)
{
    gen_opts o;
    td_grid_f32 *g = NULL;
    td_ctx cx;
    double t0 = td_now();
    int rc;
    memset(&o, 0, sizeof o);
    o.p = td_mound_defaults();
    o.size = o.p.w;
    o.seed = (int)o.p.seed;
    o.relief = -1;
    if ((rc = parse_args(argc, argv, &o)) != 0)
        return rc == 2 ? 0 : 1;
    td_ctx_init(&cx);
    o.p.w = o.w ? o.w : o.size;
    o.p.h = o.h ? o.h : o.size;
    o.p.seed = (uint64_t)o.seed;
    o.p.height = o.relief >= 0 ? o.relief : (o.p.w < o.p.h ? o.p.w : o.p.h) / 8.0;
    rc = (g = td_grid_f32_new(o.p.w, o.p.h, &cx)) ? 0 : TD_ENOMEM;
    if (rc == 0)
        rc = td_terrain_mound(g, &o.p, &cx);
    if (rc == 0)
        rc = td_dem_write(o.out, g, NULL, &cx);
    if (rc == 0 && !o.quiet)
        fprintf(stderr, "generate: mound %d x %d, relief %g, noise %g, seed "
                "%llu, %.2f s\n", o.p.w, o.p.h, o.p.height, o.p.noise,
                (unsigned long long)o.p.seed, td_now() - t0);
    td_grid_f32_free(g);
    return rc == 0 ? 0 : td_cli_fail("generate", &cx);
}
