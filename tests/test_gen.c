/* test_gen.c: the synthetic-sheet generator's truth is right, and the
 * truth-matching utility reports what it should.  Covers samples/gen/
 * terrain.c, contours.c, render.c, effects.c (blur, noise, specks, breaks)
 * and sheet.c; tdgen.c (the CLI) is run by tests/e2e_cli.sh. */
#include "samples/gen/gen.h"
#include "tests/tt.h"
#include "tests/util/match.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static td_ctx cx;

/* Bilinear interpolation of the DEM at (x,y) (pixel centres at +0.5). */
static double bilinear(const td_grid_f32 *g, double x, double y)
{
    double u = x - 0.5, v = y - 0.5, fu, fv;
    int j = (int)floor(u), i = (int)floor(v);
    j = j < 0 ? 0 : (j > g->w - 2 ? g->w - 2 : j);
    i = i < 0 ? 0 : (i > g->h - 2 ? g->h - 2 : i);
    fu = u - j;
    fv = v - i;
    return (1 - fv) * ((1 - fu) * TD_AT(g, j, i) + fu * TD_AT(g, j + 1, i)) +
           fv * ((1 - fu) * TD_AT(g, j, i + 1) + fu * TD_AT(g, j + 1, i + 1));
}

static td_lines *copy_lines(const td_lines *src)
{
    td_lines *d = td_lines_new(&cx);
    size_t i, k;
    for (i = 0; d && i < src->n; i++) {
        td_line *l = td_lines_add(d, &cx);
        const td_line *s = &src->v[i];
        l->closed = s->closed;
        l->edge = s->edge;
        l->has_height = s->has_height;
        l->height = s->height;
        for (k = 0; k < s->n; k++)
            td_line_push(l, s->xy[2 * k], s->xy[2 * k + 1], &cx);
    }
    return d;
}

static double border_dist(double x, double y, int w, int h)
{
    return fmin(fmin(x, w - x), fmin(y, h - y));
}

/* Contours at least ~6 px apart on a default sheet; fewer levels on small
 * sheets keep that. */
static void test_terrain_spacing(void)
{
    static const int sz[4][2] = {
        {1000, 1000}, {600, 450}, {200, 200}, {1500, 700}};
    int k;
    for (k = 0; k < 4; k++) {
        td_gen_params p = td_gen_defaults();
        td_grid_f32 *dem = NULL;
        double slope, iv;
        p.w = sz[k][0];
        p.h = sz[k][1];
        p.seed = 1 + 7u * (unsigned)k;
        TT_CHECK(td_gen_terrain(&p, &dem, &cx) == 0);
        if (!dem)
            return;
        slope = td_gen_max_slope(dem);
        iv = td_gen_auto_interval(&p, dem);
        TT_CHECKF(iv / slope >= 6.0, "%dx%d: interval %g, slope %g -> %g px",
                  p.w, p.h, iv, slope, iv / slope);
        if (k == 0)
            TT_NEAR(iv, 10.0, 0);
        td_grid_f32_free(dem);
    }
}

static void check_truth_lines(const td_lines *ls, const td_grid_f32 *dem,
                              double interval)
{
    size_t i, k, bad_level = 0, bad_seg = 0;
    for (i = 0; i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        size_t nseg = l->closed ? l->n : l->n - 1;
        TT_CHECK(l->has_height && l->n >= 2);
        TT_CHECK(l->closed != l->edge);
        for (k = 0; k < l->n; k++) {
            double v = bilinear(dem, l->xy[2 * k], l->xy[2 * k + 1]);
            bad_level += fabs(v - l->height) > 1e-3 * interval;
        }
        for (k = 0; k < nseg; k++) {
            const double *p = l->xy + 2 * k, *q = l->xy + 2 * ((k + 1) % l->n);
            double d = hypot(q[0] - p[0], q[1] - p[1]);
            bad_seg += !(d > 1e-9 && d <= sqrt(2.0) + 1e-9);
        }
        if (l->edge) {
            const double *e = l->xy + 2 * (l->n - 1);
            TT_CHECK(border_dist(l->xy[0], l->xy[1], dem->w, dem->h) <=
                     0.5 + 1e-9);
            TT_CHECK(border_dist(e[0], e[1], dem->w, dem->h) <= 0.5 + 1e-9);
        }
    }
    TT_CHECKF(bad_level == 0, "%zu vertices off their level", bad_level);
    TT_CHECKF(bad_seg == 0, "%zu segments not in (0, sqrt 2]", bad_seg);
}

