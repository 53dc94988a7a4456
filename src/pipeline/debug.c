/* debug.c: the debug pictures and reports of scan, label and run
 * (--debug-dir): file output, so it lives in the pipeline, not in the
 * stages that make the data. */
#include "src/pipeline/pipeline.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

/* The join's statistics, one "name value" per line. */
static int write_join_report(const char *path, const td_join_stats *j,
                             td_ctx *cx)
{
    FILE *f = fopen(path, "w");
    int bad;
    if (!f)
        return td_seterr(cx, TD_EIO, "%s: cannot write (%s)", path,
                         strerror(errno));
    fprintf(f,
            "joins %zu\nlabel_gap_joins %zu\nstream_joins %zu\n"
            "closures %zu\n"
            "fragments_removed %zu\nglyph_rings_removed %zu\nends_open %zu\n"
            "merges %zu\nmerges_left_open %zu\nwater_turns_cut %zu\n"
            "gap_ends_left_open %zu\npieces_kept_apart %zu\n"
            "alone_gap_joins %zu\ncurled_pieces_kept %zu\n",
            j->joins, j->long_joins, j->cross_joins, j->closures, j->fragments,
            j->glyphs, j->ends_open, j->merges, j->merges_open, j->water_turns,
            j->gaps_open, j->late_pieces, j->alone_joins, j->curls);
    bad = ferror(f);
    if (fclose(f) != 0 || bad)
        return td_seterr(cx, TD_EIO, "%s: cannot write", path);
    return 0;
}

static void fill(td_image *im, int x0, int y0, int w, int h,
                 const uint8_t *rgb)
{
    int x, y;
    for (y = y0; y < y0 + h && y < im->h; y++)
        for (x = x0; x < x0 + w && x < im->w; x++)
            memcpy(im->data + (size_t)y * im->stride + 3 * (size_t)x, rgb, 3);
}

/* palette.png: one row per colour found: its swatch (framed black when it
 * is the contour ink, grey when it is contour ink too, hatched when it is
 * a tint) and a bar as long as its share of the sheet (500 px = 100 %);
 * ink-K.png: the pixels each colour K explains; inks.txt: the numbers. */
static int write_palette(const char *dir, const td_image *im,
                         const td_palette *pal, td_ctx *cx)
{
    static const uint8_t white[3] = {255, 255, 255}, black[3] = {0, 0, 0},
                         grey[3] = {150, 150, 150};
    static const char *const role[3] = {"paper", "tint", "ink"};
    char path[4096];
    td_image *pic = td_image_new(580, 50 * pal->n + 10, 3, cx);
    td_grid_u8 *lbl = NULL;
    FILE *f;
    int i, rc = 0, x, y;
    if (!pic)
        return TD_ENOMEM;
    fill(pic, 0, 0, pic->w, pic->h, white);
    for (i = 0; i < pal->n; i++) {
        const td_ink *k = &pal->ink[i];
        int y0 = 10 + 50 * i;
        if (i == pal->chosen || (pal->also >> i & 1u))
            fill(pic, 7, y0 - 3, 46, 46, i == pal->chosen ? black : grey);
        fill(pic, 10, y0, 40, 40, k->rgb);
        if (k->role == TD_INKROLE_TINT)
            for (y = 0; y < 40; y++)
                for (x = 0; x < 40; x++)
                    if ((x + y) % 8 == 0)
                        fill(pic, 10 + x, y0 + y, 1, 1, white);
        fill(pic, 70, y0 + 12, 2 + (int)(500.0 * k->share), 16, k->rgb);
    }
    snprintf(path, sizeof path, "%s/palette.png", dir);
    rc = td_png_write(path, pic, cx);
    td_image_free(pic);
    if (rc != 0)
        return rc;
    if (!(lbl = td_grid_u8_new(im->w, im->h, cx)))
        return TD_ENOMEM;
    if ((rc = td_palette_label(pal, im, lbl, cx)) != 0)
        goto done;
    for (i = 0; i < pal->n && rc == 0; i++) {
        td_grid_u8 *m;
        if (i == pal->paper)
            continue;
        if (!(m = td_grid_u8_new(im->w, im->h, cx))) {
            rc = TD_ENOMEM;
            break;
        }
        for (y = 0; y < im->h; y++)
            for (x = 0; x < im->w; x++)
                TD_AT(m, x, y) = TD_AT(lbl, x, y) == i;
        snprintf(path, sizeof path, "%s/ink-%d.png", dir, i);
        rc = td_png_write_u8(path, m, 1, cx);
        td_grid_u8_free(m);
    }
    snprintf(path, sizeof path, "%s/inks.txt", dir);
    if (rc == 0 && !(f = fopen(path, "w")))
        rc = td_seterr(cx, TD_EIO, "%s: cannot write (%s)", path,
                       strerror(errno));
    if (rc == 0) {
        int bad;
        fprintf(f, "# index role rgb share width_px long_stroke_px_per_Mpx "
                   "contour\n");
        for (i = 0; i < pal->n; i++)
            fprintf(f, "%d %s #%02x%02x%02x %.4f %.2f %.0f %s\n", i,
                    role[pal->ink[i].role], pal->ink[i].rgb[0],
                    pal->ink[i].rgb[1], pal->ink[i].rgb[2],
                    pal->ink[i].share, pal->ink[i].width,
                    pal->ink[i].line_len,
                    i == pal->chosen             ? "taken"
                    : (pal->also >> i & 1u) ? "also"
                                                 : "-");
        bad = ferror(f);
        if (fclose(f) != 0 || bad)
            rc = td_seterr(cx, TD_EIO, "%s: cannot write", path);
    }
done:
    td_grid_u8_free(lbl);
    return rc;
}

