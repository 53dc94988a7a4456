/* palette.c: the inks of a colour scan (model and contract in palette.h). */
#include "scanner/palette.h"

#include "src/io/io.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define SAMPLES 250000.0 /* pixels sampled on a regular grid */
#define K_LIGHT 6        /* k-means clusters of the light samples (tints) */
#define K_STRONG 8       /* and of the strong ones (inks) */
#define K (K_LIGHT + K_STRONG)
#define SEED_CUBE 6.0 /* grid_seeds' cubes: directions x 100 (3.4 deg) */
#define SEED_CLEAR                                                             \
    0.975 /* strong_kmeans: the seeded clusters replace kmeans++'s when        \
             they cost under this share of theirs */
#define OFF_PAPER 20.0   /* RGB distance from the paper to be sampled */
#define STRONG 70.0      /* ... to be a strong sample */
#define CROSS_APART 25.0 /* a crossing's colour: this far from both inks */
#define SAME_INK 12.0    /* clusters this near are one ink (a brown that
                            k-means cut in three, each too thin alone, was
                            dropped as noise and the blue river taken) */
#define MIN_SHARE 2e-4   /* clusters rarer than this are noise */
#define CROP 2048        /* side of the crop the strokes are measured on */
#define LONG 40          /* a long stroke's bounding box side, px */
#define MIN_WIDTH 1.0    /* narrower strokes are scattered noise */
/* ... unless they make this many px of long strokes per Mpx (a thin ink
 * whose edges its lighter prints took; the red roads of the printed
 * sheets measure 0.95-1.1 px and 760-2600, scattered noise 0.5-0.8 px and
 * 0-300: at 1000 the roads were dropped on some printings and went into
 * the contour ink, recall 0.90-0.92 against 0.92-0.93) */
#define MIN_LINE_LEN 500.0
#define A_MAX 2.0        /* largest coverage fitted */
#define TINT_LIGHT 90.0  /* tints are this near the paper (RGB) */
#define SOFT0 4.0        /* the contour ink's strength where it explains a */
#define BAD0 30.0        /* ... and within BAD0 .. BAD1 in itself */
#define BAD1 60.0
#define SOFT1 10.0       /* colour within SOFT0 .. SOFT1 of the best model */
#define LUT_N TD_PALETTE_LUT_N
/* --ink brown: the inks this near brown's best match compete on their long
 * thin strokes */
#define BROWN_NEAR 30.0
#define BROWN_STROKES                                                          \
    0.1 /* ... and the inks with fewer long thin strokes than this share of   \
           the most stroky ink's do not set the bar: on the printed cone    \
           (contours 5 px apart) the contours' orange colour fringe came    \
           out as its own ink, 7 % as stroky as the contours, nearer to     \
           brown than their scanned #903d36, and the tracing of the fringe  \
           had recall 0.58 against 0.93 */
#define ALSO_HUE 10.0 /* an ink this near the contour ink's hue (CIELAB,
                         degrees) is a darker or lighter print of it; the
                         red roads of the printed sheets came out 14.8
                         degrees from their brown (22 as printed) */
#define ALSO_STROKES                                                           \
    0.1 /* ... and draws at least this share of the contour                    \
           ink's long thin strokes: on a new print the road                    \
           red and the contours' orange colour fringe came                     \
           out as one cluster, 1.4-2.6 % as stroky as the                      \
           brown, and the roads were traced as contours */

static double dist3(const double *a, const double *b)
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                (a[2] - b[2]) * (a[2] - b[2]));
}

/* Ink i over background bg at the coverage that explains v best: *a (0..
 * A_MAX: over 1 where the ink's colour, estimated from its pixels, is
 * lighter than its darkest ones) and the squared residual. */
static double fit(const double *v, const double *bg, const double *ink,
                  const double *paper, double *a)
{
    double d[3], dd = 0, t = 0, r = 0;
    int c;
    for (c = 0; c < 3; c++) {
        double T = ink[c] / (paper[c] > 1 ? paper[c] : 1);
        d[c] = bg[c] * (1.0 - (T > 1 ? 1 : T));
        dd += d[c] * d[c];
        t += (bg[c] - v[c]) * d[c];
    }
    t = dd > 0 ? t / dd : 0;
    t = t < 0 ? 0 : t > A_MAX ? A_MAX : t;
    for (c = 0; c < 3; c++) {
        double e = v[c] - (bg[c] - t * d[c]);
        r += e * e;
    }
    *a = t;
    return r;
}

static void rgb_of(const td_ink *k, double *v)
{
    v[0] = k->rgb[0], v[1] = k->rgb[1], v[2] = k->rgb[2];
}

/* A table over the 33^3 colour nodes 0, 8, ..., 248, 255 of each
 * channel: out[node] = fn(pal, node colour, u). */
typedef uint8_t (*node_fn)(const td_palette *pal, const double *v,
                           const void *u);

static void for_nodes(const td_palette *pal, node_fn fn, const void *u,
                      uint8_t *out)
{
    int i, j, k, n = 0;
    for (i = 0; i < LUT_N; i++)
        for (j = 0; j < LUT_N; j++)
            for (k = 0; k < LUT_N; k++) {
                double v[3] = {i * 8 > 255 ? 255 : i * 8,
                               j * 8 > 255 ? 255 : j * 8,
                               k * 8 > 255 ? 255 : k * 8};
                out[n++] = fn(pal, v, u);
            }
}

/* The model that explains v best.  bg_only_paper: every non-paper colour
 * is an ink over the paper (before the roles are known). */