/* Every vertex on its level, rings closed by a marching-squares step, open
 * lines end on the border; HILLS has rings and lines leaving the sheet. */
static void test_hills_truth(void)
{
    td_gen_params p = td_gen_defaults();
    td_grid_f32 *dem = NULL;
    td_lines *ls = NULL;
    size_t i, nclosed = 0, nopen = 0;
    TT_CHECK(td_gen_terrain(&p, &dem, &cx) == 0);
    TT_CHECK(td_gen_contours(dem, 0.0, 10.0, &ls, &cx) == 0);
    if (!ls)
        goto done;
    check_truth_lines(ls, dem, 10.0);
    for (i = 0; i < ls->n; i++) {
        nclosed += ls->v[i].closed;
        nopen += !ls->v[i].closed;
    }
    TT_CHECKF(nclosed >= 20 && nopen >= 6, "%zu rings, %zu open", nclosed,
              nopen);
done:
    td_lines_free(ls);
    td_grid_f32_free(dem);
}

/* Depression rings (truth: the rings around lower ground, the DEM says)
 * and their ticks (--hachures): every pixel the ticks add lies inside a
 * depression ring, within 5 px of it, and there are some. */
static void test_hachures(void)
{
    td_gen_params p = td_gen_defaults();
    td_image *a = NULL, *b = NULL;
    td_lines *ls = NULL;
    td_grid_f32 *dem = NULL;
    size_t i, added = 0, stray = 0, ndep = 0;
    int x, y;
    p.w = p.h = 1500;
    p.line_width = 1.8;
    TT_CHECK(td_gen_sheet(&p, &a, &ls, &dem, &cx) == 0);
    p.hachures = 1;
    TT_CHECK(td_gen_sheet(&p, &b, NULL, NULL, &cx) == 0);
    if (!a || !b || !ls || !dem)
        goto done;
    for (i = 0; i < ls->n; i++) { /* the flag agrees with the DEM inside */
        const td_line *l = &ls->v[i];
        double sx = 0, sy = 0;
        size_t k;
        if (!l->closed)
            continue;
        for (k = 0; k < l->n; k++)
            sx += l->xy[2 * k] / l->n, sy += l->xy[2 * k + 1] / l->n;
        ndep += l->depression;
        if (td_line_encloses(l, sx, sy) && fabs(td_line_signed_area(l)) > 400) {
            float v = dem->data[(size_t)sy * dem->stride + (size_t)sx];
            TT_CHECKF((v < l->height) == !!l->depression,
                      "ring %zu at %g: middle %g, depression %d", i,
                      l->height, v, l->depression);
        }
    }
    for (y = 0; y < p.h; y++)
        for (x = 0; x < p.w; x++) {
            size_t o = (size_t)y * a->stride + (size_t)x;
            int in = 0;
            if (a->data[o] - b->data[o] < 60)
                continue;
            added++;
            for (i = 0; i < ls->n && !in; i++)
                in = ls->v[i].depression &&
                     td_line_encloses(&ls->v[i], x + 0.5, y + 0.5) &&
                     td_contain_dist(&ls->v[i], x + 0.5, y + 0.5) <= 5.0;
            stray += !in;
        }
    TT_CHECKF(ndep >= 1 && added >= 20 && stray == 0,
              "%zu depression rings, %zu tick pixels, %zu elsewhere", ndep,
              added, stray);
done:
    td_image_free(a);
    td_image_free(b);
    td_lines_free(ls);
    td_grid_f32_free(dem);
}

