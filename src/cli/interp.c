/* topodig interp: labelled contour lines -> DEM (GeoTIFF, .asc, .png). */
#include "src/cli/cli.h"

#include "src/io/io.h"
#include "src/core/core.h"
#include "interp/homotopy.h"
#include "interp/interp.h"
#include "scanner/faces.h"
#include "scanner/label.h"

#include <stdio.h>
#include <string.h>

/* See cli.h. */
size_t td_cli_interp_opts(td_opt *v, td_interp_params *p)
{
    const td_opt o[TD_CLI_INTERP_OPTS] = {
        {"method", 0, TD_OPT_CHOICE, &p->method,
         .choices = "scanline|multidir|homotopy", .meta = "M",
         .help = "multidir: 4 scan directions blended;\nscanline: the "
         "paper's x then y pass (001 §2.4);\nhomotopy: along ridge and "
         "valley lines found\nfrom contour curvature (003), scanline where\n"
         "it cannot reach"},
        {"epsilon", 0, TD_OPT_DOUBLE, &p->homotopy.epsilon, 0, 180,
         .meta = "DEG", .help = "homotopy: turning-angle threshold"},
        {"fallback", 0, TD_OPT_CHOICE, &p->homotopy.fallback,
         .choices = "scanline|multidir", .meta = "M",
         .help = "homotopy: who fills the cells the homotopy\ncannot reach"},
        {"step", 0, TD_OPT_INT, &p->step, 1, 4096, .meta = "N",
         .help = "one DEM cell per N x N scan pixels"},
        {"summit", 0, TD_OPT_CHOICE, &p->scanline.summit,
         .choices = "flat|extrapolate", .meta = "S",
         .help = "extrapolate (paper §2.5) | flat"},
        {"peninsula", 0, TD_OPT_CHOICE, &p->scanline.peninsula,
         .choices = "flat|diagonal", .meta = "P",
         .help = "scanline: diagonal (ours) | flat (paper)"},
        {"weight", 0, TD_OPT_CHOICE, &p->multidir.weight,
         .choices = "prod|span|span2", .meta = "W",
         .help = "multidir: span | prod | span2"},
        {"dirs", 0, TD_OPT_INT, &p->multidir.ndir, 2, 4, .meta = "N",
         .help = "multidir: 4 or 2 directions"},
        {"interval", 0, TD_OPT_DOUBLE, &p->interval, 1e-9, 1e9, .meta = "I",
         .help = "contour interval for the summit cap (default:\nthe "
         "smallest step between line heights)", .no_default = 1},
        {"nodata", 0, TD_OPT_FLOAT, &p->nodata, -3e38, 3e38, .meta = "V",
         .help = "nodata value"},
        {"smooth", 0, TD_OPT_INT, &p->smooth, 0, 10000, .meta = "N",
         .help = "N sweeps of smoothing within the contour bands\n(ours: "
         "removes the creases of the linear blend,\nsee docs/interp.md)"},
    };
    memcpy(v, o, sizeof o);
    return TD_CLI_INTERP_OPTS;
}

/* See cli.h. */
int td_cli_interp_check(const char *cmd, td_interp_params *p)
{
    if (p->multidir.ndir == 3)
        return td_cli_failf(cmd, "--dirs: 2 or 4");
    p->multidir.summit = p->scanline.summit;
    return 0;
}

#define MAX_BESIDE 16

typedef struct beside_list {
    const char *v[MAX_BESIDE];
    int n;
} beside_list;

typedef struct ip_opts {
    const char *in, *out, *like;
    int quiet, margin;
    double bridge;
    beside_list beside;
    td_interp_params p;
} ip_opts;

static int add_beside(const char *arg, void *t, td_ctx *cx)
{
    beside_list *b = t;
    if (b->n == MAX_BESIDE)
        return td_seterr(cx, TD_EINVAL, "--beside: at most %d files",
                         MAX_BESIDE);
    b->v[b->n++] = arg;
    return 0;
}

