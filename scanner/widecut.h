/* widecut.h: lines cut where their ink is too wide to tell the contours
 * in it apart (ours; not in the papers).
 *
 * Where three or more contours crowd into one blob of ink (a canyon wall
 * at a small interval), the skeleton keeps one branch for several
 * contours and a traced line runs from one onto another: a line carrying
 * two heights, which no labeller can label.  The seams (binarise.h) split
 * such ink into ribs, one a contour, but the ribs touch here and there and
 * a line hops between them; so the width is measured on the ink with the
 * seams put back (the caller's mask).  A stretch of a line along
 * which the ink across it is wider than `maxw` px, over at least 4
 * vertices, with another traced line inside that ink (within maxw / 2 +
 * 1 px of the stretch), is cut out: the line ends on both sides of the
 * blob, open ends the labeller handles, instead of jumping through it.
 * A line's own ink (a ring touching itself, a dot) is left alone, and so
 * is a closed line shorter than 8 maxw (a small ring is one contour; drawn
 * as a solid dot its ink is wide all round).
 *
 * Where the seams did split the blob, most of it need not go: a line
 * follows its own rib and can only step onto the next where two ribs
 * touch.  With the ribs given (td_wide_params.ribs, ribw > 0), on a
 * sheet where contours crowd (at least WC_RIB_DENSE, 60, wide stretches
 * a megapixel; elsewhere the few blobs are pinches, cut whole), only the
 * vertices of a wide stretch within WC_RIB_MARGIN (3) of one where the
 * line's rib is wider than ribw are cut out, and those within maxw / 2
 * of another ink (td_wide_params.other: a road across crowded contours
 * hides where they touch) (docs/scanner.md, "Blobs split by their
 * seams": recall on the crowded sheets +0.03-0.04).
 *
 *     ==========            ====  ====   (the rest of the stretch
 *     =====X====    ->      ====  ====    kept: the lines end only at
 *     ==========            ====  ====    the contact X)
 *
 * Two contours whose inks overlap for a stretch (an index contour and a
 * thin one on a crisp sheet: no seam between them, one band of ink 1.6
 * times the index width) are narrower than maxw; with addw > 0 a stretch
 * is also wide where the ink is wider than the line's own width
 * (td_line.width) + addw, and such a stretch is cut only where another
 * traced line ends within maxw / 2 + 1 px of it (the contour that ran
 * into this one and was left open at the merge); lines running side by
 * side, both traced through, stay whole.
 *
 *     ====a\                      ====a
 *     =====>######=====     ->    =====      =====     (a left open,
 *     ====b/                      ====b                 not paired) */
#ifndef TD_WIDECUT_H
#define TD_WIDECUT_H

#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Cut the lines of ls where the ink of the packed w x h mask bits
 * (width.h's layout) across them is wider than maxw px, as above.  A cut
 * line's pieces are open, flagged td_line.junc at the cut ends, and get
 * width 0 (measure them again); the first keeps the line's id, the others
 * get new ids after the largest.  Pieces of fewer than 3 vertices are
 * dropped.  Returns the number of lines cut, or TD_ENOMEM. */
long td_wide_cut(const uint8_t *bits, int w, int h, td_lines *ls, double maxw,
                 td_ctx *cx);

/* What td_wide_cut_walls cuts. */
typedef struct td_wide_params {
    double maxw;         /* px: ink wider than this is a blob */
    double addw;         /* px: and wider than the line's own width + this
                            with another line ending there (0: off) */
    const uint8_t *ribs; /* the ink with the seams taken out (same layout
                            as bits; may be NULL) */
    double ribw;         /* px: with ribs, a blob's stretch is cut only
                            within a few vertices of where the line's rib
                            is wider than this (two ribs touching) */
    const uint8_t *other; /* with ribs, the other inks (a road, lettering;
                             same layout; may be NULL): near them the
                             blob's stretch is cut whole */
    int hairpins;         /* with ribs, where contours crowd, also cut open
                             lines where they turn back (more than 134
                             degrees between chords of 8 vertices): two
                             contours whose inks met at a V's tip, or one
                             contour's V whose arms touch (ours; on in
                             td_scan by default: docs/scanner.md) */
} td_wide_params;

/* The same, with wp: the merges over the line's own width + addw px,
 * and the rib contacts (the blob whole when ribs is NULL or ribw is 0);
 * walls (may be NULL) gets every stretch cut out, with the vertex before
 * and after it (where the pieces end): the blobs, for the labeller's
 * faces (faces.h: no face runs through them). */
long td_wide_cut_walls(const uint8_t *bits, int w, int h, td_lines *ls,
                       const td_wide_params *wp, td_lines *walls, td_ctx *cx);

/* After labelling: each wall of td_wide_cut_walls whose two sides (the
 * lines of ls ending at its first and at its last vertex) got one height
 * goes back into ls as a line of that height (the source and confidence
 * of the less sure side, a new id), for the interpolation: the cut was
 * needed only where the two sides are different contours, and a stretch
 * left out is ink the DEM does not see.  Returns the number put back, or
 * TD_ENOMEM. */
long td_walls_restore(td_lines *ls, const td_lines *walls, td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
