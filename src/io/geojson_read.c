/* geojson_read.c: contour lines from a GeoJSON FeatureCollection.
 *
 * The whole file is read into memory and parsed in place by a recursive
 * descent parser that knows the FeatureCollection layout, so no document
 * tree is built: coordinates go straight into one reusable point buffer
 * and from there into the lines.  Values the reader does not need are
 * skipped by a generic parser whose recursion is capped at MAX_DEPTH.
 * Numbers: a fast exact path for up to 15 significant digits with a small
 * decimal exponent (one correctly rounded multiply or divide), strtod on
 * the number's text otherwise. */
#include "src/io/io.h"
#include "src/core/core.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

enum { MAX_DEPTH = 512, MAX_COORD_DEPTH = 8 };

/* The parser: a NUL-terminated buffer (b..e, *e == '\0'), the cursor, and
 * the file name and context for messages. */
typedef struct jp {
    char *b, *s, *e;
    const char *path;
    td_ctx *cx;
} jp;

/* A short decoded string (keys, type names): n is the full decoded length,
 * which may exceed what s holds. */
typedef struct jkey {
    char s[64];
    size_t n;
} jkey;

/* One feature's properties. */
typedef struct fprops {
    int has_id, has_height, closed, edge, bridged; /* closed -1: unknown */
    long id, parent;
    double height, width, ink, confidence;
    int depression, piece;
    int hsource; /* td_hsource of "height_source" */
} fprops;

/* Reader state: the points of the current geometry (positions with their
 * nesting depth and parts), the output and counters. */
typedef struct rd {
    double *xy;
    size_t n, cap;
    size_t *part;       /* first point index of each part */
    size_t np, pcap;
    int pdepth, mixed;  /* depth of the positions; positions at 2 depths */
    long serial, last_parent;
    td_lines *ls;
    size_t skipped;
    const td_georef *g;
    double inv[6];      /* map -> pixel */
    int pixel_crs;      /* the file's "crs" is the pixel frame */
    int epsg;           /* the EPSG code its "crs" names, else 0 */
    size_t next_report;
} rd;

