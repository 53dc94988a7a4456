/* tiffio.c: reading TIFF scans through libtiff, strip by strip or tile by
 * tile straight into an 8-bit grey or RGB td_image, so peak memory is the
 * output plus one decoded block.
 *
 * Supported: 1/2/4/8/16-bit grey (MinIsWhite, MinIsBlack), 1..8-bit palette,
 * 8/16-bit RGB, each with an optional alpha sample, contiguous or separate
 * planes, striped or tiled, any codec libtiff decodes; YCbCr only with JPEG
 * compression (libtiff converts it to RGB).  Everything else fails with
 * "FILE: unsupported TIFF layout (...)". */
#include "src/io/io_int.h"

#include <libdeflate.h>
#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <xtiffio.h>

/* The decoded layout of one TIFF directory and how it maps to the output. */
typedef struct tiff_layout {
    uint32_t w, h;
    uint16_t spp, bps, photo, planar;
    int ncol;        /* colour samples in the file: 1 or 3 */
    int alpha;       /* 0 none, 1 unassociated, 2 associated (sample ncol) */
    int channels;    /* output channels: 1 or 3 */
    int palette;     /* samples are colour-map indices */
    uint8_t lut[256];        /* grey raw value (bps <= 8) -> 8 bit */
    uint8_t map[3][256];     /* palette index -> 8-bit R, G, B */
} tiff_layout;

static int on_tiff_error(TIFF *tif, void *user, const char *module,
                         const char *fmt, va_list ap)
{
    td_tiff_err *e = user;
    if (e && e->count++ == 0) {
        unsigned long got, want;
        char *p;
        vsnprintf(e->msg, sizeof e->msg, fmt, ap);
        /* a short strip: libtiff says "Read error at scanline 4294967295"
           (no row known); say what it means */
        if ((p = strstr(e->msg, "scanline 4294967295")) != NULL &&
            sscanf(p, "scanline 4294967295; got %lu bytes, expected %lu",
                   &got, &want) == 2)
            snprintf(e->msg, sizeof e->msg, "the file ends inside the image "
                     "data (a strip or tile has %lu of its %lu bytes)", got,
                     want);
    }
    return 1; /* handled: libtiff's global handler must not print */
}

static int on_tiff_warning(TIFF *tif, void *user, const char *module,
                           const char *fmt, va_list ap)
{
    return 1; /* dropped */
}

static pthread_once_t geotiff_once = PTHREAD_ONCE_INIT;

static void register_geotiff_tags(void)
{
    XTIFFInitialize();
}

/* See io_int.h. */
TIFF *td_tiff_open(const char *path, int fd, const char *mode, td_tiff_err *e)
{
    TIFFOpenOptions *o;
    TIFF *tif;
    pthread_once(&geotiff_once, register_geotiff_tags);
    o = TIFFOpenOptionsAlloc();
    if (!o) {
        snprintf(e->msg, sizeof e->msg, "out of memory");
        e->count++;
        if (fd >= 0)
            close(fd);
        return NULL;
    }
    TIFFOpenOptionsSetErrorHandlerExtR(o, on_tiff_error, e);
    TIFFOpenOptionsSetWarningHandlerExtR(o, on_tiff_warning, NULL);
    if (fd >= 0) {
        tif = TIFFFdOpenExt(fd, path, mode, o);
        if (!tif)
            close(fd);
    } else {
        tif = TIFFOpenExt(path, mode, o);
    }
    TIFFOpenOptionsFree(o);
    return tif;
}

/* See io_int.h.  libtiff often starts its messages with the file name;
 * that prefix is dropped so the name appears once. */
int td_tiff_fail(td_ctx *cx, int code, const char *path, const char *what,
                 const td_tiff_err *e)
{
    const char *m = e && e->count ? e->msg : "";
    size_t n = strlen(path);
    if (strncmp(m, path, n) == 0 && m[n] == ':')
        m += n + 1 + (m[n + 1] == ' ');
    if (*m)
        return td_seterr(cx, code, "%s: %s: %s", path, what, m);
    return td_seterr(cx, code, "%s: %s", path, what);
}

/* The largest decoded / compressed ratio of a compression, 0: unbounded. */
static double max_ratio(uint16_t comp)
{
    switch (comp) {
    case COMPRESSION_NONE: return 2.0;
    case COMPRESSION_PACKBITS: return 130.0;
    case COMPRESSION_ADOBE_DEFLATE:
    case COMPRESSION_DEFLATE: return 1100.0;
    case COMPRESSION_LZW: return 5000.0;
    default: return 0.0;
    }
}

/* See io_int.h. */
int td_tiff_check_data(TIFF *tif, const char *path, td_ctx *cx)
{
    struct stat st;
    uint32_t i, n = TIFFNumberOfStrips(tif);
    uint64_t sum = 0, raw;
    uint16_t comp = COMPRESSION_NONE;
    double ratio;
    if (TIFFIsTiled(tif)) {
        n = TIFFNumberOfTiles(tif);
        raw = (uint64_t)TIFFTileSize64(tif) * n;
    } else {
        raw = (uint64_t)TIFFStripSize64(tif) * n;
    }
    if (stat(path, &st) != 0)
        return td_seterr(cx, TD_EIO, "%s: cannot read its size", path);
    for (i = 0; i < n; i++) {
        int err = 0;
        uint64_t off = TIFFGetStrileOffsetWithErr(tif, i, &err);
        uint64_t bc = TIFFGetStrileByteCountWithErr(tif, i, &err);
        if (err || (bc > 0 && (off > (uint64_t)st.st_size ||
                               bc > (uint64_t)st.st_size - off)))
            return td_seterr(cx, TD_EFORMAT, "%s: corrupt or truncated image "
                             "data: the file ends before %s %u of %u", path,
                             TIFFIsTiled(tif) ? "tile" : "strip", i + 1, n);
        sum += bc;
    }
    TIFFGetFieldDefaulted(tif, TIFFTAG_COMPRESSION, &comp);
    ratio = max_ratio(comp);
    if (ratio > 0 && (double)raw > ratio * (double)sum + 65536.0)
        return td_seterr(cx, TD_EFORMAT, "%s: corrupt TIFF: %llu bytes of "
                         "image data cannot hold the %u x %u frame it "
                         "claims", path, (unsigned long long)sum,
                         (unsigned)TIFFScanlineSize64(tif),
                         (unsigned)(raw / (TIFFScanlineSize64(tif) ?
                                           TIFFScanlineSize64(tif) : 1)));
    return 0;
}

