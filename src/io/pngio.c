/* pngio.c: PNG reading (any bit depth, colour type and interlacing, into
 * 8-bit grey or RGB) and writing (8-bit grey/RGB, 16-bit grey) through
 * libpng; 8-bit grey and RGB without interlace are read through libdeflate
 * instead (png_fast, below: twice as fast on a colour scan), anything that
 * path does not take going to libpng.  libpng reports errors by longjmp; each
 * setjmp lives in a small static function whose resources are owned by a struct
 * in the caller's frame, so nothing it touches is an indeterminate local after
 * a jump. */
#include "src/io/io_int.h"

#include <errno.h>
#include <libdeflate.h>
#include <png.h>
#include <sched.h>
#include <setjmp.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#ifdef _OPENMP
#include <omp.h>
#else
#define omp_get_num_threads() 1
#define omp_get_thread_num() 0
#endif

/* Error sink of one libpng handle. */
typedef struct pio_err {
    jmp_buf jb;
    char msg[256];
} pio_err;

static void on_png_error(png_structp png, png_const_charp msg)
{
    pio_err *e = png_get_error_ptr(png);
    snprintf(e->msg, sizeof e->msg, "%s", msg ? msg : "libpng error");
    longjmp(e->jb, 1);
}

static void on_png_warning(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg; /* dropped: never printed */
}

/* Everything one PNG read owns. */
typedef struct pio_job {
    const char *path;
    FILE *f;
    png_structp png;
    png_infop info;
    pio_err err;
    td_image *im;
    uint8_t *buf;        /* one transformed row, or the whole image */
    int header_only;
    int w, h, channels;  /* output */
    int tchan;           /* channels after libpng's transforms */
    int palette, grey_palette;
    uint8_t plte[256][3], trns[256];
} pio_job;

/* Palette, its transparency, and whether it is all grey. */
static void load_palette(pio_job *j)
{
    png_colorp pal = NULL;
    png_bytep ta = NULL;
    int n = 0, nt = 0, i;
    memset(j->plte, 0, sizeof j->plte);
    memset(j->trns, 255, sizeof j->trns);
    png_get_PLTE(j->png, j->info, &pal, &n);
    if (png_get_valid(j->png, j->info, PNG_INFO_tRNS))
        png_get_tRNS(j->png, j->info, &ta, &nt, NULL);
    j->grey_palette = 1;
    for (i = 0; i < n && i < 256; i++) {
        j->plte[i][0] = pal[i].red;
        j->plte[i][1] = pal[i].green;
        j->plte[i][2] = pal[i].blue;
        if (pal[i].red != pal[i].green || pal[i].red != pal[i].blue)
            j->grey_palette = 0;
    }
    for (i = 0; ta && i < nt && i < 256; i++)
        j->trns[i] = ta[i];
}

/* Header, limits and transforms (to 8-bit G, GA, RGB, RGBA or indices). */
static void setup_transforms(pio_job *j)
{
    png_uint_32 w, h;
    int depth, ctype;
    /* libpng's own limit (1e6) is below TD_MAX_DIM: let td_check_dims
     * decide, with its clearer message */
    png_set_user_limits(j->png, 0x7fffffff, 0x7fffffff);
    png_set_chunk_cache_max(j->png, 1000);
    png_set_chunk_malloc_max(j->png, 64u << 20);
    png_read_info(j->png, j->info);
    png_get_IHDR(j->png, j->info, &w, &h, &depth, &ctype, NULL, NULL, NULL);
    j->w = (int)w;
    j->h = (int)h;
    j->palette = ctype == PNG_COLOR_TYPE_PALETTE;
    if (j->palette) {
        load_palette(j);
        png_set_packing(j->png);
        j->channels = j->grey_palette ? 1 : 3;
    } else {
        if (depth < 8)
            png_set_expand_gray_1_2_4_to_8(j->png);
        if (png_get_valid(j->png, j->info, PNG_INFO_tRNS))
            png_set_tRNS_to_alpha(j->png);
        if (depth == 16)
            png_set_scale_16(j->png);
        j->channels = ctype & PNG_COLOR_MASK_COLOR ? 3 : 1;
    }
}

static uint8_t over_white(unsigned c, unsigned a)
{
    return (uint8_t)((c * a + 255u * (255u - a) + 127u) / 255u);
}

