/* series.c: the heights of a map series in one solve (ours; issue 18).
 *
 * Every sheet's traced lines are put in one frame; a contour cut by a
 * shared sheet edge ends on both sheets within a pixel or two of it, and
 * the two pieces are joined back into one line (a border cap on each side
 * is one line that is no cap at all); the faces labeller (heights.c) then
 * runs once over all of them.  Its evidence is what each sheet read: a
 * line its own run labelled from a printed label or a known point is a
 * read of that height with that confidence.  Each sheet's lines get the
 * heights of the joint solve back. */
#include "src/pipeline/pipeline.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define BORDER_PX 1.5 /* a line end this close to its sheet's edge */
#define JOIN_ALONG 8.0 /* two ends on sheet edges this close, of lines
                          going opposite ways out of them: one contour (a
                          contour crossing an edge at a slant is traced
                          along the border pixels on both sides) */
#define EVIDENCE_CONF 0.6

typedef struct sr {
    td_lines *S;     /* every line, series frame */
    size_t *sheet, *line; /* where each came from */
    size_t *owner;   /* the joined line (of T) each went into */
    double *mid;     /* a point on each line as it came (x, y) */
    const td_series_sheet *v;
    int same_height; /* join only pieces of one height */
} sr;


/* End e of line i lies on the edge of its sheet (series frame). */
static int on_edge(const sr *R, size_t i, const double *xy)
{
    const td_series_sheet *s = &R->v[R->sheet[i]];
    double x = xy[0] - s->ox, y = xy[1] - s->oy;
    return x < BORDER_PX || y < BORDER_PX || x > s->w - BORDER_PX ||
           y > s->h - BORDER_PX;
}

typedef struct lend {
    size_t i;       /* the line */
    int e;          /* its end: 0 first, 1 last */
    double x, y, dx, dy; /* where, and the way out of the line there */
} lend;

typedef struct lpair {
    double cost;
    size_t a, b;    /* indexes into the ends */
} lpair;

static int cmp_x(const void *pa, const void *pb)
{
    const lend *a = pa, *b = pb;
    if (a->x != b->x)
        return (a->x > b->x) - (a->x < b->x);
    if (a->i != b->i)
        return (a->i > b->i) - (a->i < b->i);
    return a->e - b->e;
}

static int cmp_pair(const void *pa, const void *pb)
{
    const lpair *a = pa, *b = pb;
    if (a->cost != b->cost)
        return (a->cost > b->cost) - (a->cost < b->cost);
    return (a->a > b->a) - (a->a < b->a); /* the same order every time */
}

/* The pieces of contours cut by the sheet edges: each end on an edge is
 * paired with an end of another sheet's line on an edge (within
 * JOIN_ALONG, the two lines leaving their ends in about opposite
 * directions: dot < -0.5), the cheapest pairs first (distance + 4 x (1 +
 * dot)); the chains of paired pieces become single lines of T (a chain
 * that comes back to itself, a ring cut by the edges, a closed one).
 * R->owner[i]: the line of T piece i went into.  0 or TD_ENOMEM. */
