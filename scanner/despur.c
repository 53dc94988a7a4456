/* Spur removal (paper 001 §2.2; ALGORITHMS.md A.3).
 *
 * The paper assumes contours are closed and never cross, so every end point
 * and every junction of the skeleton is noise.  In the 3x3 neighbourhood
 *
 *      . . .        . # .        end point: one run of neighbours
 *      . p #        # p #        (crossing number 1);
 *      . . .        . . .        junction: three or more runs (>= 3)
 *
 * it finds end points and junctions, pairs each end point with the nearest
 * junction and erases the line from the end point to that junction.
 * Pairing with a junction (rather than erasing from any end point) keeps
 * genuine breaks in a contour.  Its known weakness (the paper says so): a
 * break closer to a junction than the noise end point is erased with the
 * whole branch.  TD_SPUR_PAPER does exactly that: the branch is walked from
 * the end point along the skeleton and erased if the walk arrives at the
 * paired junction (within 2 px, junctions can be 2-3 pixels).
 *
 * TD_SPUR_LENGTH (the default) bounds the spur: a branch is erased only if
 * the walk reaches a junction within max_len px measured along the skeleton
 * (1 per orthogonal step, sqrt 2 per diagonal step); walks are computed on
 * the skeleton as it was at the start of a round, then erased together, and
 * rounds repeat for spurs of spurs.  A junction keeps at least two of its
 * branches (shortest spurs erased first), so a genuine break end that
 * happens to lie near a whisker survives. */
#include "scanner/despur.h"

#include "scanner/skel.h"
#include "scanner/thin.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define WALKED 0x80

td_despur_params td_despur_defaults(void)
{
    td_despur_params p;
    p.mode = TD_SPUR_LENGTH;
    p.max_len = 10.0;
    p.rounds = 3;
    return p;
}

int td_despur_parse_mode(const char *s, td_despur_params *p, td_ctx *cx)
{
    if (strcmp(s, "paper") == 0)
        p->mode = TD_SPUR_PAPER;
    else if (strcmp(s, "length") == 0)
        p->mode = TD_SPUR_LENGTH;
    else if (strcmp(s, "none") == 0)
        p->mode = TD_SPUR_NONE;
    else
        return td_seterr(cx, TD_EINVAL,
                         "--spur: '%s' is not paper, length or none", s);
    return 0;
}

static int is_junction(const td_grid_u8 *g, int x, int y)
{
    return td_skel_crossings(td_skel_nbits(g, x, y)) >= 3;
}

/* End points and junctions of rows [y0, y1), in raster order. */
static int classify_rows(const td_grid_u8 *g, int y0, int y1, td_szvec *ends,
                         td_szvec *juncs, td_ctx *cx)
{
    int x, y;
    for (y = y0; y < y1; y++) {
        const uint8_t *r = g->data + (size_t)y * g->stride;
        for (x = td_skel_next_ink(r, 0, g->w); x < g->w;
             x = td_skel_next_ink(r, x + 1, g->w)) {
            int c = td_skel_crossings(td_skel_nbits(g, x, y));
            if (c == 1 && td_szvec_push(ends, (size_t)y * g->stride + x, cx))
                return TD_ENOMEM;
            if (c >= 3 && td_szvec_push(juncs, (size_t)y * g->stride + x, cx))
                return TD_ENOMEM;
        }
    }
    return 0;
}

/* End points and junctions of the skeleton, in raster order: bands of
 * CLASSIFY_ROWS rows on threads, joined in order. */
#define CLASSIFY_ROWS 512
static int classify(const td_grid_u8 *g, td_szvec *ends, td_szvec *juncs,
                    td_ctx *cx)
{
    int nb = (g->h + CLASSIFY_ROWS - 1) / CLASSIFY_ROWS, b, rc = 0;
    td_szvec *be = td_calloc(2 * (size_t)nb + 1, sizeof *be, cx);
    size_t k;
    if (!be)
        return TD_ENOMEM;
#pragma omp parallel for schedule(dynamic)
    for (b = 0; b < nb; b++) {
        int y0 = b * CLASSIFY_ROWS,
            y1 = g->h - y0 < CLASSIFY_ROWS ? g->h : y0 + CLASSIFY_ROWS;
        if (classify_rows(g, y0, y1, &be[2 * b], &be[2 * b + 1], NULL) != 0) {
#pragma omp atomic write
            rc = TD_ENOMEM;
        }
    }
    for (b = 0; b < nb && rc == 0; b++)
        for (k = 0; k < be[2 * b].n + be[2 * b + 1].n && rc == 0; k++)
            rc = k < be[2 * b].n
                     ? td_szvec_push(ends, be[2 * b].v[k], cx)
                     : td_szvec_push(juncs, be[2 * b + 1].v[k - be[2 * b].n],
                                     cx);
    for (b = 0; b < 2 * nb; b++)
        td_szvec_free(&be[b]);
    free(be);
    return rc == 0 ? 0 : td_seterr(cx, TD_ENOMEM, "out of memory");
}