/* One transformed row into 8-bit grey or RGB. */
static void convert_row(const pio_job *j, const uint8_t *src, uint8_t *out)
{
    int x, c, ch = j->channels, tc = j->tchan;
    int alpha = !j->palette && (tc == 2 || tc == 4);
    if (!j->palette && tc == ch) {
        memcpy(out, src, (size_t)j->w * (size_t)ch);
        return;
    }
    for (x = 0; x < j->w; x++, out += ch) {
        if (j->palette) {
            unsigned a = j->trns[src[x]];
            for (c = 0; c < ch; c++)
                out[c] = over_white(j->plte[src[x]][c], a);
        } else {
            const uint8_t *s = src + (size_t)x * (size_t)tc;
            for (c = 0; c < ch; c++)
                out[c] = alpha ? over_white(s[c], s[tc - 1]) : s[c];
        }
    }
}

/* Interlaced input, or rows needing no conversion: decode every pass
 * straight into the image when the layouts match, else into a whole-image
 * buffer converted at the end (the only case that buffers the image). */
static void read_rows(pio_job *j, int passes)
{
    size_t rb = png_get_rowbytes(j->png, j->info), total;
    int direct = !j->palette && j->tchan == j->channels, p, y;
    if (direct) {
        for (p = 0; p < passes; p++)
            for (y = 0; y < j->h; y++)
                png_read_row(j->png, j->im->data + (size_t)y * j->im->stride,
                             NULL);
        return;
    }
    if (td_mul2(rb, (size_t)j->h, &total) != 0)
        png_error(j->png, "image too large");
    j->buf = calloc(total ? total : 1, 1);
    if (!j->buf)
        png_error(j->png, "out of memory");
    for (p = 0; p < passes; p++)
        for (y = 0; y < j->h; y++)
            png_read_row(j->png, j->buf + (size_t)y * rb, NULL);
    for (y = 0; y < j->h; y++)
        convert_row(j, j->buf + (size_t)y * rb,
                    j->im->data + (size_t)y * j->im->stride);
}

/* Non-interlaced, converted rows: read and convert one at a time. */
static void read_rows_streamed(pio_job *j)
{
    int y;
    j->buf = calloc(png_get_rowbytes(j->png, j->info) + 1, 1);
    if (!j->buf)
        png_error(j->png, "out of memory");
    for (y = 0; y < j->h; y++) {
        png_read_row(j->png, j->buf, NULL);
        convert_row(j, j->buf, j->im->data + (size_t)y * j->im->stride);
    }
}

/* The part of a read that libpng may jump out of; returns 0, 1 after a
 * libpng error (message in j->err), or a TD_E* code set in cx. */
static int pio_decode(pio_job *j, td_ctx *cx)
{
    int passes, rc;
    if (setjmp(j->err.jb))
        return 1;
    png_init_io(j->png, j->f);
    setup_transforms(j);
    if ((rc = td_check_dims(j->w, j->h, j->path, cx)) != 0)
        return rc;
    passes = png_set_interlace_handling(j->png);
    png_read_update_info(j->png, j->info);
    j->tchan = png_get_channels(j->png, j->info);
    if (j->header_only)
        return 0;
    { /* deflate packs at most 1032:1: a file far smaller than its frame
         is cut short or forged, refused before the frame is allocated */
        struct stat st;
        double raw = (double)j->w * j->h *
                     png_get_channels(j->png, j->info) *
                     png_get_bit_depth(j->png, j->info) / 8.0;
        if (fstat(fileno(j->f), &st) == 0 && raw > 1100.0 * st.st_size + 1e6)
            return td_seterr(cx, TD_EFORMAT,
                             "%s: truncated or corrupt PNG (%d x %d pixels "
                             "claimed in only %lld bytes)",
                             j->path, j->w, j->h, (long long)st.st_size);
    }
    j->im = td_image_new(j->w, j->h, j->channels, cx);
    if (!j->im)
        return cx && cx->code ? cx->code : TD_ENOMEM;
    j->im->src_bits = png_get_bit_depth(j->png, j->info);
    if (passes == 1 && !(!j->palette && j->tchan == j->channels))
        read_rows_streamed(j);
    else
        read_rows(j, passes);
    return 0;
}