static int unsupported(td_ctx *cx, const char *path, const char *why)
{
    return td_seterr(cx, TD_EFORMAT, "%s: unsupported TIFF layout (%s)", path,
                     why);
}

/* Palette -> 8-bit colour map; colour maps whose entries all fit in 8 bits
 * are taken as 8-bit (a common writer bug libtiff also tolerates). */
static int read_palette(TIFF *tif, tiff_layout *L, const char *path,
                        td_ctx *cx)
{
    uint16_t *r, *g, *b;
    int n = 1 << L->bps, i, c, wide = 0, grey = 1;
    if (L->bps > 8)
        return unsupported(cx, path, "palette of more than 8 bits");
    if (!TIFFGetField(tif, TIFFTAG_COLORMAP, &r, &g, &b))
        return td_seterr(cx, TD_EFORMAT, "%s: palette image without a "
                         "colour map", path);
    for (i = 0; i < n; i++)
        if (r[i] > 255 || g[i] > 255 || b[i] > 255)
            wide = 1;
    for (i = 0; i < n; i++) {
        const uint16_t *v[3] = {r, g, b};
        for (c = 0; c < 3; c++)
            L->map[c][i] = (uint8_t)(wide ? (v[c][i] * 255u + 32767u) / 65535u
                                          : v[c][i]);
        if (L->map[0][i] != L->map[1][i] || L->map[0][i] != L->map[2][i])
            grey = 0;
    }
    L->palette = 1;
    L->channels = grey ? 1 : 3;
    return 0;
}

/* Colour model, sample depth and alpha of the directory; 0 or an
 * "unsupported TIFF layout" error. */
static int layout_samples(TIFF *tif, tiff_layout *L, const char *path,
                          td_ctx *cx)
{
    uint16_t sfmt = SAMPLEFORMAT_UINT, comp = COMPRESSION_NONE, nextra = 0;
    uint16_t *extra = NULL;
    char why[96];
    TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLEFORMAT, &sfmt);
    TIFFGetFieldDefaulted(tif, TIFFTAG_COMPRESSION, &comp);
    if (!TIFFGetField(tif, TIFFTAG_PHOTOMETRIC, &L->photo))
        L->photo = L->spp >= 3 ? PHOTOMETRIC_RGB : PHOTOMETRIC_MINISBLACK;
    if (sfmt != SAMPLEFORMAT_UINT && sfmt != SAMPLEFORMAT_VOID) {
        snprintf(why, sizeof why, "%s samples",
                 sfmt == SAMPLEFORMAT_IEEEFP ? "floating-point"
                 : sfmt == SAMPLEFORMAT_INT ? "signed integer" : "complex");
        return unsupported(cx, path, why);
    }
    if (L->photo == PHOTOMETRIC_YCBCR) {
        if (comp != COMPRESSION_JPEG || L->planar != PLANARCONFIG_CONTIG)
            return unsupported(cx, path, "YCbCr that is not JPEG-compressed");
        TIFFSetField(tif, TIFFTAG_JPEGCOLORMODE, JPEGCOLORMODE_RGB);
        L->photo = PHOTOMETRIC_RGB;
    }
    if (L->photo == PHOTOMETRIC_RGB)
        L->ncol = 3;
    else if (L->photo == PHOTOMETRIC_MINISBLACK ||
             L->photo == PHOTOMETRIC_MINISWHITE ||
             L->photo == PHOTOMETRIC_PALETTE)
        L->ncol = 1;
    else {
        snprintf(why, sizeof why, "photometric interpretation %u",
                 (unsigned)L->photo);
        return unsupported(cx, path, why);
    }
    if (L->spp < L->ncol || L->spp > 4) {
        snprintf(why, sizeof why, "%u samples per pixel", (unsigned)L->spp);
        return unsupported(cx, path, why);
    }
    if (L->bps != 8 && L->bps != 16 &&
        !(L->ncol == 1 && (L->bps == 1 || L->bps == 2 || L->bps == 4))) {
        snprintf(why, sizeof why, "%u-bit %s samples", (unsigned)L->bps,
                 L->ncol == 3 ? "RGB" : "grey");
        return unsupported(cx, path, why);
    }
    if (L->spp > L->ncol &&
        TIFFGetField(tif, TIFFTAG_EXTRASAMPLES, &nextra, &extra) && nextra &&
        extra) {
        if (extra[0] == EXTRASAMPLE_UNASSALPHA)
            L->alpha = 1;
        else if (extra[0] == EXTRASAMPLE_ASSOCALPHA)
            L->alpha = 2;
    }
    L->channels = L->ncol;
    if (L->photo == PHOTOMETRIC_PALETTE)
        return read_palette(tif, L, path, cx);
    return 0;
}