/* CONE: exactly the rings whose radius fits inside the sheet. */
static void test_cone_rings(void)
{
    td_gen_params p = td_gen_defaults();
    td_grid_f32 *dem = NULL;
    td_lines *ls = NULL;
    double R = 0.45 * 1000, lim = 500.0 - 0.5, L;
    size_t i, k, expect = 0, rings = 0, bad = 0;
    p.terrain = TD_GEN_CONE;
    TT_CHECK(td_gen_terrain(&p, &dem, &cx) == 0);
    TT_CHECK(td_gen_contours(dem, 0.0, 10.0, &ls, &cx) == 0);
    if (!ls)
        goto done;
    for (L = -300.0; L < 400.0; L += 10.0) {
        double r = R * (1.0 - L / 400.0);
        TT_CHECK(fabs(r - lim) > 1.0); /* no ring is a borderline case */
        expect += r < lim;
    }
    for (i = 0; i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        double r = R * (1.0 - l->height / 400.0);
        if (!l->closed)
            continue;
        rings++;
        for (k = 0; k < l->n; k++)
            bad += fabs(hypot(l->xy[2 * k] - 500, l->xy[2 * k + 1] - 500) - r) >
                   0.1;
    }
    TT_CHECKF(rings == expect, "%zu rings, expected %zu", rings, expect);
    TT_CHECK(bad == 0);
    check_truth_lines(ls, dem, 10.0);
done:
    td_lines_free(ls);
    td_grid_f32_free(dem);
}

/* PLANE: only open lines, all on the border, one per level. */
static void test_plane(void)
{
    td_gen_params p = td_gen_defaults();
    td_grid_f32 *dem = NULL;
    td_lines *ls = NULL;
    double lo = INFINITY, hi = -INFINITY;
    size_t i;
    p.terrain = TD_GEN_PLANE;
    TT_CHECK(td_gen_terrain(&p, &dem, &cx) == 0);
    TT_CHECK(td_gen_contours(dem, 5.0, 10.0, &ls, &cx) == 0);
    if (!ls)
        goto done;
    for (i = 0; i < (size_t)dem->w * dem->h; i++) {
        lo = fmin(lo, dem->data[i]);
        hi = fmax(hi, dem->data[i]);
    }
    TT_CHECK(ls->n == (size_t)(floor((hi - 5) / 10) - floor((lo - 5) / 10)));
    for (i = 0; i < ls->n; i++)
        TT_CHECK(!ls->v[i].closed && ls->v[i].edge);
    check_truth_lines(ls, dem, 10.0);
done:
    td_lines_free(ls);
    td_grid_f32_free(dem);
}

/* Hand-made grids: a peak gives one 4-point ring; a saddle resolves by the
 * centre; degenerate grids give nothing; NaN is refused. */
