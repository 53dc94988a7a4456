/* geojson.c: contour lines as a GeoJSON FeatureCollection of LineStrings.
 *
 * Numbers go through a small fixed-point formatter into a 1 MB buffer
 * (snprintf per coordinate would dominate the time for millions of
 * points): pixel units get 3 decimals, map units 9 significant digits,
 * both with trailing zeros trimmed. */
#include "src/io/io.h"
#include "src/core/core.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { JBUF_SIZE = 1 << 20 };

/* A write buffer in front of a FILE; err latches the first failure. */
typedef struct jbuf {
    FILE *f;
    char *b;
    size_t n;
    int err;
} jbuf;

static void jflush(jbuf *j)
{
    if (j->n && fwrite(j->b, 1, j->n, j->f) != j->n)
        j->err = 1;
    j->n = 0;
}

/* Room for k more bytes (k < JBUF_SIZE); returns where to write. */
static char *jroom(jbuf *j, size_t k)
{
    if (j->n + k > JBUF_SIZE)
        jflush(j);
    return j->b + j->n;
}

static void jputs(jbuf *j, const char *s)
{
    size_t k = strlen(s);
    memcpy(jroom(j, k), s, k);
    j->n += k;
}

static const uint64_t pow10u[10] = {1,      10,      100,      1000,
                                    10000,  100000,  1000000,  10000000,
                                    100000000, 1000000000};

/* v (finite, |v| < 1e9) with dec (0..9) decimals, trailing zeros trimmed,
 * into p; returns the number of chars. */
static int fmt_fixed(char *p, double v, int dec)
{
    char d[32];
    int n = 0, k = 0, i;
    uint64_t q, ip, fp;
    int neg = v < 0;
    q = (uint64_t)((neg ? -v : v) * (double)pow10u[dec] + 0.5);
    ip = q / pow10u[dec];
    fp = q % pow10u[dec];
    if (neg && q)
        p[n++] = '-';
    do {
        d[k++] = (char)('0' + ip % 10);
        ip /= 10;
    } while (ip);
    while (k)
        p[n++] = d[--k];
    while (dec > 0 && fp % 10 == 0) {
        fp /= 10;
        dec--;
    }
    if (dec > 0) {
        p[n++] = '.';
        for (i = dec - 1; i >= 0; i--) {
            p[n + i] = (char)('0' + fp % 10);
            fp /= 10;
        }
        n += dec;
    }
    return n;
}

/* A coordinate: 3 decimals in pixel units, 9 significant digits in map
 * units (snprintf outside the fast formatter's range). */
static int fmt_coord(char *p, double v, int map)
{
    double a = fabs(v);
    int dec = 3;
    if (map) {
        if (a >= 1e9 || (a < 1e-3 && a != 0.0))
            return snprintf(p, 32, "%.9g", v);
        for (dec = 9; dec > 0 && a >= (double)pow10u[9 - dec]; dec--)
            ;
    } else if (a >= 1e9) {
        return snprintf(p, 32, "%.3f", v);
    }
    return fmt_fixed(p, v, dec);
}

/* The feature's properties object. */
static void put_properties(jbuf *j, const td_line *l)
{
    static const char *src[] = {"", "known", "label", "solved", "assumed"};
    char s[640], h[40], par[32], wd[40] = "", hs[80] = "", why[200] = "";
    if (l->has_height && isfinite(l->height))
        snprintf(h, sizeof h, "%.10g", l->height);
    else
        snprintf(h, sizeof h, "null");
    if (l->parent >= 0)
        snprintf(par, sizeof par, "%ld", l->parent);
    else
        snprintf(par, sizeof par, "null");
    if (l->width > 0 && isfinite(l->width) && l->ink > 0 && isfinite(l->ink))
        snprintf(wd, sizeof wd, ",\"width\":%.2f,\"ink\":%.3f", l->width,
                 l->ink);
    else if (l->width > 0 && isfinite(l->width))
        snprintf(wd, sizeof wd, ",\"width\":%.2f", l->width);
    if (l->hsource > TD_HS_NONE && l->hsource <= TD_HS_ASSUMED)
        snprintf(hs, sizeof hs, ",\"height_source\":\"%s\",\"confidence\""
                 ":%.3f", src[l->hsource], l->confidence);
    if (l->why && !l->has_height) /* static text without quotes */
        snprintf(why, sizeof why, ",\"height_reason\":\"%.150s\"", l->why);
    snprintf(s, sizeof s,
             "{\"type\":\"Feature\",\"properties\":{\"id\":%ld,"
             "\"height\":%s,\"closed\":%s,\"edge\":%s,\"parent\":%s,"
             "\"bridged\":%d%s%s%s%s%s},\"geometry\":{\"type\":"
             "\"LineString\",\"coordinates\":[",
             l->id, h, l->closed ? "true" : "false", l->edge ? "true" : "false",
             par, l->bridged, wd, hs, why,
             l->depression ? ",\"depression\":true" : "",
             l->piece ? ",\"piece\":true" : "");
    jputs(j, s);
}

