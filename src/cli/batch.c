/* topodig batch: a map series, one `topodig run` per sheet of a manifest,
 * as child processes (--jobs at a time), or the same jobs printed for an
 * existing engine (--emit parallel|make|slurm).
 *
 *   MANIFEST.csv     sheet,options         (a header line "sheet,..." is
 *                    a.tif,--interval 10    skipped; # comments; paths
 *                    b.tif,                 relative to the manifest)
 *   DIR/<stem>/      dem.tif, lines.geojson, summary.json, run.log,
 *                    debug/, hash (what the outputs were made from)
 *   DIR/batch.log    one JSON object per sheet: status, seconds, exit
 *                    code, the run's summary, the error
 *
 * --resume skips a sheet whose dem.tif exists and whose hash (FNV-1a of
 * the sheet's bytes, its options and this program's version) is unchanged.
 * The exit code is 0 when every sheet succeeded.
 *
 * After the runs, for georeferenced sheets that share edges (found once,
 * by a sweep along x): the joint solve (td_series_label: every sheet's
 * lines labelled again as one, the contours the edges cut joined; in
 * blocks of about --joint-cells cells for a larger series; --no-joint),
 * the edge matching (each contour's heights on both sides of an edge
 * compared, in batch.log), and the DEMs cut from one interpolation of the
 * series (td_series_interp) or each sheet interpolated again with its
 * neighbours' lines beside it (topodig interp --beside; --no-seams). */
#include "src/cli/cli.h"

#include "src/io/io.h"
#include "src/pipeline/pipeline.h"
#include "interp/interp.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#define MAX_ARGS 256

typedef struct sheet {
    char *path, *opts, *stem, *dir;
    char *seeded;  /* the neighbours its heights came from, or NULL */
    uint64_t hash;
    pid_t pid;
    double t0;
    int state;     /* 0 waiting, 1 running, 2 done */
    int ok;
    int stage;     /* 0 the run, 1 its seams (interp with the neighbours) */
    int placed;    /* georeferenced: x0..y1 its map extent */
    double x0, y0, x1, y1, res;
    int epsg;
    char *beside;  /* the neighbours the seams step took, or NULL */
    size_t *nb, nnb; /* the sheets it shares an edge with (find_neighbours) */
} sheet;

typedef struct bt_opts {
    const char *manifest, *out;
    int jobs, resume, emit, quiet, neighbours, seams, margin, joint;
    int joint_only;
    double joint_cells; /* the joint solve in blocks of up to this */
} bt_opts;

static int parse_args(int argc, char **argv, bt_opts *o)
{
    const td_opt opts[] = {
        {"out", 0, TD_OPT_STRING, &o->out, .meta = "DIR",
         .help = "where each sheet's outputs go (DIR/<stem>/)\nand batch.log "
         "(required)"},
        {"jobs", 'j', TD_OPT_INT, &o->jobs, 1, 1024, .meta = "N",
         .help = "sheets run at once"},
        {"resume", 0, TD_OPT_FLAG, &o->resume,
         .help = "skip sheets whose outputs exist and whose\nsheet and "
         "options are unchanged"},
        {"neighbours", 0, TD_OPT_FLAG, &o->neighbours,
         .help = "a sheet that cannot start (no labels, no\nknown points) "
         "takes the interval and, as\nknown points, the heights of the "
         "lines its\nlabelled neighbours carry across the shared\nedge "
         "(georeferenced sheets)"},
        {"joint-only", 0, TD_OPT_FLAG, &o->joint_only,
         .help = "run no sheet: the joint steps only, on the\noutputs in "
         "DIR (after the jobs of --emit)"},
        {"no-joint", 0, TD_OPT_OFF, &o->joint,
         .help = "keep each sheet's heights as its own run\ngave them "
         "(default: georeferenced sheets\nthat share edges are labelled "
         "again as one,\nthe contours cut by the edges joined)"},
        {"no-seams", 0, TD_OPT_OFF, &o->seams,
         .help = "keep each sheet's DEM as its own run made it\n(default: "
         "georeferenced sheets are\ninterpolated again with the lines of "
         "the\nsheets beside them, so the DEMs meet at the\nshared edges)"},
        {"joint-cells", 0, TD_OPT_DOUBLE, &o->joint_cells, 1e4, 1e10,
         .meta = "N", .help = "the joint solve holds the series' raster:\n"
         "a larger series is solved in blocks of\nabout N cells, each as one, "
         "the solved\nsheets beside it as evidence (1e8: about\n1.7 GB)"},
        {"margin", 0, TD_OPT_INT, &o->margin, 1, 65536, .meta = "PX",
         .help = "seams: how far beyond its edges a sheet sees\nits "
         "neighbours' lines"},
        {"emit", 0, TD_OPT_CHOICE, &o->emit, .choices = "none|parallel|make|"
         "slurm", .meta = "E", .help = "print the jobs for GNU parallel, a "
         "Makefile\nor a Slurm array script instead of running\nthem"},
        {NULL}};
    const td_cmd c = {
        "batch", "MANIFEST.csv --out DIR [--jobs N] [--resume]\n"
        "                      [--emit parallel|make|slurm]",
        "Run a map series: one line per sheet in MANIFEST.csv, `sheet,options`\n"
        "(the options of topodig run for that sheet; empty when its printed\n"
        "labels are enough).  Each sheet's DEM (dem.tif), labelled lines\n"
        "(lines.geojson), summary.json, run.log and debug pictures go under\n"
        "DIR/<sheet stem>/; one JSON line per sheet in DIR/batch.log.  A\n"
        "failed sheet never stops the others; the exit code is 0 when all\n"
        "succeeded.  --emit prints the same jobs for an existing engine:\n"
        "  topodig batch --emit parallel M.csv --out D | parallel -j 8\n"
        "  topodig batch --emit make M.csv --out D > jobs.mk; make -j 8 -f jobs.mk\n"
        "  topodig batch --emit slurm M.csv --out D > jobs.sh; sbatch jobs.sh\n",
        NULL, opts, "one MANIFEST file", 1, 1, &o->manifest, NULL, NULL,
        &o->quiet};
    int rc = td_opt_parse(&c, argc, argv);
    if (rc)
        return rc;
    if (!o->out)
        return td_cli_failf("batch", "give --out DIR");
    return 0;
}

/* ---- the manifest ---- */

static char *dupn(const char *s, size_t n)
{
    char *d = malloc(n + 1);
    if (d)
        memcpy(d, s, n), d[n] = 0;
    return d;
}

static char *trim(char *s)
{
    char *e;
    while (*s == ' ' || *s == '\t')
        s++;
    e = s + strlen(s);
    while (e > s && (e[-1] == ' ' || e[-1] == '\t' || e[-1] == '\r' ||
                     e[-1] == '\n'))
        *--e = 0;
    if (e - s >= 2 && *s == '"' && e[-1] == '"') /* a quoted field */
        s++, e[-1] = 0;
    return s;
}

static uint64_t fnv(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = p;
    size_t i;
    for (i = 0; i < n; i++)
        h = (h ^ b[i]) * 0x100000001b3ull;
    return h;
}

/* FNV-1a of the sheet's bytes, its options and the version. */
static int hash_sheet(sheet *s, const char *version)
{
    unsigned char buf[65536];
    FILE *f = fopen(s->path, "rb");
    uint64_t h = 0xcbf29ce484222325ull;
    size_t n;
    if (!f)
        return -1;
    while ((n = fread(buf, 1, sizeof buf, f)) > 0)
        h = fnv(h, buf, n);
    fclose(f);
    h = fnv(h, "\0", 1);
    h = fnv(h, s->opts, strlen(s->opts));
    h = fnv(h, "\0", 1);
    s->hash = fnv(h, version, strlen(version));
    return 0;
}

