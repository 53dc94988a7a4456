/* label.c: what `topodig label` does around the labeller, with files: the
 * printed labels read from the sheet, the ink widths measured on it, the
 * operator's heights applied, the label sheet of the paper's operator
 * entry (001 §2.3). */
#include "src/pipeline/pipeline.h"

#include "scanner/binarise.h"
#include "scanner/width.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* See pipeline.h. */
int td_pipeline_sheet_labels(const char *scan, const td_lines *ls,
                             td_ocr_read **reads, size_t *n, td_vee **vees,
                             size_t *nvees, int *colour, td_ctx *cx)
{
    td_image *im = NULL;
    td_scan_params sp = td_scan_defaults();
    td_scan_result res;
    int rc;
    memset(&res, 0, sizeof res);
    if ((rc = td_image_read(scan, &im, NULL, cx)) != 0)
        return rc;
    sp.join.record = 1;
    sp.measure_width = 0;
    if ((rc = td_scan(im, &sp, &res, cx)) == 0) {
        td_ocr_params op = td_ocr_defaults();
        op.ink = &res.palette; /* labels on a tint read in the ink */
        rc =
            td_ocr_scan_labels(im, res.lines, &res.join, ls, &op, reads, n, cx);
        if (colour)
            *colour = res.palette.n > 0;
    }
    if (rc == 0 && vees &&
        (rc = td_streams_vees(im, &res.palette, ls, res.join.cross_at,
                              res.join.cross_joins, vees, nvees, cx)) != 0) {
        free(*reads);
        *reads = NULL;
        *n = 0;
    }
    td_scan_result_free(&res);
    td_image_free(im);
    return rc;
}

/* See pipeline.h. */
int td_pipeline_scan_widths(const char *scan, td_lines *ls, td_ctx *cx)
{
    td_image *im = NULL;
    td_grid_u8 *m = NULL;
    td_binarise_params bp = td_binarise_defaults();
    size_t i;
    int rc;
    for (i = 0; i < ls->n; i++)
        if (ls->v[i].width > 0)
            return 0;
    if ((rc = td_image_read(scan, &im, NULL, cx)) != 0)
        goto fail;
    rc = TD_ENOMEM;
    if (!(m = td_grid_u8_new(im->w, im->h, cx)))
        goto fail;
    if ((rc = td_binarise(im, &bp, m, cx)) == 0 &&
        (rc = td_line_widths(m, ls, cx)) == 0)
        rc = td_line_darkness(im, ls, cx);
fail:
    td_image_free(im);
    td_grid_u8_free(m);
    return rc;
}

/* See pipeline.h. */
int td_pipeline_apply_heights(td_lines *ls, const double *rows, size_t n,
                              td_label_report *checks,
                              const td_label_params *p, td_ctx *cx)
{
    size_t i, j;
    for (j = 0; j < n; j++) {
        double id = rows[2 * j], h = rows[2 * j + 1], k, x, y;
        if (!(id >= 0) || id != floor(id))
            return td_seterr(cx, TD_EINVAL, "--heights: bad id %g", id);
        if (h != h)
            continue; /* "id,": no height given */
        for (i = 0; i < ls->n && ls->v[i].id != (long)id; i++)
            ;
        if (i == ls->n)
            return td_seterr(cx, TD_EINVAL, "--heights: no line has id %ld",
                             (long)id);
        ls->v[i].has_height = 1;
        ls->v[i].height = h;
        k = (h - p->base) / p->interval;
        if (!checks || fabs(k - floor(k + 0.5)) <= 1e-6)
            continue;
        td_label_where(&ls->v[i], &x, &y);
        td_label_warn(checks, "--heights: height %g of line %ld (near "
                      "%.0f,%.0f) is not base %g + a multiple of %g; kept", h,
                      (long)id, x, y, p->base, p->interval);
    }
    return 0;
}

/* See pipeline.h. */
int td_pipeline_label_sheet(const char *path, const char *like, int w, int h,
                            const td_lines *ls, const double *idxy,
                            td_ctx *cx)
{
    td_image *scan = NULL, *im = NULL;
    size_t i;
    int rc;
    if (like) {
        if ((rc = td_image_read(like, &scan, NULL, cx)) != 0 ||
            (rc = td_draw_overlay(scan, ls, &im, cx)) != 0)
            goto fail;
    } else {
        rc = TD_ENOMEM;
        if (!(im = td_image_new(w, h, 3, cx)))
            goto fail;
        memset(im->data, 255, (size_t)w * h * 3);
        for (i = 0; i < ls->n; i++) {
            uint8_t c[3];
            td_draw_colour(i, c);
            td_draw_line(im, &ls->v[i], c);
        }
    }
    td_draw_ids(im, ls, idxy);
    rc = td_png_write(path, im, cx);
fail:
    td_image_free(scan);
    td_image_free(im);
    return rc;
}
