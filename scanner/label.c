/* Automatic contour heights (ALGORITHMS.md A.5 (b)): the model is in
 * label.h.  Faces and lines:
 *
 *      face 0 (root, holds the top-left corner)
 *        |  line a: d_a = level(face a+1) - level(face 0)
 *      face a+1 (inside a)
 *        |  line b (child of a)         height(b) = base + I *
 *      face b+1                             max(level(a+1), level(b+1))
 *
 * Levels are kept relative to the root (rel[]) plus one offset fixed by the
 * first known point; flipping a unit (one ring, or one slope strip of
 * border-closed lines) negates its lines' d. */
#include "scanner/label.h"

#include "scanner/heights_int.h"
#include "scanner/width.h"
#include "src/core/core.h"

#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { K_FACE, K_LINE };

typedef struct cons {
    int kind;
    long face, line;
    long k, k2, kpref; /* face: its level is in [k, k2], kpref when it fixes
                          the levels; line: its height is k (= k2) */
    size_t src;        /* index into p->known */
} cons;

typedef struct solver {
    const td_lines *ls;
    const td_label_params *p;
    td_contain ct;
    size_t n;
    int *d, *skip, *fixed; /* skip: a missing contour across the line */
    long *unit, *upar, *lock, *rel, *order, *mark;
    long off;
    cons *c;
    size_t nc;
    td_label_report *rep;
} solver;

td_label_params td_label_defaults(void)
{
    td_label_params p;
    memset(&p, 0, sizeof p);
    p.near = 3.0;
    p.far = 150.0;
    p.thick_ratio = 1.3;
    p.missing = 1;
    p.label_up = 1;
    p.gap_pairs = -1; /* by the scan: TD_GAP_PAIRS_COLOUR on colour */
    return p;
}

void td_label_report_free(td_label_report *rep)
{
    free(rep->undetermined_ids);
    free(rep->assumed_ids);
    free(rep->text);
    free(rep->oracle_ties);
    memset(rep, 0, sizeof *rep);
}

/* Contract in label.h. */
void td_label_warn(td_label_report *rep, const char *fmt, ...)
{
    char buf[400];
    va_list ap;
    size_t len, have = rep->text ? strlen(rep->text) : 0;
    char *t;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    len = strlen(buf);
    rep->warnings++;
    if (!(t = realloc(rep->text, have + len + 2)))
        return; /* the count is still right; the text is best effort */
    memcpy(t + have, buf, len);
    t[have + len] = '\n';
    t[have + len + 1] = '\0';
    rep->text = t;
}

/* Contract in label.h. */
void td_label_where(const td_line *l, double *x, double *y)
{
    *x = l->n ? l->xy[2 * (l->n / 2)] : 0;
    *y = l->n ? l->xy[2 * (l->n / 2) + 1] : 0;
}

static long face_out(const solver *s, size_t i)
{
    return s->ct.parent[i] >= 0 ? s->ct.parent[i] + 1 : 0;
}

/* ---- units: rings alone, slope strips of border-closed lines joined ---- */

static long find(solver *s, long i, int *par)
{
    int q = 1;
    while (s->unit[i] != i) {
        q *= (int)s->upar[i];
        i = s->unit[i];
    }
    *par = q;
    return i;
}

/* Lines a and b must have d_a = rel * d_b. */
static void unite(solver *s, long a, long b, int rel)
{
    int pa, pb;
    long ra = find(s, a, &pa), rb = find(s, b, &pb);
    if (ra == rb)
        return;
    s->unit[rb] = ra;
    s->upar[rb] = pa * pb * rel;
}

/* Faces bounded by exactly two border-closed lines: a slope strip. */
static void link_strips(solver *s, long *cnt, long *first, long *second)
{
    size_t i, f;
    for (f = 0; f <= s->n; f++)
        cnt[f] = 0;
    for (i = 0; i < s->n; i++) {
        long fs[2];
        int k;
        if (s->ct.parent[i] == -2 || s->ls->v[i].closed)
            continue;
        fs[0] = face_out(s, i), fs[1] = (long)i + 1;
        for (k = 0; k < 2; k++) {
            if (cnt[fs[k]] == 0)
                first[fs[k]] = (long)i;
            else if (cnt[fs[k]] == 1)
                second[fs[k]] = (long)i;
            cnt[fs[k]]++;
        }
    }
    for (f = 0; f <= s->n; f++) {
        long a = first[f], b = second[f];
        if (cnt[f] != 2)
            continue;
        /* both children of f: opposite d; parent edge and child: equal d */
        unite(s, a, b, ((long)f == a + 1 || (long)f == b + 1) ? 1 : -1);
    }
}