static int explain(const td_palette *pal, const double *v, int bg_only_paper,
                   double *a_out)
{
    double p[3], best, a;
    int i, b, who = pal->paper;
    rgb_of(&pal->ink[pal->paper], p);
    best = (v[0] - p[0]) * (v[0] - p[0]) + (v[1] - p[1]) * (v[1] - p[1]) +
           (v[2] - p[2]) * (v[2] - p[2]);
    *a_out = 0;
    for (b = 0; b < pal->n; b++) {
        double bg[3];
        if (b == pal->paper ||
            (bg_only_paper || pal->ink[b].role != TD_INKROLE_TINT))
            continue;
        rgb_of(&pal->ink[b], bg);
        if (dist3(v, bg) * dist3(v, bg) < best)
            best = dist3(v, bg) * dist3(v, bg), who = b;
    }
    for (i = 0; i < pal->n; i++) {
        double iv[3];
        if (i == pal->paper ||
            (!bg_only_paper && pal->ink[i].role != TD_INKROLE_INK))
            continue;
        rgb_of(&pal->ink[i], iv);
        for (b = 0; b < pal->n; b++) {
            double bg[3], r;
            if (b != pal->paper &&
                (bg_only_paper || pal->ink[b].role != TD_INKROLE_TINT))
                continue;
            rgb_of(&pal->ink[b], bg);
            r = fit(v, bg, iv, p, &a);
            if (r < best && a > 0)
                best = r, who = i, *a_out = a;
        }
    }
    return who;
}

int td_palette_classify(const td_palette *pal, int r, int g, int b, double *a)
{
    double v[3] = {r, g, b};
    return explain(pal, v, 0, a);
}

/* ---- clusters -> colours ------------------------------------------------ */

typedef struct clus {
    double rgb[3], mean[3]; /* its colour; the mean of its samples */
    long n;
    double key; /* distance from the paper */
} clus;

static int cmp_clus(const void *x, const void *y) /* strongest first */
{
    double a = ((const clus *)x)->key, b = ((const clus *)y)->key;
    return (a < b) - (a > b);
}

/* The colour of each of k clusters (lbl[i] of sample i, colours rgb[3i]),
 * appended to cl.  Light clusters: the mean colour.  Strong clusters (ink
 * pixels at every coverage): the paper minus q95 u, u the members' mean
 * direction from the paper and q95 the 95th percentile of their strength,
 * so a thin or faded line's ink gets its full colour. */
static void cluster_colours(const uint8_t *rgb, const int *lbl, long m, int k,
                            const double *paper, int strong, clus *cl,
                            int *ncl)
{
    long i;
    int j, c;
    for (j = 0; j < k; j++) {
        clus q;
        double u[3] = {0, 0, 0}, un, lo = 0, hi = 450;
        long hist[46] = {0}, acc = 0;
        int it;
        memset(&q, 0, sizeof q);
        for (i = 0; i < m; i++) {
            double v[3] = {rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]}, d;
            if (lbl[i] != j)
                continue;
            d = dist3(v, paper);
            for (c = 0; c < 3; c++) {
                q.rgb[c] += v[c];
                u[c] += (paper[c] - v[c]) / (d > 0 ? d : 1);
            }
            hist[(int)(d / 10) < 45 ? (int)(d / 10) : 45]++;
            q.n++;
        }
        if (q.n == 0)
            continue;
        for (c = 0; c < 3; c++)
            q.mean[c] = q.rgb[c] /= (double)q.n;
        if (strong) {
            for (it = 0; it < 46 && (acc += hist[it]) < 0.95 * q.n; it++)
                ;
            hi = 10.0 * it + 5.0;
            un = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
            for (c = 0; c < 3 && un > 0; c++) {
                double v = paper[c] - hi * u[c] / un;
                q.rgb[c] = v < 0 ? 0 : v > 255 ? 255 : v;
            }
        }
        (void)lo;
        cl[(*ncl)++] = q;
    }
}

/* The k-means cost of n 3-D points p in clusters lbl with centres cen. */
static double sse(const float *p, long n, const int *lbl, const float *cen)
{
    double e = 0;
    long i;
    int c;
    for (i = 0; i < n; i++)
        for (c = 0; c < 3; c++)
            e += (p[3 * i + c] - cen[3 * lbl[i] + c]) *
                 (p[3 * i + c] - cen[3 * lbl[i] + c]);
    return e;
}

/* A cell of grid_seeds: its key, count and the sum of its points. */
typedef struct gcell {
    int64_t key;
    long n;
    double sum[3];
} gcell;

static int cmp_gkey(const void *a, const void *b) /* key, then sample */
{
    const int64_t *x = a, *y = b;
    if (x[0] != y[0])
        return (x[0] > y[0]) - (x[0] < y[0]);
    return (x[1] > y[1]) - (x[1] < y[1]);
}

static int cmp_gcount(const void *a, const void *b)
{
    const gcell *x = a, *y = b;
    if (x->n != y->n)
        return x->n < y->n ? 1 : -1;
    return (x->key > y->key) - (x->key < y->key);
}

/* First clusters for k-means of n 3-D points p, nothing random (ours):
 * the points binned in cubes of side q, the fullest cubes taken as seeds
 * in turn when at least 2 q from every seed taken (then any, fullest
 * first), each point labelled with its nearest seed.  kmeans++ draws
 * its seeds by index, so a few hundred changed samples on a sheet moved
 * every later draw and the clusters landed in another optimum (a spot
 * height's digits turned Elkhorn's printed contour ink #a87449 into
 * #a06d45, and 625 of its 1045 traced lines); the fullest cubes move
 * only when the colours do.  Returns 0 or TD_ENOMEM. */
