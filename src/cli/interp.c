/* topodig interp: labelled contour lines -> DEM (GeoTIFF, .asc, .png). */
#define _GNU_SOURCE
#include "src/cli/cli.h"

#include "src/io/io.h"
#include "src/core/core.h"
#include "interp/homotopy.h"
#include "interp/interp.h"

#include <getopt.h>
#include <stdio.h>
#include <string.h>

static const char help[] =
    "usage: topodig interp LABELLED.geojson -o DEM.tif --like SCAN\n"
    "                      [--method multidir|scanline|homotopy] [--step N]\n"
    "\n"
    "Rasterise the labelled contour lines onto the scan's grid and\n"
    "interpolate the heights between them.  The DEM has the scan's size\n"
    "(one cell per pixel; --step N: one per N x N pixels) and its\n"
    "georeferencing; cells no contour pair determines are nodata.\n"
    "Output by extension: .tif float32 GeoTIFF (nodata tag), .asc ESRI\n"
    "ASCII grid, .png 16-bit grey.\n"
    "\n"
    "options:\n"
    "  -o, --output FILE     DEM output (required)\n"
    "      --like SCAN       the scan the lines were traced from (required:\n"
    "                        size and georeferencing)\n"
    "      --method M        multidir (default): 4 scan directions blended;\n"
    "                        scanline: the paper's x then y pass (001 §2.4);\n"
    "                        homotopy: along ridge and valley lines found\n"
    "                        from contour curvature (003), scanline where\n"
    "                        it cannot reach\n"
    "      --epsilon DEG     homotopy: turning-angle threshold (default 20)\n"
    "      --fallback M      homotopy: scanline (default) | multidir for the\n"
    "                        cells the homotopy cannot reach\n"
    "      --step N          one DEM cell per N x N scan pixels (default 1)\n"
    "      --summit S        extrapolate (default, paper §2.5) | flat\n"
    "      --peninsula P     scanline only: diagonal (default) | flat (paper)\n"
    "      --weight W        multidir only: span (default) | prod | span2\n"
    "      --dirs N          multidir only: 4 (default) or 2 directions\n"
    "      --interval I      contour interval for the summit cap (default:\n"
    "                        the smallest step between line heights)\n"
    "      --nodata V        nodata value (default -9999)\n"
    "      --smooth N        N sweeps of smoothing within the contour bands\n"
    "                        (default 0; ours: removes the creases of the\n"
    "                        linear blend, see docs/interp.md)\n"
    "  -q, --quiet           no progress and no summary\n"
    "  -h, --help            this help\n"
    "\n"
    "Summary on stderr: cells, determined fraction, method, seconds.\n";

typedef struct ip_opts {
    const char *in, *out, *like;
    int quiet;
    td_interp_params p;
} ip_opts;

enum { O_LIKE = 256, O_PASS };

static int parse_args(int argc, char **argv, ip_opts *o)
{
    static const struct option lo[] = {
        {"output", 1, 0, 'o'}, {"like", 1, 0, O_LIKE},
        {"method", 1, 0, O_PASS}, {"step", 1, 0, O_PASS},
        {"summit", 1, 0, O_PASS}, {"peninsula", 1, 0, O_PASS},
        {"weight", 1, 0, O_PASS}, {"dirs", 1, 0, O_PASS},
        {"interval", 1, 0, O_PASS}, {"nodata", 1, 0, O_PASS},
        {"smooth", 1, 0, O_PASS},
        {"epsilon", 1, 0, O_PASS}, {"fallback", 1, 0, O_PASS},
        {"quiet", 0, 0, 'q'}, {"help", 0, 0, 'h'}, {0, 0, 0, 0}};
    td_ctx cx;
    int c, li = -1;
    td_ctx_init(&cx);
    opterr = 0;
    while ((c = getopt_long(argc, argv, "o:qh", lo, &li)) != -1) {
        if (c == 'h') {
            fputs(help, stdout);
            return 2;
        } else if (c == 'o')
            o->out = optarg;
        else if (c == 'q')
            o->quiet = 1;
        else if (c == O_LIKE)
            o->like = optarg;
        else if (c == O_PASS) {
            if (td_interp_set(&o->p, lo[li].name, optarg, &cx) != 0)
                return td_cli_fail("interp", &cx);
        } else
            return td_cli_failf("interp", "bad or incomplete option '%s' "
                                "(see topodig interp --help)",
                                argv[optind - 1]);
    }
    if (optind != argc - 1)
        return td_cli_failf("interp", "expected one LABELLED.geojson file "
                            "(see topodig interp --help)");
    o->in = argv[optind];
    if (!o->out)
        return td_cli_failf("interp", "no output: give -o DEM.tif");
    if (td_cli_check_output("interp", o->out, o->in) != 0)
        return 1;
    if (!o->like)
        return td_cli_failf("interp", "no grid: give --like SCAN (the scan "
                            "the lines come from)");
    return 0;
}

