/* join.h: join traced lines across gaps the 5x5 bridge cannot span.
 * ALGORITHMS.md A.4 "beyond".  Not in the paper: the paper bridges only
 * inside its 5x5 window.  A break of b px in a line of width w leaves a
 * skeleton gap of about b + w px (thinning pulls both ends back), so breaks
 * of 2-4 px in 3-6 px lines need this step. */
#ifndef TD_JOIN_H
#define TD_JOIN_H

#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* td_join_params.keep_pieces: the short pieces the text filter takes */
enum {
    TD_PIECES_OFF,    /* removed (default) */
    TD_PIECES_JOINED, /* kept and joined like any line */
    TD_PIECES_LATE    /* set aside before the joins, put back unjoined after
                         them: the joins are the default's */
};

typedef struct td_join_params {
    double max_gap;   /* stage 1: longest small gap joined, px (default 16) */
    double max_angle; /* largest angle, degrees, between each end's outward
                         tangent and the gap (default 40) */
    double tangent;   /* length along the line over which an end's tangent is
                         measured, px (default 8) */
    int w, h;         /* sheet size: ends on the border are never joined */
    double min_length; /* stage 0: open lines shorter than this (px) with
                          both ends inside the sheet that do not continue
                          other lines are removed as label/text fragments
                          (default 25; 0: off) */
    double straight_keep; /* stage 0 (ours): a short piece whose chord is
                             at least this share of its length, with no
                             curled piece (a digit) within 12 px, is a
                             piece of a faded or broken contour and stays
                             (default 0.8; 0: off, every short piece goes) */
    double curl_keep;     /* stage 0 (ours): a compact piece (fitting in a
                             min_length box) at least this many min_length
                             long, its two ends 4 px apart or more, with no
                             other candidate piece or small ring within 8 px
                             (a label's glyphs stand side by side) and not
                             on another ink, is a stretch of contour curled
                             round a small summit or pit, or between two
                             faded breaks it pairs across with nothing: it
                             stays (docs/scanner.md, "Curled pieces";
                             default 1; 0: off) */
    int alone_gaps;       /* stage 4 (ours): after the others, gaps of 3.5-8 px
                             whose ends each head into them (within 60 degrees,
                             the two within 90 of head on), with no other open
                             end within twice the gap before stage 1 and no line
                             across, are joined: a contour's faded ink broken
                             where it bends.  Right joins, but the heights move
                             either way (docs/scanner.md, "Short gaps alone";
                             default 0) */
    int chains; /* stage 0 (ours): short pieces that pair end to end into a
                   chain running from one longer line's end to another's
                   are a contour broken several times, and stay (default
                   1) */
    int keep_pieces;   /* stage 0 (ours; TD_PIECES_*): more short pieces
                          stay as contour:
                          one end continuing a longer line (unless half the
                          piece lies on another ink: a road's dash), pieces
                          between two skeleton junctions of the contour
                          network from 0.4 min_length, and every line
                          traced from faded ridges (td_line.pale).  More
                          of a faded sheet's lines (docs/scanner.md,
                          "Pieces the text filter takes"; default
                          TD_PIECES_OFF; with TD_PIECES_LATE the caller
                          puts them back: td_scan does) */
    double long_gap;   /* stage 2: longest label gap joined, px (default
                          70: a 60-px label gap plus the skeleton's pull-back
                          at both ends; <= max_gap: off) */
    double long_tangent; /* stage 2 tangent chord length, px (default 20) */
    int curves;        /* stage 2 also joins curved gaps (one circle fits
                          both ends, each end curving alike) and every
                          stage-2 join follows a curve along both end
                          tangents; 0: straight rule and chords only
                          (default 1) */
    int record;        /* keep the stage-2 join paths in the stats */
    double bridge_max; /* before stage 0: open pieces no longer than this
                          (px) with both ends at skeleton junctions (the
                          tracer's cut, td_line.junc) are removed: a
                          stretch two touching contours share (default
                          12; 0: off) */
    double chain_max;  /* before stage 1 (ours): chains of 3 or more
                          straight open pieces no longer than this (px),
                          each lined up with the next across a gap of up
                          to 40 px that another line crosses (a road cut
                          at every contour it crosses) are removed
                          (default 80; 0: off) */
    const uint8_t *other; /* stage 2 (ours): pixels another ink covers (a
                             road, a river; td_binarise_other_ink: packed
                             bits, w x h), or NULL.  A contour hidden under
                             a road is no label gap: a stage-2 join whose
                             path runs over another ink (within 1 px) for
                             more than 8 px and a third of its length is
                             not made (default NULL; td_scan sets it on
                             colour scans) */
    const uint8_t *water; /* stage 3 (ours): pixels the water ink covers
                             (td_streams_water_bits: packed bits, w x h),
                             or NULL (default; td_scan sets it on colour
                             scans) */
    double cross_gap;     /* stage 3: contours cut where a stream crosses
                             them: two ends this near (px) whose tangents
                             meet on the water (the V of a contour cut at a
                             stream), or face each other across it, are
                             joined through that point (default 16; 0:
                             off) */
    double gap_room;      /* stage 2 (ours): a gap is not joined when
                             another open line ends within this many
                             times its length of either end (not on the
                             border): gaps side by side, a faded patch
                             of crowded contours where each end could be
                             any neighbour's (default 0.5; 0: off) */
    int water_turns;      /* after stage 0 (ours; with water and
                             cross_gap): a line that turns back by more
                             than 120 degrees next to the water, its arms
                             side by side beyond the turn and the water
                             not between them, is cut there; its two ends
                             are not joined again but across the water
                             (two contours a stream's bank links), and
                             when neither end finds its continuation
                             there the cut is undone (default 1; 0:
                             off) */
    double junc_ratio; /* junction zones: a pair whose end has another
                          partner (on another line) costing under this
                          many times as much is left open: two contours
                          running into one stretch of ink, either could
                          go on along it (default 1.5; <= 1: off) */
    double gap_ratio;  /* stage 1 (ours): a gap pair, one of whose ends has
                          another candidate on a third line costing under
                          this many times as much, is left open (<= 1:
                          off) */
    double gap_near;   /* stage 1 (ours): a gap pair 6 px long or more
                          is left open when an end of a third line
                          lies within this share of the gap's length of
                          either of its ends, whatever its direction: a
                          contour turning sharply where its ink broke
                          (default 0.5; <= 0: off) */
} td_join_params;

