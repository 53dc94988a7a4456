/* ocr.h: read the height labels printed in the gaps of index contours
 * (ALGORITHMS.md A.5, "printed labels"; ours).
 *
 * Where a label cuts a contour the scanner joins the line across the gap
 * (td_join's label-gap stage, whose joins it records).  Each such gap is a
 * candidate: the scan is sampled in a strip along the gap's chord, the ink
 * components that touch no side of the strip (the digits; the contour's
 * own ends and other lines run out of it) are kept, boxed, scaled to
 * digits about 32 px tall and read by Tesseract as one line of digits
 * (whitelist 0-9 and '-'), as sampled and binarised (the strokes' cores),
 * each way round; the most confident read wins and the other numbers read
 * are kept as its alternatives, for the labeller to choose among, with
 * each number that one digit's runner-up among Tesseract's choices gives
 * (LSTM choices: a faint "1875" read "1675" keeps "1875" at 0.67 of its
 * confidence).
 *
 *     contour ====      2 3 5 0      ==== contour      strip along the
 *                 |<---- gap ---->|                    chord, both ways
 *
 * Tesseract through its C API (Debian libtesseract-dev, the English model
 * tesseract-ocr-eng). */
#ifndef TD_OCR_H
#define TD_OCR_H

#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Another reading of a label, and how sure Tesseract was of it. */
#define TD_OCR_ALTS 4
typedef struct td_ocr_alt {
    double value, conf; /* conf 0: none */
    int turned;         /* read the other way round from (ux, uy) */
} td_ocr_alt;

typedef struct td_ocr_read {
    double x, y;      /* the label's middle, scan px */
    double ux, uy;    /* reading direction as read: the text's top is
                         towards (uy, -ux) on the screen */
    double digit_px;  /* height of the digits on the scan */
    double len;       /* length of the text along (ux, uy), px */
    double value;     /* the number read */
    double conf;      /* Tesseract's confidence, 0..1 */
    td_ocr_alt alt[TD_OCR_ALTS]; /* the other numbers read (other
                         thresholds, the digits binarised, the text turned
                         half round, one digit as Tesseract's runner-up
                         choice), most confident first, conf 0 after
                         the last: the labeller weighs them all */
    long line[2];     /* indexes into the lines: the line through the
                         label (a joined gap), or the one or two lines
                         ending at it (a gap left open); -1: none */
    char text[24];    /* the text read */
    int spot;         /* a spot height: no line through the text and a
                         dot beside it (the summit, at sx, sy) */
    double sx, sy;
    int used;         /* the labeller took it (set by td_label_auto) */
    const char *why;  /* static: why it was not used, or NULL */
} td_ocr_read;

typedef struct td_ocr_params {
    const char *tessdata; /* folder holding eng.traineddata; NULL: the
                             library's default (Debian:
                             /usr/share/tesseract-ocr/5/tessdata) */
    double min_conf;      /* reads below this are dropped (default 0.4:
                             of the benchmark sheets' reads at 0.3-0.4,
                             11 of 12 were wrong) */
    double digit_px;      /* digits are scaled to this height (32) */
    const struct td_palette *ink; /* a colour scan's inks (td_scan's
                             palette), or NULL (the default).  With the
                             contour ink chosen, a label the luminance
                             does not read sure is read again in that
                             ink's strength: a label knocked out of a
                             tint sits in a light box the luminance sees
                             as the text (ours) */
} td_ocr_params;

td_ocr_params td_ocr_defaults(void);

/* Read the labels marked by pieces (lines: the label-gap joins and the
 * text fragments that td_join records, small rings; pieces whose boxes
 * come within 6 px of each other are one candidate, read along the main
 * axis of their points) on the scan im (grey or RGB); ls are the joined
 * lines (for td_ocr_read.line).  *out (free()) and *n get the reads that parse
 * as numbers with conf >= min_conf.  Returns 0, TD_EIO (Tesseract or its
 * English model missing: the message says what to install) or
 * TD_ENOMEM. */
int td_ocr_labels(const td_image *im, const td_lines *ls, const td_lines *gaps,
                  const td_ocr_params *p, td_ocr_read **out, size_t *n,
                  td_ctx *cx);

/* The label pieces of a scan (td_scan with join.record: the label-gap
 * joins and removed text in *join) and the small closed lines of its
 * lines ls (digits traced as rings: inside a 25 px box), read as above;
 * on an RGB scan with p->ink also the pale digits near the open ends of
 * ls (type lighter than the lines, under the mask's level: a row of
 * digit-sized pieces of the contour ink's strength, their own candidates;
 * ocr.c, pale_pieces); the reads are tied to the lines of assoc (ls
 * itself, or lines traced before and edited). */
struct td_join_stats;
int td_ocr_scan_labels(const td_image *im, const td_lines *ls,
                       const struct td_join_stats *join, const td_lines *assoc,
                       const td_ocr_params *p, td_ocr_read **out, size_t *n,
                       td_ctx *cx);

/* Spot heights among the reads: a read no line runs through whose text
 * has a dot beside it (a dark compact blob of 5-40 px, at most 7 px
 * across, within 14 px of the text's box and outside it) gets spot = 1 and
 * the dot's centre in sx, sy.  Returns how many. */
size_t td_ocr_find_spots(const td_image *im, td_ocr_read *r, size_t n);

/* Remove the tiny closed lines of ls (at most 9 px across: a dot traced
 * as a ring, or redrawn from a dot by scanner/blobring.h) that have text
 * beside them: a piece of text (the joiner's removed text, td_join_stats
 * .text) within 14 px: a spot height's dot whose digits were not read.
 * The reads' line indexes follow.  Returns how many. */
size_t td_ocr_drop_dots(td_lines *ls, const td_lines *text, td_ocr_read *r,
                        size_t n);

/* Box every label read on the RGB picture im (src/draw.h): a box along
 * the text, dark blue when the labeller used it, grey when not. */
void td_ocr_draw(td_image *im, const td_ocr_read *r, size_t n);

/* Remove the closed lines of ls that lie inside a read label's box (digits
 * such as 0, 6, 8, 9 traced as rings); the reads' line indexes are kept
 * pointing at the same lines.  Returns how many. */
size_t td_ocr_drop_digits(td_lines *ls, td_ocr_read *r, size_t n);

#ifdef __cplusplus
}
#endif
#endif
