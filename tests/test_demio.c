/* test_demio.c: DEM reading and writing.  TIFFs of every sample type are
 * written here with libtiff from a known surface (striped and tiled, big
 * and little endian, several codecs, with and without GDAL_NODATA) and
 * must read back exactly; ESRI ASCII grids round-trip; bad files fail with
 * one message naming the file. */
#define _POSIX_C_SOURCE 200809L
#include "tests/tt.h"

#include "src/io/io.h"

#include <float.h>
#include <math.h>
#include <omp.h>
#include <png.h>
#include <stdlib.h>
#include <string.h>
#include <tiffio.h>

enum { W = 37, H = 29 };

typedef struct stype {
    const char *name;
    int bps, fmt;
    const char *nodata; /* GDAL_NODATA text for this type's tests */
} stype;

static const stype TYPES[] = {
    {"int8", 8, SAMPLEFORMAT_INT, "-128"},
    {"uint8", 8, SAMPLEFORMAT_UINT, "255"},
    {"int16", 16, SAMPLEFORMAT_INT, "-32768"},
    {"uint16", 16, SAMPLEFORMAT_UINT, "65535"},
    {"int32", 32, SAMPLEFORMAT_INT, "-2147483648"},
    {"uint32", 32, SAMPLEFORMAT_UINT, "4294967295"},
    {"float32", 32, SAMPLEFORMAT_IEEEFP, "-3.4028234663852886e+38"},
    {"float64", 64, SAMPLEFORMAT_IEEEFP, "nan"},
};

static char *tmp(const char *name)
{
    static char p[8][600];
    static int k;
    char *s = p[k++ & 7];
    snprintf(s, 600, "%s/%s", tt_tmpdir(), name);
    return s;
}

/* The truth at (x, y) for a sample type, exactly representable in it. */
static double truth(const stype *t, int x, int y)
{
    int b = (x * 7 + y * 13) % 101; /* 0..100 */
    if (t->fmt == SAMPLEFORMAT_IEEEFP)
        return t->bps == 32 ? (double)(float)(100.0 * sin(0.21 * x) + 0.37 * y)
                            : 100.0 * sin(0.21 * x) + 0.37 * y;
    switch (t->bps * 2 + (t->fmt == SAMPLEFORMAT_INT)) {
    case 17: return b - 50;
    case 16: return b * 2;
    case 33: return b * 300 - 15000;
    case 32: return b * 600;
    case 65: return b * 1000000.0 - 50000000.0;
    default: return b * 40000000.0;
    }
}

static int is_nd_cell(int x, int y)
{
    return (x + 2 * y) % 17 == 0;
}

/* One sample of type t with value v at row[i]. */
static void put_sample(const stype *t, uint8_t *row, int i, double v)
{
#define P(T) do { T s = (T)v; memcpy(row + (size_t)i * sizeof s, &s, sizeof s); } while (0)
    if (t->fmt == SAMPLEFORMAT_IEEEFP) {
        if (t->bps == 32) P(float); else P(double);
    } else if (t->fmt == SAMPLEFORMAT_INT) {
        if (t->bps == 8) P(int8_t); else if (t->bps == 16) P(int16_t); else P(int32_t);
    } else {
        if (t->bps == 8) P(uint8_t); else if (t->bps == 16) P(uint16_t); else P(uint32_t);
    }
#undef P
}

static TIFFFieldInfo nd_field[] = {
    {42113, -1, -1, TIFF_ASCII, FIELD_CUSTOM, 1, 0, "GDALNoDataValue"}};

/* Write a W x H single-band TIFF of type t; nodata cells get the nodata
 * value when with_nd. */
