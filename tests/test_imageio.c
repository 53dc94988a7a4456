/* test_imageio.c: scan readers and raster writers on generated files with a
 * known truth.  TIFFs are written with libtiff directly in every layout the
 * reader claims; PNGs with libpng directly; the readers must return exactly
 * the expected 8-bit pixels.  Covers src/imageio.c, tiffio.c, pngio.c,
 * georef.c and outfile.c (failed writes leave the old file, no temp). */
#define _POSIX_C_SOURCE 200809L
#include "tests/tt.h"

#include "src/io/io.h"

#include <dirent.h>
#include <geotiff.h>
#include <geovalues.h>
#include <png.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif
#include <sys/stat.h>
#include <tiffio.h>
#include <xtiffio.h>
#include <zlib.h>

/* ---- truth ------------------------------------------------------------ */

enum { K_GREY, K_RGB, K_PAL };

/* A TIFF layout to generate. */
typedef struct tspec {
    int w, h, kind, bps, spp, photo, planar, comp, tiled, rps;
    int alpha;      /* 0, EXTRASAMPLE_UNASSALPHA or EXTRASAMPLE_ASSOCALPHA */
    int grey_pal;   /* palette whose entries are all grey */
    const char *mode;
    int pred;       /* TIFFTAG_PREDICTOR when set */
} tspec;

static int pat(int x, int y) { return (x * 7 + y * 13 + ((x * y) % 5) * 3) & 255; }
static int bit(int x, int y) { return (x / 3 + y / 2) % 3 == 0; }
static int alpha8(int x, int y) { return ((x + y) % 4) * 85; }
static int pal_index(const tspec *t, int x, int y)
{
    return t->bps == 4 ? (x + y) % 16 : (x + 2 * y) % 20;
}
static int pal_entry(const tspec *t, int i, int c) /* 16-bit colour map */
{
    if (t->grey_pal)
        return i * 12 * 257;
    return c == 0 ? i * 3000 : c == 1 ? 65535 - i * 3000 : ((i * 7) % 256) * 257;
}

/* The stored value of sample s at (x,y). */
static unsigned raw(const tspec *t, int x, int y, int s)
{
    int v;
    if (t->kind == K_PAL)
        return (unsigned)pal_index(t, x, y);
    if (t->alpha && s == t->spp - 1)
        v = alpha8(x, y);
    else if (t->kind == K_GREY && t->bps == 1)
        return (unsigned)bit(x, y);
    else if (t->kind == K_GREY && t->bps == 4)
        return (unsigned)((x + y) & 15);
    else
        v = s == 0 ? pat(x, y) : s == 1 ? pat(x, y) ^ 0x5A : (x * 3 + y * 5) & 255;
    if (t->alpha == EXTRASAMPLE_ASSOCALPHA && s < t->spp - 1)
        v = v * alpha8(x, y) / 255;
    return t->bps == 16 ? (unsigned)v * 257u : (unsigned)v;
}

/* The expected 8-bit output of channel c at (x,y). */
static int expect(const tspec *t, int x, int y, int c)
{
    int v, a;
    if (t->kind == K_PAL)
        return (pal_entry(t, pal_index(t, x, y), c) * 255 + 32767) / 65535;
    if (t->kind == K_GREY && t->bps == 1) {
        v = bit(x, y) ? 255 : 0;
        return t->photo == PHOTOMETRIC_MINISWHITE ? 255 - v : v;
    }
    if (t->kind == K_GREY && t->bps == 4)
        v = ((x + y) & 15) * 17;
    else
        v = (int)raw(t, x, y, c) / (t->bps == 16 ? 257 : 1);
    if (t->photo == PHOTOMETRIC_MINISWHITE)
        v = 255 - v;
    if (!t->alpha)
        return v;
    a = alpha8(x, y);
    if (t->alpha == EXTRASAMPLE_ASSOCALPHA)
        return v + 255 - a > 255 ? 255 : v + 255 - a;
    return (v * a + 255 * (255 - a) + 127) / 255;
}

static int out_channels(const tspec *t)
{
    return t->kind == K_RGB || (t->kind == K_PAL && !t->grey_pal) ? 3 : 1;
}

/* ---- writing TIFFs with libtiff --------------------------------------- */

static void put_sample(uint8_t *row, size_t j, int bps, unsigned v)
{
    if (bps == 8) {
        row[j] = (uint8_t)v;
    } else if (bps == 16) {
        uint16_t s = (uint16_t)v;
        memcpy(row + 2 * j, &s, 2);
    } else {
        size_t b = j * (size_t)bps;
        row[b >> 3] |= (uint8_t)(v << (8 - bps - (int)(b & 7)));
    }
}

/* Pack n pixels from x0 of row y, all samples (plane < 0) or one plane. */
static void pack(const tspec *t, int y, int plane, int x0, int n, uint8_t *row,
                 size_t rowbytes)
{
    int i, s;
    memset(row, 0, rowbytes);
    for (i = 0; i < n && x0 + i < t->w; i++) {
        if (plane >= 0)
            put_sample(row, (size_t)i, t->bps, raw(t, x0 + i, y, plane));
        else
            for (s = 0; s < t->spp; s++)
                put_sample(row, (size_t)i * t->spp + s, t->bps,
                           raw(t, x0 + i, y, s));
    }
}

static void set_colormap(TIFF *tif, const tspec *t)
{
    uint16_t m[3][256];
    int i, c;
    for (i = 0; i < 256; i++)
        for (c = 0; c < 3; c++)
            m[c][i] = (uint16_t)(i < (1 << t->bps) ? pal_entry(t, i, c) : 0);
    TIFFSetField(tif, TIFFTAG_COLORMAP, m[0], m[1], m[2]);
}

static void write_tiles(TIFF *tif, const tspec *t, int np)
{
    int p, x, y, r;
    tmsize_t rb = TIFFTileRowSize(tif);
    uint8_t *buf = calloc((size_t)TIFFTileSize(tif), 1);
    for (p = 0; p < np; p++)
        for (y = 0; y < t->h; y += 16)
            for (x = 0; x < t->w; x += 16) {
                for (r = 0; r < 16; r++)
                    if (y + r < t->h)
                        pack(t, y + r, np > 1 ? p : -1, x, 16, buf + r * rb,
                             (size_t)rb);
                TIFFWriteTile(tif, buf, (uint32_t)x, (uint32_t)y, 0,
                              (uint16_t)p);
            }
    free(buf);
}

static int write_spec(const char *path, const tspec *t)
{
    TIFF *tif = TIFFOpen(path, t->mode ? t->mode : "w");
    int np = t->planar == PLANARCONFIG_SEPARATE ? t->spp : 1, p, y;
    uint8_t *row;
    if (!tif)
        return -1;
    TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, t->w);
    TIFFSetField(tif, TIFFTAG_IMAGELENGTH, t->h);
    TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, t->bps);
    TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, t->spp);
    TIFFSetField(tif, TIFFTAG_PHOTOMETRIC, t->photo);
    TIFFSetField(tif, TIFFTAG_PLANARCONFIG, t->planar);
    TIFFSetField(tif, TIFFTAG_COMPRESSION, t->comp);
    if (t->pred)
        TIFFSetField(tif, TIFFTAG_PREDICTOR, t->pred);
    if (t->alpha) {
        uint16_t es = (uint16_t)t->alpha;
        TIFFSetField(tif, TIFFTAG_EXTRASAMPLES, 1, &es);
    }
    if (t->kind == K_PAL)
        set_colormap(tif, t);
    if (t->tiled) {
        TIFFSetField(tif, TIFFTAG_TILEWIDTH, 16);
        TIFFSetField(tif, TIFFTAG_TILELENGTH, 16);
        write_tiles(tif, t, np);
    } else {
        TIFFSetField(tif, TIFFTAG_ROWSPERSTRIP, t->rps);
        row = calloc((size_t)TIFFScanlineSize(tif) + 8, 1);
        for (p = 0; p < np; p++)
            for (y = 0; y < t->h; y++) {
                pack(t, y, np > 1 ? p : -1, 0, t->w, row,
                     (size_t)TIFFScanlineSize(tif));
                TIFFWriteScanline(tif, row, (uint32_t)y, (uint16_t)p);
            }
        free(row);
    }
    TIFFClose(tif);
    return 0;
}

static char *tmpfile_path(const char *name)
{
    static char buf[8][600];
    static int k;
    char *p = buf[k++ % 8];
    snprintf(p, 600, "%s/%s", tt_tmpdir(), name);
    return p;
}