/* One point "[x,y]"; -1 when a coordinate is not finite. */
static int put_point(jbuf *j, const td_line *l, size_t i,
                     const td_georef *g, int first)
{
    double x = l->xy[2 * i], y = l->xy[2 * i + 1];
    int map = g && g->valid && !g->pixel;
    char *p;
    td_georef_apply(g, x, y, &x, &y);
    if (!isfinite(x) || !isfinite(y))
        return -1;
    p = jroom(j, 80);
    if (!first)
        *p++ = ',';
    *p++ = '[';
    p += fmt_coord(p, x, map);
    *p++ = ',';
    p += fmt_coord(p, y, map);
    *p++ = ']';
    j->n = (size_t)(p - j->b);
    return 0;
}

/* One feature; a 1-point line repeats its point, a closed line its first
 * point, so every LineString has at least two positions. */
static int put_line(jbuf *j, const td_line *l, const td_georef *g)
{
    size_t i;
    put_properties(j, l);
    for (i = 0; i < l->n; i++)
        if (put_point(j, l, i, g, i == 0) != 0)
            return -1;
    if (l->n == 1 || (l->closed && l->n >= 2))
        if (put_point(j, l, 0, g, 0) != 0)
            return -1;
    jputs(j, "]}}");
    return 0;
}

/* The collection's head with its "crs" member (td_georef_crs_json). */
static void put_head(jbuf *j, const td_georef *g)
{
    char s[320];
    jputs(j, "{\"type\":\"FeatureCollection\",\n");
    td_georef_crs_json(g, s, sizeof s);
    jputs(j, s);
    jputs(j, ",\n\"features\":[\n");
}

/* See lines.h.  Lines without points are skipped; a non-finite coordinate
 * fails with TD_EINVAL and leaves no file. */
int td_geojson_write_lines(const char *path, const td_lines *ls,
                           const td_georef *georef, td_ctx *cx)
{
    jbuf j = {NULL, NULL, 0, 0};
    char *tmp = NULL;
    size_t i, tmpsize = (path ? strlen(path) : 0) + 32;
    int rc = TD_ENOMEM, first = 1;
    if (!path || !ls)
        return td_seterr(cx, TD_EINVAL, "%s: no lines to write",
                         path ? path : "(null)");
    if (!(tmp = td_malloc(tmpsize, cx)) || !(j.b = td_malloc(JBUF_SIZE, cx)))
        goto fail;
    if (!(j.f = td_atomic_open(path, tmp, tmpsize, cx))) {
        rc = cx && cx->code ? cx->code : TD_EIO;
        goto fail;
    }
    put_head(&j, georef);
    for (i = 0; i < ls->n && !j.err; i++) {
        if (ls->v[i].n == 0)
            continue;
        if (!first)
            jputs(&j, ",\n");
        first = 0;
        if (put_line(&j, &ls->v[i], georef) != 0) {
            rc = td_seterr(cx, TD_EINVAL, "%s: line %ld has a non-finite "
                           "coordinate", path, ls->v[i].id);
            goto fail;
        }
    }
    jputs(&j, "\n]}\n");
    jflush(&j);
    if (j.err) {
        rc = td_seterr(cx, TD_EIO, "%s: write failed", path);
        goto fail;
    }
    rc = td_atomic_commit(j.f, tmp, path, cx);
    j.f = NULL;
fail:
    if (j.f)
        td_atomic_abort(j.f, tmp);
    free(j.b);
    free(tmp);
    return rc;
}
