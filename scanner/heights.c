/* Heights by one global solve over the faces (ALGORITHMS.md A.5; ours, the
 * default labeller; the model is in label.h, the faces in faces.h).
 *
 * Unknowns: the band b(v) of every side node v (its ground lies between
 * base + b I and base + (b + 1) I).  Costs:
 *
 *   line l:        |b(2l) - b(2l+1)| = 1, else PLINE; its height level
 *                  h = max of the two; known points on it (WKNOWN when
 *                  h differs), its ink width (index contours: h a multiple
 *                  of index_every, W_INDEX), the summit prior (a ring with
 *                  nothing inside: inside higher, W_SUMMIT), --depressions
 *                  (the side facing the point lower, W_DEPR);
 *   face edge:     probes say sides u and v border one face: b(u) = b(v),
 *                  else dp_face(probes) (13 (ln w + 0.5), at least 6);
 *   spot height:   on the sides its 16 rays meet, the band holding it,
 *                  WKNOWN split over the rays;
 *   gap pair:      (--gap-pairs, off by default) two free ends that face
 *                  each other (endpair.h): the two chunks one state, else
 *                  W_GAP.
 *
 *      side 0 ----- line l ----- side 1        face edges (probes) join
 *        |  b = k            b = k+1 |         sides of different lines;
 *      face edges                face edges    line edges join a line's
 *        |                           |         own two sides
 *
 * The line edges and the strongest face edges form a forest (Kruskal, all
 * line edges first); min-sum dynamic programming over it gives the best
 * bands exactly, and a second pass (messages down) the best cost of every
 * other height of every line: the gap to the best is its confidence.  The
 * face edges left out are checked afterwards: those the solution breaks are
 * leaks or merged lines (reported).  Solved twice: without the priors
 * (summit) a line whose height is still decided is "solved", one decided
 * only with them "assumed", one decided by neither has no height, unless
 * the whole model (every face edge) prefers one of its tied heights by
 * TIE_MIN or more (break_ties: "assumed"). */
#include "scanner/heights_int.h"

#include "scanner/endpair.h"
#include "scanner/faces.h"
#include "scanner/width.h"
#include "src/core/core.h"

#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PLINE 1000.0
#define WKNOWN 1000.0
#define WFACE 2.0
/* What the dynamic programme charges for breaking a face edge of w
 * probes: DP_FACE_S (ln w + DP_FACE_C), at least DP_FACE_MIN.  Measured
 * (2026-12-04, bench_heights --oracle, every traced sheet): the true
 * heights break 52 % of the face edges of 1-2 probes, 18 % at 8-16, 8 % at
 * 32-64, 1 % over 256, so the evidence grows with ln w (log-odds about
 * 0.83 ln w - 0.4); a label read for sure (W_LABEL 40) is worth about one
 * of 8 probes.  Until then a break cost 2 per probe and at least 60, more
 * than a label: one probe across a gap outweighed a printed label
 * (docs/label.md, "Face edges priced by their probes"). */
#define DP_FACE_S 13.0
#define DP_FACE_C 0.5
#define DP_FACE_MIN 6.0
#define WCONT 24.0 /* a chunk continues its line: same state */
#define CHUNK 48.0 /* px of arc per chunk */
#define W_INDEX                                                                \
    8.0 /* a line's width against its height, at 80 px of line or more         \
           (docs/label.md, "Index widths weighted 8") */
#define W_INDEX_TRIAL                                                          \
    3.0 /* ... in the interval's and the index spacing's trials: at 8 the      \
           printed Front Range 25 sheet's 6 labels fit intervals 25 and 2.5    \
           alike (its faded and crowded lines' widths err both ways) */
#define W_SUMMIT 0.5
#define W_RING 0.25
#define W_NEST                                                                 \
    20.0 /* a ring and one it holds at one level (the ground between them a    \
            ring-shaped ridge or moat): in the priors pass, per face edge      \
            between them.  Measured on the true lines of the four real-DEM     \
            sheets: 0 of 208 such pairs with the inner ring 60 px^2 or         \
            more (-ln(1/208) 5.3, times four as the face costs) */
#define NEST_AREA                                                              \
    60.0 /* px^2: smaller inner rings (Elkhorn's one-pixel                     \
            bumps and pits, 24 of its 46 nested pairs, all                     \
            under 40 px^2) may sit at their ring's level */
#define W_DEPR 50.0
#define W_TICKED 20.0  /* a ring read with depression ticks falls inwards */
#define W_LABEL 40.0 /* a printed label read with confidence 1 */
#define LAB_NEAR                                                               \
    0.5 /* a label none of whose readings gives its line's height pays     \
           this share of its weight (lab_off) ...  */
#define LAB_STEP                                                               \
    0.1 /* ... and this much more per level off, up to all of it           \
           (ridges new print: 0.888 -> 0.928; 0.3 + 0.15 d the same gains  \
           and two rows down, 0.7 + 0.06 d the same) */
#define NLAB (1 + TD_OCR_ALTS) /* readings of a label kept per chunk */
#define ALT_SHARE 0.5 /* an alternative reading this sure counts when the
                         interval is inferred */
#define SPOT_CONF 0.7 /* spot heights read with less are not used */
#define MIN_INFER_LABELS 3 /* fewer labels read: no interval inferred */
#define SPAN_CONF                                                              \
    0.7 /* a label step needs two values read at least this sure that          \
           differ by it: on Elkhorn at interval 20 every label read for        \
           sure said 200, and a "29" read at 0.5 made 0.5 m the interval */
#define FAR_LEVELS 20.0    /* label_range */
#define INFER_MARGIN 20.0  /* the runner-up interval costs at least this
                              (and 10 %) more, or none is inferred: half a
                              label read for sure */
#define W_UP 3.0     /* its top towards higher ground, confidence 1 */
#define W_VEE 6.0    /* a stream's V on a line points uphill, sharpness 1 */
#define FACE_A 4.0   /* the search: a broken face edge of w probes costs */
#define FACE_B 2.6   /* FACE_A + FACE_B ln w (see face_cost) */
#define SEARCH_WORK 4e7 /* node and edge visits per improve() */
#define SEARCH_SWEEPS 20
#define WFOLD 1.0
#define FOLD_S                                                                 \
    15.5 /* a fold across a face edge of w probes (both lines stepping the     \
            same way from the face) costs WFOLD + k FOLD_S (ln w - FOLD_C)     \
            (not below WFOLD; k: fold_strength on crowded sheets, FOLD_TIE     \
            elsewhere): of the face edges the true heights keep, the folds     \
            are 0.67 at 1-2 probes, 0.17 at 10-30, 0.007 at 100 and more       \
            (every bench sheet); -ln of the odds in the DP's units (DP_FACE_S  \
            13) */
#define FOLD_C 1.13
#define FOLD_TIE                                                               \
    0.001 /* fold_cost's k on every sheet at least: the same price by the      \
             probes, a thousandth of it, so that of two answers the weak       \
             prior prices alike the one with its folds on the face edges of    \
             fewer probes wins (the shares above), not the lower bands: on     \
             Elkhorn scanned 11 lines (1,885 px) were left undecided, two      \
             answers priced alike, one folding on face edges of 68 and 70      \
             probes (docs/label.md, "Ties broken by the folds' probes") */
#define FOLD_EXCESS                                                            \
    0.02 /* solve_all: the strong fold prior only where the answer with        \
            the weak one has folds for more than this share of the face        \
            edges' weight: 0.2-1.4 % on the crowded sheets' clean,             \
            scanned and colour scans, whose lines are good, 5-8 % on           \
            their printed scans, where leaks and jumps fold regions */
#define FOLD_R0                                                                \
    5.0 /* fold_strength: the full FOLD_S where the contours lie at most       \
           this many pens apart, none from FOLD_R1 on */
#define FOLD_R1 10.0
#define SAME_STRAIGHT                                                          \
    0.9 /* same_pieces: walls this straight (chord over                        \
           length) or more */
#define ARM_ARC                                                                \
    8.0 /* same_pieces: px of a piece back from its end for its direction      \
           (about the scanner's hairpin chord of 8 vertices, widecut.c) */
#define ARM_COS                                                                \
    0.7 /* ... two pieces leaving a wall this nearly the same way (turned      \
           back by more than 134 degrees, as the scanner's hairpin cut) are    \
           the arms of a V cut at its tip (hs.arms) */
#define SAME_KEY                                                               \
    145.0 /* same_pieces' edges in the forest's order: with a                  \
             face edge of 72 probes (WFACE each) */
#define W_GAP                                                                  \
    60.0 /* two free ends that continue each other (gap_pairs):                \
            breaking the tie costs */
#define GAP_KEY                                                                \
    150.0 /* ... its place in the forest's order (30 and 60                    \
             gave the same answers on every bench sheet) */
#define GAP_COST                                                               \
    1.0 /* ... pairs that fit worse (endpair.h's cost) are                     \
           not used: on the two printed Orkhon sheets 13 of                    \
           the 15 wrong pairs fit worse, 24 of the 190 right */
#define W_SAME                                                                 \
    20.0 /* the pieces of a line the scanner cut at a blob                     \
            of ink differ (the priors pass only).  The true                    \
            heights break 2-16 % of these ties on the crowded                  \
            Front Range sheet (7 of 59 clean, 22 of 141 new                    \
            print); at 100 they overruled the faces there */
#define GAP_SPACING                                                            \
    2.0 /* ... nor pairs farther apart than this many contour spacings (the    \
           probes' median length): on the printed Front Range 25 sheet         \
           (contours ~9 px apart) pairs 16-24 px apart join two contours in    \
           15 of 29, under 12 px in 61 of 375 (docs/label.md, "Free ends       \
           that continue each other") */
#define GAP_CLEAR                                                              \
    1.5 /* px: a pair's chord that crosses skeleton ink no line was traced     \
           on this far from both ends is not used: its ends stop in a          \
           merge of contours (faces.h), not at a break */
#define STEP_LEVEL                                                             \
    1.0 /* a step edge (faces.h) holding more than one untraced contour:       \
           each level past the first costs (a tie-breaker, like WFOLD) */
#define GAP_EPS 1e-3
#define SHORT_SURE                                                             \
    32.0 /* px: a line this short solved through the faces alone is at         \
            most SHORT_CONF sure: its height rests on a few probes, and        \
            such pieces are where the scanner cut a line that ran onto its     \
            neighbour (on the printed Orkhon map a 23-px piece left when a     \
            join that crossed another was refused came out 2 intervals off     \
            at 0.95) */
#define SHORT_CONF 0.85
#define DOUBT_SHARE 0.25 /* of a line's face edges' weight broken: doubt */
#define CONF_SCALE                                                             \
    20.0 /* confidence 1 - exp(-gap / this): one label read                    \
            for sure alone 0.85, two 0.98 */
#define MAX_CELLS (96u << 20) /* state table entries (8 bytes each, x3) */

enum { E_LINE, E_FACE, E_CONT, E_SAME, E_GAP, E_STEP };
#define IS_CONT(k) ((k) == E_CONT || (k) == E_SAME || (k) == E_GAP)

typedef struct tedge {
    uint32_t to, kind, id; /* id: chunk (line, continuity) or face edge */
} tedge;

/* A candidate edge of the forest. */
typedef struct cedge {
    uint32_t a, b, kind, id;
    double w;   /* cost to break (Kruskal: strongest first) */
    double key; /* the order the forest takes them in */
} cedge;

/* The DP's tables, per node and state; kept across the interval's trial
 * solves (infer_interval), whose fresh pages the kernel cleared in a
 * fifth of the labelling time of a crowded sheet. */
typedef struct dp_tables {
    double *up, *msg, *down;
    size_t cap; /* doubles each */
} dp_tables;

typedef struct hs {
    td_lines *ls;
    const td_label_params *p;
    td_label_report *rep;
    td_faces *fx;
    td_face_edge *fe;
    size_t nfe, N, C, V; /* lines, chunks, side nodes (2C) */
    const td_face_edge *st; /* step edges: probes across skeleton ink no
                               line traced (faces.h; step_cost), nst */
    size_t nst;
    uint32_t *same;      /* node pairs: two pieces of one cut line
                            (same_pieces), nsame pairs */
    size_t nsame;
    unsigned char *arms; /* per face edge: between the two arms of a V the
                            scanner cut at its tip (same_pieces; NULL:
                            none): the V's inside, a fold when the arms
                            are one contour (on the scanned crowded sheets
                            mostly so), so no fold prior there and no
                            count in fold_share, which is to measure the
                            folds that leaks make */
    uint32_t *gaps; /* node pairs: free ends that continue each other
                       across a gap (gap_pairs), ngaps pairs */
    size_t ngaps;
    /* per chunk */
    double *lknown;               /* level a known point gives (NAN: none) */
    double *wlab;                 /* weight of a printed label */
    double *llab, *clab; /* NLAB per chunk: the levels its label's readings
                            give and their confidences, most confident
                            first, 0 after the last */
    int *nknown;                  /* known points on the chunk */
    signed char *idx;             /* +1 thick (index), -1 thin, 0 unknown */
    double *ilen;                 /* weight of the index evidence */
    double *up_cost;     /* 2 per chunk: cost when side s is the higher */
    double *up_prior;    /* the same, priors only (rings, summits) */
    unsigned char *hole; /* per node: the outside of a closed line */
    unsigned char *ring; /* per node: 1 the inside of a closed line, 2 the
                            outside of one enclosing NEST_AREA px^2 or
                            more */
    long *rnear; /* per chunk: an empty ring's, the chunk of the line next
                    to it whose level it takes (ring_next), else -1 */
    unsigned char *contra; /* per chunk: an assumed height the lines
                              around contradict (sandwich_check) */
    unsigned char *doubt;  /* per chunk: the face edges the answer breaks
                              outweigh those it keeps (report_conflicts) */
    /* per node */
    uint32_t *uf, *comp, *par, *order, *pkind, *pid, *adj_start;
    tedge *adj;
    cedge *ce;
    size_t nce;
    unsigned char *intree; /* per candidate edge */
    /* unary evidence: (node, lo, hi, w): band outside [lo,hi] costs w */
    double *un;
    size_t nun, capun;
    double *unx; /* the same, the priors pass only: what the face edges
                    left out of the forest say (heed_dropped) */
    size_t nunx;
    long *compdepth;
    unsigned char *comp_abs; /* component holds absolute evidence */
    long kofs;
    size_t K;
    double *up, *msg, *down; /* per node and state: the DP's tables, in */
    dp_tables *dp;           /* the caller's, or own */
    dp_tables own;
    long *band, *band_prior; /* per chunk: best height (band index) */
    double *gap, *gap_prior; /* per chunk */
    int priors;              /* this pass uses the priors */
    double fold_k;           /* the fold prior's strength now, and ... */
    double fold_kg;          /* ... the sheet's (fold_strength) */
    double spacing;          /* the contour spacing (sheet_spacing), or
                                a negative value until measured */
    long need_lo, need_hi;   /* levels the domain must hold (need_lo >
                                need_hi: none) */
    int cost_only;           /* only the total cost (the interval's trials) */
} hs;

static uint32_t uf_find(uint32_t *uf, uint32_t a)
{
    while (uf[a] != a) {
        uf[a] = uf[uf[a]];
        a = uf[a];
    }
    return a;
}

/* ---- evidence ---- */

static int add_unary(hs *s, long node, long lo, long hi, double w, td_ctx *cx)
{
    if (s->nun == s->capun) {
        size_t nc = s->capun ? 2 * s->capun : 64;
        double *v = realloc(s->un, nc * 4 * sizeof *v);
        if (!v)
            return td_seterr(cx, TD_ENOMEM, "label: out of memory");
        s->un = v;
        s->capun = nc;
    }
    s->un[4 * s->nun] = (double)node;
    s->un[4 * s->nun + 1] = (double)lo;
    s->un[4 * s->nun + 2] = (double)hi;
    s->un[4 * s->nun++ + 3] = w;
    return 0;
}

/* The chunks of used line l: the first in *c0, how many returned. */
static size_t line_chunks(const hs *s, size_t l, size_t *c0)
{
    long a = td_faces_chunk_at(s->fx, l, 0);
    long b = td_faces_chunk_at(s->fx, l, s->ls->v[l].n - 1);
    if (a < 0)
        return 0;
    *c0 = (size_t)a;
    return (size_t)(b - a + 1);
}

/* The chunk of the used line nearest (x,y) within p->near px (its line in
 * *line), -1 when none. */
static long chunk_near(const hs *s, const double *box, double x, double y,
                       long *line)
{
    size_t i, k, bk = 0;
    long best = -1;
    double bd = s->p->near, d;
    for (i = 0; i < s->N; i++) {
        const td_line *l = &s->ls->v[i];
        const double *b = box + 4 * i;
        if (!td_faces_used(s->fx, i))
            continue;
        /* a box farther than bd holds no point within it (the margin:
           the distance's own rounding) */
        if (hypot(fmax(0, fmax(b[0] - x, x - b[2])),
                  fmax(0, fmax(b[1] - y, y - b[3]))) > bd + 1e-6)
            continue;
        if ((d = td_contain_dist(l, x, y)) > bd)
            continue;
        bd = d;
        best = (long)i;
    }
    if (best < 0)
        return -1;
    bd = INFINITY;
    for (k = 0; k < s->ls->v[best].n; k++) {
        const double *q = s->ls->v[best].xy + 2 * k;
        d = hypot(q[0] - x, q[1] - y);
        if (d < bd)
            bd = d, bk = k;
    }
    *line = best;
    return td_faces_chunk_at(s->fx, (size_t)best, bk);
}

static long line_by_id(const hs *s, long id)
{
    size_t i;
    for (i = 0; i < s->N; i++)
        if (s->ls->v[i].id == id)
            return td_faces_used(s->fx, i) ? (long)i : -2;
    return -1;
}

/* A known point inside a face: the band holding it on every side node
 * its rays meet. */
static int known_in_face(hs *s, const td_label_point *q, td_ctx *cx)
{
    long nodes[16], lo, hi;
    double f = (q->height - s->p->base) / s->p->interval;
    int k, hits = td_faces_around(s->fx, q->x, q->y, nodes);
    if (hits == 0) {
        td_label_warn(s->rep,
                      "known point (%g,%g)=%g: no line around it, "
                      "not used",
                      q->x, q->y, q->height);
        return 0;
    }
    lo = (long)floor(f + 1e-9);
    hi = lo;
    if (fabs(f - lround(f)) < 1e-9) { /* on a multiple: either band */
        lo = lround(f) - 1;
        hi = lround(f);
    }
    for (k = 0; k < 16; k++)
        if (nodes[k] >= 0 &&
            add_unary(s, nodes[k], lo, hi, WKNOWN / hits, cx) != 0)
            return TD_ENOMEM;
    return 0;
}

static void put_known(hs *s, size_t c, long level, long line)
{
    if (s->nknown[c] && s->lknown[c] != (double)level)
        td_label_warn(s->rep,
                      "line %ld: two known points disagree (%g "
                      "and %g); the solve decides",
                      s->ls->v[line].id,
                      s->p->base + s->lknown[c] * s->p->interval,
                      s->p->base + (double)level * s->p->interval);
    s->lknown[c] = (double)level;
    s->nknown[c]++;
}

/* Every line's bounding box (x0, y0, x1, y1), for chunk_near. */
static double *line_boxes(const hs *s, td_ctx *cx)
{
    double *box = td_malloc((4 * s->N + 1) * sizeof *box, cx);
    long i;
    if (!box)
        return NULL;
#pragma omp parallel for schedule(dynamic, 16)
    for (i = 0; i < (long)s->N; i++)
        td_line_box(&s->ls->v[i], box + 4 * i);
    return box;
}

