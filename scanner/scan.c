/* The scanner stage driver (paper 001 §2.1-2.3): each step is its own
 * file; this one only sequences them and keeps the debug copies. */
#include "scanner/scan.h"

#include "scanner/blobring.h"
#include "scanner/bordercut.h"
#include "scanner/detint.h"
#include "scanner/flank.h"
#include "scanner/foreign.h"
#include "scanner/streams.h"
#include "scanner/ticks.h"
#include "scanner/widecut.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

td_scan_params td_scan_defaults(void)
{
    td_scan_params p;
    memset(&p, 0, sizeof p);
    p.bin = td_binarise_defaults();
    p.spur = td_despur_defaults();
    p.trace = td_trace_defaults();
    p.join = td_join_defaults(0, 0);
    p.do_join = 1;
    p.measure_width = 1;
    p.blob_rings = 1;
    p.ticks = 2;
    p.wide_cut = 3.0;
    p.wide_rib = 2.2;
    p.hairpin_cut = 1;
    p.wide_own = -1.0;
    p.join_other = 1;
    p.flank_cut = 1;
    p.foreign_cut = 1;
    p.border_cut = 1;
    p.straight = td_straight_defaults();
    p.defringe = 0;
    p.fringe = td_defringe_defaults();
    p.detint = 0;
    p.pale = 1;
    p.pale_p = td_pale_defaults();
    return p;
}

void td_scan_result_free(td_scan_result *res)
{
    td_lines_free(res->lines);
    td_lines_free(res->walls);
    td_join_stats_free(&res->join);
    td_grid_u8_free(res->mask);
    td_grid_u8_free(res->skeleton);
    td_grid_u8_free(res->despurred);
    free(res->skel_bits);
    free(res->other);
    memset(res, 0, sizeof *res);
}

/* Bytes of a w x h mask packed one bit a pixel (td_width_pack). */
static size_t packed_bytes(int w, int h)
{
    return (size_t)h * (((size_t)w + 7) / 8) + 1;
}

/* The skeleton g packed one bit a pixel, less the pixels within
 * TD_FLANK_NEAR px of other's strokes (may be NULL); NULL when out of
 * memory. */
/* Before (when = 0) and after (1) a step that cuts lines: the pixels
 * of the stretches it cut out go into lost (both packed w x h; tmp the
 * lines as they were). */
static void lost_track(const td_lines *ls, int when, int w, int h, uint8_t *tmp,
                       uint8_t *lost)
{
    size_t n = packed_bytes(w, h), i;
    if (!when) {
        memset(tmp, 0, n);
        td_packed_lines(tmp, w, h, ls, NULL, 0, 1);
        return;
    }
    {
        uint8_t *now = tmp + n; /* (tmp holds two maps) */
        memset(now, 0, n);
        td_packed_lines(now, w, h, ls, NULL, 0, 1);
        for (i = 0; i < n; i++)
            lost[i] |= (uint8_t)(tmp[i] & ~now[i]);
    }
}

/* The skeleton g packed one bit a pixel for the labeller's step edges,
 * less the pixels within TD_FLANK_NEAR px of other's strokes (may be
 * NULL) and those within a pixel of lost (lost_track: the stretches cut
 * out along other inks, flank.c and foreign.c: a road's flanks, a ring's
 * stretch under a road); NULL when out of memory. */
static uint8_t *skeleton_bits(const td_grid_u8 *g, const uint8_t *other,
                              const uint8_t *lost, int w, int h, td_ctx *cx)
{
    size_t row = ((size_t)w + 7) / 8;
    uint8_t *b = td_calloc(packed_bytes(w, h) + 1, 1, cx);
    int x, y;
    if (!b)
        return NULL;
#pragma omp parallel for private(x) schedule(static)
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            int cut = 0, dx, dy;
            if (!g->data[(size_t)y * g->stride + (size_t)x] ||
                (other && td_flank_near(other, w, h, x + 0.5, y + 0.5)))
                continue;
            for (dy = -1; dy <= 1 && !cut; dy++)
                for (dx = -1; dx <= 1 && !cut; dx++)
                    cut = td_packed_at(lost, w, h, x + dx, y + dy);
            if (!cut)
                b[(size_t)y * row + (size_t)x / 8] |= (uint8_t)(1u << (x & 7));
        }
    return b;
}

