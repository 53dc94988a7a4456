/* binarise.h: scan image -> ink mask (1 = ink, 0 = paper).
 *
 * Ink selection (--ink), thresholding (--threshold) and speck removal
 * (--min-speck).  Image operations go through the OpenCV shim
 * (src/cvshim.h); this file is plain C.  User guide: docs/binarise.md.
 *
 * Pipeline: image -> "ink strength" s (u8, high = ink, built one row at a
 * time into the caller's mask) -> threshold (in place) -> speck removal
 * (in place).  No full-size temporaries. */
#ifndef TD_BINARISE_H
#define TD_BINARISE_H

#include "src/core/core.h"
#include "scanner/palette.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    TD_INK_AUTO,      /* grey: dark; colour: the palette's contour ink */
    TD_INK_DARK,      /* 255 - luma */
    TD_INK_BROWN,     /* colour: the palette's long-stroke ink
                          among those near contour brown */
    TD_INK_BROWN_HUE, /* colour: the fixed brown hue window (the first
                         brown selection; see docs/binarise.md) */
    TD_INK_RGB
} td_ink_kind;
typedef enum { TD_THR_OTSU, TD_THR_SAUVOLA, TD_THR_FIXED } td_thr_kind;

typedef struct td_binarise_params {
    td_ink_kind ink;    /* default TD_INK_DARK */
    uint8_t rgb[3];     /* TD_INK_RGB: the ink colour */
    int rgb_tol;        /* TD_INK_RGB: colour distance tolerance, default 60
                           (1..442, Euclidean in RGB levels) */
    td_thr_kind thr;    /* default TD_THR_OTSU */
    int thr_value;      /* TD_THR_FIXED: 0..255 on the ink-strength image
                           (ink where s > thr_value) */
    int sauvola_window; /* default 31 (odd, 3..181) */
    double sauvola_k;   /* default 0.2 (0 < k <= 1) */
    int min_speck;      /* ink components smaller than this many pixels
                           (8-connected) are removed; default 8, 0 = keep */
    int min_hole;       /* paper components (pinholes in the ink) smaller
                           than this are filled; default 8, 0 = keep.  Not
                           the paper's: noisy scans leave pinholes that
                           thinning would keep as tiny loops */
    int split;          /* split touching lines (not the paper's): an ink
                           pixel under the ink's mean level with ink at
                           least this many levels stronger within 2 px on
                           both sides, along a row, column or diagonal
                           within 45 degrees of the ink's normal (the
                           structure tensor over 3 x 3 px), is the lighter
                           seam between two blurred lines and becomes
                           paper; diagonal contacts across a seam are cut.
                           The margin used is at least 3 noise deviations
                           (measured on the paper).  Default 24, 0 = off.
                           Otsu and fixed thresholds only */
    int local_level;    /* Otsu: where the ink is paler than the sheet's,
                           threshold lower (the local ink level, ours;
                           docs/binarise.md); default 1, 0 = off */
    int cores;          /* with the local level, in the tiles it lowers:
                           faded line cores (ridges of strength over 0.4
                           t) 8-connected to the ink are ink (ours;
                           docs/binarise.md, "Faded line cores"); default
                           0 (off: more lines, but the labeller's heights
                           worse on the bench sheets), 1 = on */
    const td_palette *palette; /* TD_INK_AUTO / TD_INK_BROWN on a colour
                                  scan: this palette (found and chosen,
                                  e.g. on the scan before td_detint)
                                  instead of finding one; default NULL */
    const td_image *veto_im;   /* the same: the veto table reads this
                                  image (im's size; e.g. td_detint's)
                                  instead of im; default NULL */
} td_binarise_params;

/* Otsu splits whose class means differ by fewer levels than this are
 * treated as "no ink": the sheet is paper and noise only. */
#define TD_BINARISE_MIN_CONTRAST 40

td_binarise_params td_binarise_defaults(void);