static int write_tiff(const char *path, const stype *t, int tiled, int comp,
                      int big_endian, int with_nd)
{
    TIFF *tif = TIFFOpen(path, big_endian ? "wb" : "wl");
    int bw = tiled ? 16 : W, bh = tiled ? 16 : 5, x, y, x0, y0, ok = 1;
    size_t es = (size_t)t->bps / 8;
    uint8_t *buf = calloc((size_t)bw * bh, es);
    double nd = with_nd ? strtod(t->nodata, NULL) : 0;
    if (!tif || !buf)
        return -1;
    TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, W);
    TIFFSetField(tif, TIFFTAG_IMAGELENGTH, H);
    TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, 1);
    TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, t->bps);
    TIFFSetField(tif, TIFFTAG_SAMPLEFORMAT, t->fmt);
    TIFFSetField(tif, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
    TIFFSetField(tif, TIFFTAG_COMPRESSION, comp);
    if (tiled) {
        TIFFSetField(tif, TIFFTAG_TILEWIDTH, bw);
        TIFFSetField(tif, TIFFTAG_TILELENGTH, bh);
    } else {
        TIFFSetField(tif, TIFFTAG_ROWSPERSTRIP, bh);
    }
    if (with_nd) {
        TIFFMergeFieldInfo(tif, nd_field, 1);
        TIFFSetField(tif, 42113, t->nodata);
    }
    for (y0 = 0; y0 < H; y0 += bh)
        for (x0 = 0; x0 < W; x0 += bw) {
            int rows = tiled ? bh : (H - y0 < bh ? H - y0 : bh);
            for (y = 0; y < rows; y++)
                for (x = 0; x < bw; x++) {
                    int gx = x0 + x, gy = y0 + y;
                    double v = gx < W && gy < H ? truth(t, gx, gy) : 0;
                    if (with_nd && gx < W && gy < H && is_nd_cell(gx, gy))
                        v = nd;
                    put_sample(t, buf, y * bw + x, v);
                }
            if (tiled)
                ok &= TIFFWriteEncodedTile(tif, TIFFComputeTile(tif, x0, y0, 0, 0),
                                           buf, (tmsize_t)(bw * bh * es)) >= 0;
            else
                ok &= TIFFWriteEncodedStrip(tif, TIFFComputeStrip(tif, y0, 0),
                                            buf, (tmsize_t)(bw * rows * es)) >= 0;
        }
    TIFFClose(tif);
    free(buf);
    return ok ? 0 : -1;
}

/* Read path back and compare with the truth of type t. */
static void check_dem(const char *path, const stype *t, int with_nd)
{
    td_ctx cx;
    td_grid_f32 *g = NULL;
    int x, y, bad = 0;
    td_ctx_init(&cx);
    TT_CHECKF(td_dem_read(path, &g, NULL, &cx) == 0, "%s", td_errmsg(&cx));
    if (!g)
        return;
    TT_CHECK(g->w == W && g->h == H);
    TT_CHECKF(!!g->has_nodata == with_nd, "%s has_nodata %d", t->name,
              g->has_nodata);
    for (y = 0; y < H; y++)
        for (x = 0; x < W; x++) {
            float v = TD_AT(g, x, y);
            if (with_nd && is_nd_cell(x, y))
                bad += v != g->nodata;
            else
                bad += v != (float)truth(t, x, y);
        }
    TT_CHECKF(bad == 0, "%s: %d cells differ (%s)", t->name, bad, path);
    if (with_nd && strcmp(t->nodata, "nan") != 0 && t->bps < 64)
        TT_CHECKF(g->nodata == (float)strtod(t->nodata, NULL), "%s nodata %g",
                  t->name, g->nodata);
    if (with_nd && strcmp(t->nodata, "nan") == 0)
        TT_CHECK(g->nodata == -9999.0f);
    td_grid_f32_free(g);
}