/* The short pieces the joiner set aside (td_join_params.keep_pieces
 * TD_PIECES_LATE) back among the lines after the cuts, so that none of
 * the cuts sees them (the other lines come out as without them): those
 * of another ink's colour dropped, their widths measured, new ids. */
static int put_pieces(td_scan_result *res, const td_image *im,
                      const uint8_t *bits, const uint8_t *other, int foreign,
                      int widths, td_ctx *cx)
{
    td_lines *pc = res->join.late;
    size_t i;
    long id = 0;
    int rc;
    if (foreign) {
        long nf = td_foreign_cut(pc, im, &res->palette, other, cx);
        if (nf < 0)
            return (int)nf;
        res->foreign += (size_t)nf;
    }
    if (widths && (rc = td_line_widths_packed(bits, im->w, im->h, pc, cx)) != 0)
        return rc;
    for (i = 0; i < res->lines->n; i++)
        id = res->lines->v[i].id >= id ? res->lines->v[i].id + 1 : id;
    for (i = 0; i < pc->n; i++) {
        pc->v[i].id = id++;
        if ((rc = td_lines_append_copy(res->lines, &pc->v[i], cx)) != 0)
            return rc;
    }
    td_lines_free(pc);
    res->join.late = NULL;
    return 0;
}

int td_scan(const td_image *im, const td_scan_params *p, td_scan_result *res,
            td_ctx *cx)
{
    td_grid_u8 *g = NULL;
    uint8_t *lost = NULL, *lost_tmp = NULL; /* p->skel_bits: lost_track */
    td_image *clean = NULL; /* the scan defringed (colour) */
    const td_image *src = im;
    uint8_t *bits = NULL, *seams = NULL, *other = NULL, *water = NULL;
    td_join_params jp = p->join;
    td_binarise_params bin = p->bin;
    td_palette pal;
    td_image *vsrc = NULL; /* the scan with its tints divided out */
    uint8_t *pale = NULL;  /* faded lines' ridges, till the ink is traced */
    double t0, halftone = -1;
    int rc;
    memset(res, 0, sizeof *res);
    res->edge = -1;
    if (!(g = td_grid_u8_new(im->w, im->h, cx)))
        return cx ? cx->code : TD_ENOMEM;
    t0 = td_now();
    /* the seams split touching lines in the mask; the wide-ink cut
       measures across lines and seams (the ink before the split) */
    if (p->measure_width && p->wide_cut > 0 && p->bin.split > 0 &&
        !(seams = td_calloc(packed_bytes(im->w, im->h), 1, cx))) {
        rc = TD_ENOMEM;
        goto fail;
    }
    if (p->defringe && im->channels == 3 &&
        (p->bin.ink == TD_INK_AUTO || p->bin.ink == TD_INK_BROWN)) {
        if (!(clean = td_image_new(im->w, im->h, 3, cx))) {
            rc = TD_ENOMEM;
            goto fail;
        }
        if ((rc = td_defringe(im, clean, &p->fringe, cx)) != 0)
            goto fail;
        src = clean;
    }
    if (p->detint && src->channels == 3 &&
        (p->bin.ink == TD_INK_AUTO || p->bin.ink == TD_INK_BROWN)) {
        /* inks over a tint divided by it, for the veto only: the palette
           is found on the scan as it is and kept, and the contour ink's
           strength read there too (JPEG's colour blur leaves thin lines
           over a tint the tint's hue, which the division overshoots) */
        if ((rc = td_palette_find(src, &pal, cx)) != 0)
            goto fail;
        if (td_palette_choose(&pal, p->bin.ink == TD_INK_BROWN) >= 0 &&
            td_detint_any(&pal)) {
            if (!(vsrc = td_image_new(im->w, im->h, 3, cx))) {
                rc = TD_ENOMEM;
                goto fail;
            }
            if ((rc = td_detint(src, &pal, TD_DETINT_RADIUS, vsrc, cx)) != 0)
                goto fail;
            bin.veto_im = vsrc;
        }
        bin.palette = &pal;
    }
    if ((rc = td_binarise_seams(src, &bin, g, &res->palette, seams, &halftone,
                                &other, cx)) != 0 ||
        (rc = td_straight_remove(g, &p->straight, &res->straight_lines, cx)) !=
            0)
        goto fail;
    res->seconds[0] = td_now() - t0;
    if (p->pale && (rc = td_pale_find(src, &res->palette, g, other, &p->pale_p,
                                      &pale, cx)) != 0)
        goto fail;
    rc = TD_ENOMEM;
    if (p->keep_debug && !(res->mask = td_grid_u8_dup(g, cx)))
        goto fail;
    if (p->measure_width && !(bits = td_width_pack(g, cx)))
        goto fail;
    t0 = td_now();
    if ((rc = td_thin_hilditch(g, &res->thin, cx)) != 0)
        goto fail;
    res->seconds[1] = td_now() - t0;
    rc = TD_ENOMEM;
    if (p->keep_debug && !(res->skeleton = td_grid_u8_dup(g, cx)))
        goto fail;
    t0 = td_now();
    if ((rc = td_despur(g, &p->spur, &res->spur, cx)) != 0)
        goto fail;
    res->seconds[2] = td_now() - t0;
    t0 = td_now();
    if ((rc = td_trace(g, &p->trace, &res->lines, &res->trace, cx)) != 0)
        goto fail;
    if (p->skel_bits && /* what the cuts along other inks take */
        (!(lost = td_calloc(packed_bytes(im->w, im->h), 1, cx)) ||
         !(lost_tmp = td_malloc(2 * packed_bytes(im->w, im->h), cx)))) {
        rc = TD_ENOMEM;
        goto fail;
    }
    if (pale) { /* traced apart, added to the ink's lines */
        long np = td_pale_trace(pale, im->w, im->h, &p->pale_p, &p->spur,
                                &p->trace, res->lines, cx);
        free(pale);
        pale = NULL;
        if (np < 0) {
            rc = (int)np;
            goto fail;
        }
        res->pale = (size_t)np;
    }
    if (p->border_cut) {
        long nb = td_border_cut(res->lines, im->w, im->h, cx);
        if (nb < 0) {
            rc = (int)nb;
            goto fail;
        }
        res->border_cuts = (size_t)nb;
    }
    res->seconds[3] = td_now() - t0;
    t0 = td_now();
    jp.w = im->w;
    jp.h = im->h;
    jp.record = jp.record || p->keep_debug; /* the overlay draws the joins */
    if (!(p->do_join && p->join_other)) {   /* binarisation's veto bits (the
                                                other inks) not wanted */
        free(other);
        other = NULL;
    }
    jp.other = other;
    if (p->do_join && p->join_other && p->join.cross_gap > 0 &&
        (rc = td_streams_water_bits(src, &res->palette, &water, cx)) != 0)
        goto fail;
    jp.water = water;
    if (p->flank_cut && other) {
        long nf;
        if (lost)
            lost_track(res->lines, 0, im->w, im->h, lost_tmp, lost);
        nf = td_flank_cut(res->lines, other, im->w, im->h, cx);
        if (lost)
            lost_track(res->lines, 1, im->w, im->h, lost_tmp, lost);
        if (nf < 0) {
            rc = (int)nf;
            goto fail;
        }
        res->flank_cuts = (size_t)nf;
    }
    td_image_free(clean);
    td_image_free(vsrc);
    clean = vsrc = NULL;
    rc = p->do_join ? td_join(&res->lines, &jp, &res->join, cx) : 0;
    if (rc == 0 && p->foreign_cut) {
        long nf;
        if (lost)
            lost_track(res->lines, 0, im->w, im->h, lost_tmp, lost);
        nf = td_foreign_cut(res->lines, im, &res->palette, other, cx);
        if (lost)
            lost_track(res->lines, 1, im->w, im->h, lost_tmp, lost);
        if (nf < 0)
            rc = (int)nf;
        else
            res->foreign = (size_t)nf;
    }
    free(water);
    water = NULL;
    if (rc == 0 && p->skel_bits &&
        !(res->skel_bits = skeleton_bits(g, other, lost, im->w, im->h, cx)))
        rc = TD_ENOMEM;
    free(lost), free(lost_tmp);
    lost = lost_tmp = NULL;
    if (rc != 0)
        goto fail;
    if (p->measure_width &&
        (rc = td_line_widths_packed(bits, im->w, im->h, res->lines, cx)) != 0)
        goto fail;
    if (p->measure_width && p->wide_cut > 0) {
        double pen = td_pen_width(res->lines, cx), own = p->wide_own;
        td_wide_params wp;
        long nc;
        if (pen > 0 && halftone >= 0)
            res->edge = 0.5 * halftone * pen;
        if (own < 0) /* auto: where the ink is crisp */
            own = res->edge >= 0 && res->edge < TD_SCAN_CRISP_EDGE
                      ? TD_SCAN_WIDE_OWN
                      : 0.0;
        res->wide_own = own;
        if (seams) {
            size_t q, nb = packed_bytes(im->w, im->h);
            for (q = 0; q < nb; q++)
                seams[q] |= bits[q];
        }
        if (!(res->walls = td_lines_new(cx))) {
            rc = TD_ENOMEM;
            goto fail;
        }
        wp.maxw = p->wide_cut * pen;
        wp.addw = own * pen;
        wp.ribs = seams ? bits : NULL; /* the ink the seams split */
        wp.ribw = p->wide_rib * pen;
        wp.other = other;
        wp.hairpins = p->hairpin_cut;
        nc = pen > 0   ? td_wide_cut_walls(seams ? seams : bits, im->w, im->h,
                                         res->lines, &wp, res->walls, cx)
             : pen < 0 ? TD_ENOMEM
                       : 0;
        if (nc < 0 ||
            (nc > 0 && (rc = td_line_widths_packed_unset(
                            bits, im->w, im->h, res->lines, cx)) != 0)) {
            rc = nc < 0 ? (int)nc : rc;
            goto fail;
        }
        res->wide_cuts = (size_t)nc;
    }
    if (res->join.late && (rc = put_pieces(res, im, bits, other, p->foreign_cut,
                                           p->measure_width, cx)) != 0)
        goto fail;
    if (p->keep_debug)
        res->other = other;
    else
        free(other);
    other = NULL;
    if (p->measure_width && p->blob_rings) {
        long nr = td_blob_rings(bits, im->w, im->h, res->lines, cx);
        if (nr < 0) {
            rc = (int)nr;
            goto fail;
        }
        res->blob_rings = (size_t)nr;
    }
    {
        long np = td_point_rings(res->lines, cx);
        if (np < 0) {
            rc = (int)np;
            goto fail;
        }
    }
    if (p->measure_width && p->ticks > 0) {
        long nd = td_ticks_mark(res->lines, bits, im->w, im->h, p->ticks,
                                cx);
        if (nd < 0) {
            rc = (int)nd;
            goto fail;
        }
        res->depressions = (size_t)nd;
    }
    if (p->measure_width && (rc = td_line_darkness(im, res->lines, cx)) != 0)
        goto fail;
    res->seconds[4] = td_now() - t0;
    res->despurred = g;
    free(bits);
    free(seams);
    return 0;
fail:
    free(lost), free(lost_tmp);
    free(pale);
    td_image_free(clean);
    td_image_free(vsrc);
    free(other);
    free(water);
    free(bits);
    free(seams);
    td_grid_u8_free(g);
    td_scan_result_free(res);
    return rc;
}