static const double pow10d[23] = {
    1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
    1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

/* "FILE: bad JSON at byte N: expected WHAT"; returns TD_EFORMAT. */
static int bad(jp *p, const char *what)
{
    return td_seterr(p->cx, TD_EFORMAT, "%s: bad JSON at byte %zu%s: "
                     "expected %s", p->path, (size_t)(p->s - p->b),
                     p->s >= p->e ? " (end of file)" : "", what);
}

static void ws(jp *p)
{
    char *s = p->s;
    while (*s == ' ' || *s == '\n' || *s == '\r' || *s == '\t')
        s++;
    p->s = s;
}

/* Skip whitespace and the character c. */
static int expect(jp *p, char c, const char *what)
{
    ws(p);
    if (*p->s != c)
        return bad(p, what);
    p->s++;
    return 0;
}

/* ---- scalars -------------------------------------------------------------- */

static int hex4(const char *s, unsigned *u)
{
    int i;
    *u = 0;
    for (i = 0; i < 4; i++) {
        char c = s[i];
        int d = c >= '0' && c <= '9' ? c - '0'
                : c >= 'a' && c <= 'f' ? c - 'a' + 10
                : c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
        if (d < 0)
            return -1;
        *u = *u * 16 + (unsigned)d;
    }
    return 0;
}

/* Append byte c to k (counting what does not fit). */
static void kput(jkey *k, char c)
{
    if (k->n < sizeof k->s - 1)
        k->s[k->n] = c;
    k->n++;
}

/* Code point u as UTF-8 into k. */
static void kput_utf8(jkey *k, unsigned u)
{
    if (u < 0x80) {
        kput(k, (char)u);
    } else if (u < 0x800) {
        kput(k, (char)(0xc0 | u >> 6));
        kput(k, (char)(0x80 | (u & 63)));
    } else if (u < 0x10000) {
        kput(k, (char)(0xe0 | u >> 12));
        kput(k, (char)(0x80 | ((u >> 6) & 63)));
        kput(k, (char)(0x80 | (u & 63)));
    } else {
        kput(k, (char)(0xf0 | u >> 18));
        kput(k, (char)(0x80 | ((u >> 12) & 63)));
        kput(k, (char)(0x80 | ((u >> 6) & 63)));
        kput(k, (char)(0x80 | (u & 63)));
    }
}

/* A \u escape (cursor after "\u"), with surrogate pairs. */
static int unicode_escape(jp *p, jkey *k)
{
    unsigned u, lo;
    if (hex4(p->s, &u) != 0)
        return bad(p, "4 hex digits after \\u");
    p->s += 4;
    if (u >= 0xd800 && u < 0xdc00 && p->s[0] == '\\' && p->s[1] == 'u' &&
        hex4(p->s + 2, &lo) == 0 && lo >= 0xdc00 && lo < 0xe000) {
        u = 0x10000 + ((u - 0xd800) << 10) + (lo - 0xdc00);
        p->s += 6;
    } else if (u >= 0xd800 && u < 0xe000) {
        u = 0xfffd; /* a lone surrogate */
    }
    kput_utf8(k, u);
    return 0;
}

/* A string (cursor at '"'), decoded into k (may be NULL). */
static int jstr(jp *p, jkey *k)
{
    static const char esc_in[] = "\"\\/bfnrt", esc_out[] = "\"\\/\b\f\n\r\t";
    jkey tmp;
    if (!k)
        k = &tmp;
    k->n = 0;
    if (*p->s != '"')
        return bad(p, "a string");
    p->s++;
    for (;;) {
        unsigned char c = (unsigned char)*p->s;
        if (c == '"')
            break;
        if (c < 0x20)
            return bad(p, p->s == p->e ? "a closing '\"'"
                                       : "no control characters in a string");
        p->s++;
        if (c != '\\') {
            kput(k, (char)c);
        } else if (*p->s == 'u') {
            int rc;
            p->s++;
            if ((rc = unicode_escape(p, k)) != 0)
                return rc;
        } else {
            const char *q = *p->s ? strchr(esc_in, *p->s) : NULL;
            if (!q)
                return bad(p, "a valid escape after '\\'");
            kput(k, esc_out[q - esc_in]);
            p->s++;
        }
    }
    p->s++;
    k->s[k->n < sizeof k->s ? k->n : sizeof k->s - 1] = '\0';
    return 0;
}

static int is(const jkey *k, const char *w)
{
    return k->n < sizeof k->s && strcmp(k->s, w) == 0;
}

/* Digits at *q into m (while it stays below 1e18; more are counted in
 * *drop); returns the number of digits. */
static int digits(char **q, uint64_t *m, int *drop)
{
    char *s = *q;
    int n;
    while (*s >= '0' && *s <= '9') {
        if (*m < 100000000000000000ull)
            *m = *m * 10 + (uint64_t)(*s - '0');
        else
            (*drop)++;
        s++;
    }
    n = (int)(s - *q);
    *q = s;
    return n;
}

/* A JSON number (grammar checked) into *v. */
static int jnum(jp *p, double *v)
{
    char *q = p->s, save;
    uint64_t m = 0;
    int drop = 0, dec = 0, e = 0, eneg = 0, nf, e10;
    int neg = *q == '-';
    q += neg;
    if (*q == '0')
        q++;
    else if (*q < '1' || *q > '9' || digits(&q, &m, &drop) == 0)
        return bad(p, "a value");
    if (*q == '.') {
        q++;
        if ((nf = digits(&q, &m, &drop)) == 0)
            return bad(p, "a digit after '.'");
        dec = nf; /* only used when no digit was dropped */
    }
    if (*q == 'e' || *q == 'E') {
        q++;
        if (*q == '+' || *q == '-')
            eneg = *q++ == '-';
        if (*q < '0' || *q > '9')
            return bad(p, "a digit in the exponent");
        for (; *q >= '0' && *q <= '9'; q++)
            e = e < 100000 ? e * 10 + (*q - '0') : e;
    }
    e10 = (eneg ? -e : e) - dec + drop;
    if (drop == 0 && m < ((uint64_t)1 << 53) && e10 >= -22 && e10 <= 22) {
        double d = e10 < 0 ? (double)m / pow10d[-e10]
                           : (double)m * pow10d[e10];
        *v = neg ? -d : d;
    } else {
        save = *q;
        *q = '\0';
        *v = strtod(p->s, NULL);
        *q = save;
    }
    p->s = q;
    return 0;
}

/* The literal w (true, false, null) at the cursor. */
static int jlit(jp *p, const char *w)
{
    size_t n = strlen(w);
    if (strncmp(p->s, w, n) != 0)
        return bad(p, "a value");
    p->s += n;
    return 0;
}

/* ---- structure ------------------------------------------------------------ */

/* The next member of an object (cursor after '{' or after the previous
 * value): 1 with its key in k and the cursor at the value, 0 at '}'. */
static int obj_next(jp *p, jkey *k, int *first)
{
    int rc;
    ws(p);
    if (*p->s == '}') {
        p->s++;
        return 0;
    }
    if (!*first && *p->s++ != ',') {
        p->s--;
        return bad(p, "',' or '}'");
    }
    *first = 0;
    ws(p);
    if ((rc = jstr(p, k)) != 0)
        return rc;
    if ((rc = expect(p, ':', "':'")) != 0)
        return rc;
    ws(p);
    return 1;
}

/* The next element of an array: 1 with the cursor at it, 0 at ']'. */
static int arr_next(jp *p, int *first)
{
    ws(p);
    if (*p->s == ']' && *first) {
        p->s++;
        return 0;
    }
    if (!*first) {
        if (*p->s == ']') {
            p->s++;
            return 0;
        }
        if (*p->s != ',')
            return bad(p, "',' or ']'");
        p->s++;
    }
    *first = 0;
    ws(p);
    return 1;
}

/* Skip any value, nesting at most MAX_DEPTH deep. */
static int jskip(jp *p, int depth)
{
    int first = 1, r;
    double v;
    jkey k;
    ws(p);
    switch (*p->s) {
    case '{':
    case '[':
        if (depth >= MAX_DEPTH)
            return bad(p, "nesting at most 512 deep");
        if (*p->s++ == '{') {
            while ((r = obj_next(p, &k, &first)) == 1)
                if ((r = jskip(p, depth + 1)) != 0)
                    return r;
        } else {
            while ((r = arr_next(p, &first)) == 1)
                if ((r = jskip(p, depth + 1)) != 0)
                    return r;
        }
        return r;
    case '"':
        return jstr(p, NULL);
    case 't':
        return jlit(p, "true");
    case 'f':
        return jlit(p, "false");
    case 'n':
        return jlit(p, "null");
    default:
        return jnum(p, &v);
    }
}

enum { V_NULL, V_BOOL, V_NUM, V_OTHER };

/* A scalar: its kind and value (bools as 0/1); other values skipped. */
static int jscalar(jp *p, int *kind, double *v)
{
    ws(p);
    *v = 0;
    switch (*p->s) {
    case 'n':
        *kind = V_NULL;
        return jlit(p, "null");
    case 't':
        *kind = V_BOOL;
        *v = 1;
        return jlit(p, "true");
    case 'f':
        *kind = V_BOOL;
        return jlit(p, "false");
    case '-':
    case '0': case '1': case '2': case '3': case '4':
    case '5': case '6': case '7': case '8': case '9':
        *kind = V_NUM;
        return jnum(p, v);
    default:
        *kind = V_OTHER;
        return jskip(p, 0);
    }
}

/* ---- features ------------------------------------------------------------- */

static int type_err(jp *p, size_t fi, const char *key, const char *what)
{
    return td_seterr(p->cx, TD_EFORMAT, "%s: feature %zu (byte %zu): "
                     "property \"%s\" must be %s", p->path, fi,
                     (size_t)(p->s - p->b), key, what);
}

/* One property; those the reader does not know are skipped. */
static int read_prop(jp *p, const jkey *k, fprops *P, size_t fi)
{
    int kind, rc;
    double v;
    int is_int;
    if (is(k, "height_source")) { /* as td_geojson_write_lines names them */
        static const char *const src[] = {"", "known", "label", "solved",
                                          "assumed"};
        jkey t;
        int i;
        ws(p);
        if (*p->s != '"')
            return jskip(p, 1);
        if ((rc = jstr(p, &t)) != 0)
            return rc;
        for (i = 1; i < 5; i++)
            if (is(&t, src[i]))
                P->hsource = i;
        return 0;
    }
    if (!is(k, "id") && !is(k, "height") && !is(k, "closed") &&
        !is(k, "edge") && !is(k, "parent") && !is(k, "bridged") &&
        !is(k, "width") && !is(k, "ink") && !is(k, "confidence") &&
        !is(k, "depression") && !is(k, "piece"))
        return jskip(p, 1);
    if ((rc = jscalar(p, &kind, &v)) != 0)
        return rc;
    is_int = kind == V_NUM && v == floor(v) && fabs(v) < 2e18 &&
             v >= (double)LONG_MIN && v <= (double)LONG_MAX;
    if (is(k, "height")) {
        if (kind != V_NUM && kind != V_NULL)
            return type_err(p, fi, k->s, "a number or null");
        P->has_height = kind == V_NUM && isfinite(v);
        P->height = v;
    } else if (is(k, "width")) {
        if (kind != V_NUM && kind != V_NULL)
            return type_err(p, fi, k->s, "a number or null");
        P->width = kind == V_NUM && isfinite(v) && v > 0 ? v : 0.0;
    } else if (is(k, "ink")) {
        if (kind != V_NUM && kind != V_NULL)
            return type_err(p, fi, k->s, "a number or null");
        P->ink = kind == V_NUM && isfinite(v) && v > 0 && v <= 1 ? v : 0.0;
    } else if (is(k, "confidence")) {
        if (kind != V_NUM && kind != V_NULL)
            return type_err(p, fi, k->s, "a number or null");
        P->confidence = kind == V_NUM && v >= 0 && v <= 1 ? v : 0.0;
    } else if (is(k, "id") || is(k, "parent")) {
        if (!is_int && kind != V_NULL)
            return type_err(p, fi, k->s, "an integer or null");
        if (k->s[0] == 'i') {
            P->has_id = kind == V_NUM;
            P->id = (long)v;
        } else {
            P->parent = kind == V_NUM ? (long)v : -1;
        }
    } else {
        if (kind == V_OTHER)
            return type_err(p, fi, k->s, "true, false, a number or null");
        if (is(k, "closed"))
            P->closed = kind == V_NULL ? -1 : v != 0;
        else if (is(k, "edge"))
            P->edge = v != 0;
        else if (is(k, "depression"))
            P->depression = kind != V_NULL && v != 0;
        else if (is(k, "piece"))
            P->piece = kind != V_NULL && v != 0;
        else
            P->bridged = v != 0;
    }
    return 0;
}

/* Store one position [x, y, ...] (cursor after '[' at its first number). */
static int position(jp *p, rd *R, int depth, long parent)
{
    double v[2];
    int i, first = 1, r;
    for (i = 0; (r = arr_next(p, &first)) == 1; i++) {
        double t;
        if ((r = jnum(p, i < 2 ? &v[i] : &t)) != 0)
            return r;
    }
    if (r != 0)
        return r;
    if (i < 2)
        return bad(p, "a position of at least 2 numbers");
    if (R->n == R->cap) {
        size_t cap = R->cap ? 2 * R->cap : 1024;
        double *xy = realloc(R->xy, cap * 2 * sizeof *xy);
        if (!xy)
            return td_seterr(p->cx, TD_ENOMEM, "out of memory (%zu points)",
                             cap);
        R->xy = xy;
        R->cap = cap;
    }
    if (R->pdepth < 0)
        R->pdepth = depth;
    R->mixed |= R->pdepth != depth;
    if (parent != R->last_parent || R->np == 0) {
        if (R->np == R->pcap) {
            size_t cap = R->pcap ? 2 * R->pcap : 16;
            size_t *pt = realloc(R->part, cap * sizeof *pt);
            if (!pt)
                return td_seterr(p->cx, TD_ENOMEM, "out of memory");
            R->part = pt;
            R->pcap = cap;
        }
        R->part[R->np++] = R->n;
        R->last_parent = parent;
    }
    R->xy[2 * R->n] = v[0];
    R->xy[2 * R->n + 1] = v[1];
    R->n++;
    return 0;
}

/* A coordinates array (cursor at '['): a position or an array of them. */
static int coords(jp *p, rd *R, int depth, long parent)
{
    int first = 1, r;
    long me = ++R->serial;
    if (depth > MAX_COORD_DEPTH)
        return bad(p, "coordinates nested at most 8 deep");
    p->s++;
    ws(p);
    if (*p->s == '-' || (*p->s >= '0' && *p->s <= '9'))
        return position(p, R, depth, parent);
    while ((r = arr_next(p, &first)) == 1) {
        if (*p->s != '[')
            return bad(p, "'[' (a position or an array of positions)");
        if ((r = coords(p, R, depth + 1, me)) != 0)
            return r;
    }
    return r;
}

/* A geometry object (cursor at '{'): its type into t, points into R. */
static int geometry(jp *p, rd *R, jkey *t)
{
    int first = 1, r;
    jkey k;
    p->s++;
    while ((r = obj_next(p, &k, &first)) == 1) {
        if (is(&k, "type")) {
            if ((r = jstr(p, t)) != 0)
                return r;
        } else if (is(&k, "coordinates") && *p->s != 'n') {
            if (*p->s != '[')
                return bad(p, "an array for \"coordinates\"");
            if ((r = coords(p, R, 0, -1)) != 0)
                return r;
        } else if ((r = jskip(p, 1)) != 0) {
            return r;
        }
    }
    return r;
}

/* A properties object (cursor at '{' or null). */
static int properties(jp *p, fprops *P, size_t fi)
{
    int first = 1, r;
    jkey k;
    if (*p->s == 'n')
        return jlit(p, "null");
    if (*p->s != '{')
        return bad(p, "an object or null for \"properties\"");
    p->s++;
    while ((r = obj_next(p, &k, &first)) == 1)
        if ((r = read_prop(p, &k, P, fi)) != 0)
            return r;
    return r;
}

/* Points [a, b) of R as a new line with properties P. */
static int emit(rd *R, size_t a, size_t b, const fprops *P, long id,
                td_ctx *cx)
{
    const double *s = R->xy + 2 * a;
    size_t k = b - a, i;
    int eq = k >= 2 && s[0] == s[2 * k - 2] && s[1] == s[2 * k - 1];
    int closed = P->closed < 0 ? eq : P->closed;
    td_line *l;
    if (k == 0)
        return 0;
    if ((closed && eq) || (!closed && eq && k == 2))
        k--;
    if (!(l = td_lines_add(R->ls, cx)) ||
        !(l->xy = td_malloc(2 * k * sizeof *l->xy, cx)))
        return cx && cx->code ? cx->code : TD_ENOMEM;
    for (i = 0; i < k; i++) {
        l->xy[2 * i] = s[2 * i];
        l->xy[2 * i + 1] = s[2 * i + 1];
    }
    l->n = l->cap = k;
    l->id = id;
    l->closed = closed;
    l->edge = P->edge;
    l->bridged = P->bridged;
    l->depression = P->depression && l->closed;
    l->piece = (unsigned char)(P->piece && !l->closed);
    l->has_height = P->has_height;
    l->height = P->has_height ? P->height : 0.0;
    l->parent = P->parent;
    l->width = P->width;
    l->ink = P->ink;
    l->confidence = P->confidence;
    l->hsource = P->has_height ? P->hsource : TD_HS_NONE;
    return 0;
}

/* The lines of the feature just read; parts after the first get id
 * LONG_MIN,
 * fixed up once the whole file is read. */
static int emit_feature(jp *p, rd *R, const jkey *t, const fprops *P,
                        size_t fi)
{
    int multi = is(t, "MultiLineString");
    size_t i;
    int rc;
    if (!multi && !is(t, "LineString")) {
        R->skipped++;
        return 0;
    }
    if (R->n == 0)
        return 0;
    if (R->mixed || R->pdepth != (multi ? 2 : 1))
        return td_seterr(p->cx, TD_EFORMAT, "%s: feature %zu (byte %zu): "
                         "bad %s coordinates", p->path, fi,
                         (size_t)(p->s - p->b), t->s);
    for (i = 0; i < R->np; i++) {
        size_t b = i + 1 < R->np ? R->part[i + 1] : R->n;
        long id = i > 0 ? LONG_MIN : P->has_id ? P->id : (long)fi;
        if ((rc = emit(R, R->part[i], b, P, id, p->cx)) != 0)
            return rc;
    }
    return 0;
}

/* One feature object (cursor at '{'). */
static int feature(jp *p, rd *R, size_t fi)
{
    fprops P = {0, 0, -1, 0, 0, 0, -1, 0.0, 0.0, 0.0, 0.0, 0, 0, 0};
    jkey k, t = {"", 0}, ft = {"Feature", 7};
    int first = 1, r;
    R->n = R->np = 0;
    R->pdepth = -1;
    R->mixed = 0;
    R->last_parent = -1;
    if (*p->s != '{')
        return bad(p, "a Feature object");
    p->s++;
    while ((r = obj_next(p, &k, &first)) == 1) {
        if (is(&k, "type"))
            r = jstr(p, &ft);
        else if (is(&k, "properties"))
            r = properties(p, &P, fi);
        else if (is(&k, "geometry") && *p->s == '{')
            r = geometry(p, R, &t);
        else if (is(&k, "geometry") && *p->s != 'n')
            r = bad(p, "an object or null for \"geometry\"");
        else
            r = jskip(p, 1);
        if (r != 0)
            return r;
    }
    if (r != 0)
        return r;
    if (!is(&ft, "Feature"))
        return td_seterr(p->cx, TD_EFORMAT, "%s: feature %zu (byte %zu): "
                         "type is not \"Feature\"", p->path, fi,
                         (size_t)(p->s - p->b));
    return emit_feature(p, R, &t, &P, fi);
}

/* The features array (cursor at '['). */
static int features(jp *p, rd *R)
{
    int first = 1, r;
    size_t fi = 0, size = (size_t)(p->e - p->b);
    p->s++;
    while ((r = arr_next(p, &first)) == 1) {
        if ((r = feature(p, R, fi++)) != 0)
            return r;
        if ((size_t)(p->s - p->b) >= R->next_report) {
            R->next_report += (size_t)1 << 24;
            if ((r = td_progress(p->cx, "read", (double)(p->s - p->b) /
                                                    (double)size)) != 0)
                return r;
        }
    }
    return r;
}

static int not_fc(jp *p)
{
    return td_seterr(p->cx, TD_EFORMAT, "%s: not a FeatureCollection",
                     p->path);
}

/* The top-level object; members in any order. */
/* 1 when the text [s, e) contains t. */
static int has_text(const char *s, const char *e, const char *t)
{
    size_t n = strlen(t);
    for (; s + n <= e; s++)
        if (*s == *t && memcmp(s, t, n) == 0)
            return 1;
    return 0;
}

/* The EPSG code named in [s, e) ("EPSG::32633", "EPSG:4326"), else 0. */
static int epsg_in(const char *s, const char *e)
{
    for (; s + 5 < e; s++)
        if (memcmp(s, "EPSG:", 5) == 0) {
            const char *q = s + 5;
            int v = 0;
            if (q < e && *q == ':')
                q++;
            while (q < e && *q >= '0' && *q <= '9' && v < 1000000)
                v = 10 * v + (*q++ - '0');
            return v > 0 && v <= 32766 ? v : 0;
        }
    return 0;
}

static int collection(jp *p, rd *R)
{
    int first = 1, r, type_ok = 0, has_features = 0;
    jkey k, t;
    if (strncmp(p->s, "\xef\xbb\xbf", 3) == 0)
        p->s += 3; /* a UTF-8 byte order mark, as some editors write */
    ws(p);
    if (*p->s != '{')
        return not_fc(p);
    p->s++;
    while ((r = obj_next(p, &k, &first)) == 1) {
        if (is(&k, "type") && *p->s == '"') {
            if ((r = jstr(p, &t)) != 0)
                return r;
            if (!is(&t, "FeatureCollection"))
                return not_fc(p);
            type_ok = 1;
        } else if (is(&k, "crs")) {
            const char *c0 = p->s;
            if ((r = jskip(p, 1)) != 0)
                return r;
            R->pixel_crs = has_text(c0, p->s, TD_PIXEL_CRS);
            R->epsg = epsg_in(c0, p->s);
        } else if (is(&k, "features")) {
            if (*p->s != '[')
                return not_fc(p);
            if ((r = features(p, R)) != 0)
                return r;
            has_features = 1;
        } else if ((r = jskip(p, 1)) != 0) {
            return r;
        }
    }
    if (r != 0)
        return r;
    ws(p);
    if (p->s != p->e)
        return bad(p, "the end of the file");
    return type_ok && has_features ? 0 : not_fc(p);
}

/* The whole file, NUL-terminated, into *buf. */
static int slurp(const char *path, char **buf, size_t *size, td_ctx *cx)
{
    struct stat st;
    FILE *f;
    char *b = NULL;
    int rc = TD_EIO;
    *buf = NULL;
    if (td_check_input(path, cx) != 0)
        return TD_EINVAL;
    f = fopen(path, "rb");
    if (!f)
        return td_seterr(cx, TD_EIO, "%s: cannot open: %s", path,
                         strerror(errno));
    if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode) ||
        (uint64_t)st.st_size >= SIZE_MAX / 2) {
        td_seterr(cx, TD_EIO, "%s: not a regular file", path);
        goto fail;
    }
    *size = (size_t)st.st_size;
    rc = TD_ENOMEM;
    if (!(b = td_malloc(*size + 1, cx)))
        goto fail;
    rc = TD_EIO;
    if (fread(b, 1, *size, f) != *size) {
        td_seterr(cx, TD_EIO, "%s: read error", path);
        goto fail;
    }
    b[*size] = '\0';
    *buf = b;
    b = NULL;
    rc = 0;
