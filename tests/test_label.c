/* Tests of the containment tree and automatic heights (src/core/contain.c,
 * scanner/label.c) on generated terrains with a known truth: every line's
 * height must equal the truth exactly (heights are multiples of the
 * interval, so there is no tolerance to give). */
#include "tests/tt.h"
#include "tests/util/match.h"

#include "samples/gen/gen.h"
#include "src/core/core.h"
#include "scanner/label.h"
#include "scanner/scan.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

/* These tests are of the containment-tree labeller (--labeller tree). */
static td_label_params tree_defaults(void)
{
    td_label_params p = td_label_defaults();
    p.method = TD_LABEL_TREE;
    return p;
}

typedef struct truth {
    td_gen_params gp;
    td_grid_f32 *dem;
    td_lines *lines;
    double interval;
} truth;

static int make_truth(truth *t, td_gen_terrain_kind kind, int w, int h)
{
    td_ctx cx;
    td_ctx_init(&cx);
    memset(t, 0, sizeof *t);
    t->gp = td_gen_defaults();
    t->gp.terrain = kind;
    t->gp.w = w;
    t->gp.h = h;
    if (td_gen_terrain(&t->gp, &t->dem, &cx) != 0)
        return -1;
    t->interval = td_gen_auto_interval(&t->gp, t->dem);
    return td_gen_contours(t->dem, 0, t->interval, &t->lines, &cx);
}

static void free_truth(truth *t)
{
    td_grid_f32_free(t->dem);
    td_lines_free(t->lines);
}

/* A copy of the truth lines with heights and parents wiped. */
static td_lines *unlabelled(const td_lines *src)
{
    td_lines *ls = td_lines_new(NULL);
    size_t i, k;
    for (i = 0; ls && i < src->n; i++) {
        td_line *l = td_lines_add(ls, NULL);
        for (k = 0; l && k < src->v[i].n; k++)
            td_line_push(l, src->v[i].xy[2 * k], src->v[i].xy[2 * k + 1], NULL);
        l->closed = src->v[i].closed;
        l->edge = src->v[i].edge;
    }
    return ls;
}

static td_label_point on_line(const td_line *l, double height)
{
    td_label_point q;
    q.x = l->xy[2 * (l->n / 2)]; /* the middle vertex */
    q.y = l->xy[2 * (l->n / 2) + 1];
    q.height = height;
    q.id = -1;
    return q;
}

static double dem_at(const td_grid_f32 *g, double x, double y)
{
    return g->data[(size_t)y * g->stride + (size_t)x];
}

/* Innermost truth rings lower than the ground at their centre: depressions. */
static long find_pit(const truth *t, double *cx_, double *cy_)
{
    size_t i;
    for (i = 0; i < t->lines->n; i++) {
        const td_line *l = &t->lines->v[i];
        double sx = 0, sy = 0;
        size_t k;
        if (!l->closed)
            continue;
        for (k = 0; k < l->n; k++)
            sx += l->xy[2 * k], sy += l->xy[2 * k + 1];
        sx /= l->n, sy /= l->n;
        if (dem_at(t->dem, sx, sy) < l->height - 0.5 * t->interval) {
            *cx_ = sx, *cy_ = sy;
            return (long)i;
        }
    }
    return -1;
}

static size_t count_wrong(const td_lines *got, const td_lines *want, int print)
{
    size_t i, bad = 0;
    for (i = 0; i < got->n; i++)
        if (!got->v[i].has_height || got->v[i].height != want->v[i].height) {
            if (print && bad < 5)
                fprintf(stderr, "  line %zu: %g (has %d), truth %g\n", i,
                        got->v[i].height, got->v[i].has_height, want->v[i].height);
            bad++;
        }
    return bad;
}

/* The longest open line of height h0 != other, to put known points on. */
static long longest_open(const td_lines *ls, double not_h)
{
    long best = -1;
    size_t i;
    for (i = 0; i < ls->n; i++)
        if (!ls->v[i].closed && ls->v[i].height != not_h &&
            (best < 0 || ls->v[i].n > ls->v[best].n))
            best = (long)i;
    return best;
}

