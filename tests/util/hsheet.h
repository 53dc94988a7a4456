/* hsheet.h: height accuracy end to end on a generated sheet (tests and
 * benchmarks): generate (any terrain, or a real DEM), scan, label with
 * hints taken from the truth, score with td_match_heights. */
#ifndef TD_TEST_HSHEET_H
#define TD_TEST_HSHEET_H

#include "samples/gen/gen.h"
#include "scanner/label.h"
#include "tests/util/match.h"

typedef struct td_hsheet {
    td_gen_params gp;           /* the sheet (terrain, dem_in, size, defects) */
    int nknown;                 /* known points on index contours (0..8) */
    int index_every;            /* pass --index-every (0: no widths at
                                   all; -1: the spacing the widths fit,
                                   picked by the solve) */
    int use_truth_lines;        /* label the truth lines, not the traced ones */
    int paper_junctions;        /* trace through junctions as the paper does */
    int detint;                 /* colour: the scan's tints divided out
                                   (td_scan_params.detint) */
    int search;                 /* td_label_params.search: 0 its default,
                                   -1 off */
    double gap_pairs;           /* td_label_params.gap_pairs (0: the
                                   labeller's default, on for colour
                                   scans; < 0: off) */
    int oracle;                 /* price the true heights under the whole
                                   model too (rep.oracle_cost; faces) */
    int oracle_ties;            /* with oracle: rep.oracle_ties too */
    double oracle_box[4];       /* x0, y0, x1, y1: only the lines wholly
                                   inside take their true heights there,
                                   the others keep the answer (one region's
                                   price; x1 <= x0: every line) */
    int read_labels;            /* read the printed labels (scanner/ocr.h) and
                                   give them to the labeller */
    int no_interval;            /* infer the interval from the labels */
    int steps;                  /* the labeller's step edges (the scan's
                                   skeleton: td_label_params.skeleton) */
    int no_vees;                /* colour: do not read the streams' Vs
                                   (scanner/streams.h; read by default) */
    int no_stream_joins;        /* colour: the joiner's stage 3 off
                                   (td_join_params.cross_gap 0) */
    size_t nreads, reads_right; /* labels read; read right (the value of
                                   the true line under them) */
    size_t used_right, used_wrong; /* labels the labeller used, with the
                                      value it took right and wrong */
    td_labeller method;
    const char *png; /* when set: the verdicts drawn over the sheet
                        (green right, red wrong, blue assumed and
                        right, orange assumed and wrong, grey none);
                        the sheet itself beside it (png.sheet.png) and
                        the labelled lines (png.lines.geojson) */
    /* results */
    td_hscore score;
    td_label_report rep; /* the labeller's report (free it) */
    size_t traced, truth;
    double interval, label_secs;
} td_hsheet;

/* Up to n known points (into kp) on the longest index contours (levels
 * a multiple of 5 intervals) of tl with distinct heights, each at its
 * middle vertex; how many. */
int td_hsheet_pick_known(const td_lines *tl, double interval, int n,
                         td_label_point *kp);

/* Run *hs; 0, or an error in cx.  Hints: the nknown longest index contours
 * (levels multiple of 5) with distinct heights, each at its middle
 * vertex.  log (may be NULL) gets the wrong sure lines. */
int td_hsheet_run(td_hsheet *hs, FILE *log, td_ctx *cx);

/* The scanner benchmarks' sheets drawn from the real DEMs
 * (tests/data/dems): name, DEM file, scale, interval (0: automatic); and
 * the names of td_hsheet_defects' kinds 0-3. */
typedef struct td_real_sheet {
    const char *name, *dem;
    double scale, interval;
} td_real_sheet;
#define TD_REAL_SHEETS 7
extern const td_real_sheet td_real_sheets[TD_REAL_SHEETS];
extern const char *const td_defect_names[5];

/* The benchmarks' sheet defects: kind 0 clean (lines 1.8 px, index
 * contours 3.2 px), 1 scanned (blur 0.8, noise 8, 300 specks, 40 breaks of
 * 3-10 px, printed DejaVu labels), 2 the same in colour (brown on cream,
 * blue river, black lettering), 3 a printed map (tdgen --print), 4 the
 * same map new (--print --unfaded: the contours at full strength).  The
 * environment's BENCH_FRINGE=DX,DY sets the printed kinds' misregistration
 * (tdgen --fringe; default 0.6,0). */
void td_hsheet_defects(td_gen_params *p, int kind);

/* *gp (td_gen_defaults) set for a sheet drawn from tests/data/dems/<dem>
 * at scale x its size, lines 1.8 px and index lines 3.2 px (the caller
 * adds the defects); the DEM, to free once the sheet is drawn, or NULL
 * with the error in cx. */
td_grid_f32 *td_hsheet_dem_sheet(const char *dem, double scale,
                                 td_gen_params *gp, td_ctx *cx);

/* RGB image in mapped into out (the same size) as another scanner gives
 * it: per channel v -> lo + v (hi - lo) / 255, rounded and clamped
 * (gdal_translate -scale 0 255 lo hi). */
void td_hsheet_levels(const td_image *in, td_image *out, const int lo[3],
                      const int hi[3]);

/* Load a real DEM (../shared/dems/NAME) into *out, or return nonzero. */
int td_hsheet_load_dem(const char *path, td_grid_f32 **out, td_ctx *cx);

#endif