/* Read and check the directory's layout; sizes are checked against the
 * limits before anything is allocated. */
static int layout_get(TIFF *tif, tiff_layout *L, const char *path,
                      td_ctx *cx)
{
    int i, max, rc;
    memset(L, 0, sizeof *L);
    if (!TIFFGetField(tif, TIFFTAG_IMAGEWIDTH, &L->w) ||
        !TIFFGetField(tif, TIFFTAG_IMAGELENGTH, &L->h))
        return td_seterr(cx, TD_EFORMAT, "%s: TIFF without image size", path);
    if ((rc = td_check_dims((long)L->w, (long)L->h, path, cx)) != 0)
        return rc;
    TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLESPERPIXEL, &L->spp);
    TIFFGetFieldDefaulted(tif, TIFFTAG_BITSPERSAMPLE, &L->bps);
    TIFFGetFieldDefaulted(tif, TIFFTAG_PLANARCONFIG, &L->planar);
    if (L->spp == 1)
        L->planar = PLANARCONFIG_CONTIG;
    if ((rc = layout_samples(tif, L, path, cx)) != 0)
        return rc;
    max = (1 << (L->bps < 8 ? L->bps : 8)) - 1;
    for (i = 0; i <= max; i++) {
        int v = (i * 255 + max / 2) / max;
        L->lut[i] = (uint8_t)(L->photo == PHOTOMETRIC_MINISWHITE ? 255 - v
                                                                 : v);
    }
    return 0;
}

/* Sample j of a packed row, as stored (bps 1, 2, 4, 8 or 16). */
static unsigned sample_at(const uint8_t *row, size_t j, int bps)
{
    if (bps == 8)
        return row[j];
    if (bps == 16) {
        uint16_t v;
        memcpy(&v, row + 2 * j, 2);
        return v;
    }
    {
        size_t bit = j * (size_t)bps;
        int shift = 8 - bps - (int)(bit & 7);
        return (row[bit >> 3] >> shift) & ((1u << bps) - 1);
    }
}

static uint8_t scale16(unsigned v)
{
    return (uint8_t)((v * 255u + 32767u) / 65535u);
}

/* A colour or grey sample as 8 bits (MinIsWhite inverted). */
static uint8_t sample8(const tiff_layout *L, unsigned v)
{
    if (L->bps == 16) {
        uint8_t s = scale16(v);
        return L->photo == PHOTOMETRIC_MINISWHITE ? (uint8_t)(255 - s) : s;
    }
    return L->bps == 8 && L->photo != PHOTOMETRIC_MINISWHITE ? (uint8_t)v
                                                             : L->lut[v];
}

/* Composite colour value c over white with alpha a (both 8-bit). */
static uint8_t over_white(unsigned c, unsigned a, int assoc)
{
    if (assoc) {
        unsigned v = c + 255u - a;
        return (uint8_t)(v > 255u ? 255u : v);
    }
    return (uint8_t)((c * a + 255u * (255u - a) + 127u) / 255u);
}

/* The common one-sample case (grey or palette, up to 8 bits): table
 * look-ups, a byte of packed pixels at a time. */
static void convert_packed(const tiff_layout *L, const uint8_t *src,
                           uint8_t *out, size_t n)
{
    const uint8_t *lut = L->palette ? L->map[0] : L->lut;
    int b = L->bps, per = 8 / b, s;
    unsigned m = (1u << b) - 1;
    size_t i = 0, k;
    for (k = 0; i < n; k++) {
        unsigned v = src[k];
        for (s = per - 1; s >= 0 && i < n; s--, i++) {
            unsigned idx = (v >> (s * b)) & m;
            if (L->channels == 3) {
                out[3 * i] = L->map[0][idx];
                out[3 * i + 1] = L->map[1][idx];
                out[3 * i + 2] = L->map[2][idx];
            } else {
                out[i] = lut[idx];
            }
        }
    }
}

/* One row of n contiguous pixels into out (channels bytes per pixel). */
static void convert_contig(const tiff_layout *L, const uint8_t *src,
                           uint8_t *out, size_t n)
{
    size_t i;
    int c;
    if (L->bps == 8 && L->spp == L->channels && !L->palette &&
        L->photo != PHOTOMETRIC_MINISWHITE) {
        memcpy(out, src, n * (size_t)L->channels);
        return;
    }
    if (L->spp == 1 && L->bps <= 8) {
        convert_packed(L, src, out, n);
        return;
    }
    for (i = 0; i < n; i++) {
        size_t j = i * L->spp;
        uint8_t *o = out + i * (size_t)L->channels;
        if (L->palette) {
            unsigned k = sample_at(src, j, L->bps);
            for (c = 0; c < L->channels; c++)
                o[c] = L->map[c][k];
        } else {
            for (c = 0; c < L->ncol; c++)
                o[c] = sample8(L, sample_at(src, j + (size_t)c, L->bps));
        }
        if (L->alpha) {
            unsigned a = sample_at(src, j + (size_t)L->ncol, L->bps);
            a = L->bps == 16 ? scale16(a) : L->bps == 8 ? a : L->lut[a];
            if (L->photo == PHOTOMETRIC_MINISWHITE && L->bps < 8)
                a = 255u - a;
            for (c = 0; c < L->channels; c++)
                o[c] = over_white(o[c], a, L->alpha == 2);
        }
    }
}

