/* Lines cut where their ink is too wide to tell contours apart
 * (widecut.h).  Three passes: every vertex's ink width against maxw and
 * against the line's own width + addw (on threads, line by line; where
 * contours crowd, narrowed to the rib contacts and, when asked, the
 * hairpins), the other lines near each wide stretch (a sorted list of the vertices that
 * fall in cells near a stretch), and the lines rebuilt without their wide
 * stretches.  Then, after labelling, the walls whose two sides agree. */
#include "scanner/widecut.h"

#include "scanner/width.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define WC_CHORD 3 /* vertices either side for the local direction */
#define WC_MIN 4   /* a wide stretch is at least this many vertices */
#define WC_CELL 8  /* px: cells of the near-stretch vertex list */
#define WC_RING 8  /* rings shorter than this many maxw stay whole */
#define WC_RIB_MARGIN 3 /* vertices cut either side of a rib contact */
/* The ribs are heeded, and hairpins cut (when asked: td_scan asks by
 * default), on sheets with at least
 * WC_RIB_DENSE blobs (stretches wider than maxw) a megapixel: where
 * contours crowd. */
#define WC_RIB_DENSE 60
#define WC_HP 6          /* the flag of a hairpin's vertex */
#define WC_HP_CHORD 8    /* vertices: the chords of a hairpin's turn */
#define WC_HP_COS (-0.7) /* cos of a hairpin's least turn (134 deg) */

typedef struct wstretch {
    size_t line, k, e; /* vertices [k, e) of line */
} wstretch;

typedef struct wvert {
    size_t cell, line;
    int end; /* the first or last vertex of an open line */
    double x, y;
} wvert;

/* Whether the ink across vertex k of l is wider than maxw: exact, with
 * the two points at the last step within maxw / 2 tested first (a run
 * from the middle longer than maxw / 2 on one side holds ink there). */
static int wide_at(const uint8_t *bits, int w, int h, const td_line *l,
                   size_t k, double maxw)
{
    double x = l->xy[2 * k], y = l->xy[2 * k + 1], nx, ny, t;
    if (!td_line_normal(l, k, WC_CHORD, &nx, &ny) ||
        !td_packed_at_pt(bits, w, h, x, y))
        return 0;
    t = td_width_step_below(0.5 * maxw);
    if (!td_packed_at_pt(bits, w, h, x + t * nx, y + t * ny) &&
        !td_packed_at_pt(bits, w, h, x - t * nx, y - t * ny))
        return 0;
    return td_width_across(bits, w, h, x, y, nx, ny) > maxw;
}

/* Whether a pixel of bits lies in the (2r + 1)^2 square round (x, y). */
static int ink_near(const uint8_t *bits, int w, int h, double x, double y,
                    int r)
{
    int cx = (int)floor(x), cy = (int)floor(y), dx, dy;
    for (dy = -r; dy <= r; dy++)
        for (dx = -r; dx <= r; dx++)
            if (td_packed_at(bits, w, h, cx + dx, cy + dy))
                return 1;
    return 0;
}

/* Of the vertices of l flagged wider than maxw (f[k] == 1), only those
 * within WC_RIB_MARGIN vertices of one where the line's own rib (the ink
 * with the seams taken out) is wider than ribw stay flagged: where the
 * seams split a blob into one rib a contour, a line follows its rib and
 * can only step onto the next one where two ribs touch. */
static void keep_contacts(const uint8_t *ribs, int w, int h, const td_line *l,
                          const td_wide_params *wp, unsigned char *f)
{
    size_t n = l->n, k;
    long m, ln = (long)n;
    int r = (int)ceil(0.5 * wp->maxw);
    for (k = 0; k < n; k++)
        if (f[k] == 1 && (wide_at(ribs, w, h, l, k, wp->ribw) ||
                          (wp->other && ink_near(wp->other, w, h, l->xy[2 * k],
                                                 l->xy[2 * k + 1], r))))
            f[k] = 3;
    for (k = 0; k < n; k++) /* the margin either side (round a ring) */
        if (f[k] == 3)
            for (m = -WC_RIB_MARGIN; m <= WC_RIB_MARGIN; m++) {
                long j = (long)k + m;
                if (l->closed)
                    j = (j + ln) % ln;
                if (j >= 0 && j < ln && f[j] == 1)
                    f[j] = 4;
            }
    for (k = 0; k < n; k++)
        f[k] = f[k] == 1 ? 0 : f[k] >= 3 ? 1 : f[k];
}