/* Open, check the signature, decode; the caller frees j's resources. */
static int pio_run(pio_job *j, td_ctx *cx)
{
    uint8_t sig[8];
    int rc;
    j->f = fopen(j->path, "rb");
    if (!j->f)
        return td_seterr(cx, TD_EIO, "%s: cannot open: %s", j->path,
                         strerror(errno));
    if (fread(sig, 1, 8, j->f) != 8 || png_sig_cmp(sig, 0, 8) != 0)
        return td_seterr(cx, TD_EFORMAT, "%s: not a PNG image", j->path);
    j->png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &j->err,
                                    on_png_error, on_png_warning);
    if (!j->png || !(j->info = png_create_info_struct(j->png)))
        return td_seterr(cx, TD_ENOMEM, "%s: out of memory", j->path);
    png_set_sig_bytes(j->png, 8);
    rc = pio_decode(j, cx);
    if (rc == 1)
        return td_seterr(cx, TD_EFORMAT, "%s: truncated or corrupt PNG (%s)",
                         j->path, j->err.msg);
    return rc;
}

static void pio_job_free(pio_job *j)
{
    if (j->png)
        png_destroy_read_struct(&j->png, j->info ? &j->info : NULL, NULL);
    if (j->f)
        fclose(j->f);
    free(j->buf);
    td_image_free(j->im);
    free(j);
}

/* See io_int.h. */
int td_png_info(const char *path, int *w, int *h, int *channels, td_ctx *cx)
{
    pio_job *j = td_calloc(1, sizeof *j, cx);
    int rc;
    if (!j)
        return TD_ENOMEM;
    j->path = path;
    j->header_only = 1;
    if ((rc = pio_run(j, cx)) != 0)
        goto fail;
    *w = j->w;
    *h = j->h;
    *channels = j->channels;
fail:
    pio_job_free(j);
    return rc;
}

/* ---- 8-bit grey and RGB without interlace, through libdeflate (ours) ----
 *
 * libpng inflates with zlib and undoes the row filters a byte at a time:
 * 1.0 s of the printed 6000 x 6000 colour sheet's 2.4 s scan, on one
 * thread.  For the scanner's own kind of PNG (8 bits, grey or RGB, not
 * interlaced) the file is read whole, its IDAT data inflated at once by
 * libdeflate (which checks the zlib stream's Adler-32) and the filters
 * undone in place, the rows moving down over their filter bytes.
 * Anything else (a palette, alpha, tRNS, 16 or fewer bits, interlace, a
 * chunk libpng would refuse, a bad CRC, data short or long) is left to
 * libpng, which reads it or says what is wrong.  The same pixels
 * (test_png_fast). */
static uint32_t be32(const uint8_t *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 |
           p[3];
}

/* Paeth's predictor without branches (the filter is on nearly every row of
 * a scan, and its choices are as unpredictable as the paper's grain). */
static inline uint8_t paeth(int a, int b, int c)
{
    int pa = abs(b - c), pb = abs(a - c), pc = abs(a + b - 2 * c);
    int bc = pb <= pc ? b : c, ta = (pa <= pb) & (pa <= pc);
    return (uint8_t)(ta ? a : bc);
}

/* Undo filter f of bytes [x0, x1) of one row in place, the row above u
 * (NULL: the first row); 0, or -1 for an unknown filter. */
static int unfilter(int f, uint8_t *o, const uint8_t *u, size_t x0, size_t x1,
                    int bpp)
{
    size_t x = x0, b = (size_t)bpp;
    if (!u && f >= 2 && f <= 4) /* no row above: Up adds 0, Paeth is Sub */
        f = f == 4 ? 1 : f == 2 ? 0 : 5;
    switch (f) {
    case 0:
        return 0;
    case 1:
        for (x = x < b ? b : x; x < x1; x++)
            o[x] = (uint8_t)(o[x] + o[x - b]);
        return 0;
    case 2:
        for (; x < x1; x++)
            o[x] = (uint8_t)(o[x] + u[x]);
        return 0;
    case 3:
        for (; x < x1 && x < b; x++)
            o[x] = (uint8_t)(o[x] + u[x] / 2);
        for (; x < x1; x++)
            o[x] = (uint8_t)(o[x] + (u[x] + o[x - b]) / 2);
        return 0;
    case 4:
        for (; x < x1 && x < b; x++)
            o[x] = (uint8_t)(o[x] + u[x]);
        for (; x < x1; x++)
            o[x] = (uint8_t)(o[x] + paeth(o[x - b], u[x], u[x - b]));
        return 0;
    case 5: /* Average on the first row */
        for (x = x < b ? b : x; x < x1; x++)
            o[x] = (uint8_t)(o[x] + o[x - b] / 2);
        return 0;
    }
    return -1;
}