/* One row of n samples of plane p (planar separate) into out. */
static void convert_plane(const tiff_layout *L, int p, const uint8_t *src,
                          uint8_t *out, size_t n)
{
    size_t i;
    int c, ch = L->channels;
    for (i = 0; i < n; i++) {
        unsigned v = sample_at(src, i, L->bps);
        uint8_t *o = out + i * (size_t)ch;
        if (p < L->ncol) {
            if (L->palette)
                for (c = 0; c < ch; c++)
                    o[c] = L->map[c][v & 255u];
            else
                o[p] = sample8(L, v);
            continue;
        }
        v = L->bps == 16 ? scale16(v) : L->bps == 8 ? v : (255u * v) /
                                                              ((1u << L->bps) - 1);
        for (c = 0; c < ch; c++)
            o[c] = over_white(o[c], v, L->alpha == 2);
    }
}

/* Geometry of the blocks (strips or tiles) of the directory. */
typedef struct tiff_blocks {
    int tiled;
    uint32_t bw, bh;   /* block size in pixels (strips: w x rows per strip) */
    tmsize_t rowbytes; /* bytes per block row */
    tmsize_t size;     /* bytes per decoded block */
} tiff_blocks;

static int blocks_get(TIFF *tif, const tiff_layout *L, tiff_blocks *B,
                      const char *path, td_ctx *cx)
{
    memset(B, 0, sizeof *B);
    B->tiled = TIFFIsTiled(tif);
    if (B->tiled) {
        if (!TIFFGetField(tif, TIFFTAG_TILEWIDTH, &B->bw) ||
            !TIFFGetField(tif, TIFFTAG_TILELENGTH, &B->bh))
            return td_seterr(cx, TD_EFORMAT, "%s: tiled TIFF without tile "
                             "size", path);
        B->rowbytes = TIFFTileRowSize(tif);
        B->size = TIFFTileSize(tif);
    } else {
        uint32_t rps = L->h;
        TIFFGetFieldDefaulted(tif, TIFFTAG_ROWSPERSTRIP, &rps);
        B->bw = L->w;
        B->bh = rps == 0 || rps > L->h ? L->h : rps;
        B->rowbytes = TIFFScanlineSize(tif);
        B->size = TIFFStripSize(tif);
    }
    if (B->bw == 0 || B->bh == 0 || B->rowbytes <= 0 || B->size <= 0 ||
        B->size / B->rowbytes < (tmsize_t)B->bh)
        return td_seterr(cx, TD_EFORMAT, "%s: inconsistent TIFF block "
                         "layout", path);
    return 0;
}

/* Copy the rows of decoded block (x0,y0) of plane p in buf into im. */
static void put_block(const tiff_layout *L, const tiff_blocks *B, uint32_t x0,
                      uint32_t y0, int p, const uint8_t *buf, td_image *im)
{
    uint32_t r, rows = B->bh, cols = B->bw;
    if (y0 + rows > L->h)
        rows = L->h - y0;
    if (x0 + cols > L->w)
        cols = L->w - x0;
    for (r = 0; r < rows; r++) {
        const uint8_t *src = buf + (size_t)r * (size_t)B->rowbytes;
        uint8_t *dst = im->data + (size_t)(y0 + r) * im->stride +
                       (size_t)x0 * (size_t)im->channels;
        if (L->planar == PLANARCONFIG_SEPARATE)
            convert_plane(L, p, src, dst, cols);
        else
            convert_contig(L, src, dst, cols);
    }
}

/* The index of block (x0,y0) of plane p. */
static uint32_t block_index(TIFF *tif, const tiff_blocks *B, uint32_t x0,
                            uint32_t y0, int p)
{
    return B->tiled ? TIFFComputeTile(tif, x0, y0, 0, (uint16_t)p)
                    : TIFFComputeStrip(tif, y0, (uint16_t)p);
}

/* Decode block (x0,y0) of plane p through libtiff into buf and copy its
 * rows into im. */
static int read_block(TIFF *tif, const tiff_layout *L, const tiff_blocks *B,
                      uint32_t x0, uint32_t y0, int p, uint8_t *buf,
                      td_image *im)
{
    tmsize_t got;
    uint32_t i = block_index(tif, B, x0, y0, p);
    if (B->tiled)
        got = TIFFReadEncodedTile(tif, i, buf, B->size);
    else
        got = TIFFReadEncodedStrip(tif, i, buf, B->size);
    if (got < 0)
        return -1;
    put_block(L, B, x0, y0, p, buf, im);
    return 0;
}

/* ---- Deflate blocks on threads ------------------------------------------
 * 8-bit samples, Deflate (zlib streams), no predictor or the horizontal
 * one, bytes in file order as they are (8 bits: no swapping): blocks are
 * read raw in order, BATCH at a time, then inflated (libdeflate), the
 * predictor undone and the rows converted on threads (in file order when
 * an alpha plane blends the colour planes).  A block libdeflate
 * refuses goes through libtiff after the batch, so its error (or its
 * tolerance) is libtiff's: the same pixels and messages as the plain path
 * (test_tiff_deflate_threads). */

#define BATCH 64

typedef struct raw_slot {
    uint8_t *raw;
    size_t cap, n;
    uint32_t x0, y0;
    int p, ok;
} raw_slot;

static int deflate_fast(TIFF *tif, const tiff_layout *L)
{
    uint16_t comp = 0, pred = 1, fill = FILLORDER_MSB2LSB;
    TIFFGetFieldDefaulted(tif, TIFFTAG_COMPRESSION, &comp);
    TIFFGetFieldDefaulted(tif, TIFFTAG_PREDICTOR, &pred);
    TIFFGetFieldDefaulted(tif, TIFFTAG_FILLORDER, &fill);
    return (comp == COMPRESSION_ADOBE_DEFLATE ||
            comp == COMPRESSION_DEFLATE) &&
           (pred == 1 || pred == 2) && L->bps == 8 &&
           fill == FILLORDER_MSB2LSB;
}

