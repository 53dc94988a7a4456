/* defringe.h: colour fringes and bled colour taken out of a colour scan
 * before its inks are found (ours; issue 14, not in the papers, whose
 * scans were binary).
 *
 * A scanner shifts its red, green and blue channels against each other by
 * a fraction of a pixel, and JPEG keeps the colour at half the resolution
 * of the lightness: a thin brown contour comes out with an orange edge on
 * one side and a pink or blue one on the other, and its middle greyer
 * than its ink.  Those edge colours are mixtures of no ink with the paper,
 * and the palette (palette.h) took them for inks of their own: an orange
 * "ink" that took the red roads with it, vetoed or traced (docs/binarise.md,
 * "Print variants").  Shifts and blur move colour about but keep its sum
 * over a neighbourhood, so:
 *
 *   bg(p)  = the per-channel brightest value within r_bg px (the paper or
 *            tint under the ink: inks only darken)
 *   f(p)   = 1 - v(p) / bg(p)             (per channel: the ink's share of
 *                                          the light taken, as the palette's
 *                                          mixture model has it)
 *   F(p)   = sum of f over the (2 r + 1)^2 window (equal weights: a
 *            channel shifted within the window keeps its sum)
 *   v'(p)  = bg(p) (1 - F(p) L(f(p)) / L(F(p)))
 *
 * L the luminance weights (0.299, 0.587, 0.114): every ink pixel keeps its
 * own lightness (sharp) and takes the colour of the ink around it.  Pixels
 * whose lightness L(f) is under TD_DEFRINGE_MIN (paper, noise, and the
 * lightest fringe: 0.1 on every channel instead lost the palette on two
 * printed sheets, docs/binarise.md) are left as they are. */
#ifndef TD_DEFRINGE_H
#define TD_DEFRINGE_H

#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

#define TD_DEFRINGE_MIN 0.04

typedef struct td_defringe_params {
    int radius;    /* r: the window the colour is taken from (default 3) */
    int bg_radius; /* r_bg: where the background is looked for (default 3) */
} td_defringe_params;

td_defringe_params td_defringe_defaults(void);

/* The per-channel maximum of RGB row y of im (clamped to the image)
 * across x - r .. x + r (held at the edges) into out (3 w bytes): the
 * background under thin ink (defringe.c, detint.c). */
void td_rgb_row_max(const td_image *im, int y, int r, uint8_t *out);

/* out = im defringed (above).  im and out RGB, the same size, distinct;
 * out caller-allocated.  Deterministic; row bands on threads, about
 * 30 bytes per pixel of a band's width of working memory per thread.
 * Returns 0, or TD_EINVAL (images, radii 0..8), TD_ENOMEM. */
int td_defringe(const td_image *im, td_image *out, const td_defringe_params *p,
                td_ctx *cx);

#ifdef __cplusplus
}
#endif

#endif
