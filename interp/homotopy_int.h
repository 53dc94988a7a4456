/* homotopy_int.h: what the files of the homotopy stage share (orient.c,
 * spline.c, curvature.c, ridgelink.c, rvpaths.c, homotopy.c). */
#ifndef TD_INTERP_HOMOTOPY_INT_H
#define TD_INTERP_HOMOTOPY_INT_H

#include "interp/homotopy.h"
#include "src/core/core.h"

#include <stdint.h>

/* Orientation of every line (orient.c): +1 keep, -1 reverse so that higher
 * ground lies on the left in the y-up frame, 0 when the line bounds no
 * region or no neighbour tells which side is higher. */
void hm_orient(const td_lines *ls, const td_contain *ct, int *orient);

/* Band labels (orient.c): lab[r*w + c] = index of the innermost region
 * (td_contain ring) holding the centre of cell (c,r), -1 for none; the
 * rings are scaled by 1/scale first.  lab has w*h entries.  0 or
 * TD_ENOMEM. */
int hm_label(const td_contain *ct, int w, int h, double scale, int32_t *lab,
             td_ctx *cx);

/* The curve of line l (spline.c): oriented copy, resampled, smoothed,
 * cubic spline derivatives and kappa.  0 or TD_ENOMEM. */
int hm_curve_build(const td_line *l, long index, int orient,
                   const td_homotopy_params *p, td_rv_curve *c, td_ctx *cx);
void hm_curve_free(td_rv_curve *c);
/* The oriented input polyline at arc length s (wrapped on rings, clamped
 * on open lines). */
void hm_curve_at(const td_rv_curve *c, double s, double *x, double *y);
/* The same, starting the search at segment *hint (updated): fast when s
 * grows in small steps. */
void hm_curve_at_hint(const td_rv_curve *c, double s, double *x, double *y,
                      size_t *hint);

/* Ridge, valley and inflection points of curve ci appended to r->pt
 * (curvature.c).  0 or TD_ENOMEM. */
int hm_points(td_ridges *r, size_t ci, const td_homotopy_params *p,
              size_t *cap, td_ctx *cx);

/* Links and trees (ridgelink.c).  lab: band labels at scale 1, w x h. */
int hm_link(td_ridges *r, const td_contain *ct, const int32_t *lab, int w,
            int h, const td_homotopy_params *p, td_ctx *cx);

/* td_ridges_find keeping its containment tree (*ct, zeroed by the
 * caller, td_contain_free after) and band labels (lab: w*h, scale 1). */
int hm_find(const td_lines *ls, int w, int h, const td_homotopy_params *p,
            td_ridges **out, td_contain *ct, int32_t *lab, td_ctx *cx);

#endif