static int grid_seeds(const float *p, long n, int k, double q, int *lbl,
                      td_ctx *cx)
{
    int64_t *kv = td_malloc((size_t)n * 2 * sizeof *kv + 16, cx);
    gcell *g = td_malloc((size_t)n * sizeof *g + 16, cx);
    double seed[K_STRONG][3];
    long i, m = 0;
    int ns = 0, pass, j, c;
    if (!kv || !g) {
        free(kv), free(g);
        return TD_ENOMEM;
    }
    k = k < K_STRONG ? k : K_STRONG;
    for (i = 0; i < n; i++) {
        int64_t key = 0;
        for (c = 0; c < 3; c++)
            key = key * 4096 + ((int64_t)floor(p[3 * i + c] / q) + 2048);
        kv[2 * i] = key, kv[2 * i + 1] = i;
    }
    qsort(kv, (size_t)n, 2 * sizeof *kv, cmp_gkey);
    for (i = 0; i < n; i++) {
        const float *v = p + 3 * kv[2 * i + 1];
        if (m == 0 || g[m - 1].key != kv[2 * i])
            g[m++] = (gcell){kv[2 * i], 0, {0, 0, 0}};
        g[m - 1].n++;
        for (c = 0; c < 3; c++)
            g[m - 1].sum[c] += v[c];
    }
    qsort(g, (size_t)m, sizeof *g, cmp_gcount);
    for (pass = 0; pass < 2 && ns < k; pass++)
        for (i = 0; i < m && ns < k; i++) {
            double cen[3];
            int far = 1;
            if (g[i].n == 0)
                continue;
            for (c = 0; c < 3; c++)
                cen[c] = g[i].sum[c] / (double)g[i].n;
            for (j = 0; j < ns && (pass || far); j++)
                far &= (cen[0] - seed[j][0]) * (cen[0] - seed[j][0]) +
                           (cen[1] - seed[j][1]) * (cen[1] - seed[j][1]) +
                           (cen[2] - seed[j][2]) * (cen[2] - seed[j][2]) >=
                       4 * q * q;
            if (!far && !pass)
                continue;
            memcpy(seed[ns++], cen, sizeof cen);
            g[i].n = 0; /* taken */
        }
    for (i = 0; i < n; i++) {
        double bd = HUGE_VAL;
        lbl[i] = 0;
        for (j = 0; j < ns; j++) {
            double d = 0;
            for (c = 0; c < 3; c++)
                d += (p[3 * i + c] - seed[j][c]) * (p[3 * i + c] - seed[j][c]);
            if (d < bd)
                bd = d, lbl[i] = j;
        }
    }
    free(kv), free(g);
    return 0;
}

/* The strong samples' k-means (n directions fb, K_STRONG clusters into
 * lbl): kmeans++ from a fixed seed (two attempts), and once more from
 * grid_seeds; the seeded clusters are kept when they cost clearly less
 * (SEED_CLEAR), kmeans++'s otherwise.  Measured (docs/binarise.md): the
 * seeded start was the better one by 3.4 % on the printed Elkhorn sheet
 * with spot heights, where kmeans++ had landed in another optimum than
 * on the same sheet without them; by 1.5 % on the crowded printed Front
 * Range sheet two levels darker it merged the red roads into the brown,
 * so a near tie keeps kmeans++'s.  Returns 0 or an error. */
static int strong_kmeans(const float *fb, long n, int *lbl, float *cen,
                         td_ctx *cx)
{
    int *l2, rc;
    float c2[K_STRONG * 3];
    if ((rc = td_cv_kmeans(fb, (int)n, 3, K_STRONG, 2, lbl, cen, cx)) != 0)
        return rc;
    if (!(l2 = td_malloc((size_t)n * sizeof *l2 + 4, cx)))
        return TD_ENOMEM;
    if ((rc = grid_seeds(fb, n, K_STRONG, SEED_CUBE, l2, cx)) == 0 &&
        (rc = td_cv_kmeans_from(fb, (int)n, 3, K_STRONG, l2, c2, cx)) == 0 &&
        sse(fb, n, l2, c2) < SEED_CLEAR * sse(fb, n, lbl, cen)) {
        memcpy(lbl, l2, (size_t)n * sizeof *lbl);
        memcpy(cen, c2, sizeof c2);
    }
    free(l2);
    return rc;
}

/* The paper (per-channel median of the samples) and clusters of the
 * samples off the paper: the light ones (tints and faint ink) by k-means
 * in CIELAB, the strong ones (ink) by k-means (strong_kmeans) of their
 * direction from the paper in RGB, which a pixel partly covered by an ink
 * shares with the ink's full colour (so an anti-aliased red road and a
 * brown contour fall in different clusters even where their colours are
 * near). */
static int sample_clusters(const td_image *im, double *paper, clus *cl,
                           int *ncl, long *nsamp, td_ctx *cx)
{
    int step = (int)fmax(1.0, floor(sqrt((double)im->w * im->h / SAMPLES)));
    long n = 0, ma = 0, mb = 0, i, hist[3][256];
    uint8_t *rgba = NULL, *rgbb = NULL;
    float *fa = NULL, *fb = NULL, cen[K * 3];
    int *lbl = NULL, x, y, c, k, rc = TD_ENOMEM;
    memset(hist, 0, sizeof hist);
    for (y = step / 2; y < im->h; y += step)
        for (x = step / 2; x < im->w; x += step, n++)
            for (c = 0; c < 3; c++)
                hist[c][im->data[(size_t)y * im->stride + 3 * (size_t)x + c]]++;
    for (c = 0; c < 3; c++) {
        long acc = 0;
        for (k = 0; k < 256 && (acc += hist[c][k]) * 2 < n; k++)
            ;
        paper[c] = k;
    }
    *nsamp = n;
    *ncl = 0;
    if (!(rgba = td_malloc((size_t)n * 3 + 1, cx)) ||
        !(rgbb = td_malloc((size_t)n * 3 + 1, cx)))
        goto done;
    for (y = step / 2; y < im->h; y += step)
        for (x = step / 2; x < im->w; x += step) {
            const uint8_t *px = im->data + (size_t)y * im->stride + 3 * (size_t)x;
            double v[3] = {px[0], px[1], px[2]}, d = dist3(v, paper);
            if (d < OFF_PAPER || px[0] + px[1] + px[2] >
                                     paper[0] + paper[1] + paper[2] - 10)
                continue; /* paper, or lighter than the paper */
            if (d < STRONG)
                memcpy(rgba + 3 * ma++, px, 3);
            else
                memcpy(rgbb + 3 * mb++, px, 3);
        }
    if (!(fa = td_malloc((size_t)(ma > mb ? ma : mb) * 3 * sizeof *fa + 4,
                         cx)) ||
        !(fb = td_malloc((size_t)(ma > mb ? ma : mb) * 3 * sizeof *fb + 4,
                         cx)) ||
        !(lbl = td_malloc((size_t)(ma > mb ? ma : mb) * sizeof *lbl + 4, cx)))
        goto done;
    if (ma >= 4 * K_LIGHT) {
        if ((rc = td_cv_rgb_to_lab(rgba, (size_t)ma, fa, cx)) != 0 ||
            (rc = td_cv_kmeans(fa, (int)ma, 3, K_LIGHT, 2, lbl, cen, cx)) != 0)
            goto done;
        cluster_colours(rgba, lbl, ma, K_LIGHT, paper, 0, cl, ncl);
    }
    if (mb >= 4 * K_STRONG) {
        for (i = 0; i < mb; i++) {
            double v[3] = {rgbb[3 * i], rgbb[3 * i + 1], rgbb[3 * i + 2]};
            double d = dist3(v, paper);
            for (c = 0; c < 3; c++)
                fb[3 * i + c] = (float)(100.0 * (paper[c] - v[c]) / d);
        }
        if ((rc = strong_kmeans(fb, mb, lbl, cen, cx)) != 0)
            goto done;
        cluster_colours(rgbb, lbl, mb, K_STRONG, paper, 1, cl, ncl);
    }
    rc = 0;
done:
    free(rgba);
    free(rgbb);
    free(fa);
    free(fb);
    free(lbl);
    return rc;
}

