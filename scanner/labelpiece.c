/* labelpiece.c: heights for the short pieces the scanner set aside (ours).
 *
 * The joiner's text filter takes short open pieces as label digits; on
 * faded and crowded sheets most of them are pieces of contour
 * (docs/scanner.md, "Pieces the text filter takes").  With
 * td_join_params.keep_pieces TD_PIECES_LATE they are set aside before the
 * joins and put back unjoined, marked td_line.piece.  The faces labeller
 * leaves them out of the solve (joined in, or solved as lines, they move
 * the faces and turned whole regions: measured there) and they take their
 * height here, from the lines at their ends:
 *
 *        line A ========   ~~~~ piece ~~~~   ======== line A'
 *                      end                end
 *
 *   at each end of the piece, the nearest end of a labelled line within
 *   GAP px that continues it: each end's tangent within ALIGN of the gap
 *   (as the joiner's small gaps) and off the other's tangent line by at
 *   most LAT px (a neighbouring contour's end in a crowded band lies a
 *   spacing to the side).  One such line, or two of one height: the
 *   piece takes the height, with that line's source and CONF_K of its
 *   confidence; two heights or none: no height (why says which).
 *   Measured on the printed Front Range 25 and scanned Elkhorn sheets
 *   (scan --pieces late, label, each piece against the true DEM): also
 *   taking the lines passing within 2.5 px of an end (a piece cut at a
 *   junction) put 1310 px of pieces one level off against 1342 right on
 *   the first and 91 against 617 on the second; this rule 273 against
 *   638, and 0 against 203 (docs/label.md, "The scanner's pieces"). */
#include "scanner/heights_int.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#define GAP 10.0   /* px: a line's end this near continues the piece */
#define ALIGN 0.7  /* cos: tangents within 45 deg of the gap */
#define LAT 1.5    /* px: each end at most this far off the other's tangent */
#define TAN_BACK 5 /* vertices back from an end for its tangent */
#define CELL 16    /* px: the grid of labelled lines' vertices */
#define CONF_K 0.9

static const char why_none[] =
    "a short piece (the scanner's): no labelled line at its ends";
static const char why_two[] =
    "a short piece (the scanner's): the lines at its ends disagree";

typedef struct pgrid {
    int gw, gh;
    size_t *start; /* gw * gh + 1 offsets into idx */
    uint64_t *idx; /* line index << 32 | vertex index */
} pgrid;

static void pgrid_free(pgrid *g)
{
    free(g->start);
    free(g->idx);
}

static void cell_of(const pgrid *g, double x, double y, int *cx_, int *cy_)
{
    int a = (int)floor(x / CELL), b = (int)floor(y / CELL);
    *cx_ = a < 0 ? 0 : a >= g->gw ? g->gw - 1 : a;
    *cy_ = b < 0 ? 0 : b >= g->gh ? g->gh - 1 : b;
}

/* A line whose height the evidence decided (known, a label, solved), not
 * a default: an assumed line can be off by many levels, and the pieces
 * would carry it on (measured: docs/label.md, "The scanner's pieces"). */
static int partner_ok(const td_line *l)
{
    return !l->piece && !l->closed && l->n >= 2 && l->has_height &&
           l->hsource != TD_HS_ASSUMED;
}

/* Counts (fill 0) or files (fill 1) the ends of the lines that may give
 * a piece its height by cell. */
static void bin_ends(pgrid *g, const td_lines *ls, int fill)
{
    size_t i;
    int e;
    for (i = 0; i < ls->n; i++)
        for (e = 0; e < 2 && partner_ok(&ls->v[i]); e++) {
            const td_line *l = &ls->v[i];
            size_t k = e ? l->n - 1 : 0, c;
            int a, b;
            cell_of(g, l->xy[2 * k], l->xy[2 * k + 1], &a, &b);
            c = (size_t)b * (size_t)g->gw + (size_t)a;
            if (fill)
                g->idx[g->start[c + 1]++] = (uint64_t)i << 32 | k;
            else
                g->start[c + 2]++;
        }
}

