/* heights_int.h: the labellers behind td_label_auto (scanner/ only). */
#ifndef TD_HEIGHTS_INT_H
#define TD_HEIGHTS_INT_H

#include "label.h"

/* The face solve (heights.c, the default): every line of ls gets its
 * height, hsource, confidence, or has_height 0 and why.  rep is zeroed by
 * the caller.  Returns 0, TD_EINVAL or TD_ENOMEM. */
int td_heights_solve(td_lines *ls, const td_label_params *p,
                     td_label_report *rep, td_ctx *cx);

#endif