/* Colour c is ink iv mixed with the paper (a thinner, fainter or
 * blurred print of it), or nearly iv itself; *r: the fit's residual. */
static int mixture_of(const double *c, const double *iv, const double *paper,
                      double *r)
{
    double a;
    *r = sqrt(fit(c, paper, iv, paper, &a));
    return (a > 0.05 && a <= 1.0 &&
            *r < fmin(25.0, 12.0 + 0.1 * a * dist3(iv, paper))) ||
           dist3(c, iv) < SAME_INK;
}

/* Drop the clusters that are one cluster's ink printed over another's
 * (where a road crosses a contour: darker than either, rarer than both
 * and apart from both; a brown is no red over a green tint, being
 * lighter than the red).  Apart: a cluster within CROSS_APART of one of
 * the two is a shade of it, no crossing (ours, 2026-12-06: the crowded
 * printed Front Range sheet two levels darker had its brown dropped as
 * a faded brown over a darker one, and the red roads were traced).
 * Returns the new count. */
static int drop_crossings(clus *cl, int ncl, const double *paper)
{
    int k, i, j, m = 0;
    for (k = 0; k < ncl; k++) {
        int drop = 0;
        for (i = 0; i < ncl && !drop; i++)
            for (j = 0; j < ncl && !drop; j++) {
                double a;
                if (i == k || j == k || i == j || cl[i].n <= cl[k].n ||
                    cl[j].n <= cl[k].n ||
                    dist3(cl[k].rgb, paper) <= fmax(dist3(cl[i].rgb, paper),
                                                    dist3(cl[j].rgb, paper)) ||
                    dist3(cl[k].rgb, cl[i].rgb) < CROSS_APART ||
                    dist3(cl[k].rgb, cl[j].rgb) < CROSS_APART)
                    continue;
                drop = sqrt(fit(cl[k].rgb, cl[i].rgb, cl[j].rgb, paper, &a)) <
                           20.0 &&
                       a > 0.3;
            }
        if (!drop)
            cl[m++] = cl[k];
    }
    return m;
}

/* Keep the clusters that are no mixture of a stronger kept one with the
 * paper (strongest first); the mixtures add to it. */
static void keep_bases(td_palette *pal, const double *paper, clus *cl,
                       int ncl, long nsamp)
{
    int j, i;
    for (j = 0; j < ncl; j++)
        cl[j].key = dist3(cl[j].rgb, paper);
    qsort(cl, (size_t)ncl, sizeof *cl, cmp_clus);
    memset(pal, 0, sizeof *pal);
    pal->n = 1;
    pal->paper = 0;
    pal->chosen = -1;
    for (j = 0; j < 3; j++)
        pal->ink[0].rgb[j] = (uint8_t)lrint(paper[j]);
    pal->ink[0].role = TD_INKROLE_PAPER;
    pal->ink[0].share = 1.0;
    for (j = 0; j < ncl; j++) {
        double share = (double)cl[j].n / (double)nsamp, best = HUGE_VAL;
        int into = -1;
        for (i = 1; i < pal->n; i++) {
            double iv[3], r;
            rgb_of(&pal->ink[i], iv);
            if (mixture_of(cl[j].rgb, iv, paper, &r) && r < best)
                best = r, into = i;
        }
        if (into < 0 && (share < MIN_SHARE || pal->n == TD_PALETTE_MAX)) {
            for (i = 1; i < pal->n; i++) { /* noise: to the nearest */
                double iv[3];
                rgb_of(&pal->ink[i], iv);
                if (dist3(iv, cl[j].rgb) < best)
                    best = dist3(iv, cl[j].rgb), into = i;
            }
            if (into < 0)
                continue;
        }
        if (into >= 0) {
            pal->ink[into].share += share;
            continue;
        }
        for (i = 0; i < 3; i++) {
            pal->ink[pal->n].rgb[i] = (uint8_t)lrint(cl[j].rgb[i]);
            pal->ink[pal->n].mean[i] = (float)cl[j].mean[i];
        }
        pal->ink[pal->n].share = share;
        pal->ink[pal->n].role = TD_INKROLE_INK;
        pal->n++;
    }
    for (i = 1; i < pal->n; i++)
        pal->ink[0].share -= pal->ink[i].share;
}

/* ---- strokes on a crop ---------------------------------------------------- */