/* The vertices of open line l where it turns back (the chords of
 * WC_HP_CHORD vertices before and after meet at more than
 * acos(WC_HP_COS)) flagged WC_HP in f: where contours crowd, an open line
 * that turns back is mostly two contours whose inks met at a V's tip.
 * Rings are left alone: the tips of a narrow ring turn as sharply. */
static void flag_hairpins(const td_line *l, unsigned char *f)
{
    size_t n = l->n, k, c = WC_HP_CHORD;
    if (l->closed || n < 2 * c + 1)
        return;
    for (k = c; k + c < n; k++) {
        double ax = l->xy[2 * k] - l->xy[2 * (k - c)];
        double ay = l->xy[2 * k + 1] - l->xy[2 * (k - c) + 1];
        double bx = l->xy[2 * (k + c)] - l->xy[2 * k];
        double by = l->xy[2 * (k + c) + 1] - l->xy[2 * k + 1];
        double na = hypot(ax, ay), nb = hypot(bx, by);
        if (na > 0 && nb > 0 && ax * bx + ay * by < WC_HP_COS * na * nb)
            f[k] = WC_HP;
    }
}

/* Whether stretch s holds a hairpin's vertex. */
static int has_hairpin(const unsigned char *f, const wstretch *s)
{
    size_t k;
    for (k = s->k; k < s->e; k++)
        if (f[k] == WC_HP)
            return 1;
    return 0;
}

/* The wide vertices of every line (flags from off[i] on: 1 wider than
 * maxw, 2 only wider than the line's own width + addw), stretches shorter
 * than WC_MIN cleared; on threads. */
static void flag_lines(const uint8_t *bits, int w, int h, const td_lines *ls,
                       const size_t *off, const td_wide_params *wp,
                       unsigned char *wide)
{
    long n = (long)ls->n, i;
    double maxw = wp->maxw, addw = wp->addw;
#pragma omp parallel for schedule(dynamic, 16)
    for (i = 0; i < n; i++) {
        const td_line *l = &ls->v[i];
        unsigned char *f = wide + off[i];
        double own = addw > 0 && l->width > 0 ? l->width + addw : maxw;
        size_t k, e;
        if (l->n < 2 * WC_MIN ||
            (l->closed && td_line_length(l) < WC_RING * maxw))
            continue;
        for (k = 0; k < l->n; k++)
            f[k] = wide_at(bits, w, h, l, k, maxw)                 ? 1
                   : own < maxw && wide_at(bits, w, h, l, k, own) ? 2
                                                                   : 0;
        for (k = 0; k < l->n; k = e) {
            for (e = k; e < l->n && !f[e] == !f[k]; e++)
                ;
            if (f[k] && e - k < WC_MIN)
                memset(f + k, 0, e - k);
        }
    }
}

/* The stretches of flag 1 (wider than maxw) over every line. */
static size_t count_blobs(const td_lines *ls, const size_t *off,
                          const unsigned char *wide)
{
    size_t i, k, nb = 0;
    for (i = 0; i < ls->n; i++)
        for (k = 0; k < ls->v[i].n; k++)
            nb +=
                wide[off[i] + k] == 1 && (k == 0 || wide[off[i] + k - 1] != 1);
    return nb;
}

static int cmp_wvert(const void *a, const void *b)
{
    const wvert *p = a, *q = b;
    if (p->cell != q->cell)
        return (p->cell > q->cell) - (p->cell < q->cell);
    return (p->line > q->line) - (p->line < q->line);
}