/* One manifest line into s (path relative to the manifest's folder). */
static int parse_line(const char *mdir, char *line, sheet *s, long ln,
                      const char *mpath)
{
    char *comma = strchr(line, ','), *p, *o, *base, *dot;
    size_t dl = strlen(mdir);
    if (comma)
        *comma = 0;
    p = trim(line);
    o = comma ? trim(comma + 1) : "";
    if (!*p)
        return td_cli_failf("batch", "%s:%ld: no sheet", mpath, ln);
    if (*p == '/')
        s->path = dupn(p, strlen(p));
    else if ((s->path = malloc(dl + strlen(p) + 2)) != NULL)
        sprintf(s->path, "%s%s%s", mdir, dl ? "/" : "", p);
    s->opts = dupn(o, strlen(o));
    if (!s->path || !s->opts)
        return td_cli_failf("batch", "out of memory");
    base = strrchr(s->path, '/') ? strrchr(s->path, '/') + 1 : s->path;
    dot = strrchr(base, '.');
    s->stem = dupn(base, dot && dot > base ? (size_t)(dot - base) : strlen(base));
    return s->stem ? 0 : td_cli_failf("batch", "out of memory");
}

static int read_manifest(const char *path, sheet **out, size_t *n)
{
    FILE *f = fopen(path, "r");
    char line[8192], *mdir;
    const char *sl = strrchr(path, '/');
    sheet *v = NULL;
    size_t cap = 0, i, j;
    long ln = 0;
    int rc = 0;
    *out = NULL, *n = 0;
    if (!f)
        return td_cli_failf("batch", "%s: cannot open (%s)", path,
                            strerror(errno));
    mdir = dupn(path, sl ? (size_t)(sl - path) : 0);
    while (rc == 0 && fgets(line, sizeof line, f)) {
        char *t = trim(line);
        ln++;
        if (!*t || *t == '#' || (ln == 1 && !strncmp(t, "sheet,", 6)))
            continue;
        if (*n == cap) {
            sheet *nv = realloc(v, (cap ? 2 * cap : 16) * sizeof *nv);
            if (!nv) {
                rc = td_cli_failf("batch", "out of memory");
                break;
            }
            v = nv, cap = cap ? 2 * cap : 16;
        }
        memset(&v[*n], 0, sizeof *v);
        rc = parse_line(mdir ? mdir : "", t, &v[*n], ln, path);
        (*n)++;
    }
    fclose(f);
    free(mdir);
    for (i = 0; rc == 0 && i < *n; i++) /* stems name the folders */
        for (j = 0; j < i; j++)
            if (!strcmp(v[i].stem, v[j].stem)) {
                rc = td_cli_failf("batch", "%s: two sheets named %s (%s, %s): "
                                  "their outputs would share a folder", path,
                                  v[i].stem, v[j].path, v[i].path);
                break;
            }
    if (rc == 0 && *n == 0)
        rc = td_cli_failf("batch", "%s: no sheets", path);
    *out = v;
    return rc;
}

static void free_sheets(sheet *v, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++)
        free(v[i].path), free(v[i].opts), free(v[i].stem), free(v[i].dir),
            free(v[i].seeded), free(v[i].beside), free(v[i].nb);
    free(v);
}

/* ---- the command of one sheet ---- */

/* argv of `topodig run` for s (split options on blanks); the strings in
 * buf.  Returns argc or -1. */
static int run_argv(const char *exe, const sheet *s, char **av, char *buf,
                    size_t bl)
{
    int ac = 0;
    char *o;
    snprintf(buf, bl, "%s", s->opts);
    av[ac++] = (char *)exe;
    av[ac++] = "run";
    av[ac++] = s->path;
    av[ac++] = "-o";
    av[ac++] = NULL; /* dem, set by the caller */
    av[ac++] = "--save-lines";
    av[ac++] = NULL;
    av[ac++] = "--summary-json";
    av[ac++] = NULL;
    av[ac++] = "--debug-dir";
    av[ac++] = NULL;
    av[ac++] = "-q";
    for (o = strtok(buf, " \t"); o && ac < MAX_ARGS - 1; o = strtok(NULL, " \t"))
        av[ac++] = o;
    av[ac] = NULL;
    return o ? -1 : ac;
}

static char *join(const char *a, const char *b)
{
    char *s = malloc(strlen(a) + strlen(b) + 2);
    if (s)
        sprintf(s, "%s/%s", a, b);
    return s;
}

