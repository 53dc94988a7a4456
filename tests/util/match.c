/* match.c: truth-vs-traced line comparison (definitions in match.h). */
#include "tests/util/match.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define CELL 8.0
#define PAD 16.0
#define MAX_NEAR 16

/* Bucket grid of line segments: cell c holds ent[start[c] .. start[c+1]).
 * Long segments are cut into pieces of at most one cell, so each piece
 * lands in at most 2x2 cells.  An entry keeps its piece's end points as
 * floats relative to its cell's corner (precise to ~1e-6 px, and no
 * pointer chasing into the lines while querying). */
typedef struct segent {
    float x0, y0, x1, y1;
    uint32_t line;
} segent;

typedef struct segidx {
    const td_lines *ls;
    int gw, gh;
    uint64_t *start;
    segent *ent;
} segidx;

typedef struct pair {
    size_t other; /* line index on the other side */
    size_t count;
    double x, y; /* first place seen */
} pair;

typedef struct pairs {
    pair *v;
    size_t n, cap;
} pairs;

td_match_opts td_match_defaults(void)
{
    td_match_opts o;
    o.cover_tol = 2.0;
    o.assign_tol = 3.0;
    o.min_cov = 0.99;
    o.max_mean = 1.5;
    o.border_margin = 3.0;
    o.min_len = 0.0;
    return o;
}

static size_t nseg(const td_line *l)
{
    if (l->n < 2)
        return l->n; /* a single point is one zero-length segment */
    return l->closed ? l->n : l->n - 1;
}

static void seg_pts(const td_line *l, size_t s, const double **p,
                    const double **q)
{
    *p = l->xy + 2 * s;
    *q = l->xy + 2 * ((s + 1) % l->n);
}

static int cell_of(double v, int n)
{
    double c = floor((v + PAD) / CELL);
    return c < 0 ? 0 : (c >= n ? n - 1 : (int)c);
}

static void put_entry(segidx *ix, size_t c, size_t li, double x0, double y0,
                      double x1, double y1)
{
    double ox = (double)(c % (size_t)ix->gw) * CELL - PAD;
    double oy = (double)(c / (size_t)ix->gw) * CELL - PAD;
    segent *e = &ix->ent[ix->start[c]++];
    e->x0 = (float)(x0 - ox);
    e->y0 = (float)(y0 - oy);
    e->x1 = (float)(x1 - ox);
    e->y1 = (float)(y1 - oy);
    e->line = (uint32_t)li;
}

/* Visit (count or fill) the cells of segment s of line li. */
static void idx_visit(segidx *ix, size_t li, size_t s, int fill)
{
    const double *p, *q;
    double len;
    int k, n;
    seg_pts(&ix->ls->v[li], s, &p, &q);
    len = sqrt((q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]));
    n = (int)ceil(len / CELL);
    n = n < 1 ? 1 : n;
    for (k = 0; k < n; k++) {
        double a = (double)k / n, b = (double)(k + 1) / n;
        double x0 = p[0] + a * (q[0] - p[0]), x1 = p[0] + b * (q[0] - p[0]);
        double y0 = p[1] + a * (q[1] - p[1]), y1 = p[1] + b * (q[1] - p[1]);
        int cx0 = cell_of(fmin(x0, x1), ix->gw),
            cx1 = cell_of(fmax(x0, x1), ix->gw);
        int cy0 = cell_of(fmin(y0, y1), ix->gh),
            cy1 = cell_of(fmax(y0, y1), ix->gh);
        int cx, cy;
        for (cy = cy0; cy <= cy1; cy++)
            for (cx = cx0; cx <= cx1; cx++) {
                size_t c = (size_t)cy * (size_t)ix->gw + (size_t)cx;
                if (fill)
                    put_entry(ix, c, li, x0, y0, x1, y1);
                else
                    ix->start[c + 1]++;
            }
    }
}