static int setup_known(hs *s, td_ctx *cx)
{
    size_t i, k, c0, m;
    double *box = NULL;
    int rc = 0;
    for (i = 0; i < s->p->nknown; i++)
        if (s->p->known[i].id < 0) {
            if (!(box = line_boxes(s, cx)))
                return TD_ENOMEM;
            break;
        }
    for (i = 0; i < s->p->nknown && rc == 0; i++) {
        const td_label_point *q = &s->p->known[i];
        long l = -1, c;
        double f = (q->height - s->p->base) / s->p->interval;
        if (q->id >= 0) {
            if ((l = line_by_id(s, q->id)) < 0) {
                td_label_warn(s->rep,
                              "height %g for line %ld: no such line "
                              "(or too short), not used",
                              q->height, q->id);
                continue;
            }
            m = line_chunks(s, (size_t)l, &c0);
            for (k = 0; k < m; k++)
                put_known(s, c0 + k, lround(f), l);
        } else if ((c = chunk_near(s, box, q->x, q->y, &l)) >= 0) {
            put_known(s, (size_t)c, lround(f), l);
        } else {
            if (!(q->x >= 0 && q->y >= 0 && q->x <= s->p->w && q->y <= s->p->h))
                rc = td_seterr(cx, TD_EINVAL,
                               "known point (%g,%g) is off "
                               "the %d x %d sheet",
                               q->x, q->y, s->p->w, s->p->h);
            else if (known_in_face(s, q, cx) != 0)
                rc = TD_ENOMEM;
            continue;
        }
        if (fabs(f - lround(f)) > 1e-6)
            td_label_warn(s->rep,
                          "known point (%g,%g)=%g lies on line %ld "
                          "but is not base + a multiple of the interval; "
                          "taken as %g",
                          q->x, q->y, q->height, s->ls->v[l].id,
                          s->p->base + lround(f) * s->p->interval);
    }
    free(box);
    return rc;
}

/* Which side of closed line l is its inside: 0 or 1 (clockwise on the
 * screen, y down: inside on the right, side 1). */
static int inner_side(const td_line *l)
{
    return td_line_signed_area(l) > 0 ? 1 : 0;
}

/* The vertex of line l nearest (x, y). */
static size_t nearest_vertex(const td_line *l, double x, double y)
{
    size_t k, bk = 0;
    double bd = HUGE_VAL;
    for (k = 0; k < l->n; k++) {
        double d = hypot(l->xy[2 * k] - x, l->xy[2 * k + 1] - y);
        if (d < bd)
            bd = d, bk = k;
    }
    return bk;
}

/* The confidence of the reading of chunk c's label that gives level h;
 * 0: none does. */
static double lab_conf(const hs *s, size_t c, long h)
{
    const double *lv = s->llab + c * NLAB, *cf = s->clab + c * NLAB;
    int k;
    for (k = 0; k < NLAB && cf[k] > 0; k++)
        if (lv[k] == (double)h)
            return cf[k];
    return 0.0;
}

/* The share of a label's weight that line c at level h pays: 1 - the
 * confidence of the reading giving h; when none gives it, LAB_NEAR and
 * LAB_STEP more per level from the likeliest reading, up to 1 (always 1
 * in the interval's trials: there a label fits its step or it does not,
 * and a near miss must not make a wrong interval as cheap as the right
 * one). */
static double lab_off(const hs *s, size_t c, long h)
{
    double cf = lab_conf(s, c, h), d;
    if (cf > 0)
        return 1.0 - cf;
    if (s->cost_only)
        return 1.0;
    d = fabs((double)h - s->llab[c * NLAB]);
    return fmin(1.0, LAB_NEAR + LAB_STEP * d);
}

/* The levels a label's readings give, on the grid base + k interval:
 * lev[], cf[] (most confident first) and whether each was read turned
 * round; returns how many. */
static int readings(const hs *s, const td_ocr_read *r, long *lev, double *cf,
                    int *turned, double lo_v, double hi_v)
{
    int k, m = 0;
    for (k = -1; k < TD_OCR_ALTS; k++) {
        double v = k < 0 ? r->value : r->alt[k].value;
        double c = k < 0 ? r->conf : r->alt[k].conf;
        double f = (v - s->p->base) / s->p->interval;
        if (!(c > 0))
            break;
        if (fabs(f - lround(f)) > 1e-6 || v < lo_v || v > hi_v)
            continue;
        lev[m] = lround(f), cf[m] = c, turned[m] = k >= 0 && r->alt[k].turned;
        m++;
    }
    return m;
}

/* The heights the line labels read at least `least` sure (on base + a
 * multiple of the interval) and the known points span, into *lo, *hi
 * (lo > hi: none). */
static void label_span(const hs *s, double least, double *lo, double *hi)
{
    size_t i;
    *lo = HUGE_VAL, *hi = -HUGE_VAL;
    for (i = 0; i < s->p->nlabels; i++) {
        const td_ocr_read *r = &s->p->labels[i];
        double f = (r->value - s->p->base) / s->p->interval;
        if (!r->spot && r->conf >= least && fabs(f - lround(f)) < 1e-6)
            *lo = fmin(*lo, r->value), *hi = fmax(*hi, r->value);
    }
    for (i = 0; i < s->p->nknown; i++)
        *lo = fmin(*lo, s->p->known[i].height),
        *hi = fmax(*hi, s->p->known[i].height);
}

/* The heights a label can have: within the span of the labels read at
 * least SPAN_CONF sure and the known points, widened by the larger of
 * that span and FAR_LEVELS intervals (a read outside lost or gained a
 * digit: on the printed Front Range 20 sheet "2040" read as "40" at 0.5
 * tied its line 100 intervals below its neighbours); no limit without
 * such labels or points. */
static void label_range(const hs *s, double *lo_v, double *hi_v)
{
    double lo, hi, w;
    label_span(s, SPAN_CONF, &lo, &hi);
    if (lo > hi) {
        *lo_v = -HUGE_VAL, *hi_v = HUGE_VAL;
        return;
    }
    w = fmax(hi - lo, FAR_LEVELS * s->p->interval);
    *lo_v = lo - w, *hi_v = hi + w;
}

/* One printed label r on line l, read as the m levels lev (confidences
 * cf, turned round or not): the levels on the chunk next to it, and
 * (label_up) its top towards the higher side. */
static void label_on(hs *s, const td_ocr_read *r, size_t l, const long *lev,
                     const double *cf, const int *turned, int m)
{
    const td_line *L = &s->ls->v[l];
    size_t k = nearest_vertex(L, r->x, r->y), a, b;
    long c = td_faces_chunk_at(s->fx, l, k);
    double tx, ty, top;
    int j;
    if (c < 0 || m == 0)
        return;
    if (s->wlab[c] > 0 && s->llab[c * NLAB] != (double)lev[0])
        td_label_warn(s->rep,
                      "labels %g and %g on line %ld (near %.0f,%.0f) "
                      "disagree; the solve decides",
                      s->p->base + s->llab[c * NLAB] * s->p->interval,
                      s->p->base + (double)lev[0] * s->p->interval, L->id,
                      r->x, r->y);
    if (cf[0] > s->clab[c * NLAB]) { /* the surer label speaks */
        s->wlab[c] = W_LABEL;
        for (j = 0; j < NLAB; j++) {
            s->llab[c * NLAB + j] = j < m ? (double)lev[j] : 0.0;
            s->clab[c * NLAB + j] = j < m ? cf[j] : 0.0;
        }
    }
    /* the top's side: only when the text cannot be read the other way */
    if (!s->p->label_up)
        return;
    for (j = 0; j < m; j++)
        if (turned[j])
            return;
    a = k >= 2 ? k - 2 : 0;
    b = k + 2 < L->n ? k + 2 : L->n - 1;
    tx = L->xy[2 * b] - L->xy[2 * a];
    ty = L->xy[2 * b + 1] - L->xy[2 * a + 1];
    /* side 0 (left on the screen) is towards (ty, -tx); the top (uy, -ux) */
    top = r->uy * ty + -r->ux * -tx;
    if (fabs(top) < 1e-9)
        return;
    s->up_cost[2 * c + (top > 0 ? 1 : 0)] += W_UP * r->conf;
}

/* Printed spot heights (td_ocr_find_spots): the band holding the value
 * on the sides of the face around the dot, weighted as a label read with
 * that confidence (a misread costs, it does not rule). */
static int setup_spots(hs *s, td_ctx *cx)
{
    size_t i;
    double lo_v, hi_v, I = s->p->interval;
    /* the range the line labels span, widened by 20 intervals: a spot
       read outside it lost digits (2748 read as 274) */
    label_span(s, -HUGE_VAL, &lo_v, &hi_v);
    for (i = 0; i < s->p->nlabels; i++) {
        td_ocr_read *r = &s->p->labels[i];
        long nodes[16], lo;
        double f;
        int k, hits;
        if (!r->spot)
            continue;
        f = (r->value - s->p->base) / s->p->interval;
        r->used = 0;
        if (r->conf < SPOT_CONF) {
            r->why = "spot height read with too little confidence";
            continue;
        }
        if (lo_v <= hi_v &&
            (r->value < lo_v - 20 * I || r->value > hi_v + 20 * I)) {
            r->why = "spot height far outside the heights of the labels";
            continue;
        }
        hits = td_faces_around(s->fx, r->sx, r->sy, nodes);
        r->why = hits ? NULL : "spot height: no line around it";
        if (!hits)
            continue;
        lo = (long)floor(f + 1e-9);
        for (k = 0; k < 16; k++)
            if (nodes[k] >= 0 &&
                add_unary(s, nodes[k], fabs(f - lround(f)) < 1e-9
                                           ? lround(f) - 1 : lo, lo,
                          W_LABEL * r->conf / hits, cx) != 0)
                return TD_ENOMEM;
        r->used = 1;
        s->rep->labels_used++;
    }
    return 0;
}

/* Printed labels: reads with no reading on base + k * interval are
 * refused. */
static void setup_labels(hs *s)
{
    size_t i;
    int j;
    double lo_v, hi_v;
    label_range(s, &lo_v, &hi_v);
    for (i = 0; i < s->p->nlabels; i++) {
        td_ocr_read *r = &s->p->labels[i];
        long lev[NLAB];
        double cf[NLAB];
        int turned[NLAB], m, any = 0;
        if (r->spot)
            continue; /* setup_spots */
        r->used = 0;
        r->why = NULL;
        if ((m = readings(s, r, lev, cf, turned, -HUGE_VAL, HUGE_VAL)) == 0) {
            r->why = "not base + a multiple of the interval";
            continue;
        }
        if ((m = readings(s, r, lev, cf, turned, lo_v, hi_v)) == 0) {
            r->why = "far outside the heights of the surer labels";
            continue;
        }
        for (j = 0; j < 2; j++)
            if (r->line[j] >= 0 && (size_t)r->line[j] < s->N &&
                td_faces_used(s->fx, (size_t)r->line[j])) {
                label_on(s, r, (size_t)r->line[j], lev, cf, turned, m);
                any = 1;
            }
        if (!any)
            r->why = "no traced line at the label";
    }
}

/* Streams' Vs (scanner/streams.h): the side of the chunk the V points to
 * rises. */
static void setup_vees(hs *s)
{
    size_t i;
    for (i = 0; i < s->p->nvees; i++) {
        const td_vee *v = &s->p->vees[i];
        long c;
        if (v->line < 0 || (size_t)v->line >= s->N ||
            !td_faces_used(s->fx, (size_t)v->line))
            continue;
        c = td_faces_chunk_at(s->fx, (size_t)v->line,
                              nearest_vertex(&s->ls->v[v->line], v->x, v->y));
        if (c < 0)
            continue; /* cost when the other side is the higher: */
        s->up_cost[2 * c + (1 - v->up)] += W_VEE * v->conf;
        s->rep->vees += !s->cost_only;
    }
}

/* Make alternative k of r its read (the topology chose it): the read
 * becomes an alternative, the turns follow the new read's way. */
static void take_alt(td_ocr_read *r, int k)
{
    td_ocr_alt a = r->alt[k];
    int j;
    r->alt[k].value = r->value, r->alt[k].conf = r->conf;
    r->value = a.value, r->conf = a.conf;
    if (a.turned) {
        r->ux = -r->ux, r->uy = -r->uy;
        for (j = 0; j < TD_OCR_ALTS; j++)
            if (j != k && r->alt[j].conf > 0)
                r->alt[j].turned = !r->alt[j].turned;
    }
    for (j = k; j > 0 && r->alt[j].conf > r->alt[j - 1].conf; j--) {
        td_ocr_alt t = r->alt[j];
        r->alt[j] = r->alt[j - 1], r->alt[j - 1] = t;
    }
    snprintf(r->text, sizeof r->text, "%.10g", r->value);
}

/* After the solve: which labels the heights agree with (lines' ids are
 * still the chunks' until set_lines). */
static void judge_labels(hs *s)
{
    size_t i, overruled = 0;
    int j, k;
    for (i = 0; i < s->p->nlabels; i++) {
        td_ocr_read *r = &s->p->labels[i];
        double f = (r->value - s->p->base) / s->p->interval;
        int on = fabs(f - lround(f)) < 1e-6;
        int alt = -1; /* the alternative the heights agree with */
        if (r->why || r->spot)
            continue;
        for (j = 0; j < 2; j++) {
            long l = r->line[j], c;
            if (l < 0 || (size_t)l >= s->N || !td_faces_used(s->fx, (size_t)l))
                continue;
            c = td_faces_chunk_at(s->fx, (size_t)l,
                                  nearest_vertex(&s->ls->v[l], r->x, r->y));
            if (c >= 0 && on && s->band_prior[c] + s->kofs == lround(f)) {
                r->used = 1;
                continue;
            }
            for (k = 0; c >= 0 && k < TD_OCR_ALTS && r->alt[k].conf > 0; k++)
                if (fabs((r->alt[k].value - s->p->base) / s->p->interval -
                         (double)(s->band_prior[c] + s->kofs)) < 1e-6 &&
                    (alt < 0 || r->alt[k].conf > r->alt[alt].conf))
                    alt = k;
        }
        if (!r->used && alt >= 0) { /* the topology chose another reading */
            take_alt(r, alt);
            r->used = 1;
        }
        if (r->used) {
            s->rep->labels_used++;
        } else {
            long l = r->line[0] >= 0 ? r->line[0] : r->line[1], c = -1;
            r->why = "the other evidence disagrees";
            if (l >= 0 && (size_t)l < s->N)
                c = td_faces_chunk_at(s->fx, (size_t)l,
                                      nearest_vertex(&s->ls->v[l], r->x, r->y));
            if (c >= 0 && ++overruled <= 5)
                td_label_warn(s->rep,
                              "label %s (near %.0f,%.0f) on line %ld "
                              "disagrees with the other evidence; the solve "
                              "gives %g",
                              r->text, r->x, r->y, s->ls->v[l].id,
                              s->p->base +
                                  (double)(s->band_prior[c] + s->kofs) *
                                      s->p->interval);
        }
    }
}

/* Do the face edges of line l's inner side reach only line `prev`? */
static int holds_only(const hs *s, size_t l, int in, long prev)
{
    size_t i, c0, m = line_chunks(s, l, &c0);
    for (i = 0; i < s->nfe; i++) {
        uint32_t a = s->fe[i].a, b = s->fe[i].b, o;
        size_t ca = a / 2, cb = b / 2;
        if (ca >= c0 && ca < c0 + m && (int)(a & 1) == in)
            o = b;
        else if (cb >= c0 && cb < c0 + m && (int)(b & 1) == in)
            o = a;
        else
            continue;
        if ((long)td_faces_chunk_line(s->fx, o / 2) != prev)
            return 0;
    }
    return 1;
}

/* --depressions X,Y: the innermost closed line around the point falls
 * inwards, and so does each closed line around it that holds only the
 * previous one (a pit's nested rings), as the tree labeller did. */
static void depression(hs *s, double x, double y)
{
    long prev = -1;
    double last = 0;
    for (;;) {
        size_t i, k, c0, m;
        long best = -1;
        double ba = HUGE_VAL;
        int in;
        for (i = 0; i < s->N; i++) {
            const td_line *l = &s->ls->v[i];
            double a;
            if (!td_faces_used(s->fx, i) || !l->closed ||
                !td_line_encloses(l, x, y))
                continue;
            a = fabs(td_line_signed_area(l));
            if (a > last && a < ba)
                ba = a, best = (long)i;
        }
        if (best < 0)
            return;
        in = inner_side(&s->ls->v[best]);
        if (prev >= 0 && !holds_only(s, (size_t)best, in, prev))
            return;
        m = line_chunks(s, (size_t)best, &c0);
        for (k = 0; k < m; k++) /* cost when the inner side is higher */
            s->up_cost[2 * (c0 + k) + in] += W_DEPR / m;
        prev = best;
        last = ba;
    }
}

/* Priors and hints on the direction of each line: rings rise, summits
 * (rings with nothing inside) rise more, --depressions. */
static void setup_directions(hs *s, const unsigned char *touched)
{
    size_t i, k, c0, m;
    size_t marks = 0; /* the sheet marks its depressions */
    for (i = 0; i < s->N; i++)
        marks += td_faces_used(s->fx, i) && s->ls->v[i].closed &&
                 s->ls->v[i].depression;
    if (marks && !s->cost_only)
        td_label_warn(s->rep, "%zu ring%s marked as depression%s (ticks on "
                      "the inside) fall%s inwards", marks,
                      marks == 1 ? "" : "s", marks == 1 ? "" : "s",
                      marks == 1 ? "s" : "");
    for (i = 0; i < s->N; i++) {
        const td_line *l = &s->ls->v[i];
        int in, big, empty = 1;
        if (!td_faces_used(s->fx, i) || !l->closed)
            continue;
        in = inner_side(l);
        m = line_chunks(s, i, &c0);
        for (k = 0; k < m; k++)
            s->hole[2 * (c0 + k) + (1 - in)] = 1;
        big = fabs(td_line_signed_area(l)) >= NEST_AREA;
        for (k = 0; k < m; k++) {
            s->ring[2 * (c0 + k) + in] = 1;
            s->ring[2 * (c0 + k) + (1 - in)] = big ? 2 : 0;
        }
        for (k = 0; k < m; k++)
            empty &= !touched[2 * (c0 + k) + in];
        for (k = 0; k < m; k++)
            s->up_prior[2 * (c0 + k) + (1 - in)] +=
                (W_RING + (empty ? W_SUMMIT : 0)) / m;
        /* ticked: falls inwards (read).  Rings without ticks get no
         * more than the ring prior: small depressions carry none, and
         * taking unticked rings to rise lost 0.015 of the length on the
         * ticked Front Range sheet (docs/label.md) */
        for (k = 0; l->depression && k < m; k++)
            s->up_cost[2 * (c0 + k) + in] += W_TICKED / m;
    }
    for (k = 0; k < s->p->ndepressions; k++)
        depression(s, s->p->depressions[2 * k], s->p->depressions[2 * k + 1]);
}

/* Index contours by their ink width. */
static int setup_index(hs *s, td_ctx *cx)
{
    double cut;
    size_t i, k, c0, m;
    int rc, inked;
    if (s->p->index_every <= 0 || s->p->index_off)
        return 0;
    if ((rc = td_label_thick_cut(s->ls, s->p, &cut, &inked, cx)) < 0)
        return rc;
    if (rc == 0) {
        if (!s->p->index_auto)
            td_label_warn(s->rep, "--index-every: the line widths show no "
                                  "thicker index contours; not used");
        return 0;
    }
    for (i = 0; i < s->N; i++) {
        const td_line *l = &s->ls->v[i];
        double len = td_line_length(l), wt = td_line_weight(l, inked);
        if (!td_faces_used(s->fx, i) || !(wt > 0) || len < 30)
            continue;
        m = line_chunks(s, i, &c0);
        for (k = 0; k < m; k++) {
            s->idx[c0 + k] = wt >= cut ? 1 : -1;
            s->ilen[c0 + k] = (s->cost_only ? W_INDEX_TRIAL : W_INDEX) *
                              fmin(1.0, len / 80.0) / m;
        }
    }
    return 0;
}

/* ---- the forest ---- */

static int cmp_ce(const void *pa, const void *pb)
{
    const cedge *a = pa, *b = pb;
    return (a->key < b->key) - (a->key > b->key);
}

/* What a continuity edge costs when its two sides differ: a chunk's
 * line going on (WCONT), or two pieces of a cut line (same_pieces: a
 * prior, W_SAME in the priors pass only). */
static double cont_w(const hs *s, uint32_t kind)
{
    if (kind == E_GAP)
        return W_GAP;
    if (kind != E_SAME)
        return WCONT;
    return s->priors ? W_SAME : 0.0;
}

/* Candidate edges: every chunk's line edge (first: always in the forest),
 * then continuity and face edges, strongest first. */