static void flip(solver *s, long u)
{
    size_t i;
    for (i = 0; i < s->n; i++)
        if (s->unit[i] == u)
            s->d[i] = -s->d[i];
}

/* ---- levels ---- */

static long depth_of(const solver *s, size_t i)
{
    long dep = 0, j = (long)i;
    while (s->ct.parent[j] >= 0) {
        j = s->ct.parent[j];
        dep++;
    }
    return dep;
}

static int cmp_depth(const void *a, const void *b)
{
    const long *x = a, *y = b;
    return (x[0] > y[0]) - (x[0] < y[0]);
}

/* Lines in parent-before-child order (dangling lines left out). */
static int make_order(solver *s, td_ctx *cx)
{
    long *tmp = td_calloc(2 * s->n + 2, sizeof *tmp, cx);
    size_t i, m = 0;
    if (!tmp)
        return TD_ENOMEM;
    for (i = 0; i < s->n; i++)
        if (s->ct.parent[i] != -2) {
            tmp[2 * m] = depth_of(s, i);
            tmp[2 * m++ + 1] = (long)i;
        }
    qsort(tmp, m, 2 * sizeof *tmp, cmp_depth);
    for (i = 0; i < s->n; i++)
        s->order[i] = i < m ? tmp[2 * i + 1] : -1;
    free(tmp);
    return 0;
}

/* The level change across line l (inside minus outside): d, or 2d where
 * a contour is missing next to it; its height is the inside level, + 1
 * when the inside is lower. */
static long step_of(const solver *s, long l)
{
    return s->d[l] + s->skip[l];
}

static long residual_raw(const solver *s, const cons *c)
{
    long lv;
    if (c->kind == K_LINE)
        return s->rel[c->line + 1] + s->off + (step_of(s, c->line) < 0) -
               c->k;
    lv = s->rel[c->face] + s->off;
    return lv < c->k ? lv - c->k : lv > c->k2 ? lv - c->k2 : 0;
}

static void relevel(solver *s)
{
    size_t i;
    s->rel[0] = 0;
    for (i = 0; i < s->n && s->order[i] >= 0; i++) {
        long l = s->order[i];
        s->rel[l + 1] = s->rel[face_out(s, (size_t)l)] + step_of(s, l);
    }
    s->off = 0;
    if (s->nc > 0 && s->c[0].kind == K_FACE)
        s->off = s->c[0].kpref - s->rel[s->c[0].face];
    else if (s->nc > 0)
        s->off = -residual_raw(s, &s->c[0]);
}

/* ---- meeting known points ---- */

/* Units of the lines on the tree path from face a to face b, nearest b
 * first, each once; returns how many were written to out. */
static size_t path_units(solver *s, long a, long b, long *out)
{
    size_t m = 0, i, na = 0;
    long f, lca;
    for (i = 0; i <= s->n; i++)
        s->mark[i] = 0;
    for (f = a; f > 0; f = face_out(s, (size_t)(f - 1)))
        s->mark[f] = 1;
    s->mark[0] = 1;
    for (f = b; !s->mark[f]; f = face_out(s, (size_t)(f - 1)))
        out[m++] = f - 1;
    lca = f;
    for (f = a; f != lca; f = face_out(s, (size_t)(f - 1)))
        na++;
    for (i = 0; i < na; i++) { /* a's side, from the LCA down to a */
        size_t k = na - 1 - i, j;
        for (f = a, j = 0; j < k; j++)
            f = face_out(s, (size_t)(f - 1));
        out[m++] = f - 1;
    }
    for (i = 0; i < m; i++) {
        int par;
        out[i] = find(s, out[i], &par);
    }
    return m;
}