static int idx_build(segidx *ix, const td_lines *ls, int w, int h)
{
    size_t li, s, c, nc;
    memset(ix, 0, sizeof *ix);
    ix->ls = ls;
    ix->gw = (int)ceil((w + 2 * PAD) / CELL) + 1;
    ix->gh = (int)ceil((h + 2 * PAD) / CELL) + 1;
    nc = (size_t)ix->gw * (size_t)ix->gh;
    if (!(ix->start = calloc(nc + 1, sizeof *ix->start)))
        return -1;
    for (li = 0; li < ls->n; li++)
        for (s = 0; s < nseg(&ls->v[li]); s++)
            idx_visit(ix, li, s, 0);
    for (c = 0; c < nc; c++)
        ix->start[c + 1] += ix->start[c];
    if (ls->n >= UINT32_MAX ||
        !(ix->ent = malloc((ix->start[nc] + 1) * sizeof *ix->ent)))
        return -1;
    for (li = 0; li < ls->n; li++)
        for (s = 0; s < nseg(&ls->v[li]); s++)
            idx_visit(ix, li, s, 1);
    /* fill advanced start[c] to the end of cell c: shift back */
    for (c = nc; c > 0; c--)
        ix->start[c] = ix->start[c - 1];
    ix->start[0] = 0;
    return 0;
}

static void idx_free(segidx *ix)
{
    free(ix->start);
    free(ix->ent);
}

/* Squared distance from (x,y) to an entry's piece (cell-relative). */
static float ent_dist2(const segent *e, float x, float y)
{
    float dx = e->x1 - e->x0, dy = e->y1 - e->y0, len2 = dx * dx + dy * dy;
    float t = 0.0f, ex, ey;
    if (len2 > 0.0f) {
        t = ((x - e->x0) * dx + (y - e->y0) * dy) / len2;
        t = t < 0.0f ? 0.0f : (t > 1.0f ? 1.0f : t);
    }
    ex = x - e->x0 - t * dx;
    ey = y - e->y0 - t * dy;
    return ex * ex + ey * ey;
}

/* Lines within rad of (x,y): their indices (distinct, at most MAX_NEAR) in
 * near[], their distances in dist[]; returns the count, ordered by first
 * sight.  *best gets the nearest line index (SIZE_MAX when none). */
static int idx_query(const segidx *ix, double x, double y, double rad,
                     size_t *near, double *dist, size_t *best)
{
    int cx0 = cell_of(x - rad, ix->gw), cx1 = cell_of(x + rad, ix->gw);
    int cy0 = cell_of(y - rad, ix->gh), cy1 = cell_of(y + rad, ix->gh);
    int cx, cy, n = 0, i;
    double bd = INFINITY;
    float r2 = (float)(rad * rad);
    *best = SIZE_MAX;
    for (cy = cy0; cy <= cy1; cy++)
        for (cx = cx0; cx <= cx1; cx++) {
            size_t c = (size_t)cy * (size_t)ix->gw + (size_t)cx, e;
            float fx = (float)(x - (cx * CELL - PAD));
            float fy = (float)(y - (cy * CELL - PAD));
            for (e = ix->start[c]; e < ix->start[c + 1]; e++) {
                size_t li = ix->ent[e].line;
                float d2 = ent_dist2(&ix->ent[e], fx, fy);
                double d;
                if (d2 > r2)
                    continue;
                d = sqrt((double)d2);
                if (d < bd)
                    bd = d, *best = li;
                for (i = 0; i < n && near[i] != li; i++)
                    ;
                if (i == n && n < MAX_NEAR)
                    near[n] = li, dist[n] = d, n++;
                else if (i < n && d < dist[i])
                    dist[i] = d;
            }
        }
    return n;
}

static int pairs_add(pairs *ps, size_t other, double x, double y)
{
    size_t i;
    for (i = 0; i < ps->n; i++)
        if (ps->v[i].other == other) {
            ps->v[i].count++;
            return 0;
        }
    if (ps->n == ps->cap) {
        size_t cap = ps->cap ? 2 * ps->cap : 16;
        pair *v = realloc(ps->v, cap * sizeof *v);
        if (!v)
            return -1;
        ps->v = v;
        ps->cap = cap;
    }
    ps->v[ps->n].other = other;
    ps->v[ps->n].count = 1;
    ps->v[ps->n].x = x;
    ps->v[ps->n].y = y;
    ps->n++;
    return 0;
}