/* Cone: concentric rings (the lines cutting the corners below 0 left out):
 * one known point on the outermost ring labels every ring. */
static void test_cone_one_point(void)
{
    truth t;
    td_lines *ls;
    td_label_params p = tree_defaults();
    td_label_report rep;
    td_label_point q;
    td_ctx cx;
    long outer = -1;
    size_t i;
    td_ctx_init(&cx);
    TT_CHECK(make_truth(&t, TD_GEN_CONE, 400, 300) == 0);
    for (i = t.lines->n; i-- > 0;) /* the corner lines: see docs/label.md */
        if (!t.lines->v[i].closed)
            td_lines_remove(t.lines, i);
    ls = unlabelled(t.lines);
    for (i = 0; i < t.lines->n; i++)
        if (t.lines->v[i].closed &&
            (outer < 0 || t.lines->v[i].n > t.lines->v[outer].n))
            outer = (long)i;
    q = on_line(&t.lines->v[outer], t.lines->v[outer].height);
    p.interval = t.interval, p.w = 400, p.h = 300, p.known = &q, p.nknown = 1;
    TT_CHECKF(td_label_auto(ls, &p, &rep, &cx) == 0, "%s", cx.msg);
    TT_CHECK(rep.labelled == ls->n && rep.undetermined == 0);
    TT_CHECK(count_wrong(ls, t.lines, 1) == 0);
    for (i = 0; i < ls->n; i++) /* every ring's parent is one interval lower */
        if (ls->v[i].closed && ls->v[i].parent >= 0)
            TT_CHECK(t.lines->v[ls->v[i].parent].height ==
                     t.lines->v[i].height - t.interval);
    td_label_report_free(&rep);
    td_lines_free(ls);
    free_truth(&t);
}

/* Index contours decide what one known point cannot: the cone with the
 * lines that cut the sheet's corners (their slope direction is not in the
 * topology), every 5th contour drawn thicker: one known point on a thin
 * ring and --index-every 5 label every line right, and fewer lines are
 * left as assumed than without the widths. */
static size_t label_cone_index(const truth *t, int every, size_t *assumed)
{
    td_lines *ls = unlabelled(t->lines);
    td_label_params p = tree_defaults();
    td_label_report rep;
    td_label_point q;
    td_ctx cx;
    long ring = -1;
    size_t i, wrong = (size_t)-1;
    td_ctx_init(&cx);
    for (i = 0; i < t->lines->n; i++) {
        int index = fmod(fabs(t->lines->v[i].height / t->interval), 5.0) == 0;
        ls->v[i].width = index ? 4.5 : 2.5;
        if (t->lines->v[i].closed && !index &&
            (ring < 0 || t->lines->v[i].n > t->lines->v[ring].n))
            ring = (long)i;
    }
    q = on_line(&t->lines->v[ring], t->lines->v[ring].height);
    p.interval = t->interval, p.w = 1000, p.h = 1000, p.known = &q;
    p.nknown = 1, p.index_every = every;
    if (td_label_auto(ls, &p, &rep, &cx) == 0) {
        wrong = count_wrong(ls, t->lines, every > 0);
        *assumed = rep.assumed;
        td_label_report_free(&rep);
    }
    td_lines_free(ls);
    return wrong;
}

static void test_index_decides(void)
{
    truth t;
    size_t i, open = 0, a0 = 0, a1 = 0, w1;
    TT_CHECK(make_truth(&t, TD_GEN_CONE, 1000, 1000) == 0);
    for (i = 0; i < t.lines->n; i++)
        open += !t.lines->v[i].closed;
    TT_CHECK(open >= 8);
    label_cone_index(&t, 0, &a0);
    w1 = label_cone_index(&t, 5, &a1);
    TT_CHECKF(w1 == 0, "%zu of %zu lines wrong (%zu cut by the border)", w1,
              t.lines->n, open);
    TT_CHECKF(a1 < a0 / 4, "assumed: %zu with the widths, %zu without", a1,
              a0);
    free_truth(&t);
}

