/* core.h: the core every stage shares (one header for src/core/).
 *
 *   core     the error convention, progress reporting and size checks
 *   grid     the raster types
 *   lines    contour polylines in memory
 *   contain  point-in-ring tests and the containment tree of lines
 *   draw     debug and teaching pictures drawn in memory
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
/* A hot loop compiled for AVX2 + FMA (x86-64-v3) and AVX-512 (-v4) as
 * well as the default x86-64, the one the CPU runs chosen when the program
 * loads (GCC's function multiversioning, glibc's ifunc): the default build
 * is -O2 for plain x86-64, where some loops ran 3.5-5x slower than with
 * -march=native (docs/benchmarks.md).  The same operations in the same
 * order (-std=c11 contracts nothing into FMA), so the same bytes out.
 * Empty where the build already targets AVX2, or elsewhere. */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) &&     \
    defined(__linux__) && !defined(__AVX2__) && !defined(TD_NO_CLONES)
#define TD_CLONES                                                          \
    __attribute__((noinline,                                               \
                   target_clones("default", "arch=x86-64-v3",             \
                                 "arch=x86-64-v4")))
#else
#define TD_CLONES
#endif

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

/* qsort's comparison of two doubles, ascending. */
int td_cmp_double(const void *a, const void *b);

/* Allocation wrappers that set TD_ENOMEM in cx on failure. */
void *td_malloc(size_t n, td_ctx *cx);
void *td_calloc(size_t n, size_t size, td_ctx *cx);
/* Room in the array *v (capacity *cap elements of size bytes) for need
 * elements: doubled (from 64) until it fits, realloc'd.  0, or TD_ENOMEM
 * (v unchanged) when memory runs out or the size overflows. */
int td_grow(void **v, size_t *cap, size_t need, size_t size, td_ctx *cx);

/* A growable array of size_t (pixel indices): zero-initialise, push, free. */
typedef struct td_szvec {
    size_t *v;
    size_t n, cap;
} td_szvec;
int td_szvec_push(td_szvec *a, size_t x, td_ctx *cx); /* 0 or TD_ENOMEM */
void td_szvec_free(td_szvec *a);                       /* and re-zero */

/* A key and the index of what has it, to sort things by the key (qsort
 * with td_dkey_cmp: ascending key). */
typedef struct td_dkey {
    double key;
    size_t i;
} td_dkey;
int td_dkey_cmp(const void *a, const void *b);

/* Seconds from a monotonic clock. */
double td_now(void);

/* Give the memory freed so far back to the system.  glibc keeps freed
 * small blocks in its heap, resident, behind any block still in use: after
 * a scan (millions of small blocks) about 1.1 bytes per pixel of a sheet,
 * which the later stages' peak would count.  A no-op elsewhere. */
void td_trim_memory(void);

/* ---- grid ---- */
/* grid.h: the raster types every stage shares.
 *
 * Row-major, row 0 = top row of the scan, x = column to the right, y = row
 * downwards.  `stride` is the distance between rows in elements (not bytes);
 * grids made by td_grid_*_new have stride == w.  The structs are plain: read
 * and write `data` directly.  Sizes are checked against TD_MAX_DIM and
 * TD_MAX_PIXELS before anything is allocated. */

typedef struct td_grid_u8 {
    int w, h;
    size_t stride;
    uint8_t *data;
} td_grid_u8;

typedef struct td_grid_u16 {
    int w, h;
    size_t stride;
    uint16_t *data;
} td_grid_u16;

typedef struct td_grid_f32 {
    int w, h;
    size_t stride;
    float *data;
    float nodata;    /* value marking cells without data */
    int has_nodata;  /* nonzero when nodata is meaningful */
} td_grid_f32;

/* An 8-bit image of 1 (grey) or 3 (RGB, interleaved) channels, as read from
 * a scan.  stride is in bytes (>= w * channels).  src_bits records the
 * sample depth of the file it came from (1, 8 or 16) for messages. */
typedef struct td_image {
    int w, h, channels;
    size_t stride;
    uint8_t *data;
    int src_bits;
} td_image;

/* Allocate a zero-filled grid of w x h.  Returns NULL (error in cx) when the
 * size is invalid or memory runs out.  Free with the matching _free, which
 * accepts NULL. */
