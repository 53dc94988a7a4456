/* scan.h: the scanner stage as one call: scan image -> contour lines.
 *
 *   image -> td_binarise -> mask -> td_thin_hilditch -> skeleton
 *         -> td_despur -> td_trace (CCW 3x3, 5x5 bridge)
 *         -> td_pale_trace (colour: faded contours clear of the ink,
 *            traced on their own and added)
 *         -> td_border_cut (lines cut where they turn back at the border)
 *         -> td_flank_cut (colour: stretches along other inks cut out)
 *         -> td_join -> lines
 *         -> td_foreign_cut (colour: short lines in another ink dropped)
 *         -> td_line_widths (each line's ink width, from the mask)
 *         -> td_wide_cut (lines cut where contours crowd into one blob)
 *
 * Memory: the mask is thinned, despurred and traced in place; a copy of it
 * packed one bit per pixel is kept until the widths are measured (+1/8
 * byte per pixel; none with measure_width 0), and with the wide-ink cut
 * and seams on, the seam pixels packed the same way (+1/8 byte).  With
 * keep_debug, copies of the mask and the thinned skeleton are kept in the
 * result (+2 bytes per pixel).  Colour scans with pale: the faded
 * ridges packed (+1/8 byte per pixel) from before thinning until traced,
 * then their box's grid (+1 byte per pixel of it) beside the skeleton;
 * below the scan's peak (281 -> 282 MB on a 6000 x 6000 print). */
#ifndef TD_SCAN_H
#define TD_SCAN_H

#include "scanner/binarise.h"
#include "scanner/defringe.h"
#include "scanner/despur.h"
#include "scanner/join.h"
#include "scanner/pale.h"
#include "scanner/straight.h"
#include "scanner/thin.h"
#include "scanner/trace.h"
#include "scanner/width.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The automatic own-width cut (td_scan_params.wide_own < 0): this many
 * pens where the ink's edges are narrower than TD_SCAN_CRISP_EDGE px
 * (crisp sheets 0.41-0.48, blurred by 0.5 px 0.48, by 0.8 px 0.68-0.82). */
#define TD_SCAN_WIDE_OWN 0.75
#define TD_SCAN_CRISP_EDGE 0.55

typedef struct td_scan_params {
    td_binarise_params bin;
    td_despur_params spur;
    td_trace_params trace;
    td_join_params join;  /* w,h filled in by td_scan */
    int do_join;          /* default 1 */
    int join_other;       /* colour scans: the joiner is told where other
                             inks lie (td_join_params.other; ours;
                             default 1) */
    td_straight_params straight; /* grid lines erased (straight.h, ours) */
    int defringe;                /* colour scans read through the palette (--ink
                                    auto, brown): colour fringes taken out first
                                    (defringe.h, ours; on a copy of the scan,
                                    +3 bytes per pixel while binarising); default
                                    0: it saves strongly fringed scans but moves
                                    the palette on others (docs/binarise.md,
                                    "Print variants") */
    td_defringe_params fringe;
    int detint;           /* colour scans read through the palette: inks
                             over a tint divided by it (detint.h, ours; a
                             copy of the scan, +3 bytes per pixel while
                             binarising); default 0: it saves roads over
                             woodland (the printed hills sheet's heights
                             0.59 -> 1.00) but moves the heights of other
                             sheets both ways (docs/binarise.md, "Inks over
                             a tint") */
    int measure_width;    /* set each line's width (width.h), default 1 */
    int blob_rings;       /* tiny rings that printed as dots of ink get
                             back their circle (blobring.h; ours; needs
                             measure_width), default 1 */
    int ticks;            /* rings with depression ticks inside are marked
                             td_line.depression when at least this many
                             ticks are read (ticks.h; ours), default 2;
                             0: not read */
    double wide_cut;      /* lines are cut where the ink across them
                             (with the seams between touching lines) is
                             wider than this many pens (the sheet's median
                             line width) with another line inside
                             (widecut.h; ours; needs measure_width),
                             default 3; 0: off */
    double wide_rib;      /* and on sheets where contours crowd, where
                             the seams split that blob into one rib a
                             contour, only within a few vertices of where
                             the line's rib is wider than this many pens
                             (two ribs touching: widecut.h; ours),
                             default 2.2; 0: the whole blob's stretch */
    int hairpin_cut;      /* and there cut open lines where they turn back
                             (widecut.h; ours), default 1 */
    double wide_own;      /* and where it is wider than the line's own
                             width + this many pens with another line
                             ending there (two inks overlapping: widecut.h;
                             ours); < 0 (default): auto, TD_SCAN_WIDE_OWN
                             where the ink is crisp (its edges under
                             TD_SCAN_CRISP_EDGE px: there inks overlap
                             with no seam between them), else off (on
                             blurred sheets the seams split them, and the
                             cut costs the DEM: docs/scanner.md); 0: off */
    int flank_cut;        /* cut traced stretches that run along another
                             ink's strokes (a road's flanks; flank.h;
                             ours; colour scans with join_other), default
                             1 */
    int foreign_cut;      /* colour scans read through the palette: drop
                             short lines whose core colour is no mixture
                             of the contour ink (text, road dashes;
                             foreign.h; ours), default 1 */
    int border_cut;       /* lines cut where they turn back at the sheet's
                             border (two contours leaving the sheet
                             merged into one V; bordercut.h; ours),
                             default 1 */
    int pale;             /* colour scans read through the palette: faded
                             contours found apart from the ink and traced
                             on their own (pale.h; ours), default 1 */
    td_pale_params pale_p;
    int keep_debug;       /* keep mask and skeleton copies in the result */
    int skel_bits;        /* keep the skeleton the lines were traced on,
                             packed, less what lies beside another ink
                             (td_scan_result.skel_bits; default 0) */
} td_scan_params;