/* Write t, read it back and compare every pixel. */
static void check_layout(const tspec *t, const char *name)
{
    td_ctx cx;
    td_image *im = NULL;
    char *path = tmpfile_path(name);
    int x, y, c, bad = 0, bx = 0, by = 0, got = 0, want = 0;
    td_ctx_init(&cx);
    TT_CHECKF(write_spec(path, t) == 0, "%s: cannot write", name);
    if (td_image_read(path, &im, NULL, &cx) != 0) {
        TT_CHECKF(0, "%s: %s", name, td_errmsg(&cx));
        return;
    }
    TT_CHECKF(im->w == t->w && im->h == t->h, "%s: %dx%d", name, im->w, im->h);
    TT_CHECKF(im->channels == out_channels(t), "%s: %d channels", name,
              im->channels);
    for (y = 0; y < t->h && im->channels == out_channels(t); y++)
        for (x = 0; x < t->w; x++)
            for (c = 0; c < im->channels; c++) {
                int v = im->data[(size_t)y * im->stride + (size_t)x * im->channels + c];
                int e = expect(t, x, y, c);
                if (v != e && bad++ == 0) {
                    bx = x, by = y, got = v, want = e;
                }
            }
    TT_CHECKF(bad == 0, "%s: %d samples differ, first (%d,%d) got %d want %d",
              name, bad, bx, by, got, want);
    td_image_free(im);
}

static tspec grey8(int comp, int tiled)
{
    tspec t = {37, 23, K_GREY, 8, 1, PHOTOMETRIC_MINISBLACK, PLANARCONFIG_CONTIG,
               comp, tiled, 5, 0, 0, NULL, 0};
    return t;
}

static void test_tiff_grey8_all_codecs(void)
{
    const int comps[] = {COMPRESSION_NONE, COMPRESSION_LZW,
                         COMPRESSION_ADOBE_DEFLATE, COMPRESSION_PACKBITS};
    const char *names[] = {"none", "lzw", "deflate", "packbits"};
    char name[64];
    int i, tiled;
    for (i = 0; i < 4; i++)
        for (tiled = 0; tiled < 2; tiled++) {
            tspec t = grey8(comps[i], tiled);
            snprintf(name, sizeof name, "g8_%s_%s.tif", names[i],
                     tiled ? "tiled" : "striped");
            check_layout(&t, name);
        }
}

static void test_tiff_bilevel(void)
{
    tspec t = {61, 29, K_GREY, 1, 1, PHOTOMETRIC_MINISWHITE, PLANARCONFIG_CONTIG,
               COMPRESSION_CCITTFAX4, 0, 29, 0, 0, NULL, 0};
    check_layout(&t, "g4_miniswhite.tif");
    t.photo = PHOTOMETRIC_MINISBLACK;
    check_layout(&t, "g4_minisblack.tif");
    t.comp = COMPRESSION_CCITTFAX3;
    t.rps = 7;
    check_layout(&t, "g3_minisblack.tif");
    t.comp = COMPRESSION_NONE;
    t.photo = PHOTOMETRIC_MINISWHITE;
    t.tiled = 1;
    check_layout(&t, "bilevel_tiled.tif");
    t.tiled = 0;
    t.comp = COMPRESSION_PACKBITS;
    check_layout(&t, "bilevel_packbits.tif");
}

static void test_tiff_grey_depths(void)
{
    tspec t = grey8(COMPRESSION_LZW, 0);
    t.bps = 16;
    check_layout(&t, "g16_le.tif");
    t.mode = "wb"; /* big-endian: the reader must swap */
    check_layout(&t, "g16_be.tif");
    t.tiled = 1;
    check_layout(&t, "g16_be_tiled.tif");
    t = grey8(COMPRESSION_NONE, 0);
    t.bps = 4;
    check_layout(&t, "g4bit.tif");
    t = grey8(COMPRESSION_ADOBE_DEFLATE, 0);
    t.photo = PHOTOMETRIC_MINISWHITE;
    check_layout(&t, "g8_miniswhite.tif");
    t = grey8(COMPRESSION_LZW, 1);
    t.mode = "w8";
    check_layout(&t, "g8_bigtiff.tif");
}

static void test_tiff_rgb(void)
{
    tspec t = {41, 19, K_RGB, 8, 3, PHOTOMETRIC_RGB, PLANARCONFIG_CONTIG,
               COMPRESSION_LZW, 0, 4, 0, 0, NULL, 0};
    check_layout(&t, "rgb8_contig.tif");
    t.planar = PLANARCONFIG_SEPARATE;
    check_layout(&t, "rgb8_separate.tif");
    t.tiled = 1;
    check_layout(&t, "rgb8_separate_tiled.tif");
    t.planar = PLANARCONFIG_CONTIG;
    check_layout(&t, "rgb8_contig_tiled.tif");
    t.tiled = 0;
    t.bps = 16;
    check_layout(&t, "rgb16_contig.tif");
    t.planar = PLANARCONFIG_SEPARATE;
    check_layout(&t, "rgb16_separate.tif");
}

static void test_tiff_alpha(void)
{
    tspec t = {33, 17, K_RGB, 8, 4, PHOTOMETRIC_RGB, PLANARCONFIG_CONTIG,
               COMPRESSION_ADOBE_DEFLATE, 0, 3, EXTRASAMPLE_UNASSALPHA, 0, NULL, 0};
    check_layout(&t, "rgba_unassoc.tif");
    t.planar = PLANARCONFIG_SEPARATE;
    check_layout(&t, "rgba_unassoc_separate.tif");
    t.alpha = EXTRASAMPLE_ASSOCALPHA;
    t.planar = PLANARCONFIG_CONTIG;
    check_layout(&t, "rgba_assoc.tif");
    t = (tspec){33, 17, K_GREY, 8, 2, PHOTOMETRIC_MINISBLACK, PLANARCONFIG_CONTIG,
                COMPRESSION_NONE, 1, 0, EXTRASAMPLE_UNASSALPHA, 0, NULL, 0};
    check_layout(&t, "greyalpha_tiled.tif");
}

/* Deflate with the horizontal predictor, 8-bit: the blocks are inflated
 * on threads (src/io/tiffio.c), enough of them for several batches of 64:
 * every layout reads back exactly, and a tile whose data is damaged gives
 * the reader's error, not wrong pixels. */
static void test_tiff_deflate_threads(void)
{
    tspec t = {300, 203, K_GREY, 8, 1, PHOTOMETRIC_MINISBLACK,
               PLANARCONFIG_CONTIG, COMPRESSION_ADOBE_DEFLATE, 1, 3, 0, 0,
               NULL, PREDICTOR_HORIZONTAL};
    td_ctx cx;
    td_image *im = NULL;
    char *path = tmpfile_path("deflate_damaged.tif");
    TIFF *tif;
    uint64_t off = 0;
    FILE *f;
    check_layout(&t, "deflate_grey_tiled.tif");
    t.tiled = 0;
    check_layout(&t, "deflate_grey_striped.tif");
    t.pred = 0;
    check_layout(&t, "deflate_grey_nopred.tif");
    t = (tspec){300, 203, K_RGB, 8, 3, PHOTOMETRIC_RGB, PLANARCONFIG_CONTIG,
                COMPRESSION_ADOBE_DEFLATE, 1, 3, 0, 0, NULL,
                PREDICTOR_HORIZONTAL};
    check_layout(&t, "deflate_rgb_tiled.tif");
    t.planar = PLANARCONFIG_SEPARATE;
    check_layout(&t, "deflate_rgb_separate_tiled.tif");
    t.tiled = 0;
    check_layout(&t, "deflate_rgb_separate_striped.tif");
    t = (tspec){300, 203, K_RGB, 8, 4, PHOTOMETRIC_RGB, PLANARCONFIG_CONTIG,
                COMPRESSION_ADOBE_DEFLATE, 1, 3, EXTRASAMPLE_UNASSALPHA, 0,
                NULL, PREDICTOR_HORIZONTAL};
    check_layout(&t, "deflate_rgba_tiled.tif");
    /* damage tile 100's data */
    t = (tspec){300, 203, K_GREY, 8, 1, PHOTOMETRIC_MINISBLACK,
                PLANARCONFIG_CONTIG, COMPRESSION_ADOBE_DEFLATE, 1, 3, 0, 0,
                NULL, PREDICTOR_HORIZONTAL};
    TT_CHECK(write_spec(path, &t) == 0);
    if ((tif = TIFFOpen(path, "r"))) {
        off = TIFFGetStrileOffset(tif, 100);
        TIFFClose(tif);
    }
    TT_CHECK(off > 0);
    if (off > 0 && (f = fopen(path, "r+b"))) {
        static const char junk[8] = "\xff\x00\xff\x00\xff\x00\xff";
        fseek(f, (long)off + 2, SEEK_SET);
        fwrite(junk, 1, sizeof junk, f);
        fclose(f);
    }
    td_ctx_init(&cx);
    TT_CHECK(td_image_read(path, &im, NULL, &cx) != 0);
    TT_CHECKF(strstr(cx.msg, "deflate_damaged.tif") &&
                  strstr(cx.msg, "corrupt"),
              "%s", cx.msg);
    td_image_free(im);
}

