/* gen.h: synthetic contour sheets with a known truth.
 *
 * An analytic terrain -> its true contour polylines (marching squares at
 * pixel centres, same coordinate frame as the tracer: x = col + 0.5) ->
 * a rendered "scan" with line width, blur, noise, specks, breaks and colour.
 * Used by tests/, tests/bench/, samples/ and the tdgen tool. */
#ifndef TD_GEN_H
#define TD_GEN_H

#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    TD_GEN_HILLS, /* several summits, a saddle, a depression, a tilt so
                     some contours leave the sheet (the default) */
    TD_GEN_CONE,  /* one cone in the centre: concentric closed rings */
    TD_GEN_PLANE, /* tilted plane: parallel open lines, all edge */
    TD_GEN_RIDGES, /* many contours, dense (for benchmarks) */
    TD_GEN_VALLEYS, /* a valley network: main valley and four tributaries
                       cut V-shaped into a tilted plane (drainage) */
    TD_GEN_DEM /* a real DEM (td_gen_params.dem_in) upsampled smoothly to
                  the sheet: real valleys, ridges and border-cut lines */
} td_gen_terrain_kind;

typedef struct td_gen_params {
    int w, h;      /* sheet size in pixels */
    unsigned seed; /* every random choice follows from it */
    td_gen_terrain_kind terrain;
    double base, interval; /* contour levels base + k * interval;
                              interval <= 0: automatic, see
                              td_gen_auto_interval */
    double line_width;     /* ink line width in px (1..6) */
    double index_width;    /* width of the index contours (every 5th level,
                              base + 5k * interval) in px; 0: line_width
                              (the default) */
    double blur;           /* Gaussian blur sigma in px, 0 = none */
    double noise;          /* Gaussian noise sd in grey levels, 0 = none */
    int specks;            /* number of random ink specks (1-6 px blobs) */
    int breaks;            /* number of breaks cut into the lines */
    double break_min, break_max; /* break length range in px */
    int colour; /* 0: black on white grey image; 1: brown ink on
                   cream paper RGB, with blue and black distractors
                   if distractors != 0 */
    int distractors;
    int print; /* with colour: the plates of a printed map (green tint,
                  faded brown contours, red roads, blue water, black text
                  and grid) over ageing paper, scanned (colour fringing,
                  then blur and noise, then JPEG); see samples/gen/print.c */
    double fringe[2]; /* with print: the scanner's misregistration, px:
                         the red channel shifted by (fringe[0],
                         fringe[1]), the blue one by the opposite
                         (colour fringing); the default (0.6, 0) */
    int unfaded; /* with print: the contour plate at full strength
                    everywhere (a new map); 0: faded to 55-100 % in smooth
                    patches (the default) */
    int labels; /* inline elevation labels per index contour (every 5th
                   level, base + 5k * interval), 0 = none (the default):
                   see td_gen_labels */
    const td_grid_f32 *dem_in; /* TD_GEN_DEM: the source DEM (not owned;
                                  no nodata cells), stretched over the
                                  whole sheet */
    int label_font;    /* 0: seven-segment stroke digits (the default);
                          1: DejaVu Sans digits through FreeType, the top
                          of the text towards higher ground (printed maps'
                          convention), as td_gen_sheet draws them */
    int hachures;      /* depression contours (rings around lower ground)
                          drawn with short ticks on their downhill side,
                          every 8 line widths (at least 12 px), as printed
                          maps mark them (0: plain, the default) */
    int spots;         /* spot heights: up to this many summits marked with
                          a dot and their height (rounded) beside it,
                          horizontal, as printed maps do (0: none, the
                          default; needs labels' font settings) */
    int streams;       /* with colour: the water plate from the terrain's
                          flow (samples/gen/streams.c) instead of a random
                          river: streams crossing the contours at their Vs
                          (0: the river, the default) */
    double label_bend; /* labels only where the line stays within this many
                          px of the chord over the label and 25 px either
                          side; 0: 2.5 (straight stretches, the default);
                          larger puts labels on curves too */
} td_gen_params;