td_grid_u8 *td_grid_u8_new(int w, int h, td_ctx *cx);
td_grid_u16 *td_grid_u16_new(int w, int h, td_ctx *cx);
td_grid_f32 *td_grid_f32_new(int w, int h, td_ctx *cx);
void td_grid_u8_free(td_grid_u8 *g);
void td_grid_u16_free(td_grid_u16 *g);
void td_grid_f32_free(td_grid_f32 *g);

/* A deep copy of g, or NULL with the error in cx. */
td_grid_u8 *td_grid_u8_dup(const td_grid_u8 *g, td_ctx *cx);

/* Allocate a zero-filled image (channels 1 or 3). */
td_image *td_image_new(int w, int h, int channels, td_ctx *cx);
void td_image_free(td_image *im);

#define TD_AT(g, x, y) ((g)->data[(size_t)(y) * (g)->stride + (size_t)(x)])

/* ---- lines ---- */
/* lines.h: contour polylines in memory (their files: src/io).
 *
 * Coordinates are in pixel units of the scan: x = column + 0.5, y = row + 0.5
 * for a pixel centre (x right, y down).  A closed line does NOT repeat its
 * first point in memory; the GeoJSON writer repeats it, as GeoJSON requires. */

/* Where a line's height came from (the labeller, scanner/label.h). */
typedef enum td_hsource {
    TD_HS_NONE = 0, /* not labelled by the solver (input, or no height) */
    TD_HS_KNOWN,    /* a known point (--known) lies on the line */
    TD_HS_LABEL,    /* a height label read from the sheet */
    TD_HS_SOLVED,   /* implied by the other evidence through the topology */
    TD_HS_ASSUMED   /* only a default (summits rise) decided it */
} td_hsource;

typedef struct td_line {
    double *xy;       /* x0,y0,x1,y1,...: n points */
    size_t n, cap;
    long id;          /* stable id, 0-based order of creation */
    int closed;       /* first and last point are joined */
    int edge;         /* a point lies on the sheet's border pixels */
    int bridged;      /* gaps bridged inside this line */
    int has_height;
    double height;
    long parent;      /* id of the enclosing line, -1 when none/unknown */
    double width;     /* ink width in px measured from the mask (the scanner,
                         scanner/width.h), 0 when not measured */
    double ink;       /* how dark the ink is along its middle, 0..1 of the
                         paper's level (scanner/width.h), 0 when not
                         measured */
    unsigned char junc; /* the tracer (cut): bit 0 the first point, bit 1
                           the last ends next to a skeleton junction */
    int hsource;       /* td_hsource */
    double confidence; /* 0..1 that the height is right (with hsource) */
    int depression;    /* a closed line around lower ground, marked as such
                          (printed maps tick depression contours on their
                          downhill side; the generator knows, the scanner
                          reads the ticks): 1, else 0 */
    const char *why;   /* static text: why the height is null, or NULL */
    unsigned char pale; /* traced from a faded contour's ridges apart from
                           the ink (scanner/pale.h), not from the ink; read
                           by the joiner's text filter (keep_pieces) before
                           any join, and kept by copies only */
    unsigned char piece; /* a short piece the joiner's text filter set aside
                            and put back unjoined (td_join_params.keep_pieces
                            TD_PIECES_LATE): the faces labeller leaves it
                            out of the solve and gives it the height of the
                            lines at its ends (td_label_pieces) */
} td_line;

typedef struct td_lines {
    td_line *v;
    size_t n, cap;
} td_lines;

/* An empty set; free with td_lines_free (NULL is a no-op). */
td_lines *td_lines_new(td_ctx *cx);
void td_lines_free(td_lines *ls);

/* Append an empty line (id = its index, parent -1); returns it or NULL.
 * The pointer is valid until the next td_lines_add. */
td_line *td_lines_add(td_lines *ls, td_ctx *cx);
/* Append a point to a line; 0 or TD_ENOMEM. */
int td_line_push(td_line *l, double x, double y, td_ctx *cx);
/* Reverse a line's point order in place. */
void td_line_reverse(td_line *l);
/* Append src's points to dst, reversed when rev (dst stays a piece only
 * when src is one too).  0 or TD_ENOMEM. */
int td_line_append(td_line *dst, const td_line *src, int rev, td_ctx *cx);
/* Remove line i (order of the others kept; ids unchanged). */
void td_lines_remove(td_lines *ls, size_t i);
/* Length of the polyline (closing segment included when closed). */
double td_line_length(const td_line *l);

