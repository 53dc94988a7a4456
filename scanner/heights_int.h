/* heights_int.h: the labellers behind td_label_auto (scanner/ only). */
#ifndef TD_HEIGHTS_INT_H
#define TD_HEIGHTS_INT_H

#include "scanner/label.h"

/* The face solve (heights.c, the default): every line of ls gets its
 * height, hsource, confidence, or has_height 0 and why.  rep is zeroed by
 * the caller.  Returns 0, TD_EINVAL or TD_ENOMEM. */
int td_heights_solve(td_lines *ls, const td_label_params *p,
                     td_label_report *rep, td_ctx *cx);

/* The same with p->interval <= 0: the interval inferred from the printed
 * labels (p->labels) first (rep->interval; one warning says so).
 * TD_EINVAL when fewer than three labels were read, they fit no interval,
 * or fewer than three (or only half) of them agree with the solve at the
 * interval inferred, or those that agree are less sure, summed, than the
 * rest (misreads that happen to fit an interval; td_label_auto then
 * takes the solve's heights off the lines). */
int td_heights_infer(td_lines *ls, const td_label_params *p,
                     td_label_report *rep, td_ctx *cx);

/* The face solve with the interval given and p->index_every 0 (and not
 * p->index_off): when the line widths show thicker lines, each index
 * spacing (5, 4, 10, 2) is tried as td_heights_infer tries them and the
 * cheapest solve is kept; else td_heights_solve.  Returns as it. */
int td_heights_solve_index(td_lines *ls, const td_label_params *p,
                           td_label_report *rep, td_ctx *cx);

/* After the face solve (labelpiece.c, ours): every short piece the
 * scanner set aside (td_line.piece), left out of the solve, takes the
 * height of the labelled lines at its ends when they agree (their source,
 * 0.9 of their confidence); else it keeps none and why says so.  Returns
 * 0 or TD_ENOMEM. */
int td_label_pieces(td_lines *ls, td_ctx *cx);

#endif