/* Correct known points never contradict: on the hills (a depression of
 * nested rings, a saddle, lines leaving the sheet), 40 random sets of 2-12
 * points on true lines all label, and each known line gets its height. */
static void test_true_points_agree(void)
{
    truth t;
    td_label_point q[12];
    long which[12];
    unsigned seed = 7;
    int set, failed = 0, wrong_known = 0;
    TT_CHECK(make_truth(&t, TD_GEN_HILLS, 600, 450) == 0);
    for (set = 0; set < 40; set++) {
        td_lines *ls = unlabelled(t.lines);
        td_label_params p = tree_defaults();
        td_label_report rep;
        td_ctx cx;
        int k, nk = 2 + set % 11;
        td_ctx_init(&cx);
        for (k = 0; k < nk; k++) {
            seed = seed * 1103515245u + 12345u;
            which[k] = (long)((seed >> 8) % t.lines->n);
            q[k] = on_line(&t.lines->v[which[k]],
                           t.lines->v[which[k]].height);
        }
        p.interval = t.interval, p.w = 600, p.h = 450;
        p.known = q, p.nknown = (size_t)nk;
        if (td_label_auto(ls, &p, &rep, &cx) != 0) {
            if (failed++ < 3)
                fprintf(stderr, "  set %d (%d points): %s\n", set, nk,
                        cx.msg);
        } else {
            for (k = 0; k < nk; k++)
                wrong_known += ls->v[which[k]].height !=
                               t.lines->v[which[k]].height;
            td_label_report_free(&rep);
        }
        td_lines_free(ls);
    }
    TT_CHECKF(failed == 0, "%d of 40 sets refused", failed);
    TT_CHECKF(wrong_known == 0, "%d known lines off their height", wrong_known);
    free_truth(&t);
}

/* HILLS: two summits at a saddle, a depression, lines leaving the sheet.
 * Known: two points on open lines (the slope's direction across the
 * border-closed lines is not in the topology) and one spot height in the
 * depression (a ring is a hill unless told otherwise). */
static void label_hills(int w, int h, int use_mark)
{
    truth t;
    td_lines *ls;
    td_label_params p = tree_defaults();
    td_label_report rep;
    td_label_point q[3];
    td_ctx cx;
    double px = 0, py = 0, dep[2];
    long a, b, pit;
    td_ctx_init(&cx);
    TT_CHECK(make_truth(&t, TD_GEN_HILLS, w, h) == 0);
    ls = unlabelled(t.lines);
    a = longest_open(t.lines, NAN);
    b = longest_open(t.lines, t.lines->v[a].height);
    pit = find_pit(&t, &px, &py);
    TT_CHECK(a >= 0 && b >= 0 && pit >= 0);
    q[0] = on_line(&t.lines->v[a], t.lines->v[a].height);
    q[1] = on_line(&t.lines->v[b], t.lines->v[b].height);
    q[2].x = px, q[2].y = py, q[2].id = -1;
    q[2].height = dem_at(t.dem, px, py);
    dep[0] = px, dep[1] = py;
    p.interval = t.interval, p.w = w, p.h = h, p.known = q;
    p.nknown = use_mark ? 2 : 3;
    if (use_mark)
        p.depressions = dep, p.ndepressions = 1;
    TT_CHECKF(td_label_auto(ls, &p, &rep, &cx) == 0, "%s", cx.msg);
    TT_CHECK(rep.labelled == ls->n && rep.undetermined == 0);
    TT_CHECKF(count_wrong(ls, t.lines, 1) == 0, "%dx%d mark %d", w, h, use_mark);
    TT_CHECK(rep.warnings == 0);
    td_label_report_free(&rep);
    td_lines_free(ls);
    free_truth(&t);
}

static void test_hills_spot(void) { label_hills(600, 450, 0); label_hills(800, 800, 0); }
static void test_hills_mark(void) { label_hills(600, 450, 1); }

/* How many wrongly labelled lines the report lists as assumed. */
static size_t assumed_wrong(const td_lines *got, const td_lines *want,
                            const td_label_report *rep)
{
    size_t i, j, n = 0;
    for (i = 0; i < got->n; i++)
        if (got->v[i].height != want->v[i].height)
            for (j = 0; j < rep->assumed; j++)
                n += rep->assumed_ids[j] == got->v[i].id;
    return n;
}

