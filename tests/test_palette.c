/* Tests of the colour palette (scanner/palette.c) and --ink auto: a
 * hand-made sheet with one right answer, and a printed map drawn from a
 * real DEM (tdgen --print: tint, faded contours, red roads, water, text,
 * grid, fringing, JPEG) scored against its true contours. */
#include "tests/tt.h"
#include "tests/util/hsheet.h"
#include "tests/util/match.h"

#include "scanner/palette.h"
#include "scanner/scan.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Printed over cream (a filter), the inks look like cream x ink / 255:
 * brown (154,83,33), red (196,46,33). */
static const uint8_t CREAM[3] = {245, 235, 210}, BROWN[3] = {160, 90, 40},
                     RED[3] = {205, 50, 40};

/* Ink col printed over im (a filter) with coverage a at (x,y). */
static void print_px(td_image *im, int x, int y, const uint8_t *col, double a)
{
    uint8_t *p = im->data + (size_t)y * im->stride + 3 * (size_t)x;
    int c;
    for (c = 0; c < 3; c++)
        p[c] = (uint8_t)lrint(p[c] * (1.0 - a * (1.0 - col[c] / 255.0)));
}

/* A line y = y0 + slope x, width wd, anti-aliased (coverage from the
 * distance to its centre). */
static void line(td_image *im, double y0, double slope, double wd,
                 const uint8_t *col)
{
    int x, y;
    double n = sqrt(1 + slope * slope);
    for (y = 0; y < im->h; y++)
        for (x = 0; x < im->w; x++) {
            double d = fabs(y + 0.5 - y0 - slope * (x + 0.5)) / n;
            double a = wd / 2 + 0.5 - d;
            if (a > 0)
                print_px(im, x, y, col, a > 1 ? 1 : a);
        }
}

/* Brown contours (thin, thick and faded) and two red roads on cream: the
 * palette has the paper and exactly two inks (the anti-aliased and faded
 * brown pixels are mixtures, no ink of their own); auto takes the brown
 * (more line length), brown takes the brown; the strength table gives
 * full brown 255 and full red 0. */
static void test_two_inks(void)
{
    td_image *im = td_image_new(400, 300, 3, NULL);
    td_palette pal;
    uint8_t *lut = malloc(33 * 33 * 33);
    int i, x, y, k;
    for (y = 0; y < im->h; y++)
        for (x = 0; x < im->w; x++)
            memcpy(im->data + (size_t)y * im->stride + 3 * x, CREAM, 3);
    for (k = 0; k < 14; k++) {
        uint8_t faded[3];
        for (i = 0; i < 3; i++) /* every third line printed at 60 % */
            faded[i] = (uint8_t)(k % 3 ? BROWN[i]
                                       : 255 - 0.6 * (255 - BROWN[i]));
        line(im, 10 + 20 * k, 0.15, k % 5 == 0 ? 3.2 : 1.8, faded);
    }
    line(im, 150, -0.8, 2.2, RED);
    line(im, 320, -1.6, 2.2, RED);
    TT_CHECK(td_palette_find(im, &pal, NULL) == 0);
    {
        int inks = 0, brown = -1, red = -1;
        for (i = 0; i < pal.n; i++) {
            const td_ink *q = &pal.ink[i];
            if (q->role != TD_INKROLE_INK)
                continue;
            inks++;
            if (abs(q->rgb[0] - 154) < 15 && abs(q->rgb[1] - 83) < 15 &&
                abs(q->rgb[2] - 33) < 15)
                brown = i;
            if (abs(q->rgb[0] - 196) < 15 && abs(q->rgb[1] - 46) < 15 &&
                abs(q->rgb[2] - 33) < 15)
                red = i;
        }
        TT_CHECKF(inks == 2 && brown >= 0 && red >= 0,
                  "%d inks, brown %d, red %d", inks, brown, red);
        TT_CHECK(td_palette_choose(&pal, 0) == brown);
        TT_CHECK(td_palette_choose(&pal, 1) == brown);
        td_palette_lut(&pal, lut);
        /* nodes: index (r/8, g/8, b/8) */
        TT_CHECKF(lut[((152 / 8) * 33 + 80 / 8) * 33 + 32 / 8] > 200,
                  "brown %d", lut[((152 / 8) * 33 + 80 / 8) * 33 + 32 / 8]);
        TT_CHECKF(lut[((200 / 8) * 33 + 48 / 8) * 33 + 32 / 8] == 0, "red %d",
                  lut[((200 / 8) * 33 + 48 / 8) * 33 + 32 / 8]);
        TT_CHECK(lut[((248 / 8) * 33 + 232 / 8) * 33 + 208 / 8] < 20);
    }
    free(lut);
    td_image_free(im);
}