static int join_edges(sr *R, td_lines *T, td_ctx *cx)
{
    size_t N = R->S->n, ne = 0, np = 0, cap = 0, i, j;
    lend *E = td_malloc((2 * N + 1) * sizeof *E, cx);
    lpair *P = NULL;
    long *link = td_malloc((2 * N + 1) * sizeof *link, cx);
    unsigned char *seen = td_calloc(N + 1, 1, cx);
    int rc = TD_ENOMEM, e, pass;
    if (!E || !link || !seen)
        goto done;
    for (i = 0; i < 2 * N; i++)
        link[i] = -1;
    for (i = 0; i < N; i++) {
        const td_line *l = &R->S->v[i];
        if (l->closed || l->n < 2)
            continue;
        for (e = 0; e < 2; e++) {
            /* the way out from 5 vertices in, or from the middle of a
             * shorter piece (from its other end, a contour's tip poking
             * across the edge would point along the edge) */
            size_t in = l->n > 11 ? 5 : (l->n - 1) / 2;
            size_t k = e ? l->n - 1 : 0, q = e ? l->n - 1 - in : in;
            double dx = l->xy[2 * k] - l->xy[2 * q],
                   dy = l->xy[2 * k + 1] - l->xy[2 * q + 1], d = hypot(dx, dy);
            if (!on_edge(R, i, &l->xy[2 * k]))
                continue;
            E[ne++] = (lend){i, e, l->xy[2 * k], l->xy[2 * k + 1],
                             d > 0 ? dx / d : 0, d > 0 ? dy / d : 0};
        }
    }
    qsort(E, ne, sizeof *E, cmp_x); /* the pairs within JOIN_ALONG in x */
    for (i = 0; i < ne; i++)
        for (j = i + 1; j < ne && E[j].x - E[i].x <= JOIN_ALONG; j++) {
            double dx = E[j].x - E[i].x, dy = E[j].y - E[i].y;
            double d = hypot(dx, dy), dot = E[i].dx * E[j].dx + E[i].dy * E[j].dy;
            if (R->sheet[E[i].i] == R->sheet[E[j].i] || d > JOIN_ALONG ||
                dot > -0.5 ||
                (R->same_height &&
                 R->S->v[E[i].i].height != R->S->v[E[j].i].height))
                continue;
            if (np == cap) {
                lpair *nv = realloc(P, (cap ? 2 * cap : 64) * sizeof *P);
                if (!nv)
                    goto done;
                P = nv, cap = cap ? 2 * cap : 64;
            }
            P[np++] = (lpair){d + 4.0 * (1.0 + dot), i, j};
        }
    if (np)
        qsort(P, np, sizeof *P, cmp_pair);
    for (i = 0; i < np; i++) {
        size_t a = 2 * E[P[i].a].i + (size_t)E[P[i].a].e;
        size_t b = 2 * E[P[i].b].i + (size_t)E[P[i].b].e;
        if (link[a] < 0 && link[b] < 0 && E[P[i].a].i != E[P[i].b].i)
            link[a] = (long)b, link[b] = (long)a;
    }
    for (pass = 0; pass < 2; pass++) /* chains from a free end, then rings */
        for (i = 0; i < N; i++) {
            size_t cur = i, t0 = T->n, guard = 0;
            int from;
            td_line *t;
            if (seen[i])
                continue;
            if (pass == 0) { /* start only at a free end */
                if (link[2 * i] >= 0 && link[2 * i + 1] >= 0)
                    continue;
                from = link[2 * i] >= 0 ? 1 : 0;
            } else {
                from = 0;
            }
            if (!(t = td_lines_add(T, cx)))
                goto done;
            *t = R->S->v[i];
            t->xy = NULL, t->n = t->cap = 0;
            for (;;) {
                long nx;
                seen[cur] = 1;
                R->owner[cur] = t0;
                if (td_line_append(&T->v[t0], &R->S->v[cur], from, cx) != 0)
                    goto done;
                nx = link[2 * cur + (size_t)(1 - from)];
                if (nx < 0 || seen[nx / 2] || ++guard > N)
                    break;
                cur = (size_t)nx / 2, from = (int)(nx % 2);
            }
            if (pass == 1 || (link[2 * i] >= 0 && link[2 * i + 1] >= 0))
                T->v[t0].closed = R->S->v[i].closed ||
                                  (link[2 * i] >= 0 && T->v[t0].n > 3);
        }
    rc = 0;
done:
    free(E), free(P), free(link), free(seen);
    return rc;
}

static void sr_free(sr *R)
{
    td_lines_free(R->S);
    free(R->sheet), free(R->line), free(R->owner), free(R->mid);
    memset(R, 0, sizeof *R);
}

/* Every sheet's lines (with a height only, when `heights`) into R->S in
 * the series frame.  0 or TD_ENOMEM (R then freed). */
static int gather(sr *R, const td_series_sheet *v, size_t n, int heights,
                  td_ctx *cx)
{
    size_t s, i, k, N = 0;
    memset(R, 0, sizeof *R);
    R->v = v;
    R->same_height = heights;
    for (s = 0; s < n; s++)
        N += v[s].lines ? v[s].lines->n : 0;
    if (!(R->S = td_lines_new(cx)) ||
        !(R->sheet = td_malloc((N + 1) * sizeof *R->sheet, cx)) ||
        !(R->line = td_malloc((N + 1) * sizeof *R->line, cx)) ||
        !(R->owner = td_malloc((N + 1) * sizeof *R->owner, cx)) ||
        !(R->mid = td_malloc((2 * N + 1) * sizeof *R->mid, cx)))
        goto fail;
    for (s = 0; s < n; s++)
        for (i = 0; v[s].lines && i < v[s].lines->n; i++) {
            td_line *c;
            size_t j = R->S->n;
            if (heights && !v[s].lines->v[i].has_height)
                continue;
            if (td_lines_append_copy(R->S, &v[s].lines->v[i], cx) != 0)
                goto fail;
            c = &R->S->v[j];
            for (k = 0; k < c->n; k++)
                c->xy[2 * k] += v[s].ox, c->xy[2 * k + 1] += v[s].oy;
            k = c->n / 2;
            R->mid[2 * j] = c->n ? c->xy[2 * k] : 0;
            R->mid[2 * j + 1] = c->n ? c->xy[2 * k + 1] : 0;
            R->sheet[j] = s, R->line[j] = i, R->owner[j] = j;
        }
    return 0;
fail:
    sr_free(R);
    return TD_ENOMEM;
}

