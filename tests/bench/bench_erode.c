/* bench_erode: velocity-field erosion on generated mounds of 1024x1024 and
 * 2048x1024, with 1 and 2 threads, several steps (default 5) timed as one
 * run: particle moves per second (one move = one dt update of one
 * particle) by the wall clock and per core by the process CPU time (CPU
 * seconds / threads: on a shared machine the wall clock also counts the
 * time other programs held the cores), cell-steps per second, mean
 * particle path length, mass-balance residual, and whether 2 threads gave
 * the same bytes as 1.
 *
 *   bench_erode [--steps N] [--size WxH] [--threads T] [--dir DIR]
 *               [--topodig PATH]
 *
 * --size runs only that grid, --threads only that thread count (for
 * shorter experiments, or two builds side by side on two cores); the last
 * two options are unused.
 *
 * Never fails the build. */
#ifndef _DEFAULT_SOURCE
#define _DEFAULT_SOURCE /* getloadavg */
#endif
#include "src/erode/erode.h"
#include "src/model/model.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* CPU seconds of the whole process (all threads). */
static double cpu_now(void)
{
    struct timespec ts;
    if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts) != 0)
        return 0;
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int only_threads; /* --threads: this count only, no comparison */

static void one(int w, int h, int threads, int steps, float *ref)
{
    td_mound_params mp = td_mound_defaults();
    td_erode_params p = td_erode_defaults();
    td_grid_f32 *g = td_grid_f32_new(w, h, NULL), *o = td_grid_f32_new(w, h, NULL);
    td_erode_stats st;
    td_ctx cx;
    double t0, c0, s, cpu;
    td_ctx_init(&cx);
    if (!g || !o)
        goto done;
    mp.height = (w < h ? w : h) / 8.0;
    td_terrain_mound(g, &mp, NULL);
    p.steps = steps;
    p.threads = threads;
    t0 = td_now();
    c0 = cpu_now();
    if (td_erode_run(g, &p, o, NULL, &st, &cx) != 0) {
        printf("  %dx%d: %s\n", w, h, td_errmsg(&cx));
        goto done;
    }
    s = td_now() - t0;
    cpu = cpu_now() - c0;
    printf("  %4dx%-4d %d thr %d steps %7.2f s (cpu %7.2f s)  %6.1f M "
           "moves/s  %6.1f M moves/cpu-s per core  %7.2f M cell-steps/s  "
           "path %6.1f moves  residual %.1e%s\n",
           w, h, threads, steps, s, cpu, st.total.moves / s / 1e6,
           cpu > 0 ? st.total.moves / cpu / 1e6 : 0.0,
           (double)w * h * steps / s / 1e6, st.path_mean, st.max_residual,
           ref == NULL ? "" : memcmp(ref, o->data, (size_t)w * h * 4) == 0
                                  ? "  same bytes as 1 thread" : "  DIFFERS");
done: /* after the 1-thread run, the 2-thread run compared with it */
    if (ref == NULL && o && threads == 1 && only_threads == 0) {
        float *keep = malloc((size_t)w * h * 4);
        if (keep) {
            memcpy(keep, o->data, (size_t)w * h * 4);
            one(w, h, 2, steps, keep);
            free(keep);
        }
    }
    td_grid_f32_free(g);
    td_grid_f32_free(o);
}

int main(int argc, char **argv)
{
    int steps = 5, i, w = 0, h = 0;
    double load[3] = {0, 0, 0};
    for (i = 1; i + 1 < argc; i += 2)
        if (!strcmp(argv[i], "--steps"))
            steps = atoi(argv[i + 1]) > 0 ? atoi(argv[i + 1]) : 5;
        else if (!strcmp(argv[i], "--size") &&
                 (sscanf(argv[i + 1], "%dx%d", &w, &h) != 2 || w < 1 ||
                  h < 1 || w > 16384 || h > 16384))
            w = h = 0;
        else if (!strcmp(argv[i], "--threads"))
            only_threads = atoi(argv[i + 1]) > 0 ? atoi(argv[i + 1]) : 0;
    if (getloadavg(load, 3) < 1)
        load[0] = -1;
    printf("  velocity-field erosion, default parameters, mound relief "
           "size/8; load average %.2f at start\n", load[0]);
    if (w > 0) {
        one(w, h, only_threads ? only_threads : 1, steps, NULL);
        return 0;
    }
    one(1024, 1024, only_threads ? only_threads : 1, steps, NULL);
    one(2048, 1024, only_threads ? only_threads : 1, steps, NULL);
    return 0;
}
