/* Tests of the face solve (scanner/faces.c, scanner/heights.c): hand-made
 * sheets with one right answer, and sheets drawn from real DEMs scored by
 * the share of traced line length with the right height. */
#include "tt.h"
#include "util/hsheet.h"

#include "../scanner/faces.h"
#include "../scanner/label.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void circle(td_lines *ls, double cx0, double cy0, double r, int ccw)
{
    td_line *l = td_lines_add(ls, NULL);
    int k, n = (int)(2 * 3.14159265 * r);
    for (k = 0; k < n; k++) {
        double a = 2 * 3.14159265 * k / n * (ccw ? -1 : 1);
        td_line_push(l, cx0 + r * cos(a), cy0 + r * sin(a), NULL);
    }
    l->closed = 1;
}

static td_label_params params(int w, int h, double interval)
{
    td_label_params p = td_label_defaults();
    p.w = w;
    p.h = h;
    p.interval = interval;
    return p;
}

/* Three nested rings, one known point on the outer: the inner two rise
 * (the summit prior), so they are "assumed", not "solved". */
static void test_rings_rise(void)
{
    td_lines *ls = td_lines_new(NULL);
    td_label_params p = params(300, 300, 10);
    td_label_report rep;
    td_label_point kp = {250, 150, 100, -1};
    td_ctx cx;
    td_ctx_init(&cx);
    circle(ls, 150, 150, 100, 0);
    circle(ls, 150, 150, 70, 1);
    circle(ls, 150, 150, 40, 0);
    p.known = &kp;
    p.nknown = 1;
    TT_CHECK(td_label_auto(ls, &p, &rep, &cx) == 0);
    TT_CHECK(ls->v[0].has_height && ls->v[0].height == 100);
    TT_CHECK(ls->v[0].hsource == TD_HS_KNOWN);
    TT_CHECKF(ls->v[1].has_height && ls->v[1].height == 110, "%g",
              ls->v[1].height);
    TT_CHECKF(ls->v[2].has_height && ls->v[2].height == 120, "%g",
              ls->v[2].height);
    TT_CHECK(ls->v[1].hsource == TD_HS_ASSUMED);
    TT_CHECK(ls->v[2].confidence < 0.9);
    td_label_report_free(&rep);
    td_lines_free(ls);
}

/* Many nested rings, the known point on the fifth from outside. */
static void test_many_rings(void)
{
    td_lines *ls = td_lines_new(NULL);
    td_label_params p = params(600, 600, 10);
    td_label_report rep;
    td_label_point kp = {300 + 250 - 5 * 12, 300, 100, -1};
    td_ctx cx;
    int k;
    td_ctx_init(&cx);
    for (k = 0; k < 20; k++)
        circle(ls, 300, 300, 250 - 12 * k, k & 1);
    p.known = &kp;
    p.nknown = 1;
    TT_CHECK(td_label_auto(ls, &p, &rep, &cx) == 0);
    for (k = 0; k < 20; k++)
        TT_CHECKF(ls->v[k].has_height && ls->v[k].height == 50 + 10 * k,
                  "ring %d: %d %g", k, ls->v[k].has_height, ls->v[k].height);
    td_label_report_free(&rep);
    td_lines_free(ls);
}

int main(void)
{
    TT_RUN(test_many_rings);
    TT_RUN(test_rings_rise);
    return tt_summary();
}
