/* bench_ridgemodel: the ridgeline model (src/model/ridgemodel.c): a full
 * render by Algorithm 2.1 of a random ridge tree (segments/s, Mcells/s of
 * the grid, polygon cells written per second) and the time of a delete by
 * Algorithm 2.2 (lists) and 2.3 (winners) against a full re-render.
 * Numbers for docs/models.md.
 *
 *   bench_ridgemodel [--segs N] [--size N] */
#include "src/model/model.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static uint64_t rng = 0x9E3779B97F4A7C15u;
static double urand(void)
{
    rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
    return (double)(rng >> 11) / 9007199254740992.0;
}

/* A random tree of n segments of 20-40 cells grown from the centre of a
 * size x size grid (each new segment from a random node, heading away
 * from its parent within 60 degrees); heights by Algorithm 2.4. */
static td_ridgemodel *tree(int n, int size, int method, double *xy,
                           double *secs_build)
{
    td_ridge_params p = td_ridge_defaults();
    td_ridgemodel *m;
    double *dir = malloc((size_t)(n + 1) * sizeof *dir);
    int k, nn = 1;
    p.slope = 30, p.smooth = 0, p.method = method, p.snap = 1e-6;
    m = td_ridgemodel_new(size, size, &p, NULL);
    xy[0] = xy[1] = size / 2.0, dir[0] = 0;
    for (k = 0; k < n; k++) {
        int a, tries = 0;
        double x, y, d;
        do {
            a = (int)(urand() * nn);
            d = dir[a] + (urand() - 0.5) * 2.1;
            if (a == 0)
                d = urand() * 2 * M_PI;
            x = xy[2 * a] + (20 + 20 * urand()) * cos(d);
            y = xy[2 * a + 1] + (20 + 20 * urand()) * sin(d);
        } while ((x < 1 || y < 1 || x > size - 1 || y > size - 1) &&
                 ++tries < 50);
        if (tries >= 50)
            continue;
        xy[2 * nn] = x, xy[2 * nn + 1] = y, dir[nn] = d;
        td_ridgemodel_add(m, xy[2 * a], xy[2 * a + 1], NAN, x, y, NAN, NULL);
        nn++;
    }
    free(dir);
    td_ridgemodel_tree_heights(m, 0.0, NULL);
    {
        double t0 = td_now();
        td_ridgemodel_render(m, NULL);
        *secs_build = td_now() - t0;
    }
    return m;
}

static void run(int nseg, int size, int method)
{
    double *xy = malloc((size_t)(2 * nseg + 2) * sizeof *xy), secs, del = 0;
    td_ridgemodel *m = tree(nseg, size, method, xy, &secs);
    int k, nd = 0;
    for (k = 0; k < 50; k++) { /* 50 random live segments */
        long s = (long)(urand() * nseg);
        double t0 = td_now();
        if (td_ridgemodel_delete(m, s, NULL) == 0)
            nd++;
        del += td_now() - t0;
    }
    printf("%-8s %6d segs %5d^2  render %7.3f s  %8.0f segs/s  %7.1f "
           "Mcells/s  delete %8.3f ms (%d)  render/delete %7.0fx\n",
           method == TD_RM_LISTS ? "lists" : "winners", nseg, size, secs,
           nseg / secs, (double)size * size / secs / 1e6,
           nd ? 1e3 * del / nd : 0.0, nd, nd ? secs / (del / nd) : 0.0);
    td_ridgemodel_free(m);
    free(xy);
}

int main(int argc, char **argv)
{
    int segs = 10000, size = 4000, a;
    for (a = 1; a < argc; a++) {
        if (!strcmp(argv[a], "--segs") && a + 1 < argc)
            segs = atoi(argv[++a]);
        else if (!strcmp(argv[a], "--size") && a + 1 < argc)
            size = atoi(argv[++a]);
        else if (!strcmp(argv[a], "--topodig") || !strcmp(argv[a], "--dir"))
            a++; /* make bench's common options */
    }
    run(segs, size, TD_RM_WINNERS);
    run(segs / 10, size / 4, TD_RM_WINNERS);
    run(segs / 10, size / 4, TD_RM_LISTS);
    return 0;
}