/* The grid of those ends over the lines' extent. */
static int pgrid_build(pgrid *g, const td_lines *ls, td_ctx *cx)
{
    double xmax = 1, ymax = 1;
    size_t i, k, nc;
    for (i = 0; i < ls->n; i++)
        for (k = 0; k < ls->v[i].n; k++) {
            xmax = fmax(xmax, ls->v[i].xy[2 * k]);
            ymax = fmax(ymax, ls->v[i].xy[2 * k + 1]);
        }
    g->gw = (int)(xmax / CELL) + 1, g->gh = (int)(ymax / CELL) + 1;
    nc = (size_t)g->gw * (size_t)g->gh;
    if (!(g->start = td_calloc(nc + 2, sizeof *g->start, cx)))
        return TD_ENOMEM;
    bin_ends(g, ls, 0);
    for (i = 2; i < nc + 2; i++)
        g->start[i] += g->start[i - 1];
    if (!(g->idx = td_malloc((g->start[nc + 1] + 1) * sizeof *g->idx, cx)))
        return TD_ENOMEM;
    bin_ends(g, ls, 1);
    return 0;
}

/* The unit tangent at end e (0 first, 1 last) of l, pointing out of it. */
static void end_tangent(const td_line *l, int e, double *tx, double *ty)
{
    size_t k = e ? l->n - 1 : 0;
    size_t j = e ? (l->n - 1 > TAN_BACK ? l->n - 1 - TAN_BACK : 0)
                 : (l->n - 1 > TAN_BACK ? TAN_BACK : l->n - 1);
    double dx = l->xy[2 * k] - l->xy[2 * j],
           dy = l->xy[2 * k + 1] - l->xy[2 * j + 1];
    double d = hypot(dx, dy);
    *tx = d > 0 ? dx / d : 0, *ty = d > 0 ? dy / d : 0;
}

/* The labelled line whose end continues piece p's end e (0 first, 1 last):
 * its index, or -1. */
static long partner(const pgrid *g, const td_lines *ls, const td_line *p, int e)
{
    size_t k = e ? p->n - 1 : 0;
    double x = p->xy[2 * k], y = p->xy[2 * k + 1], bd = GAP, ptx, pty;
    long best = -1;
    int a0, b0, a1, b1, a, b;
    end_tangent(p, e, &ptx, &pty);
    cell_of(g, x - GAP, y - GAP, &a0, &b0);
    cell_of(g, x + GAP, y + GAP, &a1, &b1);
    for (b = b0; b <= b1; b++)
        for (a = a0; a <= a1; a++) {
            size_t c = (size_t)b * (size_t)g->gw + (size_t)a, q;
            for (q = g->start[c]; q < g->start[c + 1]; q++) {
                size_t li = (size_t)(g->idx[q] >> 32),
                       vi = (size_t)(g->idx[q] & 0xffffffffu);
                const td_line *l = &ls->v[li];
                double dx = l->xy[2 * vi] - x, dy = l->xy[2 * vi + 1] - y;
                double d = hypot(dx, dy), ltx, lty;
                if (!(d < bd) || d <= 0) /* (open lines' ends only) */
                    continue;
                end_tangent(l, vi != 0, &ltx, &lty);
                if ((ptx * dx + pty * dy) / d >= ALIGN &&
                    -(ltx * dx + lty * dy) / d >= ALIGN &&
                    fabs(ptx * dy - pty * dx) <= LAT &&
                    fabs(ltx * dy - lty * dx) <= LAT)
                    bd = d, best = (long)li;
            }
        }
    return best;
}

/* See heights_int.h. */
int td_label_pieces(td_lines *ls, td_ctx *cx)
{
    pgrid g = {0, 0, NULL, NULL};
    size_t i, any = 0;
    for (i = 0; i < ls->n; i++)
        any += ls->v[i].piece && !ls->v[i].has_height;
    if (!any)
        return 0;
    if (pgrid_build(&g, ls, cx) != 0) {
        pgrid_free(&g);
        return td_seterr(cx, TD_ENOMEM, "label: out of memory");
    }
    for (i = 0; i < ls->n; i++) {
        td_line *p = &ls->v[i];
        long m[2] = {-1, -1};
        const td_line *q;
        if (!p->piece || p->has_height || p->n < 2)
            continue;
        if (!p->closed)
            m[0] = partner(&g, ls, p, 0), m[1] = partner(&g, ls, p, 1);
        if (m[0] < 0 && m[1] < 0) {
            p->why = why_none;
            continue;
        }
        if (m[0] >= 0 && m[1] >= 0 &&
            fabs(ls->v[m[0]].height - ls->v[m[1]].height) > 1e-9) {
            p->why = why_two;
            continue;
        }
        q = &ls->v[m[0] >= 0 ? m[0] : m[1]];
        p->has_height = 1;
        p->height = q->height;
        p->hsource = q->hsource;
        p->confidence = CONF_K * q->confidence;
        p->why = NULL;
    }
    pgrid_free(&g);
    return 0;
}
