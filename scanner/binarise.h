/* binarise.h: scan image -> ink mask (1 = ink, 0 = paper).
 *
 * Ink selection (--ink), thresholding (--threshold) and speck removal
 * (--min-speck).  Image operations go through the OpenCV shim
 * (src/cvshim.h); this file is plain C. */
#ifndef TD_BINARISE_H
#define TD_BINARISE_H

#include "../src/grid.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum { TD_INK_DARK, TD_INK_BROWN, TD_INK_RGB } td_ink_kind;
typedef enum { TD_THR_OTSU, TD_THR_SAUVOLA, TD_THR_FIXED } td_thr_kind;

typedef struct td_binarise_params {
    td_ink_kind ink;      /* default TD_INK_DARK */
    uint8_t rgb[3];       /* TD_INK_RGB: the ink colour */
    int rgb_tol;          /* TD_INK_RGB: colour distance tolerance, default 60 */
    td_thr_kind thr;      /* default TD_THR_OTSU */
    int thr_value;        /* TD_THR_FIXED: 0..255 on the ink-strength image */
    int sauvola_window;   /* default 31 (odd) */
    double sauvola_k;     /* default 0.2 */
    int min_speck;        /* ink components smaller than this many pixels
                             (8-connected) are removed; default 8, 0 = keep */
} td_binarise_params;

td_binarise_params td_binarise_defaults(void);

/* Parse "--ink" and "--threshold" values into p; 0 or TD_EINVAL with a
 * message naming the bad value.  ink: dark | brown | R,G,B[:tol];
 * thr: otsu | sauvola | N (0..255). */
int td_binarise_parse_ink(const char *s, td_binarise_params *p, td_ctx *cx);
int td_binarise_parse_threshold(const char *s, td_binarise_params *p,
                                td_ctx *cx);

/* Binarise im into mask (caller allocates mask with im's w,h; values become
 * 0/1).  Returns 0, or an error (e.g. the sheet has no ink at all:
 * TD_EFORMAT "no ink found").  Peak extra memory: 1 byte per pixel plus
 * O(width x window) for Sauvola. */
int td_binarise(const td_image *im, const td_binarise_params *p,
                td_grid_u8 *mask, td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
