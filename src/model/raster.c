/* raster.c: cell spans of convex polygons, the one rasteriser of the
 * models (ridgemodel.c, skeleton.c): a cell belongs to a polygon when its
 * centre does, so two models of the same polygons cover the same cells. */
#include "src/model/model_int.h"

#include <math.h>

int td_convex_span(const double *vx, const double *vy, int nv, int row,
                   int lo, int hi, int *c0, int *c1)
{
    double yc = row + 0.5, a = HUGE_VAL, b = -HUGE_VAL;
    int e;
    for (e = 0; e < nv; e++) {
        double x0 = vx[e], y0 = vy[e];
        double x1 = vx[(e + 1) % nv], y1 = vy[(e + 1) % nv], x;
        if ((y0 > yc) == (y1 > yc))
            continue; /* the centre line misses this edge */
        x = x0 + (yc - y0) / (y1 - y0) * (x1 - x0);
        a = x < a ? x : a, b = x > b ? x : b;
    }
    if (!(a <= b))
        return 0;
    *c0 = (int)ceil(a - 0.5), *c1 = (int)floor(b - 0.5);
    *c0 = *c0 < lo ? lo : *c0, *c1 = *c1 > hi ? hi : *c1;
    return *c0 <= *c1;
}
