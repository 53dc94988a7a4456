/* test_lines.c: the polyline container and the GeoJSON writer.  The
 * written file is parsed back by a small JSON reader below, so structure,
 * properties and coordinates are checked value by value. */
#define _POSIX_C_SOURCE 200809L
#include "tests/tt.h"

#include "src/io/io.h"
#include "src/core/core.h"

#include <ctype.h>
#include <dirent.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* ---- a minimal JSON reader -------------------------------------------- */

enum { J_NULL, J_BOOL, J_NUM, J_STR, J_ARR, J_OBJ };

typedef struct jv {
    int type;
    double num;          /* J_NUM, J_BOOL */
    char *str;           /* J_STR; key when inside an object */
    struct jv *kid;      /* first element / member */
    struct jv *next;     /* next sibling */
    char *key;
} jv;

typedef struct jp {
    const char *s;
    int err;
} jp;

static void jfree(jv *v)
{
    while (v) {
        jv *n = v->next;
        jfree(v->kid);
        free(v->str);
        free(v->key);
        free(v);
        v = n;
    }
}

static void ws(jp *p)
{
    while (isspace((unsigned char)*p->s))
        p->s++;
}

static char *jstring(jp *p)
{
    const char *b = ++p->s;
    char *r;
    while (*p->s && *p->s != '"')
        p->s += *p->s == '\\' ? 2 : 1;
    if (*p->s != '"') {
        p->err = 1;
        return NULL;
    }
    r = malloc((size_t)(p->s - b) + 1);
    memcpy(r, b, (size_t)(p->s - b));
    r[p->s - b] = 0;
    p->s++;
    return r;
}

static jv *jvalue(jp *p);

/* Elements of an array or members of an object up to `close`. */
static jv *jlist(jp *p, char close, int obj)
{
    jv *first = NULL, **tail = &first;
    p->s++;
    ws(p);
    if (*p->s == close) {
        p->s++;
        return first;
    }
    while (!p->err) {
        char *key = NULL;
        jv *v;
        ws(p);
        if (obj) {
            if (*p->s != '"' || !(key = jstring(p))) {
                p->err = 1;
                break;
            }
            ws(p);
            if (*p->s++ != ':')
                p->err = 1;
        }
        v = jvalue(p);
        if (!v) {
            free(key);
            break;
        }
        v->key = key;
        *tail = v;
        tail = &v->next;
        ws(p);
        if (*p->s == ',') {
            p->s++;
            continue;
        }
        if (*p->s++ != close)
            p->err = 1;
        break;
    }
    return first;
}

static jv *jvalue(jp *p)
{
    jv *v = calloc(1, sizeof *v);
    char *end;
    ws(p);
    if (*p->s == '{' || *p->s == '[') {
        v->type = *p->s == '{' ? J_OBJ : J_ARR;
        v->kid = jlist(p, *p->s == '{' ? '}' : ']', *p->s == '{');
    } else if (*p->s == '"') {
        v->type = J_STR;
        v->str = jstring(p);
    } else if (!strncmp(p->s, "null", 4) || !strncmp(p->s, "true", 4)) {
        v->type = *p->s == 'n' ? J_NULL : J_BOOL;
        v->num = *p->s == 't';
        p->s += 4;
    } else if (!strncmp(p->s, "false", 5)) {
        v->type = J_BOOL;
        p->s += 5;
    } else {
        v->type = J_NUM;
        v->num = strtod(p->s, &end);
        if (end == p->s)
            p->err = 1;
        p->s = end;
    }
    if (p->err) {
        jfree(v);
        return NULL;
    }
    return v;
}

static jv *jget(const jv *o, const char *key)
{
    jv *k;
    for (k = o ? o->kid : NULL; k; k = k->next)
        if (k->key && !strcmp(k->key, key))
            return k;
    return NULL;
}

static int jcount(const jv *a)
{
    int n = 0;
    jv *k;
    for (k = a ? a->kid : NULL; k; k = k->next)
        n++;
    return n;
}

static jv *jat(const jv *a, int i)
{
    jv *k = a ? a->kid : NULL;
    while (k && i--)
        k = k->next;
    return k;
}

