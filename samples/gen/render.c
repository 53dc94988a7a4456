/* render.c: draw truth lines as a scanned sheet.
 *
 * Lines are drawn segment by segment into an 8-bit coverage layer, each
 * segment touching only its bounding box (long segments are cut into 8 px
 * pieces), so rendering costs O(ink) and memory is the image (plus one or
 * two layers for colour).  Coverage model, for a pixel centre at distance d
 * from the nearest segment and line width W:
 *
 *       coverage = clamp(W/2 + 0.5 - d, 0, 1)
 *
 * which integrates to exactly W across the line.  Breaks remove the ink of
 * a stretch of the line: the drawn pieces stop W/2 before the gap and start
 * again W/2 after it, so the round ends meet the gap's ends at 50% coverage
 * and the visible gap, measured along the line, is the break's length. */
#include "samples/gen/gen.h"
#include "samples/gen/gen_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void draw_piece(uint8_t *lay, int w, int h, double x0, double y0,
                       double x1, double y1, double r)
{
    double dx = x1 - x0, dy = y1 - y0, len2 = dx * dx + dy * dy;
    double inv = len2 > 0.0 ? 1.0 / len2 : 0.0, r2 = r * r;
    int xa = (int)floor(fmin(x0, x1) - r), xb = (int)ceil(fmax(x0, x1) + r);
    int ya = (int)floor(fmin(y0, y1) - r), yb = (int)ceil(fmax(y0, y1) + r);
    int x, y;
    xa = xa < 0 ? 0 : xa;
    ya = ya < 0 ? 0 : ya;
    xb = xb > w - 1 ? w - 1 : xb;
    yb = yb > h - 1 ? h - 1 : yb;
    for (y = ya; y <= yb; y++) {
        uint8_t *row = lay + (size_t)y * (size_t)w;
        double py = y + 0.5 - y0;
        for (x = xa; x <= xb; x++) {
            double px = x + 0.5 - x0, t, ex, ey, d2, cov;
            t = (px * dx + py * dy) * inv;
            t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
            ex = px - t * dx;
            ey = py - t * dy;
            d2 = ex * ex + ey * ey;
            if (d2 >= r2 || row[x] == 255)
                continue;
            cov = r - sqrt(d2);
            {
                int v = cov >= 1.0 ? 255 : (int)(cov * 255.0 + 0.5);
                if (v > row[x])
                    row[x] = (uint8_t)v;
            }
        }
    }
}

/* Contract in gen_int.h. */
void td_gen_draw_seg(uint8_t *lay, int w, int h, double x0, double y0,
                     double x1, double y1, double r)
{
    double len = sqrt((x1 - x0) * (x1 - x0) + (y1 - y0) * (y1 - y0));
    int n, k;
    if (len <= 8.0) {
        draw_piece(lay, w, h, x0, y0, x1, y1, r);
        return;
    }
    n = (int)ceil(len / 8.0);
    for (k = 0; k < n; k++) {
        double a = (double)k / n, b = (double)(k + 1) / n;
        draw_piece(lay, w, h, x0 + a * (x1 - x0), y0 + a * (y1 - y0),
                   x0 + b * (x1 - x0), y0 + b * (y1 - y0), r);
    }
}

/* Point of l at arc length s (closing segment included when closed). */
static void point_at(const td_line *l, double s, double *x, double *y)
{
    size_t i, nseg = l->closed ? l->n : l->n - 1;
    *x = l->xy[0];
    *y = l->xy[1];
    for (i = 0; i < nseg; i++) {
        const double *p = l->xy + 2 * i, *q = l->xy + 2 * ((i + 1) % l->n);
        double len = hypot(q[0] - p[0], q[1] - p[1]);
        if (s <= len || i + 1 == nseg) {
            double t = len > 0.0 ? fmin(1.0, fmax(0.0, s / len)) : 0.0;
            *x = p[0] + t * (q[0] - p[0]);
            *y = p[1] + t * (q[1] - p[1]);
            return;
        }
        s -= len;
    }
}

static int break_cmp(const void *a, const void *b)
{
    const td_gen_break *x = a, *y = b;
    if (x->line != y->line)
        return x->line < y->line ? -1 : 1;
    return (x->s0 > y->s0) - (x->s0 < y->s0);
}

