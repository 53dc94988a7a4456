/* pipeline.h: the stages joined into what the commands and batches run
 * (one header for src/pipeline/): a sheet -> lines -> heights -> DEM as
 * library calls, and the debug pictures they write.  File I/O is allowed
 * here (as in src/io and the CLI); nothing here prints or exits. */
#ifndef TD_PIPELINE_H
#define TD_PIPELINE_H

#include "src/core/core.h"
#include "src/io/io.h"
#include "scanner/scan.h"
#include "src/erode/erode.h"
#include "scanner/label.h"
#include "scanner/ocr.h"
#include "scanner/palette.h"
#include "interp/interp.h"

#ifdef __cplusplus
extern "C" {
#endif

/* scan --debug-dir DIR (made when missing): mask.png, skeleton.png,
 * despurred.png, overlay.png (traced lines over the faded scan, label-gap
 * joins magenta), join.txt, and for colour scans palette.png, ink-K.png,
 * inks.txt.  0 or an error naming the file. */
int td_pipeline_scan_debug(const char *dir, const td_image *im,
                           const td_scan_result *r, td_ctx *cx);

/* --debug-dir DIR of label and run (made when missing): heights.png,
 * every line over the scan (NULL: white, w x h) coloured by its height,
 * the streams' Vs as blue arrows uphill, and when reads is not NULL the
 * labels read boxed on it and labels.geojson, one point per label read
 * (text, value, angle, confidence, line, used, why), through geo.  0 or
 * an error. */
int td_pipeline_heights_debug(const char *dir, const td_image *scan, int w,
                              int h, const td_lines *ls,
                              const td_ocr_read *reads, size_t nreads,
                              const td_vee *vees, size_t nvees,
                              const td_georef *geo, td_ctx *cx);

/* ---- around the labeller (label.c) ---- */

/* The printed height labels of the scan the lines ls were traced from:
 * the scan traced again for where the labels are, read (Tesseract) and
 * tied to ls's lines.  *reads (free()), *n; and on a colour scan the Vs
 * where streams cross ls's lines (scanner/streams.h): *vees (free()),
 * *nvees (vees NULL: not read); *colour (may be NULL): whether the scan is
 * in colour (inks found).  0 or an error. */
int td_pipeline_sheet_labels(const char *scan, const td_lines *ls,
                             td_ocr_read **reads, size_t *n, td_vee **vees,
                             size_t *nvees, int *colour, td_ctx *cx);
/* Ink widths and darkness (width.h) of lines that carry none (a file not
 * written by topodig scan), measured on the scan binarised with the
 * scanner's defaults.  Nothing happens when any line has a width.  0 or
 * an error. */
int td_pipeline_scan_widths(const char *scan, td_lines *ls, td_ctx *cx);
/* The operator's heights (rows of id,height; a NaN height: none given)
 * onto the lines with those ids; a height off base + k * interval is a
 * warning in checks (may be NULL), and kept.  0 or TD_EINVAL (bad id,
 * no such line). */
int td_pipeline_apply_heights(td_lines *ls, const double *rows, size_t n,
                              td_label_report *checks,
                              const td_label_params *p, td_ctx *cx);
/* The label sheet of the paper's operator entry (001 §2.3): every line in
 * its own colour, its id at idxy (td_line_id_places), over the scan like
 * (may be NULL: white, w x h).  PNG at path; 0 or an error. */
int td_pipeline_label_sheet(const char *path, const char *like, int w, int h,
                            const td_lines *ls, const double *idxy,
                            td_ctx *cx);

/* ---- run: a sheet -> lines -> heights -> DEM ---- */

struct td_run_result;

/* What td_pipeline_run does.  label: the hints (interval, base, known
 * points, depressions, index_every, method); its w, h and labels are
 * filled in.  on_labelled (may be NULL) is called once every line has its
 * height or null, before the lines without one are dropped: the place to
 * write the labelled lines and the debug pictures (r->scan is kept for it
 * when keep_scan).  A nonzero return stops the run with that code.
 * on_refused (may be NULL) is called instead when the labeller refuses
 * (TD_EINVAL: no interval inferred, heights that contradict): every line
 * without a height, the labels read in r->reads; the place to write the
 * debug pictures that show why.  The run then stops with the labeller's
 * error whatever on_refused returns. */
typedef struct td_run_params {
    td_scan_params scan;
    int read_labels;       /* read the printed labels (default 1) */
    int read_streams;      /* colour scans: read the streams' Vs
                              (scanner/streams.h; default 1) */
    td_label_params label;
    td_interp_params interp;
    int steps;             /* the labeller's step edges: probes across
                              skeleton ink no line was traced on
                              (td_label_params.skeleton; ours; default 0,
                              docs/label.md) */
    int walls_back;        /* after labelling, the stretches the scanner
                              cut out of lines (td_scan_result.walls) whose
                              two sides got one height go back in as lines
                              for the interpolation (td_walls_restore;
                              ours; default 1) */
    double bridge;         /* then lines of one height are joined across
                              the breaks between their ends up to this
                              many px long (td_label_close_breaks; ours;
                              0: off; default -1: td_label_bridge_reach of
                              the labeller's contour spacing) */
    int keep_scan;         /* keep the image until on_labelled (debug) */
    int (*on_labelled)(const struct td_run_result *r, void *user);
    int (*on_refused)(const struct td_run_result *r, void *user);
    void *user;
} td_run_params;

td_run_params td_run_defaults(void);

typedef struct td_run_result {
    td_georef geo;         /* the scan's, scaled to the DEM's cells */
    int w, h;              /* the scan's size */
    td_lines *lines;       /* the lines (labelled, then the kept ones);
                              NULL once interpolated */
    td_lines *walls;       /* the scan's blobs (td_scan_result.walls);
                              NULL once labelled */
    uint8_t *skel;         /* steps: the scan's skeleton
                              (td_scan_result.skel_bits) for the
                              labeller; freed after labelling */
    td_grid_f32 *dem;
    size_t undetermined; /* cells of dem left nodata */
    size_t traced, dropped, ncross;
    size_t walls_back;     /* cut stretches put back (walls_back) */
    size_t breaks_closed;  /* breaks bridged (bridge) */
    double bridge;         /* ... up to this many px (the reach used) */
    double secs[3];        /* read + scan, label, interpolate */
    double ocr_secs;
    td_label_report rep, checks; /* the labeller's; crossings aside, the
                                    index width check's */
    td_homotopy_stats hs;
    td_ocr_read *reads;    /* printed labels read */
    size_t nreads;
    td_vee *vees;          /* where streams cross the lines (colour) */
    size_t nvees;
    td_palette pal;        /* the inks of a colour scan (n = 0: none) */
    td_image *scan;        /* keep_scan: until on_labelled (or
                              on_refused) returns */
} td_run_result;

/* Read the scan at path, trace, read its labels, label every line (with
 * the crossing and index-width checks of topodig label), drop the lines
 * left without a height and interpolate the DEM; r (initialised here) holds
 * everything; free with td_run_result_free.  Nothing is written.  0 or an
 * error (no heights to start from, no interval, no line labelled, any
 * stage's). */
int td_pipeline_run(const char *path, const td_run_params *p,
                    td_run_result *r, td_ctx *cx);
void td_run_result_free(td_run_result *r);

/* ---- a map series: one solve over every sheet (series.c) ---- */

typedef struct td_series_sheet {
    td_lines *lines;  /* the sheet's lines in its pixel frame, as its own
                         run labelled them; out: the joint solve's
                         heights (height, source, confidence, reason) */
    int w, h;         /* its size, px */
    double ox, oy;    /* its pixel (0, 0) in the series frame (>= 0; one
                         cell size for all sheets) */
    int evidence;     /* its lines labelled from a known point count as
                         evidence (0: its known points came from its
                         neighbours, batch --neighbours); those labelled
                         from a printed label always do; 2: every line
                         with a height does, at its confidence (a sheet
                         of a block solved before, beside this block) */
} td_series_sheet;

/* The heights of a series of sheets in one solve: every sheet's lines in
 * one frame, the pieces of a contour that a shared sheet edge cuts (ends
 * on both sheets' edges within 8 px, the lines leaving them in opposite
 * directions; closest pairs first) joined into one line, and the
 * faces labeller over all of them (p: interval required; base,
 * index_every, index_auto, label_up, search as td_label_auto takes them),
 * its evidence the lines each sheet labelled from a printed label or a
 * known point (confidence >= 0.6) as reads of that height.  rep: the
 * joint report.  0, TD_EINVAL (no evidence), TD_ENOMEM, the labeller's. */
int td_series_label(td_series_sheet *v, size_t n, const td_label_params *p,
                    td_label_report *rep, td_ctx *cx);

/* The DEM of every sheet of the series cut from one interpolation of all
 * their labelled lines (ip; step 1) over the series' extent, so the
 * sheets meet at their edges as cells inside a sheet do: dems[s] (free
 * with td_grid_f32_free) is sheet s's w x h part.  The sheets must lie on
 * one grid (whole-pixel offsets).  0, TD_EINVAL, TD_ETOOBIG (the extent),
 * TD_ENOMEM, the interpolation's. */
int td_series_interp(const td_series_sheet *v, size_t n,
                     const td_interp_params *ip, td_grid_f32 **dems,
                     td_ctx *cx);

/* The files of an erosion run: out (the eroded DEM; required), and each
 * of the others when not NULL: the W, E and deposited-sediment fields of
 * the last step, mass_log (CSV, one line per step); snapshots of the DEM
 * every p->snapshot_every steps as OUT-stem_stepNNNN.ext. */
typedef struct td_erode_files {
    const char *out, *water, *energy, *sediment, *mass_log;
    double cell_units; /* > 0: run the model in cell units: the heights
                          divided by this (the cell size) and the model's
                          cell 1, the DEM, its snapshots and the sediment
                          multiplied back (water, energy and the volumes
                          of the log stay in cell units); 0: as given */
} td_erode_files;

/* Erode in (p as td_erode_run takes it; its on_step and user are used
 * here) and write the files, the secondary ones first, so a failure
 * leaves the main output (new or old) as it was.  geo: the georeferencing
 * of every file (may be NULL).  0 or an error naming the file. */
int td_pipeline_erode(const td_grid_f32 *in, const td_georef *geo,
                      const td_erode_params *p, const td_erode_files *files,
                      td_erode_stats *st, td_ctx *cx);

/* ---- report: a one-page handout (report.c, cairo) ---- */

typedef struct td_report_input {
    const char *title, *subtitle; /* the top lines */
    const td_image *sheet;        /* (a): the scan with the lines drawn, or
                                     NULL */
    const td_grid_f32 *dem;       /* (b)-(d) */
    double cell;                  /* a cell's size in height units (1) */
    const char *unit;             /* of lengths along the section ("m") */
    double interval, base;        /* contours on (b): base + k interval */
    const char *const *facts;     /* lines of the figures block */
    size_t nfacts;
    int letter;                   /* US Letter (else A4) */
} td_report_input;

/* The page (points) and the four panels (x, y, w, h from the top left):
 * (a) the sheet, (b) relief, (c) 3-D view, (d) cross-section. */
void td_report_layout(int letter, double *pw, double *ph, double rect[4][4]);
/* The longest straight line through the highest cell that stays on data
 * (36 directions): its ends (cells).  0 when dem has no data. */
int td_report_section(const td_grid_f32 *dem, double *x0, double *y0,
                      double *x1, double *y1);
/* One PDF page at path (a temporary file renamed): the title, panels
 * (a)-(d) with captions, the figures.  0 or an error naming the file. */
int td_pipeline_report(const char *path, const td_report_input *in,
                       td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
