/* detint.h: inks printed over a tint shown over the paper (ours; issue 14,
 * not in the papers, whose scans were binary).
 *
 * A printed sheet's inks are filters: a red road printed over the green
 * woodland tint comes out red times green, which is brown, the contour
 * ink's colour over the paper (after the scanner's blur and JPEG's colour
 * blur, thin lines take the hue around them: a dark olive).  The palette
 * (palette.h) sees colours only, and no table of colours can tell the two
 * apart: only what lies beside the pixel can.  So:
 *
 *   bg(p)   = the per-channel brightest value within r px (inks only
 *             darken: the paper or tint under the ink)
 *   tint(p) = a tint T of the palette when a pixel within r + 1 px is of
 *             it (the palette explains it as T, with no ink at coverage
 *             0.1 or more, and it lies nearer T than the paper) and bg(p)
 *             lies nearer a tint than the paper; else none
 *   v'(p)   = v(p) * paper / T      (per channel; v(p) where no tint)
 *
 * The tint's own pixels become the paper, a road over the tint red over
 * the paper again.  A pixel on the paper within r px of a tint keeps its
 * colour (its bg is the paper).  td_scan --detint reads the veto (another
 * ink's strokes cleared) on v' and the contour ink's strength on the scan
 * as it is: thin contours over the tint, which JPEG left the tint's hue,
 * come out of the division redder than brown (docs/binarise.md, "Inks
 * over a tint"). */
#ifndef TD_DETINT_H
#define TD_DETINT_H

#include "scanner/palette.h"
#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

#define TD_DETINT_RADIUS 3

/* Whether pal has a tint to divide out (role TD_INKROLE_TINT). */
int td_detint_any(const td_palette *pal);

/* out = im with its tints divided out (above), radius r (1..8).  im and
 * out RGB, the same size, distinct; out caller-allocated.  Deterministic;
 * row bands of 32 rows on threads, 4 (34 + 2 r) + 3 bytes per pixel of
 * the width per thread (163 at r = 3), and a 36 KB table.  0, or TD_EINVAL (images, radius, no paper), TD_ENOMEM. */
int td_detint(const td_image *im, const td_palette *pal, int r, td_image *out,
              td_ctx *cx);

#ifdef __cplusplus
}
#endif

#endif