/* other.png: the other inks' strokes (white) the joiner keeps off. */
static int write_other(const char *path, int w, int h, const uint8_t *bits,
                       td_ctx *cx)
{
    size_t stride = ((size_t)w + 7) / 8;
    td_grid_u8 *g = td_grid_u8_new(w, h, cx);
    int x, y, rc;
    if (!g)
        return TD_ENOMEM;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++)
            g->data[(size_t)y * g->stride + (size_t)x] =
                (uint8_t)((bits[(size_t)y * stride + (size_t)(x >> 3)] >>
                           (x & 7)) & 1u);
    rc = td_png_write_u8(path, g, 1, cx);
    td_grid_u8_free(g);
    return rc;
}

/* See pipeline.h. */
int td_pipeline_scan_debug(const char *dir, const td_image *im,
                           const td_scan_result *r, td_ctx *cx)
{
    char path[4096];
    td_image *ov = NULL;
    int rc;
    if (mkdir(dir, 0777) != 0 && errno != EEXIST)
        return td_seterr(cx, TD_EIO, "%s: cannot create folder (%s)",
                         dir, strerror(errno));
#define DPATH(name) (snprintf(path, sizeof path, "%s/%s", dir, name), path)
    if ((rc = td_png_write_u8(DPATH("mask.png"), r->mask, 1, cx)) != 0 ||
        (rc = td_png_write_u8(DPATH("skeleton.png"), r->skeleton, 1, cx)) != 0 ||
        (rc = td_png_write_u8(DPATH("despurred.png"), r->despurred, 1, cx)) != 0 ||
        (rc = td_draw_overlay(im, r->lines, &ov, cx)) != 0)
        return rc;
    if (r->join.segments) { /* label-gap joins, magenta */
        static const uint8_t magenta[3] = {230, 0, 230};
        size_t i;
        for (i = 0; i < r->join.segments->n; i++)
            td_draw_line(ov, &r->join.segments->v[i], magenta);
    }
    { /* the pieces kept apart (--pieces late), black */
        static const uint8_t black[3] = {0, 0, 0};
        size_t i;
        for (i = 0; i < r->lines->n; i++)
            if (r->lines->v[i].piece)
                td_draw_line(ov, &r->lines->v[i], black);
    }
    rc = td_png_write(DPATH("overlay.png"), ov, cx);
    if (rc == 0)
        rc = write_join_report(DPATH("join.txt"), &r->join, cx);
    if (rc == 0 && r->palette.n > 0)
        rc = write_palette(dir, im, &r->palette, cx);
    if (rc == 0 && r->other)
        rc = write_other(DPATH("other.png"), im->w, im->h, r->other, cx);
#undef DPATH
    td_image_free(ov);
    return rc;
}