/* Defaults: 1000 x 1000, seed 1, HILLS, base 0, interval 0 (automatic),
 * line width 2, no blur, noise, specks or breaks (break length 1..3 px when
 * breaks are asked for), grey; a printed sheet's fringe 0.6 px in x. */
td_gen_params td_gen_defaults(void);

/* The truth surface sampled at pixel centres (w x h), heights in metres.
 * Cell (i,j) holds the surface at x = j + 0.5, y = i + 0.5.  Deterministic
 * from p->seed.  Shapes, with S = min(w,h):
 *   HILLS   features placed and sized relative to S (a 200 px and a 10000 px
 *           sheet look alike): three Gaussian summits (two joined by a
 *           saddle), a Gaussian depression and a gentle tilt; heights about
 *           0..450 m.  Steepest slope about 1.3 m/px * 1000 / S.
 *   CONE    h = 400 * (1 - r / (0.45 S)) about the sheet centre, continuing
 *           below 0 towards the corners.
 *   PLANE   a tilted plane, 300 m per S, direction from the seed.
 *   RIDGES  four plane waves with wavelengths 350..900 px in absolute pixels
 *           (not relative to S, so the ink fraction is the same at any size):
 *           steepest slope <= 1.5 m/px, about 14% ink with 3 px lines at
 *           interval 10.
 *   VALLEYS z = 0.3 (h - y) + 0.35 softmin_k sqrt(d_k^2 + 64), k = 6 m, d_k
 *           the distance to thalweg k (td_gen_valley_segments): V-shaped
 *           valleys 0.35 m/px steep across, falling 0.3 m/px down the
 *           sheet, sharp-crested ridges between them; slopes absolute
 *           (m/px), geometry relative to the sheet; seed ignored.
 * Returns 0 and *dem (free with td_grid_f32_free), or an error. */
int td_gen_terrain(const td_gen_params *p, td_grid_f32 **dem, td_ctx *cx);

/* The thalwegs of the VALLEYS terrain for p's sheet size: up to max
 * segments (x0, y0, x1, y1) in pixel units (x = column + 0.5 at a pixel
 * centre) into seg; returns how many there are (5). */
size_t td_gen_valley_segments(const td_gen_params *p, double (*seg)[4],
                              size_t max);

/* The steepest slope of dem in height units per pixel (central differences,
 * one-sided at the border).  Adjacent contours at interval I are then at
 * least about I / slope pixels apart. */
double td_gen_max_slope(const td_grid_f32 *dem);

/* The interval td_gen_sheet uses: p->interval when > 0, else the smallest
 * of 1, 2, 2.5, 5 x 10^k that is >= 10 and keeps adjacent contours of dem
 * at least 6.5 px apart (10 on a default 1000 x 1000 HILLS sheet, 20 at
 * 600 x 450, 50 at 200 x 200; always 10 for RIDGES).  For TD_GEN_DEM the
 * slope is the 98th percentile, not the maximum, so contours crowd and
 * touch on the steepest 2% as they do on printed maps. */
double td_gen_auto_interval(const td_gen_params *p, const td_grid_f32 *dem);

/* True contours of dem at base + k*interval: one td_line per connected
 * contour, with height, closed (ring) or edge (ends on the grid border).
 * Caller frees with td_lines_free. */
int td_gen_contours(const td_grid_f32 *dem, double base, double interval,
                    td_lines **out, td_ctx *cx);

/* A break cut into line `line` (index into the td_lines): the ink is
 * missing along the line between arc lengths s0 and s1 (s1 - s0 is the
 * visible gap, measured along the line); (x,y) is the gap's middle. */
typedef struct td_gen_break {
    size_t line;
    double s0, s1;
    double x, y;
} td_gen_break;

/* The breaks td_gen_render cuts for p (p->breaks of them, fewer when the
 * lines are too short to hold them): lines chosen at random weighted by
 * length among lines >= 40 px, length uniform in [break_min, break_max],
 * never within 10 px of an open line's ends, never overlapping.  Returns 0
 * with *out (free()) and *n, or an error. */
int td_gen_breaks(const td_lines *lines, const td_gen_params *p,
                  td_gen_break **out, size_t *n, td_ctx *cx);