typedef struct td_scan_result {
    td_lines *lines;
    td_grid_u8 *mask;      /* ink mask (keep_debug only) */
    td_grid_u8 *skeleton;  /* after thinning (keep_debug only) */
    td_grid_u8 *despurred; /* after spur removal: always kept */
    uint8_t *skel_bits;    /* p.skel_bits: the same, one bit a pixel (rows
                              of (w + 7) / 8 bytes), without the pixels
                              within TD_FLANK_NEAR px of another ink's
                              strokes (a road's flanks read as contour
                              ink) and within a pixel of the stretches
                              the cuts along other inks took out of the
                              lines (flank.h, foreign.h): the labeller's
                              step edges (td_label_params.skeleton) */
    uint8_t *other;        /* the other inks' strokes the joiner keeps
                              off (td_binarise_other_ink: packed, one bit
                              a pixel; keep_debug only, NULL when none) */
    td_thin_stats thin;
    td_despur_stats spur;
    td_trace_stats trace;
    td_join_stats join;
    size_t blob_rings;     /* tiny rings redrawn from their dots */
    size_t depressions;    /* rings read as depressions from their ticks */
    double edge;           /* the width of the ink's edges in px
                              (binarise.h's half-tone share x the pen / 2),
                              -1 when not measured */
    double wide_own;       /* the own-width cut used (pens; 0: off) */
    size_t wide_cuts;      /* lines cut where contours crowd into one blob
                              of ink (widecut.h) */
    td_lines *walls;       /* the stretches cut there (widecut.h), for the
                              labeller's faces (td_label_params.walls) */
    size_t straight_lines; /* grid lines erased from the mask */
    size_t flank_cuts;     /* stretches cut along other inks (flank.h) */
    size_t border_cuts;    /* lines cut where they turned back at the
                              border (bordercut.h) */
    size_t foreign;        /* short lines dropped as another ink's
                              (foreign.h) */
    size_t pale;           /* faded lines traced apart (pale.h) */
    td_palette palette;    /* the inks found on a colour scan (--ink auto
                              or brown; n = 0 otherwise) */
    double seconds[5];     /* binarise, thin, despur, trace, join */
} td_scan_result;

td_scan_params td_scan_defaults(void);

/* Run the scanner on im.  On success fills *res (free its members with
 * td_scan_result_free).  On failure returns the error and leaves *res
 * empty. */
int td_scan(const td_image *im, const td_scan_params *p, td_scan_result *res,
            td_ctx *cx);

void td_scan_result_free(td_scan_result *res);

#ifdef __cplusplus
}
#endif
#endif