/* Parse a whole file; NULL when it is not one valid JSON value. */
static jv *jload(const char *path)
{
    FILE *f = fopen(path, "rb");
    long n;
    char *buf;
    jp p;
    jv *v;
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    n = ftell(f);
    fseek(f, 0, SEEK_SET);
    buf = malloc((size_t)n + 1);
    buf[fread(buf, 1, (size_t)n, f)] = 0;
    fclose(f);
    p.s = buf;
    p.err = 0;
    v = jvalue(&p);
    ws(&p);
    if (*p.s) {
        jfree(v);
        v = NULL;
    }
    free(buf);
    return v;
}

/* ---- the container ------------------------------------------------------ */

static void test_lines_basic(void)
{
    td_ctx cx;
    td_lines *ls;
    td_line *l;
    int i;
    td_ctx_init(&cx);
    td_lines_free(NULL);
    ls = td_lines_new(&cx);
    TT_CHECK(ls && ls->n == 0);
    for (i = 0; i < 100; i++) {
        l = td_lines_add(ls, &cx);
        TT_CHECK(l && l->id == i && l->parent == -1 && l->n == 0 &&
                 !l->has_height);
    }
    l = &ls->v[3];
    for (i = 0; i < 1000; i++)
        TT_CHECK(td_line_push(l, i, 2.0 * i, &cx) == 0);
    TT_CHECK(l->n == 1000 && l->xy[2 * 999] == 999 && l->xy[2 * 999 + 1] == 1998);
    td_line_reverse(l);
    TT_CHECK(l->xy[0] == 999 && l->xy[1] == 1998 && l->xy[2 * 999] == 0);
    TT_NEAR(td_line_length(l), 999 * sqrt(5.0), 1e-9);
    td_lines_remove(ls, 3);
    TT_CHECK(ls->n == 99 && ls->v[3].id == 4 && ls->v[2].id == 2);
    td_lines_remove(ls, 500); /* out of range: ignored */
    TT_CHECK(ls->n == 99);
    l = td_lines_add(ls, &cx);
    TT_CHECK(l->id == 100); /* unique after a removal */
    td_lines_free(ls);
}

static void test_line_length(void)
{
    td_ctx cx;
    td_line l;
    td_ctx_init(&cx);
    memset(&l, 0, sizeof l);
    TT_NEAR(td_line_length(&l), 0, 0);
    td_line_push(&l, 0, 0, &cx);
    TT_NEAR(td_line_length(&l), 0, 0);
    td_line_push(&l, 3, 0, &cx);
    td_line_push(&l, 3, 4, &cx);
    TT_NEAR(td_line_length(&l), 7, 1e-12);
    l.closed = 1;
    TT_NEAR(td_line_length(&l), 12, 1e-12);
    td_line_reverse(&l);
    TT_NEAR(td_line_length(&l), 12, 1e-12);
    free(l.xy);
}

/* Appending: forward and reversed, onto itself, empty pieces; a chain
 * of many small pieces keeps every point in order. */
static void test_line_append(void)
{
    td_ctx cx;
    td_line a, b, e;
    size_t i;
    int ok = 1;
    td_ctx_init(&cx);
    memset(&a, 0, sizeof a), memset(&b, 0, sizeof b), memset(&e, 0, sizeof e);
    for (i = 0; i < 5; i++)
        td_line_push(&b, (double)i, 10.0 + (double)i, &cx);
    TT_CHECK(td_line_append(&a, &e, 0, &cx) == 0 && a.n == 0);
    TT_CHECK(td_line_append(&a, &b, 0, &cx) == 0 && a.n == 5);
    TT_CHECK(td_line_append(&a, &b, 1, &cx) == 0 && a.n == 10);
    TT_CHECK(a.xy[0] == 0 && a.xy[9] == 14 && a.xy[10] == 4 && a.xy[11] == 14 &&
             a.xy[18] == 0 && a.xy[19] == 10);
    TT_CHECK(td_line_append(&a, &a, 1, &cx) == 0 && a.n == 20);
    TT_CHECK(a.xy[20] == 0 && a.xy[21] == 10 && a.xy[38] == 0 &&
             a.xy[39] == 10);
    a.n = 0;
    for (i = 0; i < 1000; i++)
        if (td_line_append(&a, &b, (int)(i & 1), &cx) != 0)
            ok = 0;
    TT_CHECK(ok && a.n == 5000 && a.cap >= a.n);
    for (i = 0; i < 1000 && ok; i++) {
        size_t k = 5 * i + (i & 1 ? 4 : 0);
        ok = a.xy[2 * k] == 0 && a.xy[2 * k + 1] == 10;
    }
    TT_CHECK(ok);
    free(a.xy), free(b.xy);
}

