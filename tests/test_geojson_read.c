/* test_geojson_read.c: the GeoJSON lines reader.  Generated truth contours
 * go through td_geojson_write_lines and back (pixel and map units); hand
 * written files cover MultiLineStrings, QGIS-style members, skipped
 * geometry types and every kind of bad input. */
#define _POSIX_C_SOURCE 200809L
#include "tests/tt.h"

#include "src/io/io.h"
#include "src/core/core.h"
#include "samples/gen/gen.h"

#include <stdlib.h>
#include <string.h>

static char *tmp(const char *name)
{
    static char p[8][600];
    static int k;
    char *s = p[k++ & 7];
    snprintf(s, 600, "%s/%s", tt_tmpdir(), name);
    return s;
}

static int write_text(const char *path, const char *s)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return -1;
    fputs(s, f);
    return fclose(f);
}

/* Truth contours of a generated terrain, with varied flags. */
static td_lines *truth_lines(void)
{
    td_gen_params p = td_gen_defaults();
    td_grid_f32 *dem = NULL;
    td_lines *ls = NULL;
    size_t i;
    p.w = 300;
    p.h = 220;
    if (td_gen_terrain(&p, &dem, NULL) != 0 ||
        td_gen_contours(dem, 0.0, 20.0, &ls, NULL) != 0) {
        td_grid_f32_free(dem);
        return NULL;
    }
    td_grid_f32_free(dem);
    for (i = 0; i < ls->n; i++) {
        td_line *l = &ls->v[i];
        l->bridged = (int)(i % 3 == 1);
        l->depression = l->closed && i % 2 == 0; /* the property round trip */
        l->piece = !l->closed && i % 3 == 0;
        l->parent = i % 4 == 2 ? (long)i - 1 : -1;
        if (i % 5 == 3)
            l->has_height = 0;
        l->id = (long)(10 + 2 * i);
    }
    return ls;
}

/* a and b hold the same lines within tol px. */
static void compare_lines(const td_lines *a, const td_lines *b, double tol)
{
    size_t i, j, bad = 0;
    double worst = 0;
    TT_CHECKF(a->n == b->n, "%zu vs %zu lines", a->n, b->n);
    for (i = 0; i < a->n && i < b->n; i++) {
        const td_line *x = &a->v[i], *y = &b->v[i];
        int same = x->id == y->id && x->closed == y->closed &&
                   x->edge == y->edge && x->bridged == y->bridged &&
                   x->depression == y->depression && x->piece == y->piece &&
                   x->parent == y->parent && x->has_height == y->has_height &&
                   (!x->has_height || x->height == y->height) && x->n == y->n &&
                   fabs(x->width - y->width) <= 0.005;
        if (!same) {
            if (bad++ < 3)
                fprintf(stderr, "  line %zu: id %ld/%ld closed %d/%d n %zu/%zu\n",
                        i, x->id, y->id, x->closed, y->closed, x->n, y->n);
            continue;
        }
        for (j = 0; j < 2 * x->n; j++) {
            double d = fabs(x->xy[j] - y->xy[j]);
            worst = d > worst ? d : worst;
        }
    }
    TT_CHECKF(bad == 0, "%zu lines differ", bad);
    TT_CHECKF(worst <= tol, "worst point error %g", worst);
}

static void test_round_trip_pixels(void)
{
    td_ctx cx;
    td_lines *ls = truth_lines(), *back = NULL;
    size_t skipped = 99, closed = 0, i;
    td_ctx_init(&cx);
    TT_CHECK(ls && ls->n > 10);
    if (!ls)
        return;
    for (i = 0; i < ls->n; i++) {
        closed += ls->v[i].closed;
        ls->v[i].width = i % 3 ? 2.25 + 0.125 * (double)(i % 5) : 0.0;
    }
    TT_CHECK(closed > 0 && closed < ls->n); /* rings and open lines */
    TT_CHECKF(td_geojson_write_lines(tmp("px.geojson"), ls, NULL, &cx) == 0,
              "%s", td_errmsg(&cx));
    TT_CHECKF(td_geojson_read_lines(tmp("px.geojson"), NULL, &back, &skipped,
                                    &cx) == 0, "%s", td_errmsg(&cx));
    TT_CHECK(skipped == 0);
    if (back)
        compare_lines(ls, back, 1e-3);
    td_lines_free(back);
    td_lines_free(ls);
}

static void georef_round_trip(const double gt[6], int epsg, double tol)
{
    td_ctx cx;
    td_lines *ls = truth_lines(), *back = NULL;
    td_georef g;
    td_ctx_init(&cx);
    td_georef_init(&g);
    g.valid = 1;
    g.epsg = epsg;
    memcpy(g.gt, gt, sizeof g.gt);
    if (!ls)
        return;
    TT_CHECKF(td_geojson_write_lines(tmp("map.geojson"), ls, &g, &cx) == 0,
              "%s", td_errmsg(&cx));
    TT_CHECKF(td_geojson_read_lines(tmp("map.geojson"), &g, &back, NULL,
                                    &cx) == 0, "%s", td_errmsg(&cx));
    if (back)
        compare_lines(ls, back, tol);
    td_lines_free(back);
    td_lines_free(ls);
}

