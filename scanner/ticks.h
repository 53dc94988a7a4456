/* ticks.h: depression contours read from their ticks (ours).
 *
 * Printed maps draw a closed contour around lower ground (a pit, a
 * sinkhole, a crater) with short ticks on its downhill side.  Thinning
 * turns each tick into a short spur, which spur removal erases
 * (td_despur with record on keeps where).  A traced ring with ticks on
 * its inside and few on its outside is a depression
 * (td_line.depression), which the labeller takes as evidence
 * (docs/label.md, "Depression ticks"). */
#ifndef TD_SCANNER_TICKS_H
#define TD_SCANNER_TICKS_H

#include "scanner/despur.h"

/* Mark the closed lines of ls whose spurs (rec, n: from td_despur) point
 * inwards: at least `min_in` spurs whose junction lies within 2 px of the
 * line and whose tip is 1.5-10 px from it, pointing inwards, and more
 * than twice as many as point outwards.  Returns the number of lines
 * marked (>= 0) or TD_ENOMEM. */
long td_ticks_mark(td_lines *ls, const td_spur_rec *rec, size_t n,
                   int min_in, td_ctx *cx);

#endif
