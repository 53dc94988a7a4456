/* label_int.h: what the label command (label.c) and its operator entry
 * (label_entry.c, the paper's way, 001 §2.3) share.  Not public. */
#ifndef TD_CLI_LABEL_INT_H
#define TD_CLI_LABEL_INT_H

#include "src/cli/cli.h"

#include "src/pipeline/pipeline.h"

#include <stdio.h>

/* Points given or typed: x,y,height or a line id (scanner/label.h). */
typedef struct td_pts {
    td_label_point *v;
    size_t n, cap;
} td_pts;

/* Append a point (id -1: located by x,y); 0 or TD_ENOMEM. */
int td_pts_push(td_pts *a, double x, double y, double h, long id,
                td_ctx *cx);

/* Ask each line's height in id order on stderr, reading the answers from
 * in (Enter accepts the suggestion, a number sets the height and the
 * others are re-suggested from it, q keeps the rest automatic; end of
 * input accepts the rest).  known: the points given; rows, nrows: the
 * --heights rows (id,height).  Returns the number of warnings printed;
 * *asked gets the number of lines answered. */
size_t td_label_interact(td_lines *ls, td_label_params *p,
                         const td_pts *known, const double *rows,
                         size_t nrows, const double *idxy,
                         td_label_report *rep, FILE *in, size_t *asked);

#endif
