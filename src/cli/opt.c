/* opt.c: the option layer (cli.h): one table per subcommand -> getopt_long
 * and checked values (the --help from the table: opt_help.c). */
#define _GNU_SOURCE
#include "src/cli/cli.h"

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { O_BASE = 1000, O_OUT = 'o', O_QUIET = 'q', O_HELP = 'h' };

static size_t count(const td_opt *o)
{
    size_t n = 0;
    while (o && o[n].name)
        n++;
    return n;
}

/* The index of arg among choices, or -1. */
static int choice_of(const char *choices, const char *arg)
{
    const char *s = choices;
    int i = 0;
    size_t n = strlen(arg);
    while (s) {
        size_t len = strcspn(s, "|");
        if (len == n && !strncmp(s, arg, n))
            return i;
        s = strchr(s, '|');
        s = s ? s + 1 : NULL;
        i++;
    }
    return -1;
}

/* td_cli_parse_nums into a growing list. */
static int add_point(td_opt_points *p, const char *arg, int dim)
{
    double v[8], *nv;
    if (dim < 1 || dim > 8 || td_cli_parse_nums(arg, v, dim) != 0)
        return -1;
    if (!(nv = realloc(p->v, (p->n + 1) * (size_t)dim * sizeof *nv)))
        return -2;
    memcpy(nv + p->n * (size_t)dim, v, (size_t)dim * sizeof *v);
    p->v = nv;
    p->n++;
    return 0;
}

/* Store arg into o's target; 0, or 1 with the error printed. */
static int set_value(const td_cmd *c, const td_opt *o, const char *arg)
{
    long l;
    double d;
    int k;
    td_ctx cx;
    switch (o->kind) {
    case TD_OPT_FLAG:
        *(int *)o->target = o->n ? o->n : 1;
        return 0;
    case TD_OPT_OFF:
        *(int *)o->target = 0;
        return 0;
    case TD_OPT_INT:
    case TD_OPT_LONG:
        if (td_cli_parse_int(arg, (long)o->lo, (long)o->hi, &l) != 0)
            return td_cli_failf(c->name, "--%s: '%s' is not a whole number "
                                "%g..%g", o->name, arg, o->lo, o->hi);
        if (o->kind == TD_OPT_LONG)
            *(long *)o->target = l;
        else
            *(int *)o->target = (int)l;
        return 0;
    case TD_OPT_DOUBLE:
    case TD_OPT_FLOAT:
        if (td_cli_parse_double(arg, o->lo, o->hi, &d) != 0)
            return td_cli_failf(c->name, "--%s: '%s' is not a number %g..%g",
                                o->name, arg, o->lo, o->hi);
        if (o->kind == TD_OPT_FLOAT)
            *(float *)o->target = (float)d;
        else
            *(double *)o->target = d;
        return 0;
    case TD_OPT_STRING:
        *(const char **)o->target = arg;
        return 0;
    case TD_OPT_OUTPUT: /* checked in finish(), once the input is known */
        *(const char **)o->target = arg;
        return 0;
    case TD_OPT_CHOICE:
        if ((k = choice_of(o->choices, arg)) < 0)
            return td_cli_failf(c->name, "--%s: '%s' is not one of %s",
                                o->name, arg, o->choices);
        *(int *)o->target = k + o->n;
        return 0;
    case TD_OPT_POINTS:
        if ((k = add_point(o->target, arg, o->n)) == -2)
            return td_cli_failf(c->name, "--%s: out of memory", o->name);
        if (k != 0)
            return td_cli_failf(c->name, "--%s: '%s' is not %s (%d finite "
                                "numbers)", o->name, arg,
                                o->meta ? o->meta : "X,Y", o->n);
        return 0;
    case TD_OPT_FUNC:
        td_ctx_init(&cx);
        if (o->fn(arg, o->target, &cx) != 0)
            return cx.msg[0] ? td_cli_fail(c->name, &cx)
                             : td_cli_failf(c->name, "--%s: '%s' is not "
                                            "allowed", o->name, arg);
        return 0;
    }
    return td_cli_failf(c->name, "--%s: unknown option kind", o->name);
}