/* Without the depression's point, only the depression is wrong: the rest
 * does not depend on it, and the depression's rings are among the lines
 * reported as assumed. */
static void test_hills_without_pit(void)
{
    truth t;
    td_lines *ls;
    td_label_params p = tree_defaults();
    td_label_report rep;
    td_label_point q[2];
    td_ctx cx;
    double px, py;
    long a, b, pit;
    size_t bad;
    td_ctx_init(&cx);
    TT_CHECK(make_truth(&t, TD_GEN_HILLS, 600, 450) == 0);
    ls = unlabelled(t.lines);
    a = longest_open(t.lines, NAN);
    b = longest_open(t.lines, t.lines->v[a].height);
    pit = find_pit(&t, &px, &py);
    q[0] = on_line(&t.lines->v[a], t.lines->v[a].height);
    q[1] = on_line(&t.lines->v[b], t.lines->v[b].height);
    p.interval = t.interval, p.w = 600, p.h = 450, p.known = q, p.nknown = 2;
    TT_CHECK(td_label_auto(ls, &p, &rep, &cx) == 0);
    bad = count_wrong(ls, t.lines, 0);
    TT_CHECKF(bad >= 1 && bad <= 4, "%zu wrong", bad); /* the pit's rings */
    TT_CHECK(ls->v[pit].height != t.lines->v[pit].height);
    TT_CHECK(assumed_wrong(ls, t.lines, &rep) == bad); /* all are listed */
    td_label_report_free(&rep);
    td_lines_free(ls);
    free_truth(&t);
}

/* Two known points that cannot both hold: an error naming both and their
 * lines; nothing is labelled. */
static void test_contradiction(void)
{
    truth t;
    td_lines *ls;
    td_label_params p = tree_defaults();
    td_label_report rep;
    td_label_point q[2];
    td_ctx cx;
    size_t i;
    long in = -1, out;
    char ids[2][32];
    td_ctx_init(&cx);
    TT_CHECK(make_truth(&t, TD_GEN_CONE, 400, 300) == 0);
    ls = unlabelled(t.lines);
    TT_CHECK(td_label_auto(ls, &(td_label_params){.method = TD_LABEL_TREE,
                                                   .interval = 1, .w = 400,
                                                   .h = 300}, &rep, &cx) == 0);
    TT_CHECK(rep.undetermined == ls->n); /* no known point: nothing */
    td_label_report_free(&rep);
    for (i = 0; i < ls->n && in < 0; i++) /* a ring with a ring parent */
        if (ls->v[i].parent >= 0 && ls->v[ls->v[i].parent].closed)
            in = (long)i;
    TT_CHECK(in >= 0);
    out = ls->v[in].parent;
    q[0] = on_line(&t.lines->v[out], 100);
    q[1] = on_line(&t.lines->v[in], 100 + 3 * t.interval);
    p.interval = t.interval, p.w = 400, p.h = 300, p.known = q, p.nknown = 2;
    TT_CHECK(td_label_auto(ls, &p, &rep, &cx) == TD_EINVAL);
    snprintf(ids[0], sizeof ids[0], "line %ld", ls->v[out].id);
    snprintf(ids[1], sizeof ids[1], "line %ld", ls->v[in].id);
    TT_CHECKF(strstr(cx.msg, "contradict") && strstr(cx.msg, ids[0]) &&
              strstr(cx.msg, ids[1]), "%s", cx.msg);
    td_lines_free(ls);
    free_truth(&t);
}

/* Warnings: a height off the interval, a spot far from every line; an
 * error for a point off the sheet. */