static int candidates(hs *s, td_ctx *cx)
{
    size_t i, c, n = 0, c0, m;
    if (!(s->ce =
              td_malloc((2 * s->C + s->nfe + s->nst + s->nsame + s->ngaps + 1) *
                            sizeof *s->ce,
                        cx)))
        return TD_ENOMEM;
    for (c = 0; c < s->C; c++)
        s->ce[n++] = (cedge){(uint32_t)(2 * c), (uint32_t)(2 * c + 1), E_LINE,
                             (uint32_t)c, INFINITY, INFINITY};
    for (i = 0; i < s->N; i++) {
        if (!td_faces_used(s->fx, i))
            continue;
        m = line_chunks(s, i, &c0);
        for (c = 0; c + 1 < m + (s->ls->v[i].closed && m > 2); c++) {
            size_t a = c0 + c, b = c0 + (c + 1) % m;
            s->ce[n++] = (cedge){(uint32_t)(2 * a), (uint32_t)(2 * b), E_CONT,
                                 (uint32_t)a, WCONT, WCONT};
        }
    }
    for (i = 0; i < s->nfe; i++)
        s->ce[n++] = (cedge){s->fe[i].a, s->fe[i].b, E_FACE, (uint32_t)i,
                             WFACE * s->fe[i].w, WFACE * s->fe[i].w};
    for (i = 0; i < s->nst; i++)
        s->ce[n++] =
            (cedge){s->st[i].a,  s->st[i].b,         E_STEP,
                    (uint32_t)i, WFACE * s->st[i].w, WFACE * s->st[i].w};
    for (i = 0; i < s->nsame; i++)
        s->ce[n++] = (cedge){s->same[2 * i], s->same[2 * i + 1], E_SAME,
                             (uint32_t)i,    SAME_KEY,           SAME_KEY};
    for (i = 0; i < s->ngaps; i++)
        s->ce[n++] = (cedge){s->gaps[2 * i], s->gaps[2 * i + 1],
                             E_GAP,          (uint32_t)i,
                             W_GAP,          GAP_KEY};
    qsort(s->ce + s->C, n - s->C, sizeof *s->ce, cmp_ce);
    s->nce = n;
    return 0;
}

static int build_forest(hs *s, td_ctx *cx)
{
    size_t i, V = s->V;
    uint32_t *deg;
    free(s->intree), free(s->adj);
    s->intree = NULL, s->adj = NULL;
    if (!(s->intree = td_calloc(s->nce + 1, 1, cx)) ||
        !(s->adj = td_malloc((2 * s->nce + 1) * sizeof *s->adj, cx)) ||
        !(deg = td_calloc(V + 1, sizeof *deg, cx)))
        return TD_ENOMEM;
    for (i = 0; i < V; i++)
        s->uf[i] = (uint32_t)i;
    for (i = 0; i < s->nce; i++) {
        uint32_t a = uf_find(s->uf, s->ce[i].a), b = uf_find(s->uf, s->ce[i].b);
        if (a == b)
            continue;
        s->uf[a] = b;
        s->intree[i] = 1;
        deg[s->ce[i].a]++, deg[s->ce[i].b]++;
    }
    s->adj_start[0] = 0;
    for (i = 0; i < V; i++)
        s->adj_start[i + 1] = s->adj_start[i] + deg[i];
    memset(deg, 0, (V + 1) * sizeof *deg);
    for (i = 0; i < s->nce; i++) {
        const cedge *e = &s->ce[i];
        if (!s->intree[i])
            continue;
        s->adj[s->adj_start[e->a] + deg[e->a]++] =
            (tedge){e->b, e->kind, e->id};
        s->adj[s->adj_start[e->b] + deg[e->b]++] =
            (tedge){e->a, e->kind, e->id};
    }
    free(deg);
    return 0;
}

/* Breadth-first order, parents and components; the depth of each
 * component in line edges. */
static int order_forest(hs *s, td_ctx *cx)
{
    size_t V = s->V, head = 0, tail = 0, r;
    long *dep = td_malloc((V + 1) * sizeof *dep, cx);
    if (!dep)
        return TD_ENOMEM;
    for (r = 0; r < V; r++)
        s->comp[r] = UINT32_MAX;
    for (r = 0; r < V; r++) {
        if (s->comp[r] != UINT32_MAX)
            continue;
        s->comp[r] = (uint32_t)r;
        s->par[r] = UINT32_MAX;
        dep[r] = 0;
        s->compdepth[r] = 0;
        s->order[tail++] = (uint32_t)r;
        while (head < tail) {
            uint32_t u = s->order[head++], k;
            for (k = s->adj_start[u]; k < s->adj_start[u + 1]; k++) {
                const tedge *t = &s->adj[k];
                if (s->comp[t->to] != UINT32_MAX)
                    continue;
                s->comp[t->to] = (uint32_t)r;
                s->par[t->to] = u;
                s->pkind[t->to] = t->kind;
                s->pid[t->to] = t->id;
                dep[t->to] = dep[u] + (t->kind == E_LINE);
                if (dep[t->to] > s->compdepth[r])
                    s->compdepth[r] = dep[t->to];
                s->order[tail++] = t->to;
            }
        }
    }
    s->order[tail] = UINT32_MAX;
    free(dep);
    return 0;
}

/* [lo, hi] widened to hold level v and the band below it. */
static void widen(long *lo, long *hi, long v)
{
    *lo = *lo < v - 1 ? *lo : v - 1;
    *hi = *hi > v ? *hi : v;
}

/* The band range every node can need, from the evidence and the depths.
 * A label's other readings widen it only within the range its first
 * readings, the known points and the spot heights give, widened as
 * below (2 D + 2 either side): on the crowded sheet a "2800" also read
 * "24800" and a "2600" also "92" made the trial solves of the interval
 * span 17 to 24800 m, 1240 bands at interval 20 where 40 hold every
 * line, 756 MB for a 3.5 Mpx sheet.  A reading outside is never
 * chosen: no band there. */
static int set_domain(hs *s, td_ctx *cx)
{
    long lo = LONG_MAX, hi = LONG_MIN, D = 0, alo, ahi;
    size_t i;
    int k;
    for (i = 0; i < s->V; i++)
        if (s->comp[i] == i && s->compdepth[i] > D)
            D = s->compdepth[i];
    for (i = 0; i < s->C; i++) { /* known points, first readings */
        if (s->nknown[i])
            widen(&lo, &hi, (long)s->lknown[i]);
        if (s->wlab[i] > 0 && s->clab[i * NLAB] > 0)
            widen(&lo, &hi, (long)s->llab[i * NLAB]);
    }
    for (i = 0; i < s->nun; i++) {
        lo = lo < (long)s->un[4 * i + 1] ? lo : (long)s->un[4 * i + 1];
        hi = hi > (long)s->un[4 * i + 2] ? hi : (long)s->un[4 * i + 2];
    }
    alo = lo - 2 * D - 2, ahi = hi + 2 * D + 2;
    for (i = 0; i < s->C; i++) /* the other readings, within that */
        for (k = 1; s->wlab[i] > 0 && k < NLAB && s->clab[i * NLAB + k] > 0;
             k++) {
            long v = (long)s->llab[i * NLAB + k];
            if (v - 1 >= alo && v <= ahi)
                widen(&lo, &hi, v);
        }
    if (lo > hi)
        lo = hi = 0;
    if (s->need_lo <= s->need_hi) {
        lo = lo < s->need_lo ? lo : s->need_lo;
        hi = hi > s->need_hi ? hi : s->need_hi;
    }
    s->kofs = lo - 2 * D - 2;
    s->K = (size_t)(hi - lo) + 4 * (size_t)D + 5;
    if (2 * s->K > MAX_CELLS / (s->V + 1))
        return td_seterr(cx, TD_ENOMEM,
                         "label: %zu lines over %zu levels "
                         "are too many to solve at once",
                         s->N, s->K);
    return 0;
}

/* ---- min-sum dynamic programming over the forest ----
 *
 * A node's state is (band k, d): d = 1 when its line's other side is one
 * band higher (this side is the lower), d = 0 when one lower.  State
 * index 2k + d; K2 = 2K states.  A line edge then fixes the child's state
 * from the parent's: (k, d) -> (k + (d ? 1 : -1), 1 - d).  A face edge
 * costs WFACE * probes when the bands differ and the fold cost when both
 * lines step the same way from the face (a ridge or valley band). */

static double vmin(const double *v, size_t K, size_t *arg)
{
    double m = INFINITY;
    size_t k, am = 0;
    for (k = 0; k < K; k++)
        if (v[k] < m)
            m = v[k], am = k;
    if (arg)
        *arg = am;
    return m;
}

/* What unary term q (node, lo, hi, w) costs at band b (absolute:
 * band index + kofs). */
static double unary_at(const double *q, long b)
{
    return b < (long)q[1] || b > (long)q[2] ? q[3] : 0.0;
}

/* A ring's inside and the outside of a ring it holds (NEST_AREA px^2 or
 * more): a fold between them costs W_NEST. */
static int nest_pair(const hs *s, uint32_t a, uint32_t b)
{
    return s->ring[a] + s->ring[b] == 3;
}

/* Cost of line l with side 0 at band a0 and side 1 at a1 (adjacent), its
 * parts added to t[TD_OT_*] when t is not NULL (line_cost: without). */
static inline double line_parts(const hs *s, size_t l, long a0, long a1,
                                double *t)
{
    long h = (a0 > a1 ? a0 : a1) + s->kofs;
    double d = a0 > a1 ? s->up_cost[2 * l] : s->up_cost[2 * l + 1], k = 0,
           lb = 0, ix = 0;
    if (s->priors)
        d += a0 > a1 ? s->up_prior[2 * l] : s->up_prior[2 * l + 1];
    if (s->nknown[l] && (double)h != s->lknown[l])
        k = WKNOWN * s->nknown[l];
    if (s->wlab[l] > 0) /* W (1 - confidence of the reading giving h, or
                           the share lab_off prices a miss at) */
        lb = s->wlab[l] * lab_off(s, l, h);
    if (s->idx[l]) {
        long N = s->p->index_every, m = ((h % N) + N) % N;
        if ((s->idx[l] > 0) != (m == 0))
            ix = s->ilen[l];
    }
    if (t) {
        t[TD_OT_DIR] += d, t[TD_OT_KNOWN] += k;
        t[TD_OT_LABEL] += lb, t[TD_OT_INDEX] += ix;
    }
    return d + k + lb + ix;
}

/* Cost of line l with side 0 at band a0 and side 1 at a1 (adjacent). */
static double line_cost(const hs *s, size_t l, long a0, long a1)
{
    return line_parts(s, l, a0, a1, NULL);
}

/* The state of the other side of line l from state st of its side xs, or
 * -1 when off the band range; *cost gets the line's cost. */
static long across(const hs *s, size_t l, int xs, long st, double *cost)
{
    long a = st >> 1, d = st & 1, b = d ? a + 1 : a - 1;
    if (b < 0 || b >= (long)s->K)
        return -1;
    *cost = xs ? line_cost(s, l, b, a) : line_cost(s, l, a, b);
    return 2 * b + (1 - d);
}

/* Face edge i lies between the two arms of a V (hs.arms). */
static int arms_edge(const hs *s, size_t i)
{
    return s->arms && s->arms[i];
}

/* What a fold across a face edge of w probes costs (the priors pass): a
 * face whose two lines step the same way from it is a ridge or valley
 * band.  On sheets of crowded contours (s->fold_k, fold_strength) such
 * bands are rare where many probes agree; the share measured on the true
 * heights of every bench sheet, in docs/label.md ("Folds priced by their
 * probes"). */
static double fold_cost(const hs *s, double w)
{
    double k = s->fold_k > FOLD_TIE ? s->fold_k : FOLD_TIE;
    return WFOLD + k * fmax(0.0, FOLD_S * (log(w > 1e-3 ? w : 1e-3) - FOLD_C));
}

/* The sheet's contour spacing (td_faces_spacing over the face edges)
 * into *D, measured once a solve (the free-end pairs and the fold prior
 * both ask). */
static int sheet_spacing(hs *s, double *D, td_ctx *cx)
{
    if (s->spacing < 0 && td_faces_spacing(s->fe, s->nfe, &s->spacing, cx) != 0)
        return TD_ENOMEM;
    *D = s->spacing;
    return 0;
}

/* How strongly the face edges' folds are priced (s->fold_k, 0..1): by the
 * sheet's contour spacing (the probes' length, its median weighted by
 * their count) over its pen (the lines' median width; 2 px when no line
 * has one).  The true heights' folds are 0.2-0.9 % of the face edges'
 * weight on the crowded Front Range sheets (contours 3.5-4.5 pens
 * apart), 0.6-3 % on Orkhon (6-10), 3.5-14 % on Elkhorn (15-23) and
 * 17-37 % on Elkhorn at interval 20 (37-56): where contours lie far
 * apart the ground between them folds often, and a strong prior mirrors
 * the regions beyond the true folds. */
static int fold_strength(hs *s, td_ctx *cx)
{
    size_t i, n = 0;
    double *v, D = 0, pen = 2.0, R;
    if (sheet_spacing(s, &D, cx) != 0 ||
        !(v = td_malloc((s->N + 1) * sizeof *v, cx)))
        return TD_ENOMEM;
    for (i = 0; i < s->N; i++)
        if (s->ls->v[i].width > 0)
            v[n++] = s->ls->v[i].width;
    if (n) {
        qsort(v, n, sizeof *v, td_cmp_double);
        pen = v[n / 2];
    }
    free(v);
    R = D / pen;
    s->rep->spacing = D;
    s->fold_kg = fmin(1.0, fmax(0.0, (FOLD_R1 - R) / (FOLD_R1 - FOLD_R0)));
    s->fold_k = 0.0;
    return 0;
}

/* The fold prior on face edge (c, its parent): a face whose boundary
 * pieces (open lines, the inside of rings) step the same way is a ridge
 * or valley band, rarer than a slope.  Not between a ring's outside (a
 * hole of the face: hills and pits stand on slopes at any height, the ring
 * prior speaks for them) and anything else, except a ring's inside and
 * the outside of a ring it holds (W_NEST: a hill in a hill rises on). */
static double fold_w(const hs *s, uint32_t c)
{
    if (!s->priors)
        return 0.0;
    if (nest_pair(s, c, s->par[c]))
        return W_NEST;
    if (s->hole[c] || s->hole[s->par[c]] || arms_edge(s, s->pid[c]))
        return 0.0;
    return fold_cost(s, s->fe[s->pid[c]].w);
}

/* What breaking a face edge of w probes costs in the search's model:
 * the share of face edges that the true heights break falls slowly with
 * their probes (26 % of single probes, 10 % at 8, 2 % above 32 on the
 * Elkhorn sheets), about as -log of it; FACE_A, FACE_B four times that
 * (measured best, docs/label.md "The search"). */
static double dp_face(double w)
{
    return fmax(DP_FACE_S * (log(w > 1e-3 ? w : 1e-3) + DP_FACE_C),
                DP_FACE_MIN);
}

static double face_cost(double w)
{
    return FACE_A + FACE_B * log(w > 1 ? w : 1);
}

/* A step edge (faces.h: untraced contours between two sides) holds when
 * the ground runs on one way through it: side a with band ba whose
 * partner is higher (da) falls into the step, so b lies lower (bb < ba)
 * and its own partner lower still (!db); and the same rising.  Held, it
 * costs STEP_LEVEL for each level past the first (one contour left
 * untraced is the usual); broken, `broken`. */
static double step_cost(long ba, int da, long bb, int db, double broken)
{
    if (da == db || (da ? bb >= ba : bb <= ba))
        return broken;
    return STEP_LEVEL * (double)(labs(bb - ba) - 1);
}

/* Messages over the edge from node c to its parent (up) or back (down):
 * out[x] = min over y of cost(x, y) + in[y]. */
static void pass_edge(const hs *s, uint32_t c, const double *in, double *out,
                      int down)
{
    size_t K2 = 2 * s->K, x;
    if (s->pkind[c] == E_LINE) {
        /* x is the state of the parent (up) or of c (down) */
        int xs = down ? (int)(c & 1) : (int)(1 - (c & 1));
        for (x = 0; x < K2; x++) {
            double lc;
            long y = across(s, s->pid[c], xs, (long)x, &lc);
            out[x] = y >= 0 ? in[y] + lc : INFINITY;
        }
        return;
    } else if (IS_CONT(s->pkind[c])) {
        double m = vmin(in, K2, NULL) + cont_w(s, s->pkind[c]);
        for (x = 0; x < K2; x++)
            out[x] = in[x] < m ? in[x] : m;
    } else if (s->pkind[c] == E_STEP) {
        /* x falling into the step (its partner higher, x & 1) takes the
           best y below it whose partner is lower; rising, above it */
        double esc = vmin(in, K2, NULL) + dp_face(s->st[s->pid[c]].w), run;
        size_t K = s->K, b;
        for (b = 0, run = INFINITY; b < K; b++) { /* y below, partner lower */
            out[2 * b + 1] = run < esc ? run : esc;
            run = in[2 * b] < run + STEP_LEVEL ? in[2 * b] : run + STEP_LEVEL;
        }
        for (b = K, run = INFINITY; b-- > 0;) { /* y above, partner higher */
            out[2 * b] = run < esc ? run : esc;
            run = in[2 * b + 1] < run + STEP_LEVEL ? in[2 * b + 1]
                                                   : run + STEP_LEVEL;
        }
    } else {
        double m[2] = {INFINITY, INFINITY}, wf = dp_face(s->fe[s->pid[c]].w),
               fo = fold_w(s, c);
        for (x = 0; x < K2; x++)
            m[x & 1] = in[x] < m[x & 1] ? in[x] : m[x & 1];
        for (x = 0; x < K2; x++) {
            size_t d = x & 1;
            double v = in[x] + fo, o = in[x ^ 1];
            double esc = wf + (m[d] + fo < m[1 - d] ? m[d] + fo : m[1 - d]);
            v = o < v ? o : v;
            out[x] = esc < v ? esc : v;
        }
    }
}

static void solve_pass(hs *s)
{
    size_t K2 = 2 * s->K, i, n;
    for (i = 0; i < s->V * K2; i++)
        s->up[i] = s->down[i] = 0.0;
    for (i = 0; i < s->nun + (s->priors ? s->nunx : 0); i++) {
        const double *q =
            i < s->nun ? s->un + 4 * i : s->unx + 4 * (i - s->nun);
        long node = (long)q[0], k;
        for (k = 0; k < (long)K2; k++)
            s->up[node * K2 + k] += unary_at(q, (k >> 1) + s->kofs);
    }
    for (n = 0; s->order[n] != UINT32_MAX; n++)
        ;
    for (i = n; i-- > 0;) { /* leaves first */
        uint32_t c = s->order[i], u = s->par[c];
        size_t k;
        if (u == UINT32_MAX)
            continue;
        pass_edge(s, c, s->up + (size_t)c * K2, s->msg + (size_t)c * K2, 0);
        for (k = 0; k < K2; k++)
            s->up[(size_t)u * K2 + k] += s->msg[(size_t)c * K2 + k];
    }
    for (i = 0; i < n; i++) { /* roots first */
        uint32_t c = s->order[i], u = s->par[c];
        double *pre = s->msg + (size_t)c * K2; /* reused: msg is spent */
        size_t k;
        if (u == UINT32_MAX)
            continue;
        for (k = 0; k < K2; k++) {
            double a = s->up[(size_t)u * K2 + k];
            /* infinities: the parent state is impossible either way */
            pre[k] =
                isinf(a) ? INFINITY : s->down[(size_t)u * K2 + k] + a - pre[k];
        }
        pass_edge(s, c, pre, s->down + (size_t)c * K2, 1);
    }
}

/* The best band of every node (ties: the lowest) into band[]. */
static void decode(hs *s, long *band)
{
    size_t K2 = 2 * s->K, i;
    for (i = 0; s->order[i] != UINT32_MAX; i++) {
        uint32_t c = s->order[i];
        const double *u = s->up + (size_t)c * K2, *d = s->down + (size_t)c * K2;
        double best = INFINITY;
        size_t k, am = 0;
        for (k = 0; k < K2; k++)
            if (u[k] + d[k] < best - 1e-9)
                best = u[k] + d[k], am = k;
        band[c] = (long)(am >> 1);
    }
}

/* What child c (its forest edge no line edge) costs in state y with its
 * parent in state x: its subtree's best (up[], after solve_pass) and the
 * edge's. */