static void test_contours_small(void)
{
    td_grid_f32 *g = td_grid_f32_new(3, 3, &cx),
                *one = td_grid_f32_new(1, 1, &cx);
    td_lines *ls = NULL;
    if (!g || !one)
        return;
    TD_AT(g, 1, 1) = 10.0f;
    TT_CHECK(td_gen_contours(g, 0.0, 5.0, &ls, &cx) == 0);
    TT_CHECK(ls && ls->n == 1 && ls->v[0].closed && ls->v[0].n == 4);
    TT_CHECK(ls && ls->v[0].height == 5.0);
    td_lines_free(ls);
    /* a peak exactly on a level is a point, not a ring; the zero plain
     * exactly on level 0 counts as above it: no line at all */
    TT_CHECK(td_gen_contours(g, 0.0, 10.0, &ls, &cx) == 0);
    TT_CHECK(ls && ls->n == 0);
    td_lines_free(ls);
    /* saddle: corners 10,0,10,0, centre mean 5 >= 5: the highs connect */
    memset(g->data, 0, 9 * sizeof(float));
    TD_AT(g, 0, 0) = TD_AT(g, 1, 1) = 10.0f;
    TT_CHECK(td_gen_contours(g, 0.0, 5.0, &ls, &cx) == 0);
    TT_CHECK(ls && ls->n == 2);
    td_lines_free(ls);
    TT_CHECK(td_gen_contours(one, 0.0, 5.0, &ls, &cx) == 0);
    TT_CHECK(ls && ls->n == 0);
    td_lines_free(ls);
    TD_AT(g, 2, 2) = NAN;
    td_ctx_clear(&cx);
    TT_CHECK(td_gen_contours(g, 0.0, 5.0, &ls, &cx) == TD_EINVAL);
    TT_CHECK(td_gen_contours(g, 0.0, 0.0, &ls, &cx) == TD_EINVAL);
    td_ctx_clear(&cx);
    td_grid_f32_free(g);
    td_grid_f32_free(one);
}

/* Mark pixels whose centre is within rad of a segment of ls. */
static unsigned char *near_mask(const td_lines *ls, int w, int h, double rad)
{
    unsigned char *m = calloc((size_t)w * h, 1);
    size_t i, k;
    for (i = 0; m && i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        size_t nseg = l->closed ? l->n : l->n - 1;
        for (k = 0; k < nseg; k++) {
            const double *p = l->xy + 2 * k, *q = l->xy + 2 * ((k + 1) % l->n);
            int x, y;
            for (y = (int)(fmin(p[1], q[1]) - rad - 1);
                 y <= fmax(p[1], q[1]) + rad; y++)
                for (x = (int)(fmin(p[0], q[0]) - rad - 1);
                     x <= fmax(p[0], q[0]) + rad; x++) {
                    double dx = q[0] - p[0], dy = q[1] - p[1];
                    double t = ((x + 0.5 - p[0]) * dx + (y + 0.5 - p[1]) * dy) /
                               (dx * dx + dy * dy);
                    t = fmin(1, fmax(0, t));
                    if (x >= 0 && y >= 0 && x < w && y < h &&
                        hypot(x + 0.5 - p[0] - t * dx,
                              y + 0.5 - p[1] - t * dy) <= rad)
                        m[(size_t)y * w + x] = 1;
                }
        }
    }
    return m;
}

/* Arc length of vertex k of l. */
static double arc_at(const td_line *l, size_t k)
{
    double s = 0.0;
    size_t i;
    for (i = 0; i < k; i++)
        s += hypot(l->xy[2 * i + 2] - l->xy[2 * i],
                   l->xy[2 * i + 3] - l->xy[2 * i + 1]);
    return s;
}

/* Ink under every truth vertex (outside breaks), none far from the lines,
 * breaks are white in their middle. */