/* Indices of the largest and second largest counts (SIZE_MAX if none). */
static void pairs_top2(const pairs *ps, size_t *a, size_t *b)
{
    size_t i;
    *a = *b = SIZE_MAX;
    for (i = 0; i < ps->n; i++) {
        if (*a == SIZE_MAX || ps->v[i].count > ps->v[*a].count) {
            *b = *a;
            *a = i;
        } else if (*b == SIZE_MAX || ps->v[i].count > ps->v[*b].count) {
            *b = i;
        }
    }
}

/* Per-truth-line tallies while sampling. */
typedef struct tstat {
    size_t nsamp, ncov;
    double sumd, maxd, maxx, maxy, ux, uy;
    int have_unc;
    pairs cover; /* traced line -> samples it covers */
} tstat;

static int sample_one(const segidx *tix, const td_match_opts *o, tstat *st,
                      double x, double y)
{
    size_t near[MAX_NEAR], best;
    double dist[MAX_NEAR];
    int n = idx_query(tix, x, y, o->cover_tol, near, dist, &best), i;
    double d = INFINITY;
    st->nsamp++;
    if (n == 0) {
        if (!st->have_unc)
            st->ux = x, st->uy = y, st->have_unc = 1;
        return 0;
    }
    for (i = 0; i < n; i++) {
        d = dist[i] < d ? dist[i] : d;
        if (pairs_add(&st->cover, near[i], x, y) != 0)
            return -1;
    }
    st->ncov++;
    st->sumd += d;
    if (d > st->maxd)
        st->maxd = d, st->maxx = x, st->maxy = y;
    return 0;
}

/* Sample truth line l every 0.5 px of arc length. */
static int sample_line(const segidx *tix, const td_match_opts *o,
                       const td_line *l, tstat *st)
{
    size_t s, ns = nseg(l);
    double next = 0.0, acc = 0.0;
    for (s = 0; s < ns; s++) {
        const double *p, *q;
        double len;
        seg_pts(l, s, &p, &q);
        len =
            sqrt((q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]));
        while (next < acc + len || (len == 0.0 && next == acc && ns == 1)) {
            double t = len > 0.0 ? (next - acc) / len : 0.0;
            if (sample_one(tix, o, st, p[0] + t * (q[0] - p[0]),
                           p[1] + t * (q[1] - p[1])) != 0)
                return -1;
            next += 0.5;
            if (len == 0.0)
                break;
        }
        acc += len;
    }
    if (!l->closed && l->n >= 2)
        return sample_one(tix, o, st, l->xy[2 * (l->n - 1)],
                          l->xy[2 * (l->n - 1) + 1]);
    return 0;
}

static int near_border(const td_line *l, int w, int h, double m)
{
    size_t i;
    if (!l->closed)
        return 0;
    for (i = 0; i < l->n; i++) {
        double x = l->xy[2 * i], y = l->xy[2 * i + 1];
        if (x < m || y < m || x > w - m || y > h - m)
            return 1;
    }
    return 0;
}

