/* cvshim.h: the only door to OpenCV.  Implemented in src/io/cvshim.cpp; no
 * other file includes OpenCV or sees C++.  Every function catches C++
 * exceptions and turns them into a TD_E* code with a message in cx.
 *
 * Filters that work "in row bands" keep a private copy of only the input
 * rows a band needs (band + window halo), so their extra memory is
 * O(width x (band + window)) whatever the sheet's height, and they may
 * write their output over their input (see each contract). */
#ifndef TD_CVSHIM_H
#define TD_CVSHIM_H

#include "src/core/grid.h"

#ifdef __cplusplus
extern "C" {
#endif

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

/* k-means of n points of dim floats (pts[n * dim]) into k clusters
 * (cv::kmeans, k-means++ seeding from a fixed seed, so the same input gives
 * the same clusters; `attempts` restarts, the most compact kept).  label[n]
 * gets each point's cluster, centre[k * dim] the centres.  Returns 0 or an
 * error (TD_EINVAL when n < k). */
int td_cv_kmeans(const float *pts, int n, int dim, int k, int attempts,
                 int *label, float *centre, td_ctx *cx);

/* RGB (3-channel td_image) to 8-bit grey: BT.601 luma 0.299 R + 0.587 G +
 * 0.114 B as cv::cvtColor(COLOR_RGB2GRAY) computes it (its own fixed-point
 * rounding); grey has im's size.  A 1-channel image is copied.  Works row
 * band by row band straight into grey, no temporaries. */
int td_cv_rgb_to_grey(const td_image *im, td_grid_u8 *grey, td_ctx *cx);

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