/* One break on a line picked by length; 0 when it had to be skipped. */
static int place_break(const td_lines *ls, const double *cum, size_t ncum,
                       const size_t *idx, const td_gen_params *p, td_rng *r,
                       const td_gen_break *have, size_t nhave, td_gen_break *b)
{
    double total = cum[ncum - 1], pick = td_rng_range(r, 0.0, total);
    double g = td_rng_range(r, p->break_min, p->break_max), len, lo, hi;
    double keep = p->line_width + 4.0;
    size_t a = 0, z = ncum - 1, i;
    const td_line *l;
    while (a < z) { /* first cum > pick */
        size_t m = (a + z) / 2;
        if (cum[m] > pick)
            z = m;
        else
            a = m + 1;
    }
    l = &ls->v[idx[a]];
    len = td_line_length(l);
    lo = l->closed ? p->line_width : 10.0 + p->line_width;
    hi = len - lo - g;
    if (hi <= lo)
        return 0;
    b->line = idx[a];
    b->s0 = td_rng_range(r, lo, hi);
    b->s1 = b->s0 + g;
    for (i = 0; i < nhave; i++)
        if (have[i].line == b->line && b->s0 < have[i].s1 + keep &&
            have[i].s0 < b->s1 + keep)
            return 0;
    point_at(l, 0.5 * (b->s0 + b->s1), &b->x, &b->y);
    return 1;
}

/* Contract in gen.h. */
int td_gen_breaks(const td_lines *lines, const td_gen_params *p,
                  td_gen_break **out, size_t *n, td_ctx *cx)
{
    td_rng r = td_rng_make(p->seed, 4);
    double *cum = NULL, acc = 0.0;
    size_t *idx = NULL, ncum = 0, i, nb = 0;
    td_gen_break *br = NULL;
    int k, tries, rc = TD_ENOMEM;
    *out = NULL;
    *n = 0;
    if (p->breaks <= 0 || lines->n == 0)
        return 0;
    cum = td_malloc(lines->n * sizeof *cum, cx);
    idx = td_malloc(lines->n * sizeof *idx, cx);
    br = td_calloc((size_t)p->breaks, sizeof *br, cx);
    if (!cum || !idx || !br)
        goto fail;
    for (i = 0; i < lines->n; i++) {
        double len = lines->v[i].n >= 2 ? td_line_length(&lines->v[i]) : 0.0;
        if (len >= 40.0 && len >= 2.0 * (p->break_max + 10.0 + p->line_width)) {
            acc += len;
            cum[ncum] = acc;
            idx[ncum++] = i;
        }
    }
    for (k = 0; k < p->breaks && ncum > 0; k++)
        for (tries = 0; tries < 50; tries++)
            if (place_break(lines, cum, ncum, idx, p, &r, br, nb, &br[nb])) {
                nb++;
                break;
            }
    qsort(br, nb, sizeof *br, break_cmp);
    *out = br;
    *n = nb;
    br = NULL;
    rc = 0;
fail:
    free(cum);
    free(idx);
    free(br);
    return rc;
}

/* Contract in gen_int.h. */
double td_gen_line_interval(const td_lines *lines, const td_gen_params *p)
{
    double best = INFINITY;
    size_t i, j;
    if (p->interval > 0.0)
        return p->interval;
    for (i = 0; i < lines->n; i++) /* distinct heights are few: fast */
        for (j = i + 1; j < lines->n && j < i + 64; j++) {
            double d = fabs(lines->v[i].height - lines->v[j].height);
            if (d > 1e-9 && d < best)
                best = d;
        }
    return isfinite(best) ? best : 0.0;
}

/* Contract in gen_int.h. */
double td_gen_width_of(const td_line *l, const td_gen_params *p,
                       double interval)
{
    double k;
    if (!(p->index_width > 0.0) || !(interval > 0.0) || !l->has_height)
        return p->line_width;
    k = floor((l->height - p->base) / interval + 0.5);
    return fabs(fmod(k, 5.0)) < 0.5 ? p->index_width : p->line_width;
}

/* Draw one line, leaving out the stretches [s0 - W/2, s1 + W/2] of its
 * breaks (cuts, sorted by s0). */
