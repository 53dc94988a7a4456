/* label.h: automatic contour heights from a few known points
 * (ALGORITHMS.md A.5 (b); ours — the paper, 001 §2.3, has the operator type
 * every height, which is the CLI's --interactive).
 *
 * Model.  The containment tree (contain.h) cuts the sheet into faces: the
 * root face (holding the sheet's top-left corner) and the inside of each
 * line minus its children.  A face has an integer level k: its ground lies
 * between base + k*I and base + (k+1)*I.  Across a line the level changes
 * by d = +1 or -1 (inside minus outside), and the line's height is
 * base + I * max(level inside, level outside).  Defaults:
 *   - a closed ring: d = +1 (a child is higher than its parent), so the
 *     rings of one face at a saddle get the same height;
 *   - --depressions X,Y: the innermost ring around the point and each ring
 *     enclosing it that is closed and has that one child: d = -1;
 *   - border-closed lines: a face bounded by exactly two border-closed
 *     lines is a slope strip: its two lines differ by one interval (they
 *     flip together as one unit).
 * Known points: points on lines and spot heights off a multiple of the
 * interval first, then spots exactly on a multiple (their face may be at
 * either level: the summit reaching it or the foot of the rings inside).
 * The first fixes the levels; each further point is met by flipping the
 * fewest units among its line, the tree path between it and the first
 * point and the first point's line (the nearest to the new point when
 * there is a choice), never a unit an earlier point relied on.  Still one
 * interval off: a contour is taken as missing next to the path line with
 * the widest gap to the next line out (when 1.5 times the usual gap; a
 * warning).  Otherwise the points contradict (an error naming both and
 * their lines). */
#ifndef TD_LABEL_H
#define TD_LABEL_H

#include "scanner/ocr.h"
#include "scanner/streams.h"
#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The most intervals a known height may lie from the base. */
#define TD_LABEL_MAX_LEVELS 1e6

typedef struct td_label_point {
    double x, y;   /* scan pixel coordinates (ignored when id >= 0) */
    double height;
    long id;       /* >= 0: the line with this id (a heights file row);
                      -1: located by position */
} td_label_point;

typedef enum td_labeller {
    TD_LABEL_FACES = 0, /* one global solve over the faces (heights.c) */
    TD_LABEL_TREE       /* the containment tree (label.c; the old default) */
} td_labeller;

/* Free-end pairs on colour scans by default (td_label_params.gap_pairs;
 * measured in docs/label.md). */
#define TD_GAP_PAIRS_COLOUR 24.0

typedef struct td_label_params {
    td_labeller method;    /* default TD_LABEL_FACES */
    double base, interval; /* heights are base + k * interval; interval > 0 */
    int w, h;              /* sheet size in px (for border closing) */
    double near;           /* a known point within this many px of a line is
                              on it (default 3) */
    double far;            /* a spot height farther than this from every line
                              is warned about (default 150) */
    const td_label_point *known;
    size_t nknown;
    const double *depressions; /* x,y pairs */
    size_t ndepressions;
    const uint8_t *skeleton; /* faces: the scanner's skeleton, w x h packed
                                (td_scan_result.skel_bits; NULL: none):
                                   probes across skeleton ink that no line
                                   was traced on are steps, not one face
                                   (faces.h, docs/label.md) */
    const td_lines *walls; /* where the scanner cut lines out of a blob of
                              crowded contours (td_scan_result.walls): no
                              face runs through them; NULL: none */
    int index_every;       /* index contours every this many levels (base +
                              k * index_every * interval), drawn thicker:
                              td_label_check_index; 0 = no check (default).
                              Faces: 0 lets the solve pick the spacing the
                              line widths fit best (5, 4, 10 or 2; none
                              when the widths show no thicker lines), as
                              with the interval inferred */
    int index_off;         /* faces: the widths are not used at all (the
                              benches' known points alone; default 0) */
    double thick_ratio;    /* thick / thin mean width at least this for the
                              widths to tell index lines (default 1.3) */
    int missing;           /* a known point one interval off the nesting
                              across a gap 1.5 times the usual: a missing
                              contour (warned), not a contradiction
                              (default 1) */
    td_ocr_read *labels;   /* faces: printed labels read from the sheet
                              (scanner/ocr.h); each gets used / why */
    size_t nlabels;
    const td_vee *vees; /* faces: where streams cross the lines, their
                           Vs pointing uphill (scanner/streams.h) */
    size_t nvees;
    int index_auto;        /* index_every was inferred: no warning when the
                              widths show no thick lines */
    int label_up;          /* faces: a label's top faces uphill, as printed
                              maps draw them (default 1; 0: the reading
                              direction says nothing) */
    double gap_pairs;      /* faces: free ends at most this many px apart
                              that face each other are taken as one
                              contour (endpair.h; ours; 0: off; < 0,
                              the default: TD_GAP_PAIRS_COLOUR on a colour
                              scan, where roads and streams cut the
                              contours, off on grey; docs/label.md) */
    int colour;            /* the lines come from a colour scan (for
                              gap_pairs < 0) */
    const double *oracle_h; /* benchmarks (faces): per line of ls, its true
                               height (NAN: unknown), and ... */
    const signed char *oracle_up; /* ... 1 when its side 0 (left of its
                                     direction, y down) is the higher:
                                     rep.oracle_cost prices the truth */
    int oracle_ties;       /* benchmarks (faces, with oracle_h): also list
                              the ties the answer and the truth pay
                              differently (rep.oracle_ties) */
    int search;            /* faces: 0 the forest's best (default); N > 0
                              also N forests in other orders and a local
                              search over every face edge, the cheapest
                              under the whole model kept (ours, slower;
                              docs/label.md, "The search") */
} td_label_params;

