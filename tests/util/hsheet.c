/* hsheet.c: see hsheet.h. */
#include "tests/util/hsheet.h"

#include "src/core/core.h"
#include "scanner/ocr.h"
#include "scanner/scan.h"
#include "src/io/io.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int td_hsheet_load_dem(const char *path, td_grid_f32 **out, td_ctx *cx)
{
    td_georef g;
    int rc;
    td_georef_init(&g);
    rc = td_dem_read(path, out, &g, cx);
    td_georef_clear(&g);
    return rc;
}

/* Contract in hsheet.h. */
td_grid_f32 *td_hsheet_dem_sheet(const char *dem, double scale,
                                 td_gen_params *gp, td_ctx *cx)
{
    char path[256];
    td_grid_f32 *src = NULL;
    snprintf(path, sizeof path, "tests/data/dems/%s", dem);
    if (td_hsheet_load_dem(path, &src, cx) != 0)
        return NULL;
    *gp = td_gen_defaults();
    gp->terrain = TD_GEN_DEM;
    gp->dem_in = src;
    gp->w = (int)(src->w * scale);
    gp->h = (int)(src->h * scale);
    gp->line_width = 1.8;
    gp->index_width = 3.2;
    return src;
}

static int cmp_len_desc(const void *pa, const void *pb)
{
    const double *a = pa, *b = pb;
    return (a[0] < b[0]) - (a[0] > b[0]);
}

/* Contract in hsheet.h. */
int td_hsheet_pick_known(const td_lines *tl, double interval, int n,
                         td_label_point *kp)
{
    double *v = malloc((tl->n + 1) * 2 * sizeof *v);
    size_t i, m = 0;
    int got = 0;
    if (!v)
        return 0;
    for (i = 0; i < tl->n; i++) {
        double k = tl->v[i].height / interval;
        if (fabs(k / 5 - floor(k / 5 + 0.5)) < 1e-6) {
            v[2 * m] = td_line_length(&tl->v[i]);
            v[2 * m++ + 1] = (double)i;
        }
    }
    qsort(v, m, 2 * sizeof *v, cmp_len_desc);
    for (i = 0; i < m && got < n; i++) {
        const td_line *l = &tl->v[(size_t)v[2 * i + 1]];
        int j, dup = 0;
        for (j = 0; j < got; j++)
            dup |= kp[j].height == l->height;
        if (dup)
            continue;
        kp[got].x = l->xy[2 * (l->n / 2)];
        kp[got].y = l->xy[2 * (l->n / 2) + 1];
        kp[got].height = l->height;
        kp[got++].id = -1;
    }
    free(v);
    return got;
}

static int draw_verdicts(const td_hsheet *hs, const td_image *im,
                         const td_lines *tl, const td_lines *ls,
                         const int *verdict, td_ctx *cx)
{
    static const uint8_t col[6][3] = {{0, 160, 0},     {230, 0, 0},
                                      {150, 150, 150}, {200, 200, 255},
                                      {0, 90, 255},    {255, 140, 0}};
    td_image *out = td_image_new(im->w, im->h, 3, cx);
    size_t i;
    int x, y, rc;
    if (!out)
        return TD_ENOMEM;
    for (y = 0; y < im->h; y++)
        for (x = 0; x < im->w; x++) {
            const uint8_t *s =
                im->data + (size_t)y * im->stride + (size_t)x * im->channels;
            uint8_t *d = out->data + (size_t)y * out->stride + 3 * (size_t)x;
            int c;
            for (c = 0; c < 3; c++)
                d[c] = (uint8_t)(200 + s[im->channels == 3 ? c : 0] * 55 / 255);
        }
    for (i = 0; i < ls->n; i++) {
        int v = verdict[i];
        if (ls->v[i].hsource == TD_HS_ASSUMED && v < 2)
            v += 4;
        td_draw_line(out, &ls->v[i], col[v]);
    }
    rc = td_png_write(hs->png, out, cx);
    td_image_free(out);
    if (rc == 0) { /* the sheet, the labelled and the true lines beside it */
        char path[600];
        snprintf(path, sizeof path, "%s.sheet.png", hs->png);
        rc = td_png_write(path, im, cx);
        snprintf(path, sizeof path, "%s.lines.geojson", hs->png);
        if (rc == 0)
            rc = td_geojson_write_lines(path, ls, NULL, cx);
        snprintf(path, sizeof path, "%s.truth.geojson", hs->png);
        if (rc == 0)
            rc = td_geojson_write_lines(path, tl, NULL, cx);
    }
    return rc;
}

