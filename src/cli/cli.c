#define _POSIX_C_SOURCE 200809L
#include "src/cli/cli.h"

#include "src/io/io.h"

#include <sys/stat.h>

#include "scanner/palette.h"

#include "scanner/label.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static int show_progress(const char *stage, double frac, void *user)
{
    td_cli_progress *pr = user;
    double now = td_now();
    int pct = (int)(frac * 100.0 + 0.5);
    if (pr->quiet || now - pr->t0 < 1.0)
        return 0;
    if (strcmp(stage, pr->stage) != 0) {
        if (pr->tty && pr->stage[0])
            fputc('\n', stderr);
        snprintf(pr->stage, sizeof pr->stage, "%s", stage);
        pr->last_pct = -1;
    }
    if (pct == pr->last_pct || (now - pr->last_t < 0.2 && pct < 100))
        return 0;
    if (pr->tty)
        fprintf(stderr, "\r%s: %3d%%", stage, pct);
    else if (pct == 100 || now - pr->last_t >= 5.0)
        fprintf(stderr, "%s: %d%%\n", stage, pct);
    else
        return 0;
    pr->last_pct = pct;
    pr->last_t = now;
    return 0;
}

void td_cli_progress_init(td_cli_progress *pr, td_ctx *cx, int quiet)
{
    memset(pr, 0, sizeof *pr);
    pr->quiet = quiet;
    pr->tty = isatty(2);
    pr->t0 = td_now();
    pr->last_pct = -1;
    cx->progress = show_progress;
    cx->progress_user = pr;
}

void td_cli_progress_done(td_cli_progress *pr)
{
    if (pr->tty && pr->stage[0] && !pr->quiet)
        fputc('\n', stderr);
    pr->stage[0] = '\0';
}

int td_cli_fail(const char *cmd, const td_ctx *cx)
{
    fprintf(stderr, "topodig %s: %s\n", cmd, td_errmsg(cx));
    return 1;
}

int td_cli_fail_on(const char *cmd, const char *in, const char *out,
                   const td_ctx *cx)
{
    const char *m = td_errmsg(cx);
    if (in && *in && !strstr(m, in) && !(out && *out && strstr(m, out)))
        fprintf(stderr, "topodig %s: %s: %s\n", cmd, in, m);
    else
        fprintf(stderr, "topodig %s: %s\n", cmd, m);
    return 1;
}

int td_cli_failf(const char *cmd, const char *fmt, ...)
{
    va_list ap;
    fprintf(stderr, "topodig %s: ", cmd);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
    return 1;
}

int td_cli_parse_int(const char *s, long lo, long hi, long *out)
{
    char *end;
    long v;
    errno = 0;
    v = strtol(s, &end, 10);
    if (errno || end == s || *end || v < lo || v > hi)
        return -1;
    *out = v;
    return 0;
}

int td_cli_parse_double(const char *s, double lo, double hi, double *out)
{
    char *end;
    double v;
    errno = 0;
    v = strtod(s, &end);
    if (errno || end == s || *end || !isfinite(v) || v < lo || v > hi)
        return -1;
    *out = v;
    return 0;
}

/* Contract in cli.h. */
void td_cli_bridged_summary(const char *cmd, size_t n, double reach,
                            double spacing)
{
    if (!n)
        return;
    fprintf(stderr,
            "%s: %zu break%s between the ends of lines of one height "
            "bridged (up to %.0f px",
            cmd, n, n == 1 ? "" : "s", reach);
    if (spacing > 0)
        fprintf(stderr, "; contours %.1f px apart", spacing);
    fprintf(stderr, ")\n");
}

