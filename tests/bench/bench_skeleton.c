/* bench_skeleton: the straight skeleton of a key outline (src/model): the
 * event queue (skeleton_queue.c, the default) against the paper's
 * construction (skeleton.c) on outlines of 1,000 to 10,000 corners: a
 * wavy ring with jitter (a traced contour: small bends, most corners
 * reflex or nearly straight) and a random star (random radii at sorted
 * random angles: deep reflex corners, many split events).  Seconds per
 * skeleton with the roof drawn into a DEM.  Numbers for docs/models.md.
 *
 *   bench_skeleton [--max N] */
#include "src/model/model.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static uint64_t rng = 0x2545F4914F6CDD1Du;
static double urand(void)
{
    rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
    return (double)(rng >> 11) / 9007199254740992.0;
}

static int by_value(const void *a, const void *b)
{
    double u = *(const double *)a, v = *(const double *)b;
    return (u > v) - (u < v);
}

/* n corners in a 1000 x 1000 frame. */
static void outline(int star, int n, double *xy)
{
    double *a = malloc((size_t)n * sizeof *a);
    int i;
    for (i = 0; i < n; i++)
        a[i] = star ? urand() * 2 * M_PI : 2 * M_PI * i / n;
    qsort(a, (size_t)n, sizeof *a, by_value);
    for (i = 0; i < n; i++) {
        double r = star ? 150 + 330 * urand()
                        : 360 * (1 + 0.2 * sin(5 * a[i]) +
                                 0.06 * sin(37 * a[i])) + 3 * (urand() - 0.5);
        xy[2 * i] = 500 + r * cos(a[i]), xy[2 * i + 1] = 500 + r * sin(a[i]);
    }
    free(a);
}

static double run(const double *xy, int n, int con, td_skeleton_stats *st)
{
    td_skeleton_params p = td_skeleton_defaults();
    td_grid_f32 *g = td_grid_f32_new(1000, 1000, NULL);
    td_ctx cx;
    double t0;
    size_t i;
    int rc;
    td_ctx_init(&cx);
    g->has_nodata = 1, g->nodata = -9999;
    for (i = 0; i < (size_t)1000 * 1000; i++)
        g->data[i] = -9999;
    p.construction = con;
    t0 = td_now();
    rc = td_skeleton(xy, (size_t)n, &p, g, NULL, NULL, st, &cx);
    t0 = td_now() - t0;
    if (rc)
        printf("   (failed: %s)\n", td_errmsg(&cx));
    td_grid_f32_free(g);
    return rc ? NAN : t0;
}

int main(int argc, char **argv)
{
    static const int sizes[] = {1000, 3000, 10000};
    int a, k, star, max = 10000, paper_max = 1000;
    for (a = 1; a < argc; a++)
        if (!strcmp(argv[a], "--max") && a + 1 < argc)
            max = atoi(argv[++a]);
        else if (!strcmp(argv[a], "--topodig") || !strcmp(argv[a], "--dir"))
            a++; /* make bench's common options */
    printf("%-6s %7s %7s %7s  %9s %9s %7s\n", "shape", "corners", "events",
           "splits", "queue s", "paper s", "ratio");
    for (star = 0; star < 2; star++)
        for (k = 0; k < 3 && sizes[k] <= max; k++) {
            int n = sizes[k];
            double *xy = malloc(2 * (size_t)n * sizeof *xy), tq, tp = NAN;
            td_skeleton_stats st;
            outline(star, n, xy);
            tq = run(xy, n, TD_SKEL_QUEUE, &st);
            if (n <= paper_max)
                tp = run(xy, n, TD_SKEL_PAPER, NULL);
            printf("%-6s %7d %7zu %7zu  %9.3f ", star ? "star" : "wavy", n,
                   st.events, st.splits, tq);
            if (isnan(tp))
                printf("%9s %7s\n", "-", "-");
            else
                printf("%9.3f %6.0fx\n", tp, tp / tq);
            fflush(stdout);
            free(xy);
        }
    return 0;
}