/* Whether every vertex of l lies in the box b (x0, y0, x1, y1). */
static int line_in_box(const td_line *l, const double *b)
{
    size_t k;
    for (k = 0; k < l->n; k++)
        if (l->xy[2 * k] < b[0] || l->xy[2 * k] > b[2] ||
            l->xy[2 * k + 1] < b[1] || l->xy[2 * k + 1] > b[3])
            return 0;
    return 1;
}

/* Per line of ls: its true height (the truth line of tl nearest each
 * vertex within 2 px, the most vertices; NAN: none) and whether its side
 * 0 (left of its direction, y down) is the higher, by the true surface
 * dem 2.5 px either side of its vertices on that contour.  0 or
 * TD_ENOMEM. */
static int true_heights(const td_lines *tl, const td_lines *ls,
                        const td_grid_f32 *dem, double *h, signed char *up,
                        td_ctx *cx)
{
    const int cell = 4;
    int gw = dem->w / cell + 1, gh = dem->h / cell + 1;
    size_t nv = 0, i, k;
    long *head = td_malloc((size_t)gw * gh * sizeof *head, cx), *next;
    double *vh;
    float *vx;
    for (i = 0; i < tl->n; i++)
        nv += tl->v[i].n;
    next = td_malloc((nv + 1) * sizeof *next, cx);
    vh = td_malloc((nv + 1) * sizeof *vh, cx);
    vx = td_malloc((2 * nv + 1) * sizeof *vx, cx);
    if (!head || !next || !vh || !vx) {
        free(head), free(next), free(vh), free(vx);
        return TD_ENOMEM;
    }
    for (i = 0; i < (size_t)gw * gh; i++)
        head[i] = -1;
    for (i = 0, nv = 0; i < tl->n; i++)
        for (k = 0; k < tl->v[i].n; k++, nv++) {
            double x = tl->v[i].xy[2 * k], y = tl->v[i].xy[2 * k + 1];
            int cx0 = (int)(x / cell), cy0 = (int)(y / cell);
            size_t c;
            cx0 = cx0 < 0 ? 0 : cx0 >= gw ? gw - 1 : cx0;
            cy0 = cy0 < 0 ? 0 : cy0 >= gh ? gh - 1 : cy0;
            c = (size_t)cy0 * gw + cx0;
            vx[2 * nv] = (float)x, vx[2 * nv + 1] = (float)y;
            vh[nv] = tl->v[i].height;
            next[nv] = head[c];
            head[c] = (long)nv;
        }
    for (i = 0; i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        double hv[64], best = -1;
        size_t cnt[64], nh = 0, j;
        int pass, upv = 0, nup = 0;
        h[i] = NAN, up[i] = 0;
        for (pass = 0; pass < 2; pass++) {
            if (pass == 1) /* the majority */
                for (j = 0; j < nh; j++)
                    if ((double)cnt[j] > best)
                        best = (double)cnt[j], h[i] = hv[j];
            for (k = 0; k < l->n; k++) {
                double x = l->xy[2 * k], y = l->xy[2 * k + 1], bd = 4.0,
                       th = NAN;
                int cx0 = (int)(x / cell), cy0 = (int)(y / cell), dx, dy;
                for (dy = -1; dy <= 1; dy++)
                    for (dx = -1; dx <= 1; dx++) {
                        long q;
                        if (cx0 + dx < 0 || cy0 + dy < 0 || cx0 + dx >= gw ||
                            cy0 + dy >= gh)
                            continue;
                        for (q = head[(size_t)(cy0 + dy) * gw + cx0 + dx];
                             q >= 0; q = next[q]) {
                            double d =
                                (vx[2 * q] - x) * (vx[2 * q] - x) +
                                (vx[2 * q + 1] - y) * (vx[2 * q + 1] - y);
                            if (d < bd)
                                bd = d, th = vh[q];
                        }
                    }
                if (!isfinite(th))
                    continue;
                if (pass == 0) {
                    for (j = 0; j < nh && hv[j] != th; j++)
                        ;
                    if (j == nh && nh < 64)
                        hv[nh] = th, cnt[nh++] = 0;
                    if (j < nh)
                        cnt[j]++;
                } else if (th == h[i] && k > 0 && k + 1 < l->n) {
                    double tx = l->xy[2 * k + 2] - l->xy[2 * k - 2],
                           ty = l->xy[2 * k + 3] - l->xy[2 * k - 1],
                           t = hypot(tx, ty);
                    long ax, ay, bx, by;
                    if (!(t > 0))
                        continue;
                    ax = lround(x + 2.5 * ty / t),
                    ay = lround(y - 2.5 * tx / t);
                    bx = lround(x - 2.5 * ty / t),
                    by = lround(y + 2.5 * tx / t);
                    if (ax < 0 || ay < 0 || bx < 0 || by < 0 || ax >= dem->w ||
                        bx >= dem->w || ay >= dem->h || by >= dem->h)
                        continue;
                    upv += dem->data[(size_t)ay * dem->stride + ax] >
                           dem->data[(size_t)by * dem->stride + bx];
                    nup++;
                }
            }
        }
        up[i] = (signed char)(2 * upv > nup);
        if (nup == 0)
            h[i] = NAN;
    }
    free(head), free(next), free(vh), free(vx);
    return 0;
}