/* ---- GeoJSON ------------------------------------------------------------ */

static const char *tmp(const char *name)
{
    static char buf[4][600];
    static int k;
    char *p = buf[k++ % 4];
    snprintf(p, 600, "%s/%s", tt_tmpdir(), name);
    return p;
}

/* A square (closed, labelled, with parent), an open edge line, a one-point
 * line, an empty line (skipped). */
static td_lines *sample_lines(td_ctx *cx)
{
    td_lines *ls = td_lines_new(cx);
    td_line *l = td_lines_add(ls, cx);
    td_line_push(l, 10.5, 10.5, cx);
    td_line_push(l, 20.5, 10.5, cx);
    td_line_push(l, 20.5, 20.5, cx);
    td_line_push(l, 10.5, 20.5, cx);
    l->closed = 1;
    l->has_height = 1;
    l->height = 120.5;
    l->parent = 1;
    l->bridged = 2;
    l->depression = 1;
    l = td_lines_add(ls, cx);
    td_line_push(l, 0.5, 3.25, cx);
    td_line_push(l, 40.125, 7.0004, cx);
    l->edge = 1;
    l = td_lines_add(ls, cx);
    td_line_push(l, 5.5, 6.5, cx);
    td_lines_add(ls, cx);
    return ls;
}

static void check_point(const jv *pt, double x, double y, double tol)
{
    TT_CHECK(pt && pt->type == J_ARR && jcount(pt) == 2);
    if (pt && jcount(pt) == 2) {
        TT_NEAR(jat(pt, 0)->num, x, tol);
        TT_NEAR(jat(pt, 1)->num, y, tol);
    }
}

static void test_geojson_pixel_units(void)
{
    td_ctx cx;
    td_lines *ls;
    jv *root, *feats, *f, *props, *coords;
    const char *path = tmp("lines.geojson");
    td_ctx_init(&cx);
    ls = sample_lines(&cx);
    TT_CHECKF(td_geojson_write_lines(path, ls, NULL, &cx) == 0, "%s",
              td_errmsg(&cx));
    root = jload(path);
    TT_CHECK(root != NULL);
    if (!root)
        goto done;
    TT_CHECK(jget(root, "type") && !strcmp(jget(root, "type")->str,
                                            "FeatureCollection"));
    /* no georeferencing: the pixel frame (X = col, Y = -row) in a named
     * engineering CRS, never GeoJSON's default WGS 84 */
    TT_CHECK(jget(root, "crs") && jget(jget(root, "crs"), "properties") &&
             strstr(jget(jget(jget(root, "crs"), "properties"), "name")->str,
                    TD_PIXEL_CRS));
    feats = jget(root, "features");
    TT_CHECK(feats && jcount(feats) == 3);
    f = jat(feats, 0);
    props = jget(f, "properties");
    TT_CHECK(!strcmp(jget(f, "type")->str, "Feature"));
    TT_CHECK(jget(props, "id")->num == 0 && jget(props, "height")->num == 120.5);
    TT_CHECK(jget(props, "closed")->type == J_BOOL && jget(props, "closed")->num);
    TT_CHECK(jget(props, "edge")->type == J_BOOL && !jget(props, "edge")->num);
    TT_CHECK(jget(props, "parent")->num == 1 && jget(props, "bridged")->num == 2);
    TT_CHECK(jget(props, "depression") &&
             jget(props, "depression")->type == J_BOOL &&
             jget(props, "depression")->num);
    TT_CHECK(!strcmp(jget(jget(f, "geometry"), "type")->str, "LineString"));
    coords = jget(jget(f, "geometry"), "coordinates");
    TT_CHECK(jcount(coords) == 5); /* closed: the first point repeated */
    check_point(jat(coords, 0), 10.5, -10.5, 0);
    check_point(jat(coords, 4), 10.5, -10.5, 0);
    f = jat(feats, 1);
    props = jget(f, "properties");
    TT_CHECK(jget(props, "height")->type == J_NULL);
    TT_CHECK(jget(props, "parent")->type == J_NULL);
    TT_CHECK(jget(props, "edge")->num == 1 && jget(props, "closed")->num == 0);
    coords = jget(jget(f, "geometry"), "coordinates");
    TT_CHECK(jcount(coords) == 2);
    check_point(jat(coords, 1), 40.125, -7.0, 1e-12); /* 3 decimals */
    f = jat(feats, 2); /* one point: written twice */
    coords = jget(jget(f, "geometry"), "coordinates");
    TT_CHECK(jcount(coords) == 2);
    check_point(jat(coords, 0), 5.5, -6.5, 0);
    check_point(jat(coords, 1), 5.5, -6.5, 0);
    TT_CHECK(jget(jget(f, "properties"), "id")->num == 2);
done:
    jfree(root);
    td_lines_free(ls);
}