static void draw_line(uint8_t *lay, int w, int h, const td_line *l,
                      const td_gen_break *cuts, size_t ncut, double W)
{
    double r = 0.5 * W + 0.5, s = 0.0;
    size_t i, c, nseg;
    if (l->n == 1)
        td_gen_draw_seg(lay, w, h, l->xy[0], l->xy[1], l->xy[0], l->xy[1], r);
    nseg = l->n < 2 ? 0 : (l->closed ? l->n : l->n - 1);
    for (i = 0; i < nseg; i++) {
        const double *p = l->xy + 2 * i, *q = l->xy + 2 * ((i + 1) % l->n);
        double dx = q[0] - p[0], dy = q[1] - p[1],
               len = sqrt(dx * dx + dy * dy);
        double sa = s, sb = s + len, from = sa;
        s = sb;
        for (c = 0; c < ncut; c++) {
            double ca = cuts[c].s0 - 0.5 * W, cb = cuts[c].s1 + 0.5 * W;
            if (cb <= sa || ca >= sb)
                continue;
            if (ca > from) {
                double t0 = (from - sa) / len, t1 = (ca - sa) / len;
                td_gen_draw_seg(lay, w, h, p[0] + t0 * dx, p[1] + t0 * dy,
                                p[0] + t1 * dx, p[1] + t1 * dy, r);
            }
            from = cb > from ? cb : from;
        }
        if (from < sb || (len == 0.0 && ncut == 0)) {
            double t0 = len > 0.0 ? (from - sa) / len : 0.0;
            td_gen_draw_seg(lay, w, h, p[0] + t0 * dx, p[1] + t0 * dy, q[0],
                            q[1], r);
        }
    }
}

/* The ticks of depression line l (a ring, lower ground on its left on
 * the screen): every 8 widths (>= 12 px) along it, a stroke at right
 * angles into the ring, 1.5 widths (>= 2.5 px) beyond the ink, kept
 * within half the ring's mean half-width (2 area / perimeter): a ring
 * too small for a tick 1.5 px beyond its ink gets none. */
static void draw_ticks(uint8_t *lay, int w, int h, const td_line *l, double W)
{
    double per = td_line_length(l), step = fmax(12.0, 8.0 * W);
    double len = 0.5 * W + fmax(2.5, 1.5 * W), s = 0.0, next = 0.5 * step;
    double half = per > 0 ? 2.0 * fabs(td_line_signed_area(l)) / per : 0;
    size_t i;
    if (!l->closed || !l->depression || l->n < 3 || per <= 0)
        return;
    len = fmin(len, 0.5 * half);
    if (len < 0.5 * W + 1.5)
        return; /* a ring too small for ticks inside */
    for (i = 0; i < l->n; i++) {
        const double *p = l->xy + 2 * i, *q = l->xy + 2 * ((i + 1) % l->n);
        double dx = q[0] - p[0], dy = q[1] - p[1], d = hypot(dx, dy);
        while (d > 0 && next <= s + d) {
            double t = (next - s) / d, x = p[0] + t * dx, y = p[1] + t * dy;
            td_gen_draw_seg(lay, w, h, x, y, x + len * dy / d,
                            y - len * dx / d, 0.4 * W + 0.5);
            next += step;
        }
        s += d;
    }
}

static int draw_lines(uint8_t *lay, const td_lines *lines,
                      const td_gen_params *p, const td_gen_break *br,
                      size_t nbr, td_ctx *cx)
{
    double interval = td_gen_line_interval(lines, p);
    size_t i, b = 0;
    for (i = 0; i < lines->n; i++) {
        size_t e = b;
        while (b < nbr && br[b].line < i)
            b++;
        e = b;
        while (e < nbr && br[e].line == i)
            e++;
        draw_line(lay, p->w, p->h, &lines->v[i], br + b, e - b,
                  td_gen_width_of(&lines->v[i], p, interval));
        if (p->hachures)
            draw_ticks(lay, p->w, p->h, &lines->v[i],
                       td_gen_width_of(&lines->v[i], p, interval));
        if ((i & 4095) == 4095 &&
            td_progress(cx, "render", 0.8 * (double)i / lines->n) != 0)
            return TD_ECANCEL;
    }
    return 0;
}

