/* contain.h: the containment tree of contour lines (ALGORITHMS.md A.5 (b)).
 *
 * Every line becomes a region: a closed line bounds its inside; an open line
 * whose two ends lie on the sheet border (within TD_CONTAIN_BORDER px) is
 * closed along the border, always the way that does NOT pass the sheet's
 * top-left corner (0,0), so that corner lies outside every region and the
 * nesting of border-closed lines is consistent across the sheet.  The
 * parent of a line is the smallest region containing it.  Open lines with
 * an end inside the sheet (unjoined breaks) bound no region. */
#ifndef TD_CONTAIN_H
#define TD_CONTAIN_H

#include "src/core/lines.h"

#ifdef __cplusplus
extern "C" {
#endif

#define TD_CONTAIN_BORDER 3.0 /* px: an open end this near the border is on it */

typedef struct td_contain {
    size_t n;         /* = number of lines */
    long *parent;     /* index of the enclosing line, -1: none (root),
                         -2: the line bounds no region (dangling) */
    double *area;     /* region area in px^2 (0 when dangling) */
    td_lines *rings;  /* the regions' outlines, closed, same order */
} td_contain;

/* Build the tree of ls on a w x h sheet.  Fills *ct (free with
 * td_contain_free).  Returns 0, TD_EINVAL (w or h < 1) or TD_ENOMEM. */
int td_contain_build(const td_lines *ls, int w, int h, td_contain *ct,
                     td_ctx *cx);
void td_contain_free(td_contain *ct);

/* Index of the innermost region containing (x,y), -1 when none. */
long td_contain_locate(const td_contain *ct, double x, double y);

/* Distance from (x,y) to the nearest segment of line l (closing segment
 * included when closed). */
double td_contain_dist(const td_line *l, double x, double y);

/* Two lines crossing (contours never do: a tracing or joining error). */
typedef struct td_crossing {
    long a, b;   /* the two lines' ids, a < b */
    double x, y; /* where (the first crossing found) */
} td_crossing;

/* Every pair of different lines of ls whose segments cross, each pair once
 * (at one of its crossings), through a bucket grid of segments.  Segments
 * are half-open, so a line through a vertex of the other counts once; two
 * lines touching at a vertex count too (contours do not touch either,
 * cliffs aside).  *out (free()) and *n.  Returns 0 or TD_ENOMEM. */
int td_contain_crossings(const td_lines *ls, td_crossing **out, size_t *n,
                         td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
