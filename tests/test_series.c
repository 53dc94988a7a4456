/* test_series.c: the heights of a map series in one solve
 * (src/pipeline/series.c).  The true contours of the Front Range DEM
 * (tests/data/dems, 10x) are cut at a sheet edge into two sheets, each
 * piece ending on its sheet's border pixel centres as a traced line does;
 * only the left sheet has evidence (three lines read from labels).  Alone
 * the right sheet cannot be labelled at all; in the joint solve every cut
 * contour gets one height on both sides and the right sheet's lines their
 * true heights. */
#define _POSIX_C_SOURCE 200809L
#include "tests/tt.h"

#include "src/io/io.h"
#include "src/pipeline/pipeline.h"
#include "samples/gen/gen.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Cut l at x = cut into pieces (left: x < cut, in place; right: shifted
 * by -cut), each ending half a pixel from the edge; pieces of one line
 * get truth height h and source id src in th / tid. */
typedef struct side {
    td_lines *ls;
    double *th;  /* true height of each piece */
    long *tid;   /* the true line it comes from */
} side;

static void put(side *s, td_line *cur, double h, long id)
{
    td_line *c;
    if (cur->n >= 2) {
        td_lines_append_copy(s->ls, cur, NULL);
        c = &s->ls->v[s->ls->n - 1];
        c->id = (long)s->ls->n - 1;
        c->closed = 0, c->has_height = 0, c->hsource = TD_HS_NONE;
        c->edge = 1;
        s->th = realloc(s->th, s->ls->n * sizeof *s->th);
        s->tid = realloc(s->tid, s->ls->n * sizeof *s->tid);
        s->th[s->ls->n - 1] = h, s->tid[s->ls->n - 1] = id;
    }
    free(cur->xy);
    memset(cur, 0, sizeof *cur);
}

/* The point where segment q -> p crosses x = cut. */
static double cross_y(const double *q, const double *p, double cut)
{
    return q[1] + (cut - q[0]) / (p[0] - q[0]) * (p[1] - q[1]);
}

static void cut_line(const td_line *l, double cut, side *L, side *R)
{
    size_t n = l->n, k, k0 = 0, m;
    td_line cur;
    int where;
    memset(&cur, 0, sizeof cur);
    if (l->closed) { /* start where the ring crosses, or keep it whole */
        for (k0 = 0; k0 < n; k0++)
            if ((l->xy[2 * ((k0 + n - 1) % n)] >= cut) != (l->xy[2 * k0] >= cut))
                break;
        if (k0 == n) {
            side *s = l->xy[0] >= cut ? R : L;
            td_lines_append_copy(s->ls, l, NULL);
            td_line *c = &s->ls->v[s->ls->n - 1];
            for (k = 0; s == R && k < c->n; k++)
                c->xy[2 * k] -= cut;
            c->id = (long)s->ls->n - 1, c->has_height = 0;
            c->hsource = TD_HS_NONE, c->edge = 0;
            s->th = realloc(s->th, s->ls->n * sizeof *s->th);
            s->tid = realloc(s->tid, s->ls->n * sizeof *s->tid);
            s->th[s->ls->n - 1] = l->height, s->tid[s->ls->n - 1] = l->id;
            return;
        }
        /* the first piece begins at the crossing before vertex k0 */
        {
            const double *q = &l->xy[2 * ((k0 + n - 1) % n)], *p = &l->xy[2 * k0];
            td_line_push(&cur, p[0] >= cut ? 0.5 : cut - 0.5, cross_y(q, p, cut),
                         NULL);
        }
    }
    where = l->xy[2 * k0] >= cut;
    for (m = 0; m < n; m++) {
        const double *p = &l->xy[2 * ((k0 + m) % n)];
        int w = p[0] >= cut;
        if (m > 0 && w != where) { /* the segment crosses the edge */
            const double *q = &l->xy[2 * ((k0 + m - 1) % n)];
            double y = cross_y(q, p, cut);
            td_line_push(&cur, where ? 0.5 : cut - 0.5, y, NULL);
            put(where ? R : L, &cur, l->height, l->id);
            td_line_push(&cur, w ? 0.5 : cut - 0.5, y, NULL);
        }
        where = w;
        td_line_push(&cur, w ? p[0] - cut : p[0], p[1], NULL);
    }
    if (l->closed) { /* the last piece ends at the crossing it began at */
        const double *q = &l->xy[2 * ((k0 + n - 1) % n)], *p = &l->xy[2 * k0];
        td_line_push(&cur, where ? 0.5 : cut - 0.5, cross_y(q, p, cut), NULL);
    }
    put(where ? R : L, &cur, l->height, l->id);
    free(cur.xy);
}

