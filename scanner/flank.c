/* Traced lines along another ink's stroke: flank.h. */
#include "scanner/flank.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Contract in flank.h. */
int td_flank_near(const uint8_t *bits, int w, int h, double x, double y)
{
    size_t stride = ((size_t)w + 7) / 8;
    int X = (int)floor(x), Y = (int)floor(y), v;
    int a = X - TD_FLANK_NEAR < 0 ? 0 : X - TD_FLANK_NEAR;
    int b = X + TD_FLANK_NEAR >= w ? w - 1 : X + TD_FLANK_NEAR;
    unsigned mask;
    if (a > b)
        return 0;
    /* the window's bits of a row at once: at most 2 bytes */
    _Static_assert(2 * TD_FLANK_NEAR + 1 <= 9, "a window row in 2 bytes");
    mask = (1u << (b - a + 1)) - 1u;
    for (v = Y - TD_FLANK_NEAR; v <= Y + TD_FLANK_NEAR; v++) {
        const uint8_t *row;
        unsigned bb;
        if (v < 0 || v >= h)
            continue;
        row = bits + (size_t)v * stride;
        bb = row[a >> 3];
        if (b >> 3 != a >> 3)
            bb |= (unsigned)row[b >> 3] << 8;
        if ((bb >> (a & 7)) & mask)
            return 1;
    }
    return 0;
}

/* On the open polyline xy (n points, arc lengths s): mark in cut[] the
 * points of every near stretch (gaps of up to TD_FLANK_GAP bridged)
 * longer than TD_FLANK_MIN.  near[] is overwritten.  Returns the number
 * of stretches. */
static long mark_cuts(const double *s, size_t n, uint8_t *near, uint8_t *cut)
{
    size_t i, last = SIZE_MAX;
    long runs = 0;
    for (i = 0; i < n; i++) { /* bridge short gaps between near points */
        if (!near[i])
            continue;
        if (last != SIZE_MAX && i > last + 1 && s[i] - s[last] <= TD_FLANK_GAP)
            memset(near + last + 1, 1, i - last - 1);
        last = i;
    }
    memset(cut, 0, n);
    for (i = 0; i < n;) {
        size_t j = i;
        if (!near[i]) {
            i++;
            continue;
        }
        while (j + 1 < n && near[j + 1])
            j++;
        if (s[j] - s[i] > TD_FLANK_MIN) {
            memset(cut + i, 1, j - i + 1);
            runs++;
        }
        i = j + 1;
    }
    return runs;
}

/* Whether the stretch of l from point e (an end) to point b, beside the
 * other ink, turns off the line's course before it: its chord at least
 * TD_FLANK_TURN degrees off the chord of the TD_FLANK_HOOK px beyond b
 * (step +1 or -1 from b, away from e). */
static int hooks(const td_line *l, const double *s, size_t e, size_t b,
                 int step)
{
    size_t c = b;
    double ax, ay, hx, hy, cs;
    while ((step > 0 ? c + 1 < l->n : c > 0) &&
           fabs(s[c] - s[b]) < TD_FLANK_HOOK)
        c = step > 0 ? c + 1 : c - 1;
    ax = l->xy[2 * b] - l->xy[2 * c], ay = l->xy[2 * b + 1] - l->xy[2 * c + 1];
    hx = l->xy[2 * e] - l->xy[2 * b], hy = l->xy[2 * e + 1] - l->xy[2 * b + 1];
    if ((ax == 0 && ay == 0) || (hx == 0 && hy == 0))
        return 0;
    cs = (ax * hx + ay * hy) / (hypot(ax, ay) * hypot(hx, hy));
    return cs < cos(TD_FLANK_TURN * M_PI / 180.0);
}

/* Contract in flank.h. */
int td_flank_axis(const uint8_t *bits, int w, int h, double x, double y, int r,
                  int disc, double *ux, double *uy)
{
    size_t stride = ((size_t)w + 7) / 8;
    int X = (int)floor(x), Y = (int)floor(y), dx, dy, n = 0;
    double mx = 0, my = 0, xx = 0, yy = 0, xy = 0, a;
    for (dy = -r; dy <= r; dy++)
        for (dx = -r; dx <= r; dx++) {
            int u = X + dx, v = Y + dy;
            if ((disc && dx * dx + dy * dy > r * r) || u < 0 || v < 0 ||
                u >= w || v >= h ||
                !((bits[(size_t)v * stride + (size_t)(u >> 3)] >> (u & 7)) & 1))
                continue;
            n++, mx += dx, my += dy;
            xx += (double)dx * dx, yy += (double)dy * dy, xy += (double)dx * dy;
        }
    if (n == 0)
        return 0;
    mx /= n, my /= n;
    xx = xx / n - mx * mx, yy = yy / n - my * my, xy = xy / n - mx * my;
    a = 0.5 * atan2(2 * xy, xx - yy);
    *ux = cos(a), *uy = sin(a);
    return n;
}