/* Verdicts for one truth line from its tallies. */
static void judge_truth(const td_line *t, const td_lines *traced,
                        const tstat *st, int nb, const td_match_opts *o,
                        td_match_report *r, FILE *log)
{
    double cov = st->nsamp ? (double)st->ncov / st->nsamp : 0.0;
    double mean = st->ncov ? st->sumd / st->ncov : INFINITY;
    size_t i, pieces = 0, a, b;
    const td_line *best;
    if (cov < r->worst_cov || r->worst_cov_id < 0)
        r->worst_cov = cov, r->worst_cov_id = t->id;
    if (st->ncov && (mean > r->worst_mean || r->worst_mean_id < 0))
        r->worst_mean = mean, r->worst_mean_id = t->id;
    if (cov >= o->min_cov && mean <= o->max_mean)
        r->n_matched++;
    else if (log && cov < o->min_cov)
        fprintf(log, "truth %ld: coverage %.3f (uncovered at %.1f,%.1f)\n",
                t->id, cov, st->ux, st->uy);
    else if (log)
        fprintf(log, "truth %ld: mean distance %.2f (%.2f at %.1f,%.1f)\n",
                t->id, mean, st->maxd, st->maxx, st->maxy);
    for (i = 0; i < st->cover.n; i++)
        pieces += st->cover.v[i].count >= 0.05 * st->nsamp;
    pairs_top2(&st->cover, &a, &b);
    if (pieces > 1) {
        r->n_split++;
        if (log)
            fprintf(log,
                    "truth %ld: split into %zu pieces (traced %ld and "
                    "%ld; the second at %.1f,%.1f)\n",
                    t->id, pieces, traced->v[st->cover.v[a].other].id,
                    traced->v[st->cover.v[b].other].id, st->cover.v[b].x,
                    st->cover.v[b].y);
    }
    if (a == SIZE_MAX || nb)
        return;
    best = &traced->v[st->cover.v[a].other];
    if (!best->closed != !t->closed) {
        r->n_closed_wrong++;
        if (log)
            fprintf(log,
                    "truth %ld: closed=%d but traced %ld closed=%d "
                    "(at %.1f,%.1f)\n",
                    t->id, t->closed, best->id, best->closed, st->cover.v[a].x,
                    st->cover.v[a].y);
    }
    if (!best->edge != !t->edge) {
        r->n_edge_wrong++;
        if (log)
            fprintf(log,
                    "truth %ld: edge=%d but traced %ld edge=%d "
                    "(at %.1f,%.1f)\n",
                    t->id, t->edge, best->id, best->edge, st->cover.v[a].x,
                    st->cover.v[a].y);
    }
}

static int check_truth(const td_lines *truth, const td_lines *traced, int w,
                       int h, const td_match_opts *o, td_match_report *r,
                       FILE *log)
{
    segidx tix;
    tstat st;
    size_t i, allsamp = 0, allcov = 0;
    int rc = -1;
    memset(&st, 0, sizeof st);
    if (idx_build(&tix, traced, w, h) != 0)
        goto fail;
    for (i = 0; i < truth->n; i++) {
        const td_line *t = &truth->v[i];
        int nb;
        if (t->n == 0 || td_line_length(t) < o->min_len) {
            r->n_short++;
            continue;
        }
        r->n_truth++;
        pairs keep = st.cover;
        memset(&st, 0, sizeof st);
        st.cover = keep;
        st.cover.n = 0;
        if (sample_line(&tix, o, t, &st) != 0)
            goto fail;
        allsamp += st.nsamp;
        allcov += st.ncov;
        nb = near_border(t, w, h, o->border_margin);
        r->n_near_border += nb;
        judge_truth(t, traced, &st, nb, o, r, log);
    }
    r->cov_total = allsamp ? (double)allcov / allsamp : 1.0;
    rc = 0;
fail:
    free(st.cover.v);
    idx_free(&tix);
    return rc;
}

/* Assign the vertices of traced line l to truth lines; judge it. */
static int judge_traced(const segidx *uix, const td_line *l,
                        const td_lines *truth, const td_match_opts *o,
                        pairs *ps, td_match_report *r, FILE *log)
{
    size_t i, none = 0, a, b, near[MAX_NEAR], best;
    double dist[MAX_NEAR];
    ps->n = 0;
    for (i = 0; i < l->n; i++) {
        double x = l->xy[2 * i], y = l->xy[2 * i + 1];
        idx_query(uix, x, y, o->assign_tol, near, dist, &best);
        if (best == SIZE_MAX)
            none++;
        else if (pairs_add(ps, best, x, y) != 0)
            return -1;
    }
    if (2 * none > l->n) {
        r->n_unmatched_traced++;
        if (log && l->n)
            fprintf(log,
                    "traced %ld: unmatched (%zu of %zu points far from "
                    "truth; at %.1f,%.1f)\n",
                    l->id, none, l->n, l->xy[0], l->xy[1]);
    }
    pairs_top2(ps, &a, &b);
    if (b != SIZE_MAX && ps->v[b].count >= 10 &&
        ps->v[b].count >= 0.05 * l->n) {
        r->n_mixed++;
        if (log)
            fprintf(log,
                    "traced %ld: mixed: truth %ld (%zu points) and "
                    "truth %ld (%zu points, from %.1f,%.1f)\n",
                    l->id, truth->v[ps->v[a].other].id, ps->v[a].count,
                    truth->v[ps->v[b].other].id, ps->v[b].count, ps->v[b].x,
                    ps->v[b].y);
    }
    return 0;
}