static void test_warnings(void)
{
    truth t;
    td_lines *ls;
    td_label_params p = tree_defaults();
    td_label_report rep;
    td_label_point q[2];
    td_ctx cx;
    char at[64];
    td_ctx_init(&cx);
    TT_CHECK(make_truth(&t, TD_GEN_PLANE, 300, 300) == 0);
    ls = unlabelled(t.lines);
    q[0] = on_line(&t.lines->v[0], t.lines->v[0].height + 1);
    p.interval = t.interval, p.w = 300, p.h = 300, p.known = q, p.nknown = 1;
    q[1].x = 0.5 * (q[0].x + 150), q[1].y = 150, q[1].id = -1;
    q[1].height = dem_at(t.dem, q[1].x, q[1].y);
    TT_CHECK(td_label_auto(ls, &p, &rep, &cx) == 0);
    TT_CHECK(rep.warnings == 1 && rep.text && strstr(rep.text, "multiple"));
    snprintf(at, sizeof at, "at (%g,%g)", q[0].x, q[0].y); /* position */
    TT_CHECKF(strstr(rep.text, at), "%s", rep.text);
    td_label_report_free(&rep);
    p.far = 1; /* so that a spot height between the lines is "far" */
    p.near = 0.01;
    q[1].y = 150.3, q[1].height = dem_at(t.dem, q[1].x, q[1].y);
    p.nknown = 2;
    TT_CHECKF(td_label_auto(ls, &p, &rep, &cx) == 0, "%s", cx.msg);
    TT_CHECKF(rep.warnings == 2 && strstr(rep.text, "px from the nearest"),
              "%s", rep.text ? rep.text : "");
    TT_CHECK(count_wrong(ls, t.lines, 1) == 0);
    td_label_report_free(&rep);
    p.far = 150, p.near = 3;
    q[1].x = 301;
    p.nknown = 2;
    TT_CHECK(td_label_auto(ls, &p, &rep, &cx) == TD_EINVAL);
    TT_CHECKF(strstr(cx.msg, "off the"), "%s", cx.msg);
    td_lines_free(ls);
    free_truth(&t);
}

/* Crossing lines: two crossing lines found once with their ids and the
 * place; a line through a vertex of another found once; the true contours
 * of a generated sheet never cross. */
static void test_crossings(void)
{
    td_lines *ls = td_lines_new(NULL);
    td_crossing *v = NULL;
    td_line *l;
    truth t;
    size_t n = 9;
    double x;
    l = td_lines_add(ls, NULL); /* id 0: a horizontal line, 1-px steps */
    for (x = 10.5; x <= 90.5; x += 1)
        td_line_push(l, x, 50.5, NULL);
    l = td_lines_add(ls, NULL); /* id 1: a ring away from it */
    td_line_push(l, 20, 70, NULL), td_line_push(l, 30, 70, NULL);
    td_line_push(l, 30, 80, NULL), td_line_push(l, 20, 80, NULL);
    l->closed = 1;
    l = td_lines_add(ls, NULL); /* id 2: a vertical line through (40.5,50.5) */
    td_line_push(l, 40.5, 30.5, NULL), td_line_push(l, 40.5, 50.5, NULL);
    td_line_push(l, 40.5, 70.5, NULL);
    TT_CHECK(td_contain_crossings(ls, &v, &n, NULL) == 0);
    TT_CHECKF(n == 1 && v[0].a == 0 && v[0].b == 2 &&
                  fabs(v[0].x - 40.5) < 1e-9 && fabs(v[0].y - 50.5) < 1e-9,
              "%zu crossings", n);
    free(v);
    td_lines_free(ls);
    TT_CHECK(make_truth(&t, TD_GEN_HILLS, 600, 450) == 0);
    TT_CHECK(td_contain_crossings(t.lines, &v, &n, NULL) == 0 && n == 0);
    free(v);
    free_truth(&t);
}

/* A lattice of 30 horizontal and 30 vertical lines over 800 px (a vertex
 * per px, so the grid's cells hold many pieces): every pair crosses once,
 * at its lattice point, and one thread finds what two find, in order. */