/* Inflate slot s into buf (want bytes), undo the predictor; 0 or -1. */
static int inflate_slot(const raw_slot *s, uint8_t *buf, size_t want,
                        const tiff_layout *L, const tiff_blocks *B, int pred)
{
    static __thread struct libdeflate_decompressor *z;
    size_t got = 0, r, i, step;
    if (!z && !(z = libdeflate_alloc_decompressor()))
        return -1;
    if (libdeflate_zlib_decompress(z, s->raw, s->n, buf, want, &got) !=
            LIBDEFLATE_SUCCESS || got != want)
        return -1;
    if (pred != 2)
        return 0;
    step = L->planar == PLANARCONFIG_SEPARATE ? 1 : L->spp;
    for (r = 0; r < want / (size_t)B->rowbytes; r++) {
        uint8_t *row = buf + r * (size_t)B->rowbytes;
        for (i = step; i < (size_t)B->rowbytes; i++)
            row[i] = (uint8_t)(row[i] + row[i - step]);
    }
    return 0;
}

/* The decoded size of block (x0, y0): a tile's, or the strip's rows. */
static size_t block_bytes(const tiff_blocks *B, uint32_t y0, uint32_t h)
{
    uint32_t rows = B->bh;
    if (B->tiled)
        return (size_t)B->size;
    if (y0 + rows > h)
        rows = h - y0;
    return (size_t)rows * (size_t)B->rowbytes;
}

static int read_pixels_deflate(TIFF *tif, const tiff_layout *L,
                               const tiff_blocks *B, td_image *im, int np,
                               const char *path, td_tiff_err *e, td_ctx *cx)
{
    raw_slot slot[BATCH];
    uint8_t *dec = NULL, *one = NULL;
    uint16_t pred = 1;
    /* separate planes with alpha: the alpha plane blends the colour the
     * other planes wrote, so blocks are put in file order */
    int ordered = L->planar == PLANARCONFIG_SEPARATE && L->alpha;
    uint32_t x = 0, y = 0;
    int p = 0, n, k, rc = 0, done = 0;
    TIFFGetFieldDefaulted(tif, TIFFTAG_PREDICTOR, &pred);
    memset(slot, 0, sizeof slot);
    if (!(dec = td_malloc((size_t)BATCH * (size_t)B->size, cx)) ||
        !(one = td_malloc((size_t)B->size, cx))) {
        rc = TD_ENOMEM;
        goto done;
    }
    while (!done && rc == 0) {
        for (n = 0; n < BATCH && !done; n++) { /* read raw, in file order */
            raw_slot *s = &slot[n];
            uint32_t i = block_index(tif, B, x, y, p);
            uint64_t bc = TIFFGetStrileByteCount(tif, i);
            tmsize_t got;
            s->x0 = x, s->y0 = y, s->p = p, s->ok = 0, s->n = 0;
            if (bc > 2 * (uint64_t)B->size + (1u << 20))
                bc = 0; /* more than Deflate ever needs: libtiff judges it */
            if (bc > 0 && bc > s->cap) {
                uint8_t *v = realloc(s->raw, (size_t)bc);
                if (!v) {
                    rc = td_seterr(cx, TD_ENOMEM, "%s: out of memory", path);
                    break;
                }
                s->raw = v, s->cap = (size_t)bc;
            }
            if (bc > 0 && bc <= s->cap) {
                got = B->tiled ? TIFFReadRawTile(tif, i, s->raw, (tmsize_t)bc)
                               : TIFFReadRawStrip(tif, i, s->raw, (tmsize_t)bc);
                s->ok = got == (tmsize_t)bc;
                s->n = s->ok ? (size_t)bc : 0;
            }
            if ((x += B->bw) >= L->w) {
                x = 0;
                if ((y += B->bh) >= L->h)
                    y = 0, done = ++p >= np;
            }
        }
        if (rc != 0)
            break;
#pragma omp parallel for schedule(dynamic, 1)
        for (k = 0; k < n; k++) {
            raw_slot *s = &slot[k];
            uint8_t *buf = dec + (size_t)k * (size_t)B->size;
            if (s->ok)
                s->ok = inflate_slot(s, buf,
                                     block_bytes(B, s->y0, L->h), L, B,
                                     pred) == 0;
            if (s->ok && !ordered)
                put_block(L, B, s->x0, s->y0, s->p, buf, im);
        }
        for (k = 0; ordered && k < n; k++) /* the alpha plane after the rest */
            if (slot[k].ok)
                put_block(L, B, slot[k].x0, slot[k].y0, slot[k].p,
                          dec + (size_t)k * (size_t)B->size, im);
        for (k = 0; k < n && rc == 0; k++) /* what libdeflate refused */
            if (!slot[k].ok && read_block(tif, L, B, slot[k].x0, slot[k].y0,
                                          slot[k].p, one, im) != 0)
                rc = td_tiff_fail(cx, TD_EFORMAT, path,
                                  "corrupt or truncated image data", e);
        if (rc == 0)
            rc = td_progress(cx, "read",
                             done ? 1.0
                                  : ((double)p + (double)y / L->h) / np);
    }
done:
    for (k = 0; k < BATCH; k++)
        free(slot[k].raw);
    free(dec);
    free(one);
    return rc;
}