void td_cli_heights_summary(const char *cmd, const td_label_report *rep)
{
    const size_t *b = rep->by_source;
    if (b[TD_HS_KNOWN] + b[TD_HS_LABEL] + b[TD_HS_SOLVED] +
            b[TD_HS_ASSUMED] == 0 &&
        rep->conflicts == 0)
        return;
    fprintf(stderr, "%s: heights: %zu known, %zu from labels, %zu solved, "
            "%zu assumed, %zu without", cmd, b[TD_HS_KNOWN], b[TD_HS_LABEL],
            b[TD_HS_SOLVED], b[TD_HS_ASSUMED], rep->undetermined);
    if (rep->short_lines && rep->pieces_left)
        fprintf(stderr, " (%zu of them under 12 px long, %zu short pieces "
                "whose ends tell no one height)", rep->short_lines,
                rep->pieces_left);
    else if (rep->short_lines)
        fprintf(stderr, " (%zu of them under 12 px long)", rep->short_lines);
    else if (rep->pieces_left)
        fprintf(stderr, " (%zu of them short pieces whose ends tell no one "
                "height)", rep->pieces_left);
    fprintf(stderr, "; %zu face conflicts, %zu lines cut, %zu known points "
            "overridden\n", rep->conflicts, rep->split, rep->known_broken);
    if (rep->vees)
        fprintf(stderr, "%s: streams: %zu crossings read as Vs pointing "
                "uphill\n", cmd, rep->vees);
    /* nearly every height a default decided: say so where it is read */
    {
        size_t all = b[TD_HS_KNOWN] + b[TD_HS_LABEL] + b[TD_HS_SOLVED] +
                     b[TD_HS_ASSUMED];
        if (all > 0 && 5 * b[TD_HS_ASSUMED] > 4 * all)
            fprintf(stderr,
                    "%s: note: %zu of the %zu lines with a height (%.0f %%) "
                    "took it from the defaults alone (rings rise, slopes "
                    "run on; height_source \"assumed\"): nothing on the "
                    "sheet or in the hints tells which way they slope, and "
                    "whole regions may be upside down; add --known points "
                    "there (or labels) and look at heights.png "
                    "(--debug-dir)\n",
                    cmd, b[TD_HS_ASSUMED], all,
                    100.0 * (double)b[TD_HS_ASSUMED] / (double)all);
    }
}
/* Contract in cli.h. */
void td_cli_print_palette(const char *prog, const td_palette *pal)
{
    static const char *const role[3] = {"paper", "tint", "ink"};
    int i;
    fprintf(stderr, "%s: inks:", prog);
    for (i = 0; i < pal->n; i++) {
        const td_ink *k = &pal->ink[i];
        fprintf(stderr, "%s %s #%02x%02x%02x %.1f %%", i ? "," : "",
                role[k->role], k->rgb[0], k->rgb[1], k->rgb[2],
                100.0 * k->share);
        if (k->role == TD_INKROLE_INK)
            fprintf(stderr, " %.1f px", k->width);
        if (i == pal->chosen)
            fprintf(stderr, " (taken)");
    }
    fputc('\n', stderr);
}

/* Fail before any long computation when the output's folder does not
 * exist or is not writable. */
static int check_folder(const char *cmd, const char *path)
{
    char dir[4096];
    const char *slash = strrchr(path, '/');
    struct stat st;
    size_t n = slash ? (size_t)(slash - path) : 0;
    if (!slash)
        return access(".", W_OK) == 0 ? 0 : td_cli_failf(cmd,
                      "%s: cannot create: folder not writable", path);
    if (n == 0)
        n = 1; /* "/file" */
    if (n >= sizeof dir)
        return td_cli_failf(cmd, "%s: file name too long", path);
    memcpy(dir, path, n);
    dir[n] = 0;
    if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode))
        return td_cli_failf(cmd, "%s: cannot create: no folder '%s'", path,
                            dir);
    if (access(dir, W_OK) != 0)
        return td_cli_failf(cmd, "%s: cannot create: folder not writable",
                            path);
    return 0;
}