/* Contract in match.h. */
int td_match_lines(const td_lines *truth, const td_lines *traced, int w, int h,
                   td_match_opts *o, td_match_report *r, FILE *log)
{
    td_match_opts def = td_match_defaults();
    segidx uix;
    pairs ps = {NULL, 0, 0};
    size_t i;
    int rc = TD_ENOMEM;
    if (!o)
        o = &def;
    memset(r, 0, sizeof *r);
    r->worst_cov = 1.0;
    r->worst_cov_id = -1;
    r->worst_mean_id = -1;
    r->n_traced = (long)traced->n;
    memset(&uix, 0, sizeof uix);
    if (check_truth(truth, traced, w, h, o, r, log) != 0)
        goto fail;
    if (idx_build(&uix, truth, w, h) != 0)
        goto fail;
    for (i = 0; i < traced->n; i++)
        if (judge_traced(&uix, &traced->v[i], truth, o, &ps, r, log) != 0)
            goto fail;
    rc = 0;
fail:
    free(ps.v);
    idx_free(&uix);
    return rc;
}

/* Contract in match.h. */
int td_match_ok(const td_match_report *r)
{
    return r->n_matched == r->n_truth && r->n_mixed == 0 && r->n_split == 0 &&
           r->n_closed_wrong == 0 && r->n_edge_wrong == 0 &&
           r->n_unmatched_traced == 0;
}

/* Contract in match.h. */
void td_match_print(const td_match_report *r, FILE *f)
{
    fprintf(f,
            "match: truth %ld (short %ld, near border %ld), traced %ld, "
            "matched %ld, coverage %.4f, worst coverage %.3f (truth %ld), "
            "worst mean %.2f (truth %ld), mixed %ld, split %ld, closed wrong "
            "%ld, edge wrong %ld, noise %ld\n",
            r->n_truth, r->n_short, r->n_near_border, r->n_traced, r->n_matched,
            r->cov_total, r->worst_cov, r->worst_cov_id, r->worst_mean,
            r->worst_mean_id, r->n_mixed, r->n_split, r->n_closed_wrong,
            r->n_edge_wrong, r->n_unmatched_traced);
}

/* Contract in match.h. */
int td_match_heights(const td_lines *truth, const td_lines *traced, int w,
                     int h, double tol, td_hscore *r, FILE *log)
{
    return td_match_heights_v(truth, traced, w, h, tol, r, log, NULL);
}

/* Contract in match.h. */
int td_match_heights_v(const td_lines *truth, const td_lines *traced, int w,
                       int h, double tol, td_hscore *r, FILE *log,
                       int *verdict)
{
    segidx tix;
    size_t i, k, near[MAX_NEAR];
    double dist[MAX_NEAR];
    memset(r, 0, sizeof *r);
    if (idx_build(&tix, truth, w, h) != 0)
        return TD_ENOMEM;
    for (i = 0; i < traced->n; i++) {
        const td_line *l = &traced->v[i];
        double same = 0, other = 0, major_h = 0, major_len = 0, off = 0,
               on = 0;
        double tlen[16] = {0};
        size_t tid[16], nt = 0, j;
        for (k = 0; k < nseg(l); k++) {
            const double *p, *q;
            size_t best;
            double len, th;
            seg_pts(l, k, &p, &q);
            len = hypot(q[0] - p[0], q[1] - p[1]);
            idx_query(&tix, 0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1]), tol,
                      near, dist, &best);
            if (best == SIZE_MAX) {
                r->off += len;
                off += len;
                continue;
            }
            th = truth->v[best].height;
            for (j = 0; j < nt && tid[j] != best; j++)
                ;
            if (j == nt && nt < 16)
                tid[nt++] = best;
            if (j < 16)
                tlen[j] += len;
            on += len;
            if (!l->has_height)
                r->null_len += len;
            else if (fabs(l->height - th) < 1e-6 * (1 + fabs(th)))
                r->right += len, same += len;
            else
                r->wrong += len, other += len;
            if (l->has_height)
                r->err2 += len * (l->height - th) * (l->height - th);
            if (len > 0 && (major_len == 0 || th == major_h))
                major_h = th, major_len += len;
        }
        r->n_lines++;
        {
            double mx = 0;
            for (j = 0; j < nt; j++)
                mx = tlen[j] > mx ? tlen[j] : mx;
            r->own += mx;
        }
        if (verdict)
            verdict[i] = off > on ? 3 : !l->has_height ? 2
                         : same >= other    ? 0
                                            : 1;
        if (l->has_height && l->confidence >= 0.9)
            r->right_sure += same;
        if (l->has_height && l->confidence >= 0.9 && other > same) {
            r->n_wrong_sure++;
            r->wrong_sure_len += other;
            if (log)
                fprintf(log, "wrong sure: line %ld height %g conf %.2f, "
                        "truth mostly %g (%.0f px right, %.0f wrong)\n",
                        l->id, l->height, l->confidence, major_h, same,
                        other);
        }
    }
    idx_free(&tix);
    {
        double d = r->right + r->wrong + r->null_len;
        r->accuracy = d > 0 ? r->right / d : 0.0;
    }
    return 0;
}

