/* fuzz_readers.c: libFuzzer target for every file reader.  The input is
 * written to a private temporary file (the readers take paths) and read
 * with td_image_info, then td_image_read when the header's size is modest,
 * so legitimate huge headers do not trip the fuzzer's allocation limit;
 * then as a DEM (td_dem_read), as GeoJSON lines (td_geojson_read_lines)
 * and as the labeller's CSV files (td_csv_read_rows);
 * lines that read, with every point within a 512 x 512 sheet (a margin
 * outside allowed), go on through the homotopy stage (td_ridges_find,
 * td_ridges_paths, td_interp_lines --method homotopy) and the faces
 * labeller (td_label_auto: a known point, and a printed label with the
 * interval left to infer).
 * Run with ASAN_OPTIONS=allocator_may_return_null=1 so a DEM header of
 * 2^31 cells is an allocation failure, not a report. */
#define _POSIX_C_SOURCE 200809L
#include "src/io/io.h"
#include "src/core/core.h"
#include "interp/homotopy.h"
#include "interp/interp.h"
#include "scanner/label.h"

#include <math.h>

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

enum { FUZZ_SHEET = 512 };

/* Every point finite and near the fuzz sheet. */
static int on_sheet(const td_lines *ls)
{
    size_t i, k;
    for (i = 0; i < ls->n; i++)
        for (k = 0; k < 2 * ls->v[i].n; k++)
            if (!(ls->v[i].xy[k] >= -64 && ls->v[i].xy[k] <= FUZZ_SHEET + 64))
                return 0;
    return 1;
}

/* Ridges, their paths and the homotopy DEM: each works or says why. */
static void fuzz_homotopy(const td_lines *ls)
{
    td_homotopy_params p = td_homotopy_defaults();
    td_interp_params ip = td_interp_defaults();
    td_ridges *r = NULL;
    td_rv_path *v = NULL;
    td_grid_f32 *dem = NULL;
    size_t n = 0;
    td_ctx cx;
    td_ctx_init(&cx);
    if (td_ridges_find(ls, FUZZ_SHEET, FUZZ_SHEET, &p, &r, &cx) != 0) {
        if (!cx.msg[0])
            abort();
    } else if (td_ridges_paths(r, &v, &n, &cx) != 0 && !cx.msg[0])
        abort();
    td_rv_paths_free(v, n);
    td_ridges_free(r);
    td_ctx_init(&cx);
    ip.method = TD_INTERP_HOMOTOPY;
    if (td_interp_lines(ls, FUZZ_SHEET, FUZZ_SHEET, &ip, &dem, &cx) != 0 &&
        !cx.msg[0])
        abort();
    td_grid_f32_free(dem);
}

/* The faces labeller on copies of the lines: a known point on the first
 * line, and a label on the last with the interval to infer. */
static void fuzz_heights(const td_lines *ls)
{
    int pass;
    for (pass = 0; pass < 2; pass++) {
        td_label_params p = td_label_defaults();
        td_label_report rep;
        td_label_point kp;
        td_ocr_read rd;
        td_lines *c = td_lines_copy(ls, NULL);
        const td_line *a = &ls->v[0], *b = &ls->v[ls->n - 1];
        td_ctx cx;
        td_ctx_init(&cx);
        if (!c || a->n == 0 || b->n == 0) {
            td_lines_free(c);
            return;
        }
        p.w = p.h = FUZZ_SHEET;
        memset(&rd, 0, sizeof rd);
        if (pass == 0) {
            kp.x = a->xy[0], kp.y = a->xy[1], kp.height = 100, kp.id = -1;
            p.interval = 10, p.known = &kp, p.nknown = 1, p.index_every = 5;
        } else {
            rd.x = b->xy[2 * (b->n / 2)], rd.y = b->xy[2 * (b->n / 2) + 1];
            rd.ux = 1, rd.digit_px = 12, rd.len = 30, rd.value = 250;
            rd.conf = 0.9, rd.line[0] = (long)ls->n - 1, rd.line[1] = -1;
            p.labels = &rd, p.nlabels = 1;
        }
        if (td_label_auto(c, &p, &rep, &cx) != 0 && !cx.msg[0])
            abort(); /* a failure always says why */
        td_label_report_free(&rep);
        td_lines_free(c);
    }
}

/* The file as the labeller's CSV files (x,y,height points; id,height rows
 * with empty heights): every row read is finite, or the read says why. */
static void fuzz_csv(void)
{
    static const int cols[2] = {3, 2};
    int k;
    for (k = 0; k < 2; k++) {
        td_ctx cx;
        double *v = NULL;
        size_t n = 0, i;
        td_ctx_init(&cx);
        if (td_csv_read_rows(fuzz_path, cols[k], k, &v, &n, &cx) != 0) {
            if (!cx.msg[0] || v || n)
                abort();
            continue;
        }
        for (i = 0; i < n * (size_t)cols[k]; i++)
            if (!isfinite(v[i]) && !(k == 1 && i % 2 == 1 && v[i] != v[i]))
                abort();
        free(v);
    }
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
    if (td_geojson_read_lines(fuzz_path, NULL, &ls, NULL, &cx) != 0) {
        if (!cx.msg[0])
            abort();
    } else if (ls->n > 0 && on_sheet(ls)) {
        fuzz_homotopy(ls);
        fuzz_heights(ls);
    }
    td_lines_free(ls);
    fuzz_csv();
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
