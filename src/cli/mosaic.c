/* topodig mosaic: the sheet DEMs of a series as one (src/io/mosaic.c). */
#include "src/cli/cli.h"

#include "src/io/io.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int td_cmd_mosaic(int argc, char **argv)
{
    const char *in[4096], *out = NULL;
    const td_opt opts[] = {{NULL}};
    int quiet = 0, rc;
    td_ctx cx;
    const td_cmd c = {
        "mosaic", "DEM.tif... -o SERIES.vrt|SERIES.tif",
        "The DEMs of a map series (each sheet's dem.tif from topodig batch,\n"
        "georeferenced) as one: a GDAL VRT over them where they lie, or one\n"
        "tiled, compressed GeoTIFF.  Where sheets overlap the later one on\n"
        "the command line is drawn over the earlier.\n",
        NULL, opts, "DEM files", 1, 4096, in, &out, "SERIES.vrt", &quiet};
    size_t n;
    memset(in, 0, sizeof in);
    if ((rc = td_opt_parse(&c, argc, argv)) != 0)
        return rc == 2 ? 0 : 1;
    for (n = 0; n < 4096 && in[n]; n++)
        ;
    td_ctx_init(&cx);
    if ((rc = td_dem_mosaic(in, n, out, &cx)) != 0)
        return td_cli_fail_on("mosaic", in[0], out, &cx);
    if (!quiet)
        fprintf(stderr, "mosaic: %zu DEMs -> %s\n", n, out);
    return 0;
}
