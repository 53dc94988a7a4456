/* match.h: compare traced contour lines against the generator's truth.
 *
 * Definitions (all distances in pixels, point-to-segment):
 *  - Each truth line is sampled every 0.5 px of arc length (closing segment
 *    included for rings; an open line's last point too).  A sample is
 *    covered when some traced segment passes within o->cover_tol of it.
 *  - Per truth line: coverage = covered samples / samples; mean distance =
 *    mean over covered samples of the distance to the nearest traced
 *    segment; a traced line "covers" the truth line by the number of
 *    samples it lies within cover_tol of; pieces = number of distinct traced
 *    lines covering >= 5% of the samples; the best traced line is the one
 *    covering most samples.
 *  - A truth line is matched when coverage >= o->min_cov (0.99) and mean
 *    distance <= o->max_mean (1.5).  It is split when pieces > 1.  Its
 *    closed (edge) flag is wrong when it differs from the best traced
 *    line's closed (edge) flag; not checked for closed truth rings passing
 *    within o->border_margin (3) px of the sheet border (n_near_border: a
 *    tracer may fairly see those touch the border pixels).
 *  - Per traced line: each vertex goes to the truth line with the nearest
 *    segment within o->assign_tol (3) px, or to none.  The traced line is
 *    mixed when its second truth line gets >= max(10, 5% of its vertices);
 *    it is unmatched (noise) when more than half its vertices go to none.
 *  - Truth lines shorter than o->min_len (default 0) are skipped (n_short).
 * Segments are found through a bucket grid of 8 px cells, so a 10000 x
 * 10000 sheet with ~5M traced points is matched in seconds. */
#ifndef TD_TEST_MATCH_H
#define TD_TEST_MATCH_H

#include <stdio.h>

#include "src/core/core.h"

typedef struct td_match_opts {
    double cover_tol;     /* 2.0 */
    double assign_tol;    /* 3.0 */
    double min_cov;       /* 0.99 */
    double max_mean;      /* 1.5 */
    double border_margin; /* 3.0 */
    double min_len;       /* 0.0 */
} td_match_opts;

typedef struct td_match_report {
    long n_truth; /* truth lines checked (n_short not included) */
    long n_traced;
    long n_matched;
    long n_short;       /* truth lines skipped as shorter than min_len */
    long n_near_border; /* rings whose flags were not checked */
    double worst_cov;   /* lowest coverage, its truth id (-1: none) */
    long worst_cov_id;
    double worst_mean; /* highest mean distance, its truth id */
    long worst_mean_id;
    double cov_total; /* covered / all samples over all truth lines */
    long n_mixed;     /* traced lines over two truth lines */
    long n_closed_wrong;
    long n_edge_wrong;
    long n_split;            /* truth lines in more than one piece */
    long n_unmatched_traced; /* traced lines mostly > assign_tol from truth */
} td_match_report;

td_match_opts td_match_defaults(void);

/* Compare traced against truth on a w x h sheet per the definitions above
 * (o NULL: defaults).  Fills *r.  When log != NULL, writes one line per
 * failing item with the ids and a position (x,y) to look at.  Returns 0, or
 * TD_ENOMEM. */
int td_match_lines(const td_lines *truth, const td_lines *traced, int w, int h,
                   td_match_opts *o, td_match_report *r, FILE *log);

/* Nonzero when every checked truth line is matched and no line is mixed,
 * split, noise or has a wrong flag. */
int td_match_ok(const td_match_report *r);

/* One summary line of r. */
void td_match_print(const td_match_report *r, FILE *f);


/* Height accuracy of labelled traced lines against the truth: each traced
 * segment (its middle) goes to the nearest truth line within tol px; its
 * length counts as right (the traced line's height is that truth line's),
 * wrong (another height), null (no height) or off (no truth line near).
 * accuracy = right / (right + wrong + null).  A traced line with a height
 * and confidence >= 0.9 whose majority truth height (by length) differs
 * counts in n_wrong_sure. */
typedef struct td_hscore {
    double right, wrong, null_len, off, accuracy;
    long n_lines, n_wrong_sure;
    double wrong_sure_len;
    double right_sure; /* right length on lines with confidence >= 0.9 */
    double err2;       /* sum over labelled length of (height - truth)^2: its
                          root over right + wrong is the lines' height RMSE */
    double own; /* traced length near the line's own (majority) truth line:
                   own / (right + wrong + null) is the share of traced length
                   that stays on its own contour (the scanner's merges) */
} td_hscore;

/* The lines' height RMSE over their labelled length (sqrt of err2 over
 * right + wrong; 0 when nothing is labelled). */
double td_hscore_rmse(const td_hscore *r);

/* Fills *r; log (may be NULL) gets one line per wrong sure line.  Returns 0
 * or TD_ENOMEM. */
int td_match_heights(const td_lines *truth, const td_lines *traced, int w,
                     int h, double tol, td_hscore *r, FILE *log);

/* As td_match_heights, and verdict[i] (traced->n entries, may be NULL) gets
 * line i's majority verdict by length: 0 right, 1 wrong, 2 no height, 3 no
 * truth line near. */
int td_match_heights_v(const td_lines *truth, const td_lines *traced, int w,
                       int h, double tol, td_hscore *r, FILE *log,
                       int *verdict);

/* Scanner quality against the truth (issue 14's measures), all within tol
 * px, both sets sampled every 0.5 px of arc length:
 *  - recall: share of the truth length near some traced line;
 *  - precision: share of the traced length near some truth line;
 *  - own: share of the traced length near truth that lies near its own
 *    line's majority contour (each sample goes to the nearest truth line;
 *    a contour is a level: two truth lines of one height meeting at a
 *    saddle or cut apart by the border are one contour);
 *  - n_jump: traced lines with a run of more than jump_len px (contiguous)
 *    at a height other than their majority one. */
typedef struct td_scanscore {
    double recall, precision, own;
    long n_traced, n_truth, n_jump;
} td_scanscore;

/* Each traced line's true height: the height of the truth lines within
 * tol of most of its samples (every 0.5 px, as td_match_scan's own
 * contour), NAN when none is near, into out[traced->n].  0 or
 * TD_ENOMEM. */
int td_match_majority(const td_lines *truth, const td_lines *traced, int w,
                      int h, double tol, double *out);

/* Fills *r; log (may be NULL) gets one line per jumping traced line (its
 * id, where the run starts, the two truth heights).  Returns 0 or
 * TD_ENOMEM. */
int td_match_scan(const td_lines *truth, const td_lines *traced, int w, int h,
                  double tol, double jump_len, td_scanscore *r, FILE *log);

#endif