/* A sheet drawn from the Front Range DEM at scale times its size, lines
 * 1.8 px and index lines 3.2 px, into *gp (the caller adds the defects);
 * the DEM, to free after the sheet is drawn, or NULL when it did not
 * load. */
static td_grid_f32 *front_range(td_gen_params *gp, int scale)
{
    td_ctx cx;
    td_grid_f32 *src;
    td_ctx_init(&cx);
    src = td_hsheet_dem_sheet("frontrange_srtm3.tif", scale, gp, &cx);
    TT_CHECKF(src != NULL, "%s", td_errmsg(&cx));
    return src;
}

/* The contour ink taken is a brown. */
static void check_brown(const td_palette *pal)
{
    TT_CHECK(pal->chosen >= 0);
    if (pal->chosen >= 0) {
        const uint8_t *c = pal->ink[pal->chosen].rgb;
        TT_CHECKF(c[0] > c[1] + 30 && c[1] > c[2] + 15 && c[0] < 200,
                  "contour ink #%02x%02x%02x is no brown", c[0], c[1], c[2]);
    }
}

/* A printed map drawn from the Front Range DEM (x8), scanned as it comes
 * (fringing, blur 0.8, noise 6, JPEG): --ink auto finds the contour brown,
 * keeps the red roads and the green tint apart, and the traced lines
 * cover the true contours; the fixed brown hue window (the first brown
 * selection) recovers far less. */
static void test_printed_map(void)
{
    td_gen_params gp;
    td_grid_f32 *src = front_range(&gp, 8);
    td_image *im = NULL;
    td_lines *truth = NULL;
    td_scan_params sp = td_scan_defaults();
    td_scan_result res;
    td_scanscore sc, old;
    td_ctx cx;
    int i, tint = 0;
    td_ctx_init(&cx);
    if (!src)
        return;
    gp.colour = gp.distractors = gp.print = 1;
    gp.blur = 0.8;
    gp.noise = 6;
    TT_CHECK(td_gen_sheet(&gp, &im, &truth, NULL, &cx) == 0);
    TT_CHECK(td_scan(im, &sp, &res, &cx) == 0);
    for (i = 0; i < res.palette.n; i++)
        tint += res.palette.ink[i].role == TD_INKROLE_TINT;
    TT_CHECK(tint >= 1);
    check_brown(&res.palette);
    TT_CHECK(td_match_scan(truth, res.lines, im->w, im->h, 2.0, 20.0, &sc,
                           NULL) == 0);
    td_scan_result_free(&res);
    sp.bin.ink = TD_INK_BROWN_HUE;
    TT_CHECK(td_scan(im, &sp, &res, &cx) == 0);
    TT_CHECK(td_match_scan(truth, res.lines, im->w, im->h, 2.0, 20.0, &old,
                           NULL) == 0);
    td_scan_result_free(&res);
    fprintf(stderr, "  printed map: auto recall %.3f precision %.3f own %.3f "
            "jumps %ld/%ld; brown-hue recall %.3f precision %.3f\n",
            sc.recall, sc.precision, sc.own, sc.n_jump, sc.n_traced,
            old.recall, old.precision);
    TT_CHECK(sc.recall >= 0.96);
    TT_CHECK(sc.precision >= 0.98);
    TT_CHECK(sc.own >= 0.98);
    TT_CHECK(sc.recall > old.recall + 0.1);
    td_image_free(im);
    td_lines_free(truth);
    td_grid_f32_free(src);
}

/* Draw the sheet of gp, scan it with the defaults and ink: its palette
 * into *pal and its lines scored against the truth (within 2 px) into
 * *sc. */
