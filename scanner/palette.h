/* palette.h: the inks of a colour scan (ours; issue 14, not in the
 * papers, whose scans were binary).
 *
 * A printed topographic sheet is paper with a few inks over it (contour
 * brown, road red, water blue, black text, a green woodland tint).  Every
 * scanned pixel is paper, or a background (paper or a tint) with some
 * coverage a of one ink printed over it:
 *
 *     colour = bg * (1 - a * (1 - ink / paper))    (per RGB channel)
 *
 * (inks are filters; anti-aliased, blurred and faded line pixels are the
 * same ink at a lower a).  td_palette_find clusters a sample of the sheet
 * in CIELAB (k-means), keeps the clusters that are not such mixtures of
 * another cluster with paper or with a tint, and measures each colour's
 * strokes on a crop of the sheet: its share, its stroke width (2 area /
 * perimeter) and the length of its long thin strokes.  A colour whose
 * strokes are wider than TD_PALETTE_TINT_WIDTH px is a tint (a
 * background); the others are inks.  The contour ink is the ink with the
 * most length in long thin strokes (--ink auto), or the same among the
 * inks nearest to contour brown (--ink brown). */
#ifndef TD_PALETTE_H
#define TD_PALETTE_H

#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

#define TD_PALETTE_MAX 12
#define TD_PALETTE_TINT_WIDTH 6.0

typedef enum {
    TD_INKROLE_PAPER,
    TD_INKROLE_TINT, /* a background printed in areas */
    TD_INKROLE_INK
} td_ink_role;

typedef struct td_ink {
    uint8_t rgb[3];
    float lab[3];
    float mean[3];   /* the mean colour of its cluster's samples */
    double share;    /* of the sheet (sampled; its mixtures included) */
    double width;    /* mean stroke width, px (0 for the paper) */
    double line_len; /* px of long (>= 40 px) thin strokes per Mpx */
    td_ink_role role;
} td_ink;

typedef struct td_palette {
    int n;
    td_ink ink[TD_PALETTE_MAX];
    int paper;     /* index of the paper */
    int chosen;    /* the contour ink, or -1 */
    unsigned also; /* bit k: ink k is contour ink too (a darker or lighter
                      print of the chosen ink: same hue within 10 deg, and
                      at least a tenth of its long thin strokes) */
} td_palette;

/* Find the palette of an RGB scan (see above).  Deterministic.  Returns 0,
 * or TD_EINVAL (not RGB), TD_ENOMEM.  Memory: ~250k samples (4 KB per 1k)
 * and a crop of at most 2048 x 2048 px (5 bytes/px). */
int td_palette_find(const td_image *im, td_palette *pal, td_ctx *cx);

/* Choose the contour ink: the ink with the most long thin stroke length;
 * brown = 1: among the inks near contour brown (160,90,40) along their
 * mixtures with the paper (within BROWN_NEAR of the nearest: palette.c).
 * Sets pal->chosen; returns it, or -1 when the sheet has no ink. */
int td_palette_choose(td_palette *pal, int brown);

/* The contour ink's strength table (33^3 nodes at 0, 8, ..., 248, 255 of
 * each channel, as the brown table): 255 a for colours explained as the
 * chosen ink (or one of pal->also) over a background, within SOFT0 RGB
 * levels of the best model, falling to 0 at SOFT1 (palette.c); 0 for the
 * others. */
void td_palette_lut(const td_palette *pal, uint8_t *lut);

/* The tables' nodes per channel, and their size in bytes. */
#define TD_PALETTE_LUT_N 33
#define TD_PALETTE_LUT_SIZE                                                    \
    (TD_PALETTE_LUT_N * TD_PALETTE_LUT_N * TD_PALETTE_LUT_N)

/* Table lut at colour (r, g, b): trilinear between its nodes, integer
 * weights in eighths. */
static inline uint8_t td_palette_lut_at(const uint8_t *lut, int r, int g, int b)
{
    const int N = TD_PALETTE_LUT_N, N2 = N * N;
    const uint8_t *p = lut + ((r >> 3) * N + (g >> 3)) * N + (b >> 3);
    int fr = r & 7, fg = g & 7, fb = b & 7;
    int c00 = p[0] * (8 - fb) + p[1] * fb;
    int c01 = p[N] * (8 - fb) + p[N + 1] * fb;
    int c10 = p[N2] * (8 - fb) + p[N2 + 1] * fb;
    int c11 = p[N2 + N] * (8 - fb) + p[N2 + N + 1] * fb;
    int c0 = c00 * (8 - fg) + c01 * fg;
    int c1 = c10 * (8 - fg) + c11 * fg;
    return (uint8_t)((c0 * (8 - fr) + c1 * fr + 256) >> 9);
}

/* The node of a table nearest to the colour px[0..2]. */
static inline size_t td_palette_node(const uint8_t *px)
{
    const size_t N = TD_PALETTE_LUT_N;
    return ((size_t)((px[0] + 4) >> 3) * N + (size_t)((px[1] + 4) >> 3)) * N +
           (size_t)((px[2] + 4) >> 3);
}

/* The veto table (same nodes): 255 where an ink that is no contour ink
 * explains the colour clearly better (coverage >= 0.5, residual at least
 * 10 RGB levels under the chosen ink's), 0 elsewhere. */
void td_palette_veto_lut(const td_palette *pal, uint8_t *lut);

/* Every pixel of im labelled with the colour that explains it (an ink
 * when its coverage is >= 0.4, else the background): lbl (im's size) gets
 * the colour's index.  For --debug-dir pictures. */
int td_palette_label(const td_palette *pal, const td_image *im,
                     td_grid_u8 *lbl, td_ctx *cx);

/* How far (r,g,b) lies off the contour inks' mixtures with the paper and
 * the tints (RGB units: the best fit's residual). */
double td_palette_contour_residual(const td_palette *pal, int r, int g, int b);

/* Which colour best explains (r,g,b): the ink index (its coverage in *a)
 * or the background's (a = 0). */
int td_palette_classify(const td_palette *pal, int r, int g, int b,
                        double *a);

#ifdef __cplusplus
}
#endif

#endif