fail:
    free(b);
    fclose(f);
    return rc;
}

/* Ids for the later parts of MultiLineStrings: after the largest id. */
static void fix_ids(td_lines *ls)
{
    long max = -1;
    size_t i;
    for (i = 0; i < ls->n; i++)
        max = ls->v[i].id > max ? ls->v[i].id : max;
    for (i = 0; i < ls->n; i++)
        if (ls->v[i].id == LONG_MIN)
            ls->v[i].id = ++max;
}

/* The inverse of the georef's linear part; -1 when singular. */
static int invert(const td_georef *g, double inv[4])
{
    const double *t = g->gt;
    double det = t[1] * t[5] - t[2] * t[4];
    if (det == 0.0 || !isfinite(det))
        return -1;
    inv[0] = t[5] / det;
    inv[1] = -t[2] / det;
    inv[2] = -t[4] / det;
    inv[3] = t[1] / det;
    return 0;
}

/* Map coordinates as read -> pixel units: the pixel frame's (X, -Y) when
 * the file names it, else through the inverse of the caller's georef
 * when it is a real one, else as they are (pixel units, y down: files
 * written before the pixel frame). */
static void to_pixels(rd *R)
{
    size_t i, k;
    if (!R->pixel_crs && !R->epsg && !R->g) {
        /* no CRS: the pixel frame when no point has Y > 0 (pixel units y
           down, as files before the frame, have none below 0) */
        int neg = 0, pos = 0;
        for (i = 0; i < R->ls->n && !pos; i++)
            for (k = 0; k < R->ls->v[i].n; k++) {
                double Y = R->ls->v[i].xy[2 * k + 1];
                pos |= Y > 0;
                neg |= Y < 0;
            }
        R->pixel_crs = neg && !pos;
    }
    for (i = 0; i < R->ls->n; i++) {
        td_line *l = &R->ls->v[i];
        for (k = 0; k < l->n; k++) {
            double X = l->xy[2 * k], Y = l->xy[2 * k + 1];
            if (R->pixel_crs) {
                l->xy[2 * k + 1] = -Y;
            } else if (R->g) {
                X -= R->g->gt[0];
                Y -= R->g->gt[3];
                l->xy[2 * k] = R->inv[0] * X + R->inv[1] * Y;
                l->xy[2 * k + 1] = R->inv[2] * X + R->inv[3] * Y;
            }
        }
    }
}