static void test_render_ink(void)
{
    td_gen_params p = td_gen_defaults();
    td_image *im = NULL;
    td_lines *ls = NULL;
    td_gen_break *br = NULL;
    unsigned char *m = NULL;
    size_t nbr = 0, i, k, b, miss = 0, stray = 0, white = 0;
    p.breaks = 30;
    p.break_min = 3.0;
    p.break_max = 6.0;
    TT_CHECK(td_gen_sheet(&p, &im, &ls, NULL, &cx) == 0);
    TT_CHECK(td_gen_breaks(ls, &p, &br, &nbr, &cx) == 0);
    if (!im || !ls)
        goto done;
    TT_CHECKF(nbr == 30, "%zu breaks", nbr);
    for (i = 0; i < ls->n; i++)
        for (k = 0; k < ls->v[i].n; k++) {
            double x = ls->v[i].xy[2 * k], y = ls->v[i].xy[2 * k + 1];
            int in_break = 0;
            for (b = 0; b < nbr; b++)
                if (br[b].line == i) {
                    double s = arc_at(&ls->v[i], k);
                    in_break |= s > br[b].s0 - 1.0 && s < br[b].s1 + 1.0;
                }
            if (!in_break)
                miss += im->data[(size_t)y * im->stride + (size_t)x] >= 128;
        }
    for (b = 0; b < nbr; b++)
        white +=
            im->data[(size_t)br[b].y * im->stride + (size_t)br[b].x] == 255;
    m = near_mask(ls, p.w, p.h, p.line_width / 2 + 1.5);
    for (i = 0; m && i < (size_t)p.w * p.h; i++)
        stray += im->data[i] < 255 && !m[i];
    TT_CHECKF(miss == 0, "%zu vertices without ink", miss);
    TT_CHECKF(white == nbr, "%zu of %zu breaks white in the middle", white,
              nbr);
    TT_CHECKF(stray == 0, "%zu ink pixels far from every line", stray);
done:
    free(m);
    free(br);
    td_lines_free(ls);
    td_image_free(im);
}

/* On a straight line the white run along the centre row is the break's
 * length (to a pixel), whatever the width. */
static void test_break_gap(void)
{
    int W;
    for (W = 1; W <= 4; W++) {
        td_gen_params p = td_gen_defaults();
        td_lines *ls = td_lines_new(&cx);
        td_line *l = td_lines_add(ls, &cx);
        td_gen_break *br = NULL;
        td_image *im = NULL;
        size_t nb = 0;
        double x;
        int run = 0, k;
        for (x = 10.5; x <= 290.5; x += 1.0)
            td_line_push(l, x, 50.5, &cx);
        p.w = 300;
        p.h = 100;
        p.line_width = W;
        p.breaks = 1;
        p.break_min = 2.0;
        p.break_max = 8.0;
        p.seed = (unsigned)W;
        TT_CHECK(td_gen_breaks(ls, &p, &br, &nb, &cx) == 0 && nb == 1);
        TT_CHECK(td_gen_render(ls, &p, &im, &cx) == 0);
        for (k = 20; im && k < 280; k++)
            run += im->data[50 * im->stride + (size_t)k] > 127;
        if (br)
            TT_CHECKF(fabs(run - (br[0].s1 - br[0].s0)) <= 1.0,
                      "width %d: gap %g, white run %d", W, br[0].s1 - br[0].s0,
                      run);
        free(br);
        td_image_free(im);
        td_lines_free(ls);
    }
}

/* Specks land away from the lines: all stray ink is specks. */
static void test_render_specks(void)
{
    td_gen_params p = td_gen_defaults();
    td_image *im = NULL;
    td_lines *ls = NULL;
    unsigned char *m = NULL;
    size_t i, stray = 0;
    p.specks = 40;
    TT_CHECK(td_gen_sheet(&p, &im, &ls, NULL, &cx) == 0);
    if (!im)
        goto done;
    m = near_mask(ls, p.w, p.h, p.line_width / 2 + 0.5 + 3.0);
    for (i = 0; m && i < (size_t)p.w * p.h; i++)
        stray += im->data[i] == 0 && !m[i];
    TT_CHECKF(stray >= 40 && stray <= 240, "%zu speck pixels", stray);
done:
    free(m);
    td_lines_free(ls);
    td_image_free(im);
}

/* The benchmark sheet's ink fraction. */
static void test_ridges_ink(void)
{
    td_gen_params p = td_gen_defaults();
    td_image *im = NULL;
    double f;
    p.w = p.h = 2000;
    p.terrain = TD_GEN_RIDGES;
    p.line_width = 3.0;
    TT_CHECK(td_gen_sheet(&p, &im, NULL, NULL, &cx) == 0);
    if (!im)
        return;
    f = td_gen_ink_fraction(im, 128);
    fprintf(stderr, "  ridges 2000x2000, 3 px lines: ink %.1f%%\n", 100 * f);
    TT_CHECKF(f >= 0.10 && f <= 0.18, "ink fraction %g", f);
    td_image_free(im);
}