/* Every row's filter undone in place (rows rb + 1 bytes apart, the filter
 * byte first), then the rows moved down over their filter bytes.  Row y
 * on thread y mod T, UF_CHUNK bytes at a time once the row above is done
 * that far (done[y]: bytes of row y done): the filters chain down the
 * rows, so each thread follows the one above a chunk behind.  The
 * printed 6000 x 6000 colour sheet (96 % of its rows Paeth) took 0.40 s
 * on one thread (measured 2026-12-06, session 34).  0, or -1 for an
 * unknown filter; the same bytes for any thread count. */
#define UF_CHUNK 4096
static int unfilter_rows(uint8_t *raw, size_t rb, size_t h, int bpp, td_ctx *cx)
{
    _Atomic size_t *done = td_malloc((h + 1) * sizeof *done, cx);
    size_t y;
    int bad = 0;
    if (!done)
        return TD_ENOMEM;
    for (y = 0; y < h; y++)
        atomic_init(&done[y], 0);
#pragma omp parallel reduction(| : bad)
    {
        size_t T = (size_t)omp_get_num_threads(), yy, x;
        for (yy = (size_t)omp_get_thread_num(); yy < h; yy += T) {
            uint8_t *o = raw + yy * (rb + 1) + 1;
            const uint8_t *u = yy ? o - (rb + 1) : NULL;
            for (x = 0; x < rb; x += UF_CHUNK) {
                size_t x1 = rb - x < UF_CHUNK ? rb : x + UF_CHUNK;
                int spins = 0;
                while (u && atomic_load_explicit(&done[yy - 1],
                                                 memory_order_acquire) < x1)
                    if (++spins > 64)
                        sched_yield(), spins = 0;
                bad |= unfilter(o[-1], o, u, x, x1, bpp) != 0;
                atomic_store_explicit(&done[yy], x1, memory_order_release);
            }
        }
    }
    free((void *)done);
    if (bad)
        return -1;
    for (y = 0; y < h; y++) /* row y moves y + 1 bytes down */
        memmove(raw + y * rb, raw + y * (rb + 1) + 1, rb);
    return 0;
}