int td_hsheet_run(td_hsheet *hs, FILE *log, td_ctx *cx)
{
    td_image *im = NULL;
    td_lines *tl = NULL, *ls = NULL;
    td_grid_f32 *dem = NULL;
    td_scan_result res;
    td_label_params lp = td_label_defaults();
    td_label_point kp[8];
    td_ocr_read *reads = NULL;
    td_vee *vees = NULL;
    size_t nvees = 0;
    double t0, *truth = NULL; /* per read: the true line's height */
    double *oh = NULL;        /* hs->oracle: per traced line, its true
                                 height and up side */
    signed char *oup = NULL;
    int rc;
    memset(&res, 0, sizeof res);
    memset(&hs->rep, 0, sizeof hs->rep);
    if ((rc = td_gen_sheet(&hs->gp, &im, &tl, &dem, cx)) != 0)
        goto done;
    hs->interval = td_gen_auto_interval(&hs->gp, dem);
    hs->truth = tl->n;
    {
        size_t i;
        for (i = 0; i < tl->n; i++) { /* the ink widths as drawn */
            double k = (tl->v[i].height - hs->gp.base) / hs->interval / 5;
            tl->v[i].width =
                hs->gp.index_width > 0 && fabs(k - floor(k + 0.5)) < 1e-6
                    ? hs->gp.index_width
                    : hs->gp.line_width;
        }
    }
    if (hs->use_truth_lines) {
        size_t i;
        if (!(ls = td_lines_copy(tl, cx))) {
            rc = TD_ENOMEM;
            goto done;
        }
        for (i = 0; i < ls->n; i++) { /* the labeller starts from nothing
                                          but what the sheet shows */
            ls->v[i].has_height = 0, ls->v[i].height = 0;
            ls->v[i].depression &= hs->gp.hachures;
        }
    } else {
        td_scan_params sp = td_scan_defaults(); /* ink auto, as run */
        sp.trace.cut = !hs->paper_junctions;
        sp.detint = hs->detint;
        if (hs->no_stream_joins)
            sp.join.cross_gap = 0;
        sp.join.record = hs->read_labels;
        sp.skel_bits = hs->steps;
        if ((rc = td_scan(im, &sp, &res, cx)) != 0)
            goto done;
        if (hs->read_labels) {
            size_t i, j;
            td_ocr_params op = td_ocr_defaults();
            op.ink = &res.palette;
            if ((rc = td_ocr_scan_labels(im, res.lines, &res.join, NULL, &op,
                                         &reads, &hs->nreads, cx)) != 0)
                goto done;
            td_ocr_drop_digits(res.lines, reads, hs->nreads);
            td_ocr_drop_dots(res.lines, res.join.text, reads, hs->nreads);
            if (!(truth = calloc(hs->nreads + 1, sizeof *truth))) {
                rc = TD_ENOMEM;
                goto done;
            }
            for (i = 0; i < hs->nreads; i++) { /* right: the true line under */
                double bd = HUGE_VAL, th = 0;
                for (j = 0; j < tl->n; j++) {
                    double d =
                        td_contain_dist(&tl->v[j], reads[i].x, reads[i].y);
                    if (d < bd)
                        bd = d, th = tl->v[j].height;
                }
                hs->reads_right += fabs(th - reads[i].value) < 1e-6;
                truth[i] = th;
            }
        }
        if (!hs->no_vees && (rc = td_streams_vees(
                                 im, &res.palette, res.lines, res.join.cross_at,
                                 res.join.cross_joins, &vees, &nvees, cx)) != 0)
            goto done;
        ls = res.lines;
        res.lines = NULL;
    }
    hs->traced = ls->n;
    lp.method = hs->method;
    lp.search = hs->search < 0 ? 0 : hs->search ? hs->search : lp.search;
    lp.gap_pairs = hs->gap_pairs > 0   ? hs->gap_pairs
                   : hs->gap_pairs < 0 ? 0
                                       : lp.gap_pairs; /* by the scan */
    lp.colour = res.palette.n > 0;
    lp.interval = hs->no_interval ? 0 : hs->interval;
    lp.labels = reads;
    lp.nlabels = hs->nreads;
    lp.vees = vees;
    lp.nvees = nvees;
    lp.base = hs->gp.base;
    lp.w = im->w;
    lp.h = im->h;
    lp.index_every = hs->index_every > 0 ? hs->index_every : 0;
    /* 0: the known points alone, no widths; -1: the widths' spacing picked
       by the solve (td_label_auto with the interval given, as run does) */
    lp.index_off = hs->index_every == 0 && !hs->no_interval;
    lp.walls = res.walls;
    lp.skeleton = res.skel_bits;
    lp.nknown = (size_t)td_hsheet_pick_known(
        tl, hs->interval, hs->nknown > 8 ? 8 : hs->nknown, kp);
    lp.known = kp;
    if (hs->oracle) {
        size_t i;
        if (!(oh = malloc((ls->n + 1) * sizeof *oh)) ||
            !(oup = malloc(ls->n + 1)) ||
            (rc = true_heights(tl, ls, dem, oh, oup, cx)) != 0) {
            rc = rc ? rc : TD_ENOMEM;
            goto done;
        }
        if (hs->oracle_box[2] > hs->oracle_box[0])
            for (i = 0; i < ls->n; i++)
                if (!line_in_box(&ls->v[i], hs->oracle_box))
                    oh[i] = NAN;
        lp.oracle_h = oh, lp.oracle_up = oup;
        lp.oracle_ties = hs->oracle_ties;
    }
    t0 = td_now();
    rc = td_label_auto(ls, &lp, &hs->rep, cx);
    hs->label_secs = td_now() - t0;
    if (truth) { /* each read against the true line under it, as used */
        size_t i;
        for (i = 0; i < hs->nreads; i++) {
            if (reads[i].used && fabs(truth[i] - reads[i].value) < 1e-6)
                hs->used_right++;
            else if (reads[i].used)
                hs->used_wrong++;
        }
        for (i = 0; i < hs->nreads && log; i++) {
            int k;
            fprintf(log, "read %-6s at %5.0f,%-5.0f conf %.2f, truth %g:%s %s",
                    reads[i].text, reads[i].x, reads[i].y, reads[i].conf,
                    truth[i], reads[i].used ? " used" : "",
                    reads[i].why ? reads[i].why : "");
            for (k = 0; k < TD_OCR_ALTS && reads[i].alt[k].conf > 0; k++)
                fprintf(log, "%s%g (%.2f%s)", k ? ", " : "; or ",
                        reads[i].alt[k].value, reads[i].alt[k].conf,
                        reads[i].alt[k].turned ? ", turned" : "");
            fprintf(log, "\n");
        }
    }
    hs->interval = hs->rep.interval > 0 ? hs->rep.interval : hs->interval;
    if (rc == 0) {
        int *verdict = calloc(ls->n + 1, sizeof *verdict);
        if (!verdict)
            rc = TD_ENOMEM;
        if (rc == 0)
            rc = td_match_heights_v(tl, ls, im->w, im->h, 2.0, &hs->score, log,
                                    verdict);
        if (rc == 0 && hs->png)
            rc = draw_verdicts(hs, im, tl, ls, verdict, cx);
        free(verdict);
    }
done:
    free(oh);
    free(oup);
    free(truth);
    free(reads);
    free(vees);
    td_scan_result_free(&res);
    td_image_free(im);
    td_lines_free(tl);
    td_lines_free(ls);
    td_grid_f32_free(dem);
    return rc;
}