static void describe(const solver *s, const cons *c, char *buf, size_t len)
{
    const td_label_point *q = &s->p->known[c->src];
    if (q->id >= 0)
        snprintf(buf, len, "height %g for line %ld", q->height, q->id);
    else if (c->kind == K_LINE)
        snprintf(buf, len, "(%g,%g)=%g on line %ld", q->x, q->y, q->height,
                 s->ls->v[c->line].id);
    else if (c->face > 0)
        snprintf(buf, len, "(%g,%g)=%g inside line %ld", q->x, q->y,
                 q->height, s->ls->v[c->face - 1].id);
    else
        snprintf(buf, len, "(%g,%g)=%g outside every line", q->x, q->y,
                 q->height);
}

/* ---- a missing contour: one interval off across a double gap ---- */

static int in_subtree(const solver *s, long m, long l)
{
    for (; m >= 0; m = s->ct.parent[m])
        if (m == l)
            return 1;
    return 0;
}

/* Mean distance from (up to 32 of) line l's vertices to the nearest line
 * outside l (not l, not inside it, not dangling); *near gets the line
 * nearest l's middle vertex.  A missing contour leaves a double gap. */
static double outward_gap(const solver *s, long l, long *near)
{
    const td_line *L = &s->ls->v[l];
    size_t k, m, step = L->n / 32 + 1, cnt = 0;
    double sum = 0;
    *near = -1;
    for (k = 0; k < L->n; k += step) {
        double x = L->xy[2 * k], y = L->xy[2 * k + 1], best = INFINITY;
        for (m = 0; m < s->n; m++) {
            double dd;
            if (s->ct.parent[m] == -2 || in_subtree(s, (long)m, l))
                continue;
            dd = td_contain_dist(&s->ls->v[m], x, y);
            if (dd < best) {
                best = dd;
                if (k == (L->n / 2) / step * step)
                    *near = (long)m;
            }
        }
        if (isfinite(best))
            sum += best, cnt++;
    }
    return cnt ? sum / (double)cnt : 0.0;
}

/* Lines whose step could hold point j: those on the tree path between the
 * first point's face and j's, and the lines the two points lie on. */
static size_t path_lines(solver *s, size_t j, long *out)
{
    long a = s->c[0].face, b = s->c[j].face, f;
    size_t m = 0, i;
    for (i = 0; i <= s->n; i++)
        s->mark[i] = 0;
    for (f = a; f > 0; f = face_out(s, (size_t)(f - 1)))
        s->mark[f] = 1;
    s->mark[0] = 1;
    for (f = b; !s->mark[f]; f = face_out(s, (size_t)(f - 1)))
        out[m++] = f - 1;
    for (i = 0; i <= s->n; i++)
        s->mark[i] = 0;
    for (f = b; f > 0; f = face_out(s, (size_t)(f - 1)))
        s->mark[f] = 1;
    for (f = a; f > 0 && !s->mark[f]; f = face_out(s, (size_t)(f - 1)))
        out[m++] = f - 1;
    if (s->c[j].kind == K_LINE)
        out[m++] = s->c[j].line;
    if (s->c[0].kind == K_LINE && (m == 0 || s->c[0].line != out[m - 1]))
        out[m++] = s->c[0].line;
    return m;
}

/* Median outward gap of the path lines other than `best` and best's
 * parent and children: what one interval's gap looks like here. */
static double usual_gap(solver *s, const long *ln, size_t m, long best,
                        double *g)
{
    size_t i, k = 0;
    long nb;
    for (i = 0; i < m; i++)
        if (ln[i] != best)
            g[k++] = outward_gap(s, ln[i], &nb);
    for (i = 0; i < s->n && k < 2 * s->n; i++)
        if ((long)i != best && (s->ct.parent[i] == best ||
                                s->ct.parent[best] == (long)i))
            g[k++] = outward_gap(s, (long)i, &nb);
    if (k == 0)
        return 0.0;
    qsort(g, k, sizeof *g, td_cmp_double);
    return g[k / 2];
}

/* Point j is one interval off the nesting after flipping: suspect a
 * contour missing across one path line (its step doubled, in the
 * direction of its d), among those that meet every point so far the one
 * with the widest gap outward, if at least 1.5 times the usual gap.
 * Warns and returns 1 when done, 0 when no line fits, or TD_ENOMEM. */
