/* topodig generate: synthetic terrains; `mound` is the initial terrain of
 * the velocity-field erosion paper (Fujita, Muraoka, Chiba §3, Fig. 2a). */
#define _GNU_SOURCE
#include "src/cli/cli.h"

#include "src/io/io.h"
#include "src/model/model.h"

#include <getopt.h>
#include <stdio.h>
#include <string.h>

int td_cmd_generate(int argc, char **argv);

static const char help[] =
    "usage: topodig generate mound -o MOUND.tif [options]\n"
    "\n"
    "mound: a central mound, height H (1 - (r/R)^2)^2, plus uniform white\n"
    "noise, the initial terrain of the velocity-field erosion paper; run\n"
    "`topodig erode MOUND.tif -o ERODED.tif --snapshots 25` next.\n"
    "The same options give the same bytes.\n"
    "\n"
    "options:\n"
    "  -o, --output FILE   DEM (.tif float32 GeoTIFF, .asc, .png) (required)\n"
    "      --size N        N x N cells [512]\n"
    "      --width W, --height-cells H   a W x H grid instead\n"
    "      --relief H      mound height at the centre [size / 8]\n"
    "      --radius F      mound radius, fraction of half the side [0.9]\n"
    "      --noise A       white-noise amplitude, fraction of the relief\n"
    "                      (uniform in [-A, A] * relief) [0.02]\n"
    "      --seed N        noise seed [1]\n"
    "  -q, --quiet         no summary\n"
    "  -h, --help          this help\n";

enum { O_SIZE = 256, O_W, O_H, O_RELIEF, O_RADIUS, O_NOISE, O_SEED };

static int parse_opt(int c, const char *arg, td_mound_params *p,
                     double *relief, td_ctx *cx)
{
    long v;
    double d;
    const char *name = c == O_SIZE ? "--size" : c == O_W ? "--width"
                       : c == O_H ? "--height-cells" : c == O_SEED ? "--seed"
                       : c == O_RELIEF ? "--relief" : c == O_RADIUS
                       ? "--radius" : "--noise";
    if (c == O_SIZE || c == O_W || c == O_H || c == O_SEED) {
        long hi = c == O_SEED ? 2147483647L : 65536;
        if (td_cli_parse_int(arg, c == O_SEED ? 0 : 1, hi, &v) != 0)
            return td_seterr(cx, TD_EINVAL, "%s: '%s' is not a whole number "
                             "%d..%ld", name, arg, c == O_SEED ? 0 : 1, hi);
        if (c == O_SIZE)
            p->w = p->h = (int)v;
        else if (c == O_W)
            p->w = (int)v;
        else if (c == O_H)
            p->h = (int)v;
        else
            p->seed = (uint64_t)v;
        return 0;
    }
    if (td_cli_parse_double(arg, 0, 1e9, &d) != 0 ||
        (c == O_RADIUS && d <= 0))
        return td_seterr(cx, TD_EINVAL, "%s: '%s' is not a number in %s",
                         name, arg, c == O_RADIUS ? "(0, 1e9]" : "0..1e9");
    if (c == O_RELIEF)
        *relief = d;
    else if (c == O_RADIUS)
        p->radius = d;
    else
        p->noise = d;
    return 0;
}

/* 0: run, 1: error (printed), 2: --help shown. */
static int parse_args(int argc, char **argv, td_mound_params *p,
                      double *relief, const char **out, int *quiet)
{
    static const struct option lo[] = {
        {"output", 1, 0, 'o'}, {"quiet", 0, 0, 'q'}, {"help", 0, 0, 'h'},
        {"size", 1, 0, O_SIZE}, {"width", 1, 0, O_W},
        {"height-cells", 1, 0, O_H}, {"relief", 1, 0, O_RELIEF},
        {"radius", 1, 0, O_RADIUS}, {"noise", 1, 0, O_NOISE},
        {"seed", 1, 0, O_SEED}, {0, 0, 0, 0}};
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
        if (c == 'o' || c == 'q') {
            if (c == 'o')
                *out = optarg;
            else
                *quiet = 1;
            continue;
        }
        if (c == '?' || c == ':')
            return td_cli_failf("generate", "bad or incomplete option '%s' "
                                "(see topodig generate --help)",
                                argv[optind - 1]);
        if (parse_opt(c, optarg, p, relief, &cx) != 0)
            return td_cli_fail("generate", &cx);
    }
    if (optind != argc - 1 || strcmp(argv[optind], "mound") != 0)
        return td_cli_failf("generate", "expected the terrain kind 'mound' "
                            "(see topodig generate --help)");
    if (!*out)
        return td_cli_failf("generate", "no output: give -o MOUND.tif");
    return 0;
}

int td_cmd_generate(int argc, char **argv)
{
    td_mound_params p = td_mound_defaults();
    td_grid_f32 *g = NULL;
    td_ctx cx;
    const char *out = NULL;
    double relief = -1, t0 = td_now();
    int quiet = 0, rc;
    if ((rc = parse_args(argc, argv, &p, &relief, &out, &quiet)) != 0)
        return rc == 2 ? 0 : 1;
    td_ctx_init(&cx);
    p.height = relief >= 0 ? relief : (p.w < p.h ? p.w : p.h) / 8.0;
    rc = (g = td_grid_f32_new(p.w, p.h, &cx)) ? 0 : TD_ENOMEM;
    if (rc == 0)
        rc = td_terrain_mound(g, &p, &cx);
    if (rc == 0)
        rc = td_dem_write(out, g, NULL, &cx);
    if (rc == 0 && !quiet)
        fprintf(stderr, "generate: mound %d x %d, relief %g, noise %g, seed "
                "%llu, %.2f s\n", p.w, p.h, p.height, p.noise,
                (unsigned long long)p.seed, td_now() - t0);
    td_grid_f32_free(g);
    return rc == 0 ? 0 : td_cli_fail("generate", &cx);
}
