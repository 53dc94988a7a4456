/* cli.h: what the subcommands share: progress on stderr, the one-line
 * error convention, number parsing.  Only src/cli/ prints or exits. */
#ifndef TD_CLI_H
#define TD_CLI_H

#include "src/core/core.h"

#define TD_VERSION "0.1.0"

typedef struct td_cli_progress {
    int quiet;
    int tty;
    char stage[32];
    int last_pct;
    double t0, last_t;
} td_cli_progress;

/* Install a stderr progress reporter in cx (silent when quiet).  Progress
 * is shown for work that runs longer than about a second. */
void td_cli_progress_init(td_cli_progress *pr, td_ctx *cx, int quiet);
/* End the progress line (if one is showing). */
void td_cli_progress_done(td_cli_progress *pr);

/* Print "topodig CMD: MESSAGE" for the error in cx and return 1. */
int td_cli_fail(const char *cmd, const td_ctx *cx);
/* Print "topodig CMD: <printf message>" and return 1. */
int td_cli_failf(const char *cmd, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* Parse a whole string as a number within [lo,hi]; 0 or -1. */
int td_cli_parse_int(const char *s, long lo, long hi, long *out);
int td_cli_parse_double(const char *s, double lo, double hi, double *out);

/* --labeller faces|tree: *tree set to 1 for tree, 0 for faces; 0 or
 * TD_EINVAL with the message in cx. */
int td_cli_parse_labeller(const char *arg, int *tree, td_ctx *cx);

struct td_label_report;
/* One line "CMD: heights: N known, N solved, N assumed, N without; ..."
 * from a faces labeller's report (nothing for the tree labeller's). */
void td_cli_heights_summary(const char *cmd,
                            const struct td_label_report *rep);

/* Subcommands (src/cli/<name>.c, listed in src/cli/main.c): each returns
 * the process exit code. */
int td_cmd_scan(int argc, char **argv);
int td_cmd_label(int argc, char **argv);
int td_cmd_erode(int argc, char **argv);
int td_cmd_generate(int argc, char **argv);

/* One line on stderr naming the colours of a colour scan's palette
 * ("PROG: inks: paper #rrggbb 80.1 %, ink #rrggbb 5.2 % 1.8 px (taken),
 * tint #rrggbb ..."). */
struct td_palette;
void td_cli_print_palette(const char *prog, const struct td_palette *pal);

/* Refuse an output that would destroy an input or is no file: out the
 * same file as in (in may be NULL), or an existing folder, device or
 * FIFO.  Prints one line naming the file; returns 0 or 1. */
int td_cli_check_output(const char *cmd, const char *out, const char *in);

/* n comma-separated finite numbers within +-1e12 ("X,Y,H"; blanks around
 * each allowed) into v; 0, or -1 when s is anything else. */
int td_cli_parse_nums(const char *s, double *v, int n);

/* As td_cli_fail, and the message names the input in when it names
 * neither in nor out (an error deep in a stage: "z-buffer too big"). */
int td_cli_fail_on(const char *cmd, const char *in, const char *out,
                   const td_ctx *cx);

#endif
