/* demio.h: reading and writing DEM grids (float32 in memory).
 *
 * Readers accept any single-band GeoTIFF/TIFF DEM (8/16/32-bit signed or
 * unsigned integers, 32/64-bit floats; striped or tiled; any compression
 * libtiff decodes; GDAL_NODATA honoured) and ESRI ASCII grids (.asc,
 * recognised by content: "ncols" first).  Writers are atomic like every
 * writer (src/io/imageio.h).  GeoTIFF writing is td_geotiff_write_f32. */
#ifndef TD_DEMIO_H
#define TD_DEMIO_H

#include "src/io/imageio.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Read a DEM into a new float32 grid (*out, free with td_grid_f32_free).
 * Cells equal to the file's nodata value (or NaN) become g->nodata with
 * g->has_nodata = 1; nodata defaults to -9999 when the file has none but
 * NaNs occur.  georef may be NULL; it is initialised (not freed) first and
 * filled from GeoTIFF tags or the .asc header (xllcorner/yllcorner/
 * cellsize, also xllcenter/yllcenter).  Errors name the file: not a DEM
 * (multi-band, RGB), unsupported sample type, too large, truncated. */
int td_dem_read(const char *path, td_grid_f32 **out, td_georef *georef,
                td_ctx *cx);

/* Write an ESRI ASCII grid (atomic).  The cell size and lower-left corner
 * come from georef when valid and without rotation, else cell size 1 with
 * the corner at (0, 0); NODATA_value written when g->has_nodata. */
int td_asc_write(const char *path, const td_grid_f32 *g,
                 const td_georef *georef, td_ctx *cx);

/* Write a DEM by the file name's extension: .asc -> ESRI ASCII grid,
 * .png -> 16-bit grey PNG scaled from the grid's min..max (nodata -> 0;
 * the mapping written in a tEXt Comment chunk),
 * anything else -> float32 GeoTIFF. */
int td_dem_write(const char *path, const td_grid_f32 *g,
                 const td_georef *georef, td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
