/* geotiff_bands.h: writing several float32 grids of one size as the bands
 * of one GeoTIFF (e.g. the horizon angles of `topodig insolation
 * --horizons`, one band per direction). */
#ifndef TD_GEOTIFF_BANDS_H
#define TD_GEOTIFF_BANDS_H

#include "src/io/imageio.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Write bands[0..n-1] (same width and height, any strides) as an n-band
 * float32 GeoTIFF at path, atomically (src/io/imageio.h): separate planes
 * (band i = sample plane i, GDAL band i + 1), strips, Deflate with the
 * floating-point predictor, GDAL_NODATA from bands[0] when it has nodata,
 * the georeferencing when georef is valid (may be NULL).  BigTIFF above
 * 2 GB.  Returns 0, TD_EINVAL (no bands, sizes differ), TD_ETOOBIG,
 * TD_ENOMEM or TD_EIO (message naming path); nothing is left at path on
 * failure. */
int td_geotiff_write_bands_f32(const char *path, td_grid_f32 *const *bands,
                               int n, const td_georef *georef, td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