/* The parts of the whole model's cost that td_label_report.oracle_cost
 * prices (faces labeller): the total, broken face edges, folds (a face
 * whose two lines step the same way), folds between a ring and a ring it
 * holds, broken continuity edges (a line's pieces, free-end pairs), the
 * lines' index widths, printed labels, known points on them, their
 * directions (stream Vs, ticks, the ring priors), and the unary terms
 * (spot heights, known points off the lines). */
enum td_oracle_term {
    TD_OT_TOTAL,
    TD_OT_FACE,
    TD_OT_FOLD,
    TD_OT_NEST,
    TD_OT_CONT,
    TD_OT_INDEX,
    TD_OT_LABEL,
    TD_OT_KNOWN,
    TD_OT_DIR,
    TD_OT_UNARY,
    TD_OT_N
};

/* One tie the answer and the true heights pay differently (benchmarks,
 * td_label_params.oracle_ties): its part of the model (td_oracle_term,
 * as the one that pays more classes it), what each pays, and the lines
 * at its two ends (their ids, and the middle vertex of the chunk there;
 * a line's own terms: both ends the same). */
typedef struct td_oracle_tie {
    int term;
    double answer, truth;
    long id[2];
    double x[2], y[2];
} td_oracle_tie;

typedef struct td_label_report {
    size_t labelled, undetermined, warnings;
    size_t index_mismatches; /* td_label_check_index: lines whose width
                                disagrees with their height */
    long *undetermined_ids; /* ids of the lines left without a height */
    size_t short_lines;     /* of those, lines too short to take part
                               (faces: under 12 px of arc, specks) */
    size_t pieces_left;     /* of those, the scanner's short pieces
                               (td_line.piece) whose ends gave no one
                               height (faces) */
    size_t assumed;         /* labelled lines whose up/down (d) is only the
                               default: not between two known points, not
                               a --depressions ring */
    long *assumed_ids;
    char *text;             /* warnings, one per line ('\n'), or NULL */
    size_t by_source[5];    /* labelled lines per td_hsource (faces) */
    size_t conflicts;       /* face edges the solution breaks (faces) */
    size_t known_broken;    /* known points the solution overrode (faces) */
    size_t split;           /* lines cut where their height changes: two
                               contours traced as one (faces) */
    size_t labels_used;     /* printed labels the solution agrees with */
    size_t vees;            /* streams' Vs on the lines solved (faces) */
    size_t gaps_closed;     /* td_label_close_gaps: lines joined across a
                               label (run) */
    double interval;        /* the interval used (inferred from the labels
                               when the parameters gave none) */
    double cost;            /* the solution's total cost (faces) */
    double spacing;         /* px between neighbouring contours (faces):
                               the probes' median length, weighted by
                               their count; 0 when no probe met a line */
    double oracle_cost[2][TD_OT_N]; /* p.oracle_h: the whole model's cost
                                       (every line, unary term and edge,
                                       the priors in) of the answer [0]
                                       and of the true heights [1] (lines
                                       without one as answered): the total
                                       and its parts (td_oracle_term) */
    td_oracle_tie *oracle_ties;     /* p.oracle_ties: noracle_ties of them,
                                       in the model's order */
    size_t noracle_ties;
} td_label_report;

/* Defaults: base 0, interval 0 (must be set), w = h = 0 (must be set),
 * near 3, far 150, no points, index_every 0, thick_ratio 1.3, missing 1. */
td_label_params td_label_defaults(void);

/* Give every line of ls its parent (containment) and, when p has known
 * points, its height; lines that cannot get one keep has_height 0 and are
 * listed in rep.  Fills *rep (free with td_label_report_free).  Returns 0,
 * TD_EINVAL (bad parameters, a known point off the sheet or off every
 * region, contradictory known points: the message names the points and
 * the line ids; no interval inferred: every line is then left without a
 * height) or TD_ENOMEM. */
int td_label_auto(td_lines *ls, const td_label_params *p,
                  td_label_report *rep, td_ctx *cx);

void td_label_report_free(td_label_report *rep);

