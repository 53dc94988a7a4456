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

#ifdef __cplusplus
extern "C" {
#endif

/* scan --debug-dir DIR (made when missing): mask.png, skeleton.png,
 * despurred.png, overlay.png (traced lines over the faded scan, label-gap
 * joins magenta), join.txt, and for colour scans palette.png, ink-K.png,
 * inks.txt.  0 or an error naming the file. */
int td_pipeline_scan_debug(const char *dir, const td_image *im,
                           const td_scan_result *r, td_ctx *cx);

/* The files of an erosion run: out (the eroded DEM; required), and each
 * of the others when not NULL: the W, E and deposited-sediment fields of
 * the last step, mass_log (CSV, one line per step); snapshots of the DEM
 * every p->snapshot_every steps as OUT-stem_stepNNNN.ext. */
typedef struct td_erode_files {
    const char *out, *water, *energy, *sediment, *mass_log;
} td_erode_files;

/* Erode in (p as td_erode_run takes it; its on_step and user are used
 * here) and write the files, the secondary ones first, so a failure
 * leaves the main output (new or old) as it was.  geo: the georeferencing
 * of every file (may be NULL).  0 or an error naming the file. */
int td_pipeline_erode(const td_grid_f32 *in, const td_georef *geo,
                      const td_erode_params *p, const td_erode_files *files,
                      td_erode_stats *st, td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