static double child_cost(const hs *s, uint32_t c, size_t x, size_t y)
{
    double v = s->up[(size_t)c * 2 * s->K + y], wf, fo;
    if (s->pkind[c] == E_STEP)
        return v + step_cost((long)(x >> 1), (int)(x & 1), (long)(y >> 1),
                             (int)(y & 1), dp_face(s->st[s->pid[c]].w));
    if (IS_CONT(s->pkind[c]))
        return v + (y == x ? 0.0 : cont_w(s, s->pkind[c]));
    wf = dp_face(s->fe[s->pid[c]].w);
    fo = fold_w(s, c);
    return v + ((y >> 1) == (x >> 1) ? 0.0 : wf) +
           ((y & 1) == (x & 1) ? fo : 0.0);
}

/* Node c's state given its parent's (st[]): a line edge's is fixed, a
 * root's and the others' the best (ties: the lowest). */
static size_t best_state(const hs *s, uint32_t c, const uint32_t *st)
{
    size_t K2 = 2 * s->K, y, by = 0;
    uint32_t u = s->par[c];
    double best = INFINITY;
    if (u == UINT32_MAX) {
        vmin(s->up + (size_t)c * K2, K2, &by);
    } else if (s->pkind[c] == E_LINE) {
        double lc;
        long v = across(s, s->pid[c], (int)(1 - (c & 1)), (long)st[u], &lc);
        by = v >= 0 ? (size_t)v : 0;
    } else {
        for (y = 0; y < K2; y++) {
            double v = child_cost(s, c, st[u], y);
            if (v < best - 1e-9)
                best = v, by = y;
        }
    }
    return by;
}

/* One best assignment, consistent along every forest edge (after
 * solve_pass: up[] holds each subtree's costs): roots take their best
 * state, each child the best given its parent's (ties: the lowest);
 * bands into nb.  decode() takes each node's best alone, which may mix
 * two equally good solutions of a component no evidence anchors. */
static void decode_joint(hs *s, long *nb, uint32_t *st)
{
    size_t i;
    for (i = 0; s->order[i] != UINT32_MAX; i++) {
        uint32_t c = s->order[i];
        st[c] = (uint32_t)best_state(s, c, st);
        nb[c] = (long)(st[c] >> 1);
    }
}

/* Line l's gap: best cost of any other height minus the best cost (after
 * solve_pass, msg[c] holds everything but c's subtree with c's parent in
 * each state).  *hbest gets the best height (a band index). */
static double line_gap(const hs *s, size_t l, double *H, long *hbest)
{
    size_t K2 = 2 * s->K;
    uint32_t c =
        s->par[2 * l] == 2 * l + 1 ? (uint32_t)(2 * l) : (uint32_t)(2 * l + 1);
    const double *uc = s->up + (size_t)c * K2, *pre = s->msg + (size_t)c * K2;
    double b1 = INFINITY, b2 = INFINITY;
    long x, h1 = 0;
    *hbest = -1;
    if (s->par[c] == UINT32_MAX || s->pkind[c] != E_LINE)
        return 0.0;
    for (x = 0; x <= (long)s->K; x++)
        H[x] = INFINITY;
    for (x = 0; x < (long)K2; x++) {
        double lc, v;
        long y = across(s, l, (int)(1 - (c & 1)), x, &lc), h;
        if (y < 0)
            continue;
        h = (x >> 1) > (y >> 1) ? (x >> 1) : (y >> 1);
        v = pre[x] + lc + uc[y];
        H[h] = v < H[h] ? v : H[h];
    }
    for (x = 0; x <= (long)s->K; x++)
        if (H[x] < b1)
            b1 = H[x], h1 = x;
    for (x = 0; x <= (long)s->K; x++)
        if (x != h1 && H[x] < b2)
            b2 = H[x];
    *hbest = h1;
    return b2 - b1;
}

/* ---- results ---- */

static void mark_abs(hs *s)
{
    size_t i;
    for (i = 0; i < s->C; i++)
        if (s->nknown[i] || s->wlab[i] > 0)
            s->comp_abs[s->comp[2 * i]] = 1;
    for (i = 0; i < s->nun; i++) {
        uint32_t c = s->comp[(size_t)s->un[4 * i]];
        if (c != UINT32_MAX)
            s->comp_abs[c] = 1;
    }
}

/* Whether the evidence alone decides chunk c (the priors agree). */
static int decided(const hs *s, size_t c)
{
    return s->gap[c] > GAP_EPS && s->band[c] == s->band_prior[c];
}

/* What chunk c says: 0 undecided, else its source and confidence. */
static int chunk_verdict(const hs *s, size_t c, int *src, double *conf)
{
    double gA = s->gap_prior[c], gB = s->gap[c];
    long h = s->band_prior[c] + s->kofs;
    if (!s->comp_abs[s->comp[2 * c]] || (s->contra && s->contra[c]))
        return 0;
    if (gB > GAP_EPS && s->band[c] == s->band_prior[c]) {
        *src = s->nknown[c] && (double)h == s->lknown[c]   ? TD_HS_KNOWN
               : s->wlab[c] > 0 && lab_conf(s, c, h) > 0 ? TD_HS_LABEL
                                                         : TD_HS_SOLVED;
        *conf = *src == TD_HS_KNOWN ? 1.0 : 1.0 - exp(-gB / CONF_SCALE);
        if (*src == TD_HS_SOLVED &&
            td_faces_line_length(s->fx, td_faces_chunk_line(s->fx, c)) <
                SHORT_SURE)
            *conf = fmin(*conf, SHORT_CONF);
        if (s->doubt && s->doubt[c]) /* its own faces say otherwise */
            *conf = fmin(*conf, SHORT_CONF);
        return 1;
    }
    if (gA > GAP_EPS) {
        *src = TD_HS_ASSUMED;
        *conf = 0.5 * (1.0 - exp(-gA / W_SUMMIT));
        return 1;
    }
    return 0;
}

/* A run of chunks of one line with one height. */
typedef struct run {
    size_t c0, m; /* first chunk, count (wrapping on closed lines) */
    long h;       /* band index */
    int decided;
    size_t nsrc[5]; /* chunks per source */
    double conf;    /* mean over its chunks (undecided: 0) */
    int doubt;      /* a chunk of it is in doubt (hs.doubt) */
} run;

/* Runs of line l's chunks; undecided chunks join the run before them (or
 * the first decided one).  Returns how many (at most m) into r. */
static size_t line_runs(const hs *s, size_t c0, size_t m, int closed, run *r)
{
    size_t k, n = 0, first = m;
    for (k = 0; k < m; k++) {
        int src;
        double conf;
        if (chunk_verdict(s, c0 + k, &src, &conf)) {
            if (first == m)
                first = k;
            if (n == 0 || r[n - 1].h != s->band_prior[c0 + k]) {
                memset(&r[n], 0, sizeof r[n]);
                r[n].c0 = c0 + k;
                r[n].h = s->band_prior[c0 + k];
                r[n++].decided = 1;
            }
            r[n - 1].nsrc[src]++;
            r[n - 1].conf += conf;
            r[n - 1].doubt |= s->doubt && s->doubt[c0 + k];
        }
        if (n > 0)
            r[n - 1].m = c0 + k + 1 - r[n - 1].c0;
    }
    if (n == 0) {
        memset(r, 0, sizeof *r);
        r->c0 = c0;
        r->m = m;
        return 1;
    }
    /* the undecided chunks before the first decided one */
    if (closed && n > 1 && r[0].h == r[n - 1].h) { /* wrap: one run */
        r[0].c0 = r[n - 1].c0;
        r[0].m += r[n - 1].m + first;
        for (k = 0; k < 5; k++)
            r[0].nsrc[k] += r[n - 1].nsrc[k];
        r[0].conf += r[n - 1].conf;
        r[0].doubt |= r[n - 1].doubt;
        n--;
    } else if (closed && n > 1) {
        r[n - 1].m += first; /* wraps round to the first run */
    } else {
        r[0].c0 = c0;
        r[0].m += first;
    }
    if (n == 1 && closed) {
        r[0].c0 = c0;
        r[0].m = m;
    }
    for (k = 0; k < n; k++)
        r[k].conf /= (double)r[k].m;
    return n;
}

static void apply_run(const hs *s, td_line *l, const run *r)
{
    size_t tot = 0, k;
    l->has_height = 0;
    l->hsource = TD_HS_NONE;
    l->confidence = 0;
    if (!r->decided) {
        l->why = "undecided: the evidence allows more than one height here "
                 "(add --known on or next to it)";
        return;
    }
    for (k = 0; k < 5; k++)
        tot += r->nsrc[k];
    l->hsource = r->nsrc[TD_HS_KNOWN]                 ? TD_HS_KNOWN
                 : r->nsrc[TD_HS_LABEL]               ? TD_HS_LABEL
                 : 2 * (r->nsrc[TD_HS_SOLVED]) >= tot ? TD_HS_SOLVED
                                                      : TD_HS_ASSUMED;
    /* a known line whose own faces say otherwise (it ran onto another
       contour away from the known point) is not sure all along */
    l->confidence =
        l->hsource == TD_HS_KNOWN ? (r->doubt ? SHORT_CONF : 1.0) : r->conf;
    l->has_height = 1;
    l->height = s->p->base + (double)(r->h + s->kofs) * s->p->interval;
    l->why = NULL;
}

/* A new line with vertices [k0, k1) of l (wrapping), for a run. */
static int piece(const td_line *l, size_t k0, size_t k1, td_line *out,
                 td_ctx *cx)
{
    size_t n = (k1 + l->n - k0) % l->n, k;
    if (n == 0)
        n = l->n;
    memset(out, 0, sizeof *out);
    out->xy = td_malloc(2 * (n + 1) * sizeof *out->xy, cx);
    if (!out->xy)
        return TD_ENOMEM;
    for (k = 0; k < n; k++) {
        size_t v = (k0 + k) % l->n;
        out->xy[2 * k] = l->xy[2 * v];
        out->xy[2 * k + 1] = l->xy[2 * v + 1];
    }
    if (!l->closed || k1 != k0) { /* the next piece's first vertex too */
        size_t v = k1 % l->n;
        if (l->closed || k1 < l->n) {
            out->xy[2 * n] = l->xy[2 * v];
            out->xy[2 * n + 1] = l->xy[2 * v + 1];
            n++;
        }
    }
    out->n = out->cap = n;
    out->edge = l->edge;
    out->width = l->width;
    out->ink = l->ink;
    out->parent = -1;
    return 0;
}

/* Give every line its height; lines whose chunks disagree are cut where
 * the height changes (the pieces after the first get new ids). */
static const char short_why[] = "shorter than 12 px: not labelled";

static int set_lines(hs *s, td_ctx *cx)
{
    td_lines *ls = s->ls;
    td_line *nv = NULL;
    run *r = NULL;
    size_t i, n = 0, cap = ls->n + 16, k, maxm = 1;
    long next_id = 0;
    for (i = 0; i < ls->n; i++) {
        size_t c0, m = td_faces_used(s->fx, i) ? line_chunks(s, i, &c0) : 0;
        maxm = m > maxm ? m : maxm;
        next_id = ls->v[i].id >= next_id ? ls->v[i].id + 1 : next_id;
    }
    if (!(r = td_malloc((maxm + 1) * sizeof *r, cx)) ||
        !(nv = td_malloc(cap * sizeof *nv, cx))) {
        free(r);
        return TD_ENOMEM;
    }
    for (i = 0; i < ls->n; i++) {
        td_line *l = &ls->v[i];
        size_t c0, m, nr;
        if (!td_faces_used(s->fx, i)) {
            l->has_height = 0;
            l->hsource = TD_HS_NONE;
            l->why = short_why;
            nv[n++] = *l;
            continue;
        }
        m = line_chunks(s, i, &c0);
        nr = line_runs(s, c0, m, l->closed, r);
        if (nr == 1) {
            apply_run(s, l, &r[0]);
            nv[n++] = *l;
            continue;
        }
        s->rep->split++;
        if (n + nr > cap) {
            td_line *t = realloc(nv, (cap = 2 * (n + nr)) * sizeof *nv);
            if (!t)
                goto nomem;
            nv = t;
        }
        for (k = 0; k < nr; k++) {
            size_t a = td_faces_chunk_first(s->fx, r[k].c0);
            size_t b = td_faces_chunk_first(s->fx, r[(k + 1) % nr].c0);
            if (!l->closed && k + 1 == nr)
                b = l->n;
            if (piece(l, a, b, &nv[n], cx) != 0)
                goto nomem;
            nv[n].id = k == 0 ? l->id : next_id++;
            apply_run(s, &nv[n++], &r[k]);
        }
        l->why = "cut"; /* its vertices are freed once all is done */
    }
    for (i = 0; i < ls->n; i++)
        if (ls->v[i].why && !strcmp(ls->v[i].why, "cut"))
            free(ls->v[i].xy);
    free(ls->v);
    ls->v = nv;
    ls->n = n;
    ls->cap = cap;
    free(r);
    return 0;
nomem:
    /* ls is whole; free the pieces made so far (their own vertices, the
     * lines not cut share theirs with ls) */
    for (k = 0; k < n; k++) {
        size_t j;
        int shared = 0;
        for (j = 0; j < ls->n && !shared; j++)
            shared = nv[k].xy == ls->v[j].xy;
        if (!shared)
            free(nv[k].xy);
    }
    for (i = 0; i < ls->n; i++)
        if (ls->v[i].why && !strcmp(ls->v[i].why, "cut"))
            ls->v[i].why = NULL;
    free(nv);
    free(r);
    return td_seterr(cx, TD_ENOMEM, "label: out of memory");
}

static int cmp_w_desc(const void *pa, const void *pb)
{
    const double *a = pa, *b = pb;
    return (a[0] < b[0]) - (a[0] > b[0]);
}

/* Face edges the solution breaks: leaks or merged lines; all counted, the
 * five strongest named when they are (probe weight 8 and up: a stray
 * probe through a gap is not worth a warning). */
static int report_conflicts(hs *s, const long *node_band, td_ctx *cx)
{
    size_t i, n = 0, k;
    double *v = td_malloc((s->nce + 1) * 2 * sizeof *v, cx);
    double *kb = td_calloc(2 * s->C + 1, sizeof *kb, cx);
    if (!v || !kb || (!s->doubt && !(s->doubt = td_calloc(s->C + 1, 1, cx)))) {
        free(v), free(kb);
        return TD_ENOMEM;
    }
    for (i = 0; i < s->nce; i++) {
        const cedge *e = &s->ce[i];
        int broken = node_band[e->a] != node_band[e->b];
        if (e->kind == E_FACE) { /* kept and broken weight per chunk */
            kb[2 * (e->a / 2) + broken] += e->w;
            kb[2 * (e->b / 2) + broken] += e->w;
        }
        if (e->kind == E_FACE && !s->intree[i] && broken) {
            v[2 * n] = e->w;
            v[2 * n++ + 1] = (double)e->id;
        }
    }
    for (i = 0; i < s->C; i++)
        s->doubt[i] =
            kb[2 * i + 1] >= DOUBT_SHARE * (kb[2 * i] + kb[2 * i + 1]);
    free(kb);
    qsort(v, n, 2 * sizeof *v, cmp_w_desc);
    s->rep->conflicts = n;
    for (k = 0; k < n && k < 5 && v[2 * k] >= 8.0; k++) { /* 16 px and up */
        const td_face_edge *e = &s->fe[(size_t)v[2 * k + 1]];
        td_label_warn(s->rep,
                      "lines %ld and %ld border one face (%g probes, "
                      "near %.0f,%.0f) but differ by %ld intervals: a gap or "
                      "two contours traced as one there",
                      s->ls->v[td_faces_chunk_line(s->fx, e->a / 2)].id,
                      s->ls->v[td_faces_chunk_line(s->fx, e->b / 2)].id,
                      (double)e->w, e->x, e->y,
                      labs(node_band[e->a] - node_band[e->b]));
    }
    free(v);
    return 0;
}

/* Known points the solve overrode (before set_lines: ids still the
 * chunks' lines). */
static void report_known(hs *s)
{
    size_t c;
    for (c = 0; c < s->C; c++) {
        const td_line *l = &s->ls->v[td_faces_chunk_line(s->fx, c)];
        long h = s->band_prior[c] + s->kofs;
        double x, y;
        if (!s->nknown[c] || (double)h == s->lknown[c])
            continue;
        td_label_where(l, &x, &y);
        td_label_warn(s->rep,
                      "known height %g of line %ld (near %.0f,%.0f) "
                      "contradicts the other evidence; the solve gives %g",
                      s->p->base + s->lknown[c] * s->p->interval, l->id, x, y,
                      s->p->base + (double)h * s->p->interval);
        s->rep->known_broken++;
    }
}

/* The best total cost of the last pass: the smallest root belief summed
 * over the components. */
static double total_cost(const hs *s)
{
    size_t K2 = 2 * s->K, v;
    double t = 0;
    for (v = 0; v < s->V; v++)
        if (s->par[v] == UINT32_MAX && s->comp[v] == v)
            t += vmin(s->up + v * K2, K2, NULL);
    return t;
}

/* One dynamic-programming pass; per chunk its gap and best height. */
static void run_pass(hs *s, int priors, double *gap, long *band, double *H)
{
    size_t c;
    s->priors = priors;
    solve_pass(s);
    for (c = 0; c < s->C; c++)
        gap[c] = line_gap(s, c, H, &band[c]);
}

static int alloc_all(hs *s, td_ctx *cx)
{
    size_t C = s->C, V = s->V;
    s->lknown = td_calloc(C + 1, sizeof *s->lknown, cx);
    s->nknown = td_calloc(C + 1, sizeof *s->nknown, cx);
    s->llab = td_calloc(NLAB * (C + 1), sizeof *s->llab, cx);
    s->wlab = td_calloc(C + 1, sizeof *s->wlab, cx);
    s->clab = td_calloc(NLAB * (C + 1), sizeof *s->clab, cx);
    s->idx = td_calloc(C + 1, 1, cx);
    s->ilen = td_calloc(C + 1, sizeof *s->ilen, cx);
    s->up_cost = td_calloc(V + 1, sizeof *s->up_cost, cx);
    s->up_prior = td_calloc(V + 1, sizeof *s->up_prior, cx);
    s->hole = td_calloc(V + 1, 1, cx);
    s->ring = td_calloc(V + 1, 1, cx);
    s->uf = td_calloc(V + 1, sizeof *s->uf, cx);
    s->comp = td_calloc(V + 1, sizeof *s->comp, cx);
    s->par = td_calloc(V + 1, sizeof *s->par, cx);
    s->order = td_calloc(V + 1, sizeof *s->order, cx);
    s->pkind = td_calloc(V + 1, sizeof *s->pkind, cx);
    s->pid = td_calloc(V + 1, sizeof *s->pid, cx);
    s->adj_start = td_calloc(V + 2, sizeof *s->adj_start, cx);
    s->compdepth = td_calloc(V + 1, sizeof *s->compdepth, cx);
    s->comp_abs = td_calloc(V + 1, 1, cx);
    s->band = td_calloc(C + 1, sizeof *s->band, cx);
    s->band_prior = td_calloc(C + 1, sizeof *s->band_prior, cx);
    s->gap = td_calloc(C + 1, sizeof *s->gap, cx);
    s->gap_prior = td_calloc(C + 1, sizeof *s->gap_prior, cx);
    if (!s->lknown || !s->nknown || !s->llab || !s->wlab || !s->clab ||
        !s->idx || !s->ilen || !s->up_cost || !s->up_prior || !s->hole ||
        !s->ring || !s->uf || !s->comp || !s->par || !s->order || !s->pkind ||
        !s->pid || !s->adj_start || !s->compdepth || !s->comp_abs || !s->band ||
        !s->band_prior || !s->gap || !s->gap_prior)
        return TD_ENOMEM;
    return 0;
}

static void free_all(hs *s)
{
    free(s->lknown), free(s->nknown), free(s->idx), free(s->ilen);
    free(s->llab), free(s->wlab), free(s->clab);
    free(s->up_cost), free(s->up_prior), free(s->hole), free(s->ring);
    free(s->uf);
    free(s->rnear), free(s->contra), free(s->doubt), free(s->same),
        free(s->arms), free(s->gaps);
    free(s->comp);
    free(s->par), free(s->order), free(s->pkind), free(s->pid);
    free(s->adj_start), free(s->adj), free(s->intree), free(s->compdepth);
    free(s->comp_abs), free(s->band), free(s->band_prior), free(s->gap);
    free(s->gap_prior), free(s->un), free(s->unx), free(s->own.up);
    free(s->own.msg), free(s->own.down);
    free(s->ce); /* fx and fe belong to the caller, and so may dp */
}