static int parse_args(int argc, char **argv, ip_opts *o)
{
    td_opt opts[TD_CLI_INTERP_OPTS + 5] = {
        {"like", 0, TD_OPT_STRING, &o->like, .meta = "SCAN", .help = "the "
         "scan the lines were traced from (required:\nsize and "
         "georeferencing)"},
        {"beside", 0, TD_OPT_FUNC, &o->beside, .fn = add_beside,
         .meta = "LINES", .help = "a neighbouring sheet's labelled lines "
         "(in map\ncoordinates; repeatable): interpolated with\nthis "
         "sheet's within --margin of its edges,\nso the two DEMs meet at "
         "the shared edge", .no_default = 1},
        {"margin", 0, TD_OPT_INT, &o->margin, 1, 65536, .meta = "PX",
         .help = "how far beyond the edges --beside lines count"},
        {"bridge", 0, TD_OPT_DOUBLE, &o->bridge, 0, 1e6, .meta = "PX",
         .help = "join lines of one height across breaks\nbetween their "
         "ends up to PX long, as run\ndoes (ours; 0: off; default 5 times "
         "the\nspacing of the contours, 48 to 160)", .no_default = 1}};
    size_t n = 4 + td_cli_interp_opts(opts + 4, &o->p);
    const td_cmd c = {
        "interp", "LABELLED.geojson -o DEM.tif --like SCAN\n"
        "                      [--method multidir|scanline|homotopy] [--step N]",
        "Rasterise the labelled contour lines onto the scan's grid and\n"
        "interpolate the heights between them.  The DEM has the scan's size\n"
        "(one cell per pixel; --step N: one per N x N pixels) and its\n"
        "georeferencing; cells no contour pair determines are nodata.\n"
        "Lines: .geojson, .gpkg, .shp or .dxf.  DEM by extension: .tif\n"
        "float32 GeoTIFF (nodata tag), .asc ESRI ASCII grid, .png 16-bit grey.\n",
        "Summary on stderr: cells, determined fraction, method, seconds.\n",
        opts, "one LABELLED.geojson file", 1, 1, &o->in, &o->out, "DEM.tif",
        &o->quiet};
    int rc;
    opts[n].name = NULL;
    if ((rc = td_opt_parse(&c, argc, argv)) != 0)
        return rc;
    if (!o->like)
        return td_cli_failf("interp", "no grid: give --like SCAN (the scan "
                            "the lines come from)");
    if (o->beside.n > 0 && !strcmp(o->beside.v[0], o->in))
        return td_cli_failf("interp", "--beside %s: that is the input "
                            "itself", o->in);
    return td_cli_interp_check("interp", &o->p);
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

/* Lines a labeller left without a height (as run leaves them out of its
 * DEM) are left out, with a warning, when others have heights; with none
 * at all the rasteriser says to label the lines first. */
static void drop_unlabelled(td_lines *ls, int quiet)
{
    size_t i, with = 0, n0 = ls->n;
    for (i = 0; i < ls->n; i++)
        with += ls->v[i].has_height;
    if (with == 0 || with == ls->n)
        return;
    for (i = ls->n; i-- > 0;)
        if (!ls->v[i].has_height)
            td_lines_remove(ls, i);
    if (!quiet)
        fprintf(stderr, "interp: warning: %zu line%s without a height left "
                "out\n", n0 - ls->n, n0 - ls->n == 1 ? "" : "s");
}

/* The --beside files' lines, taken through their map coordinates into
 * the scan's pixel frame (geo), into one set (*out; NULL when none). */
static int read_beside(const ip_opts *o, const td_georef *geo,
                       td_lines **out, td_ctx *cx)
{
    int i, rc = 0;
    size_t k;
    *out = NULL;
    if (o->beside.n == 0)
        return 0;
    if (!geo->valid)
        return td_seterr(cx, TD_EINVAL, "%s: not georeferenced: --beside "
                         "needs the sheets' map coordinates", o->like);
    if (!(*out = td_lines_new(cx)))
        return TD_ENOMEM;
    for (i = 0; i < o->beside.n && rc == 0; i++) {
        td_lines *b = NULL;
        if ((rc = td_vector_read_lines(o->beside.v[i], geo, &b, NULL, NULL,
                                       cx)) != 0) {
            name_file(cx, o->beside.v[i]);
            break;
        }
        for (k = 0; k < b->n && rc == 0; k++)
            rc = td_lines_append_copy(*out, &b->v[k], cx);
        td_lines_free(b);
    }
    return rc;
}

int td_cmd_interp(int argc, char **argv)
{
    ip_opts o;
    td_ctx cx;
    td_cli_progress pr;
    td_georef geo;
    td_lines *ls = NULL, *nb = NULL;
    td_grid_f32 *dem = NULL;
    td_homotopy_stats hs;
    double t0 = td_now(), spacing = 0;
    size_t nbr = 0;
    int rc, w, h, ch;
    memset(&o, 0, sizeof o);
    o.p = td_interp_defaults();
    o.margin = 256;
    o.bridge = -1; /* five contour spacings */
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
    if ((rc = read_beside(&o, &geo, &nb, &cx)) != 0)
        goto fail;
    drop_unlabelled(ls, o.quiet);
    if (o.bridge < 0 && td_label_inner_ends(ls, w, h)) {
        if ((rc = td_lines_spacing(ls, w, h, &spacing, &cx)) != 0)
            goto fail;
        o.bridge = td_label_bridge_reach(spacing);
    }
    if (o.bridge > 0 && (rc = td_label_close_breaks(ls, w, h, o.bridge, NULL,
                                                    0, &nbr, &cx)) != 0)
        goto fail;
    if ((rc = td_interp_lines_beside(ls, nb, o.margin, w, h, &o.p, &dem,
                                     &cx)) != 0) {
        name_file(&cx, o.in);
        goto fail;
    }
    td_georef_scale(&geo, o.p.step);
    if ((rc = td_dem_write(o.out, dem, &geo, &cx)) != 0)
        goto fail;
    td_cli_progress_done(&pr);
    if (!o.quiet) {
        summary(dem, &o.p, td_now() - t0);
        td_cli_bridged_summary("interp", nbr, o.bridge, spacing);
    }
fail:
    td_cli_progress_done(&pr);
    td_grid_f32_free(dem);
    td_lines_free(ls);
    td_lines_free(nb);
    td_georef_clear(&geo);
    return rc == 0 ? 0 : td_cli_fail_on("interp", o.in, o.out, &cx);
}
