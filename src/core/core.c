#define _POSIX_C_SOURCE 200809L
#include "src/core/core.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#if defined(__linux__)
#include <sys/mman.h>
#endif
#if defined(__GLIBC__)
#include <malloc.h>
#endif

void td_ctx_init(td_ctx *cx)
{
    memset(cx, 0, sizeof *cx);
}

int td_seterr(td_ctx *cx, int code, const char *fmt, ...)
{
    va_list ap;
    if (!cx || cx->code != 0)
        return code;
    cx->code = code;
    va_start(ap, fmt);
    vsnprintf(cx->msg, sizeof cx->msg, fmt, ap);
    va_end(ap);
    return code;
}

void td_ctx_clear(td_ctx *cx)
{
    cx->code = 0;
    cx->msg[0] = '\0';
}

const char *td_errmsg(const td_ctx *cx)
{
    if (!cx || !cx->msg[0])
        return "no error";
    return cx->msg;
}

int td_progress(td_ctx *cx, const char *stage, double frac)
{
    if (!cx || !cx->progress)
        return 0;
    if (cx->progress(stage, frac, cx->progress_user) != 0)
        return td_seterr(cx, TD_ECANCEL, "%s: cancelled", stage);
    return 0;
}

int td_mul2(size_t a, size_t b, size_t *out)
{
    if (a != 0 && b > SIZE_MAX / a)
        return -1;
    *out = a * b;
    return 0;
}

int td_mul3(size_t a, size_t b, size_t c, size_t *out)
{
    size_t ab;
    if (td_mul2(a, b, &ab) != 0)
        return -1;
    return td_mul2(ab, c, out);
}

int td_check_dims(long w, long h, const char *what, td_ctx *cx)
{
    if (w <= 0 || h <= 0)
        return td_seterr(cx, TD_EFORMAT, "%s: empty image (%ld x %ld)", what,
                         w, h);
    if (w > TD_MAX_DIM || h > TD_MAX_DIM ||
        (size_t)w * (size_t)h > TD_MAX_PIXELS)
        return td_seterr(cx, TD_ETOOBIG,
                         "%s: %ld x %ld pixels is larger than the limit "
                         "(%d per side, %zu pixels)",
                         what, w, h, TD_MAX_DIM, (size_t)TD_MAX_PIXELS);
    return 0;
}

/* Blocks of BIG_BLOCK bytes or more (grids of 10000^2 cells: 100-400 MB)
 * ask for transparent huge pages on their 2-MB-aligned inside, before
 * anything touches them (malloc and calloc leave fresh mmap'd blocks
 * untouched).  The kernel then faults them in 2-MB pages, not 4-KB ones:
 * on this VM the 4-KB faults were a quarter of `topodig run`'s time on a
 * 10000^2 sheet (12.8 -> 9.5 s; docs/benchmarks.md).  Only a request: with
 * THP off, or elsewhere, nothing changes. */
#define BIG_BLOCK ((size_t)4 << 20)
#define HUGE_PAGE ((uintptr_t)2 << 20)

static void *huge_pages(void *p, size_t n)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    uintptr_t a = ((uintptr_t)p + HUGE_PAGE - 1) & ~(HUGE_PAGE - 1);
    uintptr_t b = ((uintptr_t)p + n) & ~(HUGE_PAGE - 1);
    if (p && n >= BIG_BLOCK && b > a)
        (void)madvise((void *)a, (size_t)(b - a), MADV_HUGEPAGE);
#else
    (void)n;
#endif
    return p;
}

/* Contract in core.h. */
void td_trim_memory(void)
{
#if defined(__GLIBC__)
    (void)malloc_trim(0);
#endif
}

int td_cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

void *td_malloc(size_t n, td_ctx *cx)
{
    void *p = malloc(n ? n : 1);
    if (!p)
        td_seterr(cx, TD_ENOMEM, "out of memory (%zu bytes)", n);
    return huge_pages(p, n);
}

void *td_calloc(size_t n, size_t size, td_ctx *cx)
{
    void *p = calloc(n ? n : 1, size ? size : 1);
    if (!p)
        td_seterr(cx, TD_ENOMEM, "out of memory (%zu x %zu bytes)", n, size);
    return huge_pages(p, size && n <= SIZE_MAX / size ? n * size : 0);
}

int td_grow(void **v, size_t *cap, size_t need, size_t size, td_ctx *cx)
{
    size_t nc;
    void *t;
    if (need <= *cap)
        return 0;
    nc = *cap ? *cap : 64;
    while (nc < need) {
        if (nc > SIZE_MAX / 2)
            return td_seterr(cx, TD_ENOMEM, "out of memory (%zu elements)",
                             need);
        nc *= 2;
    }
    if (size && nc > SIZE_MAX / size)
        return td_seterr(cx, TD_ENOMEM, "out of memory (%zu elements)", need);
    if (!(t = realloc(*v, nc * (size ? size : 1))))
        return td_seterr(cx, TD_ENOMEM, "out of memory (%zu x %zu bytes)", nc,
                         size);
    *v = t, *cap = nc;
    return 0;
}

double td_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int td_szvec_push(td_szvec *a, size_t x, td_ctx *cx)
{
    if (a->n == a->cap) {
        size_t cap = a->cap ? a->cap * 2 : 256;
        size_t *p = realloc(a->v, cap * sizeof *p);
        if (!p)
            return td_seterr(cx, TD_ENOMEM, "out of memory (%zu indices)", cap);
        a->v = p;
        a->cap = cap;
    }
    a->v[a->n++] = x;
    return 0;
}

void td_szvec_free(td_szvec *a)
{
    free(a->v);
    a->v = NULL;
    a->n = a->cap = 0;
}

int td_dkey_cmp(const void *a, const void *b)
{
    double x = ((const td_dkey *)a)->key, y = ((const td_dkey *)b)->key;
    return (x > y) - (x < y);
}
