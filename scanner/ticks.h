/* ticks.h: depression contours read from their ticks (ours).
 *
 * Printed maps draw a closed contour around lower ground (a pit, a
 * sinkhole, a crater) with short ticks on its downhill side.  The ticks
 * are read on the binarised mask (thinning would make them spurs, which
 * spur removal erases): along every ring, the ink's width across the line
 * at each vertex against the width about it.  A traced ring with ticks
 * on its inside and few on its outside is a depression
 * (td_line.depression), which the labeller takes as evidence
 * (docs/label.md, "Depression ticks"). */
#ifndef TD_SCANNER_TICKS_H
#define TD_SCANNER_TICKS_H

#include "src/core/core.h"

/* Mark the closed lines of ls that carry depression ticks, on the packed
 * w x h mask `bits` (td_width_pack) the lines were traced from.  A tick:
 * at most 4 vertices along the ring where the ink across it is 1.25-8 px
 * wider than at the vertices about it, the extra ink on one side of the
 * traced line and a thin stroke there (paper 2 px to either side).  A
 * ring is marked when it has at least `min_in` ticks inside, at least one
 * per 13 pen widths of its length (the sheet's pen: td_pen_width) and
 * more than twice as many inside as outside; rings whose mean half-width
 * (2 area / perimeter) is under the pen plus 2 px are left unmarked (no
 * room for a tick inside).  Returns the number of lines marked (>= 0) or
 * TD_ENOMEM. */
long td_ticks_mark(td_lines *ls, const uint8_t *bits, int w, int h,
                   int min_in, td_ctx *cx);

#endif