static int have_tool(const char *name)
{
    char cmd[128];
    snprintf(cmd, sizeof cmd, "command -v %s >/dev/null 2>&1", name);
    return system(cmd) == 0;
}

/* ogrinfo -al -so: the feature count (and the CRS when given). */
static void check_ogrinfo(const char *path, int nfeat, const char *crs)
{
    char cmd[700], out[16384], *s;
    FILE *p;
    size_t n;
    int count = -1;
    if (!have_tool("ogrinfo")) {
        fprintf(stderr, "  (ogrinfo absent: skipped)\n");
        return;
    }
    snprintf(cmd, sizeof cmd, "ogrinfo -ro -al -so '%s' 2>&1", path);
    p = popen(cmd, "r");
    n = fread(out, 1, sizeof out - 1, p);
    out[n] = 0;
    pclose(p);
    s = strstr(out, "Feature Count: ");
    TT_CHECKF(s && sscanf(s, "Feature Count: %d", &count) == 1 && count == nfeat,
              "%s", out);
    TT_CHECKF(strstr(out, "Geometry: Line String") != NULL, "%s", out);
    if (crs)
        TT_CHECKF(strstr(out, crs) != NULL, "no %s in %s", crs, out);
}

/* ogrinfo's summary of path does not contain text. */
static void check_ogrinfo_lacks(const char *path, const char *text)
{
    char cmd[700], out[16384];
    FILE *p;
    size_t n;
    if (!have_tool("ogrinfo"))
        return;
    snprintf(cmd, sizeof cmd, "ogrinfo -ro -al -so '%s' 2>&1", path);
    p = popen(cmd, "r");
    n = fread(out, 1, sizeof out - 1, p);
    out[n] = 0;
    pclose(p);
    TT_CHECKF(strstr(out, text) == NULL, "%s in %s", text, out);
}

static void test_geojson_ogrinfo(void)
{
    td_ctx cx;
    td_lines *ls;
    td_ctx_init(&cx);
    ls = sample_lines(&cx);
    TT_CHECK(td_geojson_write_lines(tmp("ogr.geojson"), ls, NULL, &cx) == 0);
    /* OGR sees the engineering CRS of the pixel frame, not EPSG:4326 */
    check_ogrinfo(tmp("ogr.geojson"), 3, "ENGCRS[\"" TD_PIXEL_CRS "\"");
    check_ogrinfo_lacks(tmp("ogr.geojson"), "4326");
    td_lines_free(ls);
}

static void test_geojson_georef(void)
{
    td_ctx cx;
    td_lines *ls;
    td_georef g;
    jv *root, *coords, *crs;
    const char *path = tmp("geo.geojson");
    td_ctx_init(&cx);
    td_georef_init(&g);
    g.valid = 1;
    g.epsg = 32633;
    g.gt[0] = 500000;
    g.gt[1] = 2;
    g.gt[2] = 0;
    g.gt[3] = 4000000;
    g.gt[4] = 0;
    g.gt[5] = -2;
    ls = sample_lines(&cx);
    TT_CHECKF(td_geojson_write_lines(path, ls, &g, &cx) == 0, "%s",
              td_errmsg(&cx));
    root = jload(path);
    TT_CHECK(root != NULL);
    crs = jget(jget(root, "crs"), "properties");
    TT_CHECK(crs && !strcmp(jget(crs, "name")->str, "urn:ogc:def:crs:EPSG::32633"));
    coords = jget(jget(jat(jget(root, "features"), 1), "geometry"), "coordinates");
    check_point(jat(coords, 0), 500001, 3999993.5, 1e-6);
    check_point(jat(coords, 1), 500080.25, 4000000 - 14.0008, 1e-3);
    jfree(root);
    check_ogrinfo(path, 3, "32633");
    td_lines_free(ls);
}

