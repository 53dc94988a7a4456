/* label_report.c: what `topodig label` tells on stderr: the labeller's
 * warnings, crossing lines, the lines assumed, the summary line. */
#include "src/cli/label_int.h"

#include <stdlib.h>
#include <string.h>

/* Each line of a report's text as "label: warning: ...". */
static void put_warnings(const char *text)
{
    while (text && *text) {
        size_t n = strcspn(text, "\n");
        fprintf(stderr, "label: warning: %.*s\n", (int)n, text);
        text += n + (text[n] == '\n');
    }
}

/* Whether id is among the points' ids or the rows' (with a height). */
static int has_id(const td_pts *a, const double *rows, size_t nrows, long id)
{
    size_t j;
    for (j = 0; a && j < a->n; j++)
        if (a->v[j].id == id)
            return 1;
    for (j = 0; j < nrows; j++)
        if (rows[2 * j] == (double)id && rows[2 * j + 1] == rows[2 * j + 1])
            return 1;
    return 0;
}

/* The lines whose up/down is only assumed (a note, not a warning); lines
 * given by --heights or answered in --interactive are not guesses. */
static void put_assumed(td_label_report *rep, const label_opts *o,
                        const td_pts *seen)
{
    size_t i, m = 0;
    for (i = 0; i < rep->assumed; i++)
        if (!has_id(NULL, o->rows, o->nrows, rep->assumed_ids[i]) &&
            !has_id(seen, NULL, 0, rep->assumed_ids[i]))
            rep->assumed_ids[m++] = rep->assumed_ids[i];
    rep->assumed = m;
    if (rep->assumed == 0)
        return;
    fprintf(stderr, "label: note: %zu lines are higher or lower than their "
            "surroundings by assumption only (no two known points or "
            "--depressions fix it; rings taken as rising), ids ",
            rep->assumed);
    for (i = 0; i < rep->assumed && i < 20; i++)
        fprintf(stderr, "%s%ld", i ? "," : "", rep->assumed_ids[i]);
    fputs(rep->assumed > 20 ? ",...\n" : "\n", stderr);
}

void td_label_summary(const td_lines *ls, td_label_report *rep,
                    const td_label_report *checks, const label_opts *o,
                    const td_pts *seen, size_t more)
{
    size_t i, lab = 0, shown = 0;
    for (i = 0; i < ls->n; i++)
        lab += ls->v[i].has_height != 0;
    put_warnings(rep->text);
    put_warnings(checks->text);
    put_assumed(rep, o, seen);
    fprintf(stderr, "label: %zu lines, %zu labelled, %zu undetermined, %zu "
            "warnings", ls->n, lab, ls->n - lab,
            rep->warnings + checks->warnings + more);
    for (i = 0; i < ls->n && shown < 20; i++)
        if (!ls->v[i].has_height)
            fprintf(stderr, "%s%ld", shown++ ? "," : " (undetermined ids: ",
                    ls->v[i].id);
    fputs(shown ? (shown < ls->n - lab ? ",...)\n" : ")\n") : "\n", stderr);
    td_cli_heights_summary("label", rep);
}

/* Warn about lines that cross (one line each, before the summary);
 * returns the number of warnings, or -1 (out of memory). */
long td_label_warn_crossings(const td_lines *ls, int quiet, td_ctx *cx)
{
    td_crossing *v = NULL;
    size_t n = 0, i;
    if (td_contain_crossings(ls, &v, &n, cx) != 0)
        return -1;
    for (i = 0; i < n && !quiet; i++)
        fprintf(stderr, "label: warning: lines %ld and %ld cross at "
                "(%.1f,%.1f)\n", v[i].a, v[i].b, v[i].x, v[i].y);
    free(v);
    return (long)n;
}