/* Which side nodes any face edge touches (a ring's inside with none holds
 * nothing). */
static int touched_nodes(const hs *s, unsigned char **out, td_ctx *cx)
{
    size_t i;
    unsigned char *t = td_calloc(s->V + 1, 1, cx);
    if (!t)
        return TD_ENOMEM;
    for (i = 0; i < s->nfe; i++)
        t[s->fe[i].a] = t[s->fe[i].b] = 1;
    *out = t;
    return 0;
}

/* Small rings at the level of the line next to them (ours; measured on
 * the true lines of four sheets drawn from real DEMs, docs/label.md): a
 * ring with nothing inside, within RFOLD_NEAR px of another line, or
 * within RFOLD_FAR px with no third line within 2 d + 3 px of it, is a
 * bump or a dip of that line's contour (Elkhorn 352 of 352, the others
 * 14 of 14); further out, where contours crowd, it is as often the next
 * level.  Such a ring whose height only the priors decide takes the
 * line's height afterwards (follow_rings): as a prior in the solve it
 * would also pull the line the way the ring's own summit prior points,
 * right for the ring about as often as wrong. */
#define RFOLD_NEAR 3.0
#define RFOLD_FAR 5.0
#define RFOLD_LINES 16
static long ring_next(const hs *s, size_t i)
{
    const td_line *l = &s->ls->v[i];
    long nodes[RFOLD_LINES], bn[RFOLD_LINES];
    double dist[RFOLD_LINES], bd[RFOLD_LINES], d1 = INFINITY, d2 = INFINITY;
    size_t k, bl = 0, bline[RFOLD_LINES];
    int j, q, nb = 0;
    for (k = 0; k < l->n; k++) {
        int n =
            td_faces_near(s->fx, l->xy[2 * k], l->xy[2 * k + 1],
                          2 * RFOLD_FAR + 3, (long)i, nodes, dist, RFOLD_LINES);
        for (j = 0; j < n; j++) {
            size_t lj = td_faces_chunk_line(s->fx, (size_t)nodes[j] / 2);
            for (q = 0; q < nb && bline[q] != lj; q++)
                ;
            if (q == nb && nb == RFOLD_LINES)
                continue;
            if (q == nb)
                bd[nb] = INFINITY, bline[nb++] = lj;
            if (dist[j] < bd[q])
                bd[q] = dist[j], bn[q] = nodes[j];
        }
    }
    for (q = 0; q < nb; q++)
        if (bd[q] < d1)
            d1 = bd[q], bl = (size_t)q;
    for (q = 0; q < nb; q++)
        if ((size_t)q != bl && bd[q] < d2)
            d2 = bd[q];
    if (d1 < RFOLD_NEAR || (d1 < RFOLD_FAR && d2 >= 2 * d1 + 3))
        return bn[bl] / 2;
    return -1;
}

static int setup_ring_next(hs *s, const unsigned char *touched, td_ctx *cx)
{
    size_t i, c0;
    if (!(s->rnear = td_malloc((s->C + 1) * sizeof *s->rnear, cx)))
        return TD_ENOMEM;
    for (i = 0; i < s->C; i++)
        s->rnear[i] = -1;
    for (i = 0; i < s->N && !s->cost_only; i++) /* only set_lines uses it */
        if (td_faces_used(s->fx, i) && s->ls->v[i].closed &&
            line_chunks(s, i, &c0) == 1 &&
            !touched[2 * c0 + inner_side(&s->ls->v[i])])
            s->rnear[c0] = ring_next(s, i);
    return 0;
}

/* After the solve: a ring of setup_ring_next's whose height only the
 * priors decided takes its line's (still assumed). */
static void follow_rings(hs *s)
{
    size_t c;
    for (c = 0; c < s->C; c++) {
        long a = s->rnear[c];
        if (a < 0 || (s->gap[c] > GAP_EPS && s->band[c] == s->band_prior[c]))
            continue; /* no line, or decided without the priors */
        if (!(s->gap_prior[a] > GAP_EPS) || !s->comp_abs[s->comp[2 * c]] ||
            s->comp[2 * c] != s->comp[2 * (size_t)a])
            continue;
        s->band_prior[c] = s->band_prior[a];
        s->gap_prior[c] = s->gap_prior[a];
        s->gap[c] = 0.0;
    }
}

/* Heights the lines around contradict (ours).  A straight probe that
 * crosses j lines can see the height change by at most j intervals:
 * every line is one level, and the ground between two lines lies within
 * one interval of them (j + SW_SLACK here: a gap in a line or a contour
 * not traced lets a probe pass one unseen).  From an assumed chunk,
 * probes every SW_STEP px on both sides (at most SW_MAX a side) run
 * through up to SW_HITS lines; a line met j lines out whose height is
 * surer (a larger gap under the priors, or decided by the evidence) and
 * more than j + SW_SLACK intervals away counts against the chunk.  A chunk with
 * at least SW_MIN such probes, and SW_SHARE of those that met a surer line,
 * gets no height: on the crowded Front Range sheet regions cut off by blobs of
 * ink came out 7-10 intervals off, which the DEM cannot take. */
#define SW_STEP 8.0
#define SW_MAX 32
#define SW_HITS 3
#define SW_MIN 3
#define SW_SHARE 0.3
#define SW_SLACK 2 /* contours missed between (gaps, untraced lines) */
static double sureness(const hs *s, size_t c)
{
    return decided(s, c) ? INFINITY : s->gap_prior[c];
}

static int has_height(const hs *s, size_t c)
{
    int src;
    double conf;
    return chunk_verdict(s, c, &src, &conf);
}

static void probe_chunk(const hs *s, size_t i, size_t c, int *viol, int *met)
{
    const td_line *l = &s->ls->v[i];
    double next = 0.5 * SW_STEP, pos = 0, me = sureness(s, c);
    long h = s->band_prior[c];
    size_t k;
    int n[2] = {0, 0};
    for (k = 0; k + 1 < l->n + (size_t)l->closed; k++) {
        size_t k1 = (k + 1) % l->n;
        double ax = l->xy[2 * k], ay = l->xy[2 * k + 1];
        double tx = l->xy[2 * k1] - ax, ty = l->xy[2 * k1 + 1] - ay;
        double L = sqrt(tx * tx + ty * ty); /* not hypot: see lines.c */
        if (td_faces_chunk_at(s->fx, i, k) != (long)c || !(L > 0)) {
            pos += L;
            continue;
        }
        for (; next <= pos + L; next += SW_STEP) {
            double x = ax + (next - pos) / L * tx,
                   y = ay + (next - pos) / L * ty;
            int side;
            for (side = 0; side < 2; side++) {
                double nx = (side ? -1 : 1) * ty / L,
                       ny = (side ? 1 : -1) * tx / L;
                double px = x, py = y, t;
                long skip = (long)i, node;
                int j, bad = 0, sure = 0;
                if (n[side] >= SW_MAX)
                    continue;
                n[side]++;
                for (j = 1; j <= SW_HITS; j++) {
                    size_t cm;
                    node = td_faces_ray(s->fx, px, py, nx, ny, skip, 1.5, &t);
                    if (node < 0)
                        break;
                    cm = (size_t)node / 2;
                    if (has_height(s, cm) && sureness(s, cm) > me) {
                        sure = 1;
                        bad |= labs(s->band_prior[cm] - h) > j + SW_SLACK;
                    }
                    px += nx * t, py += ny * t;
                    skip = (long)td_faces_chunk_line(s->fx, cm);
                }
                *met += sure;
                *viol += bad;
            }
        }
        pos += L;
    }
}

static int sandwich_check(hs *s, td_ctx *cx)
{
    size_t i, c0, m, k, nulled = 0;
    unsigned char *flag = td_calloc(s->C + 1, 1, cx);
    if (!flag || !(s->contra = td_calloc(s->C + 1, 1, cx))) {
        free(flag);
        return TD_ENOMEM;
    }
    for (i = 0; i < s->N; i++) {
        if (!td_faces_used(s->fx, i))
            continue;
        m = line_chunks(s, i, &c0);
        for (k = 0; k < m; k++) {
            size_t c = c0 + k;
            int viol = 0, met = 0;
            if (!has_height(s, c) || decided(s, c))
                continue;
            probe_chunk(s, i, c, &viol, &met);
            flag[c] = viol >= SW_MIN && viol >= SW_SHARE * met;
        }
    }
    for (c0 = 0; c0 < s->C; c0++) /* flagged after all were probed */
        nulled += s->contra[c0] = flag[c0];
    free(flag);
    if (nulled && !s->cost_only)
        td_label_warn(s->rep,
                      "%zu assumed line height%s left out: the "
                      "lines around contradict %s (more intervals apart "
                      "than lines between)",
                      nulled, nulled == 1 ? "" : "s",
                      nulled == 1 ? "it" : "them");
    return 0;
}

/* Two pieces of one traced line that the scanner cut at a blob of ink
 * (widecut.h; ours): each wall's first vertex is where the piece before
 * it ends, its last where the piece after it starts.  On the crowded
 * Front Range sheet such pieces lie on one contour in 88 % of the walls
 * (681 of 777), in 97 % where the wall runs straight (chord at least
 * SAME_STRAIGHT of its length: 637 of 657) and in none where it turns
 * back (0 of 66: the line hopped to the next contour in the blob).  For
 * the straight ones a continuity edge (E_SAME: the same height, a prior
 * of W_SAME) ties the regions the blobs wall off to the rest, which the
 * priors alone had set up to 45 intervals off. */
static int end_used(size_t i, const void *u)
{
    return td_faces_used((const td_faces *)u, i);
}

/* The side node 0 of the chunk at the first end (of ends, sorted) at (x,
 * y) that has one, and whether it is its line's last vertex; -1 when
 * none. */
static long node_at(const hs *s, const td_line_end *ends, size_t n, double x,
                    double y, int *last)
{
    size_t k;
    for (k = td_line_ends_at(ends, n, x, y);
         k < n && ends[k].x == x && ends[k].y == y; k++) {
        const td_line *l = &s->ls->v[ends[k].line];
        long c =
            td_faces_chunk_at(s->fx, ends[k].line, ends[k].last ? l->n - 1 : 0);
        if (c >= 0) {
            *last = ends[k].last;
            return 2 * c;
        }
    }
    return -1;
}

/* Whether lines a and b, ending at the two ends of one wall, leave it the
 * same way: the wall is the tip of a V (a hairpin cut, or a blob's stretch
 * where a line turned back), not a stretch across a blob that the line
 * ran on through. */
static int turned_back(const td_line *a, int alast, const td_line *b, int blast)
{
    double ua[2], ub[2];
    return td_line_end_dir(a, alast, ARM_ARC, &ua[0], &ua[1]) &&
           td_line_end_dir(b, blast, ARM_ARC, &ub[0], &ub[1]) &&
           ua[0] * ub[0] + ua[1] * ub[1] > ARM_COS;
}

static int cmp_u64(const void *pa, const void *pb)
{
    uint64_t a = *(const uint64_t *)pa, b = *(const uint64_t *)pb;
    return (a > b) - (a < b);
}

/* the key of a pair of line indices, either order */
static uint64_t line_pair(size_t a, size_t b)
{
    return a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a;
}

/* hs.arms from the na line pairs in arm (freed here): the face edges
 * between the two lines of a pair.  0 or TD_ENOMEM. */
static int mark_arms(hs *s, size_t *arm, size_t na, td_ctx *cx)
{
    uint64_t *key = na ? td_malloc(na * sizeof *key, cx) : NULL;
    size_t i;
    if (na && (!key || !(s->arms = td_calloc(s->nfe + 1, 1, cx)))) {
        free(arm), free(key);
        return TD_ENOMEM;
    }
    for (i = 0; i < na; i++)
        key[i] = line_pair(arm[2 * i], arm[2 * i + 1]);
    free(arm);
    if (!na)
        return 0;
    qsort(key, na, sizeof *key, cmp_u64);
    for (i = 0; i < s->nfe; i++) {
        uint64_t k = line_pair(td_faces_chunk_line(s->fx, s->fe[i].a / 2),
                               td_faces_chunk_line(s->fx, s->fe[i].b / 2));
        s->arms[i] = bsearch(&k, key, na, sizeof k, cmp_u64) != NULL;
    }
    free(key);
    return 0;
}

static int same_pieces(hs *s, td_ctx *cx)
{
    const td_lines *w = s->p->walls;
    td_line_end *v;
    size_t i, n = 0, *arm, na = 0;
    if (!w || !w->n)
        return 0;
    if (td_line_ends(s->ls, end_used, s->fx, &v, &n, cx) != 0 ||
        !(s->same = td_malloc((2 * w->n + 1) * sizeof *s->same, cx))) {
        free(v);
        return TD_ENOMEM;
    }
    if (!(arm = td_malloc((2 * w->n + 1) * sizeof *arm, cx))) {
        free(v);
        return TD_ENOMEM;
    }
    for (i = 0; i < w->n; i++) {
        const td_line *l = &w->v[i];
        long a, b;
        int alast = 0, blast = 0;
        size_t la, lb;
        if (l->n < 2 ||
            (a = node_at(s, v, n, l->xy[0], l->xy[1], &alast)) < 0 ||
            (b = node_at(s, v, n, l->xy[2 * l->n - 2], l->xy[2 * l->n - 1],
                         &blast)) < 0 ||
            a / 2 == b / 2)
            continue;
        la = td_faces_chunk_line(s->fx, (size_t)a / 2);
        lb = td_faces_chunk_line(s->fx, (size_t)b / 2);
        if (la != lb &&
            turned_back(&s->ls->v[la], alast, &s->ls->v[lb], blast)) {
            arm[2 * na] = la, arm[2 * na++ + 1] = lb;
            continue;
        }
        if (hypot(l->xy[2 * l->n - 2] - l->xy[0],
                  l->xy[2 * l->n - 1] - l->xy[1]) <
            SAME_STRAIGHT * td_line_length(l))
            continue;
        /* travelling on from a's end into b: the same sides when a ends
           there and b starts, else swapped */
        s->same[2 * s->nsame] = (uint32_t)a;
        s->same[2 * s->nsame++ + 1] = (uint32_t)b + (uint32_t)(alast == blast);
    }
    free(v);
    return mark_arms(s, arm, na, cx);
}

/* Free ends that continue each other across a gap (endpair.h; ours): the
 * two pieces are one contour.  A continuity edge (E_GAP, both passes:
 * W_GAP to break, in the forest's order with GAP_KEY) between the chunks
 * at the ends, sides matched as in same_pieces.  Truth lines cut where a
 * road and the streams run over them (Orkhon, new print): 532 pairs, 528
 * on one contour; the share of the length right went from 0.62 to 0.94
 * (the pieces beyond the road had hung on the rest by a leak).  Where
 * contours crowd, a pair farther apart than GAP_SPACING contour spacings
 * is as often two contours as one: not tied. */
static int gap_pairs(hs *s, td_ctx *cx)
{
    td_end_pair *v;
    size_t i, n;
    double px = s->p->gap_pairs < 0 ? (s->p->colour ? TD_GAP_PAIRS_COLOUR : 0)
                                    : s->p->gap_pairs,
           D = 0; /* the contour spacing */
    if (!(px > 0))
        return 0;
    if (sheet_spacing(s, &D, cx) != 0)
        return TD_ENOMEM;
    if (td_end_pairs(s->ls, end_used, s->fx, s->p->w, s->p->h, px, &v, &n,
                     cx) != 0)
        return TD_ENOMEM;
    if (!(s->gaps = td_malloc((2 * n + 1) * sizeof *s->gaps, cx))) {
        free(v);
        return TD_ENOMEM;
    }
    for (i = 0; i < n; i++) {
        const td_line *la = &s->ls->v[v[i].a], *lb = &s->ls->v[v[i].b];
        long a = td_faces_chunk_at(s->fx, v[i].a, v[i].alast ? la->n - 1 : 0),
             b = td_faces_chunk_at(s->fx, v[i].b, v[i].blast ? lb->n - 1 : 0);
        if (a < 0 || b < 0 || a == b || v[i].cost > GAP_COST ||
            (D > 0 && v[i].d > GAP_SPACING * D))
            continue;
        { /* the chord between the ends crosses no other line */
            const td_end_pair *q = &v[i];
            double t = 0;
            long hit =
                q->d > 1.0
                    ? td_faces_ray(s->fx, q->ax, q->ay, (q->bx - q->ax) / q->d,
                                   (q->by - q->ay) / q->d, (long)q->a, 1.5, &t)
                    : -1;
            if (hit >= 0 && t < q->d - 1.5 &&
                td_faces_chunk_line(s->fx, (size_t)hit / 2) != q->b)
                continue;
        }
        /* ends in contour ink left untraced: a merge, not a break */
        if (td_faces_untraced_between(s->fx, v[i].ax, v[i].ay, v[i].bx, v[i].by,
                                      GAP_CLEAR))
            continue;
        /* travelling on from a's end into b: the same sides when a ends
           there and b starts, else swapped */
        s->gaps[2 * s->ngaps] = (uint32_t)(2 * a);
        s->gaps[2 * s->ngaps++ + 1] =
            (uint32_t)(2 * b) + (uint32_t)(v[i].alast == v[i].blast);
    }
    free(v);
    return 0;
}

/* ---- local search over the whole graph (ours) ----
 *
 * The forest drops the face edges that close cycles; where lines are
 * broken or merged the best bands on the forest can break many of them
 * (a region folded the wrong way where its only tie in the forest is a
 * fold).  Starting from the forest's best, every forest edge is tried
 * with its subtree moved: shifted by -2..2 bands or mirrored about its
 * parent's band (b -> 2 b_parent - b + r, r in -1..1), each move priced
 * on everything it touches: the lines in the subtree (known points,
 * labels, index widths, priors), the unary evidence on its nodes and
 * every face and continuity edge leaving it, in or out of the forest.
 * Improving moves are taken until none is left (or the work budget). */

#define NMOVE 7
static long move_band(long b, long bu, int t)
{
    static const int sh[4] = {-2, -1, 1, 2};
    return t < 4 ? b + sh[t] : 2 * bu - b + (t - 5);
}

static double edge_cost(const hs *s, const cedge *e, long ba, int da, long bb,
                        int db)
{
    if (IS_CONT(e->kind))
        return ba != bb || da != db ? cont_w(s, e->kind) : 0.0;
    if (e->kind == E_STEP)
        return step_cost(ba, da, bb, db, face_cost(s->st[e->id].w));
    if (ba != bb)
        return face_cost(s->fe[e->id].w);
    if (da == db && s->priors && nest_pair(s, e->a, e->b))
        return W_NEST;
    if (da == db && s->priors && !s->hole[e->a] && !s->hole[e->b] &&
        !arms_edge(s, e->id))
        return fold_cost(s, s->fe[e->id].w);
    return 0.0;
}

static double chunk_cost(const hs *s, size_t c, long a0, long a1)
{
    return labs(a0 - a1) != 1 ? PLINE : line_cost(s, c, a0, a1);
}

/* Add to dl[t] what moving the subtree of c (parent u; a node x is in it
 * when tin[c] <= tin[x] < tout[c]) by move t does to edge e between x
 * and y. */
static void dl_edge(const hs *s, const cedge *e, uint32_t x, uint32_t y,
                    const long *nb, const uint32_t *tin, const uint32_t *tout,
                    uint32_t c, uint32_t u, double *dl)
{
    const uint32_t n4[4] = {x, x ^ 1, y, y ^ 1};
    int in[4], t, j;
    double old = edge_cost(s, e, nb[x], nb[x ^ 1] > nb[x], nb[y],
                           nb[y ^ 1] > nb[y]);
    for (j = 0; j < 4; j++)
        in[j] = tin[n4[j]] >= tin[c] && tin[n4[j]] < tout[c];
    for (t = 0; t < NMOVE; t++) {
        long b[4];
        for (j = 0; j < 4; j++)
            b[j] = in[j] ? move_band(nb[n4[j]], nb[u], t) : nb[n4[j]];
        dl[t] += edge_cost(s, e, b[0], b[1] > b[0], b[2], b[3] > b[2]) - old;
    }
}

