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
 * The exit code is 0 when every sheet succeeded. */
#include "src/cli/cli.h"

#include "src/io/io.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
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
} sheet;

typedef struct bt_opts {
    const char *manifest, *out;
    int jobs, resume, emit, quiet, neighbours;
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
            free(v[i].seeded);
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
static int emit_line(FILE *f, const char *exe, const sheet *s, const char *dir)
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
    fputs(" 2>&1\n", f);
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

static pid_t start(const char *exe, sheet *s)
{
    char *av[MAX_ARGS], buf[4096], *dem = join(s->dir, "dem.tif"),
         *lines = join(s->dir, "lines.geojson"),
         *sum = join(s->dir, "summary.json"), *dbg = join(s->dir, "debug"),
         *log = join(s->dir, "run.log");
    pid_t pid = -1;
    int fd;
    if (!dem || !lines || !sum || !dbg || !log ||
        run_argv(exe, s, av, buf, sizeof buf) < 0)
        goto done;
    av[4] = dem, av[6] = lines, av[8] = sum, av[10] = dbg;
    unlink(sum); /* a stale summary would read as this run's */
    fflush(NULL);
    pid = fork();
    if (pid == 0) {
        fd = open(log, O_WRONLY | O_CREAT | O_TRUNC, 0666);
        if (fd >= 0) {
            dup2(fd, 1), dup2(fd, 2);
            close(fd);
        }
        execv(exe, av);
        _exit(127);
    }
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

/* Run the waiting sheets, jobs at a time. */
static void run_all(const char *exe, sheet *v, size_t n, const bt_opts *o,
                    FILE *lg)
{
    size_t next = 0, running = 0, i, total = 0, done = 0;
    for (i = 0; i < n; i++)
        total += v[i].state == 0;
    while (done < total) {
        while (running < (size_t)o->jobs && next < n) {
            sheet *s = &v[next++];
            if (s->state != 0)
                continue;
            if (o->resume && !s->seeded && up_to_date(s)) {
                s->state = 2, s->ok = 1, done++;
                log_sheet(lg, s, "skipped", 0, 0);
                continue;
            }
            if (mkdir_p(s->dir) != 0 || (s->pid = start(exe, s)) < 0) {
                s->state = 2, s->ok = 0, done++;
                log_sheet(lg, s, "failed", 0, -1);
                continue;
            }
            s->state = 1, s->t0 = td_now(), running++;
        }
        if (running > 0) {
            int status;
            pid_t pid = wait(&status);
            for (i = 0; pid > 0 && i < n; i++)
                if (v[i].state == 1 && v[i].pid == pid) {
                    int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128;
                    v[i].state = 2, v[i].ok = code == 0, done++, running--;
                    if (code == 0)
                        write_hash(&v[i]);
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
    for (pass = 0; pass < 8 && more; pass++) {
        more = 0;
        for (i = 0; i < n; i++)
            if (!v[i].ok && !v[i].seeded && v[i].state == 2 &&
                seedable(&v[i]) && seed_sheet(&v[i], v, n))
                v[i].state = 0, more = 1;
        if (more)
            run_all(exe, v, n, o, lg);
    }
}

/* ---- --emit ---- */

static int emit(const char *exe, sheet *v, size_t n, const bt_opts *o)
{
    size_t i;
    if (o->emit == 2) /* make */
        fputs("# topodig batch --emit make: make -j N -f THIS\nall:", stdout);
    for (i = 0; o->emit == 2 && i < n; i++) {
        fputc(' ', stdout);
        sh_word(stdout, v[i].dir);
        fputs("/dem.tif", stdout);
    }
    if (o->emit == 2)
        fputs("\n", stdout);
    if (o->emit == 3)
        printf("#!/bin/sh\n# topodig batch --emit slurm: sbatch THIS\n"
               "#SBATCH --job-name=topodig\n#SBATCH --array=1-%zu\n"
               "case \"$SLURM_ARRAY_TASK_ID\" in\n", n);
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
        if (emit_line(stdout, exe, &v[i], v[i].dir) != 0)
            return td_cli_failf("batch", "%s: too many options", v[i].path);
        if (o->emit == 3)
            fputs("    ;;\n", stdout);
    }
    if (o->emit == 3)
        fputs("esac\n", stdout);
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
    run_all(exe, v, n, &o, lg);
    if (o.neighbours)
        seed_passes(exe, v, n, &o, lg);
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
    return rc ? 1 : 0;
}
