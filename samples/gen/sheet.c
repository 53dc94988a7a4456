/* sheet.c: terrain -> truth contours -> rendered sheet in one call. */
#include "gen.h"

/* Contract in gen.h. */
int td_gen_sheet(const td_gen_params *p, td_image **sheet, td_lines **truth,
                 td_grid_f32 **dem, td_ctx *cx)
{
    td_grid_f32 *g = NULL;
    td_lines *ls = NULL;
    td_image *im = NULL;
    double interval;
    int rc;
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
    if (sheet && (rc = td_gen_render(ls, p, &im, cx)) != 0)
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