static int temp_left(void)
{
    DIR *d = opendir(tt_tmpdir());
    struct dirent *e;
    int n = 0;
    while (d && (e = readdir(d)))
        if (strstr(e->d_name, ".tmp."))
            n++;
    if (d)
        closedir(d);
    return n;
}

static void test_geojson_failures(void)
{
    td_ctx cx;
    td_lines *ls;
    const char *path = tmp("keep.geojson");
    char bad[700];
    struct stat st0, st1;
    jv *root;
    td_ctx_init(&cx);
    ls = sample_lines(&cx);
    snprintf(bad, sizeof bad, "%s/missing/dir/x.geojson", tt_tmpdir());
    TT_CHECK(td_geojson_write_lines(bad, ls, NULL, &cx) == TD_EIO);
    TT_CHECK(strstr(td_errmsg(&cx), bad) != NULL);
    td_ctx_clear(&cx);
    TT_CHECK(td_geojson_write_lines(path, ls, NULL, &cx) == 0);
    TT_CHECK(stat(path, &st0) == 0);
    td_line_push(&ls->v[1], NAN, 1.0, &cx); /* a bad point in line 1 */
    TT_CHECK(td_geojson_write_lines(path, ls, NULL, &cx) == TD_EINVAL);
    TT_CHECK(strstr(td_errmsg(&cx), path) != NULL);
    TT_CHECK(stat(path, &st1) == 0 && st1.st_size == st0.st_size &&
             st1.st_ino == st0.st_ino);
    root = jload(path); /* the previous file, still whole */
    TT_CHECK(root && jcount(jget(root, "features")) == 3);
    jfree(root);
    TT_CHECK(temp_left() == 0);
    td_lines_free(ls);
}

static void test_geojson_empty_and_precision(void)
{
    td_ctx cx;
    td_lines *ls;
    td_line *l;
    jv *root, *c;
    const char *path = tmp("empty.geojson");
    td_ctx_init(&cx);
    ls = td_lines_new(&cx);
    TT_CHECK(td_geojson_write_lines(path, ls, NULL, &cx) == 0);
    root = jload(path);
    TT_CHECK(root && jget(root, "features") && jcount(jget(root, "features")) == 0);
    jfree(root);
    l = td_lines_add(ls, &cx);
    td_line_push(l, -0.0004, 123456.7896, &cx);
    td_line_push(l, -12.25, 2e9, &cx); /* outside the fast formatter */
    TT_CHECK(td_geojson_write_lines(path, ls, NULL, &cx) == 0);
    root = jload(path);
    c = jget(jget(jat(jget(root, "features"), 0), "geometry"), "coordinates");
    check_point(jat(c, 0), 0, -123456.790, 1e-9);
    check_point(jat(c, 1), -12.25, -2e9, 1e-9);
    jfree(root);
    td_lines_free(ls);
}

/* Distance of (x,y) from the polyline l (closing segment included when
 * closed). */
static double dist_to_line(const td_line *l, double x, double y)
{
    double best = 1e300;
    size_t i, n = l->n + (l->closed ? 1 : 0);
    for (i = 0; i + 1 < n; i++) {
        const double *a = l->xy + 2 * i, *b = l->xy + 2 * ((i + 1) % l->n);
        double dx = b[0] - a[0], dy = b[1] - a[1], L = dx * dx + dy * dy;
        double t = L > 0 ? ((x - a[0]) * dx + (y - a[1]) * dy) / L : 0;
        t = t < 0 ? 0 : t > 1 ? 1 : t;
        dx = a[0] + t * dx - x;
        dy = a[1] + t * dy - y;
        best = fmin(best, sqrt(dx * dx + dy * dy));
    }
    return best;
}

/* Douglas-Peucker on a traced-looking ring and an open staircase: every
 * traced point within the tolerance of the simplified line, far fewer
 * vertices, ends and closure kept, tol 0 a no-op. */