/* Contract in match.h. */
double td_hscore_rmse(const td_hscore *r)
{
    double d = r->right + r->wrong;
    return d > 0 ? sqrt(r->err2 / d) : 0.0;
}

/* Walk line l in steps of 0.5 px of its length (the samples at 0.25,
 * 0.75, ... px along it, whatever its vertex spacing: a share of samples
 * is a share of length); a line shorter than that gets one sample, its
 * first point. */
typedef void (*sample_fn)(void *u, double x, double y);

static void walk(const td_line *l, sample_fn fn, void *u)
{
    size_t s, got = 0;
    double pos = 0.0, next = 0.25;
    for (s = 0; s < nseg(l); s++) {
        const double *p, *q;
        double len;
        seg_pts(l, s, &p, &q);
        len = hypot(q[0] - p[0], q[1] - p[1]);
        for (; next < pos + len; next += 0.5, got++) {
            double t = (next - pos) / len;
            fn(u, p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1]));
        }
        pos += len;
    }
    if (!got && l->n > 0)
        fn(u, l->xy[0], l->xy[1]);
}

typedef struct near_walk {
    const segidx *ix;
    double tol;
    size_t n, hit;
    /* per traced line: the nearest truth line of each sample */
    size_t *who, nwho, capwho;
    double *wx, *wy;
    int fail;
} near_walk;

static void count_near(void *u, double x, double y)
{
    near_walk *nw = u;
    size_t near[MAX_NEAR], best;
    double dist[MAX_NEAR];
    idx_query(nw->ix, x, y, nw->tol, near, dist, &best);
    nw->n++;
    nw->hit += best != SIZE_MAX;
}

static void record_near(void *u, double x, double y)
{
    near_walk *nw = u;
    size_t near[MAX_NEAR], best;
    double dist[MAX_NEAR];
    idx_query(nw->ix, x, y, nw->tol, near, dist, &best);
    if (nw->nwho == nw->capwho) {
        size_t c = nw->capwho ? 2 * nw->capwho : 1024;
        size_t *w2 = realloc(nw->who, c * sizeof *w2);
        double *x2, *y2;
        if (!w2) {
            nw->fail = 1;
            return;
        }
        nw->who = w2;
        x2 = realloc(nw->wx, c * sizeof *x2);
        if (!x2) {
            nw->fail = 1;
            return;
        }
        nw->wx = x2;
        y2 = realloc(nw->wy, c * sizeof *y2);
        if (!y2) {
            nw->fail = 1;
            return;
        }
        nw->wy = y2;
        nw->capwho = c;
    }
    nw->wx[nw->nwho] = x;
    nw->wy[nw->nwho] = y;
    nw->who[nw->nwho++] = best;
}

/* The height most of a walked line's samples lie near (the last walk's
 * record_near), *nmaj of its *near samples with a truth line near; NAN
 * with none. */