static void test_tiff_sample_types(void)
{
    size_t i;
    for (i = 0; i < sizeof TYPES / sizeof TYPES[0]; i++) {
        const stype *t = &TYPES[i];
        char name[64];
        snprintf(name, sizeof name, "%s_strip_le_nd.tif", t->name);
        TT_CHECK(write_tiff(tmp(name), t, 0, COMPRESSION_NONE, 0, 1) == 0);
        check_dem(tmp(name), t, 1);
        snprintf(name, sizeof name, "%s_tile_be_deflate.tif", t->name);
        TT_CHECK(write_tiff(tmp(name), t, 1, COMPRESSION_ADOBE_DEFLATE, 1, 0) == 0);
        check_dem(tmp(name), t, 0);
        snprintf(name, sizeof name, "%s_strip_be_lzw_nd.tif", t->name);
        TT_CHECK(write_tiff(tmp(name), t, 0, COMPRESSION_LZW, 1, 1) == 0);
        check_dem(tmp(name), t, 1);
        snprintf(name, sizeof name, "%s_tile_le_deflate_nd.tif", t->name);
        TT_CHECK(write_tiff(tmp(name), t, 1, COMPRESSION_ADOBE_DEFLATE, 0, 1) == 0);
        check_dem(tmp(name), t, 1);
    }
}

/* A float grid with a smooth surface and a few nodata cells. */
static td_grid_f32 *surface(int w, int h, int with_nd)
{
    td_grid_f32 *g = td_grid_f32_new(w, h, NULL);
    int x, y;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++)
            TD_AT(g, x, y) = (float)(250.0 + 80.0 * sin(0.13 * x) * cos(0.07 * y) +
                                     0.001 * x * y - 3.3e-5 * x);
    if (with_nd) {
        g->has_nodata = 1;
        g->nodata = -9999.0f;
        for (y = 0; y < h; y++)
            for (x = 0; x < w; x++)
                if (is_nd_cell(x, y))
                    TD_AT(g, x, y) = g->nodata;
    }
    return g;
}

static void test_geotiff_georef(void)
{
    td_ctx cx;
    td_grid_f32 *g = surface(50, 40, 1), *r = NULL;
    td_georef gr, back;
    const char *p = tmp("geo.tif");
    int i;
    td_ctx_init(&cx);
    td_georef_init(&gr);
    gr.valid = 1;
    gr.epsg = 32633;
    gr.gt[0] = 500000; gr.gt[1] = 2; gr.gt[2] = 0;
    gr.gt[3] = 4200000; gr.gt[4] = 0; gr.gt[5] = -2;
    TT_CHECKF(td_geotiff_write_f32(p, g, &gr, &cx) == 0, "%s", td_errmsg(&cx));
    TT_CHECKF(td_dem_read(p, &r, &back, &cx) == 0, "%s", td_errmsg(&cx));
    TT_CHECK(back.valid && back.epsg == 32633);
    for (i = 0; i < 6; i++)
        TT_NEAR(back.gt[i], gr.gt[i], 1e-9);
    TT_CHECK(r && r->has_nodata && r->nodata == -9999.0f);
    TT_CHECK(r && memcmp(r->data, g->data, sizeof(float) * 50 * 40) == 0);
    td_georef_clear(&back);
    td_grid_f32_free(r);
    td_grid_f32_free(g);
}

static void test_asc_round_trip(void)
{
    td_ctx cx;
    td_grid_f32 *g = surface(53, 41, 1), *r = NULL;
    td_georef gr, back;
    const char *p = tmp("rt.asc");
    char head[400] = "";
    FILE *f;
    size_t i, bad = 0;
    td_ctx_init(&cx);
    td_georef_init(&gr);
    gr.valid = 1;
    gr.gt[0] = 500000.5; gr.gt[1] = 2.5; gr.gt[3] = 4200000; gr.gt[5] = -2.5;
    TT_CHECKF(td_dem_write(p, g, &gr, &cx) == 0, "%s", td_errmsg(&cx));
    f = fopen(p, "r");
    if (f) {
        TT_CHECK(fread(head, 1, sizeof head - 1, f) > 0);
        fclose(f);
    }
    TT_CHECKF(strstr(head, "NODATA_value -9999\n") != NULL, "%s", head);
    TT_CHECKF(strstr(head, "yllcorner 4199897.5\n") != NULL, "%s", head);
    TT_CHECKF(td_dem_read(p, &r, &back, &cx) == 0, "%s", td_errmsg(&cx));
    if (!r)
        return;
    TT_CHECK(r->w == 53 && r->h == 41 && r->has_nodata && r->nodata == -9999.0f);
    for (i = 0; i < 53 * 41; i++)
        bad += fabs(r->data[i] - g->data[i]) > 1e-6 * fabs(g->data[i]);
    TT_CHECKF(bad == 0, "%zu values differ", bad);
    TT_CHECK(back.valid);
    for (i = 0; i < 6; i++)
        TT_NEAR(back.gt[i], gr.gt[i], 1e-9);
    td_georef_clear(&back);
    td_grid_f32_free(r);
    td_grid_f32_free(g);
}

