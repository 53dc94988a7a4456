/* topodig mesh: DEM -> a closed solid for 3-D printing (STL) or viewers
 * (OBJ, PLY, glTF binary) (src/mesh). */
#include "src/cli/cli.h"

#include "src/io/io.h"
#include "src/mesh/mesh.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

typedef struct ms_opts {
    const char *in, *out, *texture;
    int quiet;
    td_mesh_params p;
} ms_opts;

static int parse_args(int argc, char **argv, ms_opts *o)
{
    const td_opt opts[] = {
        {"step", 0, TD_OPT_INT, &o->p.step, 1, 100000, .meta = "N",
         .help = "a vertex every N cells (fewer triangles)"},
        {"base", 0, TD_OPT_DOUBLE, &o->p.base, 0, 1e9, .meta = "T",
         .help = "thickness under the lowest point, in the\noutput's units "
         "(mm with --print-size)\n(default: a tenth of the relief)",
         .no_default = 1},
        {"exaggeration", 0, TD_OPT_DOUBLE, &o->p.exaggeration, 1e-6, 1e6,
         .meta = "Z", .help = "vertical exaggeration"},
        {"print-size", 0, TD_OPT_DOUBLE, &o->p.print_size, 1e-3, 1e7,
         .meta = "MM", .help = "scale so the longest side is MM millimetres\n"
         "(default: map units)", .no_default = 1},
        {"cellsize", 0, TD_OPT_DOUBLE, &o->p.cellsize, 1e-12, 1e12,
         .meta = "C", .help = "cell size in height units (default: from the\n"
         "DEM's georeferencing, else 1)", .no_default = 1},
        {"texture", 0, TD_OPT_STRING, &o->texture, .meta = "IMAGE",
         .help = "an image over the DEM (the scan, a map) as\nthe OBJ's "
         "texture (.obj only)"},
        {NULL}};
    const td_cmd c = {
        "mesh", "DEM.tif -o MODEL.stl|MODEL.obj|MODEL.ply|MODEL.glb\n"
        "                      [--step N] [--base T] [--print-size MM]",
        "A DEM as a closed, watertight solid: the surface on top, walls\n"
        "down every edge of the data (around holes without data too) and a\n"
        "flat base, for slicers of 3-D printers (binary STL) or viewers\n"
        "(OBJ with a texture, PLY, glTF binary).\n",
        "Summary on stderr: vertices, triangles (top, walls, base), the\n"
        "size and the volume in the output's units.\n",
        opts, "one DEM file", 1, 1, &o->in, &o->out, "MODEL.stl", &o->quiet};
    return td_opt_parse(&c, argc, argv);
}

int td_cmd_mesh(int argc, char **argv)
{
    ms_opts o;
    td_ctx cx;
    td_grid_f32 *dem = NULL;
    td_image *tex = NULL;
    td_mesh *m = NULL;
    td_mesh_info info;
    td_georef geo;
    double vol = 0, lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL},
           hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    int stream;
    double t0 = td_now();
    int rc;
    memset(&o, 0, sizeof o);
    o.p = td_mesh_defaults();
    o.p.cellsize = 0; /* unless given: from the georeferencing, else 1 */
    if ((rc = parse_args(argc, argv, &o)) != 0)
        return rc == 2 ? 0 : 1;
    td_ctx_init(&cx);
    td_georef_init(&geo);
    if ((rc = td_cli_read_dem(o.in, &dem, &geo, &o.p.cellsize, &cx)) != 0)
        goto fail;
    if (o.texture) {
        td_georef tg;
        td_georef_init(&tg);
        rc = td_image_read(o.texture, &tex, &tg, &cx);
        td_georef_clear(&tg);
        if (rc != 0)
            goto fail;
    }
    {
        const char *ext = strrchr(o.out, '.');
        stream = ext && !strcasecmp(ext, ".stl") && !tex;
    }
    if (stream) { /* straight from the grid: no triangle arrays */
        if ((rc = td_mesh_stream_stl(o.out, dem, &o.p, &info, &vol, &cx)) !=
            0)
            goto fail;
        memcpy(lo, info.lo, sizeof lo);
        memcpy(hi, info.hi, sizeof hi);
    } else {
        size_t i;
        int k;
        if ((rc = td_mesh_build(dem, &o.p, &m, &cx)) != 0 ||
            (rc = td_mesh_write(o.out, m, tex, &cx)) != 0)
            goto fail;
        for (i = 0; i < m->nv; i++)
            for (k = 0; k < 3; k++)
                lo[k] = fmin(lo[k], m->v[3 * i + k]),
                hi[k] = fmax(hi[k], m->v[3 * i + k]);
        info.nv = m->nv, info.nt = m->nt, info.ntop = m->ntop;
        info.nwall = m->nwall, info.nbase = m->nbase;
        info.dropped = m->dropped;
        vol = td_mesh_volume(m);
    }
    if (!o.quiet) {
        fprintf(stderr, "mesh: %zu vertices, %zu triangles (%zu top, %zu "
                "walls, %zu base), %.6g x %.6g x %.6g %s, volume %.6g",
                info.nv, info.nt, info.ntop, info.nwall, info.nbase,
                hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2],
                o.p.print_size > 0 ? "mm" : "units", vol);
        if (info.dropped)
            fprintf(stderr, ", %zu quads left out where data met at a "
                    "corner only", info.dropped);
        fprintf(stderr, "; %.2f s\n", td_now() - t0);
        if (hi[2] - lo[2] > fmax(hi[0] - lo[0], hi[1] - lo[1]))
            fprintf(stderr, "mesh: warning: the model is taller than it is "
                    "wide (cell size %g height units%s); give --cellsize "
                    "or a smaller --exaggeration\n", o.p.cellsize,
                    o.p.cellsize == 1 ? ": a DEM without georeferencing?"
                                      : "");
    }
fail:
    td_mesh_free(m);
    td_image_free(tex);
    td_grid_f32_free(dem);
    td_georef_clear(&geo);
    return rc == 0 ? 0 : td_cli_fail_on("mesh", o.in, o.out, &cx);
}
