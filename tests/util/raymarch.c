/* raymarch.c: the brute-force horizon reference of tests and benchmarks. */
#include "tests/util/raymarch.h"

#include <math.h>

/* The bilinear surface of cell [cx, cx+1] x [cy, cy+1] at (x, y). */
static double bil_cell(const td_grid_f32 *g, double x, double y, int cx,
                       int cy)
{
    int x1 = cx + 1 < g->w ? cx + 1 : cx, y1 = cy + 1 < g->h ? cy + 1 : cy;
    double fx = x - cx, fy = y - cy;
    return (1 - fy) * ((1 - fx) * TD_AT(g, cx, cy) + fx * TD_AT(g, x1, cy)) +
           fy * ((1 - fx) * TD_AT(g, cx, y1) + fx * TD_AT(g, x1, y1));
}

/* See raymarch.h.  The ray is cut at every grid-line crossing into pieces
 * on which the bilinear surface is a quadratic z(t) = al + be t + ga t^2;
 * the tangent (z - z0) / t is maximised on each piece exactly: its ends,
 * the interior critical point t* = sqrt((al - z0) / ga), and the initial
 * slope be on the first piece. */
double tr_exact_march(const td_grid_f32 *g, int x, int y, double az,
                          double cs)
{
    double dx = sin(az * M_PI / 180), dy = -cos(az * M_PI / 180);
    double z0 = TD_AT(g, x, y), best = 0, ta = 0, tx, ty, ex, ey;
    int first = 1;
    dx = fabs(dx) < 1e-12 ? 0 : dx;
    dy = fabs(dy) < 1e-12 ? 0 : dy;
    ex = dx > 0 ? (g->w - 1 - x) / dx : dx < 0 ? x / -dx : HUGE_VAL;
    ey = dy > 0 ? (g->h - 1 - y) / dy : dy < 0 ? y / -dy : HUGE_VAL;
    ex = fmin(ex, ey);
    tx = dx != 0 ? 1 / fabs(dx) : HUGE_VAL;
    ty = dy != 0 ? 1 / fabs(dy) : HUGE_VAL;
    while (ta < ex - 1e-12) {
        double tb = fmin(fmin(tx, ty), ex), tm = 0.5 * (ta + tb), h = tb - ta;
        int cx = (int)floor(x + tm * dx), cy = (int)floor(y + tm * dy);
        double za, zm, zb, al, be, ga;
        cx = cx > g->w - 2 ? g->w - 2 : cx;
        cy = cy > g->h - 2 ? g->h - 2 : cy;
        cx = cx < 0 ? 0 : cx;
        cy = cy < 0 ? 0 : cy;
        za = bil_cell(g, x + ta * dx, y + ta * dy, cx, cy);
        zm = bil_cell(g, x + tm * dx, y + tm * dy, cx, cy);
        zb = bil_cell(g, x + tb * dx, y + tb * dy, cx, cy);
        ga = (za - 2 * zm + zb) * 2 / (h * h);
        be = (zb - za) / h - ga * (ta + tb);
        al = za - be * ta - ga * ta * ta;
        if (first)
            best = fmax(best, be / cs);
        first = 0;
        best = fmax(best, (zb - z0) / (tb * cs));
        if (ga < 0 && al - z0 < 0) {
            double ts = sqrt((al - z0) / ga);
            if (ts > ta && ts < tb)
                best = fmax(best, ((al - z0) / ts + be + ga * ts) / cs);
        }
        ta = tb;
        if (tx - tb < 1e-9)
            tx += 1 / fabs(dx);
        if (ty - tb < 1e-9)
            ty += 1 / fabs(dy);
    }
    return atan(best) * 180 / M_PI;
}