/* The getopt tables for c (lo: n + 4 entries, sh: room for 2n + 8). */
static void tables(const td_cmd *c, size_t n, struct option *lo, char *sh)
{
    size_t i, k = 0, s = 0;
    for (i = 0; i < n; i++) {
        const td_opt *o = &c->opts[i];
        int arg = o->kind != TD_OPT_FLAG && o->kind != TD_OPT_OFF;
        lo[k++] = (struct option){o->name, arg, 0, (int)(O_BASE + i)};
        if (o->letter) {
            sh[s++] = o->letter;
            if (arg)
                sh[s++] = ':';
        }
    }
    if (c->out) {
        lo[k++] = (struct option){"output", 1, 0, O_OUT};
        sh[s++] = 'o';
        sh[s++] = ':';
    }
    if (c->quiet) {
        lo[k++] = (struct option){"quiet", 0, 0, O_QUIET};
        sh[s++] = 'q';
    }
    lo[k++] = (struct option){"help", 0, 0, O_HELP};
    sh[s++] = 'h';
    sh[s] = '\0';
    lo[k] = (struct option){0, 0, 0, 0};
}

/* The option with short letter ch, or -1. */
static long by_letter(const td_opt *o, size_t n, int ch)
{
    size_t i;
    for (i = 0; i < n; i++)
        if (o[i].letter && o[i].letter == ch)
            return (long)i;
    return -1;
}

/* Positional arguments and the -o checks once every option is read. */
static int finish(const td_cmd *c, int argc, char **argv)
{
    int i, npos = argc - optind;
    if (npos < c->min_in || npos > c->max_in)
        return td_cli_failf(c->name, "expected %s (see topodig %s --help)",
                            c->inputs, c->name);
    for (i = 0; i < npos; i++)
        c->in[i] = argv[optind + i];
    if (c->out && !*c->out)
        return td_cli_failf(c->name, "no output: give -o %s", c->out_meta);
    if (c->out && td_cli_check_output(c->name, *c->out,
                                      npos > 0 ? c->in[0] : NULL) != 0)
        return 1;
    for (i = 0; c->opts && c->opts[i].name; i++) {
        const td_opt *o = &c->opts[i];
        const char *f = o->kind == TD_OPT_OUTPUT ? *(const char **)o->target
                                                 : NULL;
        if (f && td_cli_check_output(c->name, f, npos > 0 ? c->in[0] : NULL))
            return 1;
    }
    return 0;
}

int td_opt_parse(const td_cmd *c, int argc, char **argv)
{
    size_t n = count(c->opts);
    struct option *lo = calloc(n + 4, sizeof *lo);
    char *sh = calloc(2 * n + 8, 1);
    int ch, rc = 0;
    if (!lo || !sh) {
        free(lo);
        free(sh);
        return td_cli_failf(c->name, "out of memory");
    }
    tables(c, n, lo, sh);
    opterr = 0;
    optind = 1;
    while (rc == 0 && (ch = getopt_long(argc, argv, sh, lo, NULL)) != -1) {
        long k = ch >= O_BASE ? ch - O_BASE : by_letter(c->opts, n, ch);
        if (ch == O_HELP) {
            td_opt_help(c);
            rc = 2;
        } else if (ch == O_OUT && c->out) {
            *c->out = optarg;
        } else if (ch == O_QUIET && c->quiet) {
            *c->quiet = 1;
        } else if (k >= 0 && (size_t)k < n) {
            rc = set_value(c, &c->opts[k], optarg);
        } else {
            rc = td_cli_failf(c->name, "bad or incomplete option '%s' (see "
                              "topodig %s --help)", argv[optind - 1],
                              c->name);
        }
    }
    if (rc == 0)
        rc = finish(c, argc, argv);
    free(lo);
    free(sh);
    return rc;
}

void td_opt_points_free(td_opt_points *p)
{
    if (p) {
        free(p->v);
        p->v = NULL;
        p->n = 0;
    }
}
