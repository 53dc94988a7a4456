/* homotopy.h: ridge and valley lines from contour curvature, and the
 * homotopy interpolation along them (paper 003, ALGORITHMS.md B2),
 * `topodig ridges` and `--method homotopy`.
 *
 *   labelled lines --orient--> higher ground on the left (003 §4)
 *   --spline--> smoothed arc-length curve, C2 cubic spline, kappa(s)
 *   --curvature--> inflection candidates, epsilon test, ridge points
 *   (kappa max on convex stretches), valley points (min on concave)
 *   --ridgelink--> links to the nearest point of the same kind on the
 *   adjacent contour; ridge trees from the lowest contour up, valley
 *   trees from the top down (003 §5)
 *   --homotopy--> per band between two nested contours, F(s,t) =
 *   (1-t) f(s) + t g(U(s)), U piecewise linear between the links;
 *   everything else by the scanline method (fallback).
 *
 * Frames: the library works in the scan's pixel frame (x right, y down,
 * lines.h).  The paper's "higher ground on the left" and the sign of kappa
 * are in a y-up frame (a map as printed): kappa > 0 is convex (a ridge may
 * cross), kappa < 0 concave (a valley).  A ring around a summit then runs
 * counterclockwise on the printed map, i.e. clockwise in pixel rows. */
#ifndef TD_INTERP_HOMOTOPY_H
#define TD_INTERP_HOMOTOPY_H

#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct td_homotopy_params {
    double spacing;   /* resampling step along a contour, px (2) */
    double smooth;    /* Gaussian sigma along the contour, px (3) */
    double epsilon;   /* turning-angle threshold, degrees (20) */
    double link_factor; /* a link may be link_factor x the gap + 4 px (3) */
    double join_factor; /* Suspended join: join_factor x that (2) */
    int fallback;     /* TD_HM_FALLBACK_*: who fills what the homotopy
                         cannot reach (scanline, as the issue asks) */
} td_homotopy_params;

enum { TD_HM_FALLBACK_SCANLINE = 0, TD_HM_FALLBACK_MULTIDIR = 1 };

td_homotopy_params td_homotopy_defaults(void);

enum { TD_RV_RIDGE = 0, TD_RV_VALLEY = 1, TD_RV_INFLECT = 2 };

/* One contour, oriented and resampled.  x,y: smoothed samples (pixel
 * frame); s: each sample's arc length along the oriented input polyline
 * (ox,oy, n_o points, cumulative length ocum); kappa: signed curvature in
 * the y-up frame, 1/px.  orient: +1 kept, -1 reversed, 0 unknown (a line
 * that bounds no region: no points are taken from it). */
typedef struct td_rv_curve {
    long line;       /* index into the input td_lines */
    int closed, orient;
    double z, len;
    size_t n, no;
    double *x, *y, *s, *kappa;
    double *oxy, *ocum;
} td_rv_curve;

typedef struct td_rv_point {
    size_t curve, i; /* sample i of curve */
    double x, y, z, s, kappa;
    int kind;        /* TD_RV_* */
    long tree;       /* ridge / valley tree id, -1 for inflections */
} td_rv_point;

/* A link from point a to point b: ridges and inflections go uphill,
 * valleys downhill.  join: a Suspended ridge (valley) joined to a nearby
 * one (003 §5 Step 4) rather than a nearest-point link. */
typedef struct td_rv_link {
    size_t a, b;
    int kind, join;
} td_rv_link;

typedef struct td_ridges {
    size_t ncurve, npt, nlink;
    td_rv_curve *curve;   /* one per input line, same order */
    td_rv_point *pt;
    td_rv_link *link;
    long *cparent;        /* containment parent per line (td_contain) */
    long nridge, nvalley; /* tree counts */
    size_t suspended;     /* ridge/valley points left without a partner */
} td_ridges;

/* Ridge, valley and inflection points, links and trees of the labelled
 * lines ls on a w x h sheet (pixel units).  *out is new (td_ridges_free).
 * Errors: TD_EINVAL (a line without a height, bad params), TD_ENOMEM. */
int td_ridges_find(const td_lines *ls, int w, int h,
                   const td_homotopy_params *p, td_ridges **out, td_ctx *cx);
void td_ridges_free(td_ridges *r);

/* A ridge, valley or inflection line: a chain of links as 3-D vertices
 * (x, y, height).  Ridge chains end where two ridges merge. */
typedef struct td_rv_path {
    double *xyz;
    size_t n;
    int kind;
    long tree;
} td_rv_path;

/* The links of r chained into paths (*out: free with td_rv_paths_free).
 * Returns 0 or TD_ENOMEM. */
int td_ridges_paths(const td_ridges *r, td_rv_path **out, size_t *n,
                    td_ctx *cx);
void td_rv_paths_free(td_rv_path *v, size_t n);


/* What td_homotopy_fill did, in DEM cells. */
typedef struct td_homotopy_stats {
    size_t cells_line;     /* on a contour (rasterised) */
    size_t cells_homotopy; /* interpolated along the homotopy */
    size_t cells_fallback; /* by the fallback method */
    size_t cells_none;     /* left undetermined */
    size_t bands, bands_homotopy; /* bands; those between two lines */
    size_t bands_branching; /* branching faces partly filled */
    size_t ridge_points, valley_points, links;
} td_homotopy_stats;

/* Fill g (td_rasterise_lines output for ls at `step`, on a w x h pixel
 * scan) by the homotopy in every band two lines bound (and in part in
 * branching faces, homotopy.c), then the cells it cannot reach from a
 * second grid filled from the contours alone by td_scanline_fill
 * (interval, summit, peninsula as in scanline.h) or, with p->fallback
 * multidir, td_multidir_fill (its defaults, interval and summit).  st may
 * be NULL.  Uses about 4 bytes per scan pixel and 4 per cell beside g.
 * Returns 0, TD_EINVAL, TD_ENOMEM, TD_ECANCEL. */
int td_homotopy_fill(td_grid_f32 *g, const td_lines *ls, int w, int h,
                     int step, const td_homotopy_params *p, double interval,
                     int summit, int peninsula, td_homotopy_stats *st,
                     td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