static int write_text(const char *path, const char *s)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return -1;
    fputs(s, f);
    return fclose(f);
}

static void test_asc_center_and_case(void)
{
    td_ctx cx;
    td_grid_f32 *r = NULL;
    td_georef back;
    const char *p = tmp("center.asc");
    td_ctx_init(&cx);
    write_text(p, "NCOLS 3\r\nNROWS 2\r\nXLLCENTER 10\r\nYLLCENTER 20\r\n"
                  "CellSize 2\r\nNODATA_VALUE -1\r\n1 2.5 3e1\r\n4 -1 -6.25\r\n");
    TT_CHECKF(td_dem_read(p, &r, &back, &cx) == 0, "%s", td_errmsg(&cx));
    if (!r)
        return;
    TT_CHECK(r->w == 3 && r->h == 2 && r->has_nodata && r->nodata == -1.0f);
    TT_CHECK(r->data[0] == 1 && r->data[1] == 2.5f && r->data[2] == 30 &&
             r->data[3] == 4 && r->data[4] == r->nodata && r->data[5] == -6.25f);
    TT_NEAR(back.gt[0], 9, 1e-12);
    TT_NEAR(back.gt[3], 23, 1e-12);
    TT_NEAR(back.gt[1], 2, 1e-12);
    TT_NEAR(back.gt[5], -2, 1e-12);
    td_grid_f32_free(r);
}

/* Read must fail with code and a message containing each of the words. */
static void expect_fail(const char *path, int code, const char *w1,
                        const char *w2)
{
    td_ctx cx;
    td_grid_f32 *r = NULL;
    int rc;
    td_ctx_init(&cx);
    rc = td_dem_read(path, &r, NULL, &cx);
    TT_CHECKF(rc == code, "%s: rc %d (%s)", path, rc, td_errmsg(&cx));
    TT_CHECK(r == NULL);
    TT_CHECKF(strstr(td_errmsg(&cx), path) != NULL, "%s", td_errmsg(&cx));
    TT_CHECKF(!w1 || strstr(td_errmsg(&cx), w1), "%s", td_errmsg(&cx));
    TT_CHECKF(!w2 || strstr(td_errmsg(&cx), w2), "%s", td_errmsg(&cx));
}

static void test_asc_bad(void)
{
    const char *hd = "ncols 4\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize 1\n";
    char s[400];
    snprintf(s, sizeof s, "%s1 2 3 4\n5 6 7 8\n9 10\n", hd);
    write_text(tmp("trunc.asc"), s);
    expect_fail(tmp("trunc.asc"), TD_EFORMAT, "line 8", "truncated");
    snprintf(s, sizeof s, "%s1 2 3 4\n5 6 x7 8\n9 10 11 12\n", hd);
    write_text(tmp("garbage.asc"), s);
    expect_fail(tmp("garbage.asc"), TD_EFORMAT, "line 7", "'x7'");
    write_text(tmp("huge.asc"), "ncols 100000\nnrows 100000\nxllcorner 0\n"
                                "yllcorner 0\ncellsize 1\n1 2 3\n");
    expect_fail(tmp("huge.asc"), TD_ETOOBIG, NULL, NULL);
    write_text(tmp("nohead.asc"), "ncols 4\nnrows 3\n1 2 3\n");
    expect_fail(tmp("nohead.asc"), TD_EFORMAT, "header", NULL);
    write_text(tmp("key.asc"), "ncols 4\nbogus 3\n1 2 3\n");
    expect_fail(tmp("key.asc"), TD_EFORMAT, "line 2", "bogus");
    write_text(tmp("text.tif"), "hello world\n");
    expect_fail(tmp("text.tif"), TD_EFORMAT, "not a DEM", NULL);
    expect_fail(tmp("missing.asc"), TD_EIO, NULL, NULL);
}

