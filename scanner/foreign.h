/* foreign.h: short traced lines printed in another ink (ours; not in the
 * papers).
 *
 * On a colour scan the palette takes the contour ink's strength from each
 * pixel's colour, but inks it did not find as clusters of their own (a
 * little black text, a faded red road whose dashes are thinner than its
 * veto's 2 x 2 blocks) still come through where their colour lies near
 * the contour ink's: letters and road dashes are traced as short lines.
 * Their core pixels are not mixtures of the contour ink with the paper or
 * a tint: grey text, pink dashes lie far off those mixing lines, where a
 * contour's pixels lie on them (measured on the bench_scanreal sheets:
 * docs/scanner.md, "Lines in another ink").
 *
 * A line shorter than TD_FOREIGN_LEN px whose core colour is off the
 * mixing lines by TD_FOREIGN_RES or more (RGB units, the palette's fit;
 * the median over its vertices of the darkest pixel of the 3 x 3 about
 * each) is dropped, unless it crosses the other inks' strokes (comes
 * within TD_FLANK_NEAR px of them at some of its vertices, fewer than
 * half): a contour's stretch across a road takes the road's colour
 * (dropped, one such stretch cost the printed Elkhorn sheet 0.03 of its
 * heights), while a line near them all along is the road's own flank.
 * After the joiner: a letter joined onto a contour stays with it. */
#ifndef TD_FOREIGN_H
#define TD_FOREIGN_H

#include "scanner/palette.h"
#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

#define TD_FOREIGN_LEN 150.0 /* px */
#define TD_FOREIGN_RES 30.0  /* RGB units off the contour ink's mixes */

/* The median residual of line l's core colour on im (RGB) against the
 * contour ink's mixing lines of pal; -1 when it has no vertex inside. */
double td_foreign_residual(const td_image *im, const td_palette *pal,
                           const td_line *l);

/* Drop from ls the short lines printed in another ink (above); other:
 * the other inks' strokes (td_binarise_other_ink's bits, w x h of im) or
 * NULL.  Nothing without a palette (grey scans).  The lines left keep
 * their order.  Returns the number dropped or TD_ENOMEM. */
long td_foreign_cut(td_lines *ls, const td_image *im, const td_palette *pal,
                    const uint8_t *other, td_ctx *cx);

#ifdef __cplusplus
}
#endif

#endif