static void test_tiff_palette(void)
{
    tspec t = {35, 21, K_PAL, 8, 1, PHOTOMETRIC_PALETTE, PLANARCONFIG_CONTIG,
               COMPRESSION_PACKBITS, 0, 6, 0, 0, NULL, 0};
    check_layout(&t, "pal8.tif");
    t.grey_pal = 1;
    check_layout(&t, "pal8_grey.tif");
    t.grey_pal = 0;
    t.bps = 4;
    t.tiled = 1;
    check_layout(&t, "pal4_tiled.tif");
}

/* JPEG-compressed YCbCr: lossy, so only a tolerance on flat areas. */
static void test_tiff_jpeg_ycbcr(void)
{
    td_ctx cx;
    td_image *im = NULL;
    char *path = tmpfile_path("ycbcr_jpeg.tif");
    TIFF *tif = TIFFOpen(path, "w");
    uint8_t row[64 * 3];
    int x, y, ok = 1;
    td_ctx_init(&cx);
    TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, 64);
    TIFFSetField(tif, TIFFTAG_IMAGELENGTH, 32);
    TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, 8);
    TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, 3);
    TIFFSetField(tif, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
    TIFFSetField(tif, TIFFTAG_COMPRESSION, COMPRESSION_JPEG);
    TIFFSetField(tif, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_YCBCR);
    TIFFSetField(tif, TIFFTAG_JPEGCOLORMODE, JPEGCOLORMODE_RGB);
    TIFFSetField(tif, TIFFTAG_JPEGQUALITY, 95);
    TIFFSetField(tif, TIFFTAG_ROWSPERSTRIP, 16);
    for (y = 0; y < 32; y++) {
        for (x = 0; x < 64; x++) {
            row[3 * x] = x < 32 ? 200 : 30;
            row[3 * x + 1] = x < 32 ? 40 : 180;
            row[3 * x + 2] = 90;
        }
        TIFFWriteScanline(tif, row, (uint32_t)y, 0);
    }
    TIFFClose(tif);
    if (td_image_read(path, &im, NULL, &cx) != 0) {
        TT_CHECKF(0, "%s", td_errmsg(&cx));
        return;
    }
    TT_CHECK(im->w == 64 && im->h == 32 && im->channels == 3);
    for (y = 4; y < 28; y++)
        for (x = 4; x < 60; x++) {
            const uint8_t *p = im->data + (size_t)y * im->stride + 3 * (size_t)x;
            if (x > 26 && x < 38)
                continue;
            if (abs(p[0] - (x < 32 ? 200 : 30)) > 10 ||
                abs(p[1] - (x < 32 ? 40 : 180)) > 10 || abs(p[2] - 90) > 10)
                ok = 0;
        }
    TT_CHECK(ok);
    td_image_free(im);
}

/* JPEG goes through the OpenCV shim; the magic bytes decide, not the name
 * (the file is called .tif).  Lossy, so flat areas with a tolerance. */
static void test_jpeg_by_magic(void)
{
    td_ctx cx;
    td_image *im, *back = NULL;
    char *path = tmpfile_path("really_a_jpeg.tif");
    int x, y, c, ok = 1, w = 0, h = 0, ch = 0;
    td_ctx_init(&cx);
    im = td_image_new(48, 32, 3, &cx);
    for (y = 0; y < 32; y++)
        for (x = 0; x < 48; x++)
            for (c = 0; c < 3; c++)
                im->data[(size_t)y * im->stride + 3 * (size_t)x + c] =
                    (uint8_t)(x < 24 ? 40 + 60 * c : 220 - 50 * c);
    TT_CHECKF(td_cv_write_jpeg(path, im, 95, &cx) == 0, "%s", td_errmsg(&cx));
    TT_CHECKF(td_image_read(path, &back, NULL, &cx) == 0, "%s", td_errmsg(&cx));
    TT_CHECK(td_image_info(path, &w, &h, &ch, NULL, &cx) == 0 && w == 48 &&
             h == 32 && ch == 3);
    if (back) {
        TT_CHECK(back->w == 48 && back->h == 32 && back->channels == 3);
        for (y = 0; y < 32; y++)
            for (x = 0; x < 48; x++)
                for (c = 0; c < 3 && back->channels == 3; c++) {
                    int v = back->data[(size_t)y * back->stride + 3 * (size_t)x + c];
                    if ((x < 20 || x > 27) &&
                        abs(v - (x < 24 ? 40 + 60 * c : 220 - 50 * c)) > 8)
                        ok = 0;
                }
        TT_CHECK(ok);
    }
    td_image_free(back);
    td_image_free(im);
}


/* src/io/jpegio.c: a JPEG whose frame header claims 30000 x 30000 pixels in
 * a file of a few kilobytes is refused at once (it used to allocate the
 * whole frame and decode for minutes); a JPEG cut short is refused too. */
static void test_jpeg_forged_size(void)
{
    td_ctx cx;
    td_image *im, *back = NULL;
    char *path = tmpfile_path("forged.jpg");
    unsigned char buf[65536];
    size_t n, i;
    FILE *f;
    int x, y, rc;
    td_ctx_init(&cx);
    im = td_image_new(200, 150, 1, &cx);
    for (y = 0; y < 150; y++)
        for (x = 0; x < 200; x++)
            im->data[(size_t)y * im->stride + x] = (uint8_t)((x * 7 + y * 3) & 255);
    TT_CHECK(td_cv_write_jpeg(path, im, 90, &cx) == 0);
    f = fopen(path, "rb");
    n = f ? fread(buf, 1, sizeof buf, f) : 0;
    if (f)
        fclose(f);
    TT_CHECK(n > 100);
    for (i = 0; i + 9 < n; i++) /* SOF0: FF C0 len(2) prec(1) h(2) w(2) */
        if (buf[i] == 0xff && buf[i + 1] == 0xc0) {
            buf[i + 5] = buf[i + 7] = 30000 >> 8;
            buf[i + 6] = buf[i + 8] = 30000 & 255;
            break;
        }
    TT_CHECK(i + 9 < n);
    f = fopen(path, "wb");
    if (f) {
        fwrite(buf, 1, n, f);
        fclose(f);
    }
    td_ctx_clear(&cx);
    rc = td_image_read(path, &back, NULL, &cx);
    TT_CHECKF(rc == TD_EFORMAT && strstr(td_errmsg(&cx), "forged.jpg") &&
                  strstr(td_errmsg(&cx), "30000 x 30000"),
              "rc %d: %s", rc, td_errmsg(&cx));
    td_image_free(back);
    /* cut short after half its bytes, an end marker appended: libjpeg
       warns of corrupt data, and the read fails naming the file (it used
       to return a grey-filled image with exit 0) */
    TT_CHECK(td_cv_write_jpeg(path, im, 90, &cx) == 0);
    f = fopen(path, "rb");
    n = f ? fread(buf, 1, sizeof buf, f) : 0;
    if (f)
        fclose(f);
    f = fopen(path, "wb");
    if (f) {
        fwrite(buf, 1, n / 2, f);
        fwrite("\xff\xd9", 1, 2, f);
        fclose(f);
    }
    back = NULL;
    td_ctx_clear(&cx);
    rc = td_image_read(path, &back, NULL, &cx);
    TT_CHECKF(rc == TD_EFORMAT && strstr(td_errmsg(&cx), "forged.jpg") &&
                  strstr(td_errmsg(&cx), "cannot decode JPEG"),
              "truncated: rc %d: %s", rc, td_errmsg(&cx));
    td_image_free(back);
    td_image_free(im);
}

/* ---- PNG --------------------------------------------------------------- */