/* Read every block of every needed plane into im. */
static int read_pixels(TIFF *tif, const tiff_layout *L, td_image *im,
                       const char *path, td_tiff_err *e, td_ctx *cx)
{
    tiff_blocks B;
    uint8_t *buf = NULL;
    uint32_t x, y;
    int p, np = 1, rc;
    if ((rc = blocks_get(tif, L, &B, path, cx)) != 0)
        return rc;
    if (L->planar == PLANARCONFIG_SEPARATE)
        np = L->alpha ? L->ncol + 1 : L->ncol;
    if (deflate_fast(tif, L))
        return read_pixels_deflate(tif, L, &B, im, np, path, e, cx);
    buf = td_calloc((size_t)B.size, 1, cx);
    if (!buf)
        return TD_ENOMEM;
    for (p = 0; p < np; p++) {
        for (y = 0; y < L->h; y += B.bh) {
            for (x = 0; x < L->w; x += B.bw) {
                if (read_block(tif, L, &B, x, y, p, buf, im) != 0) {
                    rc = td_tiff_fail(cx, TD_EFORMAT, path,
                                      "corrupt or truncated image data", e);
                    goto fail;
                }
            }
            rc = td_progress(cx, "read", ((double)p + (double)y / L->h) / np);
            if (rc != 0)
                goto fail;
        }
    }
    rc = 0;
fail:
    free(buf);
    return rc;
}


/* Open path and read its first directory's layout (and georef); on
 * success *tifp holds the open handle. */
static int open_layout(const char *path, tiff_layout *L, td_georef *georef,
                       td_tiff_err *e, TIFF **tifp, td_ctx *cx)
{
    int rc;
    TIFF *tif = td_tiff_open(path, -1, "rm", e);
    *tifp = NULL;
    if (!tif)
        return td_tiff_fail(cx, TD_EFORMAT, path, "corrupt or truncated TIFF",
                            e);
    if ((rc = layout_get(tif, L, path, cx)) != 0)
        goto fail;
    if (georef && (rc = td_georef_from_tiff(tif, georef, cx)) != 0)
        goto fail;
    *tifp = tif;
    return 0;
fail:
    TIFFClose(tif);
    return rc;
}

/* See io_int.h. */
int td_tiff_info(const char *path, int *w, int *h, int *channels,
                 td_georef *georef, td_ctx *cx)
{
    td_tiff_err e = {{0}, 0};
    tiff_layout *L = td_malloc(sizeof *L, cx);
    TIFF *tif;
    int rc = TD_ENOMEM;
    if (!L)
        return rc;
    if ((rc = open_layout(path, L, georef, &e, &tif, cx)) != 0)
        goto fail;
    *w = (int)L->w;
    *h = (int)L->h;
    *channels = L->channels;
    TIFFClose(tif);
    rc = 0;
fail:
    free(L);
    return rc;
}

/* See io_int.h.  The georef is filled only on success. */
int td_tiff_read(const char *path, td_image **out, td_georef *georef,
                 td_ctx *cx)
{
    td_tiff_err e = {{0}, 0};
    tiff_layout *L = td_malloc(sizeof *L, cx);
    td_image *im = NULL;
    TIFF *tif = NULL;
    td_georef g;
    int rc = TD_ENOMEM;
    td_georef_init(&g);
    if (!L)
        return rc;
    if ((rc = open_layout(path, L, georef ? &g : NULL, &e, &tif, cx)) != 0 ||
        (rc = td_tiff_check_data(tif, path, cx)) != 0)
        goto fail;
    im = td_image_new((int)L->w, (int)L->h, L->channels, cx);
    if (!im) {
        rc = cx && cx->code ? cx->code : TD_ENOMEM;
        goto fail;
    }
    im->src_bits = L->bps;
    if ((rc = read_pixels(tif, L, im, path, &e, cx)) != 0)
        goto fail;
    TIFFClose(tif);
    free(L);
    if (georef)
        *georef = g; /* initialised by the caller; ownership moves */
    *out = im;
    return 0;
fail:
    if (tif)
        TIFFClose(tif);
    td_image_free(im);
    td_georef_clear(&g);
    free(L);
    return rc;
}

/* A grid to write: w x h elements of `bytes` bytes (1: uint8, 4: float32)
 * with rows `stride` elements apart. */
typedef struct tiff_out {
    const uint8_t *data;
    size_t stride;
    int w, h, bytes;
    double fill;     /* value for the padding of edge tiles */
    int has_nodata;
    double nodata;
} tiff_out;

static TIFFFieldInfo nodata_field[] = {
    {42113, -1, -1, TIFF_ASCII, FIELD_CUSTOM, 1, 0, "GDALNoDataValue"}};