static void test_crossings_lattice(void)
{
    td_lines *ls = td_lines_new(NULL);
    td_crossing *v[2] = {NULL, NULL};
    size_t n[2] = {0, 0}, i;
    int k, th, bad = 0;
    for (k = 0; k < 60; k++) {
        td_line *l = td_lines_add(ls, NULL);
        double c = 20.5 + 25.0 * (k % 30), x;
        for (x = 5.5; x <= 800.5; x += 1)
            td_line_push(l, k < 30 ? x : c, k < 30 ? c : x, NULL);
    }
    for (th = 0; th < 2; th++) {
        omp_set_num_threads(th + 1);
        TT_CHECK(td_contain_crossings(ls, &v[th], &n[th], NULL) == 0);
    }
    omp_set_num_threads(omp_get_num_procs());
    TT_CHECKF(n[0] == 900 && n[1] == 900, "%zu and %zu crossings", n[0],
              n[1]);
    for (i = 0; i < n[0] && i < n[1]; i++) {
        const td_crossing *c = &v[0][i];
        bad += memcmp(c, &v[1][i], sizeof *c) != 0 || c->a >= 30 ||
               c->b < 30 || fabs(c->y - (20.5 + 25.0 * (double)c->a)) > 1e-9 ||
               fabs(c->x - (20.5 + 25.0 * (double)(c->b - 30))) > 1e-9;
    }
    TT_CHECKF(bad == 0, "%d crossings differ or are misplaced", bad);
    free(v[0]);
    free(v[1]);
    td_lines_free(ls);
}

/* The cone's closed rings, outermost first (they nest: longer is
 * outside); the open corner lines removed from t. */
static size_t cone_chain(truth *t, long *chain, size_t max)
{
    size_t i, j, n = 0;
    for (i = t->lines->n; i-- > 0;)
        if (!t->lines->v[i].closed)
            td_lines_remove(t->lines, i);
    for (i = 0; i < t->lines->n && n < max; i++)
        chain[n++] = (long)i;
    for (i = 1; i < n; i++) /* insertion sort by length, longest first */
        for (j = i; j > 0 && t->lines->v[chain[j]].n >
                              t->lines->v[chain[j - 1]].n; j--) {
            long x = chain[j];
            chain[j] = chain[j - 1], chain[j - 1] = x;
        }
    return n;
}

/* A ring deleted from the traced lines (a missing line): a point on the
 * outer ring and a spot at the summit are one interval off the nesting.
 * The double gap tells where the contour is missing: a warning naming the
 * ring inside it, and every height right; with missing = 0 the same points
 * are a contradiction.  Without the spot, the heights inside are one
 * interval low and the index widths catch it. */
static void test_missing_line(void)
{
    truth t;
    td_lines *ls;
    td_label_params p = tree_defaults();
    td_label_report rep;
    td_label_point q[2];
    td_ctx cx;
    long chain[64], gone, inner_id;
    size_t n, i;
    char name[32];
    td_ctx_init(&cx);
    TT_CHECK(make_truth(&t, TD_GEN_CONE, 400, 300) == 0);
    n = cone_chain(&t, chain, 64);
    TT_CHECK(n >= 5);
    gone = chain[2];
    q[0] = on_line(&t.lines->v[chain[0]], t.lines->v[chain[0]].height);
    q[1].x = 200, q[1].y = 150, q[1].id = -1;
    q[1].height = dem_at(t.dem, q[1].x, q[1].y);
    ls = unlabelled(t.lines);
    inner_id = ls->v[chain[3]].id;
    td_lines_remove(ls, (size_t)gone);
    td_lines_remove(t.lines, (size_t)gone);
    p.interval = t.interval, p.w = 400, p.h = 300, p.known = q, p.nknown = 2;
    TT_CHECKF(td_label_auto(ls, &p, &rep, &cx) == 0, "%s", cx.msg);
    TT_CHECK(count_wrong(ls, t.lines, 1) == 0);
    snprintf(name, sizeof name, "between line %ld ", inner_id);
    TT_CHECKF(rep.warnings == 1 && strstr(rep.text, "missing") &&
              strstr(rep.text, name), "%s", rep.text ? rep.text : "");
    td_label_report_free(&rep);
    p.missing = 0;
    TT_CHECK(td_label_auto(ls, &p, &rep, &cx) == TD_EINVAL &&
             strstr(cx.msg, "contradict"));
    p.missing = 1, p.nknown = 1; /* no spot: wrong inside, no warning... */
    TT_CHECK(td_label_auto(ls, &p, &rep, &cx) == 0 && rep.warnings == 0);
    TT_CHECK(count_wrong(ls, t.lines, 0) > 0);
    td_label_report_free(&rep);
    for (i = 0; i < ls->n; i++) /* ...but index lines drawn 2x as wide */
        ls->v[i].width = fmod(t.lines->v[i].height, 5 * t.interval) ? 2 : 4;
    p.index_every = 5;
    TT_CHECK(td_label_check_index(ls, &p, &rep, &cx) == 0);
    TT_CHECKF(rep.index_mismatches > 0 && strstr(rep.text, "look -"), "%s",
              rep.text ? rep.text : "");
    td_label_report_free(&rep);
    td_lines_free(ls);
    free_truth(&t);
}