/* See pipeline.h. */
int td_series_label(td_series_sheet *v, size_t n, const td_label_params *p,
                    td_label_report *rep, td_ctx *cx)
{
    sr R;
    td_lines *T = NULL;
    td_ocr_read *rd = NULL;
    size_t i, s, N = 0, nr = 0;
    double W = 0, H = 0;
    td_label_params lp = *p;
    int rc = TD_ENOMEM;
    memset(&R, 0, sizeof R);
    for (s = 0; s < n; s++) {
        N += v[s].lines ? v[s].lines->n : 0;
        W = fmax(W, v[s].ox + v[s].w), H = fmax(H, v[s].oy + v[s].h);
    }
    if (!(T = td_lines_new(cx)) ||
        !(rd = td_calloc(N + 1, sizeof *rd, cx)) ||
        (rc = gather(&R, v, n, 0, cx)) != 0 ||
        (rc = join_edges(&R, T, cx)) != 0) {
        rc = rc ? rc : TD_ENOMEM;
        goto done;
    }
    for (i = 0; i < T->n; i++) { /* the joined lines, without heights */
        td_line *c = &T->v[i];
        c->id = (long)i;
        c->has_height = 0, c->hsource = TD_HS_NONE, c->confidence = 0;
        c->why = NULL, c->edge = 0;
    }
    for (i = 0; i < N; i++) { /* what each sheet read: the evidence */
        const td_line *l = &v[R.sheet[i]].lines->v[R.line[i]];
        td_ocr_read *r = &rd[nr];
        /* a solved neighbour's lines all count (at their confidence):
         * a contour crossing into this block keeps the height it has */
        if (!l->has_height ||
            (v[R.sheet[i]].evidence == 2 ? !(l->confidence > 0)
                                         : l->confidence < EVIDENCE_CONF ||
                                               !(l->hsource == TD_HS_LABEL ||
                                                 (l->hsource == TD_HS_KNOWN &&
                                                  v[R.sheet[i]].evidence))))
            continue;
        r->x = R.mid[2 * i], r->y = R.mid[2 * i + 1];
        r->value = l->height, r->conf = l->confidence;
        r->line[0] = (long)R.owner[i], r->line[1] = -1;
        snprintf(r->text, sizeof r->text, "%.10g", l->height);
        nr++;
    }
    lp.w = (int)ceil(W), lp.h = (int)ceil(H);
    lp.labels = rd, lp.nlabels = nr;
    lp.known = NULL, lp.nknown = 0;
    lp.depressions = NULL, lp.ndepressions = 0;
    if (nr == 0) {
        rc = td_seterr(cx, TD_EINVAL, "the series: no line of any sheet "
                       "was labelled from a label or a known point");
        goto done;
    }
    if ((rc = td_label_auto(T, &lp, rep, cx)) != 0)
        goto done;
    for (i = 0; i < N; i++) { /* the joint heights back onto each sheet */
        const td_line *t = &T->v[R.owner[i]];
        td_line *l = &v[R.sheet[i]].lines->v[R.line[i]];
        l->has_height = t->has_height, l->height = t->height;
        l->hsource = t->hsource, l->confidence = t->confidence;
        l->why = t->why;
    }
    rc = 0;
done:
    sr_free(&R);
    td_lines_free(T);
    free(rd);
    return rc;
}

/* See pipeline.h. */
int td_series_interp(const td_series_sheet *v, size_t n,
                     const td_interp_params *ip, td_grid_f32 **dems,
                     td_ctx *cx)
{
    td_lines *all = NULL;
    td_grid_f32 *big = NULL;
    sr R;
    double W = 0, H = 0;
    size_t s;
    int rc = TD_ENOMEM, y;
    memset(&R, 0, sizeof R);
    for (s = 0; s < n; s++) {
        dems[s] = NULL;
        if (v[s].ox != floor(v[s].ox) || v[s].oy != floor(v[s].oy))
            return td_seterr(cx, TD_EINVAL, "the sheets are not on one grid");
        W = fmax(W, v[s].ox + v[s].w), H = fmax(H, v[s].oy + v[s].h);
    }
    if (ip->step > 1)
        return td_seterr(cx, TD_EINVAL, "one DEM cell per pixel only");
    if ((rc = td_check_dims((int)W, (int)H, "the series", cx)) != 0)
        return rc;
    /* the pieces of a contour an edge cuts joined again (when their
     * heights agree): one line across the edge, not two ends a pixel or
     * more apart on either side of it */
    if (!(all = td_lines_new(cx)) || (rc = gather(&R, v, n, 1, cx)) != 0 ||
        (rc = join_edges(&R, all, cx)) != 0) {
        rc = rc ? rc : TD_ENOMEM;
        goto done;
    }
    if ((rc = td_interp_lines(all, (int)W, (int)H, ip, &big, cx)) != 0)
        goto done;
    for (s = 0; s < n; s++) {
        if (!(dems[s] = td_grid_f32_new(v[s].w, v[s].h, cx))) {
            rc = TD_ENOMEM;
            goto done;
        }
        for (y = 0; y < v[s].h; y++)
            memcpy(&dems[s]->data[(size_t)y * dems[s]->stride],
                   &big->data[((size_t)y + (size_t)v[s].oy) * big->stride +
                              (size_t)v[s].ox],
                   (size_t)v[s].w * sizeof *big->data);
        dems[s]->nodata = big->nodata, dems[s]->has_nodata = big->has_nodata;
    }
done:
    if (rc != 0)
        for (s = 0; s < n; s++)
            td_grid_f32_free(dems[s]), dems[s] = NULL;
    td_grid_f32_free(big);
    td_lines_free(all);
    sr_free(&R);
    return rc;
}
