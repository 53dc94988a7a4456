/* model.h: terrain models built another way than from a sheet, to compare
 * reconstructions with: the ridgeline model (paper 000 §2.1-2.4,
 * ridgemodel.c; recursive ridge generation, 2.5, ridgegen.c) and synthetic initial terrains for the erosion
 * experiments (mound.c).
 *
 * The paper's initial terrain (Fujita, Muraoka, Chiba §3, Fig. 2a): a
 * terrain whose centre is a little higher, with white noise added.  Every
 * random value comes from a seeded generator, so the same parameters give
 * the same bytes on every machine. */
#ifndef TD_TERRAIN_GEN_H
#define TD_TERRAIN_GEN_H

#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct td_mound_params {
    int w, h;        /* grid size (512 x 512) */
    double height;   /* mound height at the centre (w / 8) */
    double radius;   /* mound radius as a fraction of min(w, h) / 2 (0.9) */
    double noise;    /* white-noise amplitude as a fraction of height (0.02) */
    uint64_t seed;   /* noise seed (1) */
} td_mound_params;

td_mound_params td_mound_defaults(void);

/* Fill g (caller-allocated, any size; p->w, p->h are not used here) with
 * the mound: height * (1 - r^2)^2 inside the radius, 0 outside, plus
 * uniform white noise in [-noise, +noise] * height.  0 or TD_EINVAL. */
int td_terrain_mound(td_grid_f32 *g, const td_mound_params *p, td_ctx *cx);

/* Add uniform white noise in [-amp, +amp] (height units) from `seed` to
 * every cell that is not nodata.  0 or TD_EINVAL. */
int td_terrain_noise(td_grid_f32 *g, double amp, uint64_t seed, td_ctx *cx);

/* ---- the ridgeline model (ridgemodel.c; ALGORITHMS.md D1) ----
 *
 * Ridge segments (x, y in cells: col, row, 0,0 the top-left corner; z
 * heights) become a DEM by Algorithm 2.1: two skirts sloping away at
 * p->slope from every segment, triangles closing the gaps between the
 * skirts around every node (and beyond free ends), z-buffered keeping the
 * highest, then p->smooth passes of a 3 x 3 mean.  The model keeps its
 * polygons, so segments can be added and deleted and the z-buffer updated
 * in place: Algorithm 2.2 (p->method TD_RM_LISTS: every cell keeps the
 * list of (polygon, height) covering it, highest first) or 2.3
 * (TD_RM_WINNERS: one grid of the winning polygon; a delete re-renders
 * only the cells the deleted polygons won, from the polygons that overlap
 * them).  Either way the z-buffer after any edits equals a full render of
 * the segments left, bit for bit. */
enum { TD_RM_LISTS = 0, TD_RM_WINNERS = 1 };

typedef struct td_ridge_params {
    double slope; /* skirt slope, degrees, (0, 90) (30) */
    double cell;  /* horizontal map units per cell, for the slope (1) */
    double base;  /* height the skirts fall to; cells no polygon covers (0) */
    int smooth;   /* passes of the 3 x 3 mean (1; 0: none) */
    int method;   /* TD_RM_LISTS (2.2) or TD_RM_WINNERS (2.3, default) */
    double snap;  /* end points within this many cells are one node (0.5) */
} td_ridge_params;

typedef struct td_ridgemodel td_ridgemodel;

td_ridge_params td_ridge_defaults(void);
/* An empty model of a w x h grid; NULL with the error in cx (TD_EINVAL:
 * bad size or parameters; TD_ENOMEM). */
td_ridgemodel *td_ridgemodel_new(int w, int h, const td_ridge_params *p,
                                 td_ctx *cx);
void td_ridgemodel_free(td_ridgemodel *m);
/* Add the segment (x0,y0,z0)-(x1,y1,z1); a z may be NaN before
 * td_ridgemodel_tree_heights.  Before the first render only the graph
 * grows; after it the segment is drawn and the fans at its two nodes are
 * redone.  Returns the segment's id (0, 1, ... in order of adding), or -1
 * with the error in cx. */
long td_ridgemodel_add(td_ridgemodel *m, double x0, double y0, double z0,
                       double x1, double y1, double z1, td_ctx *cx);
/* Delete segment s (and redo the fans at its nodes) by p->method.  0 or
 * TD_EINVAL (no such live segment) / TD_ENOMEM. */
int td_ridgemodel_delete(td_ridgemodel *m, long s, td_ctx *cx);
/* The live segment with these end points (either way round, within the
 * snap), or -1. */
long td_ridgemodel_find(const td_ridgemodel *m, double x0, double y0,
                        double x1, double y1);
/* Algorithm 2.4: every end point (degree 1) of each tree gets height
 * leaf, every other node leaf + tan(slope) x cell x its shortest path
 * (cells, along the tree) to an end point: leaves inward to a root, then
 * root outward.  TD_EINVAL when the lines close a cycle (naming where). */