static int try_missing(solver *s, size_t j, td_ctx *cx)
{
    long *ln = td_calloc(2 * s->n + 4, sizeof *ln, cx), best = -1, near = -1;
    double *g = td_calloc(2 * s->n + 4, sizeof *g, cx), bgap = -1, usual;
    size_t m, i, q;
    int rc = TD_ENOMEM;
    if (!ln || !g)
        goto fail;
    m = path_lines(s, j, ln);
    for (i = 0; i < m; i++) {
        long l = ln[i], nb;
        int ok = 1;
        double gl;
        if (s->skip[l] != 0)
            continue;
        s->skip[l] = s->d[l];
        relevel(s);
        for (q = 0; q <= j && ok; q++)
            ok = residual_raw(s, &s->c[q]) == 0;
        s->skip[l] = 0;
        if (ok && (gl = outward_gap(s, l, &nb)) > bgap)
            bgap = gl, best = l, near = nb;
    }
    rc = 0;
    usual = best >= 0 ? usual_gap(s, ln, m, best, g) : 0.0;
    if (best >= 0 && bgap >= 1.5 * usual) {
        char b[160], t[80] = "";
        double x, y;
        s->skip[best] = s->d[best];
        describe(s, &s->c[j], b, sizeof b);
        if (near >= 0) {
            td_label_where(&s->ls->v[near], &x, &y);
            snprintf(t, sizeof t, " and line %ld (near %.0f,%.0f)",
                     s->ls->v[near].id, x, y);
        }
        td_label_where(&s->ls->v[best], &x, &y);
        td_label_warn(s->rep, "a contour seems missing between line %ld "
                      "(near %.0f,%.0f)%s: %s is one interval off the "
                      "nesting and the gap there is %.0f px against %.0f px "
                      "usual; heights follow the known points on both sides",
                      s->ls->v[best].id, x, y, t, b, bgap, usual);
        rc = 1;
    }
    relevel(s);
fail:
    free(ln);
    free(g);
    return rc;
}

/* Flip free units on the path from the first point to point j until j is
 * met (or, one interval off, a missing contour explains it); lock the
 * path's units for j. */
enum { TD_DP_CELLS = 1 << 22 }; /* bound on the table of meet_dp */

/* Choose which of the m candidate units to flip so that c's residual r
 * becomes 0: the fewest flips, the ones nearest the new point when there
 * is a choice (dynamic programming over the reachable changes; the
 * greedy one-at-a-time search misses pairs that only work together).
 * Returns 1 and flips them, 0 when no subset works, TD_ENOMEM. */
static int meet_dp(solver *s, const cons *c, const long *cand, size_t m,
                   long r, td_ctx *cx)
{
    long *delta = td_calloc(m + 1, sizeof *delta, cx), span = 0, need, v;
    uint16_t *suf = NULL;
    size_t i, w;
    int rc = TD_ENOMEM;
    if (!delta)
        return rc;
    for (i = 0; i < m; i++) { /* each flip's own effect (they add up) */
        if (s->lock[cand[i]])
            continue;
        flip(s, cand[i]);
        relevel(s);
        delta[i] = residual_raw(s, c) - r;
        flip(s, cand[i]);
        span += labs(delta[i]);
    }
    relevel(s);
    rc = 0;
    w = 2 * (size_t)span + 1;
    if (labs(r) > span || (m + 1) * w > TD_DP_CELLS ||
        !(suf = td_malloc((m + 1) * w * sizeof *suf, cx)))
        goto done;
    /* suf[i][v + span]: fewest flips among cand[i..m) changing r by v */
    for (v = -span; v <= span; v++)
        suf[m * w + (size_t)(v + span)] = v == 0 ? 0 : UINT16_MAX;
    for (i = m; i-- > 0;)
        for (v = -span; v <= span; v++) {
            uint16_t keep = suf[(i + 1) * w + (size_t)(v + span)], take;
            long u = v - delta[i];
            take = delta[i] != 0 && u >= -span && u <= span &&
                           suf[(i + 1) * w + (size_t)(u + span)] < UINT16_MAX
                       ? suf[(i + 1) * w + (size_t)(u + span)] + 1
                       : UINT16_MAX;
            suf[i * w + (size_t)(v + span)] = take <= keep ? take : keep;
        }
    need = -r;
    if (suf[need + span] == UINT16_MAX)
        goto done;
    for (i = 0; i < m; i++) {
        long u = need - delta[i];
        if (delta[i] != 0 && u >= -span && u <= span &&
            suf[(i + 1) * w + (size_t)(u + span)] < UINT16_MAX &&
            suf[(i + 1) * w + (size_t)(u + span)] + 1 ==
                suf[i * w + (size_t)(need + span)]) {
            flip(s, cand[i]);
            need = u;
        }
    }
    relevel(s);
    rc = 1;
done:
    free(suf);
    free(delta);
    return rc;
}

