/* report.c: a one-page handout of a reconstruction (issue 17; ours),
 * drawn with cairo to PDF, vector graphics where it can be:
 *
 *   +--------------------------------------------+
 *   | title, date                                |
 *   | (a) the sheet, lines  | (b) shaded relief,  |
 *   |     by height         |     contours        |
 *   | (c) 3-D view          | (d) cross-section   |
 *   |                       |     (vector)        |
 *   | the figures (area, relief, lines, interval, |
 *   | what was inferred)                          |
 *   +--------------------------------------------+
 *
 * Pictures (a)-(c) are embedded images (at most 1600 px a side); the
 * cross-section, its axes and all text are vector graphics. */
#include "src/pipeline/pipeline.h"

#include "src/render/render.h"

#include <cairo/cairo-pdf.h>
#include <cairo/cairo.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MARGIN 36.0
#define GUTTER 14.0
#define TOP 78.0
#define PANEL_H 236.0
#define CAPTION 16.0
#define MAX_EMBED 1600

/* See pipeline.h. */
void td_report_layout(int letter, double *pw, double *ph, double rect[4][4])
{
    double w = letter ? 612 : 595.28, h = letter ? 792 : 841.89;
    double cw = (w - 2 * MARGIN - GUTTER) / 2;
    int k;
    *pw = w, *ph = h;
    for (k = 0; k < 4; k++) {
        rect[k][0] = MARGIN + (k % 2) * (cw + GUTTER);
        rect[k][1] = TOP + (k / 2) * (PANEL_H + CAPTION + GUTTER);
        rect[k][2] = cw;
        rect[k][3] = PANEL_H;
    }
}

static cairo_status_t put(void *closure, const unsigned char *data,
                          unsigned int n)
{
    return fwrite(data, 1, n, (FILE *)closure) == n ? CAIRO_STATUS_SUCCESS
                                                   : CAIRO_STATUS_WRITE_ERROR;
}

/* im as a cairo image, box-averaged down to at most MAX_EMBED a side. */
static cairo_surface_t *surface_of(const td_image *im)
{
    int f = 1, w, h, x, y, stride;
    cairo_surface_t *s;
    unsigned char *d;
    while ((im->w + f - 1) / f > MAX_EMBED || (im->h + f - 1) / f > MAX_EMBED)
        f++;
    w = im->w / f > 0 ? im->w / f : 1, h = im->h / f > 0 ? im->h / f : 1;
    s = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h);
    if (cairo_surface_status(s) != CAIRO_STATUS_SUCCESS)
        return s;
    cairo_surface_flush(s);
    d = cairo_image_surface_get_data(s);
    stride = cairo_image_surface_get_stride(s);
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            unsigned sum[3] = {0, 0, 0}, n = 0;
            int i, j, c;
            for (j = 0; j < f && y * f + j < im->h; j++)
                for (i = 0; i < f && x * f + i < im->w; i++) {
                    const uint8_t *p = im->data +
                                       (size_t)(y * f + j) * im->stride +
                                       (size_t)(x * f + i) * im->channels;
                    for (c = 0; c < 3; c++)
                        sum[c] += p[im->channels >= 3 ? c : 0];
                    n++;
                }
            ((uint32_t *)(d + (size_t)y * stride))[x] =
                (sum[0] / n) << 16 | (sum[1] / n) << 8 | (sum[2] / n);
        }
    cairo_surface_mark_dirty(s);
    return s;
}

/* im fitted into rect (kept in proportion, centred). */
static void picture(cairo_t *cr, const td_image *im, const double *r)
{
    cairo_surface_t *s = surface_of(im);
    double k, sw, sh;
    if (cairo_surface_status(s) == CAIRO_STATUS_SUCCESS) {
        sw = cairo_image_surface_get_width(s);
        sh = cairo_image_surface_get_height(s);
        k = fmin(r[2] / sw, r[3] / sh);
        cairo_save(cr);
        cairo_translate(cr, r[0] + (r[2] - k * sw) / 2,
                        r[1] + (r[3] - k * sh) / 2);
        cairo_scale(cr, k, k);
        cairo_set_source_surface(cr, s, 0, 0);
        cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_GOOD);
        cairo_paint(cr);
        cairo_restore(cr);
    }
    cairo_surface_destroy(s);
}