/* Write a PNG with libpng: rows of w pixels made by px(x,y,sample). */
static void write_png_raw(const char *path, int w, int h, int ctype, int depth,
                          int interlace, int with_trns)
{
    FILE *f = fopen(path, "wb");
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, 0, 0, 0);
    png_infop info = png_create_info_struct(png);
    int ch = png_get_channels(png, info), x, y, s, passes;
    uint8_t *row = calloc((size_t)w * 8 + 8, 1);
    png_init_io(png, f);
    png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, depth, ctype,
                 interlace ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE, 0, 0);
    if (ctype == PNG_COLOR_TYPE_PALETTE) {
        png_color pal[20];
        png_byte ta[20];
        for (x = 0; x < 20; x++) {
            pal[x].red = (png_byte)(x * 12);
            pal[x].green = (png_byte)(255 - x * 12);
            pal[x].blue = (png_byte)(x * 7);
            ta[x] = (png_byte)(x % 2 ? 255 : 0);
        }
        png_set_PLTE(png, info, pal, 20);
        if (with_trns)
            png_set_tRNS(png, info, ta, 20, NULL);
    }
    png_write_info(png, info);
    ch = ctype == PNG_COLOR_TYPE_RGB ? 3 : ctype == PNG_COLOR_TYPE_RGB_ALPHA ? 4
         : ctype == PNG_COLOR_TYPE_GRAY_ALPHA ? 2 : 1;
    passes = png_set_interlace_handling(png);
    for (s = 0; s < passes; s++)
        for (y = 0; y < h; y++) {
            memset(row, 0, (size_t)w * 8 + 8);
            for (x = 0; x < w; x++) {
                int c;
                for (c = 0; c < ch; c++) {
                    int v = c == 3 || (ch == 2 && c == 1) ? alpha8(x, y)
                            : c == 0 ? pat(x, y) : c == 1 ? pat(x, y) ^ 0x5A
                                                          : (x * 3 + y * 5) & 255;
                    if (ctype == PNG_COLOR_TYPE_PALETTE)
                        row[x] = (uint8_t)((x + 2 * y) % 20);
                    else if (depth == 16) {
                        row[2 * (x * ch + c)] = (uint8_t)v;
                        row[2 * (x * ch + c) + 1] = (uint8_t)v;
                    } else if (depth == 8)
                        row[x * ch + c] = (uint8_t)v;
                    else if (depth == 1)
                        row[x / 8] |= (uint8_t)(bit(x, y) << (7 - x % 8));
                }
            }
            png_write_row(png, row);
        }
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    fclose(f);
    free(row);
}

/* Expected 8-bit output of the PNGs written above. */
static int png_expect(int ctype, int depth, int trns, int x, int y, int c)
{
    int v, a;
    if (ctype == PNG_COLOR_TYPE_PALETTE) {
        int i = (x + 2 * y) % 20;
        v = c == 0 ? i * 12 : c == 1 ? 255 - i * 12 : i * 7;
        return trns && i % 2 == 0 ? 255 : v;
    }
    if (depth == 1)
        return bit(x, y) ? 255 : 0;
    v = c == 0 ? pat(x, y) : c == 1 ? pat(x, y) ^ 0x5A : (x * 3 + y * 5) & 255;
    if (ctype != PNG_COLOR_TYPE_RGB_ALPHA && ctype != PNG_COLOR_TYPE_GRAY_ALPHA)
        return v;
    a = alpha8(x, y);
    return (v * a + 255 * (255 - a) + 127) / 255;
}

static void check_png(const char *name, int ctype, int depth, int interlace,
                      int trns, int want_ch)
{
    td_ctx cx;
    td_image *im = NULL;
    char *path = tmpfile_path(name);
    int x, y, c, bad = 0;
    td_ctx_init(&cx);
    write_png_raw(path, 29, 19, ctype, depth, interlace, trns);
    if (td_image_read(path, &im, NULL, &cx) != 0) {
        TT_CHECKF(0, "%s: %s", name, td_errmsg(&cx));
        return;
    }
    TT_CHECKF(im->w == 29 && im->h == 19 && im->channels == want_ch,
              "%s: %dx%dx%d", name, im->w, im->h, im->channels);
    for (y = 0; y < 19 && im->channels == want_ch; y++)
        for (x = 0; x < 29; x++)
            for (c = 0; c < want_ch; c++)
                if (im->data[(size_t)y * im->stride + (size_t)x * want_ch + c] !=
                    png_expect(ctype, depth, trns, x, y, c))
                    bad++;
    TT_CHECKF(bad == 0, "%s: %d samples differ", name, bad);
    td_image_free(im);
}


static void put32(unsigned char *p, unsigned long v)
{
    p[0] = (unsigned char)(v >> 24), p[1] = (unsigned char)(v >> 16);
    p[2] = (unsigned char)(v >> 8), p[3] = (unsigned char)v;
}

/* A PNG whose header claims 40000 x 40000 pixels in 74 bytes is refused
 * before the frame is allocated (deflate cannot pack 1.6 GB into that). */
static void test_png_forged_size(void)
{
    static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', 13, 10, 26, 10};
    unsigned char ihdr[25], idat[64], iend[12], z[32];
    unsigned char zero[1000];
    uLongf zn = sizeof z;
    char *path = tmpfile_path("forged.png");
    td_image *im = NULL;
    td_ctx cx;
    FILE *f;
    int rc;
    td_ctx_init(&cx);
    memset(zero, 0, sizeof zero);
    TT_CHECK(compress(z, &zn, zero, sizeof zero) == Z_OK && zn <= 40);
    put32(ihdr, 13);
    memcpy(ihdr + 4, "IHDR", 4);
    put32(ihdr + 8, 40000);
    put32(ihdr + 12, 40000);
    ihdr[16] = 8, ihdr[17] = 0, ihdr[18] = ihdr[19] = ihdr[20] = 0;
    put32(ihdr + 21, crc32(0, ihdr + 4, 17));
    put32(idat, (unsigned long)zn);
    memcpy(idat + 4, "IDAT", 4);
    memcpy(idat + 8, z, zn);
    put32(idat + 8 + zn, crc32(0, idat + 4, (uInt)(4 + zn)));
    put32(iend, 0);
    memcpy(iend + 4, "IEND", 4);
    put32(iend + 8, crc32(0, iend + 4, 4));
    f = fopen(path, "wb");
    if (f) {
        fwrite(sig, 1, 8, f);
        fwrite(ihdr, 1, 25, f);
        fwrite(idat, 1, 12 + zn, f);
        fwrite(iend, 1, 12, f);
        fclose(f);
    }
    rc = td_image_read(path, &im, NULL, &cx);
    TT_CHECKF(rc == TD_EFORMAT && strstr(td_errmsg(&cx), "40000 x 40000"),
              "rc %d: %s", rc, td_errmsg(&cx));
    td_image_free(im);
}

static void test_png_read_kinds(void)
{
    check_png("grey8.png", PNG_COLOR_TYPE_GRAY, 8, 0, 0, 1);
    check_png("grey1.png", PNG_COLOR_TYPE_GRAY, 1, 0, 0, 1);
    check_png("grey16.png", PNG_COLOR_TYPE_GRAY, 16, 0, 0, 1);
    check_png("rgb8.png", PNG_COLOR_TYPE_RGB, 8, 0, 0, 3);
    check_png("rgb16.png", PNG_COLOR_TYPE_RGB, 16, 0, 0, 3);
    check_png("rgba8.png", PNG_COLOR_TYPE_RGB_ALPHA, 8, 0, 0, 3);
    check_png("ga16.png", PNG_COLOR_TYPE_GRAY_ALPHA, 16, 0, 0, 1);
    check_png("pal.png", PNG_COLOR_TYPE_PALETTE, 8, 0, 0, 3);
    check_png("pal_trns.png", PNG_COLOR_TYPE_PALETTE, 8, 0, 1, 3);
    check_png("rgb8_interlaced.png", PNG_COLOR_TYPE_RGB, 8, 1, 0, 3);
    check_png("rgba_interlaced.png", PNG_COLOR_TYPE_RGB_ALPHA, 8, 1, 0, 3);
    check_png("pal_interlaced.png", PNG_COLOR_TYPE_PALETTE, 8, 1, 1, 3);
    check_png("grey1_interlaced.png", PNG_COLOR_TYPE_GRAY, 1, 1, 0, 1);
}

/* An 8-bit grey or RGB PNG of w x h noisy pixels (pixel value from a fixed
 * generator into v) with every row filtered by `filter` (a PNG_FILTER_*
 * flag), in IDAT chunks of 999 bytes, a tEXt chunk after them. */
static void write_png_filtered(const char *path, int w, int h, int ch,
                               int filter, uint8_t *v)
{
    FILE *f = fopen(path, "wb");
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, 0, 0, 0);
    png_infop info = png_create_info_struct(png);
    png_text t;
    uint32_t s = 12345;
    int y;
    size_t i;
    for (i = 0; i < (size_t)w * h * ch; i++) { /* smooth plus noise */
        s = s * 1103515245u + 12345u;
        v[i] = (uint8_t)((i / (size_t)ch) % 200 + ((s >> 16) & 31));
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, 8,
                 ch == 3 ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_GRAY,
                 PNG_INTERLACE_NONE, 0, 0);
    png_set_filter(png, 0, filter);
    png_set_compression_buffer_size(png, 999);
    png_write_info(png, info);
    for (y = 0; y < h; y++)
        png_write_row(png, v + (size_t)y * (size_t)w * (size_t)ch);
    t.compression = PNG_TEXT_COMPRESSION_NONE;
    t.key = (png_charp) "Comment";
    t.text = (png_charp) "after the image data";
    png_set_text(png, info, &t, 1);
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    fclose(f);
}

