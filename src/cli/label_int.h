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

typedef struct label_opts {
    const char *in, *out, *csv_out, *label_sheet, *like, *scan, *debug_dir;
    const char *known_file, *heights, *walls;
    int quiet, w, h, interactive, no_missing, no_streams;
    td_opt_points known, dep;
    td_label_params p;
    td_pts pts;        /* --known and --known-file */
    double *rows;      /* --heights: id,height */
    size_t nrows;
} label_opts;

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

/* --interactive: write the label sheet, then ask (td_label_interact);
 * the lines answered go into seen, the warnings printed add to *more. */
int td_label_entry(label_opts *o, td_lines *ls, td_label_report *rep,
                   td_pts *seen, size_t *more, td_ctx *cx);

/* label_report.c: crossing warnings (one line each; returns how many, or
 * -1 out of memory) and the summary with the labeller's warnings. */
long td_label_warn_crossings(const td_lines *ls, int quiet, td_ctx *cx);
void td_label_summary(const td_lines *ls, td_label_report *rep,
                      const td_label_report *checks, const label_opts *o,
                      const td_pts *seen, size_t more);

#endif
