/* bench_fragments: the short pieces the joiner's stage 0 removes as text
 * (scanner/join.h), each against the true contours: on a contour (every
 * vertex within 2 px of one) or not (text, noise), with its shape, for
 * tuning the rule that tells them apart.  One line per piece:
 *
 *   sheet scan class len chord/len box near_text ends_paired
 *
 *   bench_fragments [--dems DIR] [--only NAME] */
#include "samples/gen/gen.h"
#include "scanner/scan.h"
#include "tests/util/hsheet.h"
#include "src/io/io.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


/* The largest distance from a vertex of l to the nearest true line. */
static double off_truth(const td_line *l, const td_lines *truth)
{
    double worst = 0;
    size_t k, j;
    for (k = 0; k < l->n; k++) {
        double bd = HUGE_VAL;
        for (j = 0; j < truth->n && bd > 2.0; j++) {
            double d = td_contain_dist(&truth->v[j], l->xy[2 * k],
                                       l->xy[2 * k + 1]);
            bd = d < bd ? d : bd;
        }
        worst = bd > worst ? bd : worst;
    }
    return worst;
}

int main(int argc, char **argv)
{
    const char *dir = "tests/data/dems", *only = NULL;
    size_t c;
    int a;
    for (a = 1; a < argc; a++) {
        if (!strcmp(argv[a], "--dems") && a + 1 < argc)
            dir = argv[++a];
        else if (!strcmp(argv[a], "--only") && a + 1 < argc)
            only = argv[++a];
        else if (!strcmp(argv[a], "--topodig") || !strcmp(argv[a], "--dir"))
            a++;
    }
    printf("sheet scan class len chord box\n");
    for (c = 0; c < sizeof td_real_sheets / sizeof td_real_sheets[0]; c++) {
        const td_real_sheet *k = &td_real_sheets[c];
        td_grid_f32 *src = NULL;
        td_ctx cx;
        int kind;
        char path[512];
        if (only && strcmp(only, k->name))
            continue;
        td_ctx_init(&cx);
        snprintf(path, sizeof path, "%s/%s", dir, k->dem);
        if (td_hsheet_load_dem(path, &src, &cx) != 0)
            continue;
        for (kind = 0; kind < 4; kind++) {
            td_gen_params gp = td_gen_defaults();
            td_image *im = NULL;
            td_lines *truth = NULL;
            td_scan_params sp = td_scan_defaults();
            td_scan_result res;
            size_t i;
            gp.terrain = TD_GEN_DEM;
            gp.dem_in = src;
            gp.interval = k->interval;
            gp.w = (int)(src->w * k->scale);
            gp.h = (int)(src->h * k->scale);
            td_hsheet_defects(&gp, kind);
            if (td_gen_sheet(&gp, &im, &truth, NULL, &cx) != 0)
                continue;
            sp.join.record = 1;
            if (td_scan(im, &sp, &res, &cx) == 0 && res.join.text) {
                for (i = 0; i < res.join.text->n; i++) {
                    const td_line *l = &res.join.text->v[i];
                    double len = td_line_length(l), b[4] = {1e9, 1e9, -1e9, -1e9};
                    double ch = hypot(l->xy[0] - l->xy[2 * l->n - 2],
                                      l->xy[1] - l->xy[2 * l->n - 1]);
                    size_t q;
                    for (q = 0; q < l->n; q++) {
                        b[0] = fmin(b[0], l->xy[2 * q]);
                        b[2] = fmax(b[2], l->xy[2 * q]);
                        b[1] = fmin(b[1], l->xy[2 * q + 1]);
                        b[3] = fmax(b[3], l->xy[2 * q + 1]);
                    }
                    printf("%s %s %s %.1f %.2f %.1f %.0f %.0f\n", k->name,
                           td_defect_names[kind],
                           off_truth(l, truth) <= 2.0 ? "contour" : "text",
                           len, len > 0 ? ch / len : 0,
                           fmax(b[2] - b[0], b[3] - b[1]), l->xy[0],
                           l->xy[1]);
                }
                td_scan_result_free(&res);
            }
            td_image_free(im);
            td_lines_free(truth);
        }
        td_grid_f32_free(src);
    }
    return 0;
}