/* Baseline tags, compression and the GDAL_NODATA tag. */
static int set_raster_tags(TIFF *tif, const tiff_out *d, int tiled,
                           uint32_t rps)
{
    int ok = 1;
    ok &= TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, (uint32_t)d->w);
    ok &= TIFFSetField(tif, TIFFTAG_IMAGELENGTH, (uint32_t)d->h);
    ok &= TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, 1);
    ok &= TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, 8 * d->bytes);
    ok &= TIFFSetField(tif, TIFFTAG_SAMPLEFORMAT,
                       d->bytes == 4 ? SAMPLEFORMAT_IEEEFP : SAMPLEFORMAT_UINT);
    ok &= TIFFSetField(tif, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
    ok &= TIFFSetField(tif, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
    ok &= TIFFSetField(tif, TIFFTAG_COMPRESSION, COMPRESSION_ADOBE_DEFLATE);
    /* level 1: a 10000 x 10000 float32 DEM writes in 5.6 s instead of
     * 13.0 s at zlib's default level 6, the file 7 % larger (measured) */
    ok &= TIFFSetField(tif, TIFFTAG_ZIPQUALITY, 1);
    ok &= TIFFSetField(tif, TIFFTAG_PREDICTOR,
                       d->bytes == 4 ? PREDICTOR_FLOATINGPOINT
                                     : PREDICTOR_HORIZONTAL);
    if (tiled) {
        ok &= TIFFSetField(tif, TIFFTAG_TILEWIDTH, 256);
        ok &= TIFFSetField(tif, TIFFTAG_TILELENGTH, 256);
    } else {
        ok &= TIFFSetField(tif, TIFFTAG_ROWSPERSTRIP, rps);
    }
    if (d->has_nodata) {
        char s[64];
        if (isnan(d->nodata))
            snprintf(s, sizeof s, "nan");
        else
            snprintf(s, sizeof s, "%.9g", d->nodata);
        ok &= TIFFMergeFieldInfo(tif, nodata_field, 1) == 0;
        ok &= TIFFSetField(tif, 42113, s);
    }
    return ok ? 0 : -1;
}

/* Copy the block at (x0,y0) of bw x bh into buf, padding outside the grid. */
static void fill_block(const tiff_out *d, uint8_t *buf, int x0, int y0,
                       int bw, int bh)
{
    int r, x;
    size_t eb = (size_t)d->bytes;
    int cols = d->w - x0 < bw ? d->w - x0 : bw;
    for (r = 0; r < bh; r++) {
        uint8_t *o = buf + (size_t)r * (size_t)bw * eb;
        int y = y0 + r;
        if (y < d->h) {
            memcpy(o, d->data + ((size_t)y * d->stride + (size_t)x0) * eb,
                   (size_t)cols * eb);
            x = cols;
        } else {
            x = 0;
        }
        for (; x < bw; x++) {
            if (eb == 4) {
                float f = (float)d->fill;
                memcpy(o + (size_t)x * 4, &f, 4);
            } else {
                o[x] = (uint8_t)d->fill;
            }
        }
    }
}

/* The TIFF predictor of one row of n elements in place: floating point
 * (TIFF Technical Note 3, as libtiff's fpDiff: the bytes of each float
 * regrouped most significant first, one plane after another, then each
 * byte minus the one before it) for 4-byte elements, horizontal
 * differencing for bytes.  tmp: room for the row. */
static void predict_row(uint8_t *row, int n, int bytes, uint8_t *tmp)
{
    size_t i, cc = (size_t)n * (size_t)bytes;
    if (bytes == 4) {
        memcpy(tmp, row, cc);
        for (i = 0; i < (size_t)n; i++) { /* little-endian host: byte b of
                                             a float is plane 3 - b */
            row[3 * (size_t)n + i] = tmp[4 * i];
            row[2 * (size_t)n + i] = tmp[4 * i + 1];
            row[(size_t)n + i] = tmp[4 * i + 2];
            row[i] = tmp[4 * i + 3];
        }
    }
    for (i = cc; i-- > 1;)
        row[i] = (uint8_t)(row[i] - row[i - 1]);
}

/* One row of tiles (tile row ty) encoded on threads: each tile copied,
 * predicted and Deflate-compressed (libdeflate, zlib format, level 1)
 * into out[t] (out_n[t] bytes).  The bytes depend only on the tile, not
 * on the thread count.  0, or -1 (a tile that does not compress into its
 * bound: cannot happen). */
static int encode_tile_row(const tiff_out *d, int ty, int nt, int bw,
                           int bh, uint8_t *raw, uint8_t *tmp, uint8_t **out,
                           size_t *out_n, size_t bound)
{
    size_t tb = (size_t)bw * (size_t)bh * (size_t)d->bytes;
    int t, bad = 0;
#pragma omp parallel for schedule(dynamic, 1) reduction(| : bad)
    for (t = 0; t < nt; t++) {
        static __thread struct libdeflate_compressor *z;
        uint8_t *b = raw + (size_t)t * tb;
        int r;
        if (!z && !(z = libdeflate_alloc_compressor(1))) {
            bad = 1;
            continue;
        }
        fill_block(d, b, t * bw, ty * bh, bw, bh);
        for (r = 0; r < bh; r++)
            predict_row(b + (size_t)r * bw * d->bytes, bw, d->bytes,
                        tmp + (size_t)t * (size_t)bw * d->bytes);
        out_n[t] = libdeflate_zlib_compress(z, b, tb, out[t], bound);
        bad |= out_n[t] == 0;
    }
    return bad ? -1 : 0;
}

/* Every tile, a row of them at a time compressed on threads and written
 * in order (TIFFWriteRawTile). */
static int write_tiles(TIFF *tif, const tiff_out *d, int bw, int bh,
                       td_ctx *cx)
{
    int nx = (d->w + bw - 1) / bw, ny = (d->h + bh - 1) / bh, tx, ty, rc = 0;
    size_t tb = (size_t)bw * (size_t)bh * (size_t)d->bytes;
    size_t bound = tb + tb / 8 + 1024, *out_n = NULL;
    uint8_t *raw = NULL, *tmp = NULL, **out = NULL;
    if (!(raw = td_malloc((size_t)nx * tb, cx)) ||
        !(tmp = td_malloc((size_t)nx * (size_t)bw * (size_t)d->bytes, cx)) ||
        !(out = td_calloc((size_t)nx, sizeof *out, cx)) ||
        !(out_n = td_calloc((size_t)nx, sizeof *out_n, cx))) {
        rc = TD_ENOMEM;
        goto done;
    }
    for (tx = 0; tx < nx; tx++)
        if (!(out[tx] = td_malloc(bound, cx))) {
            rc = TD_ENOMEM;
            goto done;
        }
    for (ty = 0; ty < ny && rc == 0; ty++) {
        if (encode_tile_row(d, ty, nx, bw, bh, raw, tmp, out, out_n, bound)) {
            rc = td_seterr(cx, TD_ENOMEM, "cannot compress a tile");
            break;
        }
        for (tx = 0; tx < nx && rc == 0; tx++)
            if (TIFFWriteRawTile(tif, TIFFComputeTile(tif, (uint32_t)(tx * bw),
                                                      (uint32_t)(ty * bh), 0, 0),
                                 out[tx], (tmsize_t)out_n[tx]) < 0)
                rc = -1;
        if (rc == 0)
            rc = td_progress(cx, "write", (double)(ty + 1) / ny);
    }
done:
    for (tx = 0; out && tx < nx; tx++)
        free(out[tx]);
    free(out), free(out_n), free(raw), free(tmp);
    return rc;
}

/* Encode every strip (small grids; libtiff compresses) or tile (ours). */
static int write_blocks(TIFF *tif, const tiff_out *d, int tiled, int bw,
                        int bh, uint8_t *buf, td_ctx *cx)
{
    int x, y, rc;
    if (tiled)
        return write_tiles(tif, d, bw, bh, cx);
    for (y = 0; y < d->h; y += bh) {
        int rows = d->h - y > bh ? bh : d->h - y;
        for (x = 0; x < d->w; x += bw) {
            tmsize_t n = (tmsize_t)bw * rows * d->bytes;
            fill_block(d, buf, x, y, bw, rows);
            if (TIFFWriteEncodedStrip(tif, TIFFComputeStrip(tif, y, 0), buf,
                                      n) < 0)
                return -1;
        }
        if ((rc = td_progress(cx, "write", (double)(y + rows) / d->h)) != 0)
            return rc;
    }
    return 0;
}

/* Write d as a one-band Deflate GeoTIFF at path, atomically. */
static int geotiff_write(const char *path, const tiff_out *d,
                         const td_georef *georef, td_ctx *cx)
{
    td_tiff_err e = {{0}, 0};
    char *tmp = NULL;
    size_t tmpsize = strlen(path) + 32;
    FILE *f = NULL;
    TIFF *tif = NULL;
    uint8_t *buf = NULL;
    int rc, tiled = d->w > 1024 || d->h > 1024, bw, bh, fd;
    int big = (double)d->w * d->h * d->bytes > 2e9;
    if ((rc = td_check_dims(d->w, d->h, path, cx)) != 0)
        return rc;
    if (!(tmp = td_malloc(tmpsize, cx)))
        return TD_ENOMEM;
    if (!(f = td_atomic_open(path, tmp, tmpsize, cx))) {
        rc = cx && cx->code ? cx->code : TD_EIO;
        goto fail;
    }
    bw = tiled ? 256 : d->w;
    bh = tiled ? 256 : (int)(262144 / ((size_t)d->w * d->bytes));
    if (!tiled)
        bh = bh < 1 ? 1 : bh > d->h ? d->h : bh;
    rc = TD_ENOMEM;
    if (!(buf = td_malloc((size_t)bw * (size_t)bh * (size_t)d->bytes, cx)))
        goto fail;
    rc = TD_EIO;
    fd = dup(fileno(f));
    tif = fd < 0 ? NULL : td_tiff_open(path, fd, big ? "w8" : "w", &e);
    if (!tif) {
        td_tiff_fail(cx, rc, path, "cannot write TIFF", &e);
        goto fail;
    }
    if (set_raster_tags(tif, d, tiled, (uint32_t)bh) != 0 ||
        td_georef_to_tiff(tif, georef, cx) != 0 ||
        (rc = write_blocks(tif, d, tiled, bw, bh, buf, cx)) != 0 ||
        !TIFFWriteDirectory(tif) || e.count) {
        rc = rc ? rc : TD_EIO;
        td_tiff_fail(cx, rc, path, "cannot write TIFF", &e);
        goto fail;
    }
    TIFFClose(tif);
    tif = NULL;
    rc = e.count ? td_tiff_fail(cx, TD_EIO, path, "cannot write TIFF", &e)
                 : td_atomic_commit(f, tmp, path, cx);
    f = NULL;
    if (rc != 0)
        remove(tmp);
fail:
    if (tif)
        TIFFClose(tif);
    if (f)
        td_atomic_abort(f, tmp);
    free(buf);
    free(tmp);
    return rc;
}

/* See imageio.h.  NaN cells are written as NaN; edge tiles are padded
 * with the nodata value. */
int td_geotiff_write_f32(const char *path, const td_grid_f32 *g,
                         const td_georef *georef, td_ctx *cx)
{
    tiff_out d;
    if (!path || !g || !g->data || g->stride < (size_t)g->w)
        return td_seterr(cx, TD_EINVAL, "%s: nothing to write",
                         path ? path : "(null)");
    d.data = (const uint8_t *)g->data;
    d.stride = g->stride;
    d.w = g->w;
    d.h = g->h;
    d.bytes = 4;
    d.has_nodata = g->has_nodata;
    d.nodata = g->nodata;
    d.fill = g->has_nodata ? g->nodata : 0.0;
    return geotiff_write(path, &d, georef, cx);
}

/* See imageio.h. */
int td_geotiff_write_u8(const char *path, const td_grid_u8 *g,
                        const td_georef *georef, td_ctx *cx)
{
    tiff_out d;
    if (!path || !g || !g->data || g->stride < (size_t)g->w)
        return td_seterr(cx, TD_EINVAL, "%s: nothing to write",
                         path ? path : "(null)");
    d.data = g->data;
    d.stride = g->stride;
    d.w = g->w;
    d.h = g->h;
    d.bytes = 1;
    d.has_nodata = 0;
    d.nodata = 0.0;
    d.fill = 0.0;
    return geotiff_write(path, &d, georef, cx);
}