/* The writer keeps 9 significant digits of map coordinates: a UTM
 * northing (7 integer digits) is rounded to 0.01 m, 0.0025 px at 2 m. */
static void test_round_trip_map(void)
{
    const double utm[6] = {500000, 2, 0, 4200000, 0, -2};
    const double rot[6] = {1000.5, 1.5, 0.2, 2000.25, 0.3, -1.5};
    georef_round_trip(utm, 32633, 0.5 * 0.01 / 2 + 1e-9);
    georef_round_trip(rot, 0, 1e-3);
}

static td_lines *read_text(const char *name, const char *json,
                           size_t *skipped, td_ctx *cx)
{
    td_lines *ls = NULL;
    int rc;
    write_text(tmp(name), json);
    td_ctx_init(cx);
    rc = td_geojson_read_lines(tmp(name), NULL, &ls, skipped, cx);
    TT_CHECKF(rc == 0, "%s", td_errmsg(cx));
    return ls;
}

static void test_multilinestring(void)
{
    td_ctx cx;
    size_t skipped = 0;
    td_lines *ls = read_text("multi.geojson",
        "{\"type\":\"FeatureCollection\",\"features\":["
        "{\"type\":\"Feature\",\"properties\":{\"id\":7,\"height\":100},"
        "\"geometry\":{\"type\":\"MultiLineString\",\"coordinates\":["
        "[[0,0],[1,0],[1,1],[0,0]], [[5,5],[6,6]], [], [[7,7],[8,8],[9,7]]]}},"
        "{\"type\":\"Feature\",\"properties\":{\"id\":8,\"height\":110,"
        "\"closed\":false},\"geometry\":{\"type\":\"LineString\","
        "\"coordinates\":[[2,2],[3,3]]}}]}", &skipped, &cx);
    if (!ls)
        return;
    TT_CHECKF(ls->n == 4, "%zu lines", ls->n);
    if (ls->n == 4) {
        TT_CHECK(ls->v[0].id == 7 && ls->v[0].closed && ls->v[0].n == 3);
        TT_CHECK(ls->v[1].id == 9 && !ls->v[1].closed && ls->v[1].n == 2);
        TT_CHECK(ls->v[2].id == 10 && ls->v[2].n == 3 && ls->v[2].xy[4] == 9);
        TT_CHECK(ls->v[3].id == 8 && ls->v[3].n == 2);
        TT_CHECK(ls->v[1].has_height && ls->v[1].height == 100);
        TT_CHECK(ls->v[3].height == 110);
    }
    td_lines_free(ls);
}

static void test_qgis_style(void)
{
    td_ctx cx;
    size_t skipped = 0;
    td_lines *ls = read_text("qgis.geojson",
        "\xef\xbb\xbf{\n\"type\": \"FeatureCollection\",\n\"name\": \"contours\",\n"
        "\"crs\": { \"type\": \"name\", \"properties\": { \"name\": "
        "\"urn:ogc:def:crs:EPSG::32633\" } },\n\"features\": [\n"
        "{ \"type\": \"Feature\", \"bbox\": [0, 0, 1, 1], \"geometry\": { "
        "\"coordinates\": [ [ 1.5, 2.5, 99 ], [ 1e2, 2E-1 ], [ 3.25e+1, -0.5 ] ], "
        "\"type\": \"LineString\" }, \"properties\": { \"parent\": null, "
        "\"label\": \"h\\u00f6he \\\"x\\\" \\ud83d\\ude00\", \"closed\": false, "
        "\"height\": null, \"extra\": {\"a\": [1, 2, {\"b\": [true, null]}]}, "
        "\"edge\": 1, \"id\": 3 } },\n"
        "{ \"type\": \"Feature\", \"properties\": { \"height\": 250.5 }, "
        "\"geometry\": { \"type\": \"LineString\", \"coordinates\": "
        "[[0,0],[4,0],[4,4],[0,0]] } },\n"
        "{ \"type\": \"Feature\", \"properties\": { \"id\": 20 }, "
        "\"geometry\": { \"type\": \"Point\", \"coordinates\": [1, 2] } },\n"
        "{ \"type\": \"Feature\", \"properties\": {}, \"geometry\": { "
        "\"type\": \"Polygon\", \"coordinates\": [[[0,0],[1,0],[1,1],[0,0]]] } },\n"
        "{ \"type\": \"Feature\", \"properties\": null, \"geometry\": null }\n"
        "], \"bbox\": [0, 0, 100, 4]\n}\n", &skipped, &cx);
    if (!ls)
        return;
    TT_CHECKF(ls->n == 2, "%zu lines", ls->n);
    TT_CHECKF(skipped == 3, "%zu skipped", skipped);
    if (ls->n == 2) {
        const td_line *a = &ls->v[0], *b = &ls->v[1];
        TT_CHECK(a->id == 3 && !a->has_height && a->edge && !a->closed &&
                 a->parent == -1 && a->n == 3);
        TT_CHECK(a->xy[0] == 1.5 && a->xy[1] == 2.5 && a->xy[2] == 100 &&
                 a->xy[3] == 0.2 && a->xy[4] == 32.5 && a->xy[5] == -0.5);
        /* no id: the feature's index; no closed: first == last */
        TT_CHECK(b->id == 1 && b->closed && b->n == 3 && b->has_height &&
                 b->height == 250.5);
    }
    td_lines_free(ls);
}

