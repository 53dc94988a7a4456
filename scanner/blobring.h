/* blobring.h: tiny summit rings that printed as dots of ink (ours; not in
 * the papers).
 *
 * A closed contour only a few pixels across, drawn with a pen about as
 * wide as its hole, fills in: the ink is a dot, pinhole filling closes
 * what is left of the hole, thinning leaves a point, and the tracer
 * reports a degenerate ring (a closed line fitting in 3 x 3 px).  The
 * contour was a ring around the dot's middle: td_blob_rings puts it back
 * as a circle of radius sqrt(A / pi) - pen / 2, A the dot's ink area and
 * pen the sheet's median line width. */
#ifndef TD_BLOBRING_H
#define TD_BLOBRING_H

#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* For every degenerate ring of ls (closed, within 3 x 3 px, not on the
 * border) whose dot in the packed mask bits (w x h, width.h's layout) is
 * one piece of at most 31 x 31 px: its vertices become that circle when
 * its radius is at least 1.5 px.  Needs the lines' widths (td_line_widths)
 * for the pen.  Returns the number of rings redrawn, or TD_ENOMEM. */
long td_blob_rings(const uint8_t *bits, int w, int h, td_lines *ls,
                   td_ctx *cx);

/* For every closed line of ls whose points all lie on one spot (a ring
 * that thinned to a single pixel and was not redrawn above): its points
 * become a square ring of TD_POINT_RING_R px about that spot, inside the
 * pixel.  A LineString of one point (or of one point twice) has no
 * length and is invalid to GEOS, QGIS and RFC 7946; the ring is valid and
 * rasterises to the same pixel.  Returns the number of rings so redrawn,
 * or TD_ENOMEM. */
#define TD_POINT_RING_R 0.25
long td_point_rings(td_lines *ls, td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