static void test_series_two_sheets(void)
{
    td_gen_params p = td_gen_defaults();
    td_grid_f32 *src = NULL, *dem = NULL;
    td_lines *truth = NULL;
    side S[2];
    td_series_sheet ss[2];
    td_label_params lp = td_label_defaults();
    td_label_report rep;
    td_ctx cx;
    double cut, interval, right_ok = 0, right_all = 0;
    size_t i, j, ev = 0, cutlines = 0, same = 0;
    td_ctx_init(&cx);
    memset(S, 0, sizeof S);
    memset(&rep, 0, sizeof rep);
    TT_CHECKF(td_dem_read("tests/data/dems/frontrange_srtm3.tif", &src, NULL,
                          &cx) == 0, "%s", td_errmsg(&cx));
    if (!src)
        return;
    p.terrain = TD_GEN_DEM;
    p.dem_in = src;
    p.w = src->w * 10 > 1600 ? 1600 : src->w * 10;
    p.h = src->h * 10 > 900 ? 900 : src->h * 10;
    TT_CHECK(td_gen_terrain(&p, &dem, &cx) == 0);
    if (!dem)
        goto done;
    interval = td_gen_auto_interval(&p, dem);
    TT_CHECK(td_gen_contours(dem, 0, interval, &truth, &cx) == 0);
    if (!truth)
        goto done;
    cut = floor(p.w * 0.55);
    for (j = 0; j < 2; j++)
        S[j].ls = td_lines_new(NULL);
    for (i = 0; i < truth->n; i++)
        cut_line(&truth->v[i], cut, &S[0], &S[1]);
    for (j = 0; j < 3; j++) { /* three long left lines read from labels */
        size_t best = SIZE_MAX;
        double bl = 0;
        for (i = 0; i < S[0].ls->n; i++)
            if (S[0].ls->v[i].hsource != TD_HS_LABEL &&
                td_line_length(&S[0].ls->v[i]) > bl)
                bl = td_line_length(&S[0].ls->v[i]), best = i;
        if (best == SIZE_MAX)
            break;
        S[0].ls->v[best].has_height = 1;
        S[0].ls->v[best].height = S[0].th[best];
        S[0].ls->v[best].hsource = TD_HS_LABEL;
        S[0].ls->v[best].confidence = 0.95;
        ev++;
    }
    TT_CHECK(ev == 3);
    for (j = 0; j < 2; j++) {
        ss[j].lines = S[j].ls;
        ss[j].w = j ? p.w - (int)cut : (int)cut;
        ss[j].h = p.h;
        ss[j].ox = j ? cut : 0, ss[j].oy = 0;
        ss[j].evidence = 1;
    }
    lp.interval = interval;
    TT_CHECKF(td_series_label(ss, 2, &lp, &rep, &cx) == 0, "%s",
              td_errmsg(&cx));
    for (i = 0; i < S[1].ls->n; i++) { /* the right sheet, no evidence */
        const td_line *l = &S[1].ls->v[i];
        double len = td_line_length(l);
        right_all += len;
        right_ok += l->has_height && fabs(l->height - S[1].th[i]) < 1e-6 ? len : 0;
        for (j = 0; j < S[0].ls->n; j++) /* its pieces on the left */
            if (S[0].tid[j] == S[1].tid[i]) {
                const td_line *m = &S[0].ls->v[j];
                cutlines++;
                same += l->has_height && m->has_height && l->height == m->height;
                break;
            }
    }
    fprintf(stderr, "  %zu + %zu pieces, %zu contours cut by the edge (%zu "
            "with one height on both sides), right sheet %.3f of its length "
            "right\n", S[0].ls->n, S[1].ls->n, cutlines, same,
            right_all > 0 ? right_ok / right_all : 0);
    TT_CHECK(cutlines >= 10);
    TT_CHECKF(same == cutlines, "%zu of %zu cut contours with one height",
              same, cutlines);
    TT_CHECKF(right_ok >= 0.98 * right_all, "right sheet: %.3f right",
              right_ok / right_all);
    {   /* one interpolation cut in two: across the cut as within a sheet */
        td_interp_params ip = td_interp_defaults();
        td_grid_f32 *d[2] = {NULL, NULL};
        double across = 0, inside = 0;
        int y, wl = ss[0].w;
        ip.interval = interval;
        TT_CHECKF(td_series_interp(ss, 2, &ip, d, &cx) == 0, "%s",
                  td_errmsg(&cx));
        for (y = 0; d[0] && d[1] && y < p.h; y++) {
            float a = TD_AT(d[0], wl - 2, y), b = TD_AT(d[0], wl - 1, y),
                  c = TD_AT(d[1], 0, y), e = TD_AT(d[1], 1, y);
            if (a == d[0]->nodata || b == d[0]->nodata ||
                c == d[1]->nodata || e == d[1]->nodata)
                continue;
            across += fabs(c - b);
            inside += 0.5 * (fabs(b - a) + fabs(e - c));
        }
        fprintf(stderr, "  mean |step| across the cut %.3f, beside it %.3f\n",
                across / p.h, inside / p.h);
        TT_CHECKF(across <= 1.5 * inside, "across %g, inside %g", across,
                  inside);
        td_grid_f32_free(d[0]), td_grid_f32_free(d[1]);
    }
done:
    for (j = 0; j < 2; j++)
        td_lines_free(S[j].ls), free(S[j].th), free(S[j].tid);
    td_label_report_free(&rep);
    td_lines_free(truth);
    td_grid_f32_free(dem);
    td_grid_f32_free(src);
}

int main(void)
{
    TT_RUN(test_series_two_sheets);
    return tt_summary();
}