static int same_image(const td_image *a, const td_image *b)
{
    return a && b && a->w == b->w && a->h == b->h &&
           a->channels == b->channels &&
           memcmp(a->data, b->data, a->stride * (size_t)a->h) == 0;
}

/* Same seed, same bytes; another seed, other bytes. */
static void test_determinism(void)
{
    td_gen_params p = td_gen_defaults();
    td_image *a = NULL, *b = NULL, *c = NULL;
    p.w = 500;
    p.h = 400;
    p.blur = 0.8;
    p.noise = 6;
    p.specks = 20;
    p.breaks = 10;
    p.colour = 1;
    p.distractors = 1;
    TT_CHECK(td_gen_sheet(&p, &a, NULL, NULL, &cx) == 0);
    TT_CHECK(td_gen_sheet(&p, &b, NULL, NULL, &cx) == 0);
    p.seed = 2;
    TT_CHECK(td_gen_sheet(&p, &c, NULL, NULL, &cx) == 0);
    TT_CHECK(same_image(a, b));
    TT_CHECK(c && !same_image(a, c));
    td_image_free(a);
    td_image_free(b);
    td_image_free(c);
}

/* Colour: cream paper, brown lines, blue river; black lettering keeps off
 * the contours. */
static void test_colour(void)
{
    td_gen_params p = td_gen_defaults();
    td_image *im = NULL;
    td_lines *ls = NULL;
    unsigned char *m = NULL;
    size_t i, brown = 0, blue = 0, black = 0, black_near = 0;
    p.colour = 1;
    p.distractors = 1;
    p.line_width = 3;
    TT_CHECK(td_gen_sheet(&p, &im, &ls, NULL, &cx) == 0);
    if (!im)
        goto done;
    TT_CHECK(im->channels == 3);
    TT_CHECK(im->data[0] == 245 && im->data[1] == 235 && im->data[2] == 210);
    m = near_mask(ls, p.w, p.h, p.line_width / 2 + 0.5 + 2.0);
    for (i = 0; m && i < (size_t)p.w * p.h; i++) {
        const uint8_t *v = im->data + 3 * i;
        brown += v[0] == 160 && v[1] == 90 && v[2] == 40;
        blue += v[2] > 150 && v[0] < 100;
        if (v[0] < 60 && v[1] < 60 && v[2] < 60) {
            black++;
            black_near += m[i];
        }
    }
    TT_CHECK(brown > 10000 && blue > 1000 && black > 200);
    TT_CHECKF(black_near == 0, "%zu black pixels near contours", black_near);
done:
    free(m);
    td_lines_free(ls);
    td_image_free(im);
}

static td_lines *hills_truth(td_grid_f32 **dem)
{
    td_gen_params p = td_gen_defaults();
    td_lines *ls = NULL;
    p.w = 800;
    p.h = 600;
    TT_CHECK(td_gen_sheet(&p, NULL, &ls, dem, &cx) == 0);
    return ls;
}

/* Index of a long open line and a long ring in ls. */
static void pick_lines(const td_lines *ls, size_t *open, size_t *ring)
{
    size_t i;
    double bo = 0, br = 0;
    *open = *ring = 0;
    for (i = 0; i < ls->n; i++) {
        double len = td_line_length(&ls->v[i]);
        if (!ls->v[i].closed && len > bo)
            bo = len, *open = i;
        if (ls->v[i].closed && len > br && len < 1000)
            br = len, *ring = i;
    }
}

/* Whether the log written so far contains s (then empties it). */
static int log_has(FILE *f, const char *s)
{
    char line[512];
    int found = 0;
    if (!f)
        return 0;
    rewind(f);
    while (fgets(line, sizeof line, f))
        found |= strstr(line, s) != NULL;
    fclose(f);
    return found;
}

