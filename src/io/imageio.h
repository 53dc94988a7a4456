/* imageio.h: reading scans and writing rasters (PNG, GeoTIFF).
 *
 * All writers are atomic: they write "<path>.tmp.<pid>" next to the target
 * and rename it over the target only when everything was written, so a
 * failed run never leaves a half-written file.  Readers never print: libpng
 * and libtiff errors go into the td_ctx. */
#ifndef TD_IMAGEIO_H
#define TD_IMAGEIO_H

#include "src/core/grid.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Georeferencing carried from a GeoTIFF scan to the outputs.
 * Pixel (col,row) corner -> map: X = gt[0] + col*gt[1] + row*gt[2],
 * Y = gt[3] + col*gt[4] + row*gt[5] (GDAL's geotransform convention, for the
 * pixel corner; a pixel centre is col+0.5,row+0.5).  The raw GeoKey
 * directory is kept so writers can copy it verbatim. */
typedef struct td_georef {
    int valid;          /* nonzero when gt[] holds a transform */
    double gt[6];
    int epsg;           /* EPSG code of the CRS when known, else 0 */
    /* verbatim GeoTIFF keys, written back unchanged (may be NULL/0) */
    uint16_t *geokeys;  size_t n_geokeys;
    double *geodoubles; size_t n_geodoubles;
    char *geoascii;
} td_georef;

void td_georef_init(td_georef *g);
void td_georef_clear(td_georef *g);                    /* frees, re-inits */
int td_georef_copy(td_georef *dst, const td_georef *src, td_ctx *cx);
/* Cells step pixels wide: the transform's scale and rotation terms times
 * step.  Without georeferencing, step > 1 gives the scan's pixel frame
 * (0, step, 0, 0, step, 0) (y down, as GDAL assumes for a plain image), so
 * the DEM lies over the scan's pixel-unit lines; step 1 changes nothing. */
void td_georef_scale(td_georef *g, int step);
/* Pixel coordinates (col,row as reals, 0,0 = top-left corner of the first
 * pixel) to map coordinates; identity when !g->valid. */
void td_georef_apply(const td_georef *g, double col, double row, double *X,
                     double *Y);
/* A SHORT-valued GeoKey (e.g. 1025 GTRasterTypeGeoKey) from the verbatim
 * key directory: 1 and *val when present, else 0. */
int td_georef_geokey(const td_georef *g, int key, int *val);
/* The georeferencing of any TIFF/GeoTIFF (whatever its sample layout, so
 * DEM readers can use it too); g is initialised first and stays invalid
 * when the file has no transform.  0 or an error naming the file. */
int td_georef_read(const char *path, td_georef *g, td_ctx *cx);

/* Read a scan: TIFF (1/8/16-bit grey, palette, RGB/RGBA, striped or tiled,
 * any compression libtiff decodes: CCITT G3/G4, LZW, Deflate, PackBits,
 * JPEG), PNG (any bit depth/colour type), JPEG (via the OpenCV shim).
 * The format is found from the file's first bytes, not its name.
 * The result is 8-bit grey or RGB (1-bit: ink=0, paper=255; 16-bit scaled
 * to 8; alpha composited on white; palette expanded).  georef may be NULL;
 * when given it is initialised (not freed: clear it before reuse) and filled
 * from GeoTIFF tags (valid=0 otherwise).
 * Returns 0 and *out (caller frees with td_image_free), or an error naming
 * the file. */
int td_image_read(const char *path, td_image **out, td_georef *georef,
                  td_ctx *cx);

/* Read only what td_image_read would return about path without decoding
 * the pixels (JPEG excepted): width, height, output channels (1 or 3) and,
 * when georef is not NULL, the georeferencing (georef is initialised
 * first; free it with td_georef_clear).  0 or an error naming the file. */
int td_image_info(const char *path, int *w, int *h, int *channels,
                  td_georef *georef, td_ctx *cx);

/* Write an 8-bit grey (channels 1) or RGB (channels 3) PNG, atomically. */
int td_png_write(const char *path, const td_image *im, td_ctx *cx);
/* Write a u8 grid as a grey PNG; when scale01 is nonzero, values != 0 become
 * 255 (for masks). */
int td_png_write_u8(const char *path, const td_grid_u8 *g, int scale01,
                    td_ctx *cx);
/* Write a 16-bit grey PNG, with a tEXt "Comment" chunk when comment is
 * not NULL. */
int td_png_write_u16(const char *path, const td_grid_u16 *g,
                     const char *comment, td_ctx *cx);

/* Write a single-band float32 GeoTIFF (Deflate, floating-point predictor,
 * tiled 256x256 when larger than 1024 in either side, else striped), with
 * GDAL_NODATA when g->has_nodata and the georeferencing when georef valid.
 * gdalinfo, GRASS r.in.gdal and QGIS open it. */
int td_geotiff_write_f32(const char *path, const td_grid_f32 *g,
                         const td_georef *georef, td_ctx *cx);
/* Write a single-band uint8 GeoTIFF (Deflate). */
int td_geotiff_write_u8(const char *path, const td_grid_u8 *g,
                        const td_georef *georef, td_ctx *cx);

/* Atomic file helpers for other writers (GeoJSON, CSV): td_atomic_open
 * opens "<path>.tmp.<pid>" for writing and fills tmp (size >= strlen(path)+32);
 * td_atomic_commit closes and renames it over path; td_atomic_abort closes
 * and removes it.  Both return 0 or an error. */
#include <stdio.h>
FILE *td_atomic_open(const char *path, char *tmp, size_t tmpsize,
                     td_ctx *cx);
int td_atomic_commit(FILE *f, const char *tmp, const char *path, td_ctx *cx);
void td_atomic_abort(FILE *f, const char *tmp);

/* 0, or TD_EINVAL naming path when it exists and is no regular file (a
 * folder, a device, a FIFO). */
int td_atomic_check_target(const char *path, td_ctx *cx);

/* 0, or TD_EINVAL naming path when it is a folder (readers call it before
 * opening an input). */
int td_check_input(const char *path, td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
