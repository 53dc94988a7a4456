/* label_entry.c: the paper's way of giving heights (001 §2.3): the
 * operator types each line's height, prompted on stderr, while the others
 * are re-suggested from the known points and the heights typed so far. */
#include "src/cli/label_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* See label_int.h. */
int td_pts_push(td_pts *a, double x, double y, double h, long id,
                td_ctx *cx)
{
    if (a->n == a->cap) {
        size_t cap = a->cap ? 2 * a->cap : 16;
        td_label_point *v = realloc(a->v, cap * sizeof *v);
        if (!v)
            return td_seterr(cx, TD_ENOMEM, "out of memory");
        a->v = v, a->cap = cap;
    }
    a->v[a->n].x = x, a->v[a->n].y = y, a->v[a->n].height = h;
    a->v[a->n++].id = id;
    return 0;
}

/* Re-suggest every height from the known points plus the typed ones.  On
 * failure (the typed heights contradict) the heights are left as they were
 * and a warning is printed. */
static void repropagate(td_lines *ls, td_label_params *p,
                        const td_pts *typed, const td_pts *known,
                        const double *rows, size_t nrows,
                        td_label_report *rep, size_t *warnings)
{
    td_label_point *all = NULL;
    double *saved = malloc((ls->n + 1) * 2 * sizeof *saved);
    td_label_report r2;
    td_ctx cx;
    size_t i;
    td_ctx_init(&cx);
    memset(&r2, 0, sizeof r2);
    all = malloc((known->n + typed->n + 1) * sizeof *all);
    if (!saved || !all)
        goto done;
    for (i = 0; i < ls->n; i++)
        saved[2 * i] = ls->v[i].has_height, saved[2 * i + 1] = ls->v[i].height;
    if (known->n)
        memcpy(all, known->v, known->n * sizeof *all);
    if (typed->n)
        memcpy(all + known->n, typed->v, typed->n * sizeof *all);
    p->known = all, p->nknown = known->n + typed->n;
    if (td_label_auto(ls, p, &r2, &cx) != 0 ||
        td_pipeline_apply_heights(ls, rows, nrows, NULL, p, &cx) != 0) {
        fprintf(stderr, "label: warning: %s; heights not re-suggested\n",
                td_errmsg(&cx));
        (*warnings)++;
        for (i = 0; i < ls->n; i++)
            ls->v[i].has_height = (int)saved[2 * i],
            ls->v[i].height = saved[2 * i + 1];
        td_label_report_free(&r2);
    } else {
        td_label_report_free(rep);
        *rep = r2;
    }
done:
    p->known = known->v, p->nknown = known->n;
    free(all);
    free(saved);
}

/* One answer: 0 accepted (Enter), 1 a height in *v, 2 stop (q), 3 not
 * understood, 4 end of input. */
static int read_answer(FILE *in, double *v)
{
    char buf[256], *s;
    if (!fgets(buf, sizeof buf, in))
        return 4;
    if (!isatty(fileno(in)))
        fputs(buf[strcspn(buf, "\n")] ? buf : "\n", stderr);
    for (s = buf; *s == ' ' || *s == '\t'; s++)
        ;
    s[strcspn(s, " \t\r\n")] = '\0';
    if (*s == '\0')
        return 0;
    if (!strcmp(s, "q") || !strcmp(s, "quit"))
        return 2;
    return td_cli_parse_double(s, -1e9, 1e9, v) == 0 ? 1 : 3;
}

/* See label_int.h: the paper's operator, re-suggesting the others after
 * each typed height. */
size_t td_label_interact(td_lines *ls, td_label_params *p,
                         const td_pts *known, const double *rows,
                         size_t nrows, const double *idxy,
                         td_label_report *rep, FILE *in, size_t *asked)
{
    td_pts typed = {NULL, 0, 0};
    size_t i, warnings = 0;
    for (i = 0; i < ls->n; i++) {
        *asked = i; /* lines before i were answered */
        td_line *l = &ls->v[i];
        double x = idxy[2 * i], y = idxy[2 * i + 1], v, k;
        char sug[64] = "?";
        int a;
        if (l->has_height)
            snprintf(sug, sizeof sug, "%.10g", l->height);
        fprintf(stderr, "line %ld (%s, near %.0f,%.0f) height [%s]: ", l->id,
                l->closed ? "closed" : "open", x, y, sug);
        a = read_answer(in, &v);
        if (a == 2 || a == 4) {
            if (a == 4)
                fputc('\n', stderr);
            break;
        }
        *asked = i + 1;
        if (a == 3) {
            fprintf(stderr, "  a height, Enter to accept, q to stop\n");
            i--;
            continue;
        }
        if (a == 0 || (l->has_height && v == l->height))
            continue;
        k = (v - p->base) / p->interval;
        if (fabs(k - floor(k + 0.5)) > 1e-6) {
            fprintf(stderr, "label: warning: height %g for line %ld is not "
                    "base %g + a multiple of %g\n", v, l->id, p->base,
                    p->interval);
            warnings++;
        }
        if (td_pts_push(&typed, 0, 0, v, l->id, NULL) != 0)
            break;
        l->has_height = 1, l->height = v;
        repropagate(ls, p, &typed, known, rows, nrows, rep, &warnings);
        l = &ls->v[i];
        l->has_height = 1, l->height = v; /* the operator's word stands */
    }
    free(typed.v);
    return warnings;
}

/* See label_int.h. */
int td_label_entry(label_opts *o, td_lines *ls, td_label_report *rep,
                 td_pts *seen, size_t *more, td_ctx *cx)
{
    char path[4200];
    double *idxy = NULL;
    size_t asked = 0, i;
    int rc;
    snprintf(path, sizeof path, "%s%s", o->label_sheet ? o->label_sheet
             : o->out, o->label_sheet ? "" : ".png");
    if ((rc = td_line_id_places(ls, &idxy, cx)) == 0 &&
        (rc = td_pipeline_label_sheet(path, o->like, o->w, o->h, ls, idxy,
                                      cx)) == 0) {
        fprintf(stderr, "label: label sheet %s\n", path);
        *more += td_label_interact(ls, &o->p, &o->pts, o->rows, o->nrows,
                                   idxy, rep, stdin, &asked);
        for (i = 0; i < asked && rc == 0; i++) /* seen: not "assumed" */
            rc = td_pts_push(seen, 0, 0, ls->v[i].height, ls->v[i].id, cx);
    }
    free(idxy);
    return rc;
}