/* The reader of 8-bit grey and RGB PNGs (libdeflate, the filters undone
 * in place; pngio.c) gives the pixels written, every row filter on its
 * own and libpng's mix, one pixel wide or wider, rows of several of the
 * threads' chunks (pngio.c unfilter_rows) on 1, 2 and 3 threads; a PNG with a
 * byte of its image data changed (the chunk's CRC wrong, or put right so that
 * only the zlib check can tell) or cut short is refused naming the file,
 * never read. */
static void test_png_fast(void)
{
    static const int filters[6] = {PNG_FILTER_NONE,  PNG_FILTER_SUB,
                                   PNG_FILTER_UP,    PNG_FILTER_AVG,
                                   PNG_FILTER_PAETH, PNG_ALL_FILTERS};
    static const int sizes[4][2] = {{1, 7}, {2, 3}, {97, 61}, {3001, 23}};
    char *path = tmpfile_path("fast.png");
    uint8_t *v = malloc(3001 * 23 * 3);
    int fi, si, ch, k, nt;
    for (ch = 1; ch <= 3; ch += 2)
        for (fi = 0; fi < 6; fi++)
            for (si = 0; si < 4; si++)
                for (nt = 1; nt <= 3; nt++) {
                    int w = sizes[si][0], h = sizes[si][1];
                    td_image *im = NULL;
                    td_ctx cx;
                    td_ctx_init(&cx);
                    write_png_filtered(path, w, h, ch, filters[fi], v);
#ifdef _OPENMP
                    omp_set_num_threads(nt);
#endif
                    TT_CHECKF(td_image_read(path, &im, NULL, &cx) == 0, "%s",
                              td_errmsg(&cx));
#ifdef _OPENMP
                    omp_set_num_threads(omp_get_num_procs());
#endif
                    if (!im)
                        continue;
                    TT_CHECKF(im->w == w && im->h == h && im->channels == ch &&
                                  memcmp(im->data, v, (size_t)w * h * ch) == 0,
                              "%d channels, filter %d, %d x %d, %d threads: "
                              "pixels differ",
                              ch, fi, w, h, nt);
                    td_image_free(im);
                }
    for (k = 0; k < 3; k++) { /* CRC wrong, CRC right, cut short */
        td_image *im = NULL;
        td_ctx cx;
        FILE *f;
        long n;
        unsigned char *b;
        size_t p = 8;
        td_ctx_init(&cx);
        write_png_filtered(path, 97, 61, 3, PNG_ALL_FILTERS, v);
        f = fopen(path, "rb");
        fseek(f, 0, SEEK_END);
        n = ftell(f);
        fseek(f, 0, SEEK_SET);
        b = malloc((size_t)n);
        TT_CHECK(fread(b, 1, (size_t)n, f) == (size_t)n);
        fclose(f);
        while (memcmp(b + p + 4, "IDAT", 4) != 0) /* the first IDAT */
            p += 12 + ((size_t)b[p] << 24 | (size_t)b[p + 1] << 16 |
                       (size_t)b[p + 2] << 8 | b[p + 3]);
        if (k < 2)
            b[p + 8 + 500] ^= 0x10;
        if (k == 1)
            put32(b + p + 8 + 999, crc32(0, b + p + 4, 4 + 999));
        f = fopen(path, "wb");
        fwrite(b, 1, k == 2 ? (size_t)n / 2 : (size_t)n, f);
        fclose(f);
        TT_CHECKF(td_image_read(path, &im, NULL, &cx) == TD_EFORMAT &&
                      strstr(td_errmsg(&cx), "fast.png") && !im,
                  "case %d: %s", k, td_errmsg(&cx));
        td_image_free(im);
        free(b);
    }
    free(v);
}

static void test_png_write_roundtrip(void)
{
    td_ctx cx;
    td_image *im, *back = NULL;
    td_grid_u8 *g;
    int x, y, c, bad = 0;
    char *path = tmpfile_path("rt_rgb.png");
    td_ctx_init(&cx);
    im = td_image_new(45, 31, 3, &cx);
    for (y = 0; y < 31; y++)
        for (x = 0; x < 45; x++)
            for (c = 0; c < 3; c++)
                im->data[(size_t)y * im->stride + 3 * x + c] =
                    (uint8_t)(c == 0 ? pat(x, y) : c == 1 ? x * 5 : y * 8);
    TT_CHECK(td_png_write(path, im, &cx) == 0);
    TT_CHECKF(td_image_read(path, &back, NULL, &cx) == 0, "%s", td_errmsg(&cx));
    if (back) {
        TT_CHECK(back->channels == 3 && back->w == 45 && back->h == 31);
        TT_CHECK(memcmp(back->data, im->data, 45 * 31 * 3) == 0);
        td_image_free(back);
        back = NULL;
    }
    g = td_grid_u8_new(20, 10, &cx);
    for (y = 0; y < 10; y++)
        for (x = 0; x < 20; x++)
            TD_AT(g, x, y) = (uint8_t)((x + y) % 3);
    path = tmpfile_path("mask.png");
    TT_CHECK(td_png_write_u8(path, g, 1, &cx) == 0);
    TT_CHECK(td_image_read(path, &back, NULL, &cx) == 0);
    if (back) {
        for (y = 0; y < 10; y++)
            for (x = 0; x < 20; x++)
                if (back->data[y * back->stride + x] != (TD_AT(g, x, y) ? 255 : 0))
                    bad++;
        TT_CHECK(bad == 0 && back->channels == 1);
        td_image_free(back);
    }
    td_grid_u8_free(g);
    td_image_free(im);
}

static void test_png_write_u16(void)
{
    td_ctx cx;
    td_grid_u16 *g;
    char *path = tmpfile_path("dem16.png");
    FILE *f;
    png_structp png;
    png_infop info;
    png_bytepp rows;
    int x, y, bad = 0;
    td_ctx_init(&cx);
    g = td_grid_u16_new(17, 9, &cx);
    for (y = 0; y < 9; y++)
        for (x = 0; x < 17; x++)
            TD_AT(g, x, y) = (uint16_t)(x * 3000 + y * 7);
    TT_CHECK(td_png_write_u16(path, g, NULL, &cx) == 0);
    f = fopen(path, "rb");
    TT_CHECK(f != NULL);
    if (!f)
        return;
    png = png_create_read_struct(PNG_LIBPNG_VER_STRING, 0, 0, 0);
    info = png_create_info_struct(png);
    png_init_io(png, f);
    png_read_png(png, info, PNG_TRANSFORM_IDENTITY, NULL);
    TT_CHECK(png_get_bit_depth(png, info) == 16);
    TT_CHECK(png_get_image_width(png, info) == 17);
    rows = png_get_rows(png, info);
    for (y = 0; y < 9; y++)
        for (x = 0; x < 17; x++)
            if (((rows[y][2 * x] << 8) | rows[y][2 * x + 1]) != TD_AT(g, x, y))
                bad++;
    TT_CHECK(bad == 0);
    png_destroy_read_struct(&png, &info, NULL);
    fclose(f);
    td_grid_u16_free(g);
}

/* ---- GeoTIFF ------------------------------------------------------------ */

/* An 8-bit GeoTIFF written with libgeotiff: 2 m pixels, origin
 * (500000, 4000000), EPSG:32633, raster type area or point. */
static void write_geo_scan(const char *path, int point, int matrix)
{
    TIFF *tif = XTIFFOpen(path, "w");
    GTIF *gt = GTIFNew(tif);
    double sc[3] = {2, 2, 0}, tp[6] = {0, 0, 0, 500000, 4000000, 0};
    double m[16] = {2, 0.5, 0, 500000, 0.25, -2, 0, 4000000,
                    0, 0, 0, 0, 0, 0, 0, 1};
    uint8_t row[10] = {0};
    int y;
    TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, 10);
    TIFFSetField(tif, TIFFTAG_IMAGELENGTH, 8);
    TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, 8);
    TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, 1);
    TIFFSetField(tif, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
    TIFFSetField(tif, TIFFTAG_ROWSPERSTRIP, 8);
    if (matrix) {
        TIFFSetField(tif, TIFFTAG_GEOTRANSMATRIX, 16, m);
    } else {
        TIFFSetField(tif, TIFFTAG_GEOPIXELSCALE, 3, sc);
        TIFFSetField(tif, TIFFTAG_GEOTIEPOINTS, 6, tp);
    }
    GTIFKeySet(gt, GTModelTypeGeoKey, TYPE_SHORT, 1, ModelTypeProjected);
    GTIFKeySet(gt, GTRasterTypeGeoKey, TYPE_SHORT, 1,
               point ? RasterPixelIsPoint : RasterPixelIsArea);
    GTIFKeySet(gt, ProjectedCSTypeGeoKey, TYPE_SHORT, 1, 32633);
    GTIFKeySet(gt, GTCitationGeoKey, TYPE_ASCII, 0, "WGS 84 / UTM zone 33N");
    GTIFWriteKeys(gt);
    for (y = 0; y < 8; y++)
        TIFFWriteScanline(tif, row, (uint32_t)y, 0);
    GTIFFree(gt);
    XTIFFClose(tif);
}

