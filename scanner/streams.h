/* streams.h: which way the contours rise, read where streams cross them
 * (ours; issue 13, "on colour sheets, streams"; not in the papers).
 *
 * A contour crossing a valley bends upstream: its V points up the stream,
 * to higher ground (the rule of Vs).  On a colour scan the water inks (the
 * palette's blue inks) mark the streams.  Where a traced line
 * crosses water (a stretch of at most VEE_RUN px with water within 2 px,
 * at least 8 water pixels within 8 px, and water again 3-10 px away on
 * both sides of the line: the stream goes through, it does not run along
 * or start there, and it is more than a few stray pixels), the line's bend is
 * measured: the crossing's offset from the chord between the points 8, 16
 * and 24 px along the line either way.  A V is sharp at its apex: offset
 * at least VEE_APEX (2 px) at 8 px, more at 16, all on one side (a round
 * bend that a river happens to cross, or a kink where the stream's ink cut
 * the line, is not taken); its apex's side is the higher one. */
#ifndef TD_SCANNER_STREAMS_H
#define TD_SCANNER_STREAMS_H

#include "scanner/palette.h"
#include "src/core/core.h"

typedef struct td_vee {
    double x, y;   /* where the stream crosses the line, scan px */
    long line;     /* index into the lines */
    int up;        /* the higher side: 0 towards (ty, -tx) of the line's
                      travel (tx, ty) there, 1 the other */
    double ux, uy; /* unit vector from (x, y) towards the higher side */
    double conf;   /* 0..1: the V's sharpness (its offset 8 px either side
                      over VEE_SURE, 4 px) */
} td_vee;

/* The palette's water inks, bit k for ink k: the inks (not the contour
 * ink) blue in CIELAB (b* <= -8 and -b* >= |a*|; a stream's ink comes as
 * two colours where it is drawn wider or over the tint). */
unsigned td_streams_water_inks(const td_palette *pal);

/* The pixels of the RGB scan im that pal's water inks cover (coverage
 * >= 0.4), packed one bit a pixel as td_width_pack, into *bits (calloc'ed;
 * free it); *bits NULL when pal has no water ink.  0 or TD_ENOMEM. */
int td_streams_water_bits(const td_image *im, const td_palette *pal,
                          uint8_t **bits, td_ctx *cx);

/* The Vs of the lines ls where the water ink of pal crosses them on the
 * RGB scan im (none when the palette has no water ink): *out (free()) and
 * *n.  Crossings within 4 px of one of the nskip points skip (x, y pairs:
 * where the joiner joined a contour across the water, td_join_stats.
 * cross_at) are not read: the bend there is the join's, drawn from the
 * ends' tangents, and it is a V only where the water is a stream in its
 * valley (across the generator's random river 7 of 8 such "Vs" were
 * wrong).  Returns 0 or TD_ENOMEM.  Memory: a 33^3 table and the Vs. */
int td_streams_vees(const td_image *im, const td_palette *pal,
                    const td_lines *ls, const double *skip, size_t nskip,
                    td_vee **out, size_t *n, td_ctx *cx);

/* Each V drawn on im (RGB): an arrow 9 px long from the crossing towards
 * the higher side, in blue. */
void td_streams_draw(td_image *im, const td_vee *v, size_t n);

#endif