/* See lines.h.  A MultiLineString gives one line per part with the
 * feature's properties; the first part keeps the feature's id, the others
 * get new ids after the largest in the file.  Parts and LineStrings
 * without positions are dropped.  A feature with null geometry counts as
 * skipped. */
int td_geojson_read_lines(const char *path, const td_georef *georef,
                          td_lines **out, size_t *skipped, td_ctx *cx)
{
    return td_geojson_read_lines_frame(path, georef, out, skipped, NULL, cx);
}

/* See io.h. */
int td_geojson_read_lines_frame(const char *path, const td_georef *georef,
                                td_lines **out, size_t *skipped,
                                td_georef *frame, td_ctx *cx)
{
    jp p = {NULL, NULL, NULL, path, cx};
    rd R;
    size_t size = 0;
    int rc;
    memset(&R, 0, sizeof R);
    if (!path || !out)
        return td_seterr(cx, TD_EINVAL, "no GeoJSON file name given");
    *out = NULL;
    if (georef && georef->valid && !georef->pixel) {
        if (invert(georef, R.inv) != 0)
            return td_seterr(cx, TD_EINVAL, "%s: georeferencing is not "
                             "invertible", path);
        R.g = georef;
    }
    if ((rc = slurp(path, &p.b, &size, cx)) != 0)
        return rc;
    p.s = p.b;
    p.e = p.b + size;
    R.next_report = (size_t)1 << 24;
    if (!(R.ls = td_lines_new(cx))) {
        rc = TD_ENOMEM;
        goto fail;
    }
    if ((rc = collection(&p, &R)) != 0)
        goto fail;
    to_pixels(&R);
    fix_ids(R.ls);
    if (frame) {
        td_georef_init(frame);
        if (R.pixel_crs) {
            td_georef_pixel_frame(frame);
        } else if (R.epsg > 0) {
            frame->valid = 1; /* identity: map units as they are */
            frame->epsg = R.epsg;
        }
    }
    if (skipped)
        *skipped = R.skipped;
    *out = R.ls;
    R.ls = NULL;
fail:
    td_lines_free(R.ls);
    free(R.xy);
    free(R.part);
    free(p.b);
    return rc;
}