static void test_geotiff_georef_read(void)
{
    td_ctx cx;
    td_image *im = NULL;
    td_georef g;
    char *path = tmpfile_path("geo_area.tif");
    td_ctx_init(&cx);
    write_geo_scan(path, 0, 0);
    TT_CHECKF(td_image_read(path, &im, &g, &cx) == 0, "%s", td_errmsg(&cx));
    TT_CHECK(g.valid && g.epsg == 32633);
    TT_NEAR(g.gt[0], 500000, 1e-9);
    TT_NEAR(g.gt[1], 2, 1e-12);
    TT_NEAR(g.gt[3], 4000000, 1e-9);
    TT_NEAR(g.gt[5], -2, 1e-12);
    TT_CHECK(g.gt[2] == 0 && g.gt[4] == 0);
    TT_CHECK(g.n_geokeys >= 16 && g.geoascii && strstr(g.geoascii, "UTM"));
    td_image_free(im);
    td_georef_clear(&g);

    path = tmpfile_path("geo_point.tif");
    write_geo_scan(path, 1, 0);
    TT_CHECK(td_georef_read(path, &g, &cx) == 0);
    TT_NEAR(g.gt[0], 499999, 1e-9); /* half a pixel left and up */
    TT_NEAR(g.gt[3], 4000001, 1e-9);
    td_georef_clear(&g);

    path = tmpfile_path("geo_matrix.tif");
    write_geo_scan(path, 0, 1);
    TT_CHECK(td_image_info(path, &(int){0}, &(int){0}, &(int){0}, &g, &cx) == 0);
    TT_CHECK(g.valid);
    TT_NEAR(g.gt[0], 500000, 1e-9);
    TT_NEAR(g.gt[2], 0.5, 1e-12);
    TT_NEAR(g.gt[4], 0.25, 1e-12);
    TT_NEAR(g.gt[5], -2, 1e-12);
    td_georef_clear(&g);

    path = tmpfile_path("g8_none_striped.tif");
    TT_CHECK(td_georef_read(path, &g, &cx) == 0 && !g.valid && g.epsg == 0);
    td_georef_clear(&g);
}

/* Run a command, return its output (caller frees) or NULL. */
static char *run_cmd(const char *cmd)
{
    FILE *p = popen(cmd, "r");
    size_t n = 0, cap = 1 << 16;
    char *buf;
    if (!p)
        return NULL;
    buf = calloc(cap, 1);
    n = fread(buf, 1, cap - 1, p);
    buf[n] = 0;
    pclose(p);
    return buf;
}

static int have_tool(const char *name)
{
    char cmd[128];
    snprintf(cmd, sizeof cmd, "command -v %s >/dev/null 2>&1", name);
    return system(cmd) == 0;
}

/* gdalinfo -stats: size, nodata, min, max and origin as gdal reads them. */
static void check_gdalinfo(const char *path, int w, int h, double nodata,
                           double mn, double mx, const td_georef *g)
{
    char cmd[700], *out, *s;
    int gw = 0, gh = 0;
    double v = 0, a = 0, b = 0;
    if (!have_tool("gdalinfo")) {
        fprintf(stderr, "  (gdalinfo absent: skipped)\n");
        return;
    }
    snprintf(cmd, sizeof cmd, "gdalinfo -stats '%s' 2>&1", path);
    out = run_cmd(cmd);
    TT_CHECK(out != NULL);
    if (!out)
        return;
    s = strstr(out, "Size is ");
    TT_CHECKF(s && sscanf(s, "Size is %d, %d", &gw, &gh) == 2 && gw == w && gh == h,
              "%s", out);
    s = strstr(out, "NoData Value=");
    TT_CHECKF(s && sscanf(s, "NoData Value=%lf", &v) == 1 && v == nodata, "%s", out);
    s = strstr(out, "Minimum=");
    TT_CHECKF(s && sscanf(s, "Minimum=%lf, Maximum=%lf", &a, &b) == 2, "%s", out);
    TT_NEAR(a, mn, 1e-3);
    TT_NEAR(b, mx, 1e-3);
    if (g) {
        s = strstr(out, "Origin = (");
        TT_CHECKF(s && sscanf(s, "Origin = (%lf,%lf)", &a, &b) == 2, "%s", out);
        TT_NEAR(a, g->gt[0], 1e-6);
        TT_NEAR(b, g->gt[3], 1e-6);
        TT_CHECKF(strstr(out, "32633") != NULL, "no EPSG in %s", out);
    }
    free(out);
}

/* Read a float32 TIFF back with libtiff; checks tags and every value. */
static void check_f32_file(const char *path, const td_grid_f32 *g, int tiled)
{
    TIFF *tif = TIFFOpen(path, "r");
    uint32_t w = 0, h = 0, tw = 0;
    uint16_t bps = 0, sf = 0, comp = 0, pred = 0;
    char *nd = NULL;
    int x, y, bad = 0;
    float *row;
    TT_CHECK(tif != NULL);
    if (!tif)
        return;
    TIFFGetField(tif, TIFFTAG_IMAGEWIDTH, &w);
    TIFFGetField(tif, TIFFTAG_IMAGELENGTH, &h);
    TIFFGetField(tif, TIFFTAG_BITSPERSAMPLE, &bps);
    TIFFGetField(tif, TIFFTAG_SAMPLEFORMAT, &sf);
    TIFFGetField(tif, TIFFTAG_COMPRESSION, &comp);
    TIFFGetField(tif, TIFFTAG_PREDICTOR, &pred);
    TT_CHECK((int)w == g->w && (int)h == g->h && bps == 32);
    TT_CHECK(sf == SAMPLEFORMAT_IEEEFP && comp == COMPRESSION_ADOBE_DEFLATE &&
             pred == PREDICTOR_FLOATINGPOINT);
    TT_CHECK(TIFFIsTiled(tif) == tiled);
    if (tiled)
        TT_CHECK(TIFFGetField(tif, TIFFTAG_TILEWIDTH, &tw) && tw == 256);
    if (g->has_nodata) { /* unregistered here: an anonymous counted field */
        const TIFFField *fld = TIFFFindField(tif, 42113, TIFF_ANY);
        uint32_t n = 0;
        TT_CHECK(fld && TIFFFieldPassCount(fld) &&
                 TIFFFieldReadCount(fld) == TIFF_VARIABLE2);
        TT_CHECK(TIFFGetField(tif, 42113, &n, &nd) && nd && n > 0 &&
                 atof(nd) == g->nodata);
    }
    if (!tiled) {
        row = malloc(sizeof(float) * w);
        for (y = 0; y < (int)h; y++) {
            TIFFReadScanline(tif, row, (uint32_t)y, 0);
            for (x = 0; x < (int)w; x++)
                if (row[x] != TD_AT(g, x, y))
                    bad++;
        }
        free(row);
    } else {
        uint32_t *rgba = NULL; /* tiled: read each tile */
        float *t = malloc((size_t)TIFFTileSize(tif));
        for (y = 0; y < (int)h; y += 256)
            for (x = 0; x < (int)w; x += 256) {
                int i, j;
                TIFFReadTile(tif, t, (uint32_t)x, (uint32_t)y, 0, 0);
                for (j = 0; j < 256 && y + j < (int)h; j++)
                    for (i = 0; i < 256 && x + i < (int)w; i++)
                        if (t[j * 256 + i] != TD_AT(g, x + i, y + j))
                            bad++;
            }
        free(t);
        free(rgba);
    }
    TT_CHECKF(bad == 0, "%d values differ", bad);
    TIFFClose(tif);
}

static td_grid_f32 *ramp(int w, int h, td_ctx *cx)
{
    td_grid_f32 *g = td_grid_f32_new(w, h, cx);
    int x, y;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++)
            TD_AT(g, x, y) = 100.25f + (float)x * 0.5f - (float)y * 0.125f;
    TD_AT(g, 0, 0) = -9999.0f;
    g->nodata = -9999.0f;
    g->has_nodata = 1;
    return g;
}

