/* topodig: git-style subcommands.
 *
 * Every subcommand lives in its own file src/cli/<name>.c and defines
 * `int td_cmd_<name>(int argc, char **argv)` (argv[0] is the command name).
 * The table below names them all; a command whose file is not in this build
 * is a weak, null reference and is simply not offered, so subcommands can
 * be added one file at a time. */
#include "src/cli/cli.h"

#include <stdio.h>
#include <string.h>

typedef int (*td_cmd_fn)(int argc, char **argv);

#define CMD(name) int td_cmd_##name(int argc, char **argv) __attribute__((weak));
CMD(run) CMD(scan) CMD(label) CMD(interp) CMD(compare) CMD(ridges)
CMD(render) CMD(erode) CMD(flow) CMD(insolation) CMD(generate)
CMD(ridgemodel) CMD(skeleton) CMD(view) CMD(mesh) CMD(report) CMD(batch) CMD(mosaic)
#undef CMD

static const struct {
    const char *name;
    td_cmd_fn fn;
    const char *what;
} cmds[] = {
    {"run", td_cmd_run, "scanned sheet -> DEM (scan, label, interpolate)"},
    {"scan", td_cmd_scan, "scanned sheet -> traced contour lines (GeoJSON)"},
    {"label", td_cmd_label, "traced lines -> lines with heights"},
    {"interp", td_cmd_interp, "labelled lines -> DEM (GeoTIFF)"},
    {"compare", td_cmd_compare, "two DEMs -> RMSE, MAE, max |d|, bias"},
    {"ridges", td_cmd_ridges, "labelled lines -> ridge and valley lines"},
    {"render", td_cmd_render, "DEM -> shaded-relief picture"},
    {"view", td_cmd_view, "DEM -> perspective 3-D view (PNG)"},
    {"batch", td_cmd_batch, "a map series: one run per sheet of a manifest"},
    {"mosaic", td_cmd_mosaic, "sheet DEMs -> one DEM (VRT or GeoTIFF)"},
    {"report", td_cmd_report, "scanned sheet -> one-page PDF handout"},
    {"mesh", td_cmd_mesh, "DEM -> solid for 3-D printing (STL, OBJ, PLY, glb)"},
    {"erode", td_cmd_erode, "DEM -> hydraulically eroded DEM"},
    {"flow", td_cmd_flow, "DEM -> rain-flow pass counts, ridge/valley classes"},
    {"insolation", td_cmd_insolation, "DEM -> daily insolation, horizons"},
    {"generate", td_cmd_generate, "synthetic terrains"},
    {"ridgemodel", td_cmd_ridgemodel, "ridge lines -> DEM"},
    {"skeleton", td_cmd_skeleton, "key outline -> DEM (straight skeleton)"},
};

static void usage(FILE *f)
{
    size_t i;
    fputs("usage: topodig COMMAND [options]\n\n"
          "Turn scanned topographic contour sheets into elevation models.\n\n"
          "commands:\n", f);
    for (i = 0; i < sizeof cmds / sizeof *cmds; i++)
        if (cmds[i].fn)
            fprintf(f, "  %-11s %s\n", cmds[i].name, cmds[i].what);
    fputs("\nRun 'topodig COMMAND --help' for a command's options.\n"
          "  topodig --version   print the version\n", f);
}

int main(int argc, char **argv)
{
    size_t i;
    if (argc < 2) {
        usage(stderr);
        return 1;
    }
    if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") ||
        !strcmp(argv[1], "help")) {
        usage(stdout);
        return 0;
    }
    if (!strcmp(argv[1], "--version")) {
        printf("topodig %s\n", TD_VERSION);
        return 0;
    }
    for (i = 0; i < sizeof cmds / sizeof *cmds; i++)
        if (cmds[i].fn && !strcmp(argv[1], cmds[i].name))
            return cmds[i].fn(argc - 1, argv + 1);
    fprintf(stderr, "topodig: '%s' is not a command (see topodig --help)\n",
            argv[1]);
    return 1;
}