static void test_simplify(void)
{
    td_ctx cx;
    td_lines *ls, *orig;
    size_t i, k;
    td_ctx_init(&cx);
    ls = td_lines_new(&cx);
    td_line *l = td_lines_add(ls, &cx);
    for (i = 0; i < 400; i++) { /* a ring of radius 60 on pixel centres */
        double a = 2 * M_PI * i / 400.0;
        td_line_push(l, floor(100 + 60 * cos(a)) + 0.5,
                     floor(100 + 60 * sin(a)) + 0.5, &cx);
    }
    l->closed = 1;
    l = td_lines_add(ls, &cx);
    for (i = 0; i < 300; i++) /* a staircase: a line of slope 1/3 */
        td_line_push(l, i + 0.5, floor(i / 3.0) + 0.5, &cx);
    orig = td_lines_copy(ls, &cx);
    TT_CHECK(td_lines_simplify(ls, 0, &cx) == 0 && ls->v[0].n == 400 &&
             ls->v[1].n == 300);
    TT_CHECK(td_lines_simplify(ls, 0.25, &cx) == 0);
    for (k = 0; k < 2; k++) {
        double worst = 0;
        for (i = 0; i < orig->v[k].n; i++)
            worst = fmax(worst, dist_to_line(&ls->v[k], orig->v[k].xy[2 * i],
                                             orig->v[k].xy[2 * i + 1]));
        TT_CHECKF(worst <= 0.25 + 1e-9, "line %zu: %g px off", k, worst);
        TT_CHECKF(ls->v[k].n < orig->v[k].n * 3 / 4 && ls->v[k].n >= 3,
                  "line %zu: %zu of %zu points", k, ls->v[k].n,
                  orig->v[k].n);
    }
    TT_CHECK(ls->v[0].closed && ls->v[0].xy[0] == orig->v[0].xy[0]);
    TT_CHECK(ls->v[1].xy[0] == 0.5 && ls->v[1].xy[2 * ls->v[1].n - 2] ==
                                           299.5);
    TT_CHECK(td_lines_simplify(ls, 5, &cx) == 0 && ls->v[0].n >= 3);
    td_lines_free(ls);
    td_lines_free(orig);
}

/* The ends of open lines, sorted, found by their point: two lines
 * ending at one point are both found there (the lower index first), a
 * closed line has no ends, a line the filter refuses none either. */
static int not_line_2(size_t i, const void *u)
{
    (void)u;
    return i != 2;
}

static void test_line_ends(void)
{
    static const double pt[4][4] = {
        {5, 5, 9, 1}, {9, 1, 0, 3}, {7, 7, 8, 8}, {2, 2, 3, 3}};
    td_lines *ls = td_lines_new(NULL);
    td_line_end *e = NULL;
    size_t n = 0, k;
    int i;
    for (i = 0; i < 4; i++) {
        td_line *l = td_lines_add(ls, NULL);
        td_line_push(l, pt[i][0], pt[i][1], NULL);
        td_line_push(l, pt[i][2], pt[i][3], NULL);
        l->closed = i == 3;
    }
    TT_CHECK(td_line_ends(ls, not_line_2, NULL, &e, &n, NULL) == 0 && n == 4);
    for (k = 1; e && k < n; k++)
        TT_CHECK(e[k - 1].x < e[k].x ||
                 (e[k - 1].x == e[k].x && e[k - 1].y <= e[k].y));
    k = td_line_ends_at(e, n, 9, 1);
    TT_CHECKF(k + 1 < n && e[k].line == 0 && e[k].last == 1 &&
                  e[k + 1].line == 1 && e[k + 1].last == 0,
              "at 9,1: end %zu of %zu", k, n);
    TT_CHECK(td_line_ends_at(e, n, 7, 7) == n); /* line 2: refused */
    TT_CHECK(td_line_ends_at(e, n, 2, 2) == n); /* line 3: closed */
    TT_CHECK(td_line_ends_at(e, n, 0, 3) < n);
    free(e);
    td_lines_free(ls);
}

int main(void)
{
    TT_RUN(test_lines_basic);
    TT_RUN(test_line_length);
    TT_RUN(test_line_append);
    TT_RUN(test_geojson_pixel_units);
    TT_RUN(test_geojson_ogrinfo);
    TT_RUN(test_geojson_georef);
    TT_RUN(test_geojson_failures);
    TT_RUN(test_geojson_empty_and_precision);
    TT_RUN(test_simplify);
    TT_RUN(test_line_ends);
    return tt_summary();
}
