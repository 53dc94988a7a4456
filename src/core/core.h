/* core.h: the error convention, progress reporting and size checks every
 * stage shares.
 *
 * Every library function returns int: 0 on success, a negative TD_E* code on
 * failure, with a one-line message stored in the caller's td_ctx.  Library
 * code never prints and never exits; only src/cli/ does. */
#ifndef TD_CORE_H
#define TD_CORE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

enum {
    TD_OK = 0,
    TD_EINVAL = -1,   /* bad argument or option value */
    TD_ENOMEM = -2,   /* allocation failed */
    TD_EIO = -3,      /* file could not be opened, read or written */
    TD_EFORMAT = -4,  /* file is corrupt, truncated or of an unsupported layout */
    TD_ETOOBIG = -5,  /* sizes exceed TD_MAX_DIM / TD_MAX_PIXELS */
    TD_ECANCEL = -6,  /* the progress callback asked to stop */
    TD_EINTERNAL = -7 /* a bug: an invariant did not hold */
};

/* Largest accepted width or height, and largest pixel count of one grid.
 * 2^31 pixels keep every pixel index inside uint32_t and keep the scanner's
 * peak memory (under 6 bytes per pixel) within a 24 GB machine. */
#define TD_MAX_DIM (1 << 20)
#define TD_MAX_PIXELS ((size_t)1 << 31)

/* Progress callback: stage is a short name ("thin"), frac in [0,1].
 * Return 0 to go on, nonzero to cancel (the stage then fails with
 * TD_ECANCEL). */
typedef int (*td_progress_fn)(const char *stage, double frac, void *user);

typedef struct td_ctx {
    int code;               /* last error code, 0 if none */
    char msg[512];          /* last error message, "" if none */
    td_progress_fn progress; /* may be NULL */
    void *progress_user;
} td_ctx;

/* A context with no error and no progress callback. */
void td_ctx_init(td_ctx *cx);

/* Store a printf-style message and code in cx (cx may be NULL); returns
 * code so callers can write `return td_seterr(cx, TD_EINVAL, ...)`.  The
 * first error set wins until td_ctx_clear(): the innermost cause is kept. */
int td_seterr(td_ctx *cx, int code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
void td_ctx_clear(td_ctx *cx);
const char *td_errmsg(const td_ctx *cx);

/* Report progress; returns 0 to go on, TD_ECANCEL (with the message set)
 * when the callback asked to stop. */
int td_progress(td_ctx *cx, const char *stage, double frac);

/* Overflow-checked size arithmetic: store a*b (a*b*c) in *out, return 0, or
 * return -1 on overflow. */
int td_mul2(size_t a, size_t b, size_t *out);
int td_mul3(size_t a, size_t b, size_t c, size_t *out);

/* Check a grid size: 1..TD_MAX_DIM per side and at most TD_MAX_PIXELS;
 * `what` names the thing in the message ("image 'a.tif'"). */
int td_check_dims(long w, long h, const char *what, td_ctx *cx);

/* Allocation wrappers that set TD_ENOMEM in cx on failure. */
void *td_malloc(size_t n, td_ctx *cx);
void *td_calloc(size_t n, size_t size, td_ctx *cx);

/* A growable array of size_t (pixel indices): zero-initialise, push, free. */
typedef struct td_szvec {
    size_t *v;
    size_t n, cap;
} td_szvec;
int td_szvec_push(td_szvec *a, size_t x, td_ctx *cx); /* 0 or TD_ENOMEM */
void td_szvec_free(td_szvec *a);                       /* and re-zero */

/* Seconds from a monotonic clock. */
double td_now(void);

#ifdef __cplusplus
}
#endif
#endif