int td_ridgemodel_tree_heights(td_ridgemodel *m, double leaf, td_ctx *cx);
/* Draw every polygon (Algorithm 2.1) into the z-buffer: once, after the
 * segments are in and every node has a height (TD_EINVAL naming a node
 * without one). */
int td_ridgemodel_render(td_ridgemodel *m, td_ctx *cx);
/* The z-buffer M (unsmoothed), owned by the model. */
const td_grid_f32 *td_ridgemodel_zbuffer(const td_ridgemodel *m);
/* A new DEM: the z-buffer after p->smooth passes of the 3 x 3 mean. */
td_grid_f32 *td_ridgemodel_dem(const td_ridgemodel *m, td_ctx *cx);
/* The nodes with segments: x, y, z of up to cap of them into xyz (3 per
 * node); returns how many there are. */
size_t td_ridgemodel_nodes(const td_ridgemodel *m, double *xyz, size_t cap);
/* The live segments: x0 y0 z0 x1 y1 z1 (their nodes') of up to cap of them
 * into v; returns how many there are. */
size_t td_ridgemodel_segments(const td_ridgemodel *m, double *v, size_t cap);

/* ---- recursive ridge generation (ridgegen.c; Algorithm 2.5) ---- */
typedef struct td_ridgegen_params {
    int rounds;            /* rounds of generation (2) */
    uint64_t seed;         /* every random choice (1) */
    double spacing;        /* d of the first round: cells between drops (40) */
    double spacing_factor; /* d times this each round (0.5) */
    double slope_step;     /* degrees the slope rises each round (10) */
    double max_path;       /* longest path of a drop, cells (400) */
} td_ridgegen_params;

td_ridgegen_params td_ridgegen_defaults(void);
/* Grow the ridge segments *segs (*n of them, 6 numbers each: x0 y0 z0 x1
 * y1 z1, cells and heights; realloc'ed) on a w x h grid by p->rounds of
 * Algorithm 2.5, starting at rp->slope; *final_slope (may be NULL) gets
 * the slope of the round after the last, for the final render.  0, or
 * TD_EINVAL / TD_ENOMEM with *segs still valid. */
int td_ridgegen(double **segs, size_t *n, int w, int h,
                const td_ridge_params *rp, const td_ridgegen_params *p,
                double *final_slope, td_ctx *cx);

/* ---- the straight skeleton of a key outline (skeleton.c; paper 004) ---- */
typedef struct td_skeleton_params {
    double contour_step; /* time (distance shrunk, cells) between contours;
                            0: none (0) */
    size_t max_events;   /* give up after this many events (1000000) */
    td_lines *nodes;     /* when set: one point per skeleton node (where
                            vertices meet, a split lands, a polygon ends),
                            height = its time; repeats possible (NULL) */
    int construction;    /* TD_SKEL_QUEUE (ours: the same events from a
                            queue, O(n log n)-ish) or TD_SKEL_PAPER (the
                            paper's: every step searches all, O(n^3))
                            (TD_SKEL_QUEUE) */
} td_skeleton_params;

enum { TD_SKEL_PAPER, TD_SKEL_QUEUE };

typedef struct td_skeleton_stats {
    size_t events, splits; /* steps taken; split events among them */
    double max_time;       /* when the last polygon shrank away (cells) */
} td_skeleton_stats;

td_skeleton_params td_skeleton_defaults(void);
/* Shrink the outline xy (n points x, y in cells, a ring, either way
 * round; not crossing itself) by the paper's construction.  dem (may be
 * NULL; cells set to nodata first by the caller) gets the roof: the time
 * (distance, cells) at which the front passed each cell inside; contours
 * (may be NULL) gets the shrunk polygons every p->contour_step, closed,
 * with height = their time; peaks (may be NULL) one point where each
 * polygon shrank away, height = that time.  0, TD_EINVAL (fewer than 3
 * points, a crossing, no area, non-finite), TD_ENOMEM. */
int td_skeleton(const double *xy, size_t n, const td_skeleton_params *p,
                td_grid_f32 *dem, td_lines *contours, td_lines *peaks,
                td_skeleton_stats *st, td_ctx *cx);

/* The paper's surface (004 §3, tin.c): each ring of `rings` (closed, with
 * a height: the contours) smoothed as a closed uniform cubic B-spline with
 * its corners as control points and sampled every `spacing` cells; the
 * outline (edges sampled every `spacing`, at base) and the peaks (points
 * with heights) as they are; all Delaunay-triangulated (OpenCV Subdiv2D)
 * and the triangles' planes written into the cells of dem that have data
 * (the outline's inside).  0, TD_EINVAL, TD_ENOMEM. */
int td_skeleton_tin(const double *outline, size_t n, double base,
                    const td_lines *rings, const td_lines *peaks,
                    double spacing, td_grid_f32 *dem, td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