/* Flip free units among the new point's own line, the tree path from the
 * first point to point j and the first point's line until j is met; lock
 * those units for j. */
static int meet(solver *s, size_t j, long *cand, td_ctx *cx)
{
    cons *c = &s->c[j];
    size_t m = 0, i, k;
    long r, blocker = 0;
    int rc;
    if (c->kind == K_LINE) {
        int par;
        cand[m++] = find(s, c->line, &par);
    }
    m += path_units(s, s->c[0].face, c->face, cand + m);
    if (s->c[0].kind == K_LINE) { /* the first point's line: its d picks
                                     which side's level is its height */
        int par;
        cand[m++] = find(s, s->c[0].line, &par);
    }
    for (i = 0, k = 0; i < m; i++) { /* each unit once, nearest first */
        size_t q;
        for (q = 0; q < k && cand[q] != cand[i]; q++)
            ;
        if (q == k)
            cand[k++] = cand[i];
    }
    for (i = 0, m = k; i < m && !blocker; i++)
        blocker = s->lock[cand[i]];
    relevel(s);
    r = residual_raw(s, c);
    if (r != 0 && (rc = meet_dp(s, c, cand, m, r, cx)) < 0)
        return rc;
    r = residual_raw(s, c);
    if (labs(r) == 1 && s->p->missing) {
        int rm = try_missing(s, j, cx);
        if (rm < 0)
            return rm;
        r = rm ? 0 : r;
    }
    if (r != 0) {
        char a[160], b[160];
        describe(s, &s->c[blocker ? blocker - 1 : 0], a, sizeof a);
        describe(s, c, b, sizeof b);
        return td_seterr(cx, TD_EINVAL, "known points contradict: %s and %s "
                         "(off by %ld interval%s across the lines between "
                         "them)", a, b, labs(r), labs(r) == 1 ? "" : "s");
    }
    for (i = 0; i < m; i++)
        if (!s->lock[cand[i]])
            s->lock[cand[i]] = (long)j + 1;
    return 0;
}

/* ---- known points and depression marks -> constraints and defaults ---- */

static void depression(solver *s, double x, double y)
{
    long l = td_contain_locate(&s->ct, x, y);
    if (l < 0) {
        td_label_warn(s->rep, "depression mark (%g,%g) lies outside every "
                      "contour", x, y);
        return;
    }
    for (;;) {
        long par = s->ct.parent[l];
        size_t i, kids = 0;
        s->d[l] = -1;
        s->fixed[l] = 1;
        if (par < 0 || !s->ls->v[par].closed)
            return;
        for (i = 0; i < s->n; i++)
            kids += s->ct.parent[i] == par;
        if (kids != 1)
            return;
        l = par;
    }
}

static long nearest_line(const solver *s, double x, double y, double *dist)
{
    long best = -1;
    size_t i;
    *dist = INFINITY;
    for (i = 0; i < s->n; i++) {
        double d = td_contain_dist(&s->ls->v[i], x, y);
        if (d < *dist) {
            *dist = d;
            best = (long)i;
        }
    }
    return best;
}

static int has_child(const solver *s, long l)
{
    size_t i;
    for (i = 0; i < s->n; i++)
        if (s->ct.parent[i] == l)
            return 1;
    return 0;
}

/* Turn known point q into constraint *c; 1 when it only sets the height of
 * a dangling line (*line set), 0 for a constraint, or an error. */
