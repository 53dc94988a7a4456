/* sheet.c: terrain -> truth contours -> rendered sheet in one call. */
#include "samples/gen/gen_int.h"

/* With inline labels, spot heights or streams: render without the
 * scanner's effects, draw the streams, cut the labels and spot heights into
 * the clean sheet, then scan
 * it as td_gen_render would. */
static int render_labelled(const td_lines *ls, const td_gen_params *p,
                           double interval, const td_grid_f32 *dem,
                           td_image **im, td_ctx *cx)
{
    int rc;
    if ((rc = td_gen_render_clean(ls, p, im, cx)) != 0)
        return rc;
    if ((rc = td_gen_streams(p, dem, *im, cx)) != 0 ||
        (rc = td_gen_labels_dem(ls, p, interval, dem, *im, NULL, NULL, cx)) !=
            0 ||
        (rc = td_gen_spots(p, dem, *im, NULL, NULL, cx)) != 0 ||
        (rc = td_gen_scan_effects(*im, p, cx)) != 0) {
        td_image_free(*im);
        *im = NULL;
        return rc;
    }
    return 0;
}

/* Contract in gen.h. */
int td_gen_sheet(const td_gen_params *p, td_image **sheet, td_lines **truth,
                 td_grid_f32 **dem, td_ctx *cx)
{
    td_grid_f32 *g = NULL;
    td_lines *ls = NULL;
    td_image *im = NULL;
    double interval;
    int rc, plain = p->labels <= 0 && p->spots <= 0 && !p->streams;
    if (sheet)
        *sheet = NULL;
    if (truth)
        *truth = NULL;
    if (dem)
        *dem = NULL;
    if ((rc = td_gen_terrain(p, &g, cx)) != 0)
        goto fail;
    interval = td_gen_auto_interval(p, g);
    if ((rc = td_gen_contours(g, p->base, interval, &ls, cx)) != 0)
        goto fail;
    if (sheet && plain && (rc = td_gen_render(ls, p, &im, cx)) != 0)
        goto fail;
    if (sheet && !plain &&
        (rc = render_labelled(ls, p, interval, g, &im, cx)) != 0)
        goto fail;
    if (sheet)
        *sheet = im;
    if (truth)
        *truth = ls;
    else
        td_lines_free(ls);
    if (dem)
        *dem = g;
    else
        td_grid_f32_free(g);
    return 0;
fail:
    td_image_free(im);
    td_lines_free(ls);
    td_grid_f32_free(g);
    return rc;
}