static int check_params(const td_gen_params *p, td_ctx *cx)
{
    int rc = td_check_dims(p->w, p->h, "sheet", cx);
    if (rc)
        return rc;
    if (!(p->line_width > 0.0 && p->line_width <= 50.0) ||
        !(p->index_width >= 0.0 && p->index_width <= 50.0))
        return td_seterr(cx, TD_EINVAL, "render: line width %g or index "
                         "width %g not in (0,50]", p->line_width,
                         p->index_width);
    if (!(p->blur >= 0.0 && p->blur <= 50.0) ||
        !(p->noise >= 0.0 && p->noise <= 255.0))
        return td_seterr(cx, TD_EINVAL,
                         "render: blur %g or noise %g out of "
                         "range",
                         p->blur, p->noise);
    if (p->breaks > 0 &&
        !(p->break_min >= 0.0 && p->break_max >= p->break_min &&
          p->break_max <= 1000.0))
        return td_seterr(cx, TD_EINVAL, "render: break length %g..%g invalid",
                         p->break_min, p->break_max);
    if (p->specks < 0 || p->breaks < 0 || p->specks > 10000000 ||
        p->breaks > 10000000)
        return td_seterr(cx, TD_EINVAL, "render: specks/breaks out of range");
    return 0;
}

/* Colour: brown contours over cream, then the distractors. */
static int paint_colour(td_image *im, const uint8_t *lay,
                        const td_gen_params *p, const td_gen_break *br,
                        size_t nbr, td_ctx *cx)
{
    static const uint8_t brown[3] = {160, 90, 40};
    size_t i, n = (size_t)p->w * (size_t)p->h;
    uint8_t *scratch;
    if (p->print)
        return td_gen_print_plates(im, lay, p, br, nbr, cx);
    for (i = 0; i < n; i++) {
        im->data[3 * i] = 245;
        im->data[3 * i + 1] = 235;
        im->data[3 * i + 2] = 210;
    }
    td_gen_composite(im, lay, brown);
    if (!p->distractors)
        return 0;
    if (!(scratch = td_calloc(n, 1, cx)))
        return TD_ENOMEM;
    td_gen_distractors(im, lay, scratch, p, br, nbr);
    free(scratch);
    return 0;
}

static int render(const td_lines *lines, const td_gen_params *p, int scan,
                  td_image **sheet, td_ctx *cx)
{
    td_gen_break *br = NULL;
    size_t nbr = 0, i, n;
    td_image *im = NULL;
    uint8_t *lay = NULL;
    int rc;
    *sheet = NULL;
    if ((rc = check_params(p, cx)) != 0)
        return rc;
    if ((rc = td_gen_breaks(lines, p, &br, &nbr, cx)) != 0)
        return rc;
    rc = TD_ENOMEM;
    if (!(im = td_image_new(p->w, p->h, p->colour ? 3 : 1, cx)))
        goto fail;
    n = (size_t)p->w * (size_t)p->h;
    lay = p->colour ? td_calloc(n, 1, cx) : im->data; /* grey: draw in place */
    if (!lay)
        goto fail;
    if ((rc = draw_lines(lay, lines, p, br, nbr, cx)) != 0)
        goto fail;
    td_gen_specks(lay, p, br, nbr);
    if (p->colour) {
        if ((rc = paint_colour(im, lay, p, br, nbr, cx)) != 0)
            goto fail;
    } else {
        for (i = 0; i < n; i++)
            im->data[i] = (uint8_t)(255 - im->data[i]);
    }
    if (scan && (rc = td_gen_scan_effects(im, p, cx)) != 0)
        goto fail;
    *sheet = im;
    im = NULL;
    rc = 0;
fail:
    if (p->colour)
        free(lay);
    td_image_free(im);
    free(br);
    return rc;
}

/* Contract in gen.h. */
int td_gen_render(const td_lines *lines, const td_gen_params *p,
                  td_image **sheet, td_ctx *cx)
{
    return render(lines, p, 1, sheet, cx);
}

/* Contract in gen_int.h. */
int td_gen_render_clean(const td_lines *lines, const td_gen_params *p,
                        td_image **sheet, td_ctx *cx)
{
    return render(lines, p, 0, sheet, cx);
}

/* Contract in gen.h. */
double td_gen_ink_fraction(const td_image *im, int threshold)
{
    size_t ink = 0;
    int x, y, c;
    for (y = 0; y < im->h; y++) {
        const uint8_t *row = im->data + (size_t)y * im->stride;
        for (x = 0; x < im->w; x++) {
            int s = 0;
            for (c = 0; c < im->channels; c++)
                s += row[x * im->channels + c];
            ink += s < threshold * im->channels;
        }
    }
    return (double)ink / ((double)im->w * (double)im->h);
}