/* A spot height exactly on a multiple, outside a ring one interval above
 * it (90 outside a 100 ring): the face between may be at either level; with
 * a point on the ring, or alone, every height is right. */
static void test_spot_on_multiple(void)
{
    truth t;
    td_lines *ls;
    td_label_params p = tree_defaults();
    td_label_report rep;
    td_label_point q[2];
    td_ctx cx;
    long chain[64], r;
    double vx, vy, d, gap;
    td_ctx_init(&cx);
    TT_CHECK(make_truth(&t, TD_GEN_CONE, 400, 300) == 0);
    TT_CHECK(cone_chain(&t, chain, 64) >= 4);
    r = chain[2];
    q[0] = on_line(&t.lines->v[r], t.lines->v[r].height);
    vx = q[0].x - 200, vy = q[0].y - 150, d = hypot(vx, vy);
    gap = td_contain_dist(&t.lines->v[chain[1]], q[0].x, q[0].y);
    q[1].x = q[0].x + vx / d * 0.5 * gap, q[1].y = q[0].y + vy / d * 0.5 * gap;
    q[1].height = t.lines->v[r].height - t.interval, q[1].id = -1;
    ls = unlabelled(t.lines);
    p.interval = t.interval, p.w = 400, p.h = 300, p.known = q, p.nknown = 2;
    TT_CHECKF(td_label_auto(ls, &p, &rep, &cx) == 0, "%s", cx.msg);
    TT_CHECK(count_wrong(ls, t.lines, 1) == 0 && rep.warnings == 0);
    td_label_report_free(&rep);
    p.known = q + 1, p.nknown = 1;
    TT_CHECKF(td_label_auto(ls, &p, &rep, &cx) == 0, "%s", cx.msg);
    TT_CHECK(count_wrong(ls, t.lines, 1) == 0);
    TT_CHECK(rep.assumed == ls->n); /* one point fixes no direction */
    td_label_report_free(&rep);
    td_lines_free(ls);
    free_truth(&t);
}

/* Index contours drawn 4 px wide among 2 px lines, scanned: the widths
 * separate them, a right labelling has no mismatch, a labelling one
 * interval high has one per checked index line and the shift is named. */