/* Render lines as a scanned sheet per p (size p->w x p->h).
 * Ink coverage of a pixel = clamp(width/2 + 0.5 - d, 0, 1), d = distance
 * from the pixel centre to the nearest drawn segment; grey = 255 * (1 -
 * coverage) on white (colour: brown (160,90,40) mixed over cream
 * (245,235,210) by coverage).  Then, in this order: breaks (td_gen_breaks),
 * specks (1..6 px blobs at least 4 px from any ink and 15 px from any
 * break), distractors (colour only: a blue 2 px river and black text-like
 * words that keep 4 px away from the contours), Gaussian blur, Gaussian
 * noise.  Grey: 1 channel; colour: 3.  Returns 0 and *sheet (free with
 * td_image_free), or an error. */
int td_gen_render(const td_lines *lines, const td_gen_params *p,
                  td_image **sheet, td_ctx *cx);

/* Fraction of pixels darker than threshold (grey, or the mean of the
 * channels for RGB). */
double td_gen_ink_fraction(const td_image *im, int threshold);

/* All three in one: sheet, truth lines and the truth DEM (any out pointer
 * may be NULL when not wanted).  The interval is td_gen_auto_interval's.
 * Truth lines carry height, closed (rings never touch the border) and edge
 * (open lines, both ends on the border pixels' centres, i.e. within 0.5 px
 * of the sheet's edge). */
int td_gen_sheet(const td_gen_params *p, td_image **sheet, td_lines **truth,
                 td_grid_f32 **dem, td_ctx *cx);

/* Inline elevation labels, as printed maps write them: on each index
 * contour of truth (height base + 5k * interval) up to p->labels places
 * (one per 250 px of line) where the line is straight within
 * p->label_bend px (default 2.5) over the label and 25 px either side and
 * no other line comes within the digits' half height + line width + 4 px
 * of the chord, the line is erased over a gap of 20-60 px along it (along
 * its curve) and its height
 * is drawn inside the gap as stroke digits (seven-segment shapes, 10-16 px
 * tall, 1.5-2 px strokes, along the line, reading left to right) in the
 * contour ink.  Drawn into im (td_gen_render's output before blur and
 * noise; grey or colour).  The truth is not changed.  Places are seeded by
 * p->seed.  *nplaced (may be NULL) gets the number of labels drawn.
 * Returns 0 or TD_ENOMEM. */
int td_gen_labels(const td_lines *truth, const td_gen_params *p,
                  double interval, td_image *im, size_t *nplaced, td_ctx *cx);

/* As td_gen_labels; with dem (the truth surface, may be NULL) the text's
 * top faces uphill (dem's gradient at the label), else it reads left to
 * right.  With p->label_font 1 the digits are DejaVu Sans (FreeType,
 * Debian fonts-dejavu-core; TD_EIO naming the font file when it is not
 * there).  The labels drawn are reported in *out (may be NULL; free()):
 * per label its centre x, y, the text's reading direction (unit dx, dy),
 * digit height and value, 6 doubles each, *nout of them. */
int td_gen_labels_dem(const td_lines *truth, const td_gen_params *p,
                      double interval, const td_grid_f32 *dem, td_image *im,
                      double **out, size_t *nout, td_ctx *cx);

/* Spot heights on the sheet im drawn from dem (the truth surface at the
 * sheet's size): up to p->spots summits and pits (the highest or lowest
 * point within 20 px, at least half an interval above or below the ground
 * 30 px around, 40 px from the border, 120 px from each other; summits
 * first, the highest first, then pits), each a dot of 2 px
 * radius at the summit and its height rounded to whole units in the label
 * font, horizontal, beside it (right, left, above or below) where it
 * covers no ink; a summit with no clear place is left out, as a
 * cartographer would.
 * *out (may be NULL; free()) gets x, y, height per spot, *nout how many.
 * Returns 0, TD_EINVAL (dem not the sheet's size) or TD_ENOMEM. */
int td_gen_spots(const td_gen_params *p, const td_grid_f32 *dem,
                 td_image *im, double **out, size_t *nout, td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
