/* tt.h: the project's small test runner.
 *
 * A test file defines `static void test_x(void)` functions, lists them with
 * TT_RUN in main(), and ends with `return tt_summary();`, which prints
 * "N passed, N failed".  tests/run.sh adds up the lines of all files.
 *
 *   static void test_ring(void) { TT_CHECK(n == 1); TT_NEAR(d, 0.0, 1e-9); }
 *   int main(void) { TT_RUN(test_ring); return tt_summary(); }
 */
#ifndef TD_TT_H
#define TD_TT_H

#include <math.h>
#include <stdio.h>

extern int tt_passed, tt_failed, tt_cur_failed;
extern const char *tt_cur_name;

#define TT_CHECK(cond)                                                       \
    do {                                                                     \
        if (!(cond)) {                                                       \
            fprintf(stderr, "  FAIL %s:%d %s: %s\n", __FILE__, __LINE__,     \
                    tt_cur_name, #cond);                                     \
            tt_cur_failed = 1;                                               \
        }                                                                    \
    } while (0)

/* Like TT_CHECK, with a printf-style explanation on failure. */
#define TT_CHECKF(cond, ...)                                                 \
    do {                                                                     \
        if (!(cond)) {                                                       \
            fprintf(stderr, "  FAIL %s:%d %s: %s: ", __FILE__, __LINE__,     \
                    tt_cur_name, #cond);                                     \
            fprintf(stderr, __VA_ARGS__);                                    \
            fputc('\n', stderr);                                             \
            tt_cur_failed = 1;                                               \
        }                                                                    \
    } while (0)

#define TT_NEAR(a, b, tol)                                                   \
    TT_CHECKF(fabs((double)(a) - (double)(b)) <= (tol), "%g vs %g (tol %g)", \
              (double)(a), (double)(b), (double)(tol))

#define TT_RUN(fn)                                                           \
    do {                                                                     \
        tt_cur_name = #fn;                                                   \
        tt_cur_failed = 0;                                                   \
        fn();                                                                \
        if (tt_cur_failed) {                                                 \
            tt_failed++;                                                     \
            fprintf(stderr, "FAIL %s\n", #fn);                               \
        } else {                                                             \
            tt_passed++;                                                     \
            fprintf(stderr, "ok   %s\n", #fn);                               \
        }                                                                    \
    } while (0)

int tt_summary(void);

/* A fresh scratch directory for the current test binary (created on first
 * use, under $TMPDIR or /tmp); returns a path valid until exit. */
const char *tt_tmpdir(void);

#endif