static void text(cairo_t *cr, double x, double y, double size, int bold,
                 const char *s)
{
    cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL,
                           bold ? CAIRO_FONT_WEIGHT_BOLD
                                : CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, size);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    cairo_move_to(cr, x, y);
    cairo_show_text(cr, s);
}

static int valid(const td_grid_f32 *g, float v)
{
    return isfinite(v) && !(g->has_nodata && v == g->nodata);
}

/* The longest straight line through the summit within the data (36
 * directions): its ends in cells; 0 when the DEM has no data. */
int td_report_section(const td_grid_f32 *dem, double *x0, double *y0,
                      double *x1, double *y1)
{
    double best = -1, sx = 0, sy = 0, top = -HUGE_VAL;
    int x, y, k;
    for (y = 0; y < dem->h; y++)
        for (x = 0; x < dem->w; x++)
            if (valid(dem, TD_AT(dem, x, y)) && TD_AT(dem, x, y) > top)
                top = TD_AT(dem, x, y), sx = x + 0.5, sy = y + 0.5;
    if (!(top > -HUGE_VAL))
        return 0;
    for (k = 0; k < 36; k++) {
        double a = k * M_PI / 36, dx = cos(a), dy = sin(a), t[2];
        int s;
        for (s = 0; s < 2; s++) { /* walk out both ways to the data's end */
            double d = 0, sg = s ? -1 : 1;
            for (;;) {
                double px = sx + sg * (d + 0.5) * dx, py = sy + sg * (d + 0.5) * dy;
                int cx = (int)floor(px), cy = (int)floor(py);
                if (cx < 0 || cy < 0 || cx >= dem->w || cy >= dem->h ||
                    !valid(dem, TD_AT(dem, cx, cy)))
                    break;
                d += 0.5;
            }
            t[s] = d;
        }
        if (t[0] + t[1] > best) {
            best = t[0] + t[1];
            *x0 = sx - t[1] * dx, *y0 = sy - t[1] * dy;
            *x1 = sx + t[0] * dx, *y1 = sy + t[0] * dy;
        }
    }
    return 1;
}

/* Panel (d): the profile along the section, axes and figures in vector. */
static void section(cairo_t *cr, const td_grid_f32 *dem, double cell,
                    const char *unit, const double *r)
{
    double x0, y0, x1, y1, len, lo = HUGE_VAL, hi = -HUGE_VAL, L, px, py;
    double ax = r[0] + 34, ay = r[1] + 8, aw = r[2] - 42, ah = r[3] - 34;
    char buf[64];
    int n, i, pen = 0;
    if (!td_report_section(dem, &x0, &y0, &x1, &y1))
        return;
    len = hypot(x1 - x0, y1 - y0);
    n = (int)ceil(len) + 1;
    for (i = 0; i < n; i++) {
        int cx = (int)floor(x0 + (x1 - x0) * i / (n - 1 > 0 ? n - 1 : 1));
        int cy = (int)floor(y0 + (y1 - y0) * i / (n - 1 > 0 ? n - 1 : 1));
        cx = cx < 0 ? 0 : cx >= dem->w ? dem->w - 1 : cx;
        cy = cy < 0 ? 0 : cy >= dem->h ? dem->h - 1 : cy;
        if (valid(dem, TD_AT(dem, cx, cy)))
            lo = fmin(lo, TD_AT(dem, cx, cy)), hi = fmax(hi, TD_AT(dem, cx, cy));
    }
    if (!(hi > lo))
        hi = lo + 1;
    cairo_set_source_rgb(cr, 0.35, 0.35, 0.35);
    cairo_set_line_width(cr, 0.6);
    cairo_rectangle(cr, ax, ay, aw, ah);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.55, 0.30, 0.10);
    cairo_set_line_width(cr, 1.2);
    for (i = 0; i < n; i++) {
        int cx = (int)floor(x0 + (x1 - x0) * i / (n - 1 > 0 ? n - 1 : 1));
        int cy = (int)floor(y0 + (y1 - y0) * i / (n - 1 > 0 ? n - 1 : 1));
        float z;
        cx = cx < 0 ? 0 : cx >= dem->w ? dem->w - 1 : cx;
        cy = cy < 0 ? 0 : cy >= dem->h ? dem->h - 1 : cy;
        z = TD_AT(dem, cx, cy);
        if (!valid(dem, z)) {
            pen = 0;
            continue;
        }
        px = ax + aw * i / (n - 1 > 0 ? n - 1 : 1);
        py = ay + ah * (1 - (z - lo) / (hi - lo));
        if (pen)
            cairo_line_to(cr, px, py);
        else
            cairo_move_to(cr, px, py);
        pen = 1;
    }
    cairo_stroke(cr);
    L = len * cell;
    snprintf(buf, sizeof buf, "%.5g", hi);
    text(cr, r[0], ay + 7, 7, 0, buf);
    snprintf(buf, sizeof buf, "%.5g", lo);
    text(cr, r[0], ay + ah, 7, 0, buf);
    text(cr, ax, ay + ah + 10, 7, 0, "0");
    snprintf(buf, sizeof buf, "%.4g %s", L, unit);
    text(cr, ax + aw - 40, ay + ah + 10, 7, 0, buf);
}