/* The forest in a depth-first order eul (parents first), a subtree an
 * interval: node x is in c's when tin[c] <= tin[x] < tout[c]. */
static int preorder(const hs *s, uint32_t *eul, uint32_t *tin, uint32_t *tout,
                    td_ctx *cx)
{
    size_t V = s->V, i, n = 0, k;
    uint32_t *kid = td_malloc((V + 1) * sizeof *kid, cx),
             *ks = td_calloc(V + 2, sizeof *ks, cx),
             *stk = td_malloc((V + 1) * sizeof *stk, cx);
    if (!kid || !ks || !stk) {
        free(kid), free(ks), free(stk);
        return TD_ENOMEM;
    }
    for (i = 0; i < V; i++) /* children */
        if (s->par[i] != UINT32_MAX)
            ks[s->par[i] + 1]++;
    for (i = 0; i < V; i++)
        ks[i + 1] += ks[i];
    for (i = 0; i < V; i++)
        stk[i] = ks[i];
    for (i = 0; i < V; i++)
        if (s->par[i] != UINT32_MAX)
            kid[stk[s->par[i]]++] = (uint32_t)i;
    for (i = 0; i < V; i++) {
        size_t top = 0;
        if (s->par[i] != UINT32_MAX)
            continue;
        stk[top++] = (uint32_t)i;
        while (top) {
            uint32_t u = stk[--top];
            tin[u] = (uint32_t)n;
            eul[n++] = u;
            for (k = ks[u]; k < ks[u + 1]; k++)
                stk[top++] = kid[k];
        }
    }
    for (i = V; i-- > 0;) { /* tout: end of the interval */
        uint32_t u = eul[i];
        tout[u] = tin[u] + 1;
    }
    for (i = V; i-- > 0;) {
        uint32_t u = eul[i], p = s->par[u];
        if (p != UINT32_MAX && tout[u] > tout[p])
            tout[p] = tout[u];
    }
    free(kid), free(ks), free(stk);
    return 0;
}

static double full_cost(hs *s, const long *nb);
static int improve(hs *s, long *nb, td_ctx *cx)
{
    size_t V = s->V, i, n, k;
    uint32_t *eul = NULL, *tin = NULL, *tout = NULL, *ea = NULL, *es = NULL,
             *ua = NULL, *us = NULL, *stk = NULL;
    double work = 0;
    int rc = TD_ENOMEM, sweep, moved = 1;
    if (!(eul = td_malloc((V + 1) * sizeof *eul, cx)) ||
        !(tin = td_malloc((V + 1) * sizeof *tin, cx)) ||
        !(tout = td_malloc((V + 1) * sizeof *tout, cx)) ||
        !(es = td_calloc(V + 2, sizeof *es, cx)) ||
        !(ea = td_malloc((2 * s->nce + 1) * sizeof *ea, cx)) ||
        !(us = td_calloc(V + 2, sizeof *us, cx)) ||
        !(ua = td_malloc((s->nun + 1) * sizeof *ua, cx)) ||
        !(stk = td_malloc((V + 1) * sizeof *stk, cx)) ||
        preorder(s, eul, tin, tout, cx) != 0)
        goto done;
    /* every face and continuity edge at each node; unary terms */
    for (i = 0; i < s->nce; i++)
        if (s->ce[i].kind != E_LINE)
            es[s->ce[i].a + 1]++, es[s->ce[i].b + 1]++;
    for (i = 0; i < V; i++)
        es[i + 1] += es[i];
    for (i = 0; i < V; i++)
        stk[i] = es[i];
    for (i = 0; i < s->nce; i++)
        if (s->ce[i].kind != E_LINE)
            ea[stk[s->ce[i].a]++] = (uint32_t)i,
            ea[stk[s->ce[i].b]++] = (uint32_t)i;
    for (i = 0; i < s->nun; i++)
        us[(size_t)s->un[4 * i] + 1]++;
    for (i = 0; i < V; i++)
        us[i + 1] += us[i];
    for (i = 0; i < V; i++)
        stk[i] = us[i];
    for (i = 0; i < s->nun; i++)
        ua[stk[(size_t)s->un[4 * i]]++] = (uint32_t)i;

    for (sweep = 0; sweep < SEARCH_SWEEPS && moved && work < SEARCH_WORK; sweep++) {
        moved = 0;
        for (n = 0; n < V && work < SEARCH_WORK; n++) {
            uint32_t c = eul[n], u = s->par[c];
            double dl[NMOVE] = {0};
            size_t j, bt = 0;
            int t;
            if (u == UINT32_MAX)
                continue;
#define INT(w) (tin[w] >= tin[c] && tin[w] < tout[c])
            for (j = tin[c]; j < tout[c]; j++) {
                uint32_t v = eul[j], w = v ^ 1;
                int win = INT(w);
                work += 1 + (es[v + 1] - es[v]);
                if (!(v & 1) || !win) { /* its chunk, once */
                    size_t ch = v / 2;
                    double old = chunk_cost(s, ch, nb[2 * ch], nb[2 * ch + 1]);
                    for (t = 0; t < NMOVE; t++) {
                        long b0 = 2 * ch == v || INT(2 * ch)
                                      ? move_band(nb[2 * ch], nb[u], t)
                                      : nb[2 * ch];
                        long b1 = 2 * ch + 1 == v || INT(2 * ch + 1)
                                      ? move_band(nb[2 * ch + 1], nb[u], t)
                                      : nb[2 * ch + 1];
                        dl[t] += chunk_cost(s, ch, b0, b1) - old;
                    }
                }
                for (k = us[v]; k < us[v + 1]; k++) {
                    const double *q = s->un + 4 * ua[k];
                    double old = unary_at(q, nb[v] + s->kofs);
                    for (t = 0; t < NMOVE; t++)
                        dl[t] +=
                            unary_at(q, move_band(nb[v], nb[u], t) + s->kofs) -
                            old;
                }
                for (k = es[v]; k < es[v + 1]; k++) {
                    const cedge *e = &s->ce[ea[k]];
                    uint32_t o = e->a == v ? e->b : e->a;
                    /* an edge inside keeps its cost (its ends move alike)
                       unless one end is c stepping the other way from a
                       partner left outside: counted once, from c */
                    if (INT(o) && !(v == c && !INT(c ^ 1)))
                        continue;
                    dl_edge(s, e, v, o, nb, tin, tout, c, u, dl);
                }
            }
            if (!INT(c ^ 1)) { /* c's partner stays, stepping the other
                                  way: its edges leaving the subtree */
                uint32_t w = c ^ 1;
                for (k = es[w]; k < es[w + 1]; k++) {
                    const cedge *e = &s->ce[ea[k]];
                    uint32_t o = e->a == w ? e->b : e->a;
                    if (!INT(o)) /* (those into it: counted from inside) */
                        dl_edge(s, e, w, o, nb, tin, tout, c, u, dl);
                }
            }
            for (t = 1; t < NMOVE; t++)
                if (dl[t] < dl[bt])
                    bt = (size_t)t;
            if (dl[bt] < -1e-6) {
                long bu = nb[u];
                for (j = tin[c]; j < tout[c]; j++)
                    nb[eul[j]] = move_band(nb[eul[j]], bu, (int)bt);
                moved = 1;
            }
#undef INT
        }
    }
    rc = 0;
done:
    free(eul), free(tin), free(tout), free(ea);
    free(es), free(ua), free(us), free(stk);
    return rc;
}

/* The cost of node bands nb under the whole model, with the priors:
 * every line, unary term and face or continuity edge, in the forest or
 * not. */
static double full_cost(hs *s, const long *nb)
{
    double t = 0;
    size_t c, i;
    int pri = s->priors;
    s->priors = 1;
    for (c = 0; c < s->C; c++)
        t += chunk_cost(s, c, nb[2 * c], nb[2 * c + 1]);
    for (i = 0; i < s->nun; i++)
        t += unary_at(s->un + 4 * i, nb[(size_t)s->un[4 * i]] + s->kofs);
    for (i = 0; i < s->nce; i++) {
        const cedge *e = &s->ce[i];
        if (e->kind != E_LINE)
            t += edge_cost(s, e, nb[e->a], nb[e->a ^ 1] > nb[e->a], nb[e->b],
                           nb[e->b ^ 1] > nb[e->b]);
    }
    s->priors = pri;
    return t;
}

/* The middle vertex of chunk c, its line's id into *id. */
static void chunk_mid(const hs *s, size_t c, long *id, double *x, double *y)
{
    size_t l = td_faces_chunk_line(s->fx, c),
           k0 = td_faces_chunk_first(s->fx, c),
           k1 = c + 1 < s->C && td_faces_chunk_line(s->fx, c + 1) == l
                    ? td_faces_chunk_first(s->fx, c + 1)
                    : s->ls->v[l].n - 1,
           k = (k0 + k1) / 2;
    const td_line *ln = &s->ls->v[l];
    *id = ln->id;
    *x = ln->xy[2 * k], *y = ln->xy[2 * k + 1];
}

/* The edge's part of the model under the bands b (as oracle_costs). */
static int edge_term(const hs *s, const cedge *e, const long *b)
{
    return IS_CONT(e->kind)                          ? TD_OT_CONT
           : e->kind == E_STEP || b[e->a] != b[e->b] ? TD_OT_FACE
           : nest_pair(s, e->a, e->b)                ? TD_OT_NEST
                                                     : TD_OT_FOLD;
}

/* Appends a tie to rep->oracle_ties (p->oracle_ties). */
static int add_tie(hs *s, int term, double va, double vt, size_t ca, size_t cb,
                   size_t *cap, td_ctx *cx)
{
    td_label_report *r = s->rep;
    td_oracle_tie *t;
    if (r->noracle_ties == *cap) {
        size_t nc = *cap ? 2 * *cap : 64;
        td_oracle_tie *v = realloc(r->oracle_ties, nc * sizeof *v);
        if (!v)
            return td_seterr(cx, TD_ENOMEM, "out of memory");
        r->oracle_ties = v, *cap = nc;
    }
    t = &r->oracle_ties[r->noracle_ties++];
    t->term = term, t->answer = va, t->truth = vt;
    chunk_mid(s, ca, &t->id[0], &t->x[0], &t->y[0]);
    chunk_mid(s, cb, &t->id[1], &t->x[1], &t->y[1]);
    return 0;
}

/* Benchmarks (p->oracle_ties): every edge and every line's own term that
 * the answer nb and the truth no pay differently, into rep->oracle_ties:
 * where the model prefers which (bench_heights --oracle-ties). */
static int oracle_ties(hs *s, const long *nb, const long *no, td_ctx *cx)
{
    size_t i, c, cap = 0;
    int q, rc;
    free(s->rep->oracle_ties);
    s->rep->oracle_ties = NULL, s->rep->noracle_ties = 0;
    for (i = 0; i < s->nce; i++) {
        const cedge *e = &s->ce[i];
        double va, vt;
        if (e->kind == E_LINE)
            continue;
        va = edge_cost(s, e, nb[e->a], nb[e->a ^ 1] > nb[e->a], nb[e->b],
                       nb[e->b ^ 1] > nb[e->b]);
        vt = edge_cost(s, e, no[e->a], no[e->a ^ 1] > no[e->a], no[e->b],
                       no[e->b ^ 1] > no[e->b]);
        if (fabs(va - vt) > 1e-9 &&
            (rc = add_tie(s, edge_term(s, e, va > vt ? nb : no), va, vt,
                          e->a / 2, e->b / 2, &cap, cx)) != 0)
            return rc;
    }
    for (i = 0; i < s->nun; i++) {
        size_t v = (size_t)s->un[4 * i];
        double va = unary_at(s->un + 4 * i, nb[v] + s->kofs),
               vt = unary_at(s->un + 4 * i, no[v] + s->kofs);
        if (fabs(va - vt) > 1e-9 &&
            (rc = add_tie(s, TD_OT_UNARY, va, vt, v / 2, v / 2, &cap, cx)) != 0)
            return rc;
    }
    for (c = 0; c < s->C; c++) {
        double ta[TD_OT_N] = {0}, tt[TD_OT_N] = {0};
        if (labs(nb[2 * c] - nb[2 * c + 1]) == 1)
            line_parts(s, c, nb[2 * c], nb[2 * c + 1], ta);
        if (labs(no[2 * c] - no[2 * c + 1]) == 1)
            line_parts(s, c, no[2 * c], no[2 * c + 1], tt);
        for (q = 1; q < TD_OT_N; q++)
            if (fabs(ta[q] - tt[q]) > 1e-9 &&
                (rc = add_tie(s, q, ta[q], tt[q], c, c, &cap, cx)) != 0)
                return rc;
    }
    return 0;
}

/* Benchmarks: the whole model's cost of the answer nb and of the true
 * heights (p->oracle_h, p->oracle_up; chunks of lines without one keep
 * their answer) and its parts (td_oracle_term, priced here term by term;
 * the total is full_cost's) into rep->oracle_cost: an answer that costs
 * more than the truth is the optimiser's error, one that costs less the
 * model's. */
static int oracle_costs(hs *s, const long *nb, td_ctx *cx)
{
    long *no = td_malloc((s->V + 1) * sizeof *no, cx);
    size_t c, i;
    int pass, pri = s->priors, rc;
    if (!no)
        return TD_ENOMEM;
    memcpy(no, nb, s->V * sizeof *no);
    for (c = 0; c < s->C; c++) {
        size_t l = td_faces_chunk_line(s->fx, c);
        double H = s->p->oracle_h[l];
        long L;
        if (!isfinite(H))
            continue;
        L = lround((H - s->p->base) / s->p->interval) - s->kofs;
        if (L < 1 || L >= (long)s->K)
            continue;
        no[2 * c] = s->p->oracle_up[l] ? L : L - 1;
        no[2 * c + 1] = s->p->oracle_up[l] ? L - 1 : L;
    }
    s->priors = 1;
    for (pass = 0; pass < 2; pass++) {
        const long *b = pass ? no : nb;
        double *t = s->rep->oracle_cost[pass];
        memset(t, 0, TD_OT_N * sizeof *t);
        for (c = 0; c < s->C; c++) /* (a line's sides always one band
                                        apart: no PLINE) */
            if (labs(b[2 * c] - b[2 * c + 1]) == 1)
                line_parts(s, c, b[2 * c], b[2 * c + 1], t);
        for (i = 0; i < s->nun; i++)
            t[TD_OT_UNARY] +=
                unary_at(s->un + 4 * i, b[(size_t)s->un[4 * i]] + s->kofs);
        for (i = 0; i < s->nce; i++) {
            const cedge *e = &s->ce[i];
            double v;
            if (e->kind == E_LINE)
                continue;
            v = edge_cost(s, e, b[e->a], b[e->a ^ 1] > b[e->a], b[e->b],
                          b[e->b ^ 1] > b[e->b]);
            t[edge_term(s, e, b)] += v;
        }
        t[TD_OT_TOTAL] = full_cost(s, b); /* the parts add up to it */
    }
    rc = s->p->oracle_ties ? oracle_ties(s, nb, no, cx) : 0;
    s->priors = pri;
    free(no);
    return rc;
}

/* The forest in the order of the candidates' keys, its domain and tables. */
static int forest_tables(hs *s, double **H, td_ctx *cx)
{
    size_t KV;
    int rc;
    qsort(s->ce + s->C, s->nce - s->C, sizeof *s->ce, cmp_ce);
    if ((rc = build_forest(s, cx)) != 0 || (rc = order_forest(s, cx)) != 0 ||
        (rc = set_domain(s, cx)) != 0)
        return rc;
    KV = 2 * s->K * s->V;
    free(*H);
    if (s->dp->cap < KV) {
        dp_tables *d = s->dp;
        free(d->up), free(d->msg), free(d->down);
        d->msg = d->down = NULL, d->cap = 0;
        if (!(d->up = td_malloc(KV * sizeof *d->up + 8, cx)) ||
            !(d->msg = td_malloc(KV * sizeof *d->msg + 8, cx)) ||
            !(d->down = td_malloc(KV * sizeof *d->down + 8, cx))) {
            *H = NULL;
            return TD_ENOMEM;
        }
        d->cap = KV;
    }
    s->up = s->dp->up, s->msg = s->dp->msg, s->down = s->dp->down;
    if (!(*H = td_malloc((s->K + 1) * sizeof **H, cx)))
        return TD_ENOMEM;
    return 0;
}

/* A small deterministic generator (the output may not depend on luck). */
static double unit_rand(uint64_t *st)
{
    *st = *st * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*st >> 11) / 9007199254740992.0;
}

/* The search (ours, label params search = R > 0): R forests, the first
 * in the usual order (strongest edges first), the others with every
 * edge's strength scaled by a factor between 1/e and e (a fixed
 * sequence: the result does not depend on luck); each forest's best
 * improved by improve(); the bands (absolute: band + kofs) the cheapest
 * under the whole model into bb, and the levels the final domain must
 * hold into need_lo..need_hi. */
static int search(hs *s, int R, long *bb, double **H, td_ctx *cx)
{
    double best = INFINITY;
    long *nb = td_malloc((s->V + 1) * sizeof *nb, cx);
    uint32_t *st = td_malloc((s->V + 1) * sizeof *st, cx);
    uint64_t rs = 0x9e3779b97f4a7c15ULL;
    size_t i;
    int r, rc = 0;
    if (!nb || !st) {
        free(nb), free(st);
        return TD_ENOMEM;
    }
    for (r = 0; r < R; r++) {
        double f;
        for (i = s->C; i < s->nce; i++)
            s->ce[i].key = r == 0 ? s->ce[i].w
                                  : s->ce[i].w * exp(2 * unit_rand(&rs) - 1);
        if ((rc = forest_tables(s, H, cx)) != 0)
            break;
        s->priors = 1;
        solve_pass(s);
        decode_joint(s, nb, st);
        if ((rc = improve(s, nb, cx)) != 0)
            break;
        if ((f = full_cost(s, nb)) < best) {
            best = f;
            for (i = 0; i < s->V; i++)
                bb[i] = nb[i] + s->kofs;
        }
    }
    for (i = 0; rc == 0 && i < s->V; i++) {
        if (i == 0 || bb[i] < s->need_lo)
            s->need_lo = bb[i];
        if (i == 0 || bb[i] > s->need_hi)
            s->need_hi = bb[i];
    }
    free(nb), free(st);
    return rc;
}

/* The face edges the forest left out (they close cycles) say nothing to
 * the dynamic programme; where the priors alone set a region's direction
 * (a fold prior, a ring), a strong one of them that the result breaks
 * may say the opposite (ours): on Elkhorn a line between two faces hung
 * on the rest by its lower side only, and the fold prior turned it down
 * although 210 probes from its upper side met the line above.  Each such
 * edge of at least HEED_MIN probes, in a component with absolute
 * evidence, pulls a side whose line only the priors decide towards the
 * band of the other side, when the evidence decides that one, or when
 * the priors decide it too but more surely (on Elkhorn a chain of three
 * lines hung on one face edge each went up from a pair of equal lines
 * while 57 probes met a line two levels lower; a unary cost in the
 * priors pass: the whole model's price of breaking the edge,
 * face_cost); the priors pass runs again, and solve_all keeps its answer
 * only when the whole model costs less.  What the evidence alone decides
 * does not change. */
#define HEED_MIN 32.0
static int heed_dropped(hs *s, const long *nb, td_ctx *cx)
{
    size_t i, n = 0;
    for (i = 0; i < s->nce; i++) {
        const cedge *e = &s->ce[i];
        n += e->kind == E_FACE && !s->intree[i] && nb[e->a] != nb[e->b] &&
             s->fe[e->id].w >= HEED_MIN && s->comp_abs[s->comp[e->a]];
    }
    if (!n)
        return 0;
    if (!(s->unx = td_malloc(8 * n * sizeof *s->unx, cx)))
        return TD_ENOMEM;
    for (i = 0; i < s->nce; i++) {
        const cedge *e = &s->ce[i];
        double w;
        int k;
        if (!(e->kind == E_FACE && !s->intree[i] && nb[e->a] != nb[e->b] &&
              s->fe[e->id].w >= HEED_MIN && s->comp_abs[s->comp[e->a]]))
            continue;
        w = face_cost(s->fe[e->id].w);
        for (k = 0; k < 2; k++) {
            double *q;
            uint32_t u = k ? e->b : e->a, v = k ? e->a : e->b;
            /* only a side whose line the priors decide, towards one whose
               line the evidence decides, or the priors more surely */
            if (decided(s, u / 2) ||
                (!decided(s, v / 2) &&
                 !(s->gap_prior[v / 2] > s->gap_prior[u / 2] + GAP_EPS)))
                continue;
            q = s->unx + 4 * s->nunx++;
            q[0] = (double)u;
            q[1] = q[2] = (double)(nb[v] + s->kofs);
            q[3] = w;
        }
    }
    return 0;
}

