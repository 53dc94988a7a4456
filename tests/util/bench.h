/* bench.h: what the benchmarks share: the generated 10000 x 10000 sheet
 * and running a child process for its time and memory. */
#ifndef TD_TEST_BENCH_H
#define TD_TEST_BENCH_H

#include "samples/gen/gen.h"

/* Make the benchmark sheet at path unless it exists: TD_GEN_RIDGES,
 * size x size, 3-px lines, seed 7, an 8-bit Deflate TIFF.  With truth
 * non-NULL the sheet is generated (again) and its truth lines returned
 * (free with td_lines_free).  0, or an error in cx. */
int td_bench_ridges_sheet(const char *path, int size, td_lines **truth,
                          td_ctx *cx);

/* Run argv[0] with argv; its stderr to err_path (NULL: /dev/null), its
 * stdout to /dev/null.  *secs gets the wall seconds, *peak the peak
 * resident bytes, *cpu the user + system seconds (any may be NULL).
 * Returns 0 when it exits 0, else -1. */
int td_bench_child(char *const argv[], const char *err_path, double *secs,
                   double *peak, double *cpu);

/* The common options at argv[i] (--size N, --dir DIR, --topodig PATH;
 * each needs its value at argv[i + 1]): stored, and 1 returned; 0 when
 * argv[i] is none of them. */
int td_bench_option(int argc, char **argv, int i, int *size,
                    const char **dir, const char **exe);

/* argv[i] is no option the benchmark knows: --help or -h print usage
 * (stdout) and give 0; anything else is named on stderr with the usage
 * and gives 2 (a mistyped option must not start a long run). */
int td_bench_usage(const char *prog, const char *arg, const char *usage);

/* An output folder (--png, --out, --dir): made with its parents unless it
 * exists; 0, or -1 with the reason on stderr (before a run of minutes, not
 * after it). */
int td_bench_outdir(const char *prog, const char *dir);

#endif
