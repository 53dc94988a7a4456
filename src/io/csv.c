/* csv.c: the small CSV files of the labeller: x,y,height points,
 * id,height rows (read), and id,height of every line (written). */
#include "src/io/io.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* n comma-separated finite numbers (blanks allowed) of s into v; 0 or -1. */
static int nums(const char *s, double *v, int n)
{
    int k;
    for (k = 0; k < n; k++) {
        char *e;
        while (*s == ' ' || *s == '\t')
            s++;
        v[k] = strtod(s, &e);
        if (e == s || !isfinite(v[k]) || fabs(v[k]) > 1e12)
            return -1;
        for (s = e; *s == ' ' || *s == '\t'; s++)
            ;
        if (k < n - 1 && *s++ != ',')
            return -1;
    }
    return *s == '\0' ? 0 : -1;
}

/* A row "A," or "A" (one number, the last value empty) into v[0]. */
static int empty_last(const char *line, double *v)
{
    char buf[64];
    size_t n = strcspn(line, ",");
    const char *t = line + n;
    if (n >= sizeof buf)
        return 0;
    if (*t == ',')
        for (t++; *t == ' ' || *t == '\t'; t++)
            ;
    if (*t != '\0')
        return 0;
    memcpy(buf, line, n);
    buf[n] = '\0';
    return nums(buf, v, 1) == 0;
}

static int push_row(double **v, size_t *n, size_t *cap, const double *row,
                    int ncols, td_ctx *cx)
{
    if (*n == *cap) {
        size_t c = *cap ? 2 * *cap : 64;
        double *nv = realloc(*v, c * (size_t)ncols * sizeof *nv);
        if (!nv)
            return td_seterr(cx, TD_ENOMEM, "out of memory");
        *v = nv;
        *cap = c;
    }
    memcpy(*v + *n * (size_t)ncols, row, (size_t)ncols * sizeof *row);
    (*n)++;
    return 0;
}

/* See io.h. */
int td_csv_read_rows(const char *path, int ncols, int allow_empty_last,
                     double **v, size_t *n, td_ctx *cx)
{
    FILE *f;
    char line[512];
    long no = 0;
    size_t cap = 0;
    int rc = 0;
    *v = NULL;
    *n = 0;
    if (ncols < 1 || ncols > 8)
        return td_seterr(cx, TD_EINVAL, "%s: bad column count", path);
    if (td_check_input(path, cx) != 0)
        return TD_EINVAL;
    if (!(f = fopen(path, "r")))
        return td_seterr(cx, TD_EIO, "%s: cannot open (%s)", path,
                         strerror(errno));
    while (rc == 0 && fgets(line, sizeof line, f)) {
        double row[8];
        no++;
        line[strcspn(line, "\r\n")] = '\0';
        if (line[0] == '\0' || line[0] == '#')
            continue;
        if (allow_empty_last && ncols > 1 && empty_last(line, row)) {
            int k;
            for (k = 1; k < ncols; k++)
                row[k] = NAN;
            rc = push_row(v, n, &cap, row, ncols, cx);
        } else if (nums(line, row, ncols) == 0) {
            rc = push_row(v, n, &cap, row, ncols, cx);
        } else if (no == 1 && strpbrk(line, "abcdefghijklmnopqrstuvwxyz")) {
            continue; /* a header */
        } else {
            rc = td_seterr(cx, TD_EINVAL, "%s:%ld: expected %d numbers, got "
                           "'%.40s'", path, no, ncols, line);
        }
    }
    fclose(f);
    if (rc != 0) {
        free(*v);
        *v = NULL;
        *n = 0;
    }
    return rc;
}

/* See io.h. */
int td_csv_write_heights(const char *path, const td_lines *ls, td_ctx *cx)
{
    size_t i, tmpsize = strlen(path) + 32;
    char *tmp = td_malloc(tmpsize, cx);
    FILE *f;
    int rc;
    if (!tmp)
        return TD_ENOMEM;
    if (!(f = td_atomic_open(path, tmp, tmpsize, cx))) {
        free(tmp);
        return cx && cx->code ? cx->code : TD_EIO;
    }
    fputs("id,height\n", f);
    for (i = 0; i < ls->n; i++) {
        if (ls->v[i].has_height)
            fprintf(f, "%ld,%.10g\n", ls->v[i].id, ls->v[i].height);
        else
            fprintf(f, "%ld,\n", ls->v[i].id);
    }
    rc = td_atomic_commit(f, tmp, path, cx);
    free(tmp);
    return rc;
}