static void scan_scored_ink(const td_gen_params *gp, td_ink_kind ink,
                            int defringe, td_palette *pal, td_scanscore *sc)
{
    td_image *im = NULL;
    td_lines *truth = NULL;
    td_scan_params sp = td_scan_defaults();
    td_scan_result res;
    td_ctx cx;
    td_ctx_init(&cx);
    memset(pal, 0, sizeof *pal);
    memset(sc, 0, sizeof *sc);
    pal->chosen = -1;
    sp.bin.ink = ink;
    sp.defringe = defringe;
    TT_CHECK(td_gen_sheet(gp, &im, &truth, NULL, &cx) == 0);
    if (!im)
        return;
    TT_CHECKF(td_scan(im, &sp, &res, &cx) == 0, "%s", td_errmsg(&cx));
    *pal = res.palette;
    TT_CHECK(td_match_scan(truth, res.lines, im->w, im->h, 2.0, 20.0, sc,
                           NULL) == 0);
    td_scan_result_free(&res);
    td_image_free(im);
    td_lines_free(truth);
}

static void scan_scored(const td_gen_params *gp, td_palette *pal,
                        td_scanscore *sc)
{
    scan_scored_ink(gp, TD_INK_AUTO, 0, pal, sc);
}

/* Printed maps as other scanners and printings give them (the benchmark's
 * printed defects): Orkhon with the contours at full strength, whose
 * colour fringe (red channel 0.6 px right) made an orange colour of the
 * contours' edges and the red roads together, and Front Range faded with
 * no fringe, whose greyed thin brown came out farther from brown than
 * the roads' red.  Both --ink auto and --ink brown take the contour ink,
 * and the fringe is not vetoed as another ink (the lines were cut into
 * 736 pieces, 3.9 per true line, recall 0.928; --ink brown took the
 * roads: recall 0.139 and 0.120). */
static void test_print_variants(void)
{
    static const struct {
        const char *dem;
        int kind;
        double fringe;
    } v[2] = {{"orkhon_92m.tif", 4, 0.6}, {"frontrange_srtm3.tif", 3, 0.0}};
    int i, k;
    for (i = 0; i < 2; i++) {
        td_gen_params gp;
        td_grid_f32 *src;
        td_ctx cx;
        td_ctx_init(&cx);
        src = td_hsheet_dem_sheet(v[i].dem, 10, &gp, &cx);
        TT_CHECKF(src != NULL, "%s", td_errmsg(&cx));
        if (!src)
            continue;
        td_hsheet_defects(&gp, v[i].kind);
        gp.fringe[0] = v[i].fringe;
        for (k = 0; k < 2; k++) {
            td_palette pal;
            td_scanscore sc;
            scan_scored_ink(&gp, k ? TD_INK_BROWN : TD_INK_AUTO, 0, &pal, &sc);
            fprintf(stderr,
                    "  %s %s fringe %.1f --ink %s: recall %.3f "
                    "precision %.3f, %ld lines for %ld\n",
                    v[i].dem, td_defect_names[v[i].kind], v[i].fringe,
                    k ? "brown" : "auto", sc.recall, sc.precision, sc.n_traced,
                    sc.n_truth);
            check_brown(&pal);
            TT_CHECK(sc.recall >= 0.96 && sc.precision >= 0.98);
            TT_CHECK(sc.n_traced <= 3 * sc.n_truth);
        }
        td_grid_f32_free(src);
    }
}

/* The generator's printed cone (800 px, contours 5-7 px apart): the
 * contours' orange colour fringe comes out as an ink of its own (1.6 % of
 * the sheet), nearer to contour brown than the scanned contours
 * (#903d36, 22.7 %); --ink brown took the fringe (659 lines for 116
 * contours, recall 0.578).  Only inks with a tenth of the most stroky
 * ink's long strokes set brown's bar (palette.c, BROWN_STROKES): brown
 * takes the ink auto takes, recall 0.931. */
