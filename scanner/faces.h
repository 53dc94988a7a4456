/* faces.h: which contour lines border one face, found by probes
 * (ALGORITHMS.md A.5, "faces"; ours).
 *
 * Every line has two sides: side 0 on the left of its direction of travel
 * as seen on the screen (y down), side 1 on the right.  Lines are cut into
 * chunks along their arc (p->chunk_len; one chunk per line by default), and
 * side node 2c + s is side s of chunk c (chunks are numbered line by line,
 * in order along each line).  A probe leaves line i perpendicular to it, from
 * one side, and runs straight until it meets the first other line (or the sheet
 * border):
 *
 *        line m  ------------<------------      the probe meets m's side
 *                            ^                  that faces where it came
 *                            |  probe           from: both sides border
 *        line i  ---->-------+--------->        one face, so they lie in
 *                         (from side 0)         one band of heights
 *
 * Probes every p->spacing px along each line (at most 256 a side: longer
 * lines further apart), on both sides, give "same face" edges between side
 * nodes, weighted by the length of line that agrees.  Lines are simplified
 * (Douglas-Peucker, 0.6 px) for the index and the probes: traced lines are
 * pixel staircases, and their runs cost time, not accuracy.  Unlike faces cut from a raster, a gap in a line (a label gap left
 * open, a break) does not merge two faces: only the few probes that pass
 * exactly through the gap say so, and they are outvoted (the solver keeps
 * the strongest edges, heights.c).  The same index answers "which sides
 * face this point" for spot heights and known points. */
#ifndef TD_FACES_H
#define TD_FACES_H

#include "src/core/core.h"

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct td_face_edge {
    uint32_t a, b; /* side nodes, a < b (a == b never stored) */
    float w;       /* probes that say so, each weighted by its spacing
                      over p->spacing (a line probes at most 256 times a
                      side: longer lines further apart) */
    float x, y;    /* where one of them started (for messages) */
    float hx, hy;  /* and where it met the other line */
    uint32_t step; /* 1: the probes crossed skeleton ink on the way that
                      is no line of the index (td_faces_set_skeleton):
                      contours left untraced lie between the two sides,
                      which are then not one face but a step of one or
                      more levels; kept apart from the probes that did
                      not (the same pair may have both) */
} td_face_edge;

typedef struct td_faces_params {
    double spacing;   /* px between probes along a line (default 4) */
    double min_len;   /* lines shorter than this take no part (default 12) */
    double chunk_len; /* cut lines into chunks of about this many px of
                         arc, each with its own two side nodes; <= 0: one
                         chunk per line (the default) */
} td_faces_params;

typedef struct td_faces td_faces; /* the segment index; opaque */

/* Defaults as listed above. */
td_faces_params td_faces_defaults(void);

/* Index ls on a w x h sheet.  ls must outlive the index.  Returns NULL with
 * the error in cx (TD_EINVAL: w or h < 1; TD_ENOMEM). */
td_faces *td_faces_new(const td_lines *ls, int w, int h,
                       const td_faces_params *p, td_ctx *cx);

/* The same with walls (may be NULL): polylines that stop a probe like the
 * sheet border, with no side of their own (where the scanner cut lines out
 * of a blob of crowded contours, widecut.h: no face runs through it). */
td_faces *td_faces_new_walls(const td_lines *ls, const td_lines *walls, int w,
                             int h, const td_faces_params *p, td_ctx *cx);
void td_faces_free(td_faces *f);

/* The scanner's skeleton (td_scan_result.skel_bits: the sheet's w x h,
 * one bit a pixel, rows of (w + 7) / 8 bytes): its pixels that no used
 * line runs within a pixel of are kept (a copy), and from now on
 * td_faces_edges marks the probes that cross one more than 1.6 px from
 * both their ends (td_face_edge.step).  NULL: off.  Returns 0 or
 * TD_ENOMEM. */
int td_faces_set_skeleton(td_faces *f, const uint8_t *bits, td_ctx *cx);

/* Whether the segment (x0,y0)-(x1,y1) crosses a pixel of that untraced
 * skeleton more than `clear` px from both its ends (0: no skeleton set,
 * or the segment is too short). */
int td_faces_untraced_between(const td_faces *f, double x0, double y0,
                              double x1, double y1, double clear);

/* Nonzero when line i takes part (long enough). */
int td_faces_used(const td_faces *f, size_t i);

/* The length of line i (px, as td_line_length), measured once. */
double td_faces_line_length(const td_faces *f, size_t i);

/* Chunks: how many, the line of chunk c, its first vertex, and the chunk
 * of vertex k of line i (-1 when the line takes no part). */
size_t td_faces_nchunks(const td_faces *f);
size_t td_faces_chunk_line(const td_faces *f, size_t c);
size_t td_faces_chunk_first(const td_faces *f, size_t c);
long td_faces_chunk_at(const td_faces *f, size_t i, size_t k);

/* The "same face" edges of every line's probes, merged per node pair:
 * *out (free()) and *n.  Returns 0 or TD_ENOMEM. */
int td_faces_edges(const td_faces *f, td_face_edge **out, size_t *n,
                   td_ctx *cx);

/* The spacing of the contours: the median length of the probes of the n
 * face edges e (each probe counted by its edge's weight w), into
 * *spacing (0 when there is none).  Returns 0 or TD_ENOMEM. */
int td_faces_spacing(const td_face_edge *e, size_t n, double *spacing,
                     td_ctx *cx);

/* The same for the lines ls on a w x h sheet (their faces with the
 * default parameters, built and freed).  Returns 0 or an error code. */
int td_lines_spacing(const td_lines *ls, int w, int h, double *spacing,
                     td_ctx *cx);

/* The first line met from (x,y) in direction (dx,dy) (any length), not
 * counting line `skip` within `skip_t` px of the start: returns the side
 * node met (2 * chunk + side facing the start) and its distance in *t, or
 * -1 when the ray leaves the sheet first. */
long td_faces_ray(const td_faces *f, double x, double y, double dx, double dy,
                  long skip, double skip_t, double *t);

/* The other lines within r px of (x,y), not counting line `skip`, up to
 * max of them (walls not counted): for each its side node facing the
 * point into nodes[] and its distance into dist[], in no order.  Returns
 * how many. */
int td_faces_near(const td_faces *f, double x, double y, double r, long skip,
                  long *nodes, double *dist, int max);
/* The side nodes around point (x,y): rays in 16 directions; nodes[k] gets
 * the node met by ray k (-1: none).  Returns how many rays met a line. */
int td_faces_around(const td_faces *f, double x, double y, long nodes[16]);

#ifdef __cplusplus
}
#endif
#endif