/* Label every pixel of the crop with the colour explaining it (ink
 * coverage >= 0.4, else the paper), through a nearest-node table. */
static uint8_t crop_node(const td_palette *pal, const double *v,
                         const void *u)
{
    double a;
    int who = explain(pal, v, 1, &a);
    (void)u;
    return (uint8_t)(who != pal->paper && a < 0.4 ? pal->paper : who);
}

static void label_crop(const td_palette *pal, const td_image *im, int x0,
                       int y0, int cw, int ch, uint8_t *lbl)
{
    uint8_t node[LUT_N * LUT_N * LUT_N];
    int y;
    for_nodes(pal, crop_node, NULL, node);
#pragma omp parallel for schedule(static)
    for (y = 0; y < ch; y++) {
        const uint8_t *px = im->data + (size_t)(y0 + y) * im->stride +
                            3 * (size_t)x0;
        int x;
        for (x = 0; x < cw; x++, px += 3)
            lbl[(size_t)y * cw + x] = node[td_palette_node(px)];
    }
}

/* Speckle closed (ours): a paper pixel with FILL_NEAR or more of its 8
 * neighbours of one colour takes that colour, FILL_PASSES times.  A flat
 * tint whose pixels straddle the coverage cut (0.4) labels as speckle,
 * which measures as 1-2 px strokes (an ink); a thin line's paper
 * neighbours have at most 3 of its pixels around them and stay paper.
 * tmp: cw x ch bytes of scratch. */
#define FILL_NEAR 5
#define FILL_PASSES 2
static void fill_speckle(const td_palette *pal, uint8_t *lbl, int cw, int ch,
                         uint8_t *tmp)
{
    int pass, y;
    for (pass = 0; pass < FILL_PASSES; pass++) {
        memcpy(tmp, lbl, (size_t)cw * ch);
#pragma omp parallel for schedule(static)
        for (y = 1; y < ch - 1; y++) {
            int x;
            for (x = 1; x + 1 < cw; x++) {
                size_t at = (size_t)y * cw + x;
                const uint8_t *up = tmp + at - cw, *dn = tmp + at + cw;
                int cnt[TD_PALETTE_MAX], dx, dy, best = pal->paper, P;
                P = pal->paper;
                if (tmp[at] != P || (up[-1] != P) + (up[0] != P) +
                                            (up[1] != P) + (tmp[at - 1] != P) +
                                            (tmp[at + 1] != P) + (dn[-1] != P) +
                                            (dn[0] != P) + (dn[1] != P) <
                                        FILL_NEAR)
                    continue; /* (most paper pixels: nothing near) */
                memset(cnt, 0, sizeof cnt);
                for (dy = -1; dy <= 1; dy++)
                    for (dx = -1; dx <= 1; dx++) {
                        int v = tmp[at + (ptrdiff_t)dy * cw + dx];
                        if ((dx || dy) && v != pal->paper &&
                            ++cnt[v] >= FILL_NEAR)
                            best = v;
                    }
                lbl[at] = (uint8_t)best;
            }
        }
    }
}

/* Per colour, the per-channel median of the crop's pixels labelled with
 * it into med (the cluster's colour where none are); h: TD_PALETTE_MAX
 * histograms of scratch. */
static void label_medians(const td_palette *pal, const td_image *im, int x0,
                          int y0, int cw, int ch, const uint8_t *lbl,
                          double (*med)[3], long (*h)[3][256])
{
    long n[TD_PALETTE_MAX] = {0};
    int t, y, c, v;
    memset(h, 0, sizeof *h * TD_PALETTE_MAX);
#pragma omp parallel private(t, c, v)
    { /* each thread's counts (a crop has under 2^32 pixels), then summed */
        uint32_t lh[TD_PALETTE_MAX][3][256], ln[TD_PALETTE_MAX];
        memset(lh, 0, sizeof lh), memset(ln, 0, sizeof ln);
#pragma omp for schedule(static) nowait
        for (y = 0; y < ch; y++) {
            const uint8_t *px =
                im->data + (size_t)(y0 + y) * im->stride + 3 * (size_t)x0;
            int x;
            for (x = 0; x < cw; x++, px += 3) {
                t = lbl[(size_t)y * cw + x];
                for (c = 0; c < 3; c++)
                    lh[t][c][px[c]]++;
                ln[t]++;
            }
        }
#pragma omp critical(td_palette_medians)
        for (t = 0; t < TD_PALETTE_MAX; t++) {
            n[t] += ln[t];
            for (c = 0; c < 3; c++)
                for (v = 0; v < 256; v++)
                    h[t][c][v] += lh[t][c][v];
        }
    }
    for (t = 0; t < pal->n; t++)
        for (c = 0; c < 3; c++) {
            long acc = 0;
            if (!n[t]) {
                med[t][c] = pal->ink[t].rgb[c];
                continue;
            }
            for (v = 0; v < 256 && (acc += h[t][c][v]) * 2 < n[t]; v++)
                ;
            med[t][c] = v;
        }
}

/* Area, perimeter and long-stroke area of every colour on the crop:
 * 8-connected components by flood fill (stack in *stk). */