static void test_geotiff_write_f32(void)
{
    td_ctx cx;
    td_georef geo, back;
    td_grid_f32 *g;
    char *scan = tmpfile_path("geo_area.tif"), *path = tmpfile_path("dem.tif");
    td_ctx_init(&cx);
    TT_CHECK(td_georef_read(scan, &geo, &cx) == 0 && geo.valid);
    g = ramp(300, 200, &cx);
    TT_CHECKF(td_geotiff_write_f32(path, g, &geo, &cx) == 0, "%s", td_errmsg(&cx));
    check_f32_file(path, g, 0);
    TT_CHECK(td_georef_read(path, &back, &cx) == 0);
    TT_CHECK(back.valid && back.epsg == 32633);
    TT_NEAR(back.gt[0], geo.gt[0], 1e-9);
    TT_NEAR(back.gt[3], geo.gt[3], 1e-9);
    TT_NEAR(back.gt[5], geo.gt[5], 1e-12);
    TT_CHECK(back.n_geokeys == geo.n_geokeys &&
             memcmp(back.geokeys, geo.geokeys, 2 * geo.n_geokeys) == 0);
    check_gdalinfo(path, 300, 200, -9999, 100.25 - 199 * 0.125,
                   100.25 + 299 * 0.5, &geo);
    td_georef_clear(&back);
    td_grid_f32_free(g);

    g = ramp(1500, 40, &cx); /* > 1024 wide: tiled */
    path = tmpfile_path("dem_tiled.tif");
    TT_CHECKF(td_geotiff_write_f32(path, g, NULL, &cx) == 0, "%s", td_errmsg(&cx));
    check_f32_file(path, g, 1);
    check_gdalinfo(path, 1500, 40, -9999, 100.25 - 39 * 0.125,
                   100.25 + 1499 * 0.5, NULL);
    td_grid_f32_free(g);
    td_georef_clear(&geo);
}

static void test_geotiff_write_u8_and_epsg(void)
{
    td_ctx cx;
    td_georef geo, back;
    td_grid_u8 *g;
    td_image *im = NULL;
    char *path = tmpfile_path("mask_geo.tif");
    int x, y, bad = 0;
    td_ctx_init(&cx);
    td_georef_init(&geo);
    geo.valid = 1;
    geo.gt[0] = 10.0; geo.gt[1] = 0.001; geo.gt[2] = 0;
    geo.gt[3] = 50.0; geo.gt[4] = 0; geo.gt[5] = -0.001;
    geo.epsg = 4326; /* no verbatim keys: the writer builds them */
    g = td_grid_u8_new(70, 50, &cx);
    for (y = 0; y < 50; y++)
        for (x = 0; x < 70; x++)
            TD_AT(g, x, y) = (uint8_t)pat(x, y);
    TT_CHECKF(td_geotiff_write_u8(path, g, &geo, &cx) == 0, "%s", td_errmsg(&cx));
    TT_CHECK(td_image_read(path, &im, &back, &cx) == 0);
    if (im) {
        for (y = 0; y < 50; y++)
            for (x = 0; x < 70; x++)
                if (im->data[y * im->stride + x] != TD_AT(g, x, y))
                    bad++;
        TT_CHECK(bad == 0 && im->channels == 1);
    }
    TT_CHECK(back.valid && back.epsg == 4326);
    TT_NEAR(back.gt[1], 0.001, 1e-15);
    td_image_free(im);
    td_georef_clear(&back);

    /* a rotated transform goes out as a ModelTransformation matrix */
    geo.gt[2] = 0.0002;
    geo.gt[4] = 0.0001;
    path = tmpfile_path("rot.tif");
    TT_CHECK(td_geotiff_write_u8(path, g, &geo, &cx) == 0);
    TT_CHECK(td_georef_read(path, &back, &cx) == 0 && back.valid);
    TT_NEAR(back.gt[2], 0.0002, 1e-15);
    TT_NEAR(back.gt[4], 0.0001, 1e-15);
    td_georef_clear(&back);
    td_grid_u8_free(g);
}

/* ---- bad input and failed writes -------------------------------------- */

/* A little-endian classic TIFF with one IFD at offset 8 and `data` after
 * it; a LONG entry value of 0xFFFFFFFF is replaced by the data offset. */
typedef struct ifd_ent {
    uint16_t tag, type;
    uint32_t count, value;
} ifd_ent;

static void craft_tiff(const char *path, const ifd_ent *e, int n,
                       const uint8_t *data, size_t ndata)
{
    FILE *f = fopen(path, "wb");
    uint8_t hdr[8] = {'I', 'I', 42, 0, 8, 0, 0, 0};
    uint32_t doff = 8 + 2 + 12 * (uint32_t)n + 4, zero = 0;
    uint16_t cnt = (uint16_t)n;
    int i;
    fwrite(hdr, 1, 8, f);
    fwrite(&cnt, 2, 1, f);
    for (i = 0; i < n; i++) {
        uint32_t v = e[i].value == 0xFFFFFFFFu ? doff : e[i].value;
        fwrite(&e[i].tag, 2, 1, f);
        fwrite(&e[i].type, 2, 1, f);
        fwrite(&e[i].count, 4, 1, f);
        if (e[i].type == 3) {
            uint16_t s[2] = {(uint16_t)v, 0};
            fwrite(s, 2, 2, f);
        } else {
            fwrite(&v, 4, 1, f);
        }
    }
    fwrite(&zero, 4, 1, f);
    if (ndata)
        fwrite(data, 1, ndata, f);
    fclose(f);
}

static void craft_grey(const char *path, uint32_t w, uint32_t h,
                       uint32_t bytecount, size_t ndata)
{
    uint8_t data[256] = {0};
    ifd_ent e[] = {{256, 4, 1, w},      {257, 4, 1, h},
                   {258, 3, 1, 8},      {259, 3, 1, 1},
                   {262, 3, 1, 1},      {273, 4, 1, 0xFFFFFFFFu},
                   {278, 4, 1, h},      {279, 4, 1, bytecount}};
    craft_tiff(path, e, 8, data, ndata);
}

/* An 8-bit grey TIFF of w x h claiming Deflate, with 200 bytes of data. */
static void craft_deflate(const char *path, uint32_t w, uint32_t h)
{
    uint8_t data[256] = {0x78, 0x9c};
    ifd_ent e[] = {{256, 4, 1, w},      {257, 4, 1, h},
                   {258, 3, 1, 8},      {259, 3, 1, 8},
                   {262, 3, 1, 1},      {273, 4, 1, 0xFFFFFFFFu},
                   {278, 4, 1, h},      {279, 4, 1, 200}};
    craft_tiff(path, e, 8, data, 200);
}

/* Read path: must fail with a message naming the file (and containing
 * `want` when given), leaving the output pointer NULL. */
static void expect_fail(const char *path, int code, const char *want)
{
    td_ctx cx;
    td_image *im = NULL;
    int rc;
    td_ctx_init(&cx);
    rc = td_image_read(path, &im, NULL, &cx);
    TT_CHECKF(rc != 0 && im == NULL, "%s: read succeeded", path);
    TT_CHECKF(code == 0 || rc == code, "%s: code %d, want %d (%s)", path, rc,
              code, td_errmsg(&cx));
    TT_CHECKF(strstr(td_errmsg(&cx), path) != NULL, "message '%s' lacks %s",
              td_errmsg(&cx), path);
    if (want)
        TT_CHECKF(strstr(td_errmsg(&cx), want) != NULL, "message '%s' lacks '%s'",
                  td_errmsg(&cx), want);
    td_image_free(im);
}

/* Copy the first frac of src (or, when frac > 1, that many bytes). */
static void truncate_copy(const char *src, const char *dst, double frac)
{
    FILE *f = fopen(src, "rb"), *g = fopen(dst, "wb");
    static uint8_t buf[1 << 20];
    size_t n = fread(buf, 1, sizeof buf, f);
    fwrite(buf, 1, frac > 1 ? (size_t)frac : (size_t)(n * frac), g);
    fclose(f);
    fclose(g);
}

static void put_chunk(FILE *f, const char *type, const uint8_t *d, uint32_t n)
{
    uint8_t be[4] = {(uint8_t)(n >> 24), (uint8_t)(n >> 16), (uint8_t)(n >> 8),
                     (uint8_t)n};
    uLong crc = crc32(crc32(0, (const Bytef *)type, 4), d, n);
    fwrite(be, 1, 4, f);
    fwrite(type, 1, 4, f);
    fwrite(d, 1, n, f);
    be[0] = (uint8_t)(crc >> 24);
    be[1] = (uint8_t)(crc >> 16);
    be[2] = (uint8_t)(crc >> 8);
    be[3] = (uint8_t)crc;
    fwrite(be, 1, 4, f);
}

/* Signature, IHDR (8-bit grey, w x h), a token IDAT, IEND. */
static void craft_png_header(const char *path, uint32_t w, uint32_t h)
{
    static const uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    uint8_t ihdr[13] = {(uint8_t)(w >> 24), (uint8_t)(w >> 16), (uint8_t)(w >> 8),
                        (uint8_t)w, (uint8_t)(h >> 24), (uint8_t)(h >> 16),
                        (uint8_t)(h >> 8), (uint8_t)h, 8, 0, 0, 0, 0};
    uint8_t idat[8] = {0x78, 0x9c, 0, 0, 0, 0, 0, 0};
    FILE *f = fopen(path, "wb");
    fwrite(sig, 1, 8, f);
    put_chunk(f, "IHDR", ihdr, 13);
    put_chunk(f, "IDAT", idat, 8);
    put_chunk(f, "IEND", idat, 0);
    fclose(f);
}