/* The share of the weight of the face edges answer nb keeps (both sides
 * one band; not a ring's outside) that are folds. */
static double fold_share(const hs *s, const long *nb)
{
    double all = 0, fold = 0;
    size_t i;
    for (i = s->C; i < s->nce; i++) {
        const cedge *e = &s->ce[i];
        double w;
        if (e->kind != E_FACE || nb[e->a] != nb[e->b] || s->hole[e->a] ||
            s->hole[e->b] || arms_edge(s, e->id))
            continue;
        w = s->fe[e->id].w;
        all += w;
        fold += (nb[e->a ^ 1] > nb[e->a]) == (nb[e->b ^ 1] > nb[e->b]) ? w : 0;
    }
    return all > 0 ? fold / all : 0.0;
}

/* Ties the priors pass leaves (ours): a line two of whose heights cost
 * the same in the forest gets none.  On the Orkhon 50 m new print with
 * three known points and the index widths the north-east quarter (29
 * lines, 0.23 of the length) hung on the rest by forest edges whose two
 * ways the priors price alike; the face edges the forest left out tell
 * them apart.  The forest's best answer is decoded again, parents first;
 * where a node's best states given its parent's tie (within GAP_EPS),
 * each (at most TIE_MAX) is tried with its subtree decoded under it
 * (ties: the lowest) and priced under the whole model (full_cost); the
 * cheapest is kept.  g[] gets each node's margin: the least, over the
 * ties on its path from the root, of the runner-up's extra cost
 * (INFINITY: no tie above it; 0 below a tie left untried when the
 * work, subtree states and terms priced, passed TIE_WORK).  Into nb the
 * bands. */
#define TIE_MAX 8
#define TIE_WORK 2e8
#define TIE_MIN                                                                \
    10.0 /* break_ties: a tie decided by less stays undecided.  Over every     \
            bench_heights row, of the tied length decided by a margin under    \
            1 none was right (50,818 px), 1-3: 41 %, 3-10: 3 %, 10-30: 89 %,   \
            30 and more: 93 %.  (A face edge broken costs 4 at least,          \
            face_cost; margins under that are the size of the tie-breakers,    \
            WFOLD, FOLD_TIE, STEP_LEVEL.) */
static int decode_ties(hs *s, long *nb, double *g, td_ctx *cx)
{
    size_t V = s->V, K2 = 2 * s->K, n, j, y;
    uint32_t *eul = td_malloc((V + 1) * sizeof *eul, cx),
             *tin = td_malloc((V + 1) * sizeof *tin, cx),
             *tout = td_malloc((V + 1) * sizeof *tout, cx),
             *st = td_malloc((V + 1) * sizeof *st, cx);
    double *v = td_malloc((K2 + 1) * sizeof *v, cx), work = 0;
    int rc = TD_ENOMEM;
    if (!eul || !tin || !tout || !st || !v || preorder(s, eul, tin, tout, cx))
        goto done;
    decode_joint(s, nb, st);
    for (n = 0; n < V; n++) {
        uint32_t c = eul[n], u = s->par[c], cand[TIE_MAX];
        double best = INFINITY, f1 = INFINITY, f2 = INFINITY;
        size_t nc = 0, by = 0;
        int tie;
        g[c] = u == UINT32_MAX ? INFINITY : g[u];
        if (u != UINT32_MAX && s->pkind[c] == E_LINE) {
            st[c] = (uint32_t)best_state(s, c, st);
            nb[c] = (long)(st[c] >> 1);
            continue;
        }
        for (y = 0; y < K2; y++) {
            v[y] = u == UINT32_MAX ? s->up[(size_t)c * K2 + y]
                                   : child_cost(s, c, st[u], y);
            best = v[y] < best ? v[y] : best;
        }
        for (y = 0; y < K2 && nc < TIE_MAX; y++)
            if (isfinite(v[y]) && v[y] <= best + GAP_EPS)
                cand[nc++] = (uint32_t)y;
        tie = nc >= 2 && s->comp_abs[s->comp[c]];
        if (tie)
            work += (double)nc * ((double)(tout[c] - tin[c]) * (double)K2 +
                                  (double)(s->C + s->nce + s->nun));
        if (!tie || work > TIE_WORK) {
            if (tie)
                g[c] = 0.0; /* out of time: left undecided */
            st[c] = (uint32_t)best_state(s, c, st);
            nb[c] = (long)(st[c] >> 1);
            continue;
        }
        for (j = 0; j < nc; j++) {
            size_t m;
            double f;
            st[c] = cand[j];
            nb[c] = (long)(cand[j] >> 1);
            for (m = tin[c] + 1; m < tout[c]; m++) {
                uint32_t w = eul[m];
                st[w] = (uint32_t)best_state(s, w, st);
                nb[w] = (long)(st[w] >> 1);
            }
            f = full_cost(s, nb);
            if (f < f1)
                f2 = f1, f1 = f, by = cand[j];
            else if (f < f2)
                f2 = f;
        }
        st[c] = (uint32_t)by; /* its subtree: decoded again below */
        nb[c] = (long)(by >> 1);
        g[c] = fmin(g[c], f2 - f1);
    }
    rc = 0;
done:
    free(eul), free(tin), free(tout), free(st), free(v);
    return rc;
}

/* Chunk c is tied: two heights cost the same in the priors pass, in a
 * component with absolute evidence, and the evidence alone does not
 * decide it. */
static int tied(const hs *s, size_t c)
{
    return !(s->gap_prior[c] > GAP_EPS) && s->comp_abs[s->comp[2 * c]] &&
           !decided(s, c);
}

/* The lines the priors pass leaves tied, in components with absolute
 * evidence, take decode_ties' answer, improved by the local search over
 * the whole model (improve()), where decode_ties' margin is TIE_MIN or
 * more (assumed, that margin their gap).  On the Orkhon 50 m new print
 * decode_ties alone left a band of nine lines at the top mirrored about
 * the line below it (-50 to -550 m; the whole model preferred neither of
 * the two ways tried there); improve() turned it (accuracy 0.940 ->
 * 0.971).  stale: the DP's tables are not the priors pass's
 * (heed_dropped's pass was refused). */
static int break_ties(hs *s, double *H, int stale, td_ctx *cx)
{
    size_t c, n = 0, nun0 = s->nun;
    long *nb;
    double *g;
    int rc;
    for (c = 0; c < s->C; c++)
        n += tied(s, c);
    if (!n)
        return 0;
    nb = td_malloc((s->V + 1) * sizeof *nb, cx);
    g = td_malloc((s->V + 1) * sizeof *g, cx);
    if (!nb || !g) {
        free(nb), free(g);
        return TD_ENOMEM;
    }
    if (stale) {
        s->nunx = 0;
        run_pass(s, 1, s->gap_prior, s->band_prior, H);
    }
    s->priors = 1;
    rc = decode_ties(s, nb, g, cx);
    /* the search moves the tied lines only: the others pinned */
    for (c = 0; rc == 0 && c < s->C; c++)
        if (!tied(s, c) &&
            ((rc = add_unary(s, (long)(2 * c), nb[2 * c] + s->kofs,
                             nb[2 * c] + s->kofs, PLINE, cx)) != 0 ||
             (rc = add_unary(s, (long)(2 * c + 1), nb[2 * c + 1] + s->kofs,
                             nb[2 * c + 1] + s->kofs, PLINE, cx)) != 0))
            break;
    if (rc == 0)
        rc = improve(s, nb, cx);
    s->nun = nun0;
    for (c = 0; rc == 0 && c < s->C; c++) {
        double m = fmin(g[2 * c], g[2 * c + 1]);
        if (!tied(s, c) || !(m >= TIE_MIN) || !isfinite(m))
            continue;
        s->band_prior[c] =
            nb[2 * c] > nb[2 * c + 1] ? nb[2 * c] : nb[2 * c + 1];
        s->gap_prior[c] = m;
    }
    free(nb), free(g);
    return rc;
}

static double full_cost(hs *s, const long *nb);
static int solve_all(hs *s, td_ctx *cx)
{
    double *H = NULL;
    long *nb = NULL, *bb = NULL;
    int rc, R = s->p->search, stale = 0;
    size_t i;
    if ((rc = candidates(s, cx)) != 0)
        return rc;
    if (!(nb = td_malloc((s->V + 1) * sizeof *nb, cx)) ||
        !(bb = td_malloc((s->V + 1) * sizeof *bb, cx))) {
        rc = TD_ENOMEM;
        goto done;
    }
    if (R > 0 && !s->cost_only && (rc = search(s, R, bb, &H, cx)) != 0)
        goto done;
    for (i = s->C; i < s->nce; i++) { /* what the search's best keeps first */
        cedge *e = &s->ce[i];
        e->key = e->w;
        if (R > 0 && !s->cost_only && bb[e->a] == bb[e->b] &&
            (!IS_CONT(e->kind) ||
             (bb[e->a ^ 1] > bb[e->a]) == (bb[e->b ^ 1] > bb[e->b])))
            e->key += 1e15;
    }
    if ((rc = forest_tables(s, &H, cx)) != 0)
        goto done;
    mark_abs(s);
    run_pass(s, 0, s->gap, s->band, H);
    run_pass(s, 1, s->gap_prior, s->band_prior, H);
    decode(s, nb);
    if (s->fold_kg > 0 && !s->cost_only && fold_share(s, nb) > FOLD_EXCESS) {
        /* (not in the interval's and the index spacing's trials, whose
           costs are compared with one another) */
        s->fold_k = s->fold_kg;
        run_pass(s, 1, s->gap_prior, s->band_prior, H);
        decode(s, nb);
    }
    if (!s->cost_only && (rc = heed_dropped(s, nb, cx)) != 0)
        goto done;
    if (s->nunx) { /* kept when the whole model says it is better */
        double c0 = full_cost(s, nb);
        long *nb0 = td_malloc((s->V + 1) * sizeof *nb0, cx),
             *bp0 = td_malloc((s->C + 1) * sizeof *bp0, cx);
        double *gp0 = td_malloc((s->C + 1) * sizeof *gp0, cx);
        if (!nb0 || !bp0 || !gp0) {
            free(nb0), free(bp0), free(gp0);
            rc = TD_ENOMEM;
            goto done;
        }
        memcpy(nb0, nb, s->V * sizeof *nb);
        memcpy(bp0, s->band_prior, s->C * sizeof *bp0);
        memcpy(gp0, s->gap_prior, s->C * sizeof *gp0);
        run_pass(s, 1, s->gap_prior, s->band_prior, H);
        decode(s, nb);
        if (!(full_cost(s, nb) < c0 - 1e-9)) {
            memcpy(nb, nb0, s->V * sizeof *nb);
            memcpy(s->band_prior, bp0, s->C * sizeof *bp0);
            memcpy(s->gap_prior, gp0, s->C * sizeof *gp0);
            stale = 1;
        }
        free(nb0), free(bp0), free(gp0);
    }
    if (!s->cost_only && (rc = break_ties(s, H, stale, cx)) != 0)
        goto done;
    s->rep->cost = total_cost(s);
    if (!s->cost_only && s->p->oracle_h && s->p->oracle_up &&
        (rc = oracle_costs(s, nb, cx)) != 0)
        goto done;
    if (!s->cost_only && (rc = report_conflicts(s, nb, cx)) == 0) {
        report_known(s);
        judge_labels(s);
        follow_rings(s);
        if ((rc = sandwich_check(s, cx)) == 0)
            rc = set_lines(s, cx);
    }
done:
    free(H);
    free(nb);
    free(bb);
    return rc;
}

static void count(hs *s)
{
    td_label_report *r = s->rep;
    size_t i;
    for (i = 0; i < s->ls->n; i++) {
        const td_line *l = &s->ls->v[i];
        if (!l->has_height) {
            r->undetermined_ids[r->undetermined++] = l->id;
            r->short_lines += l->why == short_why;
            r->pieces_left += l->piece;
            continue;
        }
        r->labelled++;
        r->by_source[l->hsource]++;
        if (l->hsource == TD_HS_ASSUMED)
            r->assumed_ids[r->assumed++] = l->id;
    }
}

/* Known points and labels read that all give one level (two known
 * points on the 200 m contour, labels that all say 200) fix the levels
 * but not which way the ground slopes from them: where the defaults then
 * decide most lines' direction, say so, and what would help (ours). */
static void one_level_note(hs *s)
{
    const td_label_params *p = s->p;
    td_label_report *r = s->rep;
    double lv = 0;
    size_t i, n = 0, nk = p->nknown, nl = 0;
    for (i = 0; i < p->nknown; i++) {
        double f = (p->known[i].height - p->base) / p->interval;
        if (n++ && fabs(f - lv) > 1e-6)
            return;
        lv = f;
    }
    for (i = 0; i < p->nlabels; i++) {
        const td_ocr_read *q = &p->labels[i];
        double f = (q->value - p->base) / p->interval;
        if (q->spot && !q->why)
            return; /* a spot height sets a direction of its own */
        if (!q->used)
            continue;
        if (n++ && fabs(f - lv) > 1e-6)
            return;
        lv = f, nl++;
    }
    if (n < 2 || 2 * r->by_source[TD_HS_ASSUMED] <= r->labelled)
        return;
    td_label_warn(r,
                  "every height given or read is %g (%zu known point%s, "
                  "%zu label%s): that sets the levels, not which way the "
                  "ground slopes from them; %zu of the %zu lines took "
                  "their direction from the defaults (height_source "
                  "\"assumed\") and whole regions may be upside down: add "
                  "a known point at another height",
                  p->base + lv * p->interval, nk, nk == 1 ? "" : "s", nl,
                  nl == 1 ? "" : "s", r->by_source[TD_HS_ASSUMED],
                  r->labelled);
}

static int is_nice(double v)
{
    static const double nice[4] = {1.0, 2.0, 2.5, 5.0};
    double dec;
    int k;
    for (dec = 0.001; dec <= 1e6; dec *= 10)
        for (k = 0; k < 4; k++)
            if (fabs(v - nice[k] * dec) < 1e-9 * dec)
                return 1;
    return 0;
}

/* Whether v is base + a multiple of S, to a millionth of v - base (not of
 * S: a read of "2" is no multiple of an interval of 10^6). */
static int on_multiple(double v, double base, double S)
{
    double d = v - base;
    return fabs(d - S * (double)lround(d / S)) < 1e-6 * fmax(1.0, fabs(d));
}

/* The confidence of r's surest reading (its read, or an alternative as
 * sure as least) on base + k S; 0: none. */
static double on_step(const td_ocr_read *r, double base, double S,
                      double least)
{
    double best = 0;
    int k;
    if (on_multiple(r->value, base, S))
        return r->conf;
    for (k = 0; k < TD_OCR_ALTS && r->alt[k].conf > 0; k++)
        if (r->alt[k].conf >= least && r->alt[k].conf > best &&
            on_multiple(r->alt[k].value, base, S))
            best = r->alt[k].conf;
    return best;
}

/* The share of the labels whose values are base + a multiple of S. */
static double share_on(const td_label_params *p, double S)
{
    size_t i, fit = 0;
    size_t m = 0;
    for (i = 0; i < p->nlabels; i++) {
        if (p->labels[i].spot)
            continue; /* spot heights are any value */
        fit += on_step(&p->labels[i], p->base, S, ALT_SHARE) > 0;
        m++;
    }
    return m ? (double)fit / (double)m : 0.0;
}

/* With no interval given.  Labels sit on index contours, every Nth line
 * (N = --index-every, else 5, 4, 10 or 2) at a nice interval I (1, 2,
 * 2.5, 5 x 10^k): the label step S is one of the MAX_STEPS largest N x I
 * that at least half of the values are multiples of (misreads; until
 * 2026-12-04 the largest that 80 % fit and the two largest that half fit,
 * which missed the step where a few small numbers were misread), and the
 * interval the nice S / N with the cheapest solve (labels off it counted
 * at their weight, spacings of index lines rarer than every 5th a little)
 * among those that keep the labels' span within the sheet's number of
 * lines (levels_spanned). */
static int solve_on(td_lines *ls, const td_label_params *p, td_faces *fx,
                    td_face_edge *fe, const size_t *nfe, int cost_only,
                    dp_tables *dp, td_label_report *rep, td_ctx *cx);
static int faces_of(const td_lines *ls, const td_label_params *p, td_faces **fx,
                    td_face_edge **fe, size_t *nfe, td_ctx *cx);

#define MAX_STEPS 4 /* label steps tried for the interval */

static int cmp_desc(const void *pa, const void *pb)
{
    double a = *(const double *)pa, b = *(const double *)pb;
    return (a < b) - (a > b);
}

/* How many intervals I the labels read on base + a multiple of I span:
 * each level between the lowest and the highest needs a line of its own
 * (misreads such as "2" and "16" beside "1875" fit an interval of 0.2
 * over 9000 levels on a sheet of 400 lines). */
static double levels_spanned(const td_label_params *p, double I, double least)
{
    double lo = HUGE_VAL, hi = -HUGE_VAL;
    size_t i;
    for (i = 0; i < p->nlabels; i++) {
        const td_ocr_read *r = &p->labels[i];
        if (r->spot || r->conf < least || !on_multiple(r->value, p->base, I))
            continue;
        lo = fmin(lo, r->value), hi = fmax(hi, r->value);
    }
    return hi > lo ? (hi - lo) / I : 0.0;
}

/* The spacings of index lines tried when none is given, and how much
 * rarer than every 5th each is (infer_interval, td_heights_solve_index). */
static const int index_every[4] = {5, 4, 10, 2};
static const double index_rarer[4] = {0.0, 8.0, 15.0, 15.0};

/* What the transects say against spacing `every`: COUNT_W x (1 - its
 * count / the largest count of the spacings tried), hist as
 * td_label_index_count's; 0 without counts.  On the printed cone (rings
 * 7 px apart, widths blurred together) the solve with every 10th thick
 * cost 47.6 against 59.4 for every 5th, and the inner rings came out one
 * interval off; the transects there count 139 runs of 4 thin lines
 * between thick ones and none of 9. */
#define COUNT_W 30.0
static double count_cost(const long *hist, int every)
{
    long most = 0;
    int k;
    if (hist[0] <= 0)
        return 0.0;
    for (k = 0; k < 4; k++)
        if (index_every[k] - 1 <= 20 && hist[index_every[k] - 1] > most)
            most = hist[index_every[k] - 1];
    if (most <= 0 || every - 1 > 20)
        return most > 0 ? COUNT_W : 0.0;
    return COUNT_W * (1.0 - (double)hist[every - 1] / (double)most);
}

/* The transects' counts (td_label_index_count) into hist: 1, or 0 with
 * hist[0] = 0 when the widths show no thick lines, or TD_ENOMEM. */
static int index_counts(const td_lines *ls, const td_label_params *p,
                        long *hist, td_ctx *cx)
{
    double cut;
    int inked = 0, rc = td_label_thick_cut(ls, p, &cut, &inked, cx);
    hist[0] = 0;
    if (rc <= 0)
        return rc;
    rc = td_label_index_count(ls, cut, inked, p->h, hist, cx);
    return rc < 0 ? rc : 1;
}