/* 0 with *out read, 1 when libpng should read the file, or TD_ENOMEM. */
static int png_fast(const char *path, td_image **out, td_ctx *cx)
{
    FILE *f = fopen(path, "rb");
    uint8_t *b = NULL, *raw = NULL;
    struct libdeflate_decompressor *z = NULL;
    struct stat st;
    size_t n, p = 8, nz = 0, rb, tot;
    uint32_t w = 0, h = 0;
    int ch = 0, rc = 1, seen_idat = 0, ended = 0, uf;
    td_image *im;
    if (!f)
        return 1;
    if (fstat(fileno(f), &st) != 0 || st.st_size < 45 ||
        (unsigned long long)st.st_size > SIZE_MAX / 2)
        goto done;
    n = (size_t)st.st_size;
    if (!(b = malloc(n)) || fread(b, 1, n, f) != n ||
        memcmp(b, "\211PNG\r\n\032\n", 8) != 0)
        goto done;
    while (!ended && p + 12 <= n) { /* the chunks; IDAT data moved down */
        uint32_t L = be32(b + p);
        const uint8_t *t = b + p + 4;
        if (L > n - p - 12 ||
            libdeflate_crc32(0, t, (size_t)L + 4) != be32(b + p + 8 + L))
            goto done;
        if (p == 8) {
            if (memcmp(t, "IHDR", 4) != 0 || L != 13)
                goto done;
            w = be32(t + 4), h = be32(t + 8);
            /* 8 bits, grey (0) or RGB (2), deflate, filters 0, no
               interlace */
            if (t[12] != 8 || (t[13] != 0 && t[13] != 2) || t[14] || t[15] ||
                t[16])
                goto done;
            ch = t[13] == 2 ? 3 : 1;
        } else if (!memcmp(t, "IDAT", 4)) {
            if (seen_idat == 2)
                goto done; /* IDAT after another chunk: libpng's call */
            seen_idat = 1;
            memmove(b + nz, t + 4, L);
            nz += L;
        } else if (!memcmp(t, "IEND", 4)) {
            ended = 1;
        } else if (!memcmp(t, "tRNS", 4) || !(t[0] & 0x20)) {
            goto done; /* transparency, or another critical chunk */
        } else if (seen_idat) {
            seen_idat = 2;
        }
        p += 12 + (size_t)L;
    }
    if (!ended || !nz || td_check_dims((long)w, (long)h, path, NULL) != 0)
        goto done;
    rb = (size_t)w * (size_t)ch;
    if (td_mul2(rb + 1, (size_t)h, &tot) != 0 ||
        (double)tot > 1100.0 * (double)n + 1e6)
        goto done; /* forged or cut short: libpng says so */
    if (!(raw = malloc(tot)) || !(z = libdeflate_alloc_decompressor())) {
        rc = TD_ENOMEM;
        goto done;
    }
    if (libdeflate_zlib_decompress(z, b, nz, raw, tot, NULL) !=
        LIBDEFLATE_SUCCESS)
        goto done;
    free(b), b = NULL;
    if ((uf = unfilter_rows(raw, rb, h, ch, cx)) != 0) {
        rc = uf == TD_ENOMEM ? TD_ENOMEM : 1;
        goto done;
    }
    if (!(im = calloc(1, sizeof *im))) {
        rc = TD_ENOMEM;
        goto done;
    }
    { /* the filter bytes' room given back */
        uint8_t *s = realloc(raw, rb * (size_t)h);
        im->data = s ? s : raw;
    }
    raw = NULL;
    im->w = (int)w, im->h = (int)h, im->channels = ch;
    im->stride = rb, im->src_bits = 8;
    *out = im;
    rc = 0;
done:
    if (rc == TD_ENOMEM)
        td_seterr(cx, TD_ENOMEM, "%s: out of memory", path);
    if (z)
        libdeflate_free_decompressor(z);
    free(b), free(raw);
    fclose(f);
    return rc;
}

/* See io_int.h. */
int td_png_read(const char *path, td_image **out, td_ctx *cx)
{
    pio_job *j;
    int rc;
    if ((rc = png_fast(path, out, cx)) != 1)
        return rc;
    if (!(j = td_calloc(1, sizeof *j, cx)))
        return TD_ENOMEM;
    j->path = path;
    if ((rc = pio_run(j, cx)) != 0)
        goto fail;
    *out = j->im;
    j->im = NULL;
fail:
    pio_job_free(j);
    return rc;
}

/* Produces row y of a picture to write, in PNG byte order (tmp may be used
 * as scratch of the row's size). */
typedef const uint8_t *(*pio_row_fn)(const void *src, int y, uint8_t *tmp);

typedef struct pio_wjob {
    FILE *f;
    png_structp png;
    png_infop info;
    pio_err err;
    uint8_t *tmp;
    const char *comment; /* a tEXt "Comment" chunk, or NULL */
} pio_wjob;