/* The cells within r of vertices [k, e) of l marked in cm (cw x ch). */
static void mark_cells(const td_line *l, size_t k, size_t e, double r, int cw,
                       int ch, unsigned char *cm)
{
    for (; k < e; k++) {
        int x0 = (int)floor((l->xy[2 * k] - r) / WC_CELL);
        int x1 = (int)floor((l->xy[2 * k] + r) / WC_CELL);
        int y0 = (int)floor((l->xy[2 * k + 1] - r) / WC_CELL);
        int y1 = (int)floor((l->xy[2 * k + 1] + r) / WC_CELL);
        int cx, cy;
        for (cy = y0 < 0 ? 0 : y0; cy <= y1 && cy < ch; cy++)
            for (cx = x0 < 0 ? 0 : x0; cx <= x1 && cx < cw; cx++)
                cm[(size_t)cy * (size_t)cw + (size_t)cx] = 1;
    }
}

/* Whether a vertex of another line than s->line (with ends: an end of
 * one) lies within r of the stretch s (v: the vertices in marked cells,
 * sorted by cell). */
static int other_near(const td_line *l, const wstretch *s, double r, int cw,
                      int ch, const wvert *v, size_t nv, int ends)
{
    size_t k;
    for (k = s->k; k < s->e; k++) {
        double x = l->xy[2 * k], y = l->xy[2 * k + 1];
        int x0 = (int)floor((x - r) / WC_CELL),
            x1 = (int)floor((x + r) / WC_CELL);
        int y0 = (int)floor((y - r) / WC_CELL),
            y1 = (int)floor((y + r) / WC_CELL);
        int cx, cy;
        for (cy = y0 < 0 ? 0 : y0; cy <= y1 && cy < ch; cy++)
            for (cx = x0 < 0 ? 0 : x0; cx <= x1 && cx < cw; cx++) {
                size_t c = (size_t)cy * (size_t)cw + (size_t)cx, lo = 0,
                       hi = nv;
                while (lo < hi) { /* the cell's first vertex */
                    size_t mid = lo + (hi - lo) / 2;
                    if (v[mid].cell < c)
                        lo = mid + 1;
                    else
                        hi = mid;
                }
                for (; lo < nv && v[lo].cell == c; lo++)
                    if (v[lo].line != s->line && (v[lo].end || !ends) &&
                        hypot(v[lo].x - x, v[lo].y - y) <= r)
                        return 1;
            }
    }
    return 0;
}

/* Line l without its flagged vertices, as pieces appended to out. */
static int cut_line(const td_line *l, const unsigned char *f, int w, int h,
                    long *next_id, td_lines *out, td_ctx *cx)
{
    size_t n = l->n, start = 0, s, e, k;
    int first = 1;
    if (l->closed) /* start just after a wide stretch */
        for (k = 0; k < n; k++)
            if (f[k] && !f[(k + 1) % n]) {
                start = (k + 1) % n;
                break;
            }
    for (s = 0; s < n; s = e) {
        td_line *c;
        for (e = s; e < n && !f[(start + e) % n]; e++)
            ;
        if (e - s >= 3) {
            if (!(c = td_lines_add(out, cx)))
                return TD_ENOMEM;
            {
                td_line keep = *c;
                *c = *l;
                c->xy = keep.xy, c->n = keep.n, c->cap = keep.cap;
            }
            c->id = first ? l->id : (*next_id)++;
            first = 0;
            c->closed = 0;
            c->width = 0.0;
            c->depression = 0;
            c->junc = (unsigned char)((s > 0 || l->closed ? 1 : l->junc & 1) |
                                      (e < n || l->closed ? 2 : l->junc & 2));
            for (k = s; k < e; k++)
                if (td_line_push(c, l->xy[2 * ((start + k) % n)],
                                 l->xy[2 * ((start + k) % n) + 1], cx) != 0)
                    return TD_ENOMEM;
            c->edge = td_line_on_border(c, w, h);
        }
        for (; e < n && f[(start + e) % n]; e++)
            ;
    }
    return 0;
}

/* Contract in widecut.h. */
long td_wide_cut(const uint8_t *bits, int w, int h, td_lines *ls, double maxw,
                 td_ctx *cx)
{
    td_wide_params wp = {maxw, 0.0, NULL, 0.0, NULL, 0};
    return td_wide_cut_walls(bits, w, h, ls, &wp, NULL, cx);
}