/* Parse "--ink" and "--threshold" values into p; 0 or TD_EINVAL with a
 * message naming the bad value.  ink: dark | brown | R,G,B[:tol] (tol kept
 * from p when not given); thr: otsu | sauvola | N (0..255). */
int td_binarise_parse_ink(const char *s, td_binarise_params *p, td_ctx *cx);
int td_binarise_parse_threshold(const char *s, td_binarise_params *p,
                                td_ctx *cx);

/* The exact "brownness" of one colour, 0..255 (docs/binarise.md):
 *   255 * hue_weight(H) * sat_weight(C / max(V, 128)) * value_weight(V)
 * with H the HSV hue in degrees, C = max - min, V = max (RGB levels).
 * td_binarise uses a 33^3 table of this function with trilinear lookup. */
uint8_t td_binarise_brown_score(uint8_t r, uint8_t g, uint8_t b);

/* The ink-strength image of im for p->ink into s (caller allocates s with
 * im's w,h): dark: 255 - luma; brown: table brownness; R,G,B:tol:
 * 255 * max(0, 1 - dist/tol).  For debugging (--debug-dir) and tests.
 * Returns 0 or TD_EINVAL (bad sizes, colour ink on a grey scan). */
int td_binarise_strength(const td_image *im, const td_binarise_params *p,
                         td_grid_u8 *s, td_ctx *cx);

/* Binarise im into mask (caller allocates mask with im's w,h; values become
 * 0/1).  Returns 0, or an error: TD_EINVAL (bad parameters, --ink brown or
 * R,G,B on a grey scan), TD_EFORMAT "no ink found (is --ink right?)" when
 * the sheet has no ink at all (Otsu classes closer than
 * TD_BINARISE_MIN_CONTRAST levels, or an empty mask), TD_ECANCEL.
 * On error the mask's contents are unspecified.
 * Progress: stage "binarise".  Peak extra memory: no per-pixel memory (the
 * strength image is built in mask and thresholded in place); 36 KB table
 * for brown; O(width x (128 + window)) for Sauvola; O(min_speck) for speck
 * removal. */
int td_binarise(const td_image *im, const td_binarise_params *p,
                td_grid_u8 *mask, td_ctx *cx);

/* td_binarise, and *pal (may be NULL) gets the palette found for
 * TD_INK_AUTO and TD_INK_BROWN on a colour scan (pal->n = 0 otherwise). */
int td_binarise_pal(const td_image *im, const td_binarise_params *p,
                    td_grid_u8 *mask, td_palette *pal, td_ctx *cx);

/* td_binarise_pal, and with --seams the seam pixels (ink made paper as
 * the seam between two touching lines) set in seams (packed one bit a
 * pixel as td_width_pack, zeroed by the caller; may be NULL).  *halftone
 * (may be NULL) gets the share of half-tone pixels to ink pixels: those
 * whose strength lies a quarter to three quarters of the way from the
 * paper's mean to the ink's, over those above the sheet's level (-1 with
 * Sauvola's local levels).  Times half the lines' width it is about the
 * width of the ink's edges in px: 0.41-0.48 on crisp sheets, 0.68-0.93
 * blurred by 0.8-1.2 px (binarise.md, "Crisp ink").  *other (may be
 * NULL) gets what td_binarise_other_ink gives for im and the palette
 * found (the bits the veto cleared the strength round, computed once;
 * free them), NULL when there is no veto. */
int td_binarise_seams(const td_image *im, const td_binarise_params *p,
                      td_grid_u8 *mask, td_palette *pal, uint8_t *seams,
                      double *halftone, uint8_t **other, td_ctx *cx);

/* The pixels of im that another ink than the contour ink covers (the
 * palette's veto, as binarisation clears them: a road, a river, black
 * lettering) packed one bit a pixel as td_width_pack, into *bits
 * (calloc'ed; free it); *bits NULL when pal found no such ink (grey scans,
 * pal->n == 0).  0 or TD_ENOMEM. */
int td_binarise_other_ink(const td_image *im, const td_palette *pal,
                          uint8_t **bits, td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