static void stroke_stats(td_palette *pal, const uint8_t *lbl, int cw, int ch,
                         uint8_t *seen, int *stk, double (*med)[3])
{
    double area[TD_PALETTE_MAX] = {0}, per[TD_PALETTE_MAX] = {0},
           longa[TD_PALETTE_MAX] = {0};
    int x, y, i;
    /* whole numbers summed: the same for any thread count */
#pragma omp parallel for schedule(static) private(x)                          \
    reduction(+ : area[:TD_PALETTE_MAX], per[:TD_PALETTE_MAX])
    for (y = 0; y < ch; y++)
        for (x = 0; x < cw; x++) {
            int v = lbl[(size_t)y * cw + x];
            area[v]++;
            per[v] += (x + 1 < cw && lbl[(size_t)y * cw + x + 1] != v) +
                      (y + 1 < ch && lbl[(size_t)(y + 1) * cw + x] != v) +
                      (x > 0 && lbl[(size_t)y * cw + x - 1] != v) +
                      (y > 0 && lbl[(size_t)(y - 1) * cw + x] != v);
        }
    memset(seen, 0, (size_t)cw * ch);
    for (y = 0; y < ch; y++)
        for (x = 0; x < cw; x++) {
            size_t at = (size_t)y * cw + x, top = 0, cnt = 0;
            int v = lbl[at], bx0 = x, bx1 = x, by0 = y, by1 = y;
            if (seen[at] || v == pal->paper)
                continue;
            seen[at] = 1;
            stk[top++] = x, stk[top++] = y;
            while (top) {
                int cy = stk[--top], cxx = stk[--top], dx, dy;
                cnt++;
                bx0 = cxx < bx0 ? cxx : bx0, bx1 = cxx > bx1 ? cxx : bx1;
                by0 = cy < by0 ? cy : by0, by1 = cy > by1 ? cy : by1;
                for (dy = -1; dy <= 1; dy++)
                    for (dx = -1; dx <= 1; dx++) {
                        int nx = cxx + dx, ny = cy + dy;
                        size_t q = (size_t)ny * cw + nx;
                        if (nx < 0 || ny < 0 || nx >= cw || ny >= ch ||
                            seen[q] || lbl[q] != v)
                            continue;
                        seen[q] = 1;
                        stk[top++] = nx, stk[top++] = ny;
                    }
            }
            if (bx1 - bx0 + 1 >= LONG || by1 - by0 + 1 >= LONG)
                longa[v] += (double)cnt;
        }
    for (i = 1; i < pal->n; i++) {
        pal->ink[i].width = per[i] > 0 ? 2.0 * area[i] / per[i] : 0;
        pal->ink[i].line_len =
            pal->ink[i].width > 0
                ? longa[i] / pal->ink[i].width * 1e6 / ((double)cw * ch)
                : 0;
        {
            double v[3], p[3];
            rgb_of(&pal->ink[pal->paper], p);
            memcpy(v, med[i], sizeof v);
            /* wide, or light and in patches (a tint cut into strips by
               crowded contours is narrow but stays light); light as its
               pixels are (their median), not as its cluster's colour,
               which comes from its darkest pixels (ours, 2026-12-04: the
               green tint of Elkhorn drawn at interval 20 has pixels
               (188, 201, 131), 84 from the paper, and a cluster colour
               #84863a, 180 from it: it was taken for the contour ink) */
            pal->ink[i].role =
                pal->ink[i].width > TD_PALETTE_TINT_WIDTH ||
                        (dist3(v, p) < TINT_LIGHT && pal->ink[i].width > 2.5)
                    ? TD_INKROLE_TINT
                    : TD_INKROLE_INK;
        }
    }
}

/* Colours whose pixels form no strokes (mean width under MIN_WIDTH px:
 * scattered pixels) are noise: the scanner's noise pushed part of an ink's
 * thin edges or of the paper that way.  Removed; returns how many. */
static int drop_noise(td_palette *pal)
{
    int k, n = 0;
    for (k = pal->n - 1; k > 0; k--)
        if (pal->ink[k].role == TD_INKROLE_INK &&
            pal->ink[k].width < MIN_WIDTH &&
            pal->ink[k].line_len < MIN_LINE_LEN) {
            pal->ink[0].share += pal->ink[k].share;
            memmove(&pal->ink[k], &pal->ink[k + 1],
                    (size_t)(pal->n - k - 1) * sizeof pal->ink[0]);
            pal->n--;
            n++;
        }
    return n;
}

/* A tint's colour: the per-channel median over the crop's pixels labelled
 * with it (med, label_medians'; its cluster came from its darkest
 * pixels). */
static void tint_colours(td_palette *pal, const double (*med)[3])
{
    int t, c;
    for (t = 1; t < pal->n; t++)
        for (c = 0; c < 3 && pal->ink[t].role == TD_INKROLE_TINT; c++)
            pal->ink[t].rgb[c] = (uint8_t)med[t][c];
}

/* Per colour, the share of its crop pixels with a tint 2 px away along a
 * row or a column. */
static void tint_contact(const td_palette *pal, const uint8_t *lbl, int cw,
                         int ch, double *frac)
{
    double n[TD_PALETTE_MAX] = {0}, in[TD_PALETTE_MAX] = {0};
    int x, y, k;
    for (y = 2; y + 2 < ch; y++)
        for (x = 2; x + 2 < cw; x++) {
            const uint8_t *q = lbl + (size_t)y * cw + x;
            int v = *q;
            n[v]++;
            in[v] += pal->ink[q[2]].role == TD_INKROLE_TINT ||
                     pal->ink[q[-2]].role == TD_INKROLE_TINT ||
                     pal->ink[q[2 * cw]].role == TD_INKROLE_TINT ||
                     pal->ink[q[-2 * cw]].role == TD_INKROLE_TINT;
        }
    for (k = 0; k < pal->n; k++)
        frac[k] = n[k] > 0 ? in[k] / n[k] : 0;
}

/* An ink that is another ink printed over a tint is that ink: its mean
 * colour is explained so, and most of its pixels lie in the tint (red
 * over a green tint looks brown; a brown contour on paper is no red).
 * The mean, not the colour extrapolated from the paper: pixels of an
 * ink over a tint lie on a line from the tint, not from the paper. */