/* Reading json must fail with TD_EFORMAT and a message with the file
 * name and word. */
static void expect_bad(const char *json, const char *word)
{
    td_ctx cx;
    td_lines *ls = NULL;
    const char *p = tmp("bad.geojson");
    int rc;
    write_text(p, json);
    td_ctx_init(&cx);
    rc = td_geojson_read_lines(p, NULL, &ls, NULL, &cx);
    TT_CHECKF(rc == TD_EFORMAT, "rc %d for %.60s", rc, json);
    TT_CHECK(ls == NULL);
    TT_CHECKF(strstr(td_errmsg(&cx), p) && strstr(td_errmsg(&cx), word),
              "'%s' for %.60s", td_errmsg(&cx), json);
}

#define FC_HEAD "{\"type\":\"FeatureCollection\",\"features\":["
#define F_HEAD "{\"type\":\"Feature\",\"properties\":"

static char *nested(const char *head, size_t depth, const char *tail)
{
    size_t hn = strlen(head), tn = strlen(tail);
    char *s = malloc(hn + depth + tn + 1);
    memcpy(s, head, hn);
    memset(s + hn, '[', depth);
    memcpy(s + hn + depth, tail, tn + 1);
    return s;
}

static void test_bad_json(void)
{
    char *s;
    expect_bad("", "not a FeatureCollection");
    expect_bad("[1,2]", "not a FeatureCollection");
    expect_bad("{\"type\":\"Feature\",\"features\":[]}", "not a FeatureCollection");
    expect_bad("{\"type\":\"FeatureCollection\",\"features\":{}}",
               "not a FeatureCollection");
    expect_bad("{\"type\":\"FeatureCollection\"}", "not a FeatureCollection");
    expect_bad(FC_HEAD F_HEAD "{\"id\":1},\"geometry\":{\"type\":\"LineString\","
               "\"coordinates\":[[1,2],[3,", "bad JSON at byte");
    expect_bad(FC_HEAD F_HEAD "{\"id\":1}}", "expected ',' or ']'");
    expect_bad(FC_HEAD "]} x", "the end of the file");
    expect_bad(FC_HEAD F_HEAD "{\"height\":\"abc\"}}]}", "\"height\" must be");
    expect_bad(FC_HEAD F_HEAD "{\"id\":1.5}}]}", "\"id\" must be");
    expect_bad(FC_HEAD F_HEAD "{},\"geometry\":{\"type\":\"LineString\","
               "\"coordinates\":\"x\"}}]}", "an array for \"coordinates\"");
    expect_bad(FC_HEAD F_HEAD "{},\"geometry\":{\"type\":\"LineString\","
               "\"coordinates\":[[1],[2]]}}]}", "at least 2 numbers");
    expect_bad(FC_HEAD F_HEAD "{},\"geometry\":{\"type\":\"LineString\","
               "\"coordinates\":[[[1,2]]]}}]}", "bad LineString coordinates");
    expect_bad(FC_HEAD F_HEAD "{\"a\":\"\\q\"}}]}", "escape");
    expect_bad(FC_HEAD F_HEAD "{\"a\":1.}}]}", "digit after '.'");
    expect_bad(FC_HEAD F_HEAD "{\"a\":-}}]}", "a value");
    expect_bad(FC_HEAD F_HEAD "{\"a\":tru}}]}", "a value");
    expect_bad(FC_HEAD "{\"type\":\"Other\"}]}", "not \"Feature\"");
    s = nested("", 100000, "");
    expect_bad(s, "not a FeatureCollection");
    free(s);
    s = nested(FC_HEAD F_HEAD "{\"deep\":", 100000, "");
    expect_bad(s, "nesting at most 512 deep");
    free(s);
    s = nested(FC_HEAD F_HEAD "{},\"geometry\":{\"type\":\"LineString\","
               "\"coordinates\":", 100000, "");
    expect_bad(s, "coordinates nested");
    free(s);
}

static void test_missing_file(void)
{
    td_ctx cx;
    td_lines *ls = NULL;
    td_ctx_init(&cx);
    TT_CHECK(td_geojson_read_lines(tmp("nope.geojson"), NULL, &ls, NULL,
                                   &cx) == TD_EIO);
    TT_CHECK(ls == NULL && strstr(td_errmsg(&cx), "nope.geojson"));
}

int main(void)
{
    TT_RUN(test_round_trip_pixels);
    TT_RUN(test_round_trip_map);
    TT_RUN(test_multilinestring);
    TT_RUN(test_qgis_style);
    TT_RUN(test_bad_json);
    TT_RUN(test_missing_file);
    return tt_summary();
}