/* The matcher: truth against itself is perfect; a shifted line, a split
 * line, a joined pair and a wrong flag are each reported. */
static void test_match(void)
{
    td_lines *t = hills_truth(NULL), *u = NULL;
    FILE *log = tmpfile();
    td_match_report r;
    size_t io, ir, k, half;
    td_line *l;
    if (!t || !log) {
        TT_CHECK(t && log);
        td_lines_free(t);
        if (log)
            fclose(log);
        return;
    }
    pick_lines(t, &io, &ir);
    TT_CHECK(td_match_lines(t, t, 800, 600, NULL, &r, NULL) == 0);
    TT_CHECK(td_match_ok(&r) && r.n_truth == (long)t->n &&
             r.n_matched == r.n_truth);
    TT_NEAR(r.cov_total, 1.0, 0);
    TT_NEAR(r.worst_mean, 0.0, 1e-4);
    /* shift the ring by 3 px */
    u = copy_lines(t);
    for (k = 0; k < u->v[ir].n; k++)
        u->v[ir].xy[2 * k] += 3.0;
    TT_CHECK(td_match_lines(t, u, 800, 600, NULL, &r, NULL) == 0);
    TT_CHECK(r.n_matched == r.n_truth - 1 && r.worst_cov_id == t->v[ir].id);
    TT_CHECK(r.worst_cov < 0.9);
    td_lines_free(u);
    /* split the open line into two halves */
    u = copy_lines(t);
    half = u->v[io].n / 2;
    l = td_lines_add(u, &cx);
    for (k = half; k < u->v[io].n; k++)
        td_line_push(l, u->v[io].xy[2 * k], u->v[io].xy[2 * k + 1], &cx);
    u->v[io].n = half + 1;
    TT_CHECK(td_match_lines(t, u, 800, 600, NULL, &r, log) == 0);
    TT_CHECK(log_has(log, "split into 2 pieces"));
    TT_CHECK(r.n_split == 1 && r.n_matched == r.n_truth && r.n_mixed == 0);
    td_lines_free(u);
    /* join the ring onto the open line; flip the ring's flag */
    u = copy_lines(t);
    for (k = 0; k < t->v[ir].n; k++)
        td_line_push(&u->v[io], t->v[ir].xy[2 * k], t->v[ir].xy[2 * k + 1],
                     &cx);
    u->v[ir].closed = 0;
    TT_CHECK(td_match_lines(t, u, 800, 600, NULL, &r, NULL) == 0);
    TT_CHECK(r.n_mixed == 1 && r.n_closed_wrong == 1 && !td_match_ok(&r));
    td_lines_free(u);
    /* noise: a traced squiggle far from everything */
    u = copy_lines(t);
    l = td_lines_add(u, &cx);
    for (k = 0; k < 20; k++)
        td_line_push(l, -50.0 - k, -50.0, &cx);
    TT_CHECK(td_match_lines(t, u, 800, 600, NULL, &r, NULL) == 0);
    TT_CHECK(r.n_unmatched_traced == 1 && r.n_matched == r.n_truth);
    td_lines_free(u);
    td_lines_free(t);
}

int main(void)
{
    td_ctx_init(&cx);
    TT_RUN(test_terrain_spacing);
    TT_RUN(test_hills_truth);
    TT_RUN(test_hachures);
    TT_RUN(test_cone_rings);
    TT_RUN(test_plane);
    TT_RUN(test_contours_small);
    TT_RUN(test_render_ink);
    TT_RUN(test_break_gap);
    TT_RUN(test_render_specks);
    TT_RUN(test_ridges_ink);
    TT_RUN(test_determinism);
    TT_RUN(test_colour);
    TT_RUN(test_match);
    return tt_summary();
}
