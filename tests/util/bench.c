/* What the benchmarks share (bench.h). */
#include "tests/util/bench.h"
#include "src/io/io.h"

#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <stdio.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

/* Contract in bench.h. */
int td_bench_ridges_sheet(const char *path, int size, td_lines **truth,
                          td_ctx *cx)
{
    td_gen_params gp = td_gen_defaults();
    td_image *im = NULL;
    td_grid_u8 g;
    struct stat sb;
    int rc, have = stat(path, &sb) == 0;
    if (have && !truth)
        return 0;
    gp.w = gp.h = size;
    gp.terrain = TD_GEN_RIDGES;
    gp.line_width = 3.0;
    gp.seed = 7;
    fprintf(stderr, "generating %dx%d sheet %s ...\n", size, size, path);
    if ((rc = td_gen_sheet(&gp, &im, truth, NULL, cx)) != 0 || have)
        goto done;
    g.w = im->w;
    g.h = im->h;
    g.stride = im->stride;
    g.data = im->data;
    rc = td_geotiff_write_u8(path, &g, NULL, cx);
done:
    td_image_free(im);
    return rc;
}

/* Contract in bench.h. */
int td_bench_child(char *const argv[], const char *err_path, double *secs,
                   double *peak, double *cpu)
{
    double t0 = td_now();
    struct rusage ru;
    int status;
    pid_t pid;
    fflush(stdout);
    fflush(stderr);
    pid = fork();
    if (pid == 0) {
        int fo = open("/dev/null", O_WRONLY);
        int fe = open(err_path ? err_path : "/dev/null",
                      O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fo >= 0)
            dup2(fo, 1);
        if (fe >= 0)
            dup2(fe, 2);
        execvp(argv[0], argv);
        _exit(127);
    }
    if (pid < 0 || wait4(pid, &status, 0, &ru) < 0)
        return -1;
    if (secs)
        *secs = td_now() - t0;
    if (peak)
        *peak = (double)ru.ru_maxrss * 1024.0;
    if (cpu)
        *cpu = (double)ru.ru_utime.tv_sec + 1e-6 * (double)ru.ru_utime.tv_usec +
               (double)ru.ru_stime.tv_sec + 1e-6 * (double)ru.ru_stime.tv_usec;
    return WIFEXITED(status) && WEXITSTATUS(status) == 0 ? 0 : -1;
}

/* Contract in bench.h. */
int td_bench_option(int argc, char **argv, int i, int *size,
                    const char **dir, const char **exe)
{
    if (i + 1 >= argc)
        return 0;
    if (!strcmp(argv[i], "--size"))
        *size = atoi(argv[i + 1]);
    else if (!strcmp(argv[i], "--dir"))
        *dir = argv[i + 1];
    else if (!strcmp(argv[i], "--topodig"))
        *exe = argv[i + 1];
    else
        return 0;
    return 1;
}

/* See bench.h. */
int td_bench_usage(const char *prog, const char *arg, const char *usage)
{
    if (!strcmp(arg, "--help") || !strcmp(arg, "-h")) {
        fputs(usage, stdout);
        return 0;
    }
    fprintf(stderr, "%s: unknown option '%s'\n%s", prog, arg, usage);
    return 2;
}

/* See bench.h. */
int td_bench_outdir(const char *prog, const char *dir)
{
    char p[4096];
    size_t i, n = strlen(dir);
    struct stat st;
    if (n == 0 || n >= sizeof p)
        goto fail;
    memcpy(p, dir, n + 1);
    for (i = 1; i <= n; i++) /* each parent, then the folder itself */
        if (p[i] == '/' || p[i] == 0) {
            char c = p[i];
            p[i] = 0;
            if (mkdir(p, 0777) != 0 &&
                (stat(p, &st) != 0 || !S_ISDIR(st.st_mode)))
                goto fail;
            p[i] = c;
        }
    return 0;
fail:
    fprintf(stderr, "%s: %s: cannot make the folder\n", prog, dir);
    return -1;
}