static void test_brown_not_fringe(void)
{
    td_gen_params gp = td_gen_defaults();
    td_palette pa, pb;
    td_scanscore sa, sb;
    gp.terrain = TD_GEN_CONE;
    gp.w = gp.h = 800;
    td_hsheet_defects(&gp, 3);
    scan_scored_ink(&gp, TD_INK_AUTO, 0, &pa, &sa);
    scan_scored_ink(&gp, TD_INK_BROWN, 0, &pb, &sb);
    fprintf(stderr,
            "  printed cone: auto recall %.3f, %ld lines; brown %.3f, %ld\n",
            sa.recall, sa.n_traced, sb.recall, sb.n_traced);
    TT_CHECK(pa.chosen >= 0 && pb.chosen == pa.chosen);
    TT_CHECK(sb.recall >= 0.9 && sb.n_traced <= 3 * sb.n_truth);
}

/* Elkhorn as a new print: the red roads and the contours' orange colour
 * fringe came out as one ink near the brown's hue and were taken as
 * contour ink too, so the roads were traced across the contours (own
 * contour 0.988, 11 lines jumping contours); an ink near the brown with
 * under a tenth of its long strokes is another ink (palette.c,
 * ALSO_STROKES): 0.999, 3 lines. */
/* The sheet drawn from real DEM `dem` at `scale` as print kind
 * (td_hsheet_defects) into *gp; its source DEM for the caller to free,
 * NULL when it did not load. */
static td_grid_f32 *dem_print(const char *dem, int scale, td_gen_params *gp,
                              int kind)
{
    td_ctx cx;
    td_grid_f32 *src;
    td_ctx_init(&cx);
    src = td_hsheet_dem_sheet(dem, scale, gp, &cx);
    TT_CHECKF(src != NULL, "%s", td_errmsg(&cx));
    if (src)
        td_hsheet_defects(gp, kind);
    return src;
}

/* The Elkhorn sheet (x6) as print kind `kind`. */
static td_grid_f32 *elkhorn_print(td_gen_params *gp, int kind)
{
    return dem_print("elkhorn_srtm3.tif", 6, gp, kind);
}

/* The printed Elkhorn sheet of kind (td_hsheet_defects) as the scanner
 * gets it; NULL when the DEM is missing (then skipped) or on failure. */
static td_image *elkhorn_print_image(int kind, td_ctx *cx)
{
    td_gen_params gp;
    td_grid_f32 *src = elkhorn_print(&gp, kind);
    td_image *im = NULL;
    if (src)
        TT_CHECKF(td_gen_sheet(&gp, &im, NULL, NULL, cx) == 0, "%s",
                  td_errmsg(cx));
    td_grid_f32_free(src);
    return im;
}

static void test_new_print_roads(void)
{
    td_gen_params gp;
    td_grid_f32 *src = elkhorn_print(&gp, 4);
    td_palette pal;
    td_scanscore sc;
    if (!src)
        return;
    scan_scored(&gp, &pal, &sc);
    check_brown(&pal);
    TT_CHECKF(sc.own >= 0.995 && sc.n_jump <= 6 && sc.precision >= 0.985,
              "Elkhorn new: own %.3f, %ld lines jump, precision %.3f", sc.own,
              sc.n_jump, sc.precision);
    td_grid_f32_free(src);
}

/* Elkhorn (x6) drawn at interval 20 and printed: fewer contours than at
 * 10 leave the sheet's median near the real paper, and the green tint,
 * (188, 201, 131), straddles the light/strong split of the samples; its
 * strong cluster (#84863a, from its darkest pixels) labelled the tint as
 * speckle 1.6 px "wide", an ink, and with the contours over the tint the
 * longest strokes: taken for the contour ink (recall 0.135, precision
 * 0.705).  With the speckle closed and the lightness read on the pixels
 * (palette.c) it is a tint and the brown is taken (0.941, 0.983). */
static void test_tint_straddling_split(void)
{
    td_gen_params gp;
    td_grid_f32 *src = elkhorn_print(&gp, 3);
    td_palette pal;
    td_scanscore sc;
    int i, tint = 0;
    if (!src)
        return;
    gp.interval = 20;
    scan_scored(&gp, &pal, &sc);
    check_brown(&pal);
    for (i = 0; i < pal.n; i++)
        tint += pal.ink[i].role == TD_INKROLE_TINT;
    TT_CHECKF(tint >= 1 && sc.recall >= 0.9 && sc.precision >= 0.97,
              "Elkhorn at 20, printed: %d tints, recall %.3f, precision %.3f",
              tint, sc.recall, sc.precision);
    td_grid_f32_free(src);
}

