/* fuzz_readers.c: libFuzzer target for every file reader.  The input is
 * written to a private temporary file (the readers take paths) and read
 * with td_image_info, then td_image_read when the header's size is modest,
 * so legitimate huge headers do not trip the fuzzer's allocation limit;
 * then as a DEM (td_dem_read) and as GeoJSON lines (td_geojson_read_lines).
 * Run with ASAN_OPTIONS=allocator_may_return_null=1 so a DEM header of
 * 2^31 cells is an allocation failure, not a report. */
#define _POSIX_C_SOURCE 200809L
#include "demio.h"
#include "imageio.h"
#include "lines.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

enum { MAX_INPUT = 1 << 20, MAX_FUZZ_PIXELS = 1 << 24 };

static char fuzz_path[512];

/* One temporary file per process, removed at exit. */
static void remove_fuzz_file(void)
{
    if (fuzz_path[0])
        unlink(fuzz_path);
}

static int fuzz_file(void)
{
    const char *t = getenv("TMPDIR");
    int fd;
    if (fuzz_path[0])
        return 0;
    snprintf(fuzz_path, sizeof fuzz_path, "%s/tdfuzz.XXXXXX",
             t && *t ? t : "/tmp");
    fd = mkstemp(fuzz_path);
    if (fd < 0) {
        fuzz_path[0] = 0;
        return -1;
    }
    close(fd);
    atexit(remove_fuzz_file);
    return 0;
}

/* The same file as a DEM and as GeoJSON lines: either reads it or fails
 * with a message. */
static void fuzz_dem_and_lines(void)
{
    td_ctx cx;
    td_grid_f32 *dem = NULL;
    td_lines *ls = NULL;
    td_georef g;
    td_ctx_init(&cx);
    if (td_dem_read(fuzz_path, &dem, &g, &cx) != 0 && !cx.msg[0])
        abort(); /* a failure always says why */
    td_grid_f32_free(dem);
    td_georef_clear(&g);
    td_ctx_init(&cx);
    if (td_geojson_read_lines(fuzz_path, NULL, &ls, NULL, &cx) != 0 &&
        !cx.msg[0])
        abort();
    td_lines_free(ls);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    td_ctx cx;
    td_image *im = NULL;
    td_georef g;
    FILE *f;
    int w = 0, h = 0, ch = 0;
    if (size > MAX_INPUT || fuzz_file() != 0)
        return 0;
    f = fopen(fuzz_path, "wb");
    if (!f)
        return 0;
    if (size)
        fwrite(data, 1, size, f);
    fclose(f);
    td_ctx_init(&cx);
    if (td_image_info(fuzz_path, &w, &h, &ch, &g, &cx) == 0 &&
        (size_t)w * (size_t)h <= MAX_FUZZ_PIXELS) {
        td_georef_clear(&g);
        td_ctx_clear(&cx);
        if (td_image_read(fuzz_path, &im, &g, &cx) == 0 &&
            (im->w != w || im->h != h || im->channels != ch))
            abort(); /* info and read must agree */
        td_image_free(im);
    }
    td_georef_clear(&g);
    fuzz_dem_and_lines();
    return 0;
}