static void merge_overprints(td_palette *pal, const double *in_tint)
{
    double p[3];
    int k, i, b;
    rgb_of(&pal->ink[pal->paper], p);
    for (k = pal->n - 1; k > 0; k--) {
        double kv[3];
        if (pal->ink[k].role != TD_INKROLE_INK || in_tint[k] < 0.3)
            continue;
        for (i = 0; i < 3; i++)
            kv[i] = pal->ink[k].mean[i];
        for (i = 1; i < pal->n; i++) {
            double iv[3], a;
            if (i == k || pal->ink[i].role != TD_INKROLE_INK)
                continue;
            rgb_of(&pal->ink[i], iv);
            for (b = 1; b < pal->n; b++) {
                double bg[3];
                if (pal->ink[b].role != TD_INKROLE_TINT)
                    continue;
                rgb_of(&pal->ink[b], bg);
                if (sqrt(fit(kv, bg, iv, p, &a)) <
                        fmax(12.0, 0.15 * dist3(kv, p)) &&
                    a > 0.3)
                    break;
            }
            if (b < pal->n)
                break;
        }
        if (i < pal->n) {
            pal->ink[i].share += pal->ink[k].share;
            pal->ink[i].line_len += pal->ink[k].line_len;
            memmove(&pal->ink[k], &pal->ink[k + 1],
                    (size_t)(pal->n - k - 1) * sizeof pal->ink[0]);
            pal->n--;
        }
    }
}

int td_palette_find(const td_image *im, td_palette *pal, td_ctx *cx)
{
    double paper[3];
    clus cl[K];
    long nsamp;
    int ncl, cw, ch, x0, y0, i, rc;
    uint8_t *lbl = NULL, *seen = NULL;
    int *stk = NULL;
    double med[TD_PALETTE_MAX][3];
    long(*hist)[3][256] = NULL;
    memset(pal, 0, sizeof *pal);
    pal->chosen = -1;
    if (!im || im->channels != 3)
        return td_seterr(cx, TD_EINVAL, "palette: not an RGB scan");
    if ((rc = sample_clusters(im, paper, cl, &ncl, &nsamp, cx)) != 0)
        return rc;
    ncl = drop_crossings(cl, ncl, paper);
    keep_bases(pal, paper, cl, ncl, nsamp);
    cw = im->w < CROP ? im->w : CROP;
    ch = im->h < CROP ? im->h : CROP;
    x0 = (im->w - cw) / 2, y0 = (im->h - ch) / 2;
    rc = TD_ENOMEM;
    if (!(hist = td_malloc(sizeof *hist * TD_PALETTE_MAX, cx)) ||
        !(lbl = td_malloc((size_t)cw * ch, cx)) ||
        !(seen = td_malloc((size_t)cw * ch, cx)) ||
        !(stk = td_malloc((size_t)cw * ch * 2 * sizeof *stk + 8, cx)))
        goto done;
    label_crop(pal, im, x0, y0, cw, ch, lbl);
    fill_speckle(pal, lbl, cw, ch, seen);
    label_medians(pal, im, x0, y0, cw, ch, lbl, med, hist);
    stroke_stats(pal, lbl, cw, ch, seen, stk, med);
    if (drop_noise(pal)) { /* measured again without them */
        label_crop(pal, im, x0, y0, cw, ch, lbl);
        fill_speckle(pal, lbl, cw, ch, seen);
        label_medians(pal, im, x0, y0, cw, ch, lbl, med, hist);
        stroke_stats(pal, lbl, cw, ch, seen, stk, med);
    }
    tint_colours(pal, (const double(*)[3])med);
    {
        double in_tint[TD_PALETTE_MAX];
        tint_contact(pal, lbl, cw, ch, in_tint);
        merge_overprints(pal, in_tint);
    }
    {
        float lab[3 * TD_PALETTE_MAX];
        uint8_t rgb[3 * TD_PALETTE_MAX] = {0};
        for (i = 0; i < pal->n; i++)
            memcpy(rgb + 3 * i, pal->ink[i].rgb, 3);
        if ((rc = td_cv_rgb_to_lab(rgb, (size_t)pal->n, lab, cx)) != 0)
            goto done;
        for (i = 0; i < pal->n; i++)
            memcpy(pal->ink[i].lab, lab + 3 * i, sizeof pal->ink[i].lab);
    }
    rc = 0;
done:
    free(hist);
    free(lbl);
    free(seen);
    free(stk);
    return rc;
}

int td_palette_choose(td_palette *pal, int brown)
{
    static const double ref[3] = {160, 90, 40};
    double p[3], r[TD_PALETTE_MAX], best = HUGE_VAL, most = -1, top = 0;
    int i;
    rgb_of(&pal->ink[pal->paper], p);
    pal->chosen = -1;
    for (i = 0; i < pal->n; i++)
        if (pal->ink[i].role == TD_INKROLE_INK && pal->ink[i].line_len > top)
            top = pal->ink[i].line_len;
    for (i = 0; i < pal->n; i++) {
        /* brown: the distance from brown to the ink's line of mixtures
           with the paper (a faded or thin brown still matches); the
           nearest among the inks that draw strokes at all (BROWN_STROKES)
           sets the bar */
        double iv[3], a;
        rgb_of(&pal->ink[i], iv);
        r[i] = sqrt(fit(ref, p, iv, p, &a)) + 0.25 * dist3(iv, ref);
        if (pal->ink[i].role == TD_INKROLE_INK && r[i] < best &&
            pal->ink[i].line_len >= BROWN_STROKES * top)
            best = r[i];
    }
    for (i = 0; i < pal->n; i++) {
        /* the most long thin strokes; brown: among the inks near brown
           (a red road came out within 1-8 of the contours' brown on the
           printed sheets, blue and black over 100 further) */
        const td_ink *k = &pal->ink[i];
        if (k->role == TD_INKROLE_INK &&
            (!brown || r[i] <= best + BROWN_NEAR) && k->line_len > most)
            most = k->line_len, pal->chosen = i;
    }
    pal->also = 0;
    if (pal->chosen >= 0) {
        const float *c = pal->ink[pal->chosen].lab;
        double hc = atan2(c[2], c[1]), cc = hypot(c[1], c[2]);
        for (i = 0; i < pal->n; i++) {
            const float *l = pal->ink[i].lab;
            double dh = fabs(atan2(l[2], l[1]) - hc);
            dh = dh > M_PI ? 2 * M_PI - dh : dh;
            if (i != pal->chosen && pal->ink[i].role == TD_INKROLE_INK &&
                cc > 10 && hypot(l[1], l[2]) > 0.5 * cc &&
                pal->ink[i].line_len >=
                    ALSO_STROKES * pal->ink[pal->chosen].line_len &&
                dh < ALSO_HUE * M_PI / 180.0)
                pal->also |= 1u << i;
        }
    }
    return pal->chosen;
}