/* The next pixel of a walk: an unwalked ink neighbour, orthogonal ones
 * first so a 4-connected corner is not skipped; -1 when none. */
static int walk_next(const td_grid_u8 *g, int x, int y)
{
    int pass, k;
    for (pass = 0; pass < 2; pass++)
        for (k = pass; k < 8; k += 2) {
            int nx = x + TD_DX[k], ny = y + TD_DY[k];
            if (nx >= 0 && ny >= 0 && nx < g->w && ny < g->h &&
                TD_AT(g, nx, ny) == 1)
                return k;
        }
    return -1;
}

/* Walk from end point e along the skeleton until a junction (its index in
 * *junction, not part of the path), a dead end (*junction = SIZE_MAX) or
 * more than max_len px.  The path (e first) is left in `path`, flagged
 * WALKED; the caller clears the flags.  Returns the length walked. */
static double walk_branch(td_grid_u8 *g, size_t e, double max_len,
                          td_szvec *path, size_t *junction, td_ctx *cx)
{
    int x = (int)(e % g->stride), y = (int)(e / g->stride), k;
    double len = 0.0;
    *junction = SIZE_MAX;
    path->n = 0;
    for (;;) {
        size_t i = (size_t)y * g->stride + (size_t)x;
        if (path->n > 0 && is_junction(g, x, y)) {
            *junction = i;
            return len;
        }
        if (td_szvec_push(path, i, cx) != 0)
            return -1.0;
        g->data[i] |= WALKED;
        k = walk_next(g, x, y);
        if (k < 0)
            return len;
        len += (k & 1) ? M_SQRT2 : 1.0;
        if (len > max_len)
            return len;
        x += TD_DX[k];
        y += TD_DY[k];
    }
}

static void unflag(td_grid_u8 *g, const td_szvec *path)
{
    size_t i;
    for (i = 0; i < path->n; i++)
        g->data[path->v[i]] &= (uint8_t)~WALKED;
}

/* Nearest junction to pixel e by straight distance (brute force over a
 * bucket grid of 32 px cells, searched in growing square rings). */
typedef struct jindex {
    int cell, cw, ch;
    size_t *start, *items; /* CSR: bucket b holds items[start[b]..start[b+1]) */
} jindex;

static int jindex_build(jindex *ix, const td_grid_u8 *g, const td_szvec *j,
                        td_ctx *cx)
{
    size_t i, nb;
    ix->cell = 32;
    ix->cw = (g->w + 31) / 32;
    ix->ch = (g->h + 31) / 32;
    nb = (size_t)ix->cw * (size_t)ix->ch;
    ix->start = td_calloc(nb + 1, sizeof(size_t), cx);
    ix->items = td_calloc(j->n, sizeof(size_t), cx);
    if (!ix->start || !ix->items)
        return TD_ENOMEM;
    for (i = 0; i < j->n; i++) {
        size_t x = j->v[i] % g->stride, y = j->v[i] / g->stride;
        ix->start[(y / 32) * (size_t)ix->cw + x / 32 + 1]++;
    }
    for (i = 0; i < nb; i++)
        ix->start[i + 1] += ix->start[i];
    for (i = 0; i < j->n; i++) {
        size_t x = j->v[i] % g->stride, y = j->v[i] / g->stride;
        size_t b = (y / 32) * (size_t)ix->cw + x / 32;
        ix->items[ix->start[b]++] = j->v[i];
    }
    for (i = nb; i > 0; i--)
        ix->start[i] = ix->start[i - 1];
    ix->start[0] = 0;
    return 0;
}

static size_t jindex_nearest(const jindex *ix, const td_grid_u8 *g, size_t e)
{
    long ex = (long)(e % g->stride), ey = (long)(e / g->stride);
    long cx0 = ex / ix->cell, cy0 = ey / ix->cell, r, bx, by;
    double best = INFINITY;
    size_t besti = SIZE_MAX, k;
    for (r = 0; r < ix->cw + ix->ch; r++) {
        if (besti != SIZE_MAX && (double)(r - 1) * ix->cell > best)
            break;
        for (by = cy0 - r; by <= cy0 + r; by++)
            for (bx = cx0 - r; bx <= cx0 + r; bx++) {
                size_t b;
                if (bx < 0 || by < 0 || bx >= ix->cw || by >= ix->ch ||
                    (labs(bx - cx0) != r && labs(by - cy0) != r))
                    continue;
                b = (size_t)by * (size_t)ix->cw + (size_t)bx;
                for (k = ix->start[b]; k < ix->start[b + 1]; k++) {
                    long jx = (long)(ix->items[k] % g->stride);
                    long jy = (long)(ix->items[k] / g->stride);
                    double d = hypot((double)(jx - ex), (double)(jy - ey));
                    if (d < best) {
                        best = d;
                        besti = ix->items[k];
                    }
                }
            }
    }
    return besti;
}