/* The part of a write libpng may jump out of; 0, or 1 after an error. */
static int pio_encode(pio_wjob *j, int w, int h, int ctype, int depth,
                      pio_row_fn row, const void *src)
{
    int y;
    if (setjmp(j->err.jb))
        return 1;
    png_init_io(j->png, j->f);
    png_set_IHDR(j->png, j->info, (png_uint_32)w, (png_uint_32)h, depth,
                 ctype, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(j->png, 6);
    if (j->comment) {
        png_text t;
        memset(&t, 0, sizeof t);
        t.compression = PNG_TEXT_COMPRESSION_NONE;
        t.key = (png_charp) "Comment";
        t.text = (png_charp)j->comment;
        png_set_text(j->png, j->info, &t, 1);
    }
    png_write_info(j->png, j->info);
    for (y = 0; y < h; y++)
        png_write_row(j->png, row(src, y, j->tmp));
    png_write_end(j->png, j->info);
    return 0;
}

/* Write w x h rows from row() as a PNG at path, atomically. */
static int pio_write_rows(const char *path, int w, int h, int ctype,
                          int depth, pio_row_fn row, const void *src,
                          const char *comment, td_ctx *cx)
{
    pio_wjob j;
    char *tmp = NULL;
    size_t tmpsize = strlen(path) + 32, rowbytes;
    int rc, ch = ctype == PNG_COLOR_TYPE_RGB ? 3 : 1;
    memset(&j, 0, sizeof j);
    j.comment = comment;
    if ((rc = td_check_dims(w, h, path, cx)) != 0)
        return rc;
    rc = TD_ENOMEM;
    if (td_mul3((size_t)w, (size_t)ch, (size_t)depth / 8, &rowbytes) != 0 ||
        !(tmp = td_malloc(tmpsize, cx)) || !(j.tmp = td_malloc(rowbytes, cx)))
        goto fail;
    if (!(j.f = td_atomic_open(path, tmp, tmpsize, cx))) {
        rc = cx && cx->code ? cx->code : TD_EIO;
        goto fail;
    }
    j.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &j.err,
                                    on_png_error, on_png_warning);
    if (!j.png || !(j.info = png_create_info_struct(j.png))) {
        td_seterr(cx, rc, "%s: out of memory", path);
        goto fail;
    }
    if (pio_encode(&j, w, h, ctype, depth, row, src) != 0) {
        rc = td_seterr(cx, TD_EIO, "%s: cannot write PNG (%s)", path,
                       j.err.msg);
        goto fail;
    }
    rc = td_atomic_commit(j.f, tmp, path, cx);
    j.f = NULL;
fail:
    if (j.png)
        png_destroy_write_struct(&j.png, j.info ? &j.info : NULL);
    if (j.f)
        td_atomic_abort(j.f, tmp);
    free(j.tmp);
    free(tmp);
    return rc;
}

static const uint8_t *image_row(const void *src, int y, uint8_t *tmp)
{
    const td_image *im = src;
    (void)tmp;
    return im->data + (size_t)y * im->stride;
}

/* See imageio.h. */
int td_png_write(const char *path, const td_image *im, td_ctx *cx)
{
    if (!path || !im || !im->data || (im->channels != 1 && im->channels != 3) ||
        im->stride < (size_t)im->w * (size_t)im->channels)
        return td_seterr(cx, TD_EINVAL, "%s: no 1- or 3-channel image to "
                         "write", path ? path : "(null)");
    return pio_write_rows(path, im->w, im->h,
                          im->channels == 3 ? PNG_COLOR_TYPE_RGB
                                            : PNG_COLOR_TYPE_GRAY,
                          8, image_row, im, NULL, cx);
}

static const uint8_t *u8_row(const void *src, int y, uint8_t *tmp)
{
    const td_grid_u8 *g = src;
    return g->data + (size_t)y * g->stride;
}

static const uint8_t *u8_row01(const void *src, int y, uint8_t *tmp)
{
    const td_grid_u8 *g = src;
    const uint8_t *s = g->data + (size_t)y * g->stride;
    int x;
    for (x = 0; x < g->w; x++)
        tmp[x] = s[x] ? 255 : 0;
    return tmp;
}

/* See imageio.h. */
int td_png_write_u8(const char *path, const td_grid_u8 *g, int scale01,
                    td_ctx *cx)
{
    if (!path || !g || !g->data || g->stride < (size_t)g->w)
        return td_seterr(cx, TD_EINVAL, "%s: no grid to write",
                         path ? path : "(null)");
    return pio_write_rows(path, g->w, g->h, PNG_COLOR_TYPE_GRAY, 8,
                          scale01 ? u8_row01 : u8_row, g, NULL, cx);
}

static const uint8_t *u16_row(const void *src, int y, uint8_t *tmp)
{
    const td_grid_u16 *g = src;
    const uint16_t *s = g->data + (size_t)y * g->stride;
    int x;
    for (x = 0; x < g->w; x++) {
        tmp[2 * x] = (uint8_t)(s[x] >> 8);
        tmp[2 * x + 1] = (uint8_t)(s[x] & 255);
    }
    return tmp;
}

/* See imageio.h. */
int td_png_write_u16(const char *path, const td_grid_u16 *g,
                     const char *comment, td_ctx *cx)
{
    if (!path || !g || !g->data || g->stride < (size_t)g->w)
        return td_seterr(cx, TD_EINVAL, "%s: no grid to write",
                         path ? path : "(null)");
    return pio_write_rows(path, g->w, g->h, PNG_COLOR_TYPE_GRAY, 16, u16_row,
                          g, comment, cx);
}
