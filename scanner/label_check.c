/* Checks of labelled heights (label.h): the interval and base, and the
 * index contours' ink widths (ours; printed sheets draw every 5th contour
 * thicker, so a labelling one interval off shows as thick lines at the
 * wrong heights).
 *
 *   widths (log)   thin |||||||        thick |||      Otsu's split of the
 *                  -----+-------+------+-----+---     log widths; checked
 *                      2.2     ratio >= 1.3  4.2      only with contrast
 */
#include "scanner/label.h"
#include "scanner/width.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MIN_CHECK_LEN 30.0 /* px: shorter lines' widths are not trusted */

static long level_of(const td_label_params *p, double h, int *off)
{
    double t = (h - p->base) / p->interval;
    long k = (long)floor(t + 0.5);
    *off = fabs(t - (double)k) > 1e-6;
    return k;
}

/* Otsu's split of sorted log widths v[0..n-1]: the first thick index
 * (1..n-1), the class means in *thin and *thick (as widths).  Every Nth
 * line is an index line: the thick class holds 0.4/N .. 2.5/N of the
 * lines, and when len (the lines' lengths) is given, at most SHARE_HI/N
 * of their length (ours: the index contours hold 0.18-0.21 of the length
 * of every bench sheet with every 5th thick, and on the crowded printed
 * Front Range sheet, where thin lines that touch measure 3-3.7 px against
 * the index lines' 3.7-4.5, the count alone put 0.35 of the length in the
 * thick class). */
#define SHARE_HI 1.6
static size_t otsu_split(const double *v, const double *len, size_t n,
                         double *thin, double *thick, int every)
{
    double total = 0, left = 0, L = 0, ll = 0, best = -1;
    size_t i, cut = 1;
    for (i = 0; i < n; i++)
        total += v[i], L += len ? len[i] : 0.0;
    for (i = 1; i < n; i++) {
        double m0, m1, between, share = (double)(n - i) / (double)n;
        left += v[i - 1];
        ll += len ? len[i - 1] : 0.0;
        if (every >= 2 && (share < 0.4 / every || share > 2.5 / every))
            continue;
        if (every >= 2 && len && L > 0 && (L - ll) / L > SHARE_HI / every)
            continue;
        m0 = left / (double)i;
        m1 = (total - left) / (double)(n - i);
        between = (double)i * (double)(n - i) * (m1 - m0) * (m1 - m0);
        if (between > best)
            best = between, cut = i, *thin = exp(m0), *thick = exp(m1);
    }
    return cut;
}

/* A line's log weight and length, sorted by the weight. */
typedef struct lw {
    double v, len;
} lw;

static int cmp_lw(const void *a, const void *b)
{
    double x = ((const lw *)a)->v, y = ((const lw *)b)->v;
    return (x > y) - (x < y);
}

/* The log ink weights (and lengths) of the lines long enough to check,
 * sorted, into v and len (n each); 0 or TD_ENOMEM. */
static int weights(const td_lines *ls, int inked, double **v, double **len,
                   size_t *n, td_ctx *cx)
{
    lw *t = td_malloc((ls->n + 1) * sizeof *t, cx);
    size_t i, k = 0;
    *v = td_malloc((ls->n + 1) * sizeof **v, cx);
    *len = td_malloc((ls->n + 1) * sizeof **len, cx);
    if (!t || !*v || !*len) {
        free(t), free(*v), free(*len);
        *v = *len = NULL;
        return TD_ENOMEM;
    }
    for (i = 0; i < ls->n; i++) {
        double wt = td_line_weight(&ls->v[i], inked),
               L = td_line_length(&ls->v[i]);
        if (wt > 0 && L >= MIN_CHECK_LEN && !ls->v[i].piece)
            t[k++] = (lw){log(wt), L};
    }
    qsort(t, k, sizeof *t, cmp_lw);
    for (i = 0; i < k; i++)
        (*v)[i] = t[i].v, (*len)[i] = t[i].len;
    *n = k;
    free(t);
    return 0;
}