/* Elkhorn (x6) at interval 20 as a new print: the place names' black
 * text and a faded red road's thin dashes make no palette cluster of
 * their own and were traced as short lines (precision 0.964 in
 * bench_scanreal); the foreign cut (scanner/foreign.c) drops them while
 * recall stays (0.974), and since 2026-12-05 also the pieces that run
 * along a red road's flank all their length (0.976). */
static void test_foreign_lines_real(void)
{
    td_gen_params gp;
    td_grid_f32 *src = elkhorn_print(&gp, 4);
    td_palette pal;
    td_scanscore sc;
    if (!src)
        return;
    gp.interval = 20;
    scan_scored(&gp, &pal, &sc);
    check_brown(&pal);
    TT_CHECKF(sc.precision >= 0.975 && sc.recall >= 0.945,
              "Elkhorn at 20, new print: recall %.3f, precision %.3f",
              sc.recall, sc.precision);
    td_grid_f32_free(src);
}

/* The Orkhon valley (x10) at interval 50 as a new print, drawn from the
 * real DEM: its faded black grid reads as contour ink along 36-41 % of
 * the lines at x = 326 and 653, and their pieces between the contours were
 * traced as contours (precision 0.978) until the grid finder took lines
 * inked along 0.35 of their length (scanner/straight.c). */
static void test_faint_grid_real(void)
{
    td_gen_params gp;
    td_grid_f32 *src = dem_print("orkhon_92m.tif", 10, &gp, 4);
    td_palette pal;
    td_scanscore sc;
    if (!src)
        return;
    gp.interval = 50;
    scan_scored(&gp, &pal, &sc);
    check_brown(&pal);
    TT_CHECKF(sc.precision >= 0.985 && sc.recall >= 0.97,
              "Orkhon at 50, new print: recall %.3f, precision %.3f", sc.recall,
              sc.precision);
    td_grid_f32_free(src);
}

/* A scanner that misregisters the red channel by 1.2 px and the blue one
 * by -1.2 (Elkhorn printed, the benchmark's printed defects): the fringes
 * make colours of their own and the palette takes an olive for the
 * contour ink (recall 0.100); with --defringe each ink pixel takes the
 * colour around it first and the lines are found (0.937).  Since
 * 2026-12-06 the plain palette keeps the contours' orange fringe (0.79 px,
 * 808 px of long strokes per Mpx) as a second contour ink: recall 0.823
 * -> 0.864 without --defringe (precision 0.995 -> 0.983), 0.924 with. */
static void test_defringe_scan(void)
{
    td_gen_params gp;
    td_grid_f32 *src = elkhorn_print(&gp, 3);
    td_palette pal;
    td_scanscore off, on;
    if (!src)
        return;
    gp.fringe[0] = 1.2;
    scan_scored_ink(&gp, TD_INK_AUTO, 0, &pal, &off);
    scan_scored_ink(&gp, TD_INK_AUTO, 1, &pal, &on);
    fprintf(stderr,
            "  fringe 1.2 px: recall %.3f precision %.3f; "
            "defringed %.3f %.3f\n",
            off.recall, off.precision, on.recall, on.precision);
    check_brown(&pal);
    TT_CHECK(on.recall >= 0.92 && on.precision >= 0.98);
    TT_CHECK(on.recall > off.recall + 0.04 && off.precision >= 0.98);
    td_grid_f32_free(src);
}

/* Brown lines on cream with noise 8 (Front Range x10, the labelled sheet
 * of test_heights with depression ticks): the noise splits the brown into
 * darker, greyer and yellower clusters that share the lines, each too
 * thin alone; the brown is still the contour ink (it was dropped as
 * noise, and the blue river taken) and the lines are found. */