/* --debug-dir labels.geojson: one point per label read. */
static int write_labels_geojson(const char *path, const td_lines *ls,
                                const td_ocr_read *reads, size_t nreads,
                                const td_georef *geo, td_ctx *cx)
{
    char tmp[4200];
    size_t i;
    FILE *f = td_atomic_open(path, tmp, sizeof tmp, cx);
    if (!f)
        return cx->code;
    char crs[320];
    td_georef_crs_json(geo, crs, sizeof crs);
    fprintf(f, "{\"type\":\"FeatureCollection\",%s,\"features\":[\n", crs);
    for (i = 0; i < nreads; i++) {
        const td_ocr_read *r = &reads[i];
        double x = r->x, y = r->y;
        td_georef_apply(geo, x, y, &x, &y);
        char ids[64] = "null", alts[TD_OCR_ALTS * 48 + 8] = "[";
        size_t at = 1;
        int k;
        if (r->line[0] >= 0 && (size_t)r->line[0] < ls->n)
            snprintf(ids, sizeof ids, "%ld", ls->v[r->line[0]].id);
        for (k = 0; k < TD_OCR_ALTS && r->alt[k].conf > 0; k++)
            at += (size_t)snprintf(alts + at, sizeof alts - at,
                                   "%s[%.10g,%.3f]", k ? "," : "",
                                   r->alt[k].value, r->alt[k].conf);
        snprintf(alts + at, sizeof alts - at, "]");
        fprintf(f, "%s{\"type\":\"Feature\",\"properties\":{\"text\":\"%s\","
                "\"value\":%.10g,\"angle\":%.1f,\"confidence\":%.3f,"
                "\"alternatives\":%s,"
                "\"digit_px\":%.1f,\"line\":%s,\"used\":%s,\"why\":%s%s%s},"
                "\"geometry\":{\"type\":\"Point\",\"coordinates\":[%.3f,"
                "%.3f]}}", i ? ",\n" : "", r->text, r->value,
                atan2(-r->uy, r->ux) * 180.0 / 3.14159265358979323846,
                r->conf, alts, r->digit_px, ids, r->used ? "true" : "false",
                r->why ? "\"" : "", r->why ? r->why : "null",
                r->why ? "\"" : "", x, y);
    }
    fputs("\n]}\n", f);
    return td_atomic_commit(f, tmp, path, cx);
}

/* See pipeline.h. */
int td_pipeline_heights_debug(const char *dir, const td_image *scan, int w,
                              int h, const td_lines *ls,
                              const td_ocr_read *reads, size_t nreads,
                              const td_vee *vees, size_t nvees,
                              const td_georef *geo, td_ctx *cx)
{
    td_image *pic = NULL;
    char path[4096];
    int rc;
    if (mkdir(dir, 0777) != 0 && errno != EEXIST)
        return td_seterr(cx, TD_EIO, "%s: cannot make the folder: %s", dir,
                         strerror(errno));
    snprintf(path, sizeof path, "%s/heights.png", dir);
    if ((rc = td_draw_heights(scan, w, h, ls, &pic, cx)) == 0) {
        td_streams_draw(pic, vees, nvees);
        if (reads)
            td_ocr_draw(pic, reads, nreads);
        rc = td_png_write(path, pic, cx);
    }
    td_image_free(pic);
    snprintf(path, sizeof path, "%s/labels.geojson", dir);
    if (rc == 0 && reads)
        rc = write_labels_geojson(path, ls, reads, nreads, geo, cx);
    return rc;
}