/* Whether the chord from (x0, y0) to (x1, y1) runs along the other ink's
 * strokes round (x0, y0): within TD_FLANK_ALONG degrees of the main axis
 * of its pixels in a (2 TD_FLANK_AXIS + 1)^2 window (td_flank_axis), with
 * at least 2 TD_FLANK_AXIS of them. */
static int along_ink(const uint8_t *bits, int w, int h, double x0, double y0,
                     double x1, double y1)
{
    double ux = 0, uy = 0, cx = x1 - x0, cy = y1 - y0;
    if (td_flank_axis(bits, w, h, x0, y0, TD_FLANK_AXIS, 0, &ux, &uy) <
            2 * TD_FLANK_AXIS ||
        (cx == 0 && cy == 0))
        return 0;
    return fabs(cx * ux + cy * uy) / hypot(cx, cy) >=
           cos(TD_FLANK_ALONG * M_PI / 180.0);
}

/* The corner of the hook at end e (0 or n - 1; step +1 from 0, -1 from
 * n - 1) whose stretch beside the other ink ends just before point b (the
 * first point past it): b when the line turns off its course there
 * (hooks) and the stretch is at least TD_FLANK_HOOK px long.  Else, when
 * the stretch is shorter than TD_FLANK_TIP, the first point q from b on, no
 * more than TD_FLANK_CORNER px past the stretch, where it does, provided
 * the chord from e to q runs along the other ink (along_ink): where a
 * contour crosses a road, the road's map has a gap (the crossing's pixels
 * are neither ink), so only the tip of a hook up the road's flank lies
 * beside it and its corner does not (the ridges print at 1233,746: 3 px
 * beside the road, the corner 2.8 px on).  Without the test along the
 * ink, a contour's end bent a little beside a stream lost its bend and
 * was joined to the next contour (Orkhon new print, 910,992); without
 * the limit on the stretch, a contour running beside a road for 11 px
 * lost them (Orkhon new print, 652,936; the ridges print's hook at
 * 1235,771 runs 6.4 px beside its road).  Returns the corner, or
 * SIZE_MAX. */
static size_t hook_corner(const td_line *l, const double *s,
                          const uint8_t *bits, int w, int h, size_t e, size_t b,
                          int step)
{
    size_t q = b, last = step > 0 ? b - 1 : b + 1; /* the stretch's end */
    double len = fabs(s[last] - s[e]);
    if (len >= TD_FLANK_HOOK && hooks(l, s, e, b, step))
        return b;
    if (len >= TD_FLANK_TIP)
        return SIZE_MAX;
    for (;; q = step > 0 ? q + 1 : q - 1) {
        if (fabs(s[q] - s[last]) > TD_FLANK_CORNER)
            return SIZE_MAX;
        if (fabs(s[q] - s[e]) >= TD_FLANK_HOOK && hooks(l, s, e, q, step))
            return along_ink(bits, w, h, l->xy[2 * e], l->xy[2 * e + 1],
                             l->xy[2 * q], l->xy[2 * q + 1])
                       ? q
                       : SIZE_MAX;
        if (step > 0 ? q + 1 >= l->n : q == 0)
            return SIZE_MAX;
    }
}

/* An open line's ends that hook along the other ink: the stretch from each
 * end while it stays within TD_FLANK_NEAR px of it, and on to the hook's
 * corner (hook_corner), is marked in cut[] (a contour crossing a road
 * whose end turns along the road's flank, shorter than TD_FLANK_MIN: the
 * joiner then pairs the hook's tip, heading along the road, with the next
 * contour's end).  A line near the other ink all along is left to
 * mark_cuts.  s: arc lengths.  Returns the number of ends marked. */
static long trim_ends(const td_line *l, const double *s, const uint8_t *bits,
                      int w, int h, uint8_t *cut)
{
    size_t n = l->n, i, j, q, q0 = 0;
    long r = 0;
    for (i = 0;
         i < n && td_flank_near(bits, w, h, l->xy[2 * i], l->xy[2 * i + 1]);
         i++)
        ;
    if (i == n)
        return 0;
    for (j = n;
         j > i && td_flank_near(bits, w, h, l->xy[2 * j - 2], l->xy[2 * j - 1]);
         j--)
        ;
    if (i > 0 && !cut[0] &&
        (q = hook_corner(l, s, bits, w, h, 0, i, 1)) != SIZE_MAX && q < j) {
        memset(cut, 1, q);
        q0 = q;
        r++;
    }
    if (j < n && !cut[n - 1] &&
        (q = hook_corner(l, s, bits, w, h, n - 1, j - 1, -1)) != SIZE_MAX &&
        q > q0) {
        memset(cut + q + 1, 1, n - 1 - q);
        r++;
    }
    return r;
}

/* Append to out the pieces of l's points pts (n) between the cut points,
 * walking from point off round to it again (a closed walk; 0 for an open
 * line, whose first and last points are l's own ends: they keep their
 * junction bits). */