static void test_split_brown(void)
{
    td_gen_params gp;
    td_grid_f32 *src = front_range(&gp, 10);
    td_palette pal;
    td_scanscore sc;
    if (!src)
        return;
    gp.blur = 0.8, gp.noise = 8, gp.specks = 200;
    gp.breaks = 30, gp.break_min = 3, gp.break_max = 10;
    gp.labels = 3, gp.label_bend = 40, gp.label_font = 1;
    gp.colour = gp.distractors = gp.hachures = 1;
    scan_scored(&gp, &pal, &sc);
    check_brown(&pal);
    TT_CHECKF(sc.recall >= 0.97 && sc.precision >= 0.98,
              "recall %.3f precision %.3f", sc.recall, sc.precision);
    td_grid_f32_free(src);
}

/* The crowded printed sheet (Front Range x10 at interval 20, the
 * benchmark's printed defects): the lines under the green tint are the
 * contour ink printed over it, not an ink of their own, and the red roads
 * are not contour ink (recall was 0.72 and the roads were traced; the
 * printed sheets keep precision >= 0.99). */
static void test_crowded_print(void)
{
    td_gen_params gp;
    td_grid_f32 *src = front_range(&gp, 10);
    td_palette pal;
    td_scanscore sc;
    int i;
    if (!src)
        return;
    gp.interval = 20;
    td_hsheet_defects(&gp, 3);
    scan_scored(&gp, &pal, &sc);
    for (i = 0; i < pal.n; i++) {
        const uint8_t *c = pal.ink[i].rgb;
        int contour = i == pal.chosen || (pal.also >> i & 1);
        TT_CHECKF(!contour || c[0] < c[1] + 100,
                  "ink %d #%02x%02x%02x, a red, is contour ink", i, c[0], c[1],
                  c[2]);
        TT_CHECKF(!(c[1] > c[0] && c[1] > c[2] + 40 &&
                    pal.ink[i].role == TD_INKROLE_INK),
                  "ink %d #%02x%02x%02x: an olive ink (brown over the tint)",
                  i, c[0], c[1], c[2]);
    }
    TT_CHECKF(sc.recall >= 0.8 && sc.precision >= 0.99,
              "recall %.3f precision %.3f", sc.recall, sc.precision);
    td_grid_f32_free(src);
}

/* The crowded printed sheet as another scanner gives it: its levels
 * mapped by v -> lo + v (hi - lo) / 255 (gdal_translate -scale 0 255 lo
 * hi).  Two levels darker, a faded brown cluster over a darker brown one
 * looked like a crossing of two inks and the brown was dropped: the red
 * roads were taken (recall 0.861; palette.c, CROSS_APART).  Five levels
 * lighter at the paper end the benchmark's copy of this sheet lost its
 * red as noise (0.98 px, 971 px of long strokes per Mpx; MIN_LINE_LEN);
 * here the red stays at either noise bar.  The contour ink is no red, a
 * red ink stays in the palette, and the recall holds (0.916-0.933 over
 * ten such mappings of the benchmark's copy, docs/binarise.md). */
static void test_crowded_print_levels(void)
{
    static const int lev[2][2] = {{-2, 253}, {5, 255}};
    int lo[3], hi[3];
    td_gen_params gp;
    td_grid_f32 *src = front_range(&gp, 10);
    td_image *im = NULL;
    td_lines *truth = NULL;
    td_ctx cx;
    int v;
    td_ctx_init(&cx);
    if (!src)
        return;
    gp.interval = 20;
    td_hsheet_defects(&gp, 3);
    TT_CHECK(td_gen_sheet(&gp, &im, &truth, NULL, &cx) == 0);
    for (v = 0; v < 2 && im; v++) {
        td_image *sh = td_image_new(im->w, im->h, 3, &cx);
        td_scan_params sp = td_scan_defaults();
        td_scan_result res;
        td_scanscore sc;
        int i, red = 0;
        TT_CHECK(sh != NULL);
        if (!sh)
            break;
        lo[0] = lo[1] = lo[2] = lev[v][0];
        hi[0] = hi[1] = hi[2] = lev[v][1];
        td_hsheet_levels(im, sh, lo, hi);
        TT_CHECKF(td_scan(sh, &sp, &res, &cx) == 0, "%s", td_errmsg(&cx));
        for (i = 0; i < res.palette.n; i++) {
            const uint8_t *c = res.palette.ink[i].rgb;
            int r = c[0] > c[1] + 100 && c[0] > c[2] + 100;
            red |= r && res.palette.ink[i].role == TD_INKROLE_INK;
            TT_CHECKF(!r || i != res.palette.chosen,
                      "levels %d..%d: the red #%02x%02x%02x taken", lev[v][0],
                      lev[v][1], c[0], c[1], c[2]);
        }
        TT_CHECKF(red, "levels %d..%d: no red ink in the palette", lev[v][0],
                  lev[v][1]);
        TT_CHECK(td_match_scan(truth, res.lines, im->w, im->h, 2.0, 20.0, &sc,
                               NULL) == 0);
        fprintf(stderr,
                "  crowded print, levels %d..%d: recall %.3f "
                "precision %.3f\n",
                lev[v][0], lev[v][1], sc.recall, sc.precision);
        TT_CHECKF(sc.recall >= 0.91 && sc.precision >= 0.99,
                  "levels %d..%d: recall %.3f precision %.3f", lev[v][0],
                  lev[v][1], sc.recall, sc.precision);
        td_scan_result_free(&res);
        td_image_free(sh);
    }
    td_image_free(im);
    td_lines_free(truth);
    td_grid_f32_free(src);
}

