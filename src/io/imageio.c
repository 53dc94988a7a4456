/* imageio.c: the scan reader's front door.  The format is found from the
 * file's first bytes (never its name) and the file handed to the TIFF, PNG
 * or JPEG (libjpeg, src/io/jpegio.c) reader. */
#include "src/io/io_int.h"

#include "src/io/io.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

enum { FMT_PNG = 1, FMT_TIFF, FMT_JPEG };

/* The format of path from its magic bytes, or a TD_E* code set in cx. */
static int sniff(const char *path, td_ctx *cx)
{
    static const uint8_t png[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    uint8_t b[8];
    size_t n;
    FILE *f;
    if (td_check_input(path, cx) != 0)
        return cx ? cx->code : TD_EINVAL;
    f = fopen(path, "rb");
    if (!f)
        return td_seterr(cx, TD_EIO, "%s: cannot open: %s", path,
                         strerror(errno));
    n = fread(b, 1, sizeof b, f);
    fclose(f);
    if (n == 8 && memcmp(b, png, 8) == 0)
        return FMT_PNG;
    if (n >= 4 && ((b[0] == 'I' && b[1] == 'I' && b[3] == 0 &&
                    (b[2] == 42 || b[2] == 43)) ||
                   (b[0] == 'M' && b[1] == 'M' && b[2] == 0 &&
                    (b[3] == 42 || b[3] == 43))))
        return FMT_TIFF;
    if (n >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF)
        return FMT_JPEG;
    if (n == 0)
        return td_seterr(cx, TD_EFORMAT, "%s: empty file", path);
    return td_seterr(cx, TD_EFORMAT, "%s: not a PNG, TIFF or JPEG image",
                     path);
}

/* Whether path (of format fmt) holds colour, from its header alone (PNG:
 * IHDR's colour type; JPEG: the frame's component count; TIFF: the
 * samples per pixel, through libtiff); 0 when unsure. */
static int colour_file(const char *path, int fmt)
{
    uint8_t b[4096];
    size_t n, p = 2;
    FILE *f;
    int ch = 0, w, h;
    if (fmt == FMT_TIFF)
        return td_tiff_info(path, &w, &h, &ch, NULL, NULL) == 0 && ch == 3;
    if (!(f = fopen(path, "rb")))
        return 0;
    n = fread(b, 1, sizeof b, f);
    fclose(f);
    if (fmt == FMT_PNG)
        return n > 25 && (b[25] == 2 || b[25] == 3 || b[25] == 6);
    while (p + 10 <= n && b[p] == 0xFF) { /* JPEG: segments to the frame */
        uint8_t m = b[p + 1];
        if (m >= 0xC0 && m <= 0xCF && m != 0xC4 && m != 0xC8 && m != 0xCC)
            return b[p + 9] == 3;
        p += 2 + ((size_t)b[p + 2] << 8 | b[p + 3]);
    }
    return 0;
}

/* See imageio.h.  On failure *out is left unchanged; georef (when given)
 * is overwritten without being freed (clear it before reuse).  A colour
 * scan is read while OpenCV builds its CIELAB tables for the palette
 * (td_cv_lab_warm_begin): 0.13-0.17 s of one core otherwise. */
int td_image_read(const char *path, td_image **out, td_georef *georef,
                  td_ctx *cx)
{
    int fmt = sniff(path, cx), rc;
    void *warm;
    if (georef)
        td_georef_init(georef);
    if (!out)
        return td_seterr(cx, TD_EINVAL, "%s: no output image", path);
    if (fmt < 0)
        return fmt;
    warm = colour_file(path, fmt) ? td_cv_lab_warm_begin() : NULL;
    if (fmt == FMT_TIFF)
        rc = td_tiff_read(path, out, georef, cx);
    else if (fmt == FMT_PNG)
        rc = td_png_read(path, out, cx);
    else
        rc = td_jpeg_read(path, out, cx);
    td_cv_lab_warm_end(warm);
    return rc;
}

/* See imageio.h. */
int td_image_info(const char *path, int *w, int *h, int *channels,
                  td_georef *georef, td_ctx *cx)
{
    int fmt = sniff(path, cx), rc;
    td_image *im = NULL;
    if (georef)
        td_georef_init(georef);
    if (fmt < 0)
        return fmt;
    if (fmt == FMT_TIFF)
        return td_tiff_info(path, w, h, channels, georef, cx);
    if (fmt == FMT_PNG)
        return td_png_info(path, w, h, channels, cx);
    /* JPEG: decoded whole (and so checked) */
    if ((rc = td_jpeg_read(path, &im, cx)) != 0)
        return rc;
    *w = im->w;
    *h = im->h;
    *channels = im->channels;
    td_image_free(im);
    return 0;
}