static void test_tiff_rgb_rejected(void)
{
    const char *p = tmp("rgb.tif");
    TIFF *tif = TIFFOpen(p, "w");
    uint8_t row[3 * 8] = {0};
    int y;
    TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, 8);
    TIFFSetField(tif, TIFFTAG_IMAGELENGTH, 4);
    TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, 3);
    TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, 8);
    TIFFSetField(tif, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_RGB);
    TIFFSetField(tif, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
    for (y = 0; y < 4; y++)
        TIFFWriteScanline(tif, row, (uint32_t)y, 0);
    TIFFClose(tif);
    expect_fail(p, TD_EFORMAT, "3 bands; a DEM has one", NULL);
    write_text(tmp("cut.tif"), "II*\0");
    expect_fail(tmp("cut.tif"), TD_EFORMAT, NULL, NULL);
}

/* Read a 16-bit grey PNG with libpng: 0 and the values (and its tEXt
 * Comment into note, "" when none), or -1. */
static int read_png16(const char *path, uint16_t *v, int w, int h,
                      char *note, size_t notesize)
{
    FILE *f = fopen(path, "rb");
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL,
                                             NULL, NULL);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    int ok = 0, x, y;
    if (f && info && !setjmp(png_jmpbuf(png))) {
        png_bytepp rows;
        png_textp text;
        int nt = 0, k;
        png_init_io(png, f);
        png_read_png(png, info, PNG_TRANSFORM_IDENTITY, NULL);
        note[0] = 0;
        png_get_text(png, info, &text, &nt);
        for (k = 0; k < nt; k++)
            if (!strcmp(text[k].key, "Comment"))
                snprintf(note, notesize, "%s", text[k].text);
        rows = png_get_rows(png, info);
        ok = png_get_bit_depth(png, info) == 16 &&
             png_get_color_type(png, info) == PNG_COLOR_TYPE_GRAY &&
             (int)png_get_image_width(png, info) == w &&
             (int)png_get_image_height(png, info) == h;
        for (y = 0; ok && y < h; y++)
            for (x = 0; x < w; x++)
                v[y * w + x] = (uint16_t)(rows[y][2 * x] << 8 | rows[y][2 * x + 1]);
    }
    png_destroy_read_struct(&png, &info, NULL);
    if (f)
        fclose(f);
    return ok ? 0 : -1;
}