/* The unit direction out of open line l through its end (last: its last
 * point, else its first), over arc px of the line back from that end (or
 * all of it), into *ux, *uy; 0 (and no direction) when that end lies
 * less than 1 px from the point the arc reaches. */
int td_line_end_dir(const td_line *l, int last, double arc, double *ux,
                    double *uy);

/* The bounding box of l's vertices: b = x0, y0, x1, y1 (x0 = +inf, x1 =
 * -inf when l has none).  Comparisons, not fmin/fmax (library calls here;
 * vertices are never NaN). */
void td_line_box(const td_line *l, double b[4]);
/* 1 when a point of l lies on the border pixels of a w x h sheet (x or y
 * under 1, or over w - 1 or h - 1: td_line.edge), else 0. */
int td_line_on_border(const td_line *l, int w, int h);

/* An end of an open line: its index in the set, and whether it is the
 * last vertex (else the first). */
typedef struct td_line_end {
    double x, y;
    size_t line;
    int last;
} td_line_end;

/* Both ends of every open line of ls that keep (may be NULL: every one)
 * accepts, sorted by x, y, line, end, into *out (free it), *n of them.
 * 0 or TD_ENOMEM. */
int td_line_ends(const td_lines *ls, int (*keep)(size_t i, const void *u),
                 const void *u, td_line_end **out, size_t *n, td_ctx *cx);
/* The index of the first of the n sorted ends lying exactly at (x, y)
 * (the others there follow it); n when none does. */
size_t td_line_ends_at(const td_line_end *e, size_t n, double x, double y);

/* Append a copy of l to ls: its points and every property (id
 * included; td_lines_add's own id is overwritten).  0 or TD_ENOMEM. */
int td_lines_append_copy(td_lines *ls, const td_line *l, td_ctx *cx);

/* Append a piece of l to be: an empty open line with l's other
 * properties and td_lines_add's own id (l must not lie in ls->v, which
 * may move); returns it or NULL (TD_ENOMEM).  Valid until the next
 * td_lines_add. */
td_line *td_lines_add_piece(td_lines *ls, const td_line *l, td_ctx *cx);

/* A new set with copies of every line of ls (free with td_lines_free);
 * NULL with the error in cx. */
td_lines *td_lines_copy(const td_lines *ls, td_ctx *cx);

/* Douglas-Peucker (1973) on l in place: drop the points whose removal
 * keeps every dropped point within tol (pixel units) of the segment that
 * replaces it, so the line stays within tol of its traced path.  The
 * first and last points stay; a closed line is split at its first point
 * and the point farthest from it, so it keeps at least 3 points.  tol <= 0
 * changes nothing.  Returns 0 or TD_ENOMEM (l unchanged). */
int td_line_simplify(td_line *l, double tol, td_ctx *cx);
/* The sheet size the lines imply when none is given: their extent (traced
 * lines ending on the border reach the border pixels' centres, +0.5).
 * 0, or TD_ETOOBIG when they reach beyond TD_MAX_DIM. */
int td_lines_extent(const td_lines *ls, int *w, int *h, td_ctx *cx);
/* td_line_simplify on every line; 0 or TD_ENOMEM. */
int td_lines_simplify(td_lines *ls, double tol, td_ctx *cx);

/* Signed area of l taken as a closed polygon (shoelace, pixel units): > 0
 * when its points run clockwise on the screen (y down). */
double td_line_signed_area(const td_line *l);

/* Even-odd test of (x,y) against l taken as a closed polygon. */
int td_line_encloses(const td_line *l, double x, double y);

/* ---- contain ---- */
/* contain.h: the containment tree of contour lines (ALGORITHMS.md A.5 (b)).
 *
 * Every line becomes a region: a closed line bounds its inside; an open line
 * whose two ends lie on the sheet border (within TD_CONTAIN_BORDER px) is
 * closed along the border, always the way that does NOT pass the sheet's
 * top-left corner (0,0), so that corner lies outside every region and the
 * nesting of border-closed lines is consistent across the sheet.  The
 * parent of a line is the smallest region containing it.  Open lines with
 * an end inside the sheet (unjoined breaks) bound no region. */

#define TD_CONTAIN_BORDER 3.0 /* px: an open end this near the border is on it */

typedef struct td_contain {
    size_t n;         /* = number of lines */
    long *parent;     /* index of the enclosing line, -1: none (root),
                         -2: the line bounds no region (dangling) */
    double *area;     /* region area in px^2 (0 when dangling) */
    td_lines *rings;  /* the regions' outlines, closed, same order */
} td_contain;