/* See pipeline.h. */
int td_pipeline_report(const char *path, const td_report_input *in,
                       td_ctx *cx)
{
    double pw, ph, rect[4][4], cell = in->cell > 0 ? in->cell : 1, y;
    static const char *const cap[4] = {
        "(a) the sheet, the traced lines coloured by height",
        "(b) the DEM: shaded relief and contours",
        "(c) the DEM in perspective (paper 001, 2.6)",
        "(d) cross-section through the summit"};
    char tmp[4096];
    td_render_params rp = td_render_defaults();
    td_view_params vp = td_view_defaults();
    td_image *relief = NULL, *view = NULL;
    cairo_surface_t *surf = NULL;
    cairo_t *cr = NULL;
    FILE *f = NULL;
    size_t k;
    int rc;
    td_report_layout(in->letter, &pw, &ph, rect);
    rp.style = TD_RENDER_TINT;
    rp.interval = in->interval;
    rp.base = in->base;
    rp.cellsize = cell;
    vp.drape = TD_DRAPE_TINT;
    vp.cellsize = cell;
    vp.patch = in->dem->w > 900 || in->dem->h > 900 ? 3 : 1;
    if ((rc = td_render_hillshade(in->dem, &rp, &relief, cx)) != 0 ||
        !(view = td_image_new(1200, 900, 3, cx)) ||
        (rc = td_view_render(in->dem, NULL, &vp, view, cx)) != 0) {
        rc = rc ? rc : TD_ENOMEM;
        goto done;
    }
    if (!(f = td_atomic_open(path, tmp, sizeof tmp, cx))) {
        rc = cx && cx->code ? cx->code : TD_EIO;
        goto done;
    }
    surf = cairo_pdf_surface_create_for_stream(put, f, pw, ph);
    cr = cairo_create(surf);
    text(cr, MARGIN, MARGIN + 8, 15, 1, in->title ? in->title : "topodig");
    text(cr, MARGIN, MARGIN + 24, 8, 0, in->subtitle ? in->subtitle : "");
    if (in->sheet)
        picture(cr, in->sheet, rect[0]);
    picture(cr, relief, rect[1]);
    picture(cr, view, rect[2]);
    section(cr, in->dem, cell, in->unit ? in->unit : "cells", rect[3]);
    for (k = 0; k < 4; k++)
        text(cr, rect[k][0], rect[k][1] + rect[k][3] + 11, 7.5, 0, cap[k]);
    y = rect[2][1] + rect[2][3] + CAPTION + GUTTER + 4;
    text(cr, MARGIN, y, 10, 1, "Figures");
    for (k = 0; k < in->nfacts && y < ph - MARGIN; k++) {
        y += 12;
        text(cr, MARGIN, y, 8.5, 0, in->facts[k]);
    }
    cairo_show_page(cr);
    cairo_destroy(cr);
    cr = NULL;
    cairo_surface_finish(surf);
    if (cairo_surface_status(surf) != CAIRO_STATUS_SUCCESS) {
        rc = td_seterr(cx, TD_EIO, "%s: cairo: %s", path,
                       cairo_status_to_string(cairo_surface_status(surf)));
        td_atomic_abort(f, tmp);
        f = NULL;
        goto done;
    }
    rc = td_atomic_commit(f, tmp, path, cx);
    f = NULL;
done:
    if (cr)
        cairo_destroy(cr);
    if (surf)
        cairo_surface_destroy(surf);
    if (f)
        td_atomic_abort(f, tmp);
    td_image_free(relief);
    td_image_free(view);
    return rc;
}