static int to_cons(solver *s, size_t qi, cons *c, long *line, td_ctx *cx)
{
    const td_label_point *q = &s->p->known[qi];
    double t = (q->height - s->p->base) / s->p->interval, dist = 0;
    long l = -1;
    size_t i;
    c->src = qi;
    if (q->id >= 0) {
        for (i = 0; i < s->n && l < 0; i++)
            if (s->ls->v[i].id == q->id)
                l = (long)i;
        if (l < 0)
            return td_seterr(cx, TD_EINVAL, "no line has id %ld", q->id);
    } else {
        if (!(q->x >= 0 && q->y >= 0 && q->x <= s->p->w && q->y <= s->p->h))
            return td_seterr(cx, TD_EINVAL, "known point (%g,%g) is off the "
                             "%dx%d sheet", q->x, q->y, s->p->w, s->p->h);
        l = nearest_line(s, q->x, q->y, &dist);
    }
    if (l >= 0 && (q->id >= 0 || dist <= s->p->near)) {
        if (fabs(t - floor(t + 0.5)) > 1e-6) {
            double x = q->x, y = q->y;
            if (q->id >= 0)
                td_label_where(&s->ls->v[l], &x, &y);
            td_label_warn(s->rep, "known height %g on line %ld at (%g,%g) is "
                          "not base %g + a multiple of %g; rounded",
                          q->height, s->ls->v[l].id, x, y, s->p->base,
                          s->p->interval);
        }
        c->kind = K_LINE;
        c->line = l;
        c->k = c->k2 = c->kpref = (long)floor(t + 0.5);
        c->face = s->ct.parent[l] == -2 ? -1 : face_out(s, (size_t)l);
        *line = l;
        return c->face < 0;
    }
    if (dist > s->p->far)
        td_label_warn(s->rep, "known point (%g,%g)=%g is %.0f px from the "
                      "nearest line", q->x, q->y, q->height, dist);
    l = td_contain_locate(&s->ct, q->x, q->y);
    c->kind = K_FACE;
    c->face = l + 1;
    c->line = -1;
    c->k = c->k2 = c->kpref = (long)floor(t);
    if (fabs(t - floor(t + 0.5)) <= 1e-6) { /* on a multiple: either level */
        c->k2 = (long)floor(t + 0.5);
        c->k = c->k2 - 1;
        /* preferred: an innermost face is a summit (or pit) reaching it,
           a face with lines inside is their foot */
        c->kpref = has_child(s, l) || (l >= 0 && s->d[l] < 0) ? c->k2 : c->k;
    }
    return 0;
}

/* ---- driver ---- */

static int setup(solver *s, td_ctx *cx)
{
    size_t n = s->n, i;
    long *first = NULL, *second = NULL;
    s->d = td_calloc(n + 1, sizeof *s->d, cx);
    s->skip = td_calloc(n + 1, sizeof *s->skip, cx);
    s->fixed = td_calloc(n + 1, sizeof *s->fixed, cx);
    s->unit = td_calloc(n + 1, sizeof *s->unit, cx);
    s->upar = td_calloc(n + 1, sizeof *s->upar, cx);
    s->lock = td_calloc(n + 1, sizeof *s->lock, cx);
    s->rel = td_calloc(n + 2, sizeof *s->rel, cx);
    s->order = td_calloc(n + 1, sizeof *s->order, cx);
    s->mark = td_calloc(n + 2, sizeof *s->mark, cx);
    s->c = td_calloc(s->p->nknown + 1, sizeof *s->c, cx);
    first = td_calloc(n + 2, sizeof *first, cx);
    second = td_calloc(n + 2, sizeof *second, cx);
    if (!s->d || !s->skip || !s->fixed || !s->unit || !s->upar || !s->lock || !s->rel || !s->order ||
        !s->mark || !s->c || !first || !second || make_order(s, cx) != 0) {
        free(first);
        free(second);
        return TD_ENOMEM;
    }
    for (i = 0; i < n; i++) {
        s->unit[i] = (long)i;
        s->upar[i] = 1;
    }
    link_strips(s, s->mark, first, second);
    for (i = 0; i < n; i++) { /* each unit's root line has d = +1 */
        int par;
        long r = find(s, (long)i, &par);
        s->unit[i] = r;
        s->upar[i] = par;
        s->d[i] = par;
    }
    for (i = 0; i < s->p->ndepressions; i++)
        depression(s, s->p->depressions[2 * i], s->p->depressions[2 * i + 1]);
    free(first);
    free(second);
    return 0;
}