/* Ink k's best fit to v over any background: its coverage in *a and the
 * residual (RGB units). */
static double fit_ink(const td_palette *pal, int k, const double *v, double *a)
{
    double p[3], iv[3], best = HUGE_VAL, t;
    int b;
    rgb_of(&pal->ink[pal->paper], p);
    rgb_of(&pal->ink[k], iv);
    *a = 0;
    for (b = 0; b < pal->n; b++) {
        double bg[3], r;
        if (b != pal->paper && pal->ink[b].role != TD_INKROLE_TINT)
            continue;
        rgb_of(&pal->ink[b], bg);
        r = fit(v, bg, iv, p, &t);
        if (r < best)
            best = r, *a = t;
    }
    return sqrt(best);
}

static int is_contour(const td_palette *pal, int k)
{
    return k == pal->chosen || (k >= 0 && (pal->also >> k & 1u));
}

double td_palette_contour_residual(const td_palette *pal, int r, int g, int b)
{
    double v[3] = {r, g, b}, a, best = HUGE_VAL;
    int k;
    for (k = 0; k < pal->n; k++)
        if (is_contour(pal, k))
            best = fmin(best, fit_ink(pal, k, v, &a));
    return best;
}

static uint8_t strength_node(const td_palette *pal, const double *v,
                             const void *u)
{
    double a, ab, rb, rk, w, best = 0, bv[3];
    int who = explain(pal, v, 0, &ab), k;
    (void)u;
    /* the best model's residual */
    if (who == pal->paper || pal->ink[who].role == TD_INKROLE_TINT) {
        rgb_of(&pal->ink[who], bv);
        rb = dist3(v, bv);
    } else {
        rb = fit_ink(pal, who, v, &ab);
    }
    { /* or a tint's blurred edge: the tint mixed with the paper (a pale
         tint edge read as pale brown once the level is lowered:
         binarise.c, the local ink level) */
        double p[3];
        int b;
        rgb_of(&pal->ink[pal->paper], p);
        for (b = 0; b < pal->n; b++) {
            double tv[3], at;
            if (b == pal->paper || pal->ink[b].role != TD_INKROLE_TINT)
                continue;
            rgb_of(&pal->ink[b], tv);
            rb = fmin(rb, sqrt(fit(v, p, tv, p, &at)));
        }
    }
    for (k = 0; k < pal->n; k++) {
        if (!is_contour(pal, k))
            continue;
        rk = fit_ink(pal, k, v, &a);
        /* the ink's share: full when it explains v within SOFT0 of the
           best model (a colour fringe, JPEG), none beyond SOFT1 (another
           ink) */
        w = (SOFT1 - (rk - rb)) / (SOFT1 - SOFT0);
        w = w < 0 ? 0 : w > 1 ? 1 : w;
        /* and none where it explains v badly in itself: an ink the
           palette missed (a little black text) */
        w *= rk < BAD0 ? 1.0 : rk > BAD1 ? 0.0 : (BAD1 - rk) / (BAD1 - BAD0);
        best = fmax(best, 255.0 * fmin(a, 1.0) * w);
    }
    return (uint8_t)lrint(best);
}

void td_palette_lut(const td_palette *pal, uint8_t *lut)
{
    for_nodes(pal, strength_node, NULL, lut);
}

static uint8_t veto_node(const td_palette *pal, const double *v,
                         const void *u)
{
    double a, ak;
    int who = explain(pal, v, 0, &a);
    (void)u;
    return !is_contour(pal, who) && pal->ink[who].role == TD_INKROLE_INK &&
                   a >= 0.5 &&
                   fit_ink(pal, who, v, &a) + 10.0 <
                       fit_ink(pal, pal->chosen, v, &ak)
               ? 255
               : 0;
}

void td_palette_veto_lut(const td_palette *pal, uint8_t *lut)
{
    for_nodes(pal, veto_node, NULL, lut);
}

static uint8_t label_node(const td_palette *pal, const double *v,
                          const void *u)
{
    double a, bg = HUGE_VAL;
    int who = explain(pal, v, 0, &a), b, wb = pal->paper;
    (void)u;
    if (pal->ink[who].role == TD_INKROLE_INK && a < 0.4) {
        for (b = 0; b < pal->n; b++) { /* the nearest background */
            double bv[3];
            if (pal->ink[b].role == TD_INKROLE_INK)
                continue;
            rgb_of(&pal->ink[b], bv);
            if (dist3(v, bv) < bg)
                bg = dist3(v, bv), wb = b;
        }
        who = wb;
    }
    return (uint8_t)who;
}

int td_palette_label(const td_palette *pal, const td_image *im,
                     td_grid_u8 *lbl, td_ctx *cx)
{
    uint8_t *node;
    int x, y;
    if (!im || im->channels != 3 || !lbl || lbl->w != im->w ||
        lbl->h != im->h || pal->n < 1)
        return td_seterr(cx, TD_EINVAL, "palette: bad image or labels");
    if (!(node = td_malloc(LUT_N * LUT_N * LUT_N, cx)))
        return TD_ENOMEM;
    for_nodes(pal, label_node, NULL, node);
    for (y = 0; y < im->h; y++) {
        const uint8_t *px = im->data + (size_t)y * im->stride;
        uint8_t *out = lbl->data + (size_t)y * lbl->stride;
        for (x = 0; x < im->w; x++, px += 3)
            out[x] = node[td_palette_node(px)];
    }
    free(node);
    return 0;
}