/* A grey scan saved as RGB: auto takes the dark ink, as --ink dark. */
static void test_grey_as_rgb(void)
{
    td_image *im = td_image_new(300, 200, 3, NULL);
    static const uint8_t white[3] = {250, 250, 250}, black[3] = {20, 20, 20};
    td_palette pal;
    int x, y, k;
    for (y = 0; y < im->h; y++)
        for (x = 0; x < im->w; x++)
            memcpy(im->data + (size_t)y * im->stride + 3 * x, white, 3);
    for (k = 0; k < 9; k++)
        line(im, 12 + 20 * k, 0.1, 2.0, black);
    TT_CHECK(td_palette_find(im, &pal, NULL) == 0);
    TT_CHECK(td_palette_choose(&pal, 0) >= 0);
    if (pal.chosen >= 0)
        TT_CHECK(pal.ink[pal.chosen].rgb[0] < 60 &&
                 pal.ink[pal.chosen].rgb[1] < 60);
    td_image_free(im);
}

/* No ink at all: a clear error, no mask. */
static void test_paper_only(void)
{
    td_image *im = td_image_new(200, 100, 3, NULL);
    td_binarise_params p = td_binarise_defaults();
    td_grid_u8 *m = td_grid_u8_new(200, 100, NULL);
    td_ctx cx;
    int x, y;
    td_ctx_init(&cx);
    for (y = 0; y < im->h; y++)
        for (x = 0; x < im->w; x++)
            memcpy(im->data + (size_t)y * im->stride + 3 * x, CREAM, 3);
    TT_CHECK(td_binarise(im, &p, m, &cx) == TD_EFORMAT);
    TT_CHECK(strstr(td_errmsg(&cx), "no ink") != NULL);
    td_grid_u8_free(m);
    td_image_free(im);
}

/* The other inks' map the joiner and the flank cut read comes from
 * binarisation's veto now (computed once): on the printed Elkhorn sheet
 * with its red roads it is what td_binarise_other_ink gives for the same
 * scan and palette, bit for bit, and covers the roads (a few thousand
 * pixels, not the contours' millions). */
static void test_other_ink_once(void)
{
    td_image *im;
    td_grid_u8 *m = NULL;
    td_palette pal;
    uint8_t *once = NULL, *again = NULL;
    td_binarise_params bp = td_binarise_defaults();
    td_ctx cx;
    td_ctx_init(&cx);
    im = elkhorn_print_image(4, &cx);
    if (im && (m = td_grid_u8_new(im->w, im->h, &cx)) != NULL) {
        size_t nb = (size_t)im->h * (((size_t)im->w + 7) / 8), i, set = 0;
        TT_CHECKF(td_binarise_seams(im, &bp, m, &pal, NULL, NULL, &once, &cx) ==
                      0,
                  "%s", td_errmsg(&cx));
        TT_CHECK(td_binarise_other_ink(im, &pal, &again, &cx) == 0);
        TT_CHECK(once && again);
        for (i = 0; once && i < nb; i++)
            set += (size_t)__builtin_popcount(once[i]);
        TT_CHECKF(once && again && memcmp(once, again, nb) == 0 && set > 1000 &&
                      set < (size_t)im->w * im->h / 20,
                  "%zu pixels of other ink", set);
    }
    free(once), free(again);
    td_grid_u8_free(m);
    td_image_free(im);
}