static double majority(const near_walk *nw, const td_lines *truth, size_t *nmaj,
                       size_t *near)
{
    size_t k, cnt[64], nc = 0, c;
    double cnt_h[64], major = NAN;
    *nmaj = *near = 0;
    for (k = 0; k < nw->nwho; k++) {
        double th;
        if (nw->who[k] == SIZE_MAX)
            continue;
        th = truth->v[nw->who[k]].height;
        (*near)++;
        for (c = 0; c < nc && cnt_h[c] != th; c++)
            ;
        if (c == nc && nc < 64)
            cnt_h[nc] = th, cnt[nc++] = 0;
        if (c < nc)
            cnt[c]++;
    }
    for (c = 0; c < nc; c++)
        if (cnt[c] > *nmaj)
            *nmaj = cnt[c], major = cnt_h[c];
    return major;
}

/* Contract in match.h. */
int td_match_majority(const td_lines *truth, const td_lines *traced, int w,
                      int h, double tol, double *out)
{
    segidx tix;
    near_walk nw;
    size_t i, nmaj, near;
    memset(&nw, 0, sizeof nw);
    if (idx_build(&tix, truth, w, h) != 0) {
        idx_free(&tix);
        return TD_ENOMEM;
    }
    nw.tol = tol;
    nw.ix = &tix;
    for (i = 0; i < traced->n && !nw.fail; i++) {
        nw.nwho = 0;
        walk(&traced->v[i], record_near, &nw);
        out[i] = majority(&nw, truth, &nmaj, &near);
    }
    free(nw.who);
    free(nw.wx);
    free(nw.wy);
    idx_free(&tix);
    return nw.fail ? TD_ENOMEM : 0;
}

/* Contract in match.h. */
int td_match_scan(const td_lines *truth, const td_lines *traced, int w, int h,
                  double tol, double jump_len, td_scanscore *r, FILE *log)
{
    segidx tix, rix;
    near_walk nw;
    size_t i, tot_near = 0, tot_own = 0;
    memset(r, 0, sizeof *r);
    memset(&nw, 0, sizeof nw);
    memset(&tix, 0, sizeof tix);
    memset(&rix, 0, sizeof rix);
    if (idx_build(&tix, truth, w, h) != 0 || idx_build(&rix, traced, w, h)) {
        idx_free(&tix);
        idx_free(&rix);
        return TD_ENOMEM;
    }
    nw.tol = tol;
    nw.ix = &rix;
    for (i = 0; i < truth->n; i++)
        walk(&truth->v[i], count_near, &nw);
    r->recall = nw.n ? (double)nw.hit / (double)nw.n : 0.0;
    nw.n = nw.hit = 0;
    nw.ix = &tix;
    for (i = 0; i < traced->n; i++)
        walk(&traced->v[i], count_near, &nw);
    r->precision = nw.n ? (double)nw.hit / (double)nw.n : 0.0;
    r->n_traced = (long)traced->n;
    r->n_truth = (long)truth->n;
    for (i = 0; i < traced->n && !nw.fail; i++) {
        size_t k, nmaj, run = 0, near;
        double major, rh = 0, rx = 0, ry = 0;
        int jumped = 0;
        nw.nwho = 0;
        walk(&traced->v[i], record_near, &nw);
        major = majority(&nw, truth, &nmaj, &near);
        tot_near += near;
        tot_own += nmaj;
        /* contiguous runs at another height (samples with no truth line
           near do not break a run) */
        for (k = 0; k < nw.nwho && !jumped; k++) {
            double th;
            if (nw.who[k] == SIZE_MAX)
                continue;
            th = truth->v[nw.who[k]].height;
            if (th == major) {
                run = 0;
                continue;
            }
            if (run == 0 || th != rh)
                rh = th, rx = nw.wx[k], ry = nw.wy[k], run = 0;
            if (++run * 0.5 > jump_len) {
                jumped = 1;
                if (log)
                    fprintf(log,
                            "jump: traced line %ld (%.0f,%.0f) runs from "
                            "contour %g onto %g\n",
                            traced->v[i].id, rx, ry, major, rh);
            }
        }
        r->n_jump += jumped;
    }
    r->own = tot_near ? (double)tot_own / (double)tot_near : 0.0;
    free(nw.who);
    free(nw.wx);
    free(nw.wy);
    idx_free(&tix);
    idx_free(&rix);
    return nw.fail ? TD_ENOMEM : 0;
}