static void test_png_write(void)
{
    td_ctx cx;
    td_grid_f32 *g = surface(40, 30, 1);
    uint16_t v[40 * 30];
    size_t i, j, nonmono = 0, nd_bad = 0;
    float lo = FLT_MAX, hi = -FLT_MAX;
    uint16_t vlo = 65535, vhi = 0;
    char note[256];
    double z0 = NAN, step = NAN, worst = 0;
    int base = -1;
    td_ctx_init(&cx);
    TT_CHECKF(td_dem_write(tmp("dem.png"), g, NULL, &cx) == 0, "%s",
              td_errmsg(&cx));
    TT_CHECK(read_png16(tmp("dem.png"), v, 40, 30, note, sizeof note) == 0);
    /* the Comment gives the heights back to within half a step */
    TT_CHECKF(sscanf(note, "topodig DEM: height = %lf + (value - %d) * %lf",
                     &z0, &base, &step) == 3 && base == 1 &&
                  strstr(note, "value 0 = nodata"), "comment '%s'", note);
    for (i = 0; i < 40 * 30; i++)
        if (g->data[i] != g->nodata && v[i] > 0)
            worst = fmax(worst, fabs(z0 + (v[i] - base) * step - g->data[i]));
    TT_CHECKF(worst <= 0.5001 * step, "worst %g, step %g", worst, step);
    for (i = 0; i < 40 * 30; i++) {
        float a = g->data[i];
        if (a == g->nodata) {
            nd_bad += v[i] != 0;
            continue;
        }
        if (a < lo) lo = a, vlo = v[i];
        if (a > hi) hi = a, vhi = v[i];
        for (j = 0; j < 40 * 30; j += 7)
            if (g->data[j] != g->nodata && g->data[j] < a && v[j] > v[i])
                nonmono++;
    }
    TT_CHECK(nd_bad == 0 && nonmono == 0);
    TT_CHECKF(vlo == 1 && vhi == 65535, "%u %u", vlo, vhi);
    td_grid_f32_free(g);
}

static void test_gdalinfo_asc(void)
{
    td_ctx cx;
    td_grid_f32 *g = surface(64, 48, 0);
    char cmd[1400], line[512];
    const char *p = tmp("gdal.asc"), *out = tmp("gdal.txt");
    double mn = NAN, mx = NAN, tmn = 1e30, tmx = -1e30;
    FILE *f;
    size_t i;
    if (system("gdalinfo --version > /dev/null 2>&1") != 0) {
        fprintf(stderr, "  (gdalinfo not installed: skipped)\n");
        td_grid_f32_free(g);
        return;
    }
    td_ctx_init(&cx);
    TT_CHECK(td_asc_write(p, g, NULL, &cx) == 0);
    snprintf(cmd, sizeof cmd, "gdalinfo -stats '%s' > '%s' 2>&1", p, out);
    TT_CHECK(system(cmd) == 0);
    f = fopen(out, "r");
    while (f && fgets(line, sizeof line, f)) {
        const char *s;
        if ((s = strstr(line, "STATISTICS_MINIMUM=")))
            mn = atof(s + 19);
        if ((s = strstr(line, "STATISTICS_MAXIMUM=")))
            mx = atof(s + 19);
    }
    if (f)
        fclose(f);
    for (i = 0; i < 64 * 48; i++) {
        tmn = g->data[i] < tmn ? g->data[i] : tmn;
        tmx = g->data[i] > tmx ? g->data[i] : tmx;
    }
    TT_NEAR(mn, tmn, 1e-3);
    TT_NEAR(mx, tmx, 1e-3);
    td_grid_f32_free(g);
}

/* Bytes of a file (*n), or NULL. */
static unsigned char *slurp_file(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    unsigned char *b = NULL;
    long k;
    if (!f)
        return NULL;
    if (fseek(f, 0, SEEK_END) == 0 && (k = ftell(f)) > 0 &&
        fseek(f, 0, SEEK_SET) == 0 && (b = malloc((size_t)k)) != NULL)
        *n = fread(b, 1, (size_t)k, f);
    fclose(f);
    return b;
}

/* Grids over 1024 px are written in 256 x 256 tiles that we predict and
 * compress on threads (src/io/tiffio.c): decoded by libtiff itself (its
 * own predictor and inflate) they are the grid, cell for cell (negative,
 * tiny, huge, NaN, the nodata value, edge tiles padded), and the file is
 * the same bytes on 1 thread and on 2. */