/* Contract in hsheet.h. */
const td_real_sheet td_real_sheets[TD_REAL_SHEETS] = {
    {"elkhorn", "elkhorn_srtm3.tif", 6, 0},
    {"frontrange", "frontrange_srtm3.tif", 10, 0},
    {"orkhon", "orkhon_92m.tif", 10, 0},
    {"frontrange20", "frontrange_srtm3.tif", 10, 20},
    /* held out (2026-12-04, session 15): other scales and intervals,
       not tuned on */
    {"elkhorn20", "elkhorn_srtm3.tif", 6, 20},
    {"orkhon50", "orkhon_92m.tif", 10, 50},
    {"frontrange25", "frontrange_srtm3.tif", 8, 25},
};
const char *const td_defect_names[5] = {"clean", "scanned", "colour", "printed",
                                        "new"};

/* Contract in hsheet.h. */
void td_hsheet_levels(const td_image *in, td_image *out, const int lo[3],
                      const int hi[3])
{
    int x, y, c;
    for (y = 0; y < in->h; y++)
        for (x = 0; x < in->w; x++)
            for (c = 0; c < 3; c++) {
                double q =
                    lo[c] +
                    in->data[(size_t)y * in->stride + 3 * (size_t)x + c] *
                        (hi[c] - lo[c]) / 255.0;
                out->data[(size_t)y * out->stride + 3 * (size_t)x + c] =
                    (uint8_t)(q < 0     ? 0
                              : q > 255 ? 255
                                        : lrint(q));
            }
}

void td_hsheet_defects(td_gen_params *p, int kind)
{
    p->line_width = 1.8;
    p->index_width = 3.2;
    if (!kind)
        return;
    if (kind >= 2) {
        p->colour = 1;
        p->distractors = 1;
        p->print = kind >= 3;
        p->unfaded = kind == 4;
        if (getenv("BENCH_FRINGE")) /* "DX,DY": another scanner */
            sscanf(getenv("BENCH_FRINGE"), "%lf,%lf", &p->fringe[0],
                   &p->fringe[1]);
    }
    p->blur = 0.8;
    p->noise = 8;
    p->specks = 300;
    p->breaks = 40;
    p->break_min = 3;
    p->break_max = 10;
    p->labels = 3;
    p->label_bend = 40;
    p->label_font = 1;
}