static void summary(const td_grid_f32 *g, const td_interp_params *p,
                    double secs)
{
    static const char *const names[] = {"scanline", "multidir", "homotopy"};
    size_t n = (size_t)g->w * g->h, i, ok = 0;
    const td_homotopy_stats *hs = p->hstats;
    for (i = 0; i < n; i++)
        ok += g->data[i] != g->nodata;
    fprintf(stderr, "interp: %d x %d cells, %.1f%% determined, method %s, "
            "%.2f s\n", g->w, g->h, 100.0 * ok / n, names[p->method], secs);
    if (p->method == TD_INTERP_HOMOTOPY && hs)
        fprintf(stderr, "interp: homotopy %zu cells in %zu of %zu bands, "
                "%s fallback %zu cells; %zu ridge, %zu valley points, "
                "%zu links\n", hs->cells_homotopy, hs->bands_homotopy,
                hs->bands, p->homotopy.fallback == TD_HM_FALLBACK_MULTIDIR ? "multidir" : "scanline",
                hs->cells_fallback, hs->ridge_points, hs->valley_points,
                hs->links);
}

/* Prefix the file name when the message does not name it. */
static void name_file(td_ctx *cx, const char *path)
{
    char m[sizeof cx->msg];
    if (!cx->msg[0] || strstr(cx->msg, path))
        return;
    snprintf(m, sizeof m, "%.200s: %.300s", path, cx->msg);
    memcpy(cx->msg, m, sizeof m);
}

int td_cmd_interp(int argc, char **argv)
{
    ip_opts o;
    td_ctx cx;
    td_cli_progress pr;
    td_georef geo;
    td_lines *ls = NULL;
    td_grid_f32 *dem = NULL;
    td_homotopy_stats hs;
    double t0 = td_now();
    int rc, w, h, ch;
    memset(&o, 0, sizeof o);
    o.p = td_interp_defaults();
    memset(&hs, 0, sizeof hs);
    o.p.hstats = &hs;
    if ((rc = parse_args(argc, argv, &o)) != 0)
        return rc == 2 ? 0 : 1;
    td_ctx_init(&cx);
    td_georef_init(&geo);
    td_cli_progress_init(&pr, &cx, o.quiet);
    if ((rc = td_image_info(o.like, &w, &h, &ch, &geo, &cx)) != 0)
        goto fail;
    if ((rc = td_vector_read_lines(o.in, &geo, &ls, NULL, NULL, &cx)) != 0)
        goto fail;
    if ((rc = td_interp_lines(ls, w, h, &o.p, &dem, &cx)) != 0) {
        name_file(&cx, o.in);
        goto fail;
    }
    td_georef_scale(&geo, o.p.step);
    if ((rc = td_dem_write(o.out, dem, &geo, &cx)) != 0)
        goto fail;
    td_cli_progress_done(&pr);
    if (!o.quiet)
        summary(dem, &o.p, td_now() - t0);
fail:
    td_cli_progress_done(&pr);
    td_grid_f32_free(dem);
    td_lines_free(ls);
    td_georef_clear(&geo);
    return rc == 0 ? 0 : td_cli_fail_on("interp", o.in, o.out, &cx);
}