/* Whether stretch s holds WC_MIN vertices in a row wider than maxw. */
static int over_maxw(const unsigned char *f, const wstretch *s)
{
    size_t k, run = 0;
    for (k = s->k; k < s->e; k++)
        if ((run = f[k] == 1 ? run + 1 : 0) >= WC_MIN)
            return 1;
    return 0;
}

/* Stretch s of l, with the vertex either side of it, as a wall. */
static int add_wall(const td_line *l, const wstretch *s, td_lines *walls,
                    td_ctx *cx)
{
    size_t n = l->n, a, b, cnt, k;
    td_line *o;
    a = s->k > 0 ? s->k - 1 : l->closed ? n - 1 : 0;
    b = s->e < n ? s->e : l->closed ? 0 : n - 1;
    cnt = (b + n - a) % n + 1;
    if (!(o = td_lines_add(walls, cx)))
        return TD_ENOMEM;
    for (k = 0; k < cnt; k++)
        if (td_line_push(o, l->xy[2 * ((a + k) % n)],
                         l->xy[2 * ((a + k) % n) + 1], cx) != 0)
            return TD_ENOMEM;
    return 0;
}

long td_wide_cut_walls(const uint8_t *bits, int w, int h, td_lines *ls,
                       const td_wide_params *wp, td_lines *walls, td_ctx *cx)
{
    double maxw = wp->maxw;
    size_t *off = td_malloc((ls->n + 1) * sizeof *off, cx), i, k, e, tot = 0;
    size_t ns = 0, scap = 0, nv = 0, vcap = 0;
    unsigned char *wide = NULL, *cm = NULL, *cut = NULL;
    wstretch *st = NULL;
    wvert *v = NULL;
    td_lines *out = NULL;
    double r = 0.5 * maxw + 1.0;
    int cw = w / WC_CELL + 1, ch = h / WC_CELL + 1;
    long ncut = 0, next_id = 0;
    if (!off)
        return TD_ENOMEM;
    for (i = 0; i < ls->n; i++) {
        off[i] = tot;
        tot += ls->v[i].n;
        next_id = ls->v[i].id >= next_id ? ls->v[i].id + 1 : next_id;
    }
    if (!(wide = td_calloc(tot + 1, 1, cx)))
        goto nomem;
    flag_lines(bits, w, h, ls, off, wp, wide);
    if (wp->ribs && wp->ribw > 0 &&
        (double)count_blobs(ls, off, wide) * 1e6 >=
            WC_RIB_DENSE * (double)w * (double)h)
        for (i = 0; i < ls->n; i++) {
            keep_contacts(wp->ribs, w, h, &ls->v[i], wp, wide + off[i]);
            if (wp->hairpins)
                flag_hairpins(&ls->v[i], wide + off[i]);
        }
    for (i = 0; i < ls->n; i++) /* the stretches */
        for (k = 0; k < ls->v[i].n; k = e) {
            for (e = k; e < ls->v[i].n && wide[off[i] + e]; e++)
                ;
            if (e == k) {
                e++;
                continue;
            }
            if (td_grow((void **)&st, &scap, ns + 1, sizeof *st, cx) != 0)
                goto nomem;
            st[ns].line = i, st[ns].k = k, st[ns++].e = e;
        }
    if (ns == 0) {
        free(off), free(wide);
        return 0;
    }
    if (!(cm = td_calloc((size_t)cw * (size_t)ch, 1, cx)) ||
        !(cut = td_calloc(ls->n + 1, 1, cx)))
        goto nomem;
    for (i = 0; i < ns; i++)
        mark_cells(&ls->v[st[i].line], st[i].k, st[i].e, r, cw, ch, cm);
    for (i = 0; i < ls->n; i++) /* the vertices in marked cells */
        for (k = 0; k < ls->v[i].n; k++) {
            double x = ls->v[i].xy[2 * k], y = ls->v[i].xy[2 * k + 1];
            size_t c;
            if (!(x >= 0 && y >= 0 && x < w && y < h))
                continue;
            c = (size_t)(y / WC_CELL) * (size_t)cw + (size_t)(x / WC_CELL);
            if (!cm[c])
                continue;
            if (td_grow((void **)&v, &vcap, nv + 1, sizeof *v, cx) != 0)
                goto nomem;
            v[nv].end = !ls->v[i].closed && (k == 0 || k + 1 == ls->v[i].n);
            v[nv].cell = c, v[nv].line = i, v[nv].x = x, v[nv++].y = y;
        }
    qsort(v, nv, sizeof *v, cmp_wvert);
    for (i = 0; i < ns; i++) { /* a stretch in its own ink is no merge */
        const wstretch *s = &st[i];
        if (has_hairpin(wide + off[s->line], s) ||
            other_near(&ls->v[s->line], s, r, cw, ch, v, nv,
                       !over_maxw(wide + off[s->line], s))) {
            cut[s->line] = 1;
            if (walls && add_wall(&ls->v[s->line], s, walls, cx) != 0)
                goto nomem;
        } else
            memset(wide + off[s->line] + s->k, 0, s->e - s->k);
    }
    if (!(out = td_lines_new(cx)))
        goto nomem;
    for (i = 0; i < ls->n; i++) {
        int rc =
            cut[i] ? cut_line(&ls->v[i], wide + off[i], w, h, &next_id, out, cx)
                   : td_lines_append_copy(out, &ls->v[i], cx);
        if (rc != 0)
            goto nomem;
        ncut += cut[i];
    }
    for (i = 0; i < ls->n; i++)
        free(ls->v[i].xy);
    free(ls->v);
    *ls = *out;
    free(out);
    free(off), free(wide), free(cm), free(cut), free(st), free(v);
    return ncut;
nomem:
    td_lines_free(out);
    free(off), free(wide), free(cm), free(cut), free(st), free(v);
    return td_seterr(cx, TD_ENOMEM, "wide ink cut: out of memory");
}

