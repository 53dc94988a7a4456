/* draw.h: debug and teaching pictures drawn in memory (no file I/O). */
#ifndef TD_DRAW_H
#define TD_DRAW_H

#include "src/core/grid.h"
#include "src/core/lines.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A distinct, well-separated colour for index i (golden-ratio hues). */
void td_draw_colour(size_t i, uint8_t rgb[3]);

/* Draw a 1-px polyline (closing segment when l->closed) into an RGB image,
 * clipped to it. */
void td_draw_line(td_image *im, const td_line *l, const uint8_t rgb[3]);

/* The traced-lines overlay: the scan faded towards white, every line drawn
 * in its own colour, open line ends off the border marked with a red 3x3
 * box.
 * *out is a new RGB image of the scan's size (free with td_image_free). */
int td_draw_overlay(const td_image *scan, const td_lines *ls, td_image **out,
                    td_ctx *cx);

/* The heights picture (label, run --debug-dir): the scan (NULL: white
 * w x h) faded, every line coloured by its height (blue low .. brown
 * high), 3 px wide when known or read from a label, solid when solved,
 * dashed when assumed, grey dotted without a height.  *out is new (free
 * with td_image_free).  Returns 0 or TD_ENOMEM. */
int td_draw_heights(const td_image *scan, int w, int h, const td_lines *ls,
                    td_image **out, td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