/* After td_label_auto (faces, with printed labels; ours): for every
 * label the solve used, the nearest open line ends on either side of the
 * text (along its reading direction, within half its length + 2 digit
 * heights of its middle, heading towards it), of lines at the label's
 * height, become one line through the label's middle: the joiner leaves
 * a label gap open where the line bends under the text, and the
 * interpolation then leaks through it.  A ring the label cut open (both
 * ends one line's) is closed through the middle.  The first line keeps
 * its id; the reads' line indexes follow.  *closed gets the number of
 * gaps closed.  Returns 0 or TD_ENOMEM. */
int td_label_close_gaps(td_lines *ls, td_ocr_read *reads, size_t nreads,
                        size_t *closed, td_ctx *cx);

/* Lines of one height joined across the breaks between their ends (ours,
 * for the interpolation: a break lets it see the next contour through):
 * two open ends of lines with a height (or the two ends of one line),
 * neither on the sheet's border (2 px), each the other's nearest such end
 * within reach px, each line heading towards the other end (within 90
 * degrees), the straight bridge between them crossing no line and no
 * shorter bridge.  Joined lines keep the first's id and the less sure
 * piece's confidence and source; a line whose ends meet is closed when it
 * is at least 3 bridges long.  The reads' line indexes follow (reads may
 * be NULL with nreads 0).  *closed gets the number of breaks closed.
 * Returns 0, TD_ENOMEM or TD_ETOOBIG. */
int td_label_close_breaks(td_lines *ls, int w, int h, double reach,
                          td_ocr_read *reads, size_t nreads, size_t *closed,
                          td_ctx *cx);

/* Whether a line of ls (open) ends more than 2 px inside the w x h
 * sheet: only then has td_label_close_breaks a break to bridge. */
int td_label_inner_ends(const td_lines *ls, int w, int h);

/* The reach run and interp bridge breaks with by default (ours):
 * TD_BRIDGE_SPACINGS contour spacings (td_label_report.spacing,
 * td_lines_spacing), at least TD_BRIDGE_MIN px and at most
 * TD_BRIDGE_MAX.  Past about five spacings a bridge joins pieces of one
 * height across the bends of other contours (the crowded Front Range
 * sheet, 8-9 px apart: 48 px best); where contours lie far apart the
 * breaks are longer (docs/interp.md, "Breaks bridged"). */
#define TD_BRIDGE_SPACINGS 5.0
#define TD_BRIDGE_MIN 48.0
#define TD_BRIDGE_MAX 160.0
double td_label_bridge_reach(double spacing);

/* Append one warning (printf format, no newline, no prefix) to rep:
 * counted in rep->warnings; the text is best effort (kept when memory
 * runs out). */
void td_label_warn(td_label_report *rep, const char *fmt, ...)
#ifdef __GNUC__
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* A point to name line l by in messages: its middle vertex. */
void td_label_where(const td_line *l, double *x, double *y);

/* The index-contour check (p->index_every > 0): lines with a measured
 * width (td_line.width > 0, scanner/width.h) and at least 30 px long are
 * split into thin and thick by Otsu's rule on their log widths (the thick
 * class 0.4/N to 2.5/N of the lines and at most 1.6/N of their length,
 * N = index_every); when the
 * thick class's mean is at least p->thick_ratio times the thin one's, a
 * thick line whose height is not base + a multiple of index_every *
 * interval, or a thin one whose height is, is a mismatch: one warning each
 * (id, position, width, height), counted in rep->index_mismatches.  When
 * the thick lines fit heights shifted by j intervals better, one more
 * warning says so.  No contrast in the widths, or no widths: one warning,
 * nothing checked.  Returns 0, TD_EINVAL (index_every < 0) or TD_ENOMEM. */
int td_label_check_index(const td_lines *ls, const td_label_params *p,
                         td_label_report *rep, td_ctx *cx);

/* Whether the index contours are told by their ink weight (width times
 * darkness, width.h) rather than their width: the lines are inked
 * (td_lines_inked) and the weights split into two pens more clearly
 * (class means' squared gap over their variances at Otsu's cut of the
 * logs; blur leaves thin lines' middles lighter, so on a new print the
 * weights part the pens that the mask's widths, quantized, mix; where
 * the print fades in patches the widths are the clearer).  1, 0, or
 * TD_ENOMEM. */
int td_label_use_ink(const td_lines *ls, int every, td_ctx *cx);

/* The width that splits ls's lines into thin and thick (as the index check
 * does): 1 and *cut when the widths have that contrast, 0 when not (no
 * widths, or no thicker lines), TD_ENOMEM.  *inked (may be NULL): whether
 * the cut is in ink weights (td_label_use_ink), for td_line_weight. */
int td_label_thick_cut(const td_lines *ls, const td_label_params *p,
                       double *cut, int *inked, td_ctx *cx);

/* How many thin lines lie between two consecutive thick ones (weight >=
 * cut; lines under 30 px or unmeasured break a count) along transects
 * every 16 px, rows and columns, of an h px high sheet: hist[k] (k =
 * 1..20) the counts of k, hist[0] their total (hist: 21 entries).
 * Returns the commonest k (0 when none), or TD_ENOMEM. */
int td_label_index_count(const td_lines *ls, double cut, int inked, int h,
                         long *hist, td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