static int solve(solver *s, td_ctx *cx)
{
    long *cand = td_calloc(2 * s->n + 2, sizeof *cand, cx);
    cons *all = td_calloc(s->p->nknown + 1, sizeof *all, cx);
    char *use = td_calloc(s->p->nknown + 1, 1, cx);
    size_t i;
    int rc = TD_ENOMEM, pass;
    if (!cand || !all || !use)
        goto fail;
    for (i = 0, rc = 0; i < s->p->nknown && rc >= 0; i++) {
        long l = -1;
        rc = to_cons(s, i, &all[i], &l, cx);
        if (rc == 1) { /* a dangling line: its own height only */
            s->ls->v[l].has_height = 1;
            s->ls->v[l].height = s->p->base + all[i].k * s->p->interval;
        }
        use[i] = rc == 0;
    }
    /* exact points first, spots on a multiple (two possible levels) last,
       so that an exact one fixes the levels when there is one */
    for (pass = 0; pass < 2 && rc >= 0; pass++)
        for (i = 0, rc = 0; i < s->p->nknown && rc >= 0; i++)
            if (use[i] && (all[i].k != all[i].k2) == pass) {
                s->c[s->nc++] = all[i]; /* the first fixes the offset */
                if (s->nc > 1)
                    rc = meet(s, s->nc - 1, cand, cx);
            }
fail:
    free(cand);
    free(all);
    free(use);
    return rc < 0 ? rc : 0;
}

/* ---- index contours decide what the known points leave open ---- */

enum { MIN_INDEX_LEN = 30 }; /* px, as the index check */

/* Lines whose level is (not) an index level while drawn thin (thick):
 * thick[i] 1 thick, 0 thin, -1 not measured. */
static size_t index_misfits(solver *s, const signed char *thick)
{
    size_t i, bad = 0;
    relevel(s);
    for (i = 0; i < s->n; i++) {
        long k;
        if (thick[i] < 0)
            continue;
        k = s->rel[i + 1] + s->off + (step_of(s, (long)i) < 0);
        bad += (k % s->p->index_every == 0) != thick[i];
    }
    return bad;
}

/* With --index-every and lines of two widths, the direction of every unit
 * no known point or depression mark fixed is chosen to put the thick
 * lines on index heights: parents first, a unit flipped when that leaves
 * fewer misfits (twice over).  Decided units get lock -1 (not listed as
 * assumed).  Returns 0 or TD_ENOMEM. */
static int index_directions(solver *s, td_ctx *cx)
{
    signed char *thick;
    double cut = 0;
    size_t i, k, best, m;
    int rc, pass, inked;
    if (s->p->index_every <= 0 || s->nc == 0 ||
        (rc = td_label_thick_cut(s->ls, s->p, &cut, &inked, cx)) <= 0)
        return s->p->index_every <= 0 || s->nc == 0 ? 0 : rc;
    if (!(thick = td_calloc(s->n + 1, 1, cx)))
        return TD_ENOMEM;
    for (i = 0; i < s->n; i++) {
        double wt = td_line_weight(&s->ls->v[i], inked);
        thick[i] = s->ct.parent[i] != -2 && wt > 0 &&
                           td_line_length(&s->ls->v[i]) >= MIN_INDEX_LEN
                       ? wt >= cut
                       : -1;
    }
    best = index_misfits(s, thick);
    for (pass = 0; pass < 2 && best > 0; pass++)
        for (k = 0; k < s->n && s->order[k] >= 0; k++) {
            int par;
            long l = s->order[k], u = find(s, l, &par);
            if (s->lock[u] > 0 || s->fixed[l] || u != l)
                continue; /* each unit once, through its root line */
            flip(s, u);
            if ((m = index_misfits(s, thick)) < best) {
                best = m;
                s->lock[u] = -1;
            } else {
                flip(s, u);
                if (m > best) /* the widths back its direction */
                    s->lock[u] = -1;
            }
        }
    relevel(s);
    free(thick);
    return 0;
}

static void assign(solver *s)
{
    size_t i;
    relevel(s);
    for (i = 0; i < s->n; i++) {
        td_line *l = &s->ls->v[i];
        long in;
        if (s->ct.parent[i] == -2 || s->nc == 0)
            continue;
        in = s->rel[i + 1] + s->off + (step_of(s, (long)i) < 0);
        l->has_height = 1;
        l->height = s->p->base + s->p->interval * (double)in;
    }
}