/* The other inks' map is the veto table's pixels (their nearest node)
 * that lie in a 2 x 2 block of such pixels: found 64 pixels at a time, it
 * must match that definition pixel by pixel, across the words' seams and
 * at the sheet's edges (the printed Elkhorn sheet, 4524 px wide, not a
 * multiple of 64; roads run off every side). */
static int veto_px(const td_image *im, const uint8_t *lut, int x, int y)
{
    if (x < 0 || y < 0 || x >= im->w || y >= im->h)
        return 0;
    return lut[td_palette_node(im->data + (size_t)y * im->stride +
                               3 * (size_t)x)] != 0;
}

static void test_other_ink_blocks(void)
{
    td_image *im;
    td_grid_u8 *m = NULL;
    td_palette pal;
    uint8_t *bits = NULL, *lut = malloc(TD_PALETTE_LUT_SIZE);
    td_binarise_params bp = td_binarise_defaults();
    td_ctx cx;
    size_t bad = 0, set = 0, edge = 0;
    td_ctx_init(&cx);
    if (!lut || !(im = elkhorn_print_image(4, &cx))) {
        free(lut);
        return;
    }
    if ((m = td_grid_u8_new(im->w, im->h, &cx)) != NULL &&
        td_binarise_pal(im, &bp, m, &pal, &cx) == 0 &&
        td_binarise_other_ink(im, &pal, &bits, &cx) == 0 && bits) {
        size_t stride = ((size_t)im->w + 7) / 8;
        int x, y;
        td_palette_veto_lut(&pal, lut);
        for (y = 0; y < im->h; y++)
            for (x = 0; x < im->w; x++) {
                int dx, dy, core = 0, got;
                for (dy = -1; dy <= 0; dy++)
                    for (dx = -1; dx <= 0; dx++)
                        core |= veto_px(im, lut, x + dx, y + dy) &&
                                veto_px(im, lut, x + dx + 1, y + dy) &&
                                veto_px(im, lut, x + dx, y + dy + 1) &&
                                veto_px(im, lut, x + dx + 1, y + dy + 1);
                core &= veto_px(im, lut, x, y);
                got = (bits[(size_t)y * stride + (size_t)(x >> 3)] >> (x & 7)) &
                      1;
                bad += got != core;
                set += (size_t)core;
                edge +=
                    core && (x < 1 || y < 1 || x >= im->w - 1 ||
                             y >= im->h - 1 || (x & 63) == 63 || (x & 63) == 0);
            }
        TT_CHECK(im->w % 64 != 0);
        TT_CHECKF(bad == 0 && set > 1000 && edge > 10,
                  "%zu pixels differ from the definition (%zu set, %zu at "
                  "edges and word seams)",
                  bad, set, edge);
    } else {
        TT_CHECKF(0, "%s", td_errmsg(&cx));
    }
    free(bits), free(lut);
    td_grid_u8_free(m);
    td_image_free(im);
}

int main(void)
{
    TT_RUN(test_two_inks);
    TT_RUN(test_printed_map);
    TT_RUN(test_split_brown);
    TT_RUN(test_crowded_print);
    TT_RUN(test_crowded_print_levels);
    TT_RUN(test_print_variants);
    TT_RUN(test_brown_not_fringe);
    TT_RUN(test_new_print_roads);
    TT_RUN(test_defringe_scan);
    TT_RUN(test_tint_straddling_split);
    TT_RUN(test_foreign_lines_real);
    TT_RUN(test_faint_grid_real);
    TT_RUN(test_grey_as_rgb);
    TT_RUN(test_paper_only);
    TT_RUN(test_other_ink_once);
    TT_RUN(test_other_ink_blocks);
    return tt_summary();
}