static void test_index_widths(void)
{
    td_gen_params gp = td_gen_defaults();
    td_image *im = NULL;
    td_lines *truth_ls = NULL;
    td_grid_f32 *dem = NULL;
    td_scan_result res;
    td_scan_params sp = td_scan_defaults();
    td_label_params p = tree_defaults();
    td_label_report rep;
    td_label_point q[3];
    td_ctx cx;
    truth tr;
    double I;
    long a, b;
    size_t i, thick = 0, thin = 0;
    td_ctx_init(&cx);
    gp.w = 600, gp.h = 450, gp.index_width = 4;
    TT_CHECK(td_gen_sheet(&gp, &im, &truth_ls, &dem, &cx) == 0);
    I = td_gen_auto_interval(&gp, dem);
    TT_CHECKF(td_scan(im, &sp, &res, &cx) == 0, "%s", cx.msg);
    for (i = 0; i < res.lines->n; i++) {
        double w = res.lines->v[i].width;
        thick += w > 3.5 && w < 5;
        thin += w > 1.5 && w < 3;
    }
    TT_CHECKF(thick >= 3 && thin + thick == res.lines->n, "%zu thick %zu "
              "thin of %zu", thick, thin, res.lines->n);
    a = longest_open(truth_ls, NAN);
    b = longest_open(truth_ls, truth_ls->v[a].height);
    q[0] = on_line(&truth_ls->v[a], truth_ls->v[a].height);
    q[1] = on_line(&truth_ls->v[b], truth_ls->v[b].height);
    tr.dem = dem, tr.lines = truth_ls, tr.interval = I;
    TT_CHECK(find_pit(&tr, &q[2].x, &q[2].y) >= 0); /* the depression */
    q[2].height = dem_at(dem, q[2].x, q[2].y), q[2].id = -1;
    p.interval = I, p.w = 600, p.h = 450, p.known = q, p.nknown = 3;
    p.index_every = 5;
    TT_CHECKF(td_label_auto(res.lines, &p, &rep, &cx) == 0, "%s", cx.msg);
    TT_CHECK(td_label_check_index(res.lines, &p, &rep, &cx) == 0);
    TT_CHECKF(rep.index_mismatches == 0 && rep.warnings == 0, "%s",
              rep.text ? rep.text : "");
    td_label_report_free(&rep);
    q[0].height += I, q[1].height += I, q[2].height += I; /* one high */
    TT_CHECKF(td_label_auto(res.lines, &p, &rep, &cx) == 0, "%s", cx.msg);
    TT_CHECK(td_label_check_index(res.lines, &p, &rep, &cx) == 0);
    TT_CHECKF(rep.index_mismatches >= 2 * thick - 2 &&
              strstr(rep.text, "drawn thick") && strstr(rep.text, "look +"),
              "%zu: %s", rep.index_mismatches, rep.text ? rep.text : "");
    td_label_report_free(&rep);
    td_scan_result_free(&res);
    td_image_free(im);
    td_lines_free(truth_ls);
    td_grid_f32_free(dem);
}

/* The index spacing counted along transects (td_label_index_count):
 * 40 lines climbing a slope 8 px apart, every 5th 3.2 px wide and the
 * others 1.8: the
 * count of thin lines between two thick ones is 4 on every transect
 * across the slope; an unmeasured line breaks a count. */
static void test_index_counted(void)
{
    td_lines *ls = td_lines_new(NULL);
    long hist[21];
    int k, mode, x;
    for (k = 0; k < 40; k++) {
        td_line *l = td_lines_add(ls, NULL);
        for (x = 0; x <= 400; x += 4)
            td_line_push(l, x, 10 + 8 * k, NULL);
        l->width = k % 5 == 0 ? 3.2 : 1.8;
    }
    mode = td_label_index_count(ls, 2.4, 0, 340, hist, NULL);
    /* 25 columns (x = 8, 24, ..., 392) cross 7 pairs of thick lines */
    TT_CHECKF(mode == 4 && hist[4] == 175 && hist[0] == 175,
              "mode %d, %ld of %ld", mode, hist[4], hist[0]);
    { /* a short piece (unmeasured) between two thick lines breaks it */
        td_line *l = td_lines_add(ls, NULL);
        for (x = 0; x <= 400; x += 4)
            td_line_push(l, x, 14, NULL);
    }
    mode = td_label_index_count(ls, 2.4, 0, 340, hist, NULL);
    TT_CHECKF(mode == 4 && hist[0] == 150, "mode %d, %ld", mode, hist[0]);
    td_lines_free(ls);
}

int main(void)
{
    TT_RUN(test_index_counted);
    TT_RUN(test_cone_one_point);
    TT_RUN(test_true_points_agree);
    TT_RUN(test_index_decides);
    TT_RUN(test_hills_spot);
    TT_RUN(test_hills_mark);
    TT_RUN(test_hills_without_pit);
    TT_RUN(test_contradiction);
    TT_RUN(test_warnings);
    TT_RUN(test_crossings);
    TT_RUN(test_crossings_lattice);
    TT_RUN(test_missing_line);
    TT_RUN(test_spot_on_multiple);
    TT_RUN(test_index_widths);
    return tt_summary();
}