static void test_bad_inputs(void)
{
    char *p;
    FILE *f;
    tspec t = grey8(COMPRESSION_LZW, 0);
    p = tmpfile_path("text.png");
    f = fopen(p, "w");
    fputs("this is not an image\n", f);
    fclose(f);
    expect_fail(p, TD_EFORMAT, "not a PNG, TIFF or JPEG");
    expect_fail(tmpfile_path("missing.tif"), TD_EIO, NULL);
    p = tmpfile_path("empty.tif");
    fclose(fopen(p, "w"));
    expect_fail(p, TD_EFORMAT, NULL);

    write_png_raw(tmpfile_path("big.png"), 300, 200, PNG_COLOR_TYPE_RGB, 8, 0, 0);
    truncate_copy(tmpfile_path("big.png"), tmpfile_path("trunc.png"), 0.5);
    expect_fail(tmpfile_path("trunc.png"), TD_EFORMAT, "PNG");
    truncate_copy(tmpfile_path("big.png"), tmpfile_path("trunc_hdr.png"), 20);
    expect_fail(tmpfile_path("trunc_hdr.png"), TD_EFORMAT, "PNG");

    p = tmpfile_path("huge.png"); /* a valid header, no pixel data */
    craft_png_header(p, 100000, 100000);
    expect_fail(p, TD_ETOOBIG, "larger than");

    t.w = 300;
    t.h = 200;
    write_spec(tmpfile_path("big.tif"), &t);
    truncate_copy(tmpfile_path("big.tif"), tmpfile_path("trunc.tif"), 0.6);
    expect_fail(tmpfile_path("trunc.tif"), TD_EFORMAT, NULL);
    craft_grey(tmpfile_path("short_strip.tif"), 64, 64, 4096, 100);
    expect_fail(tmpfile_path("short_strip.tif"), TD_EFORMAT, "file ends");
    /* headers under the pixel limit whose data cannot fill them: refused
       before the frame is allocated (no 900 MB for a 300-byte file) */
    craft_grey(tmpfile_path("claims.tif"), 30000, 30000, 900000000u, 100);
    expect_fail(tmpfile_path("claims.tif"), TD_EFORMAT, "file ends before");
    craft_deflate(tmpfile_path("claims_deflate.tif"), 30000, 30000);
    expect_fail(tmpfile_path("claims_deflate.tif"), TD_EFORMAT,
                "cannot hold");
    craft_grey(tmpfile_path("huge.tif"), 100000, 100000, 16, 16);
    expect_fail(tmpfile_path("huge.tif"), TD_ETOOBIG, "larger than");
    craft_grey(tmpfile_path("zero.tif"), 0, 64, 16, 16);
    expect_fail(tmpfile_path("zero.tif"), 0, NULL);
}

static void test_unsupported_tiff(void)
{
    TIFF *tif;
    const char *names[] = {"float.tif", "int32.tif", "five.tif"};
    const char *why[] = {"floating-point", "32-bit", "5 samples"};
    /* float samples (a DEM handed in as a scan), 32-bit integers, 5 samples */
    uint8_t row[4 * 5 * 8] = {0};
    int k, y;
    for (k = 0; k < 3; k++) {
        char *p = tmpfile_path(names[k]);
        tif = TIFFOpen(p, "w");
        TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, 8);
        TIFFSetField(tif, TIFFTAG_IMAGELENGTH, 4);
        TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, k == 2 ? 8 : 32);
        TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, k == 2 ? 5 : 1);
        TIFFSetField(tif, TIFFTAG_SAMPLEFORMAT,
                     k == 0 ? SAMPLEFORMAT_IEEEFP : SAMPLEFORMAT_UINT);
        TIFFSetField(tif, TIFFTAG_PHOTOMETRIC,
                     k == 2 ? PHOTOMETRIC_RGB : PHOTOMETRIC_MINISBLACK);
        TIFFSetField(tif, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
        if (k == 2) {
            uint16_t es[2] = {0, 0};
            TIFFSetField(tif, TIFFTAG_EXTRASAMPLES, 2, es);
        }
        for (y = 0; y < 4; y++)
            TIFFWriteScanline(tif, row, (uint32_t)y, 0);
        TIFFClose(tif);
        expect_fail(p, TD_EFORMAT, "unsupported TIFF layout");
        expect_fail(p, TD_EFORMAT, why[k]);
    }
}

/* No "<name>.tmp.*" file may remain in the scratch folder. */
static int temp_left(void)
{
    DIR *d = opendir(tt_tmpdir());
    struct dirent *e;
    int n = 0;
    while (d && (e = readdir(d)))
        if (strstr(e->d_name, ".tmp."))
            n++;
    if (d)
        closedir(d);
    return n;
}

static int cancel_at_half(const char *stage, double frac, void *user)
{
    (void)stage;
    (void)user;
    return frac > 0.5;
}

static void test_failed_writes(void)
{
    td_ctx cx;
    td_grid_f32 *g;
    td_image *im;
    char bad[700], *path = tmpfile_path("keep.tif");
    struct stat st0, st1;
    td_ctx_init(&cx);
    g = ramp(64, 512, &cx);
    im = td_image_new(8, 8, 1, &cx);
    snprintf(bad, sizeof bad, "%s/no/such/dir/out.png", tt_tmpdir());
    TT_CHECK(td_png_write(bad, im, &cx) == TD_EIO);
    TT_CHECK(strstr(td_errmsg(&cx), bad) != NULL);
    td_ctx_clear(&cx);
    TT_CHECK(td_geotiff_write_f32(bad, g, NULL, &cx) == TD_EIO);
    td_ctx_clear(&cx);

    /* a cancelled write leaves the previous file as it was, and no temp */
    TT_CHECK(td_geotiff_write_u8(path, &(td_grid_u8){8, 8, 8, im->data}, NULL,
                                 &cx) == 0);
    TT_CHECK(stat(path, &st0) == 0);
    cx.progress = cancel_at_half;
    TT_CHECK(td_geotiff_write_f32(path, g, NULL, &cx) == TD_ECANCEL);
    TT_CHECK(stat(path, &st1) == 0 && st1.st_size == st0.st_size &&
             st1.st_ino == st0.st_ino);
    TT_CHECK(temp_left() == 0);
    td_ctx_init(&cx);
    g->w = 0;
    TT_CHECK(td_geotiff_write_f32(path, g, NULL, &cx) != 0);
    TT_CHECK(strstr(td_errmsg(&cx), path) != NULL);
    TT_CHECK(temp_left() == 0);
    td_grid_f32_free(g);
    td_image_free(im);
}

static void test_image_info(void)
{
    td_ctx cx;
    int w = 0, h = 0, ch = 0;
    td_ctx_init(&cx);
    TT_CHECK(td_image_info(tmpfile_path("rgb8_contig.tif"), &w, &h, &ch, NULL,
                           &cx) == 0);
    TT_CHECK(w == 41 && h == 19 && ch == 3);
    TT_CHECK(td_image_info(tmpfile_path("pal8_grey.tif"), &w, &h, &ch, NULL,
                           &cx) == 0 && ch == 1);
    TT_CHECK(td_image_info(tmpfile_path("rgba8.png"), &w, &h, &ch, NULL, &cx) == 0);
    TT_CHECK(w == 29 && h == 19 && ch == 3);
    TT_CHECK(td_image_info(tmpfile_path("huge.tif"), &w, &h, &ch, NULL, &cx) ==
             TD_ETOOBIG);
}

int main(void)
{
    TIFFSetWarningHandler(NULL); /* the test's own libtiff writes */
    TT_RUN(test_tiff_grey8_all_codecs);
    TT_RUN(test_tiff_bilevel);
    TT_RUN(test_tiff_grey_depths);
    TT_RUN(test_tiff_rgb);
    TT_RUN(test_tiff_alpha);
    TT_RUN(test_tiff_deflate_threads);
    TT_RUN(test_tiff_palette);
    TT_RUN(test_tiff_jpeg_ycbcr);
    TT_RUN(test_jpeg_by_magic);
    TT_RUN(test_jpeg_forged_size);
    TT_RUN(test_png_read_kinds);
    TT_RUN(test_png_forged_size);
    TT_RUN(test_png_fast);
    TT_RUN(test_png_write_roundtrip);
    TT_RUN(test_png_write_u16);
    TT_RUN(test_geotiff_georef_read);
    TT_RUN(test_geotiff_write_f32);
    TT_RUN(test_geotiff_write_u8_and_epsg);
    TT_RUN(test_bad_inputs);
    TT_RUN(test_unsupported_tiff);
    TT_RUN(test_failed_writes);
    TT_RUN(test_image_info);
    return tt_summary();
}