/* Does a known point lie on line l? */
static int known_on(const solver *s, long l)
{
    size_t j;
    for (j = 0; j < s->nc; j++)
        if (s->c[j].kind == K_LINE && s->c[j].line == l)
            return 1;
    return 0;
}

/* Contract in label.h. */
/* Heights the solver counts in intervals from the base: a known point
 * more than TD_LABEL_MAX_LEVELS intervals away (--interval 1e-9 with a
 * height of 1e12) is refused, not turned into an overflowing level. */
static int check_levels(const td_label_params *p, td_ctx *cx)
{
    size_t i;
    if (!(p->interval > 0))
        return 0;
    for (i = 0; i < p->nknown; i++) {
        double k = (p->known[i].height - p->base) / p->interval;
        if (!isfinite(p->known[i].height) || !(fabs(k) <= TD_LABEL_MAX_LEVELS))
            return td_seterr(cx, TD_EINVAL,
                             "known height %g at %g,%g is %.3g intervals "
                             "from the base %g: check --interval",
                             p->known[i].height, p->known[i].x,
                             p->known[i].y, k, p->base);
    }
    return 0;
}

static int label_auto(td_lines *ls, const td_label_params *p,
                      td_label_report *rep, td_ctx *cx)
{
    solver s;
    size_t i;
    int rc;
    memset(rep, 0, sizeof *rep);
    memset(&s, 0, sizeof s);
    if ((rc = check_levels(p, cx)) != 0)
        return rc;
    if (p->method == TD_LABEL_FACES && p->interval == 0 && isfinite(p->base))
        return td_heights_infer(ls, p, rep, cx);
    if (!(p->interval > 0) || !isfinite(p->interval) || !isfinite(p->base))
        return td_seterr(cx, TD_EINVAL, "label: the interval must be > 0");
    if (p->method == TD_LABEL_FACES)
        return p->index_every <= 0 && !p->index_off
                   ? td_heights_solve_index(ls, p, rep, cx)
                   : td_heights_solve(ls, p, rep, cx);
    s.ls = ls, s.p = p, s.n = ls->n, s.rep = rep;
    if ((rc = td_contain_build(ls, p->w, p->h, &s.ct, cx)) != 0)
        return rc;
    for (i = 0; i < ls->n; i++) {
        long par = s.ct.parent[i];
        ls->v[i].parent = par >= 0 ? ls->v[par].id : -1;
        ls->v[i].has_height = 0;
    }
    if ((rc = setup(&s, cx)) != 0 || (rc = solve(&s, cx)) != 0 ||
        (rc = index_directions(&s, cx)) != 0)
        goto fail;
    assign(&s);
    rc = TD_ENOMEM;
    if (!(rep->undetermined_ids = td_calloc(ls->n + 1, sizeof(long), cx)) ||
        !(rep->assumed_ids = td_calloc(ls->n + 1, sizeof(long), cx)))
        goto fail;
    for (i = 0; i < ls->n; i++) {
        int par;
        if (ls->v[i].has_height)
            rep->labelled++;
        else
            rep->undetermined_ids[rep->undetermined++] = ls->v[i].id;
        if (ls->v[i].has_height && s.ct.parent[i] != -2 && !s.fixed[i] &&
            !s.lock[find(&s, (long)i, &par)] && !known_on(&s, (long)i))
            rep->assumed_ids[rep->assumed++] = ls->v[i].id;
    }
    rc = 0;
fail:
    if (rc)
        td_label_report_free(rep);
    td_contain_free(&s.ct);
    free(s.d), free(s.skip), free(s.fixed);
    free(s.unit), free(s.upar), free(s.lock);
    free(s.rel), free(s.order), free(s.mark), free(s.c);
    return rc;
}

/* Contract in label.h: the labeller refused, so no line keeps a height (a
 * refused trial solve, the interval's, had given them some). */
int td_label_auto(td_lines *ls, const td_label_params *p, td_label_report *rep,
                  td_ctx *cx)
{
    int rc = label_auto(ls, p, rep, cx);
    size_t i;
    for (i = 0; rc == TD_EINVAL && i < ls->n; i++)
        ls->v[i].has_height = 0;
    return rc;
}