static void test_tiled_write_threads(void)
{
    int w = 1300, h = 1037, x, y, t, bad = 0;
    td_grid_f32 *g = td_grid_f32_new(w, h, NULL);
    td_grid_u8 *m = td_grid_u8_new(1100, 1029, NULL);
    td_ctx cx;
    unsigned char *a = NULL, *b = NULL;
    size_t na = 0, nb = 0;
    char *p1 = tmp("tiled1.tif"), *p2 = tmp("tiled2.tif"), *pm = tmp("tiledm.tif");
    TIFF *tif;
    td_ctx_init(&cx);
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++)
            TD_AT(g, x, y) = (float)((x - 600) * 0.37 + sin(y * 0.05) * 1e3 +
                                     ((x * 31 + y * 17) % 97) * 1e-3);
    TD_AT(g, 3, 5) = NAN, TD_AT(g, 1299, 1036) = -9999.0f;
    TD_AT(g, 700, 700) = 3e38f, TD_AT(g, 701, 700) = 1e-38f;
    g->has_nodata = 1, g->nodata = -9999.0f;
    for (y = 0; y < m->h; y++)
        for (x = 0; x < m->w; x++)
            m->data[(size_t)y * m->stride + x] = (uint8_t)(x * 7 + y * 3);
    for (t = 1; t <= 2; t++) {
        omp_set_num_threads(t);
        TT_CHECKF(td_dem_write(t == 1 ? p1 : p2, g, NULL, &cx) == 0, "%s",
                  td_errmsg(&cx));
    }
    omp_set_num_threads(omp_get_num_procs());
    TT_CHECK(td_geotiff_write_u8(pm, m, NULL, &cx) == 0);
    a = slurp_file(p1, &na), b = slurp_file(p2, &nb);
    TT_CHECKF(a && b && na == nb && memcmp(a, b, na) == 0,
              "1 and 2 threads: %zu and %zu bytes", na, nb);
    if ((tif = TIFFOpen(p1, "r")) != NULL) {
        uint32_t tw = 0;
        TIFFGetField(tif, TIFFTAG_TILEWIDTH, &tw);
        TT_CHECK(TIFFIsTiled(tif) && tw == 256);
        {   /* libtiff's decoder, tile by tile */
            float *tb = malloc((size_t)TIFFTileSize(tif));
            uint32_t tx, ty;
            for (ty = 0; tb && ty < (uint32_t)h; ty += 256)
                for (tx = 0; tx < (uint32_t)w; tx += 256) {
                    TIFFReadTile(tif, tb, tx, ty, 0, 0);
                    for (y = 0; y < 256; y++)
                        for (x = 0; x < 256; x++) {
                            float v = tb[y * 256 + x], e;
                            int gx = (int)tx + x, gy = (int)ty + y;
                            e = gx < w && gy < h ? TD_AT(g, gx, gy) : -9999.0f;
                            bad += !(v == e || (isnan(v) && isnan(e)));
                        }
                }
            free(tb);
        }
        TIFFClose(tif);
    } else {
        TT_CHECK(!"libtiff opens the file");
    }
    TT_CHECKF(bad == 0, "%d cells differ", bad);
    if ((tif = TIFFOpen(pm, "r")) != NULL) {
        uint8_t *tb = malloc((size_t)TIFFTileSize(tif));
        int badm = 0;
        TIFFReadTile(tif, tb, 768, 1024, 0, 0); /* an edge tile */
        for (y = 0; tb && y < 5; y++)
            for (x = 0; x < 256; x++)
                badm += tb[y * 256 + x] !=
                        (768 + x < 1100 ? (uint8_t)((768 + x) * 7 + (1024 + y) * 3) : 0);
        TT_CHECKF(badm == 0, "bytes grid: %d cells differ", badm);
        free(tb);
        TIFFClose(tif);
    }
    free(a), free(b);
    td_grid_f32_free(g);
    td_grid_u8_free(m);
}

int main(void)
{
    TT_RUN(test_tiff_sample_types);
    TT_RUN(test_geotiff_georef);
    TT_RUN(test_tiled_write_threads);
    TT_RUN(test_asc_round_trip);
    TT_RUN(test_asc_center_and_case);
    TT_RUN(test_asc_bad);
    TT_RUN(test_tiff_rgb_rejected);
    TT_RUN(test_png_write);
    TT_RUN(test_gdalinfo_asc);
    return tt_summary();
}
