/* io.h: files in and out (one header for src/io/).
 *
 *   imageio        scans in (TIFF, PNG, JPEG), rasters out (PNG, GeoTIFF),
 *                  georeferencing, atomic output files, vector files
 *   demio          DEM grids in and out (GeoTIFF, ESRI ASCII)
 *   geotiff_bands  several float32 grids as the bands of one GeoTIFF
 *   cvshim         the only door to OpenCV (src/io/cvshim.cpp)
 *
 * All writers are atomic: they write a new temporary file next to the
 * target and rename it over the target only when everything was written,
 * so a failed run never leaves a half-written file.  Readers never print:
 * libpng, libtiff and libjpeg errors go into the td_ctx. */
#ifndef TD_IO_H
#define TD_IO_H

#include "src/core/core.h"

#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Georeferencing carried from a GeoTIFF scan to the outputs.
 * Pixel (col,row) corner -> map: X = gt[0] + col*gt[1] + row*gt[2],
 * Y = gt[3] + col*gt[4] + row*gt[5] (GDAL's geotransform convention, for the
 * pixel corner; a pixel centre is col+0.5,row+0.5).  The raw GeoKey
 * directory is kept so writers can copy it verbatim.
 *
 * The pixel frame.  A scan with no georeferencing has its outputs in the
 * frame in which QGIS shows an ungeoreferenced image: X = col, Y = -row
 * (geotransform 0, 1, 0, 0, 0, -1), in the local engineering CRS named
 * TD_PIXEL_CRS ("topodig scan pixels").  Every writer uses it when its
 * georef is NULL or invalid, so the DEM, the lines and the scan lie on
 * each other in QGIS, and no file claims WGS 84 for pixel coordinates. */