/* A word for sh: single quotes, ' as '\''. */
static void sh_word(FILE *f, const char *w)
{
    const char *p;
    if (*w && strspn(w, "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                        "0123456789_-./,:=+@%") == strlen(w)) {
        fputs(w, f);
        return;
    }
    fputc('\'', f);
    for (p = w; *p; p++)
        if (*p == '\'')
            fputs("'\\''", f);
        else
            fputc(*p, f);
    fputc('\'', f);
}

/* The shell line of one sheet: mkdir, run, the log; the hash last. */
static int emit_line(FILE *f, const char *exe, const sheet *s, const char *dir,
                     int tolerate)
{
    char *av[MAX_ARGS], buf[4096], *dem = join(dir, "dem.tif"),
         *lines = join(dir, "lines.geojson"), *sum = join(dir, "summary.json"),
         *dbg = join(dir, "debug"), *log = join(dir, "run.log");
    int ac = run_argv(exe, s, av, buf, sizeof buf), i, rc = 0;
    if (ac < 0 || !dem || !lines || !sum || !dbg || !log) {
        rc = -1;
        goto done;
    }
    av[4] = dem, av[6] = lines, av[8] = sum, av[10] = dbg;
    fputs("mkdir -p ", f);
    sh_word(f, dir);
    fputs(" && ", f);
    for (i = 0; i < ac; i++) {
        sh_word(f, av[i]);
        fputc(' ', f);
    }
    fputs("> ", f); /* the log, on the same line: one job, one line */
    sh_word(f, log);
    /* --neighbours: a sheet that cannot start is the joint step's to
     * seed and run, not a failed job that stops make */
    fputs(tolerate ? " 2>&1 || :\n" : " 2>&1\n", f);
done:
    free(dem), free(lines), free(sum), free(dbg), free(log);
    return rc;
}

/* ---- running ---- */

static int mkdir_p(const char *path)
{
    char tmp[PATH_MAX], *p;
    if (strlen(path) >= sizeof tmp)
        return -1;
    strcpy(tmp, path);
    for (p = tmp + 1; *p; p++)
        if (*p == '/') {
            *p = 0;
            if (mkdir(tmp, 0777) != 0 && errno != EEXIST)
                return -1;
            *p = '/';
        }
    return mkdir(tmp, 0777) != 0 && errno != EEXIST ? -1 : 0;
}

/* Fork and exec av with stdout and stderr to log; the pid or -1. */
static pid_t spawn(char **av, const char *log)
{
    pid_t pid;
    int fd;
    fflush(NULL);
    pid = fork();
    if (pid == 0) {
        fd = open(log, O_WRONLY | O_CREAT | O_TRUNC, 0666);
        if (fd >= 0) {
            dup2(fd, 1), dup2(fd, 2);
            close(fd);
        }
        execv(av[0], av);
        _exit(127);
    }
    return pid;
}

static pid_t start(const char *exe, sheet *s)
{
    char *av[MAX_ARGS], buf[4096], *dem = join(s->dir, "dem.tif"),
         *lines = join(s->dir, "lines.geojson"),
         *sum = join(s->dir, "summary.json"), *dbg = join(s->dir, "debug"),
         *log = join(s->dir, "run.log");
    pid_t pid = -1;
    if (!dem || !lines || !sum || !dbg || !log ||
        run_argv(exe, s, av, buf, sizeof buf) < 0)
        goto done;
    av[4] = dem, av[6] = lines, av[8] = sum, av[10] = dbg;
    unlink(sum); /* a stale summary would read as this run's */
    pid = spawn(av, log);
done:
    free(dem), free(lines), free(sum), free(dbg), free(log);
    return pid;
}

/* The contents of a small file (NULL: none), the last line only when
 * last. */
static char *slurp(const char *path, int last)
{
    FILE *f = fopen(path, "rb");
    char *b, *e;
    long n;
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    n = ftell(f);
    fseek(f, 0, SEEK_SET);
    if (n < 0 || n > (1 << 20) || !(b = malloc((size_t)n + 1))) {
        fclose(f);
        return NULL;
    }
    n = (long)fread(b, 1, (size_t)n, f);
    fclose(f);
    b[n] = 0;
    while (n > 0 && (b[n - 1] == '\n' || b[n - 1] == '\r'))
        b[--n] = 0;
    if (last && (e = strrchr(b, '\n')) != NULL)
        memmove(b, e + 1, strlen(e + 1) + 1);
    return b;
}

static void json_str(FILE *f, const char *s)
{
    fputc('"', f);
    td_cli_json_str(f, s, SIZE_MAX);
    fputc('"', f);
}

/* One finished (or skipped) sheet into batch.log. */
static void log_sheet(FILE *lg, const sheet *s, const char *status,
                      double secs, int code)
{
    char *sp = join(s->dir, "summary.json"), *lp = join(s->dir, "run.log");
    char *sum = sp && !strcmp(status, "ok") ? slurp(sp, 0) : NULL;
    char *err = lp && strcmp(status, "ok") && strcmp(status, "skipped")
                    ? slurp(lp, 1) : NULL;
    fputs("{\"sheet\": ", lg);
    json_str(lg, s->path);
    fputs(", \"status\": ", lg);
    json_str(lg, status);
    fprintf(lg, ", \"exit\": %d, \"seconds\": %.3f, \"options\": ", code, secs);
    json_str(lg, s->opts);
    fputs(", \"out\": ", lg);
    json_str(lg, s->dir);
    if (s->seeded) {
        fputs(", \"heights_from\": ", lg);
        json_str(lg, s->seeded);
    }
    if (sum)
        fprintf(lg, ", \"summary\": %s", sum);
    if (err) {
        fputs(", \"error\": ", lg);
        json_str(lg, err);
    }
    fputs("}\n", lg);
    fflush(lg);
    free(sp), free(lp), free(sum), free(err);
}

static int up_to_date(const sheet *s)
{
    char *dem = join(s->dir, "dem.tif"), *hp = join(s->dir, "hash");
    char *h = hp ? slurp(hp, 0) : NULL, want[32];
    struct stat st;
    int ok;
    snprintf(want, sizeof want, "%016llx", (unsigned long long)s->hash);
    ok = dem && h && stat(dem, &st) == 0 && !strcmp(h, want);
    free(dem), free(hp), free(h);
    return ok;
}

static void write_hash(const sheet *s)
{
    char *hp = join(s->dir, "hash");
    FILE *f = hp ? fopen(hp, "w") : NULL;
    if (f) {
        fprintf(f, "%016llx\n", (unsigned long long)s->hash);
        fclose(f);
    }
    free(hp);
}

/* ---- seams: each sheet interpolated again with its neighbours' lines ----
 *
 * Georeferenced sheets that share an edge (or a corner) in one CRS are
 * neighbours; `topodig interp` takes a sheet's labelled lines with theirs
 * (--beside) within --margin of its edges, so the DEMs meet at the
 * edges.  Sheets that overlap instead of sharing an edge are not used for
 * each other (batch.log says so). */

#define EDGE_TOL 1.5 /* cells: a gap or an overlap this small is an edge */

static void place_sheet(sheet *s)
{
    td_georef g;
    td_ctx cx;
    int w, h, ch;
    td_ctx_init(&cx);
    td_georef_init(&g);
    s->placed = 0;
    if (td_image_info(s->path, &w, &h, &ch, &g, &cx) == 0 && g.valid &&
        g.gt[2] == 0 && g.gt[4] == 0 && g.gt[1] > 0 && g.gt[5] < 0) {
        s->x0 = g.gt[0], s->x1 = g.gt[0] + w * g.gt[1];
        s->y1 = g.gt[3], s->y0 = g.gt[3] + h * g.gt[5];
        s->res = g.gt[1] > -g.gt[5] ? g.gt[1] : -g.gt[5];
        s->epsg = g.epsg;
        s->placed = 1;
    }
    td_georef_clear(&g);
    td_ctx_clear(&cx);
}

/* 1: a and b share an edge or a corner; 0: apart; -1: they overlap. */
static int beside(const sheet *a, const sheet *b)
{
    double tol = EDGE_TOL * (a->res > b->res ? a->res : b->res);
    double ox = (a->x1 < b->x1 ? a->x1 : b->x1) - (a->x0 > b->x0 ? a->x0 : b->x0);
    double oy = (a->y1 < b->y1 ? a->y1 : b->y1) - (a->y0 > b->y0 ? a->y0 : b->y0);
    if (!a->placed || !b->placed || a->epsg != b->epsg || ox < -tol || oy < -tol)
        return 0;
    return ox > tol && oy > tol ? -1 : 1;
}

static int cmp_size(const void *pa, const void *pb)
{
    size_t a = *(const size_t *)pa, b = *(const size_t *)pb;
    return (a > b) - (a < b);
}

static void crs_name(FILE *f, int epsg)
{
    if (epsg > 0)
        fprintf(f, "EPSG:%d", epsg);
    else
        fputs("a CRS without an EPSG code", f);
}

/* The placed sheets' neighbours (s->nb: those sharing an edge or a
 * corner), by a sweep along x (linear in the sheets for a grid of them,
 * not quadratic).  Sheets that overlap instead are named in lg and left
 * unplaced (out of the joint steps).  0, or -1 out of memory. */
static int find_neighbours(sheet *v, size_t n, FILE *lg)
{
    td_dkey *ord = malloc((n + 1) * sizeof *ord);
    size_t m = 0, a, b, np = 0, cap = 0, i, *pr = NULL;
    double tol = 0;
    int rc = -1;
    if (!ord)
        return -1;
    for (i = 0; i < n; i++) {
        free(v[i].nb), v[i].nb = NULL, v[i].nnb = 0;
        if (v[i].ok && v[i].placed) {
            ord[m].key = v[i].x0, ord[m++].i = i;
            tol = fmax(tol, EDGE_TOL * v[i].res);
        }
    }
    qsort(ord, m, sizeof *ord, td_dkey_cmp);
    for (a = 0; a < m; a++)
        for (b = a + 1; b < m && ord[b].key <= v[ord[a].i].x1 + tol; b++) {
            sheet *p = &v[ord[a].i], *q = &v[ord[b].i];
            int r = beside(p, q);
            if (r == 0 && p->epsg != q->epsg) {
                int pe = p->epsg, qe = q->epsg;
                p->epsg = qe; /* where they would meet in one CRS */
                r = beside(p, q);
                p->epsg = pe;
                if (r != 0) {
                    fputs("{\"sheet\": ", lg);
                    json_str(lg, p->path);
                    fputs(", \"step\": \"edges\", \"warning\": \"in ", lg);
                    crs_name(lg, pe);
                    fputs(", ", lg);
                    td_cli_json_str(lg, q->path, SIZE_MAX);
                    fputs(" in ", lg);
                    crs_name(lg, qe);
                    fputs(": not matched with each other\"}\n", lg);
                }
                continue;
            }
            if (r == -1) {
                fputs("{\"sheet\": ", lg);
                json_str(lg, p->path);
                fputs(", \"step\": \"edges\", \"warning\": \"overlaps ", lg);
                td_cli_json_str(lg, q->path, SIZE_MAX);
                fputs(" instead of sharing an edge: neither takes part in "
                      "the joint steps\"}\n", lg);
                p->stage = q->stage = -1; /* marked */
            } else if (r == 1) {
                if (np == cap) {
                    size_t *t = realloc(pr, 2 * (cap = 2 * cap + 64) *
                                                sizeof *pr);
                    if (!t)
                        goto done;
                    pr = t;
                }
                pr[2 * np] = ord[a].i, pr[2 * np++ + 1] = ord[b].i;
            }
        }
    for (i = 0; i < n; i++) /* overlapping sheets are left as they are */
        if (v[i].stage == -1)
            v[i].placed = 0, v[i].stage = 0;
    for (i = 0; i < 2 * np; i++) /* count, then fill */
        if (v[pr[i]].placed && v[pr[i ^ 1]].placed)
            v[pr[i]].nnb++;
    for (i = 0; i < n; i++)
        if (v[i].nnb && !(v[i].nb = malloc(v[i].nnb * sizeof *v[i].nb)))
            goto done;
    for (i = 0; i < n; i++)
        v[i].nnb = 0;
    for (i = 0; i < 2 * np; i++)
        if (v[pr[i]].placed && v[pr[i ^ 1]].placed)
            v[pr[i]].nb[v[pr[i]].nnb++] = pr[i ^ 1];
    for (i = 0; i < n; i++) /* in manifest order */
        if (v[i].nnb > 1)
            qsort(v[i].nb, v[i].nnb, sizeof *v[i].nb, cmp_size);
    rc = 0;
done:
    free(ord), free(pr);
    return rc;
}

/* Appends "--NAME VALUE" pairs of s's options that interp knows (the
 * interpolation options) to av from ac; returns the new ac. */
static int interp_opts(char *opts, char **av, int ac)
{
    td_opt t[TD_CLI_INTERP_OPTS];
    td_interp_params p;
    char *o, *save = NULL;
    size_t n = td_cli_interp_opts(t, &p), k;
    for (o = strtok_r(opts, " \t", &save); o && ac < MAX_ARGS - 3;
         o = strtok_r(NULL, " \t", &save)) {
        char *eq = strchr(o, '=');
        size_t nl = eq ? (size_t)(eq - o) - 2 : strlen(o) - 2;
        if (strncmp(o, "--", 2) != 0)
            continue;
        for (k = 0; k < n; k++)
            if (strlen(t[k].name) == nl && !strncmp(o + 2, t[k].name, nl))
                break;
        if (k == n)
            continue;
        av[ac++] = o;
        if (!eq && (o = strtok_r(NULL, " \t", &save)) != NULL)
            av[ac++] = o;
    }
    return ac;
}

/* interp of sheet s with its neighbours' lines into its dem.tif. */
static pid_t start_seam(const char *exe, sheet *s, const sheet *v,
                        const bt_opts *o)
{
    char *av[MAX_ARGS], buf[4096], mg[32], *paths[MAX_ARGS];
    char *lines = join(s->dir, "lines.geojson"), *dem = join(s->dir, "dem.tif"),
         *log = join(s->dir, "seams.log");
    size_t i, np = 0, bl = 0;
    int ac = 0;
    pid_t pid = -1;
    if (!lines || !dem || !log)
        goto done;
    snprintf(buf, sizeof buf, "%s", s->opts);
    snprintf(mg, sizeof mg, "%d", o->margin);
    av[ac++] = (char *)exe, av[ac++] = "interp", av[ac++] = lines;
    av[ac++] = "--like", av[ac++] = s->path, av[ac++] = "-o", av[ac++] = dem;
    av[ac++] = "-q", av[ac++] = "--margin", av[ac++] = mg;
    for (i = 0; o->seams && i < s->nnb && ac < 200; i++)
        if ((paths[np] = join(v[s->nb[i]].dir, "lines.geojson")) != NULL) {
            av[ac++] = "--beside", av[ac++] = paths[np++];
            bl += strlen(v[s->nb[i]].stem) + 2;
        }
    free(s->beside);
    if ((s->beside = calloc(1, bl + 1)) != NULL)
        for (i = 0; o->seams && i < np; i++)
            sprintf(s->beside + strlen(s->beside), "%s%s",
                    *s->beside ? ", " : "", v[s->nb[i]].stem);
    ac = interp_opts(buf, av, ac);
    av[ac] = NULL;
    pid = spawn(av, log);
    for (i = 0; i < np; i++)
        free(paths[i]);
done:
    free(lines), free(dem), free(log);
    return pid;
}

/* Copy a small file; 0 or -1. */
static int copy_file(const char *from, const char *to)
{
    FILE *a = fopen(from, "rb"), *b = a ? fopen(to, "wb") : NULL;
    char buf[65536];
    size_t k;
    int rc = a && b ? 0 : -1;
    while (rc == 0 && (k = fread(buf, 1, sizeof buf, a)) > 0)
        rc = fwrite(buf, 1, k, b) == k ? 0 : -1;
    if (a)
        fclose(a);
    if (b && fclose(b) != 0)
        rc = -1;
    return rc;
}

/* The lines as the sheet's own run labelled them, own.geojson: copied
 * from lines.geojson when the run is newer (its run.log), so the joint
 * solve (which rewrites lines.geojson) starts from them every time, also
 * after jobs run by --emit.  Its path, or NULL. */
static char *own_lines(const sheet *s)
{
    char *a = join(s->dir, "lines.geojson"), *b = join(s->dir, "own.geojson"),
         *r = join(s->dir, "run.log");
    struct stat so, sr_;
    if (a && b && r && (stat(b, &so) != 0 ||
                        (stat(r, &sr_) == 0 &&
                         (sr_.st_mtim.tv_sec > so.st_mtim.tv_sec ||
                          (sr_.st_mtim.tv_sec == so.st_mtim.tv_sec &&
                           sr_.st_mtim.tv_nsec > so.st_mtim.tv_nsec))))) {
        if (copy_file(a, b) != 0) {
            unlink(b);
            free(b);
            b = a, a = NULL;
        }
    }
    free(a), free(r);
    return b;
}

/* One seams step into batch.log. */
static void log_seam(FILE *lg, const sheet *s, double secs, int code)
{
    char *lp = join(s->dir, "seams.log");
    char *err = lp && code ? slurp(lp, 1) : NULL;
    fputs("{\"sheet\": ", lg);
    json_str(lg, s->path);
    fprintf(lg, ", \"step\": \"%s\", \"status\": \"%s\", \"exit\": %d, "
            "\"seconds\": %.3f, \"beside\": ", s->beside && *s->beside
            ? "seams" : "interp", code ? "failed" : "ok", code, secs);
    json_str(lg, s->beside ? s->beside : "");
    if (err) {
        fputs(", \"error\": ", lg);
        json_str(lg, err);
    }
    fputs("}\n", lg);
    fflush(lg);
    free(lp), free(err);
}

/* DIR/<stem>/seeded names the neighbours a sheet's heights came from
 * (--neighbours): written after its run (write 1; removed when it had
 * none), read back when --resume skips it (write 0), so the joint solve
 * knows its known points were its neighbours'. */
static void seeded_mark(sheet *s, int write)
{
    char *p = join(s->dir, "seeded");
    FILE *f;
    if (!p)
        return;
    if (!write) {
        free(s->seeded);
        s->seeded = slurp(p, 0);
    } else if (!s->seeded) {
        unlink(p);
    } else if ((f = fopen(p, "w")) != NULL) {
        fprintf(f, "%s\n", s->seeded);
        fclose(f);
    }
    free(p);
}

/* Run the waiting sheets, jobs at a time. */
/* SIGINT or SIGTERM: the running sheets are stopped, nothing new starts,
 * and batch exits 128 + the signal (--resume goes on from there). */
static volatile sig_atomic_t bt_stop;

static void on_signal(int sig)
{
    bt_stop = sig;
}

/* Stop the running sheets (a signal came): each is killed, waited for and
 * logged as interrupted; its outputs, written atomically, are the last
 * whole ones or none. */
static void stop_all(sheet *v, size_t n, FILE *lg)
{
    size_t i;
    for (i = 0; i < n; i++)
        if (v[i].state == 1)
            kill(v[i].pid, SIGTERM);
    for (i = 0; i < n; i++)
        if (v[i].state == 1) {
            int status;
            while (waitpid(v[i].pid, &status, 0) < 0 && errno == EINTR)
                ;
            v[i].state = 2, v[i].ok = 0;
            if (!v[i].stage)
                log_sheet(lg, &v[i], "interrupted", td_now() - v[i].t0, -1);
        }
    fflush(lg);
}

static void run_all(const char *exe, sheet *v, size_t n, const bt_opts *o,
                    FILE *lg)
{
    size_t next = 0, running = 0, i, total = 0, done = 0;
    for (i = 0; i < n; i++)
        total += v[i].state == 0;
    while (done < total && !bt_stop) {
        while (running < (size_t)o->jobs && next < n && !bt_stop) {
            sheet *s = &v[next++];
            if (s->state != 0)
                continue;
            if (o->resume && !s->stage && !s->seeded && up_to_date(s)) {
                s->state = 2, s->ok = 1, done++;
                seeded_mark(s, 0);
                log_sheet(lg, s, "skipped", 0, 0);
                continue;
            }
            if (mkdir_p(s->dir) != 0 ||
                (s->pid = s->stage ? start_seam(exe, s, v, o)
                                   : start(exe, s)) < 0) {
                s->state = 2, done++;
                if (s->stage)
                    log_seam(lg, s, 0, -1);
                else
                    s->ok = 0, log_sheet(lg, s, "failed", 0, -1);
                continue;
            }
            s->state = 1, s->t0 = td_now(), running++;
        }
        if (running > 0) {
            int status;
            pid_t pid = wait(&status);
            if (pid < 0 && bt_stop)
                break;
            for (i = 0; pid > 0 && i < n; i++)
                if (v[i].state == 1 && v[i].pid == pid) {
                    int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128;
                    v[i].state = 2, done++, running--;
                    if (v[i].stage) { /* the sheet's own DEM stays on failure */
                        log_seam(lg, &v[i], td_now() - v[i].t0, code);
                        continue;
                    }
                    v[i].ok = code == 0;
                    if (code == 0) {
                        write_hash(&v[i]);
                        seeded_mark(&v[i], 1);
                    }
                    log_sheet(lg, &v[i], code == 0 ? "ok" : "failed",
                              td_now() - v[i].t0, code);
                    if (!o->quiet)
                        fprintf(stderr, "batch: %s %s%s\n", v[i].stem,
                                code == 0 ? "ok" : "FAILED",
                                v[i].seeded ? " (heights from its neighbours)"
                                            : "");
                }
        } else if (next >= n) {
            break;
        }
    }
    if (bt_stop)
        stop_all(v, n, lg);
}

/* ---- heights from the neighbours (a first step of edge matching) ----
 *
 * A sheet that failed for want of a start (no interval, no label, no
 * known point) takes the interval its labelled neighbours agree on and,
 * as known points, where their labelled lines (confidence >= 0.5) leave
 * them across the shared edge: a contour goes on across a sheet edge, so
 * the point just inside this sheet beside a neighbour's line end lies on
 * the same contour.  Read in this sheet's frame through both sheets'
 * georeferencing. */

#define SEED_TOL 3.0 /* px beyond the edge a neighbour's line end may lie */
#define MAX_SEEDS 64
#define SEED_CONF 0.3 /* the least confidence of a neighbour's line */

static int seedable(const sheet *s)
{
    char *lp = join(s->dir, "run.log"), *e = lp ? slurp(lp, 1) : NULL;
    int yes = e && (strstr(e, "no interval") || strstr(e, "no heights to "
                                                          "start from") ||
                    strstr(e, "could be labelled from the known points"));
    free(lp), free(e);
    return yes;
}

/* The interval of a labelled sheet (its summary), or 0. */
static double interval_of(const sheet *s)
{
    char *sp = join(s->dir, "summary.json"), *j = sp ? slurp(sp, 0) : NULL,
         *k = j ? strstr(j, "\"interval\": ") : NULL;
    double v = k ? atof(k + 12) : 0;
    free(sp), free(j);
    return v > 0 ? v : 0;
}

/* Known points from neighbour t's labelled lines into buf (appended):
 * its lines' file coordinates (the map coordinates run wrote them in,
 * whatever frame the file names) through g to this sheet's cells;
 * returns how many. */
static int seeds_from(const sheet *t, const td_georef *g, int w, int h,
                      char *buf, size_t bl, int room)
{
    char *lp = join(t->dir, "lines.geojson");
    td_lines *ls = NULL;
    td_georef gt, fr;
    td_ctx cx;
    size_t i;
    int n = 0, e, tw, th, ch;
    td_ctx_init(&cx);
    td_georef_init(&gt);
    td_georef_init(&fr);
    (void)tw, (void)th, (void)ch;
    if (!lp || td_vector_read_lines(lp, NULL, &ls, NULL, &fr, &cx) != 0)
        goto done;
    for (i = 0; i < ls->n && n < room; i++) {
        const td_line *l = &ls->v[i];
        if (!l->has_height || l->closed || l->n < 2 || l->confidence < SEED_CONF)
            continue;
        for (e = 0; e < 2 && n < room; e++) {
            double X, Y, x, y;
            X = l->xy[e ? 2 * l->n - 2 : 0], Y = l->xy[e ? 2 * l->n - 1 : 1];
            if (fr.valid) /* back to the file's coordinates */
                td_georef_apply(&fr, X, Y, &X, &Y);
            else
                Y = -Y;
            if (td_georef_to_cells(g, X, Y, &x, &y) != 0)
                continue;
            {
                int in_y = y >= 0 && y <= h, in_x = x >= 0 && x <= w;
                if (in_y && x >= -SEED_TOL && x <= 0.5)
                    x = 0.5;
                else if (in_y && x >= w - 0.5 && x <= w + SEED_TOL)
                    x = w - 0.5;
                else if (in_x && y >= -SEED_TOL && y <= 0.5)
                    y = 0.5;
                else if (in_x && y >= h - 0.5 && y <= h + SEED_TOL)
                    y = h - 0.5;
                else
                    continue;
            }
            snprintf(buf + strlen(buf), bl - strlen(buf),
                     " --known %.2f,%.2f,%.10g", x, y, l->height);
            n++;
        }
    }
done:
    td_lines_free(ls);
    free(lp);
    td_georef_clear(&gt);
    td_georef_clear(&fr);
    td_ctx_clear(&cx);
    return n;
}

/* The options a failed sheet gets from its labelled neighbours; 1 when
 * there are some. */
static int seed_sheet(sheet *s, sheet *v, size_t n)
{
    td_georef g;
    td_ctx cx;
    char *buf = NULL, *from = NULL;
    double iv = 0;
    size_t i, fl = 0;
    int w, h, ch, got = 0, room = MAX_SEEDS;
    td_ctx_init(&cx);
    td_georef_init(&g);
    if (td_image_info(s->path, &w, &h, &ch, &g, &cx) != 0 || !g.valid ||
        !(buf = calloc(1, 64 * MAX_SEEDS + strlen(s->opts) + 64)) ||
        !(from = calloc(1, 1)))
        goto done;
    for (i = 0; i < n && room > 0; i++) {
        int k;
        if (&v[i] == s || !v[i].ok || v[i].seeded)
            continue; /* only sheets labelled by their own evidence */
        if ((k = seeds_from(&v[i], &g, w, h, buf, 64 * MAX_SEEDS, room)) > 0) {
            char *nf = realloc(from, fl + strlen(v[i].stem) + 3);
            if (!nf)
                break;
            from = nf;
            fl += (size_t)sprintf(from + fl, "%s%s", fl ? ", " : "", v[i].stem);
            room -= k, got += k;
            if (!(iv > 0))
                iv = interval_of(&v[i]);
        }
    }
    if (got > 0) {
        char *o = malloc(strlen(s->opts) + strlen(buf) + 64);
        if (o) {
            sprintf(o, "%s%s", s->opts, buf);
            if (iv > 0 && !strstr(s->opts, "--interval"))
                sprintf(o + strlen(o), " --interval %.10g", iv);
            free(s->opts);
            s->opts = o;
            free(s->seeded);
            s->seeded = from;
            from = NULL;
        } else {
            got = 0;
        }
    }
done:
    free(buf), free(from);
    td_georef_clear(&g);
    td_ctx_clear(&cx);
    return got > 0;
}

/* Passes until no failed sheet can be seeded any more. */
static void seed_passes(const char *exe, sheet *v, size_t n,
                        const bt_opts *o, FILE *lg)
{
    int pass, more = 1;
    size_t i;
    for (pass = 0; pass < 8 && more && !bt_stop; pass++) {
        more = 0;
        for (i = 0; i < n; i++)
            if (!v[i].ok && !v[i].seeded && v[i].state == 2 &&
                seedable(&v[i]) && seed_sheet(&v[i], v, n))
                v[i].state = 0, more = 1;
        if (more)
            run_all(exe, v, n, o, lg);
    }
}

/* ---- edge matching: the heights on both sides of each shared edge ----
 * A contour crossing a shared edge ends on both sheets within a cell or
 * two of it: the two ends are paired (the nearest within MATCH_TOL cells)
 * and their heights compared; batch.log gets one line per edge. */

#define MATCH_TOL 3.0
#define MAX_REPORT 8

typedef struct endpt {
    double X, Y, h, conf;
} endpt;

/* The ends of s's labelled open lines that lie on its border, in map
 * coordinates (*out, free()); their number, -1 when unreadable. */
static long edge_ends(const sheet *s, endpt **out)
{
    char *lp = join(s->dir, "lines.geojson");
    td_lines *ls = NULL;
    td_georef fr;
    td_ctx cx;
    size_t i, n = 0;
    int e;
    long rc = -1;
    double tol = EDGE_TOL * s->res;
    *out = NULL;
    td_ctx_init(&cx);
    td_georef_init(&fr);
    if (!lp || td_vector_read_lines(lp, NULL, &ls, NULL, &fr, &cx) != 0 ||
        !(*out = malloc((2 * ls->n + 1) * sizeof **out)))
        goto done;
    for (i = 0; i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        if (!l->has_height || l->closed || l->n < 2)
            continue;
        for (e = 0; e < 2; e++) {
            double X = l->xy[e ? 2 * l->n - 2 : 0], Y = l->xy[e ? 2 * l->n - 1 : 1];
            if (fr.valid)
                td_georef_apply(&fr, X, Y, &X, &Y);
            else
                Y = -Y;
            if (X - s->x0 > tol && s->x1 - X > tol && Y - s->y0 > tol &&
                s->y1 - Y > tol)
                continue; /* inside: not at the border */
            (*out)[n++] = (endpt){X, Y, l->height, l->confidence};
        }
    }
    rc = (long)n;
done:
    if (rc < 0)
        free(*out), *out = NULL;
    td_lines_free(ls);
    free(lp);
    td_georef_clear(&fr);
    td_ctx_clear(&cx);
    return rc;
}

/* Pair the ends of a and b along their shared edge; one line in lg.
 * Adds to *cross and *conf. */
static void match_edge(FILE *lg, const sheet *a, const endpt *ea, long na,
                       const sheet *b, const endpt *eb, long nb,
                       size_t *cross, size_t *conf)
{
    double tol = MATCH_TOL * (a->res > b->res ? a->res : b->res);
    double bt = EDGE_TOL * (a->res > b->res ? a->res : b->res);
    long i, j, best, nc = 0, nx = 0;
    fputs("{\"edge\": [", lg);
    json_str(lg, a->stem);
    fputs(", ", lg);
    json_str(lg, b->stem);
    fputs("], \"step\": \"edges\", \"conflicts\": [", lg);
    for (i = 0; i < na; i++) {
        double bd = tol * tol;
        /* only ends on b's side of a: within b's extent */
        if (ea[i].X < b->x0 - bt || ea[i].X > b->x1 + bt ||
            ea[i].Y < b->y0 - bt || ea[i].Y > b->y1 + bt)
            continue;
        for (j = 0, best = -1; j < nb; j++) {
            double dx = ea[i].X - eb[j].X, dy = ea[i].Y - eb[j].Y;
            if (dx * dx + dy * dy <= bd)
                bd = dx * dx + dy * dy, best = j;
        }
        if (best < 0)
            continue;
        nx++;
        if (ea[i].h != eb[best].h) {
            if (nc < MAX_REPORT)
                fprintf(lg, "%s{\"x\": %.10g, \"y\": %.10g, \"heights\": "
                        "[%.10g, %.10g], \"confidence\": [%.3f, %.3f]}",
                        nc ? ", " : "", ea[i].X, ea[i].Y, ea[i].h, eb[best].h,
                        ea[i].conf, eb[best].conf);
            nc++;
        }
    }
    fprintf(lg, "], \"crossings\": %ld, \"conflicting\": %ld}\n", nx, nc);
    *cross += (size_t)nx, *conf += (size_t)nc;
}

/* Every pair of neighbours; a line on stderr. */
static void match_edges(FILE *lg, const sheet *v, size_t n, int quiet)
{
    endpt **E = calloc(n + 1, sizeof *E);
    long *ne = calloc(n + 1, sizeof *ne);
    size_t i, j, k, edges = 0, cross = 0, conf = 0;
    if (!E || !ne)
        goto done;
    for (i = 0; i < n; i++)
        ne[i] = v[i].ok && v[i].placed ? edge_ends(&v[i], &E[i]) : -1;
    for (i = 0; i < n; i++)
        for (k = 0; ne[i] >= 0 && k < v[i].nnb; k++)
            if ((j = v[i].nb[k]) > i && ne[j] >= 0) {
                match_edge(lg, &v[i], E[i], ne[i], &v[j], E[j], ne[j], &cross,
                           &conf);
                edges++;
            }
    fflush(lg);
    if (!quiet && edges)
        fprintf(stderr, "batch: %zu shared edges, %zu contour crossings, %zu "
                "with different heights on the two sides (batch.log)\n",
                edges, cross, conf);
done:
    for (i = 0; E && i < n; i++)
        free(E[i]);
    free(E), free(ne);
}

/* ---- the heights of the series in one solve (td_series_label) ---- */

/* "index contours every N" in a sheet's summary warnings, or 0. */
static int index_of(const sheet *s)
{
    char *sp = join(s->dir, "summary.json"), *j = sp ? slurp(sp, 0) : NULL,
         *k = j ? strstr(j, "index contours every ") : NULL;
    int v = k ? atoi(k + 21) : 0;
    free(sp), free(j);
    return v > 1 ? v : 0;
}

/* Whole-series interpolation limits: every sheet with the default
 * interpolation (no interpolation option in its manifest line) and the
 * series' extent at most this many cells. */
#define WHOLE_CELLS 3e8

/* The sheets' DEMs cut from one interpolation of all their lines
 * (td_series_interp), written to their dem.tif: 0, or -1 (then each sheet
 * is interpolated with its neighbours beside it instead). */
static int whole_dems(const sheet *v, const size_t *idx,
                      const td_series_sheet *ss, const td_georef *g,
                      size_t m, double interval)
{
    static const char *const iopt[] = {"--method", "--step", "--summit",
        "--peninsula", "--weight", "--dirs", "--smooth", "--epsilon",
        "--fallback", "--nodata", NULL};
    td_interp_params ip = td_interp_defaults();
    td_grid_f32 **d = calloc(m + 1, sizeof *d);
    td_ctx cx;
    double W = 0, H = 0;
    size_t i;
    int k, rc = -1;
    td_ctx_init(&cx);
    for (i = 0; i < m; i++) {
        W = fmax(W, ss[i].ox + ss[i].w), H = fmax(H, ss[i].oy + ss[i].h);
        for (k = 0; iopt[k]; k++)
            if (strstr(v[idx[i]].opts, iopt[k]))
                goto done;
    }
    if (!d || W * H > WHOLE_CELLS)
        goto done;
    ip.interval = interval;
    if (td_series_interp(ss, m, &ip, d, &cx) != 0)
        goto done;
    for (i = 0; i < m; i++) {
        char *p = join(v[idx[i]].dir, "dem.tif");
        if (!p || td_dem_write(p, d[i], &g[i], &cx) != 0) {
            free(p);
            goto done;
        }
        free(p);
    }
    rc = 0;
done:
    for (i = 0; d && i < m; i++)
        td_grid_f32_free(d[i]);
    free(d);
    td_ctx_clear(&cx);
    return rc;
}

/* Label the placed sheets sel[0..nsel) again as one; their lines.geojson
 * rewritten.  Returns 1 when it did, 2 when it also cut their DEMs from
 * one interpolation (whole).  With solve 0, only that interpolation, of
 * the lines as they are (the blocks labelled before). */
static int joint_block(sheet *v, const size_t *sel, size_t nsel,
                       const size_t *ctx, size_t nctx, FILE *lg, int quiet,
                       int whole, long block, int solve)
{
    size_t n = nsel + nctx, nown = 0, ctx_lines = 0;
    td_series_sheet *ss = calloc(n + 1, sizeof *ss);
    td_georef *g = calloc(n + 1, sizeof *g);
    size_t *idx = calloc(n + 1, sizeof *idx), m = 0, i, k, changed = 0,
           lines = 0;
    double x0 = INFINITY, y1 = -INFINITY, res = 0, iv, *old = NULL;
    td_label_params lp = td_label_defaults();
    td_label_report rep;
    td_ctx cx;
    const char *why = NULL;
    int ok = 0, ch, w, h;
    td_ctx_init(&cx);
    memset(&rep, 0, sizeof rep);
    if (!ss || !g || !idx)
        goto done;
    for (k = 0; k < n; k++) {
        size_t si = k < nsel ? sel[k] : ctx[k - nsel];
        char *lp_ = !(v[si].ok && v[si].placed) ? NULL
                    : solve && k < nsel ? own_lines(&v[si])
                                        : join(v[si].dir, "lines.geojson");
        td_georef_init(&g[m]);
        if (v[si].ok && v[si].placed && lp_ &&
            td_image_info(v[si].path, &w, &h, &ch, &g[m], &cx) == 0 &&
            td_vector_read_lines(lp_, &g[m], &ss[m].lines, NULL, NULL,
                                 &cx) == 0) {
            if (m > 0 && (fabs(v[si].res - res) > 1e-9 * res ||
                          v[si].epsg != v[idx[0]].epsg))
                why = "the sheets differ in cell size or CRS";
            res = v[si].res;
            x0 = fmin(x0, v[si].x0), y1 = fmax(y1, v[si].y1);
            ss[m].w = w, ss[m].h = h;
            ss[m].evidence = k >= nsel ? 2 : !v[si].seeded;
            nown += k < nsel;
            iv = v[si].seeded ? 0 : interval_of(&v[si]);
            if (!(lp.interval > 0))
                lp.interval = iv;
            else if (iv > 0 && iv != lp.interval)
                why = "the sheets were labelled at different intervals";
            if (!lp.index_every && !v[si].seeded)
                lp.index_every = index_of(&v[si]);
            lines += ss[m].lines->n;
            idx[m++] = si;
        } else {
            td_georef_clear(&g[m]);
            cx.msg[0] = 0, cx.code = 0;
        }
        free(lp_);
    }
    if (m < 2 || nown < 1)
        goto done;
    if (!why && !(lp.interval > 0))
        why = "no sheet's interval is known";
    if (!why && !(old = malloc((lines + 1) * sizeof *old)))
        why = "out of memory";
    for (i = 0, lines = 0; !why && i < m; i++)
        for (k = 0; k < ss[i].lines->n; k++)
            old[lines++] = ss[i].lines->v[k].has_height
                               ? ss[i].lines->v[k].height : NAN;
    for (i = 0; !why && i < m; i++) {
        ss[i].ox = (v[idx[i]].x0 - x0) / res;
        ss[i].oy = (y1 - v[idx[i]].y1) / res;
    }
    lp.index_auto = 1;
    if (!solve) {
        ok = !why && whole_dems(v, idx, ss, g, m, lp.interval) == 0 ? 2 : 0;
        fprintf(lg, "{\"step\": \"dems\", \"status\": \"%s\", "
                "\"sheets\": %zu, \"dems\": \"%s\"}\n",
                ok ? "ok" : "skipped", m,
                ok ? "one interpolation" : "each sheet");
        fflush(lg);
        goto done;
    }
    if (!why && td_series_label(ss, m, &lp, &rep, &cx) != 0)
        why = cx.msg;
    for (i = 0, lines = 0; !why && i < m; i++) {
        char *lp_;
        if (ss[i].evidence == 2) { /* a solved neighbour: left as it is */
            lines += ss[i].lines->n, ctx_lines += ss[i].lines->n;
            continue;
        }
        lp_ = join(v[idx[i]].dir, "lines.geojson");
        for (k = 0; k < ss[i].lines->n; k++, lines++) {
            const td_line *l = &ss[i].lines->v[k];
            changed += l->has_height ? !(l->height == old[lines])
                                     : old[lines] == old[lines];
        }
        if (!lp_ || td_vector_write_lines(lp_, ss[i].lines, &g[i], &cx) != 0)
            why = cx.msg[0] ? cx.msg : "cannot write the lines";
        free(lp_);
    }
    ok = !why;
    if (ok && whole && whole_dems(v, idx, ss, g, m, lp.interval) == 0)
        ok = 2; /* the DEMs cut from one interpolation */
    fprintf(lg, "{\"step\": \"joint\", \"status\": \"%s\", \"sheets\": %zu, "
            "\"lines\": %zu, \"changed\": %zu, \"labelled\": %zu, "
            "\"dems\": \"%s\"", ok ? "ok" : "skipped", nown,
            lines - ctx_lines, changed, rep.labelled,
            ok == 2 ? "one interpolation" : "each sheet");
    if (block >= 0)
        fprintf(lg, ", \"block\": %ld, \"beside\": %zu", block, m - nown);
    if (why) {
        fputs(", \"why\": ", lg);
        json_str(lg, why);
    }
    fputs("}\n", lg);
    fflush(lg);
    if (!quiet && ok && m >= 2)
        fprintf(stderr, "batch: the %zu sheets%s labelled as one: %zu of %zu "
                "lines changed height\n", nown,
                block >= 0 ? " of a block" : "", changed, lines - ctx_lines);
    else if (!quiet)
        fprintf(stderr, "batch: the sheets keep their own heights (%s)\n",
                why);
done:
    for (i = 0; ss && i < m; i++)
        td_lines_free(ss[i].lines), td_georef_clear(&g[i]);
    free(ss), free(g), free(idx), free(old);
    td_label_report_free(&rep);
    td_ctx_clear(&cx);
    return ok;
}

typedef struct bkey {
    size_t block, sheet;
} bkey;

static int cmp_bkey(const void *pa, const void *pb)
{
    const bkey *a = pa, *b = pb;
    if (a->block != b->block)
        return a->block < b->block ? -1 : 1;
    return (a->sheet > b->sheet) - (a->sheet < b->sheet);
}

/* The joint solve of the placed sheets, in one piece or, for a series
 * larger than `cells` cells (the solve holds the whole series' raster), in
 * blocks of about that size (sheets by their centres), one after another,
 * each with the solved sheets beside it as evidence; the edge matching
 * then reports what differs across the blocks' edges.  Returns 0 when
 * nothing was labelled again, 1 when it was, 2 when the DEMs were cut
 * from one interpolation too. */
static int joint(sheet *v, size_t n, FILE *lg, int quiet, int whole,
                 double cells)
{
    double X0 = INFINITY, Y1 = -INFINITY, X1 = -INFINITY, Y0 = INFINITY,
           res = 0, side;
    size_t i, m = 0, *sel = NULL, a, b, nb = 0, *ctx = NULL, *blk = NULL;
    bkey *key = NULL;
    int ok = 0, r, one;
    for (i = 0; i < n; i++)
        if (v[i].ok && v[i].placed) {
            X0 = fmin(X0, v[i].x0), X1 = fmax(X1, v[i].x1);
            Y0 = fmin(Y0, v[i].y0), Y1 = fmax(Y1, v[i].y1);
            res = fmax(res, v[i].res);
            m++;
        }
    if (m < 2 || !(res > 0))
        return 0;
    one = (X1 - X0) / res * ((Y1 - Y0) / res) <= cells; /* one block */
    side = one ? INFINITY : sqrt(cells) * res;
    sel = malloc(m * sizeof *sel), key = malloc(m * sizeof *key);
    if (!sel || !key) {
        free(sel), free(key);
        return 0;
    }
    for (i = 0, m = 0; i < n; i++)
        if (v[i].ok && v[i].placed) {
            size_t bx = (size_t)((0.5 * (v[i].x0 + v[i].x1) - X0) / side);
            size_t by = (size_t)((Y1 - 0.5 * (v[i].y0 + v[i].y1)) / side);
            key[m].block = by * (size_t)((X1 - X0) / side + 2) + bx;
            key[m++].sheet = i;
        }
    qsort(key, m, sizeof *key, cmp_bkey); /* by block, then manifest order */
    for (i = 0; i < m; i++)
        sel[i] = key[i].sheet;
    if (!(ctx = malloc(m * sizeof *ctx)) ||
        !(blk = malloc(n * sizeof *blk))) {
        free(sel), free(key), free(ctx);
        return 0;
    }
    for (i = 0; i < n; i++)
        blk[i] = SIZE_MAX;
    for (i = 0; i < m; i++)
        blk[key[i].sheet] = key[i].block;
    for (a = 0; a < m; a = b, nb++) {
        size_t nc = 0, q, t;
        for (b = a; b < m && key[b].block == key[a].block; b++)
            ;
        /* the sheets of blocks solved before that touch this block: their
         * heights are evidence here, so a contour crossing the blocks'
         * edge gets one height */
        for (q = a; q < b; q++)
            for (t = 0; t < v[sel[q]].nnb; t++) {
                size_t j = v[sel[q]].nb[t], u;
                if (blk[j] == SIZE_MAX || blk[j] >= key[a].block)
                    continue;
                for (u = 0; u < nc && ctx[u] != j; u++)
                    ;
                if (u == nc && nc < m)
                    ctx[nc++] = j;
            }
        r = b - a + nc >= 2
                ? joint_block(v, sel + a, b - a, ctx, nc, lg, quiet,
                              one && whole, one ? -1 : (long)nb, 1)
                : 0;
        ok = one ? r : ok | (r ? 1 : 0);
    }
    free(ctx), free(blk);
    /* the DEMs still from one interpolation of the whole series when it
     * fits (whole_dems' limit), the blocks' heights as they came */
    if (!one && whole && ok &&
        joint_block(v, sel, m, NULL, 0, lg, quiet, 1, -1, 0) == 2)
        ok = 2;
    if (!quiet && !one)
        fprintf(stderr, "batch: the series (%.3g cells) was labelled in %zu "
                "blocks of up to %.3g cells\n",
                (X1 - X0) / res * ((Y1 - Y0) / res), nb, cells);
    free(sel), free(key);
    return ok;
}

/* After the runs: the joint solve (o->joint), the edge matching, and each
 * sheet interpolated again (with its neighbours' lines beside it when
 * o->seams; every sheet the joint solve relabelled); overlapping sheets
 * are named in the log. */
static void seams(const char *exe, sheet *v, size_t n, const bt_opts *o,
                  FILE *lg)
{
    size_t i, any = 0;
    int relabelled;
    for (i = 0; i < n; i++)
        if (v[i].ok)
            place_sheet(&v[i]);
    if (find_neighbours(v, n, lg) != 0) {
        fputs("{\"step\": \"edges\", \"error\": \"out of memory\"}\n", lg);
        for (i = 0; i < n; i++)
            v[i].placed = 0;
    }
    relabelled =
        o->joint ? joint(v, n, lg, o->quiet, o->seams, o->joint_cells) : 0;
    match_edges(lg, v, n, o->quiet);
    for (i = 0; i < n; i++) {
        int has = o->seams && v[i].ok && v[i].nnb > 0;
        v[i].stage = 1;
        v[i].state = relabelled != 2 && (has || (relabelled && v[i].ok &&
                                                 v[i].placed)) ? 0 : 2;
        any += v[i].state == 0;
    }
    if (any)
        run_all(exe, v, n, o, lg);
}

/* ---- --emit ---- */

/* The joint step's command line (after the per-sheet jobs). */
static void joint_line(FILE *f, const char *exe, const bt_opts *o)
{
    char mg[64];
    sh_word(f, exe);
    fputs(" batch --joint-only ", f);
    sh_word(f, o->manifest);
    fputs(" --out ", f);
    sh_word(f, o->out);
    if (!o->joint)
        fputs(" --no-joint", f);
    if (!o->seams)
        fputs(" --no-seams", f);
    if (o->neighbours)
        fputs(" --neighbours", f);
    if (o->margin != 256) {
        snprintf(mg, sizeof mg, " --margin %d", o->margin);
        fputs(mg, f);
    }
    if (o->joint_cells != 1e8) {
        snprintf(mg, sizeof mg, " --joint-cells %.17g", o->joint_cells);
        fputs(mg, f);
    }
}

static int emit(const char *exe, sheet *v, size_t n, const bt_opts *o)
{
    size_t i;
    char *stamp = join(o->out, "joint.done");
    if (!stamp)
        return td_cli_failf("batch", "out of memory");
    if (o->emit == 2) { /* make: the sheets, then the joint step */
        fputs("# topodig batch --emit make: make -j N -f THIS\nall: ", stdout);
        sh_word(stdout, stamp);
        fputs("\n\n", stdout);
        sh_word(stdout, stamp);
        fputc(':', stdout);
    }
    for (i = 0; o->emit == 2 && i < n; i++) {
        fputc(' ', stdout);
        sh_word(stdout, v[i].dir);
        fputs("/dem.tif", stdout);
    }
    if (o->emit == 2) {
        fputs("\n\t", stdout);
        joint_line(stdout, exe, o);
        fputs(" && touch ", stdout);
        sh_word(stdout, stamp);
        fputs("\n", stdout);
    }
    if (o->emit == 3)
        printf("#!/bin/sh\n# topodig batch --emit slurm: sbatch THIS; when the "
               "array is done, the joint step\n# (edge matching, the series "
               "labelled as one, seams) as one job:\n#   sbatch "
               "--dependency=afterany:ARRAY_JOB_ID --wrap \"...\" with:\n#   ");
    if (o->emit == 3) {
        joint_line(stdout, exe, o);
        printf("\n#SBATCH --job-name=topodig\n#SBATCH --array=1-%zu\n"
               "case \"$SLURM_ARRAY_TASK_ID\" in\n", n);
    }
    for (i = 0; i < n; i++) {
        if (o->emit == 2) {
            fputc('\n', stdout);
            sh_word(stdout, v[i].dir);
            fputs("/dem.tif: ", stdout);
            sh_word(stdout, v[i].path);
            fputs("\n\t", stdout);
        } else if (o->emit == 3) {
            printf("%zu) ", i + 1);
        }
        if (emit_line(stdout, exe, &v[i], v[i].dir, o->neighbours) != 0) {
            free(stamp);
            return td_cli_failf("batch", "%s: too many options", v[i].path);
        }
        if (o->emit == 3)
            fputs("    ;;\n", stdout);
    }
    if (o->emit == 3)
        fputs("esac\n", stdout);
    free(stamp);
    return 0;
}

int td_cmd_batch(int argc, char **argv)
{
    bt_opts o;
    sheet *v = NULL;
    size_t n = 0, i, failed = 0;
    char exe[PATH_MAX], *logp = NULL;
    ssize_t el;
    FILE *lg = NULL;
    int rc;
    memset(&o, 0, sizeof o);
    o.jobs = 1;
    o.seams = 1;
    o.joint = 1;
    o.margin = 256;
    o.joint_cells = 1e8;
    if ((rc = parse_args(argc, argv, &o)) != 0)
        return rc == 2 ? 0 : 1;
    if ((el = readlink("/proc/self/exe", exe, sizeof exe - 1)) <= 0)
        return td_cli_failf("batch", "cannot find this program's path");
    exe[el] = 0;
    if ((rc = read_manifest(o.manifest, &v, &n)) != 0)
        goto done;
    for (i = 0; i < n; i++) {
        if (!(v[i].dir = join(o.out, v[i].stem))) {
            rc = td_cli_failf("batch", "out of memory");
            goto done;
        }
        if (!o.emit && hash_sheet(&v[i], TD_VERSION) != 0)
            v[i].hash = 0; /* unreadable: run reports it */
    }
    if (o.emit) {
        rc = emit(exe, v, n, &o);
        goto done;
    }
    if (mkdir_p(o.out) != 0 || !(logp = join(o.out, "batch.log")) ||
        !(lg = fopen(logp, "w"))) {
        rc = td_cli_failf("batch", "%s: cannot write (%s)", o.out,
                          strerror(errno));
        goto done;
    }
    {
        struct sigaction sa;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = on_signal; /* no SA_RESTART: wait() returns */
        sigemptyset(&sa.sa_mask);
        sigaction(SIGINT, &sa, NULL);
        sigaction(SIGTERM, &sa, NULL);
    }
    if (o.joint_only) /* the sheets whose run left its outputs */
        for (i = 0; i < n; i++) {
            char *d = join(v[i].dir, "dem.tif"), *l = join(v[i].dir,
                                                           "lines.geojson");
            struct stat st;
            v[i].state = 2;
            v[i].ok = d && l && stat(d, &st) == 0 && stat(l, &st) == 0;
            free(d), free(l);
        }
    else
        run_all(exe, v, n, &o, lg);
    if (o.neighbours && !bt_stop) /* also after emitted jobs: the joint
                                     step seeds */
        seed_passes(exe, v, n, &o, lg);
    if (!bt_stop)
        seams(exe, v, n, &o, lg); /* the edge matching always; the joint
                                     solve and the seams unless turned off */
    if (bt_stop) {
        if (!o.quiet)
            fprintf(stderr, "batch: interrupted; --resume goes on from "
                    "here\n");
        rc = 128 + (int)bt_stop;
        goto done;
    }
    for (i = 0; i < n; i++)
        failed += !v[i].ok;
    if (!o.quiet)
        fprintf(stderr, "batch: %zu sheets, %zu failed; log in %s\n", n, failed,
                logp);
    rc = failed ? 1 : 0;
done:
    if (lg)
        fclose(lg);
    free(logp);
    free_sheets(v, n);
    return bt_stop ? 128 + (int)bt_stop : rc ? 1 : 0;
}