/* Contract in cli.h. */
int td_cli_check_output(const char *cmd, const char *out, const char *in)
{
    struct stat so, si;
    td_ctx cx;
    td_ctx_init(&cx);
    if (in && stat(out, &so) == 0 && stat(in, &si) == 0 &&
        so.st_dev == si.st_dev && so.st_ino == si.st_ino)
        return td_cli_failf(cmd, "%s: the output is the input; give another "
                            "file name", out);
    if (td_atomic_check_target(out, &cx) != 0)
        return td_cli_fail(cmd, &cx);
    return check_folder(cmd, out);
}

/* Contract in cli.h. */
int td_cli_parse_nums(const char *s, double *v, int n)
{
    char buf[256], *tok, *save = NULL;
    int k = 0;
    if (strlen(s) >= sizeof buf)
        return -1;
    strcpy(buf, s);
    for (tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        while (*tok == ' ' || *tok == '\t')
            tok++;
        tok[strcspn(tok, " \t\r\n")] = '\0';
        if (k >= n || td_cli_parse_double(tok, -1e12, 1e12, &v[k++]) != 0)
            return -1;
    }
    return k == n ? 0 : -1;
}

/* See cli.h. */
int td_cli_parse_size(const char *arg, void *t, td_ctx *cx)
{
    long w, h;
    char buf[64], *x;
    int *wh = t;
    snprintf(buf, sizeof buf, "%s", arg);
    if (!(x = strchr(buf, 'x')) || (*x = '\0', 0) ||
        td_cli_parse_int(buf, 1, TD_MAX_DIM, &w) != 0 ||
        td_cli_parse_int(x + 1, 1, TD_MAX_DIM, &h) != 0)
        return td_seterr(cx, TD_EINVAL, "--size: '%s' is not WxH", arg);
    wh[0] = (int)w, wh[1] = (int)h;
    return 0;
}

/* See cli.h. */
int td_cli_grid(const char *like, const int wh[2], int *w, int *h,
                td_georef *geo, double *cell, td_ctx *cx)
{
    int rc = 0;
    if (like) {
        rc = td_cli_grid_of(like, w, h, geo, cx);
    } else {
        *w = wh[0], *h = wh[1];
        td_georef_pixel_frame(geo);
    }
    if (rc == 0 && !(*cell > 0) &&
        (*cell = td_georef_cell_size(geo, *w, *h, NULL)) <= 0)
        *cell = 1.0;
    return rc;
}

/* See cli.h. */
int td_cli_grid_of(const char *path, int *w, int *h, td_georef *geo,
                   td_ctx *cx)
{
    td_grid_f32 *g = NULL;
    int ch, rc = td_image_info(path, w, h, &ch, geo, cx);
    if (rc == 0)
        return 0;
    td_ctx_clear(cx); /* not a scan: a DEM (float samples) */
    td_georef_clear(geo);
    if ((rc = td_dem_read(path, &g, geo, cx)) != 0)
        return rc;
    *w = g->w, *h = g->h;
    td_grid_f32_free(g);
    return 0;
}

/* See cli.h. */
int td_cli_read_dem(const char *path, td_grid_f32 **dem, td_georef *geo,
                    double *cell, td_ctx *cx)
{
    int rc;
    td_georef_init(geo);
    if ((rc = td_dem_read(path, dem, geo, cx)) != 0)
        return rc;
    if (!(*cell > 0))
        *cell = td_georef_cell_size(geo, (*dem)->w, (*dem)->h, NULL);
    if (!(*cell > 0))
        *cell = 1.0;
    return 0;
}

/* See cli.h. */
void td_cli_json_str(FILE *f, const char *s, size_t n)
{
    size_t i;
    for (i = 0; s && i < n && s[i]; i++) {
        unsigned char c = (unsigned char)s[i];
        if (c == '"' || c == '\\')
            fprintf(f, "\\%c", c);
        else if (c < 0x20)
            fprintf(f, "\\u%04x", c);
        else
            fputc(c, f);
    }
}
