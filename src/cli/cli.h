/* cli.h: what the subcommands share: progress on stderr, the one-line
 * error convention, number parsing.  Only src/cli/ prints or exits. */
#ifndef TD_CLI_H
#define TD_CLI_H

#include "src/core/core.h"

#include <stdio.h>

#include <stddef.h>

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

struct td_label_report;
/* One line "CMD: heights: N known, N solved, N assumed, N without; ..."
 * from a faces labeller's report (nothing for the tree labeller's), and a
 * note when more than 80 % of the lines with a height are "assumed". */
void td_cli_heights_summary(const char *cmd,
                            const struct td_label_report *rep);

/* One line "CMD: N breaks between the ends of lines of one height
 * bridged (up to R px; contours S px apart)" (the spacing when known;
 * nothing when n is 0). */
void td_cli_bridged_summary(const char *cmd, size_t n, double reach,
                            double spacing);

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
 * same file as in (in may be NULL), an existing folder, device or FIFO,
 * or in a folder that does not exist or is not writable (found before any
 * long work).  Prints one line naming the file; returns 0 or 1. */
int td_cli_check_output(const char *cmd, const char *out, const char *in);

/* The grid of --like SHEET: a scan's size and georeferencing from its
 * header, else a DEM's (read whole: float samples).  0 or an error naming
 * the file (geo initialised; clear it). */
struct td_georef;
int td_cli_grid_of(const char *path, int *w, int *h, struct td_georef *geo,
                   td_ctx *cx);
/* The two grid options of a model command (ridgemodel, skeleton), for
 * an option table: --like SHEET into *like, --size WxH into wh[2]. */
#define TD_CLI_GRID_OPTS(like, wh)                                            \
    {"like", 0, TD_OPT_STRING, (like), .meta = "SHEET",                      \
     .help = "the grid: the size and georeferencing of a\nscan or DEM"},    \
    {"size", 0, TD_OPT_FUNC, (wh), .fn = td_cli_parse_size, .meta = "WxH",   \
     .help = "the grid without a sheet (the pixel frame)", .no_default = 1}

/* s (at most n bytes; NUL ends it sooner) as the body of a JSON string:
 * quotes and backslashes escaped, control characters as \uXXXX. */
void td_cli_json_str(FILE *f, const char *s, size_t n);

/* A DEM command's input: the DEM at path and its georeferencing (geo
 * initialised here); *cell, when not > 0, the georeferencing's cell size
 * (degrees as metres), else 1.  0 or an error naming the file. */
int td_cli_read_dem(const char *path, td_grid_f32 **dem,
                    struct td_georef *geo, double *cell, td_ctx *cx);

/* The grid of a model command: --like SHEET (like != NULL) or --size
 * (wh, the pixel frame); *cell, when not > 0, from the georeferencing's
 * cell size, else 1.  0 or an error naming the file. */
int td_cli_grid(const char *like, const int wh[2], int *w, int *h,
                struct td_georef *geo, double *cell, td_ctx *cx);

/* An option's "WxH" (1..TD_MAX_DIM each) into t, two ints (a TD_OPT_FUNC
 * target). */
int td_cli_parse_size(const char *arg, void *t, td_ctx *cx);

/* n comma-separated finite numbers within +-1e12 ("X,Y,H"; blanks around
 * each allowed) into v; 0, or -1 when s is anything else. */
int td_cli_parse_nums(const char *s, double *v, int n);

/* As td_cli_fail, and the message names the input in when it names
 * neither in nor out (an error deep in a stage: "z-buffer too big"). */
int td_cli_fail_on(const char *cmd, const char *in, const char *out,
                   const td_ctx *cx);

/* ---- the option layer (opt.c) -------------------------------------
 * Every subcommand is a table of options, each with a kind, a target, a
 * range and its help (as GRASS's G_parser, without its globals).
 * td_opt_parse checks every value (finite numbers in range, whole numbers,
 * choices, points), the input and output files, and prints --help
 * generated from the table, with each default read from the target as the
 * library's *_defaults() constructors set it: defaults are written once. */

typedef enum td_opt_kind {
    TD_OPT_FLAG,   /* int *: set to `n` (1 when n is 0) */
    TD_OPT_OFF,    /* int *: set to 0 (--no-... options) */
    TD_OPT_INT,    /* int *: a whole number lo..hi */
    TD_OPT_LONG,   /* long *: a whole number lo..hi */
    TD_OPT_DOUBLE, /* double *: a finite number lo..hi */
    TD_OPT_FLOAT,  /* float *: a finite number lo..hi */
    TD_OPT_STRING, /* const char **: the argument as given */
    TD_OPT_OUTPUT, /* const char **: a secondary output file (checked as -o) */
    TD_OPT_CHOICE, /* int *: the index of the argument in `choices`
                      ("a|b|c"); `n` != 0: its value is choices' index + n */
    TD_OPT_POINTS, /* td_opt_points *: n comma-separated finite numbers,
                      repeatable ("--known X,Y,H" n = 3) */
    TD_OPT_FUNC    /* fn(arg, target, cx): 0, or an error whose message
                      (in cx) names the option */
} td_opt_kind;

typedef struct td_opt {
    const char *name;  /* long name without "--"; NULL ends a table */
    char letter;       /* short option, 0: none */
    td_opt_kind kind;
    void *target;
    double lo, hi;     /* range of INT, DOUBLE, FLOAT */
    const char *meta;  /* the argument's name in the help ("PX") */
    const char *help;  /* may hold '\n' for more lines */
    const char *choices;
    int n;
    int (*fn)(const char *arg, void *target, td_ctx *cx);
    int no_default;    /* 1: print no "(default ...)" */
} td_opt;

/* Points given with a TD_OPT_POINTS option: v holds n x dim numbers. */
typedef struct td_opt_points {
    double *v;
    size_t n;
} td_opt_points;

/* A subcommand: its name, usage line, paragraph, options, the files. */
typedef struct td_cmd {
    const char *name;   /* "scan" */
    const char *usage;  /* after "topodig NAME ": "SCAN -o LINES [options]" */
    const char *about;  /* what it does (paragraphs) */
    const char *after;  /* text after the options (may be NULL) */
    const td_opt *opts; /* ends with {NULL} */
    const char *inputs; /* what the positional arguments are ("SCAN") */
    int min_in, max_in; /* how many positional arguments */
    const char **in;    /* out: the positional arguments (max_in slots) */
    const char **out;   /* -o target (NULL: the command has no -o) */
    const char *out_meta; /* "LINES.geojson" */
    int *quiet;         /* -q target (NULL: no -q) */
} td_cmd;

/* The interpolation options of interp and run (--method, --epsilon,
 * --fallback, --step, --summit, --peninsula, --weight, --dirs,
 * --interval, --nodata, --smooth) into v (room for TD_CLI_INTERP_OPTS
 * entries), targets in p; returns how many.  td_cli_interp_check after
 * parsing: --summit to both methods, --dirs 2 or 4; 0 or 1 (printed). */
enum { TD_CLI_INTERP_OPTS = 11 };
struct td_interp_params;
size_t td_cli_interp_opts(td_opt *v, struct td_interp_params *p);
int td_cli_interp_check(const char *cmd, struct td_interp_params *p);

/* Parse argv (argv[0] is the command's name) against c.  Returns 0 to
 * run, 2 when --help was printed (exit 0), 1 when an error was printed
 * (one line "topodig NAME: ..."; exit 1). */
int td_opt_parse(const td_cmd *c, int argc, char **argv);

/* Print c's generated help on stdout. */
void td_opt_help(const td_cmd *c);

void td_opt_points_free(td_opt_points *p);

#endif