static int add_pieces(td_lines *out, const td_line *l, const double *pts,
                      size_t n, const uint8_t *cut, size_t off, int w, int h,
                      td_ctx *cx)
{
    size_t i = 0;
#define AT(p) (((p) + off) % n)
    while (i < n) {
        size_t j = i, k;
        td_line *c;
        if (cut[AT(i)]) {
            i++;
            continue;
        }
        while (j + 1 < n && !cut[AT(j + 1)])
            j++;
        if (j > i) {
            if (!(c = td_lines_add_piece(out, l, cx)))
                return TD_ENOMEM;
            c->junc =
                (unsigned char)(l->closed ? 0u
                                          : ((i == 0 ? l->junc & 1u : 0u) |
                                             (j == n - 1 ? l->junc & 2u : 0u)));
            for (k = i; k <= j; k++)
                if (td_line_push(c, pts[2 * AT(k)], pts[2 * AT(k) + 1], cx) !=
                    0)
                    return TD_ENOMEM;
            c->edge = td_line_on_border(c, w, h);
        }
        i = j + 1;
    }
#undef AT
    return 0;
}

/* Contract in flank.h. */
long td_flank_cut(td_lines *ls, const uint8_t *bits, int w, int h, td_ctx *cx)
{
    td_lines *out = NULL;
    double *pts = NULL, *s = NULL;
    uint8_t *near = NULL, *cut = NULL;
    size_t i, cap = 0;
    long runs = 0;
    int rc = TD_ENOMEM;
    if (!bits || ls->n == 0)
        return 0;
    if (!(out = td_lines_new(cx)))
        return TD_ENOMEM;
    for (i = 0; i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        size_t n = l->n, m, k, k0 = 0;
        long r;
        int any;
        if (n + 2 > cap) {
            cap = 2 * (n + 2);
            free(pts), free(s), free(near), free(cut);
            pts = malloc(2 * cap * sizeof *pts);
            s = malloc(cap * sizeof *s);
            near = malloc(cap);
            cut = malloc(cap);
            if (!pts || !s || !near || !cut)
                goto fail;
        }
        for (k = 0, any = 0; k < n; k++) {
            near[k] = (uint8_t)td_flank_near(bits, w, h, l->xy[2 * k],
                                             l->xy[2 * k + 1]);
            any |= near[k];
        }
        if (!any) { /* most lines: nowhere near another ink */
            if (td_lines_append_copy(out, l, cx) != 0)
                goto fail;
            out->v[out->n - 1].id = (long)out->n - 1;
            continue;
        }
        /* a closed line is walked round from the middle of its longest
           stretch off the other ink (the gaps bridged are all inside) */
        if (l->closed && n >= 3) {
            size_t best = 0, run = 0, at = 0;
            for (k = 0; k < 2 * n; k++) {
                run = near[k % n] ? 0 : run + 1;
                if (run > best && run <= n)
                    best = run, at = k;
            }
            if (best == 0) { /* all of it along the other ink */
                if (td_line_length(l) > TD_FLANK_MIN) {
                    runs++;
                    continue;
                }
            } else {
                k0 = (at + n - best / 2) % n;
            }
        }
        m = l->closed && n >= 3 ? n + 1 : n;
        for (k = 0; k < m; k++) {
            size_t q = (k0 + k) % n;
            pts[2 * k] = l->xy[2 * q];
            pts[2 * k + 1] = l->xy[2 * q + 1];
            s[k] = k == 0 ? 0.0
                          : s[k - 1] + hypot(pts[2 * k] - pts[2 * k - 2],
                                             pts[2 * k + 1] - pts[2 * k - 1]);
        }
        for (k = 0; k < m; k++) /* near[] in the walk's order */
            cut[k] = near[(k0 + k) % n];
        memcpy(near, cut, m);
        r = mark_cuts(s, m, near, cut);
        if (!l->closed || n < 3)
            r += trim_ends(l, s, bits, w, h, cut);
        if (r == 0) {
            if (td_lines_append_copy(out, l, cx) != 0)
                goto fail;
            out->v[out->n - 1].id = (long)out->n - 1;
            continue;
        }
        runs += r;
        k0 = 0; /* a closed walk: from its first point cut, so no piece is
                   split where the walk starts */
        if (l->closed && n >= 3)
            for (m = n; !cut[k0]; k0++)
                ;
        if (add_pieces(out, l, pts, m, cut, k0, w, h, cx) != 0)
            goto fail;
    }
    /* the cut lines in place of ls's */
    for (i = 0; i < ls->n; i++)
        free(ls->v[i].xy);
    free(ls->v);
    *ls = *out;
    free(out);
    out = NULL;
    rc = 0;
fail:
    if (out)
        td_lines_free(out);
    free(pts), free(s), free(near), free(cut);
    return rc ? (long)td_seterr(cx, TD_ENOMEM, "flank: out of memory") : runs;
}