/* The line of ls with a height whose end (of ends, sorted) is at (x, y);
 * -1 when none. */
static long line_ending_at(const td_lines *ls, const td_line_end *ends,
                           size_t ne, double x, double y)
{
    size_t k;
    for (k = td_line_ends_at(ends, ne, x, y);
         k < ne && ends[k].x == x && ends[k].y == y; k++)
        if (ls->v[ends[k].line].has_height)
            return (long)ends[k].line;
    return -1;
}

/* Contract in widecut.h. */
long td_walls_restore(td_lines *ls, const td_lines *walls, td_ctx *cx)
{
    size_t nl = ls->n, ne = 0, i;
    td_line_end *ends;
    long next_id = 0, put = 0;
    if (!walls || walls->n == 0)
        return 0;
    if (td_line_ends(ls, NULL, NULL, &ends, &ne, cx) != 0)
        return TD_ENOMEM;
    for (i = 0; i < nl; i++)
        next_id = ls->v[i].id >= next_id ? ls->v[i].id + 1 : next_id;
    for (i = 0; i < walls->n; i++) {
        const td_line *wl = &walls->v[i];
        long a, b;
        const td_line *la, *lb, *weak;
        td_line *o;
        size_t k;
        if (wl->n < 2)
            continue;
        a = line_ending_at(ls, ends, ne, wl->xy[0], wl->xy[1]);
        b = line_ending_at(ls, ends, ne, wl->xy[2 * wl->n - 2],
                           wl->xy[2 * wl->n - 1]);
        if (a < 0 || b < 0)
            continue;
        la = &ls->v[a], lb = &ls->v[b];
        if (la->height != lb->height)
            continue;
        if (!(o = td_lines_add(ls, cx))) {
            free(ends);
            return TD_ENOMEM;
        }
        la = &ls->v[a], lb = &ls->v[b]; /* td_lines_add may move them */
        weak = la->confidence <= lb->confidence ? la : lb;
        o->id = next_id++;
        o->has_height = 1;
        o->height = la->height;
        o->hsource = weak->hsource;
        o->confidence = weak->confidence;
        for (k = 0; k < wl->n; k++)
            if (td_line_push(o, wl->xy[2 * k], wl->xy[2 * k + 1], cx) != 0) {
                free(ends);
                return TD_ENOMEM;
            }
        put++;
    }
    free(ends);
    return put;
}
