/* opt_help.c: --help generated from a command's option table (cli.h),
 * each default read from the option's target as the library's
 * *_defaults() set it. */
#include "src/cli/cli.h"

#include <stdio.h>
#include <string.h>

static size_t count(const td_opt *o)
{
    size_t n = 0;
    while (o && o[n].name)
        n++;
    return n;
}

/* Choice i of "a|b|c" into buf ("" past the end). */
static void choice_at(const char *choices, int i, char *buf, size_t size)
{
    const char *s = choices;
    size_t len;
    while (i-- > 0 && s && (s = strchr(s, '|')))
        s++;
    len = s ? strcspn(s, "|") : 0;
    snprintf(buf, size, "%.*s", (int)(len < size ? len : size - 1),
             s ? s : "");
}

/* The option's current value as the help's "(default ...)", or "". */
static void default_text(const td_opt *o, char *buf, size_t size)
{
    char c[64];
    buf[0] = '\0';
    if (o->no_default || !o->target)
        return;
    switch (o->kind) {
    case TD_OPT_INT:
        snprintf(buf, size, " (default %d)", *(const int *)o->target);
        break;
    case TD_OPT_LONG:
        snprintf(buf, size, " (default %ld)", *(const long *)o->target);
        break;
    case TD_OPT_DOUBLE:
        snprintf(buf, size, " (default %g)", *(const double *)o->target);
        break;
    case TD_OPT_FLOAT:
        snprintf(buf, size, " (default %g)", *(const float *)o->target);
        break;
    case TD_OPT_STRING:
        if (*(const char *const *)o->target)
            snprintf(buf, size, " (default %s)",
                     *(const char *const *)o->target);
        break;
    case TD_OPT_CHOICE:
        choice_at(o->choices, *(const int *)o->target - o->n, c, sizeof c);
        if (c[0])
            snprintf(buf, size, " (default %s)", c);
        break;
    default:
        break;
    }
}

/* One option's lines: "  -x, --name META   help" wrapped at its '\n's. */
static void help_line(const char *flags, const char *help, const char *dflt)
{
    const char *h = help ? help : "";
    int first = 1;
    if (strlen(flags) > 24) { /* a long flag: its help below it */
        printf("  %s\n", flags);
        first = 0;
    }
    do {
        size_t len = strcspn(h, "\n");
        int last = h[len] == '\0';
        printf("  %-24s %.*s%s\n", first ? flags : "", (int)len, h,
               last ? dflt : "");
        h += len + !last;
        first = 0;
        if (last)
            break;
    } while (1);
}

void td_opt_help(const td_cmd *c)
{
    size_t i, n = count(c->opts);
    char flags[96], d[96];
    printf("usage: topodig %s %s\n\n%s", c->name, c->usage, c->about);
    printf("\noptions:\n");
    if (c->out) {
        snprintf(flags, sizeof flags, "-o, --output %s", c->out_meta);
        help_line(flags, "the output (required)", "");
    }
    for (i = 0; i < n; i++) {
        const td_opt *o = &c->opts[i];
        char m[40] = "";
        if (o->kind == TD_OPT_CHOICE && !o->meta)
            snprintf(m, sizeof m, " %s", o->choices);
        else if (o->kind != TD_OPT_FLAG && o->kind != TD_OPT_OFF)
            snprintf(m, sizeof m, " %s", o->meta ? o->meta : "X");
        if (o->letter)
            snprintf(flags, sizeof flags, "-%c, --%s%s", o->letter, o->name, m);
        else
            snprintf(flags, sizeof flags, "    --%s%s", o->name, m);
        default_text(o, d, sizeof d);
        help_line(flags, o->help, d);
    }
    if (c->quiet)
        help_line("-q, --quiet", "no progress and no summary", "");
    help_line("-h, --help", "this help", "");
    if (c->after)
        printf("\n%s", c->after);
}