static int cmp_d(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Is level k an index level when the index levels are shifted by j? */
static int is_index(long k, long j, int every)
{
    long r = (k - j) % every;
    return r == 0;
}

/* How many checked lines agree with index levels shifted by j. */
static size_t agree(const td_lines *ls, const td_label_params *p, double cut,
                    long j, int inked)
{
    size_t i, n = 0;
    for (i = 0; i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        double wt = td_line_weight(l, inked);
        int off;
        long k;
        if (!l->has_height || !(wt > 0) || l->piece ||
            td_line_length(l) < MIN_CHECK_LEN)
            continue;
        k = level_of(p, l->height, &off);
        n += is_index(k, j, p->index_every) == (wt >= cut);
    }
    return n;
}

/* One warning per line whose width and height disagree. */
static void mismatches(const td_lines *ls, const td_label_params *p, double cut,
                       double thin, double thick, td_label_report *rep,
                       int inked)
{
    size_t i;
    double every = p->index_every * p->interval;
    for (i = 0; i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        double wt = td_line_weight(l, inked), x, y;
        int off, idx;
        if (!l->has_height || !(wt > 0) || td_line_length(l) < MIN_CHECK_LEN)
            continue;
        idx = is_index(level_of(p, l->height, &off), 0, p->index_every);
        if (idx == (wt >= cut))
            continue;
        td_label_where(l, &x, &y);
        td_label_warn(rep,
                      "line %ld (near %.0f,%.0f) is drawn %s (%s %.2f; "
                      "%s lines %.2f) but its height %g is %san index "
                      "height (base %g + a multiple of %g)",
                      l->id, x, y, idx ? "thin" : "thick",
                      inked ? "ink weight, px x darkness" : "px", wt,
                      idx ? "index" : "other", idx ? thick : thin, l->height,
                      idx ? "" : "not ", p->base, every);
        rep->index_mismatches++;
    }
}

/* How clearly sorted log values v[0..n-1] split into two pens at Otsu's
 * cut: the squared gap of the class means over the summed variances. */
static double split_clarity(const double *v, size_t n, int every)
{
    double thin, thick, m0 = 0, m1 = 0, s0 = 0, s1 = 0;
    size_t k, i;
    if (n < 4)
        return 0;
    k = otsu_split(v, NULL, n, &thin, &thick, every);
    for (i = 0; i < n; i++)
        *(i < k ? &m0 : &m1) += v[i];
    m0 /= (double)k, m1 /= (double)(n - k);
    for (i = 0; i < n; i++)
        *(i < k ? &s0 : &s1) +=
            (v[i] - (i < k ? m0 : m1)) * (v[i] - (i < k ? m0 : m1));
    s0 /= (double)k, s1 /= (double)(n - k);
    return (m1 - m0) * (m1 - m0) / (s0 + s1 + 1e-12);
}

/* Contract in label.h. */
int td_label_use_ink(const td_lines *ls, int every, td_ctx *cx)
{
    double *a, *b, ca, cb;
    size_t i, n = 0;
    if (!td_lines_inked(ls))
        return 0;
    a = td_malloc((ls->n + 1) * sizeof *a, cx);
    b = td_malloc((ls->n + 1) * sizeof *b, cx);
    if (!a || !b) {
        free(a), free(b);
        return TD_ENOMEM;
    }
    for (i = 0; i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        if (l->width > 0 && l->ink > 0 && !l->piece &&
            td_line_length(l) >= MIN_CHECK_LEN)
            a[n] = log(l->width), b[n++] = log(l->width * l->ink);
    }
    qsort(a, n, sizeof *a, cmp_d);
    qsort(b, n, sizeof *b, cmp_d);
    ca = split_clarity(a, n, every);
    cb = split_clarity(b, n, every);
    free(a), free(b);
    return cb > ca;
}

/* Contract in label.h. */
int td_label_thick_cut(const td_lines *ls, const td_label_params *p,
                       double *cut, int *inked_out, td_ctx *cx)
{
    double *v, *len, thin = 0, thick = 0;
    size_t n = 0, k = 1;
    int inked = td_label_use_ink(ls, p->index_every, cx);
    if (inked < 0)
        return inked;
    if (inked_out)
        *inked_out = inked;
    if (weights(ls, inked, &v, &len, &n, cx) != 0)
        return TD_ENOMEM;
    if (n >= 2)
        k = otsu_split(v, len, n, &thin, &thick, p->index_every);
    if (n >= 2) /* the widest gap's middle between the classes */
        *cut = exp(0.5 * (v[k - 1] + v[k]));
    free(v), free(len);
    if (n < 2 || thick < p->thick_ratio * thin)
        return 0;
    return 1;
}

/* Contract in label.h. */
int td_label_check_index(const td_lines *ls, const td_label_params *p,
                         td_label_report *rep, td_ctx *cx)
{
    double *v, *len, thin = 0, thick = 0, cut;
    size_t n = 0, best = 0, cnt;
    long j, bestj = 0;
    int inked;
    if (p->index_every < 0)
        return td_seterr(cx, TD_EINVAL, "label: index-every must be >= 0");
    if (p->index_every == 0 || !(p->interval > 0))
        return 0;
    if ((inked = td_label_use_ink(ls, p->index_every, cx)) < 0)
        return inked;
    if (weights(ls, inked, &v, &len, &n, cx) != 0)
        return TD_ENOMEM;
    if (n < 2 || (otsu_split(v, len, n, &thin, &thick, p->index_every),
                  thick < p->thick_ratio * thin)) {
        td_label_warn(rep, "index check skipped: %s", n < 2 ? "no measured "
                      "line widths (scan the sheet again, or give --like "
                      "SCAN)" : "no thicker lines among the widths");
        free(v), free(len);
        return 0;
    }
    cut = sqrt(thin * thick); /* the geometric middle */
    free(v), free(len);
    mismatches(ls, p, cut, thin, thick, rep, inked);
    for (j = 0; j < p->index_every; j++)
        if ((cnt = agree(ls, p, cut, j, inked)) > best)
            best = cnt, bestj = j;
    if (bestj != 0 && best > (cnt = agree(ls, p, cut, 0, inked))) {
        long sh = bestj <= p->index_every / 2 ? bestj : bestj - p->index_every;
        td_label_warn(rep, "the heights look %+g off: with the index heights "
                      "moved by that, %zu lines' widths agree against %zu; "
                      "check the known points", (double)sh * p->interval,
                      best, cnt);
    }
    return 0;
}

/* ---- the index spacing counted along transects ---------------------------
 * Along a straight transect, consecutive index contours are N lines apart
 * (N - 1 thin ones between) wherever the ground climbs steadily; ridges,
 * valleys and untraced lines make other counts, but the commonest is
 * N - 1.  Transects: every SPACING_STEP px, rows and columns. */
#define SPACING_STEP 16
#define SPACING_MAX 20 /* thin lines between two thick ones counted */

typedef struct xing {
    int32_t t;  /* transect: rows first, then columns */
    int8_t cls; /* 1 thick, 0 thin, -1 unknown (short or unmeasured) */
    float at;   /* position along it */
} xing;

static int cmp_xing(const void *pa, const void *pb)
{
    const xing *a = pa, *b = pb;
    if (a->t != b->t)
        return (a->t > b->t) - (a->t < b->t);
    return (a->at > b->at) - (a->at < b->at);
}

static int push_xing(xing **v, size_t *n, size_t *cap, xing x)
{
    if (*n == *cap) {
        size_t nc = *cap ? 2 * *cap : 4096;
        xing *q = realloc(*v, nc * sizeof *q);
        if (!q)
            return TD_ENOMEM;
        *v = q, *cap = nc;
    }
    (*v)[(*n)++] = x;
    return 0;
}

/* Contract in label.h. */
int td_label_index_count(const td_lines *ls, double cut, int inked, int h,
                         long *hist, td_ctx *cx)
{
    xing *v = NULL;
    size_t n = 0, cap = 0, i, k;
    long best = 0, total = 0;
    int mode = 0, nrow = (h + SPACING_STEP - 1) / SPACING_STEP;
    for (k = 0; k <= SPACING_MAX; k++)
        hist[k] = 0;
    for (i = 0; i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        double wt = td_line_weight(l, inked);
        int8_t cls = wt > 0 && !l->piece && td_line_length(l) >= MIN_CHECK_LEN
                         ? (int8_t)(wt >= cut)
                         : (int8_t)-1;
        size_t m = l->n + (l->closed && l->n > 2 ? 1 : 0);
        for (k = 0; k + 1 < m; k++) {
            const double *a = l->xy + 2 * k, *b = l->xy + 2 * ((k + 1) % l->n);
            int d;
            for (d = 0; d < 2; d++) { /* 0: rows (y = const), 1: columns */
                double a0 = a[1 - d], b0 = b[1 - d], lo = fmin(a0, b0),
                       hi = fmax(a0, b0);
                long r = (long)ceil((lo - 0.5 * SPACING_STEP) / SPACING_STEP);
                for (; r * SPACING_STEP + 0.5 * SPACING_STEP < hi; r++) {
                    double at = r * SPACING_STEP + 0.5 * SPACING_STEP, f;
                    xing x;
                    if (at < lo)
                        continue;
                    f = (at - a0) / (b0 - a0);
                    x.t = (int32_t)(d ? nrow + r : r);
                    x.cls = cls;
                    x.at = (float)(a[d] + f * (b[d] - a[d]));
                    if (push_xing(&v, &n, &cap, x) != 0) {
                        free(v);
                        return td_seterr(cx, TD_ENOMEM, "label: out of memory");
                    }
                }
            }
        }
    }
    if (n > 1)
        qsort(v, n, sizeof *v, cmp_xing);
    for (i = 0; i < n; i++) { /* from each thick crossing to the next */
        int thin = 0;
        if (v[i].cls != 1)
            continue;
        for (k = i + 1;
             k < n && v[k].t == v[i].t && v[k].cls == 0 && thin <= SPACING_MAX;
             k++)
            thin++;
        if (k < n && v[k].t == v[i].t && v[k].cls == 1 && thin >= 1 &&
            thin <= SPACING_MAX)
            hist[thin]++, total++;
    }
    free(v);
    for (k = 1; k <= SPACING_MAX; k++)
        if (hist[k] > best)
            best = hist[k], mode = (int)k;
    hist[0] = total;
    return mode;
}
