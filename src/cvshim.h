/* cvshim.h: the only door to OpenCV.  Implemented in src/cvshim.cpp; no
 * other file includes OpenCV or sees C++.  Every function catches C++
 * exceptions and turns them into a TD_E* code with a message in cx. */
#ifndef TD_CVSHIM_H
#define TD_CVSHIM_H

#include "grid.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Decode a JPEG file into an 8-bit grey (1-channel source) or RGB image.
 * Returns 0 and *out (free with td_image_free) or an error naming path. */
int td_cv_read_jpeg(const char *path, td_image **out, td_ctx *cx);

/* RGB (3-channel td_image) to 8-bit grey (BT.601 luma); grey has im's
 * size.  Works row band by row band, no full-size temporaries. */
int td_cv_rgb_to_grey(const td_image *im, td_grid_u8 *grey, td_ctx *cx);

/* Otsu's threshold of an 8-bit grid (histogram over all cells); *thr gets
 * the threshold t such that values > t are the upper class. */
int td_cv_otsu(const td_grid_u8 *g, int *thr, td_ctx *cx);

/* Sauvola local threshold on an "ink strength" grid s (high = ink):
 * mask = 1 where s > m + ... per Sauvola with window (odd) and k, computed
 * in row bands so extra memory is O(width x (window + band)). */
int td_cv_sauvola(const td_grid_u8 *s, int window, double k, td_grid_u8 *mask,
                  td_ctx *cx);

/* 3x3 median filter in place, in row bands. */
int td_cv_median3(td_grid_u8 *g, td_ctx *cx);

/* Remove 8-connected components of nonzero cells with fewer than min_area
 * cells; *removed gets how many components were removed (may be NULL). */
int td_cv_remove_specks(td_grid_u8 *mask, int min_area, size_t *removed,
                        td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