typedef struct td_join_stats {
    size_t joins;      /* gaps joined (including closures), both stages */
    size_t closures;   /* lines closed by joining their own two ends */
    size_t ends_open;  /* open ends left (not on the border) */
    size_t fragments;  /* short open fragments removed (stage 0) */
    size_t late_pieces; /* keep_pieces TD_PIECES_LATE: pieces set aside by
                           stage 0 (in late) */
    size_t long_joins; /* of joins: made by stage 2 */
    size_t cross_joins; /* of joins: made by stage 3, across the water */
    size_t alone_joins; /* of joins: made by stage 4, short gaps alone */
    double *cross_at;   /* x, y of each stage-3 join's middle (its bend
                           P, or its chord's middle): cross_joins pairs;
                           free with td_join_stats_free */
    size_t water_turns; /* lines cut where they turned back at the water
                           (two contours linked by a stream's bank) */
    double *water_at;   /* per cut 6 values: x, y of the vertex dropped
                           and of the two ends it left; free with
                           td_join_stats_free */
    size_t gaps_open;   /* ends left open by stage 1's side-step and
                           near-end rules (td_join_params.gap_ratio,
                           gap_near); the later stages do not join them
                           either */
    double *gaps_at;    /* x, y of each of those ends, sorted; free with
                           td_join_stats_free */
    size_t curls;       /* compact pieces kept as curled contour
                           (td_join_params.curl_keep) */
    size_t bridges;    /* short pieces between two junctions removed */
    size_t road_pieces; /* straight pieces in chains removed (chain_max) */
    size_t glyphs;     /* small closed rings (digits such as 0, 6, 8, 9)
                          removed because a stage-2 join passes through,
                          or next to a removed label fragment */
    size_t merges;      /* junction zones (contours touching): all */
    size_t merges_open; /* of them: with a branch left open (no pairing
                           without a crossing or a sharp turn) */
    td_lines *segments; /* p->record only: each stage-2 join as a line
                           (its path: 2 points for a chord, more along a
                           curve); free with td_join_stats_free */
    td_lines *text;     /* p->record only: the fragments (stage 0) and
                           glyph rings (stage 2) removed: where text is,
                           for reading the labels (scanner/ocr.h) */
    td_lines *late;     /* keep_pieces TD_PIECES_LATE: the pieces stage 0
                           set aside (late_pieces of them), not joined,
                           marked td_line.piece, for the caller to put
                           back after its own cuts (td_scan does) */
} td_join_stats;

td_join_params td_join_defaults(int w, int h);

/* Free what td_join left in st (the recorded segments); st itself is the
 * caller's.  NULL is a no-op. */
void td_join_stats_free(td_join_stats *st);

/* Join open lines of *ls whose ends face each other across a gap, and close
 * lines whose two ends meet, in three stages:
 *   0. (min_length > 0) remove short open fragments (label digits, text)
 *      whose ends do not both continue other lines across a small gap;
 *   1. small gaps up to max_gap: both end tangents point across the gap;
 *   2. (long_gap > max_gap) label gaps up to long_gap: both tangents face
 *      the gap, the ends' sideways shift is at most max(2.5, 0.15 * gap) px
 *      and their common bend at most 0.3 * gap, or (curves) a circle fits
 *      both ends and their own curvature agrees with it (join.c), and the
 *      join crosses no other line (small closed rings excepted: a ring
 *      under min_length that a stage-2 join passes through is a digit and
 *      is removed).
 * Pairs are taken cheapest first (gap length weighted by the tangent
 * disagreement), each end at most once.  *ls is replaced by the joined set
 * (ids renumbered in order); bridged counts add up.  st may be NULL (and
 * must be freed with td_join_stats_free when p->record).  Returns 0 or
 * TD_ENOMEM (then *ls may have lost fragments but is a valid set). */
int td_join(td_lines **ls, const td_join_params *p, td_join_stats *st,
            td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