#define TD_PIXEL_CRS "topodig scan pixels"
typedef struct td_georef {
    int valid;          /* nonzero when gt[] holds a transform */
    int pixel;          /* gt is the pixel frame (possibly scaled by a
                           step): no real georeferencing behind it */
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
/* Make g (cleared first) the pixel frame: valid, pixel, gt (0,1,0,0,0,-1). */
void td_georef_pixel_frame(td_georef *g);
/* Cells step pixels wide: the transform's scale and rotation terms times
 * step.  Without georeferencing, g becomes the pixel frame first, so the
 * DEM of (0, step, 0, 0, 0, -step) lies over the scan's lines. */
void td_georef_scale(td_georef *g, int step);
/* Pixel coordinates (col,row as reals, 0,0 = top-left corner of the first
 * pixel) to map coordinates; the pixel frame (X = col, Y = -row) when g is
 * NULL or invalid. */
void td_georef_apply(const td_georef *g, double col, double row, double *X,
                     double *Y);
/* Its inverse: map coordinates to cells (col, row as reals); the pixel
 * frame when g is NULL or invalid.  0, or -1 when the transform cannot be
 * inverted. */
int td_georef_to_cells(const td_georef *g, double X, double Y, double *col,
                       double *row);
/* The "crs" member of a GeoJSON file for g (without a trailing comma):
 * the EPSG code when known; the pixel frame's engineering CRS when g is
 * NULL, invalid or the pixel frame; else an engineering CRS saying the
 * scan's CRS is not named (never WGS 84, which GeoJSON without a "crs"
 * implies).  Writes at most n bytes (256 is enough) to buf. */
void td_georef_crs_json(const td_georef *g, char *buf, size_t n);
/* The one cell-size rule of every command: the size of a w x h grid's
 * cells in metres from its georeferencing, the mean of |gt[1]| and |gt[5]|
 * (square cells expected); for a geographic CRS (GTModelTypeGeoKey 2,
 * degrees) converted to metres at the grid's centre latitude.  0 when g is
 * NULL, invalid or the pixel frame (no real cell size: the caller's
 * default).  *geographic (may be NULL) says whether degrees were
 * converted. */
double td_georef_cell_size(const td_georef *g, int w, int h, int *geographic);
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
/* An animated GIF (gifio.c) of n frames of one size (grey or RGB), each
 * quantised to 256 colours of its own, shown delay_cs hundredths of a
 * second each, looping; atomically.  0, TD_EINVAL, TD_EIO. */
int td_gif_write(const char *path, td_image *const *frames, size_t n,
                 int delay_cs, td_ctx *cx);
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

/* The DEMs in[0..n-1] as one (mosaic.c, GDAL BuildVRT at the finest
 * resolution): out ".vrt" (a virtual raster over them, paths relative to
 * it where they can be) or ".tif" (one tiled Deflate GeoTIFF).  0 or an
 * error naming out. */
int td_dem_mosaic(const char *const *in, size_t n, const char *out,
                  td_ctx *cx);

/* Atomic file helpers for other writers (GeoJSON, CSV): td_atomic_open
 * opens "<path>.tmp.<pid>" for writing and fills tmp (size >= strlen(path)+32);
 * td_atomic_commit closes and renames it over path; td_atomic_abort closes
 * and removes it.  Both return 0 or an error. */
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

/* ---- vector files (geojson_read.c, geojson_write.c) ---- */

/* Write lines as a GeoJSON FeatureCollection of LineStrings, atomically.
 * Properties: id, height (null unless has_height), closed, edge, parent
 * (null when -1), bridged, width (px, only when measured, > 0), and when the
 * labeller set them height_source ("known", "label", "solved", "assumed"),
 * confidence (0..1) and height_reason (why the height is null).  When georef is valid, coordinates are mapped
 * through it and its EPSG code (if known) is named in a "crs" member, which
 * GDAL/OGR and QGIS read.  Returns 0 or an error naming the file. */
int td_geojson_write_lines(const char *path, const td_lines *ls,
                           const struct td_georef *georef, td_ctx *cx);

/* Read a GeoJSON FeatureCollection of LineString (and MultiLineString,
 * one line per part) features, as written by td_geojson_write_lines or
 * edited in QGIS: properties id, height (number or null), closed, edge,
 * parent, width are read when present (missing id: the feature's index; missing
 * closed: first point == last point, the repeated last point dropped).
 * When georef is valid, coordinates are map coordinates and are mapped back
 * to pixel units through its inverse.  Other geometry types are skipped
 * and counted in *skipped (may be NULL).  *out gets a new td_lines.
 * Errors name the file and the byte offset of bad JSON. */
int td_geojson_read_lines(const char *path, const struct td_georef *georef,
                          td_lines **out, size_t *skipped, td_ctx *cx);

/* The same, and *frame (may be NULL; initialised) says how the file's
 * coordinates map to the lines' pixel units, for writing them back the same
 * way: the pixel frame when the file is in it, an identity transform with
 * the EPSG code when its "crs" names one (and no georef maps it), else
 * invalid (pixel units, y down: write back in the pixel frame). */
int td_geojson_read_lines_frame(const char *path,
                                const struct td_georef *georef,
                                td_lines **out, size_t *skipped,
                                struct td_georef *frame, td_ctx *cx);

/* Lines in any vector format, by the file name's extension: .geojson /
 * .json (topodig's own writer: fast, exact), .gpkg (GeoPackage), .shp
 * (Shapefile: field names cut to 10 characters, as the format has them)
 * and .dxf (3-D polylines at their heights, layer "contours", lines
 * without a height at z 0 on layer "contours_unlabelled"; DXF carries no
 * other property) through GDAL/OGR.  The same properties and frames as
 * td_geojson_write_lines; written to a new private folder beside path and
 * renamed into place.  0 or an error naming the file. */
int td_vector_write_lines(const char *path, const td_lines *ls,
                          const struct td_georef *georef, td_ctx *cx);
/* 3-D paths (ridge and valley lines): xyz holds n points x, y (pixel
 * units), z; kind and tree become properties (tree -1: null). */
typedef struct td_path3 {
    const double *xyz;
    size_t n;
    const char *kind;
    long tree;
} td_path3;
typedef struct td_paths3 {
    const td_path3 *v;
    size_t n;
} td_paths3;
/* Write paths by extension, as td_vector_write_lines: GeoJSON with
 * [x, y, z] positions and the properties kind, tree and heights (the z of
 * each vertex); GeoPackage and Shapefile 3-D LineStrings with kind and
 * tree; DXF 3-D polylines on a layer named after the kind.  0, TD_EINVAL
 * (a non-finite coordinate, an unknown extension) or an error naming the
 * file. */
int td_vector_write_paths(const char *path, const td_paths3 *P,
                          const struct td_georef *georef, td_ctx *cx);
/* Read lines back from any of those formats (other extensions: GeoJSON),
 * as td_geojson_read_lines_frame: the first layer (or the layer named
 * "contours"), LineString and MultiLineString features (one line per part;
 * others counted in *skipped), properties id, height, closed, edge,
 * parent, bridged, width when present; a DXF polyline's height is its z. */
int td_vector_read_lines(const char *path, const struct td_georef *georef,
                         td_lines **out, size_t *skipped,
                         struct td_georef *frame, td_ctx *cx);

/* Lines with a height per vertex (ridge lines), any format GDAL/OGR reads:
 * LineString and MultiLineString features of the first layer, and the
 * outer ring of a Polygon as a closed line (others counted in *skipped), in pixel units as td_vector_read_lines; *z (free())
 * gets one height per vertex of every line in order: the geometry's z when
 * 3-D, else the "heights" list property (one per vertex, as
 * td_vector_write_paths writes), else the "height" property, else NaN.
 * kind (may be NULL): features whose "kind" property is another string
 * (valley and inflection lines beside ridge lines) are skipped too.
 * 0 or an error naming the file. */
int td_vector_read_lines_z(const char *path, const struct td_georef *georef,
                           const char *kind, td_lines **out, double **z,
                           size_t *skipped, struct td_georef *frame,
                           td_ctx *cx);

/* ---- CSV (csv.c) ---- */

/* Rows of ncols (1..8) finite numbers from a CSV file (x,y,height: 3;
 * id,height: 2): blank lines and '#' lines skipped, a first line with
 * letters taken as a header.  With allow_empty_last, a row "A," gives NaN
 * in the other columns (an id without a height).  *v: n x ncols numbers
 * (free()).  Errors name the file and the line. */
int td_csv_read_rows(const char *path, int ncols, int allow_empty_last,
                     double **v, size_t *n, td_ctx *cx);
/* "id,height" of every line ("id," when it has none), atomically. */
int td_csv_write_heights(const char *path, const td_lines *ls, td_ctx *cx);

/* ---- demio ---- */
/* demio.h: reading and writing DEM grids (float32 in memory).
 *
 * Readers accept any single-band GeoTIFF/TIFF DEM (8/16/32-bit signed or
 * unsigned integers, 32/64-bit floats; striped or tiled; any compression
 * libtiff decodes; GDAL_NODATA honoured) and ESRI ASCII grids (.asc,
 * recognised by content: "ncols" first).  Writers are atomic like every
 * writer (src/io/imageio.h).  GeoTIFF writing is td_geotiff_write_f32. */

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

/* ---- geotiff_bands ---- */
/* geotiff_bands.h: writing several float32 grids of one size as the bands
 * of one GeoTIFF (e.g. the horizon angles of `topodig insolation
 * --horizons`, one band per direction). */

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

/* ---- cvshim ---- */
/* cvshim.h: the only door to OpenCV.  Implemented in src/io/cvshim.cpp; no
 * other file includes OpenCV or sees C++.  Every function catches C++
 * exceptions and turns them into a TD_E* code with a message in cx.
 *
 * Filters that work "in row bands" keep a private copy of only the input
 * rows a band needs (band + window halo), so their extra memory is
 * O(width x (band + window)) whatever the sheet's height, and they may
 * write their output over their input (see each contract). */

/* Decode a JPEG file into an 8-bit grey (1-channel source) or RGB image.
 * The frame header is parsed first and its size checked with
 * td_check_dims before any pixel memory is allocated; OpenCV then decodes
 * straight into the td_image (no second copy).  EXIF orientation is
 * ignored: pixels come in stored order, as pixel coordinates assume.
 * Returns 0 and *out (free with td_image_free) or an error naming path:
 * TD_EIO (cannot open/read), TD_EFORMAT ("PATH: cannot decode JPEG"),
 * TD_ETOOBIG. */
int td_cv_read_jpeg(const char *path, td_image **out, td_ctx *cx);

/* Encode im (grey or RGB) as a baseline JPEG of the given quality (1..100)
 * and write it atomically (temporary file renamed over path).  Makes one
 * full-size BGR copy for colour images (a writer for samples and tests, not
 * for huge sheets).  Returns 0 or an error naming path. */
int td_cv_write_jpeg(const char *path, const td_image *im, int quality,
                     td_ctx *cx);

/* Encode im (grey or RGB) as JPEG of the given quality (1..100) in memory
 * and decode it back into im: the losses of a scanner's JPEG output (the
 * generator's scans).  Returns 0 or an error. */
int td_cv_jpeg_roundtrip(td_image *im, int quality, td_ctx *cx);

/* n packed 8-bit sRGB colours (rgb[3n]) to CIELAB (D65; lab[3n]: L 0..100,
 * a, b) as cv::cvtColor(COLOR_RGB2Lab) on float input computes it. */
int td_cv_rgb_to_lab(const uint8_t *rgb, size_t n, float *lab, td_ctx *cx);

/* OpenCV's CIELAB tables built on a thread of their own (the first
 * conversion's 0.13-0.17 s) while a colour scan is read: begin returns a
 * handle (NULL when no thread could start), end waits for it (NULL: no-op).
 * Nothing may convert colours in between. */
void *td_cv_lab_warm_begin(void);
void td_cv_lab_warm_end(void *h);

/* k-means of n points of dim floats (pts[n * dim]) into k clusters
 * (cv::kmeans, k-means++ seeding from a fixed seed, so the same input gives
 * the same clusters; `attempts` restarts, the most compact kept).  label[n]
 * gets each point's cluster, centre[k * dim] the centres.  Returns 0 or an
 * error (TD_EINVAL when n < k). */
int td_cv_kmeans(const float *pts, int n, int dim, int k, int attempts,
                 int *label, float *centre, td_ctx *cx);

/* The same from the caller's seeding: label[n] in holds each point's
 * first cluster (0..k-1; cv::KMEANS_USE_INITIAL_LABELS, one attempt), out
 * its last.  Nothing random: the same input gives the same clusters. */
int td_cv_kmeans_from(const float *pts, int n, int dim, int k, int *label,
                      float *centre, td_ctx *cx);

/* RGB (3-channel td_image) to 8-bit grey: BT.601 luma 0.299 R + 0.587 G +
 * 0.114 B as cv::cvtColor(COLOR_RGB2GRAY) computes it (its own fixed-point
 * rounding); grey has im's size.  A 1-channel image is copied.  Works row
 * band by row band straight into grey, no temporaries. */
int td_cv_rgb_to_grey(const td_image *im, td_grid_u8 *grey, td_ctx *cx);
/* The Delaunay triangulation of n points xy (OpenCV Subdiv2D): *tri
 * (free()) gets *ntri triangles as three point indices each (a repeated
 * point takes the index of its first copy).  0, TD_EINVAL (under 3
 * points, non-finite), TD_ENOMEM. */
int td_cv_delaunay(const double *xy, size_t n, int32_t **tri, size_t *ntri,
                   td_ctx *cx);

/* Otsu's threshold of an 8-bit grid (histogram over all cells); *thr gets
 * the threshold t such that values > t are the upper class.  The choice is
 * the one cv::threshold(THRESH_OTSU) makes on the same data (first maximum
 * of the between-class variance; splits leaving a class with a weight
 * below FLT_EPSILON are not considered; 0 when no split exists). */
int td_cv_otsu(const td_grid_u8 *g, int *thr, td_ctx *cx);

/* Otsu's threshold from a 256-bin histogram (hist[v] = number of cells of
 * value v), as td_cv_otsu.  Lets a caller that already made the histogram
 * skip a second pass over the image.  TD_EINVAL when the histogram is
 * empty. */
int td_cv_otsu_hist(const uint64_t hist[256], int *thr, td_ctx *cx);

/* Reference for tests: the threshold cv::threshold(THRESH_OTSU) itself
 * returns on g.  Allocates a full-size temporary; not for production. */
int td_cv_otsu_opencv(const td_grid_u8 *g, int *thr, td_ctx *cx);

/* Sauvola local threshold on an "ink strength" grid s (high = ink).
 * Sauvola's rule on the paper-white image g = 255 - s is "ink where
 * g < m_g (1 + k (sd/R - 1))", R = 128; with m_g = 255 - m and the same sd
 * that is, on s:
 *     mask = 1 where s > 255 - (255 - m) (1 + k (sd/128 - 1))
 * m, sd: mean and standard deviation of s over the window x window square
 * around the cell (border cells: the sheet reflected, OpenCV's
 * BORDER_REFLECT_101).  window odd, 3..181; k in (0, 1].
 * Computed in row bands of 128 rows with cv::boxFilter/sqrBoxFilter over
 * band + halo; mask may be s itself (in place).  Progress: "sauvola". */
int td_cv_sauvola(const td_grid_u8 *s, int window, double k, td_grid_u8 *mask,
                  td_ctx *cx);

/* 3x3 median filter in place, in row bands (sheet border replicated). */
int td_cv_median3(td_grid_u8 *g, td_ctx *cx);

/* Remove 8-connected components of nonzero cells with fewer than min_area
 * cells; *removed gets how many components were removed (may be NULL).
 * The mask becomes 0/1.  A bounded flood fill: each fill stops as soon as
 * it has seen min_area cells or touched a component already known to be
 * large, so extra memory is 8 bytes x min_area (no label image, 0 bytes
 * per pixel) and time is linear in the number of cells.  min_area <= 1
 * removes nothing and leaves the mask as it is.  Progress: "specks". */
int td_cv_remove_specks(td_grid_u8 *mask, int min_area, size_t *removed,
                        td_ctx *cx);

/* Fill holes: 4-connected components of zero cells (the dual of 8-connected
 * ink, so a pinhole touching the paper only diagonally is a hole too) with
 * fewer than min_area cells become 1.  Same bounded fill and memory as
 * td_cv_remove_specks; *filled may be NULL.  Progress: "holes". */
int td_cv_fill_holes(td_grid_u8 *mask, int min_area, size_t *filled,
                     td_ctx *cx);

/* Zhang-Suen thinning by OpenCV ximgproc (opencv_contrib), in place on a
 * mask (nonzero = ink; result 0/1).  The benchmark anchor for Hilditch
 * thinning, not a stage: the library is loaded at run time, so programs
 * need not link it; TD_EINVAL "... not available" when it cannot be
 * loaded.  Makes two full-size temporaries (1 byte per pixel each). */
int td_cv_thin_zhangsuen(td_grid_u8 *g, td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