static int infer_interval(td_lines *ls, const td_label_params *p,
                          double *best_i, int *best_n, double *best_c,
                          double *second, double *second_i, td_ctx *cx)
{
    td_faces *fx = NULL;
    td_face_edge *fe = NULL;
    size_t nfe[2] = {0, 0};
    static const double nice[4] = {1.0, 2.0, 2.5, 5.0};
    double dec, Ss[MAX_STEPS], all[160], sh, best = HUGE_VAL;
    dp_tables dp = {NULL, NULL, NULL, 0};
    size_t i;
    long hist[21];
    int k, rc = 0, si, ns = 0, na = 0;
    *best_i = 0, *best_c = HUGE_VAL;
    if (p->index_every <= 0 && (rc = index_counts(ls, p, hist, cx)) < 0)
        return rc;
    rc = 0;
    *second = HUGE_VAL, *second_i = 0;
    /* the steps S = N x a nice interval that half the values or more fit
     * (a few misreads) whose intervals keep the labels' span within the
     * lines there are: the two largest, and smaller ones that fit more of
     * the values than any larger step tried (MAX_STEPS in all) */
    for (dec = 0.001; dec <= 1e6; dec *= 10)
        for (k = 0; k < 4; k++) {
            int j;
            for (j = 0; j < 4; j++) {
                double c = nice[k] * dec * index_every[j];
                int m, fits = 0;
                if (share_on(p, c) < 0.5 ||
                    levels_spanned(p, c, SPAN_CONF) < 1.0)
                    continue; /* a step no two values read for sure
                                 differ by cannot be told from its
                                 multiples */
                for (m = 0; m < 4; m++)
                    fits |= levels_spanned(p, c / index_every[m], 0.0) <=
                            (double)ls->n;
                for (m = 0; m < na && fits; m++)
                    fits = fabs(all[m] - c) > 1e-9 * c;
                if (fits && na < (int)(sizeof all / sizeof all[0]))
                    all[na++] = c;
            }
        }
    qsort(all, (size_t)na, sizeof all[0], cmp_desc);
    for (si = 0, sh = 0; si < na && ns < MAX_STEPS; si++) {
        double f = share_on(p, all[si]);
        if (ns < 2 || f > sh + 1e-9)
            Ss[ns++] = all[si], sh = fmax(sh, f);
    }
    for (si = 0; si < ns; si++)
        for (k = 0; k < 4; k++) {
            int N = p->index_every > 0 ? p->index_every : index_every[k];
            double S = Ss[si], I = S / N;
            double cost =
                p->index_every > 0 ? 0.0 : index_rarer[k] + count_cost(hist, N);
            td_label_params q = *p;
            td_label_report r;
            if ((p->index_every > 0 && k > 0) || !is_nice(I) ||
                levels_spanned(p, I, 0.0) > (double)ls->n)
                continue;
            for (i = 0; i < p->nlabels; i++) /* reads off it: not
                                                   used, or less sure */
                if (!p->labels[i].spot)
                    cost += W_LABEL * (p->labels[i].conf -
                                       on_step(&p->labels[i], p->base, I, 0));
            if (cost >= best + fmax(INFER_MARGIN, 0.1 * best))
                continue; /* the solve only adds: neither the best nor
                             near enough to it to make the choice unsure */
            q.interval = I;
            q.index_every = N; /* the widths speak when index lines are
                                  thick */
            q.index_auto = 1;
            memset(&r, 0, sizeof r);
            if (!fx && (rc = faces_of(ls, p, &fx, &fe, nfe, cx)) != 0)
                goto done;
            rc = solve_on(ls, &q, fx, fe, nfe, 1, &dp, &r, cx);
            cost += r.cost;
            td_label_report_free(&r);
            if (rc)
                goto done;
            if (cost < best - 1e-9) {
                if (I != *best_i)
                    *second = best, *second_i = *best_i;
                best = cost, *best_i = I, *best_n = N;
            } else if (I != *best_i && cost < *second) {
                *second = cost, *second_i = I;
            }
        }
    *best_c = best;
    rc = 0;
done:
    free(dp.up), free(dp.msg), free(dp.down);
    free(fe);
    td_faces_free(fx);
    return rc;
}

/* How many labels were read at least SPAN_CONF sure (spot heights and
 * label `skip` aside; SIZE_MAX: none) when they all give one value (into
 * *v); 0 when they differ or none is that sure. */
static size_t one_value_but(const td_label_params *p, size_t skip, double *v)
{
    size_t i, n = 0;
    for (i = 0; i < p->nlabels; i++) {
        const td_ocr_read *r = &p->labels[i];
        if (i == skip || r->spot || r->conf < SPAN_CONF)
            continue;
        if (n++ && r->value != *v)
            return 0;
        *v = r->value;
    }
    return n;
}

static size_t one_value(const td_label_params *p, double *v)
{
    return one_value_but(p, SIZE_MAX, v);
}

/* The same when all but one of them give one value: how many do (the
 * odd one into *odd), 0 otherwise. */
static size_t one_value_but_one(const td_label_params *p, double *v,
                                const td_ocr_read **odd)
{
    size_t j, n;
    *odd = NULL;
    for (j = 0; j < p->nlabels; j++) { /* j: the read left out */
        const td_ocr_read *r = &p->labels[j];
        if (r->spot || r->conf < SPAN_CONF)
            continue;
        if ((n = one_value_but(p, j, v)) > 0 && *v != r->value) {
            *odd = r;
            return n;
        }
    }
    return 0;
}

/* Contract in heights_int.h. */
int td_heights_infer(td_lines *ls, const td_label_params *p,
                     td_label_report *rep, td_ctx *cx)
{
    td_label_params q = *p;
    const td_ocr_read *odd = NULL;
    double I, I2, c1, c2, conf_all = 0, conf_agree = 0, v1 = 0;
    int rc, N = 0;
    size_t i, nl = 0, agree, nsure;
    for (i = 0; i < p->nlabels; i++)
        nl += !p->labels[i].spot;
    if (nl == 0)
        return td_seterr(cx, TD_EINVAL,
                         "no interval: give --interval I "
                         "(no printed labels were read to infer it from)");
    if (nl < MIN_INFER_LABELS) /* two values fit too many intervals */
        return td_seterr(cx, TD_EINVAL,
                         "no interval: only %zu printed label%s read, too "
                         "few to infer it from; give --interval I", nl,
                         nl == 1 ? " was" : "s were");
    if ((rc = infer_interval(ls, p, &I, &N, &c1, &c2, &I2, cx)) != 0)
        return rc;
    if (I > 0 && (nsure = one_value_but_one(p, &v1, &odd)) >= MIN_INFER_LABELS)
        /* the steps tried rest on one read, most likely a misread (on the
           printed Elkhorn 20 sheet "260" among nine "200": once the
           spacings' counts (count_cost) told intervals 2 and 1 apart,
           2 was taken, DEM RMSE 25.4 m against 4.0 m with the right
           interval) */
        return td_seterr(cx, TD_EINVAL,
                         "no interval: the %zu labels read for sure all say "
                         "%g but one (%g near %.0f,%.0f, most likely "
                         "misread), so no step between two of them tells "
                         "it; give --interval I",
                         nsure, v1, odd->value, odd->x, odd->y);
    if (I > 0 && c2 - c1 < fmax(INFER_MARGIN, 0.1 * c1))
        /* a broken or crowded trace: the topology cannot tell */
        return td_seterr(cx, TD_EINVAL,
                         "no interval: the %zu printed labels read fit "
                         "intervals %g and %g about equally well; give "
                         "--interval I",
                         nl, I, I2);
    if (!(I > 0) && (nsure = one_value(p, &v1)) > 0)
        return td_seterr(cx, TD_EINVAL,
                         "no interval: the %zu labels read for sure all say "
                         "%g, so no step between two of them tells it; give "
                         "--interval I",
                         nsure, v1);
    if (!(I > 0))
        return td_seterr(cx, TD_EINVAL,
                         "no interval: the %zu labels read "
                         "share no interval; give --interval I",
                         p->nlabels);
    q.interval = I;
    q.index_every = N;
    q.index_auto = p->index_every <= 0;
    if ((rc = td_heights_solve(ls, &q, rep, cx)) != 0)
        return rc;
    for (i = 0, agree = 0; i < p->nlabels; i++) {
        const td_ocr_read *r = &p->labels[i];
        double sure = r->conf;
        int k;
        if (r->spot)
            continue;
        for (k = 0; k < TD_OCR_ALTS; k++)
            sure = fmax(sure, r->alt[k].conf);
        agree += r->used;
        conf_all += sure;
        conf_agree += r->used ? r->conf : 0.0;
    }
    if (agree < MIN_INFER_LABELS || 2 * agree <= nl)
        /* misreads and the solve agree on an interval: not enough */
        return td_seterr(cx, TD_EINVAL,
                         "no interval: only %zu of the %zu printed labels "
                         "read agree with the interval %g they suggest; "
                         "give --interval I",
                         agree, nl, I);
    if (2 * conf_agree <= conf_all)
        /* short misreads ("2", "4", "12") agree on a small interval
           that the surest reads do not fit */
        return td_seterr(cx, TD_EINVAL,
                         "no interval: the %zu of the %zu printed labels "
                         "read that agree with the interval %g they suggest "
                         "were read less surely than the rest; give "
                         "--interval I",
                         agree, nl, I);
    td_label_warn(rep,
                  "interval %g inferred from %zu printed labels, index "
                  "contours every %d (give --interval to set it)",
                  I, p->nlabels, N);
    return 0;
}

/* The solve on lines ls with their faces index fx and its edges fe (the
 * caller's: the interval's trials share them, and the DP's tables dp, or
 * NULL); with cost_only the lines are left as they are and only
 * rep->cost is set. */
static int solve_on(td_lines *ls, const td_label_params *p, td_faces *fx,
                    td_face_edge *fe, const size_t *nfe, int cost_only,
                    dp_tables *dp, td_label_report *rep, td_ctx *cx)
{
    hs s;
    unsigned char *touched = NULL;
    int rc;
    memset(&s, 0, sizeof s);
    s.need_lo = 1, s.need_hi = 0, s.spacing = -1;
    s.ls = ls, s.p = p, s.rep = rep, s.N = ls->n, s.cost_only = cost_only;
    s.fx = fx, s.fe = fe, s.nfe = nfe[0];
    s.st = fe + nfe[0], s.nst = nfe[1];
    s.dp = dp ? dp : &s.own;
    s.C = td_faces_nchunks(fx);
    s.V = 2 * s.C;
    if ((rc = alloc_all(&s, cx)) != 0 || (rc = same_pieces(&s, cx)) != 0 ||
        (rc = gap_pairs(&s, cx)) != 0 ||
        (rc = touched_nodes(&s, &touched, cx)) != 0 ||
        (rc = setup_known(&s, cx)) != 0 || (rc = setup_spots(&s, cx)) != 0)
        goto fail;
    if (!cost_only && (rc = fold_strength(&s, cx)) != 0)
        goto fail; /* (the trials keep the weak prior: solve_all) */
    setup_directions(&s, touched);
    if ((rc = setup_ring_next(&s, touched, cx)) != 0)
        goto fail;
    setup_labels(&s);
    setup_vees(&s);
    if ((rc = setup_index(&s, cx)) != 0 || (rc = solve_all(&s, cx)) != 0 ||
        cost_only)
        goto fail;
    rc = TD_ENOMEM;
    if (!(rep->undetermined_ids = td_calloc(ls->n + 1, sizeof(long), cx)) ||
        !(rep->assumed_ids = td_calloc(ls->n + 1, sizeof(long), cx)))
        goto fail;
    if ((rc = td_label_pieces(ls, cx)) != 0)
        goto fail;
    count(&s);
    one_level_note(&s);
    rep->interval = p->interval;
    rc = 0;
fail:
    if (rc && !cx->code)
        td_seterr(cx, rc, "label: out of memory");
    free(touched);
    free_all(&s);
    return rc;
}

/* A wall through the n points pts into *out (started as a copy of
 * base, or empty, on the first wall). */
static int add_wall(td_lines **out, const td_lines *base, const double *pts,
                    size_t n, td_ctx *cx)
{
    td_line *w;
    size_t k;
    if ((!*out &&
         !(*out = base ? td_lines_copy(base, cx) : td_lines_new(cx))) ||
        !(w = td_lines_add(*out, cx)))
        return TD_ENOMEM;
    for (k = 0; k < n; k++)
        if (td_line_push(w, pts[2 * k], pts[2 * k + 1], cx) != 0)
            return TD_ENOMEM;
    return 0;
}

/* The open end of line l nearest (x,y) within reach on the side sg of
 * the text (the sign of its offset along (ux,uy)): 1 and the end in e. */
static int gap_end(const td_line *l, const td_ocr_read *r, int sg, double reach,
                   double e[2])
{
    int k, got = 0;
    for (k = 0; k < 2 && !l->closed && l->n >= 2; k++) {
        const double *q = l->xy + (k ? 2 * (l->n - 1) : 0);
        double dx = q[0] - r->x, dy = q[1] - r->y, d = hypot(dx, dy);
        if (d > reach || (dx * r->ux + dy * r->uy) * sg <= 0 ||
            (got && d >= hypot(e[0] - r->x, e[1] - r->y)))
            continue;
        e[0] = q[0], e[1] = q[1], got = 1;
    }
    return got;
}

/* Walls across the label gaps (ours): a printed label cuts a gap in its
 * contour, and the probes of the lines round it that pass through the
 * gap meet the lines beyond as if the two sides were one face.  On the
 * scanned Orkhon 50 sheet the 1550 contour's probes through the 1500
 * label's gap outweighed the three pieces of the 1500 line round a
 * corner piece, which came out 1550 for 1450.  Each read (not a spot
 * height) with a line ending at it (its line[], within half the text
 * and two digits of its middle) gets a wall from that end through the
 * middle to the end on the other side, or, with none there, half the
 * text and a digit on along the reading direction. */
static int label_walls(const td_lines *ls, const td_label_params *p,
                       td_lines **out, td_ctx *cx)
{
    size_t i, k;
    for (i = 0; i < p->nlabels; i++) {
        const td_ocr_read *r = &p->labels[i];
        double reach = 0.5 * r->len + 2.0 * r->digit_px, e[2][2], pts[6];
        int sg, has[2] = {0, 0};
        if (r->spot || !(r->len > 0) || !isfinite(r->x) || !isfinite(r->y))
            continue;
        for (sg = 0; sg < 2; sg++)
            for (k = 0; k < 2; k++)
                if (r->line[k] >= 0 && (size_t)r->line[k] < ls->n &&
                    gap_end(&ls->v[r->line[k]], r, sg ? 1 : -1, reach, e[sg]))
                    has[sg] = 1;
        if (!has[0] && !has[1])
            continue;
        for (sg = 0; sg < 2; sg++)
            if (!has[sg]) {
                double t = (sg ? 1.0 : -1.0) * (0.5 * r->len + r->digit_px);
                e[sg][0] = r->x + t * r->ux, e[sg][1] = r->y + t * r->uy;
            }
        pts[0] = e[0][0], pts[1] = e[0][1], pts[2] = r->x, pts[3] = r->y;
        pts[4] = e[1][0], pts[5] = e[1][1];
        if (add_wall(out, p->walls, pts, 3, cx) != 0)
            return TD_ENOMEM;
    }
    return 0;
}

static int long_enough(size_t i, const void *u)
{
    const td_line *l = &((const td_lines *)u)->v[i];
    return !l->piece && td_line_length(l) >= td_faces_defaults().min_len;
}

/* Walls across the gaps between free ends that continue each other (ours;
 * the pairs gap_pairs ties, the same reach: colour scans by default): the
 * probes that pass through such a gap (a contour cut by a road or a
 * stream) say the faces on its two sides are one.  bench_heights, 10 rows
 * up, 3 down (crowded Front Range new print +0.013 / +0.015, -0.005 with
 * known points and labels); docs/label.md. */
static int pair_walls(const td_lines *ls, const td_label_params *p,
                      td_lines **out, td_ctx *cx)
{
    double px =
        p->gap_pairs < 0 ? (p->colour ? TD_GAP_PAIRS_COLOUR : 0) : p->gap_pairs;
    td_end_pair *v;
    size_t i, n;
    int rc = 0;
    if (!(px > 0))
        return 0;
    if (td_end_pairs(ls, long_enough, ls, p->w, p->h, px, &v, &n, cx) != 0)
        return TD_ENOMEM;
    for (i = 0; i < n && rc == 0; i++) {
        double pts[4] = {v[i].ax, v[i].ay, v[i].bx, v[i].by};
        if (v[i].cost <= GAP_COST && v[i].d >= 1.0)
            rc = add_wall(out, p->walls, pts, 2, cx);
    }
    free(v);
    return rc;
}

/* The faces of ls: the index and its edges (one chunk per line; chunks
 * of CHUNK px: see docs/label.md); the scanner's walls, the label
 * gaps' (label_walls) and the gaps between paired ends' (pair_walls)
 * stop the probes. */
static int faces_of(const td_lines *ls, const td_label_params *p, td_faces **fx,
                    td_face_edge **fe, size_t *nfe, td_ctx *cx)
{
    td_faces_params fp = td_faces_defaults();
    td_lines *walls;
    size_t n = 0, i;
    int rc;
    fp.chunk_len = 0;
    *fe = NULL;
    if (ls->n > UINT32_MAX / 4)
        return td_seterr(cx, TD_EINVAL, "label: too many lines (%zu)", ls->n);
    walls = NULL;
    if ((rc = label_walls(ls, p, &walls, cx)) != 0 ||
        (rc = pair_walls(ls, p, &walls, cx)) != 0) {
        td_lines_free(walls);
        return rc;
    }
    *fx = td_faces_new_walls(ls, walls ? walls : p->walls, p->w, p->h, &fp, cx);
    td_lines_free(walls);
    if (!*fx)
        return cx && cx->code ? cx->code : TD_ENOMEM;
    if ((rc = td_faces_set_skeleton(*fx, p->skeleton, cx)) != 0 ||
        (rc = td_faces_edges(*fx, fe, &n, cx)) != 0)
        return rc;
    for (i = 0, nfe[1] = 0; i < n; i++)
        nfe[1] += (*fe)[i].step != 0;
    if (nfe[1]) { /* the step edges last, each part in its order */
        td_face_edge *t = td_malloc(nfe[1] * sizeof *t, cx);
        size_t a = 0, b = 0;
        if (!t)
            return TD_ENOMEM;
        for (i = 0; i < n; i++) {
            if ((*fe)[i].step)
                t[b++] = (*fe)[i];
            else
                (*fe)[a++] = (*fe)[i];
        }
        memcpy(*fe + a, t, b * sizeof *t);
        free(t);
    }
    nfe[0] = n - nfe[1];
    return 0;
}

/* Contract in heights_int.h. */
int td_heights_solve(td_lines *ls, const td_label_params *p,
                     td_label_report *rep, td_ctx *cx)
{
    td_faces *fx = NULL;
    td_face_edge *fe = NULL;
    size_t nfe[2] = {0, 0};
    int rc = faces_of(ls, p, &fx, &fe, nfe, cx);
    if (rc == 0)
        rc = solve_on(ls, p, fx, fe, nfe, 0, NULL, rep, cx);
    free(fe);
    td_faces_free(fx);
    return rc;
}

/* Contract in heights_int.h.  The spacings and their small costs are
 * infer_interval's (index_every, index_rarer), with what the transects
 * count (td_label_index_count, count_cost). */
int td_heights_solve_index(td_lines *ls, const td_label_params *p,
                           td_label_report *rep, td_ctx *cx)
{
    td_faces *fx = NULL;
    td_face_edge *fe = NULL;
    size_t nfe[2] = {0, 0};
    dp_tables dp = {NULL, NULL, NULL, 0};
    td_label_params q = *p;
    double best = HUGE_VAL;
    long hist[21];
    int rc, k, N = 0;
    if ((rc = index_counts(ls, p, hist, cx)) < 0)
        return rc;
    if (rc == 0) /* no thicker lines: nothing to try */
        return td_heights_solve(ls, p, rep, cx);
    if ((rc = faces_of(ls, p, &fx, &fe, nfe, cx)) != 0)
        goto done;
    q.index_auto = 1;
    for (k = 0; k < 4; k++) {
        td_label_report r;
        double c;
        memset(&r, 0, sizeof r);
        q.index_every = index_every[k];
        rc = solve_on(ls, &q, fx, fe, nfe, 1, &dp, &r, cx);
        c = r.cost + index_rarer[k] + count_cost(hist, index_every[k]);
        if (rc == 0 && c < best - 1e-9)
            best = c, N = index_every[k];
        td_label_report_free(&r);
        if (rc)
            goto done;
    }
    q.index_every = N;
    rc = solve_on(ls, &q, fx, fe, nfe, 0, &dp, rep, cx);
done:
    free(dp.up), free(dp.msg), free(dp.down);
    free(fe);
    td_faces_free(fx);
    return rc;
}