/* Build the tree of ls on a w x h sheet.  Fills *ct (free with
 * td_contain_free).  Returns 0, TD_EINVAL (w or h < 1) or TD_ENOMEM. */
int td_contain_build(const td_lines *ls, int w, int h, td_contain *ct,
                     td_ctx *cx);
void td_contain_free(td_contain *ct);

/* Index of the innermost region containing (x,y), -1 when none. */
long td_contain_locate(const td_contain *ct, double x, double y);

/* Distance from (x,y) to the nearest segment of line l (closing segment
 * included when closed). */
double td_contain_dist(const td_line *l, double x, double y);

/* Two lines crossing (contours never do: a tracing or joining error). */
typedef struct td_crossing {
    long a, b;   /* the two lines' ids, a < b */
    double x, y; /* where (the first crossing found) */
} td_crossing;

/* Every pair of different lines of ls whose segments cross, each pair once
 * (at one of its crossings), through a bucket grid of segments.  Segments
 * are half-open, so a line through a vertex of the other counts once; two
 * lines touching at a vertex count too (contours do not touch either,
 * cliffs aside).  *out (free()) and *n.  Returns 0 or TD_ENOMEM. */
int td_contain_crossings(const td_lines *ls, td_crossing **out, size_t *n,
                         td_ctx *cx);

/* Where the lines through ab and cd meet: a + t (b - a) = c + u (d - c);
 * 0 when they are parallel (t, u untouched), else 1.  The callers decide
 * which ends count. */
int td_seg_meet_at(const double *a, const double *b, const double *c,
                   const double *d, double *t, double *u);

/* A bucket grid of the segments of ls (which must outlive it, unchanged)
 * for "does this segment cross a line" queries.  NULL with the error in cx
 * (TD_ENOMEM, TD_ETOOBIG). */
typedef struct td_seggrid td_seggrid;
td_seggrid *td_seggrid_new(const td_lines *ls, td_ctx *cx);
void td_seggrid_free(td_seggrid *s);
/* Nonzero when segment ab meets a segment of the grid's lines anywhere
 * but at a or b (a and b may lie on lines: ends at junctions). */
int td_seggrid_crosses(const td_seggrid *s, const double *a, const double *b);

/* ---- draw ---- */
/* draw.h: debug and teaching pictures drawn in memory (no file I/O). */

/* A distinct, well-separated colour for index i (golden-ratio hues). */
void td_draw_colour(size_t i, uint8_t rgb[3]);

/* Draw a 1-px polyline (closing segment when l->closed) into an RGB image,
 * clipped to it. */
void td_draw_line(td_image *im, const td_line *l, const uint8_t rgb[3]);

/* The traced-lines overlay: the scan faded towards white, every line drawn
 * in its own colour, open line ends off the border marked with a red 3x3
 * box.
 * *out is a new RGB image of the scan's size (free with td_image_free). */
int td_draw_overlay(const td_image *scan, const td_lines *ls, td_image **out,
                    td_ctx *cx);

/* The heights picture (label, run --debug-dir): the scan (NULL: white
 * w x h) faded, every line coloured by its height (blue low .. brown
 * high), 3 px wide when known or read from a label, solid when solved,
 * dashed when assumed, grey dotted without a height.  *out is new (free
 * with td_image_free).  Returns 0 or TD_ENOMEM. */
int td_draw_heights(const td_image *scan, int w, int h, const td_lines *ls,
                    td_image **out, td_ctx *cx);

/* Where each line's id goes on a label sheet: near its middle, or the
 * first of eight places along it whose box overlaps no earlier id.  x,y
 * pairs in *out (free()); 0 or TD_ENOMEM. */
int td_line_id_places(const td_lines *ls, double **out, td_ctx *cx);
/* Each line's id in small digits on a white box framed in the line's
 * colour (td_draw_colour of its index) at xy[2i], xy[2i+1]. */
void td_draw_ids(td_image *im, const td_lines *ls, const double *xy);
/* Digits, '-' and '.' of t (other characters: a blank) in the 3x5 font
 * scaled by `scale`, top-left at (x0, y0), into an RGB image (clipped). */
void td_draw_text(td_image *im, int x0, int y0, const char *t, int scale,
                  const uint8_t c[3]);

#ifdef __cplusplus
}
#endif
#endif
