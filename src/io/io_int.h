/* io_int.h: internals shared by the image I/O files (imageio.c,
 * tiffio.c, pngio.c, georef.c, outfile.c).  Not for other stages. */
#ifndef TD_IMAGEIO_INT_H
#define TD_IMAGEIO_INT_H

#include "src/io/io.h"

#include <tiffio.h>

/* Where a libtiff handle's first error message lands (warnings are
 * dropped).  Zero-initialise before opening. */
typedef struct td_tiff_err {
    char msg[400];
    int count;
} td_tiff_err;

/* Open a TIFF with per-handle error/warning handlers writing into *e, the
 * GeoTIFF tags registered.  fd >= 0 opens that descriptor (libtiff closes
 * it), else path.  Returns NULL on failure (message in e). */
TIFF *td_tiff_open(const char *path, int fd, const char *mode, td_tiff_err *e);

/* Set an error "PATH: what: libtiff's message" in cx; returns code. */
/* Before the frame is allocated: every strip or tile of tif's current
 * directory lies inside the file (a truncated file is refused up front,
 * not after allocating its frame), and the data could decode to the frame
 * (the decoded size at most the compression's largest ratio times the
 * compressed bytes: 2 uncompressed, 130 PackBits, 1100 Deflate, 5000 LZW;
 * the others unbounded), so a tiny file claiming a huge frame is refused.
 * 0 or TD_EFORMAT naming path. */
int td_tiff_check_data(TIFF *tif, const char *path, td_ctx *cx);
int td_tiff_fail(td_ctx *cx, int code, const char *path, const char *what,
                 const td_tiff_err *e);

/* Header only: the size and channel count td_tiff_read would return, and
 * the georef (may be NULL). */
int td_tiff_info(const char *path, int *w, int *h, int *channels,
                 td_georef *georef, td_ctx *cx);
int td_tiff_read(const char *path, td_image **out, td_georef *georef,
                 td_ctx *cx);
int td_png_info(const char *path, int *w, int *h, int *channels, td_ctx *cx);
int td_png_read(const char *path, td_image **out, td_ctx *cx);
/* JPEG through libjpeg (src/io/jpegio.c): every libjpeg warning (corrupt or
 * truncated data) is an error naming path; a frame the file is far too
 * small for is refused before any pixel memory is allocated. */
int td_jpeg_read(const char *path, td_image **out, td_ctx *cx);

/* Fill g from the GeoTIFF tags of the open directory (g->valid stays 0
 * when the tags give no affine transform).  Returns 0 or TD_ENOMEM. */
int td_georef_from_tiff(TIFF *tif, td_georef *g, td_ctx *cx);
/* Write g's tags into a TIFF being written (w x h). */
int td_georef_to_tiff(TIFF *tif, const td_georef *g, td_ctx *cx);

#endif
