/* topodig: git-style subcommands. */
#include "cli.h"

#include <stdio.h>
#include <string.h>

static const char usage[] =
    "usage: topodig COMMAND [options]\n"
    "\n"
    "Turn scanned topographic contour sheets into elevation models.\n"
    "\n"
    "commands:\n"
    "  scan     scanned sheet -> traced contour lines (GeoJSON)\n"
    "\n"
    "Run 'topodig COMMAND --help' for a command's options.\n"
    "  topodig --version   print the version\n";

int main(int argc, char **argv)
{
    if (argc < 2) {
        fputs(usage, stderr);
        return 1;
    }
    if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") ||
        !strcmp(argv[1], "help")) {
        fputs(usage, stdout);
        return 0;
    }
    if (!strcmp(argv[1], "--version")) {
        printf("topodig %s\n", TD_VERSION);
        return 0;
    }
    if (!strcmp(argv[1], "scan"))
        return td_cmd_scan(argc - 1, argv + 1);
    fprintf(stderr, "topodig: '%s' is not a command (see topodig --help)\n",
            argv[1]);
    return 1;
}
