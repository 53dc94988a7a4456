/* pale.h: faded contours traced apart from the ink (ours; colour scans;
 * not in the papers).  docs/scanner.md, "Faded lines apart".
 *
 * A printed sheet fades and yellows unevenly: where its paper is lighter
 * than the palette's paper, a contour at a third of the ink's strength is
 * as dark as the palette's paper and no threshold on the ink's strength
 * keeps it, though the eye sees it plainly.  What stays is its shape: a
 * thin ridge of colour change along the paper-to-ink direction.  Such
 * ridges, found apart from (never touching) the thresholded ink, are
 * thinned and traced on their own, and the joiner pairs their ends with
 * the ink's lines by its end rules, so a faded stretch never ties two
 * contours by a contact. */
#ifndef TD_PALE_H
#define TD_PALE_H

#include "scanner/despur.h"
#include "scanner/palette.h"
#include "scanner/trace.h"
#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct td_pale_params {
    double depth;   /* a ridge pixel is at least this share of the paper
                       to ink distance darker (along it) than both pixels
                       2 px off across it (default 0.15) */
    double hue_cos; /* and its difference from them points from paper to
                       ink within this cosine (default 0.9) */
    int apart;      /* px kept clear round the ink and other inks
                       (default 2) */
    int min_points; /* shortest pale line kept, points (default 12) */
} td_pale_params;

td_pale_params td_pale_defaults(void);

/* The faded lines' ridges of RGB scan im (pal: its palette, with a
 * chosen contour ink) not within p->apart px of mask's ink (0/1, w x h of
 * im) nor of other's pixels (packed bits as td_binarise_other_ink, or
 * NULL), packed one bit a pixel (rows of (w + 7) / 8 bytes) into *bits
 * (free it); *bits NULL on grey scans or without a chosen ink.  Called on
 * the mask before thinning.  0 or TD_ENOMEM. */
int td_pale_find(const td_image *im, const td_palette *pal,
                 const td_grid_u8 *mask, const uint8_t *other,
                 const td_pale_params *p, uint8_t **bits, td_ctx *cx);

/* Those ridges (w x h) as a layer of their own: the grid erased, specks
 * removed, thinned, despurred (sp) and traced (tp); the lines of
 * p->min_points or more that are no piece of a faint grid appended to
 * lines (ids renumbered).  Returns how many, or a negative TD_E*. */
long td_pale_trace(const uint8_t *bits, int w, int h, const td_pale_params *p,
                   const td_despur_params *sp, const td_trace_params *tp,
                   td_lines *lines, td_ctx *cx);

#ifdef __cplusplus
}
#endif

#endif