static int same_junction(const td_grid_u8 *g, size_t a, size_t b)
{
    long ax = (long)(a % g->stride), ay = (long)(a / g->stride);
    long bx = (long)(b % g->stride), by = (long)(b / g->stride);
    return labs(ax - bx) <= 2 && labs(ay - by) <= 2;
}

/* A branch that qualifies as a spur: its junction, length and path (a
 * slice of the round's pooled path array). */
typedef struct spur {
    size_t junction, off, n;
    double len;
} spur;

static int cmp_spur(const void *pa, const void *pb)
{
    const spur *a = pa, *b = pb;
    if (a->junction != b->junction)
        return a->junction < b->junction ? -1 : 1;
    return (a->len > b->len) - (a->len < b->len);
}

/* Length rule: a junction with c branches keeps at least two of them, so a
 * break end near a whisker is not erased with it; the shortest spurs go
 * first.  The paper's rule erases every paired branch. */
static void choose(const td_grid_u8 *g, spur *s, size_t n, int paper)
{
    size_t i = 0, k;
    if (paper)
        return;
    qsort(s, n, sizeof *s, cmp_spur);
    while (i < n) {
        size_t j = s[i].junction, end = i;
        int x = (int)(j % g->stride), y = (int)(j / g->stride);
        long allowed = td_skel_crossings(td_skel_nbits(g, x, y)) - 2;
        while (end < n && s[end].junction == j)
            end++;
        for (k = i; k < end; k++)
            if ((long)(k - i) >= allowed)
                s[k].n = 0; /* kept */
        i = end;
    }
}

/* One round: decide every end point's branch on the unmodified skeleton,
 * then erase the chosen ones.  Returns the number of branches erased or a
 * negative error. */
static long despur_round(td_grid_u8 *g, const td_despur_params *p,
                         td_despur_stats *st, int first, td_ctx *cx)
{
    td_szvec ends = {0}, juncs = {0}, path = {0}, pool = {0}, touched = {0};
    spur *sp = NULL;
    jindex ix = {0};
    long spurs = 0;
    size_t i, k, nsp = 0;
    int rc = 0, paper = p->mode == TD_SPUR_PAPER;
    if ((rc = classify(g, &ends, &juncs, cx)) != 0)
        goto fail;
    if (first) {
        st->endpoints = ends.n;
        st->junctions = juncs.n;
    }
    if (juncs.n == 0)
        goto done;
    rc = TD_ENOMEM;
    if (!(sp = td_calloc(ends.n, sizeof *sp, cx)))
        goto fail;
    if (paper && jindex_build(&ix, g, &juncs, cx) != 0)
        goto fail;
    for (i = 0; i < ends.n; i++) {
        size_t j;
        double len = walk_branch(g, ends.v[i], paper ? INFINITY : p->max_len,
                                 &path, &j, cx);
        unflag(g, &path);
        if (len < 0)
            goto fail;
        if (j == SIZE_MAX || (paper ? !same_junction(g, j, jindex_nearest(&ix, g, ends.v[i]))
                                    : len > p->max_len))
            continue;
        sp[nsp].junction = j;
        sp[nsp].len = len;
        sp[nsp].off = pool.n;
        sp[nsp++].n = path.n;
        for (k = 0; k < path.n; k++)
            if (td_szvec_push(&pool, path.v[k], cx) != 0)
                goto fail;
    }
    choose(g, sp, nsp, paper);
    for (i = 0; i < nsp; i++) {
        if (sp[i].n == 0)
            continue;
        spurs++;
        st->pixels += sp[i].n;
        for (k = 0; k < sp[i].n; k++)
            g->data[pool.v[sp[i].off + k]] = 0;
        if (td_szvec_push(&touched, sp[i].junction, cx) != 0)
            goto fail;
    }
    st->spurs += (size_t)spurs;
    rc = td_thin_hilditch_near(g, touched.v, touched.n, cx);
    goto fail;
done:
    rc = 0;
fail:
    td_szvec_free(&ends);
    td_szvec_free(&juncs);
    td_szvec_free(&path);
    td_szvec_free(&pool);
    td_szvec_free(&touched);
    free(sp);
    free(ix.start);
    free(ix.items);
    return rc ? rc : spurs;
}

int td_despur(td_grid_u8 *skel, const td_despur_params *p,
              td_despur_stats *st, td_ctx *cx)
{
    td_despur_stats local;
    int round, rounds;
    if (!st)
        st = &local;
    memset(st, 0, sizeof *st);
    if (p->mode == TD_SPUR_NONE)
        return 0;
    rounds = p->mode == TD_SPUR_PAPER ? 1 : (p->rounds > 0 ? p->rounds : 1);
    for (round = 0; round < rounds; round++) {
        long n = despur_round(skel, p, st, round == 0, cx);
        if (n < 0)
            return (int)n;
        if (td_progress(cx, "despur", (round + 1.0) / rounds) != 0)
            return TD_ECANCEL;
        if (n == 0)
            break;
    }
    return 0;
}
