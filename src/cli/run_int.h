/* run_int.h: the options of topodig run, shared with topodig report (which
 * takes the same ones: run_opts.c). */
#ifndef TD_CLI_RUN_INT_H
#define TD_CLI_RUN_INT_H

#include "src/cli/cli.h"
#include "src/pipeline/pipeline.h"

typedef struct td_cli_run {
    const char *save_lines, *debug_dir;
    int no_labels, no_streams;
    td_opt_points known, dep;
    td_run_params p;
} td_cli_run;

enum { TD_CLI_RUN_OPTS = 21 + TD_CLI_INTERP_OPTS };

/* r's defaults (td_run_defaults). */
void td_cli_run_init(td_cli_run *r);
/* The run options into v (room for TD_CLI_RUN_OPTS entries; not ended),
 * targets in r: the labeller's hints, the scanner's ink and threshold,
 * --save-lines and --debug-dir, the interpolation's.  Returns how many. */
size_t td_cli_run_opts(td_opt *v, td_cli_run *r);
/* After parsing: --known and --depressions into the labeller's hints;
 * reading labels unless --labels none.  0, or 1 (message printed). */
int td_cli_run_hints(td_cli_run *r, const char *cmd);
void td_cli_run_free(td_cli_run *r);

#endif
