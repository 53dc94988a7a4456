/* bench_heights: height accuracy of the labeller on sheets drawn from real
 * DEMs (../shared/dems) and the generator's terrains, clean, scanned, in colour
 * printed (tdgen --print) or printed new (--unfaded), with three known points
 * (alone, with the index contours' widths every 5th, or as `run --interval
 * --known` x3 takes them: the printed labels read too and the widths'
 * spacing picked by the solve, "3 known+lab"), or the labels alone (no
 * option at all, "labels only"); the share of traced line
 * length with the right height (td_match_heights), lines wrong with confidence
 * >= 0.9, where heights came from, and the labelling time.  Numbers for
 * docs/benchmarks.md.
 *
 *   bench_heights [--dems DIR] [--only NAME] [--tree] [--search N] [--log]
 *                 [--all-hints] [--png DIR] [--streams] [--no-vees]
 *                 [--no-stream-joins] [--gap-pairs PX] [--oracle]
 *                 [--oracle-box X0,Y0,X1,Y1] [--oracle-ties N] [--steps]
 *                 [--detint] [--spots N]
 *
 * --detint: the scanner divides the colour sheets' tints out (scan
 * --detint, scanner/detint.h); --spots N: up to N spot heights drawn on
 * the scanned, colour and printed sheets (tdgen --spot-heights; real
 * maps carry them, docs/label.md "Spot heights");
 * --streams: the colour sheets' water drawn from the terrain (tdgen
 * --streams) instead of the random river; --no-vees: the streams' Vs not
 * read (scanner/streams.h); --no-stream-joins: the joiner's stage 3 (across
 * the water) off; --gap-pairs PX: the labeller's free-end pairs at PX
 * (td_label_params.gap_pairs, endpair.h; default: the labeller's, 24 on
 * colour scans, off on grey; -1: off everywhere); --oracle: each traced row
 * also prices the true heights under the labeller's whole model (each
 * traced line's majority contour, its up side from the true surface):
 * an answer dearer than the truth is the optimiser's error, a cheaper
 * one the model's; and the parts of both (td_oracle_term: where the truth
 * pays more than the answer, the model's weights are worth a look);
 * --oracle-box X0,Y0,X1,Y1: the same with the true heights only on the
 * lines wholly inside the box (scan pixels), the answer's elsewhere: one
 * region's price; --oracle-ties N (with --oracle or --oracle-box): the
 * N ties the answer and the truth pay most differently (a face edge, a
 * fold, a continuity tie, a line's own term: td_oracle_tie), each with
 * the two lines at its ends (ids, positions), those that favour the
 * answer marked "<": where the model prefers a wrong region, what holds
 * it there; --steps: the labeller's step edges (the scan's
 * skeleton, td_label_params.skeleton; off by default). */
#include "tests/util/bench.h"
#include "tests/util/hsheet.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct sheet_case {
    const char *name, *dem; /* dem NULL: analytic terrain */
    td_gen_terrain_kind terrain;
    double scale, interval;
    int size;
} sheet_case;

static const sheet_case cases[] = {
    {"elkhorn", "elkhorn_srtm3.tif", TD_GEN_DEM, 6, 0, 0},
    {"frontrange", "frontrange_srtm3.tif", TD_GEN_DEM, 10, 0, 0},
    {"orkhon", "orkhon_92m.tif", TD_GEN_DEM, 10, 0, 0},
    {"frontrange20", "frontrange_srtm3.tif", TD_GEN_DEM, 10, 20, 0},
    /* held out (2026-12-04, session 15): drawn at other scales and
       intervals, not tuned on */
    {"elkhorn20", "elkhorn_srtm3.tif", TD_GEN_DEM, 6, 20, 0},
    {"orkhon50", "orkhon_92m.tif", TD_GEN_DEM, 10, 50, 0},
    {"frontrange25", "frontrange_srtm3.tif", TD_GEN_DEM, 8, 25, 0},
    {"cone", NULL, TD_GEN_CONE, 0, 0, 800},
    {"hills", NULL, TD_GEN_HILLS, 0, 0, 1500},
    {"ridges", NULL, TD_GEN_RIDGES, 0, 0, 2000},
};

static const char usage[] =
    "usage: bench_heights [--dems DIR] [--only NAME] [--tree] [--search N]\n"
    "                     [--log] [--all-hints] [--png DIR] [--streams]\n"
    "                     [--no-vees] [--no-stream-joins] [--gap-pairs PX]\n"
    "                     [--oracle] [--oracle-box X0,Y0,X1,Y1]\n"
    "                     [--oracle-ties N] [--steps]\n"
    "                     [--detint] [--hachures]\n"
    "                     [--paper-junctions] [--spots N]\n";

static const char *const scan_name[6] = {"truth",  "clean",   "scanned",
                                         "colour", "printed", "new"};
static const char *const hint_name[4] = {"3 known", "3 known+index",
                                         "labels only", "3 known+lab"};

static int tie_order(const void *pa, const void *pb)
{
    const td_oracle_tie *a = pa, *b = pb;
    double da = fabs(a->truth - a->answer), db = fabs(b->truth - b->answer);
    return da > db ? -1 : da < db;
}

/* The n ties the answer and the truth pay most differently, those with
 * an end in the box (x1 <= x0: all); "<" where the answer pays less. */
static void print_ties(td_label_report *r, const double *box, int n)
{
    static const char *const part[TD_OT_N] = {"",     "face",  "fold",  "nest",
                                              "cont", "index", "label", "known",
                                              "dir",  "unary"};
    size_t i;
    int shown = 0;
    qsort(r->oracle_ties, r->noracle_ties, sizeof *r->oracle_ties, tie_order);
    for (i = 0; i < r->noracle_ties && shown < n; i++) {
        const td_oracle_tie *t = &r->oracle_ties[i];
        int k, in = !(box[2] > box[0]);
        for (k = 0; k < 2; k++)
            in |= t->x[k] >= box[0] && t->x[k] < box[2] && t->y[k] >= box[1] &&
                  t->y[k] < box[3];
        if (!in)
            continue;
        printf("%-11s     %c %-5s answer %6.1f truth %6.1f  line %ld at "
               "%.0f,%.0f  line %ld at %.0f,%.0f\n",
               "", t->answer < t->truth ? '<' : '>', part[t->term], t->answer,
               t->truth, t->id[0], t->x[0], t->y[0], t->id[1], t->x[1],
               t->y[1]);
        shown++;
    }
}

int main(int argc, char **argv)
{
    const char *dir = "tests/data/dems", *only = NULL, *png = NULL;
    int tree = 0, logit = 0, paperj = 0, all = 0, search = 0, hach = 0, a;
    int streams = 0, novees = 0, nojoins = 0, detint = 0;
    double gap_pairs = 0;
    int oracle = 0, spots = 0, steps = 0, nties = 0;
    double obox[4] = {0, 0, 0, 0};
    size_t c;
    for (a = 1; a < argc; a++) {
        if (!strcmp(argv[a], "--dems") && a + 1 < argc)
            dir = argv[++a];
        else if (!strcmp(argv[a], "--only") && a + 1 < argc)
            only = argv[++a];
        else if (!strcmp(argv[a], "--tree"))
            tree = 1;
        else if (!strcmp(argv[a], "--search") && a + 1 < argc)
            search = atoi(argv[++a]) ? atoi(argv[a]) : -1; /* 0: off */
        else if (!strcmp(argv[a], "--streams"))
            streams = 1;
        else if (!strcmp(argv[a], "--oracle"))
            oracle = 1;
        else if (!strcmp(argv[a], "--oracle-ties") && a + 1 < argc) {
            if ((nties = atoi(argv[++a])) <= 0)
                return td_bench_usage("bench_heights", argv[a], usage);
        } else if (!strcmp(argv[a], "--steps"))
            steps = 1;
        else if (!strcmp(argv[a], "--oracle-box") && a + 1 < argc) {
            if (sscanf(argv[++a], "%lf,%lf,%lf,%lf", &obox[0], &obox[1],
                       &obox[2], &obox[3]) != 4 ||
                !(obox[2] > obox[0] && obox[3] > obox[1]))
                return td_bench_usage("bench_heights", argv[a], usage);
            oracle = 1;
        } else if (!strcmp(argv[a], "--detint"))
            detint = 1;
        else if (!strcmp(argv[a], "--gap-pairs") && a + 1 < argc)
            gap_pairs = atof(argv[++a]);
        else if (!strcmp(argv[a], "--no-vees"))
            novees = 1;
        else if (!strcmp(argv[a], "--no-stream-joins"))
            nojoins = 1;
        else if (!strcmp(argv[a], "--hachures"))
            hach = 1;
        else if (!strcmp(argv[a], "--spots") && a + 1 < argc)
            spots = atoi(argv[++a]); /* spot heights on the scanned kinds */
        else if (!strcmp(argv[a], "--paper-junctions"))
            paperj = 1;
        else if (!strcmp(argv[a], "--log"))
            logit = 1;
        else if (!strcmp(argv[a], "--all-hints"))
            all = 1; /* colour sheets with 3 known points alone too */
        else if (!strcmp(argv[a], "--png") && a + 1 < argc)
            png = argv[++a];
        else if ((!strcmp(argv[a], "--topodig") || !strcmp(argv[a], "--dir")) &&
                 a + 1 < argc)
            a++; /* make bench's common options */
        else
            return td_bench_usage("bench_heights", argv[a], usage);
    }
    if (png && td_bench_outdir("bench_heights", png) != 0)
        return 1;
    printf("%-11s %-7s %-13s %6s %6s %6s  %5s %5s %5s %5s %5s  %5s %6s "
           "%5s %9s %5s %5s %7s\n",
           "sheet", "scan", "hints", "lines", "acc", "null", "known", "solvd",
           "assum", "none", "sure!", "confl", "secs", "own", "labels", "intvl",
           "sure", "hrmse");
    for (c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        const sheet_case *k = &cases[c];
        td_grid_f32 *src = NULL;
        td_ctx cx;
        int scanned, hint;
        char path[512];
        if (only && strcmp(only, k->name))
            continue;
        td_ctx_init(&cx);
        if (k->dem) {
            snprintf(path, sizeof path, "%s/%s", dir, k->dem);
            if (td_hsheet_load_dem(path, &src, &cx) != 0) {
                printf("%-11s (skipped: %s)\n", k->name, td_errmsg(&cx));
                continue;
            }
        }
        for (scanned = 0; scanned < 6; scanned++)
            for (hint = 0; hint < 4; hint++) {
                td_hsheet hs;
                memset(&hs, 0, sizeof hs);
                hs.gp = td_gen_defaults();
                hs.gp.terrain = k->terrain;
                hs.gp.dem_in = src;
                hs.gp.interval = k->interval;
                if (src) {
                    hs.gp.w = (int)(src->w * k->scale);
                    hs.gp.h = (int)(src->h * k->scale);
                } else {
                    hs.gp.w = hs.gp.h = k->size;
                }
                td_hsheet_defects(&hs.gp, scanned >= 2 ? scanned - 1 : 0);
                hs.gp.hachures = hach;
                hs.gp.spots = scanned >= 2 ? spots : 0;
                hs.gp.streams = streams && hs.gp.colour;
                hs.no_vees = novees;
                hs.no_stream_joins = nojoins;
                hs.use_truth_lines = scanned == 0;
                if (hint >= 2 && scanned < 2)
                    continue; /* labels: on the scanned sheets (3 known
                                 + labels: `run --interval I --known` x3,
                                 the labels read too and the widths'
                                 spacing the solve's) */
                if (scanned >= 3 && hint == 0 && !all)
                    continue; /* colour, printed: with index widths and
                                 labels */
                hs.nknown = hint == 2 ? 0 : 3;
                hs.index_every = hint == 1 ? 5 : hint == 3 ? -1 : 0;
                hs.read_labels = hint >= 2;
                hs.no_interval = hint == 2;
                hs.method = tree ? TD_LABEL_TREE : TD_LABEL_FACES;
                hs.paper_junctions = paperj;
                hs.search = search;
                hs.detint = detint;
                hs.gap_pairs = gap_pairs;
                hs.oracle = oracle;
                hs.oracle_ties = oracle && nties > 0;
                hs.steps = steps;
                memcpy(hs.oracle_box, obox, sizeof obox);
                if (png) {
                    snprintf(path, sizeof path, "%s/%s_%d_%d.png", png, k->name,
                             scanned, hint);
                    hs.png = path;
                }
                if (td_hsheet_run(&hs, logit ? stdout : NULL, &cx) != 0) {
                    printf("%-11s %-7s %-13s failed: %s\n", k->name,
                           scan_name[scanned], hint_name[hint], td_errmsg(&cx));
                    td_ctx_clear(&cx);
                    td_label_report_free(&hs.rep);
                    continue;
                }
                printf("%-11s %-7s %-13s %6zu %6.3f %6.3f  %5zu %5zu %5zu "
                       "%5zu %5ld  %5zu %6.2f %5.3f %4zu/%-4zu %5g %5.3f "
                       "%7.2f\n",
                       k->name, scan_name[scanned], hint_name[hint], hs.traced,
                       hs.score.accuracy,
                       hs.score.null_len / (hs.score.right + hs.score.wrong +
                                            hs.score.null_len + 1e-9),
                       hs.rep.by_source[TD_HS_KNOWN] +
                           hs.rep.by_source[TD_HS_LABEL],
                       hs.rep.by_source[TD_HS_SOLVED],
                       hs.rep.by_source[TD_HS_ASSUMED], hs.rep.undetermined,
                       hs.score.n_wrong_sure, hs.rep.conflicts, hs.label_secs,
                       hs.score.own / (hs.score.right + hs.score.wrong +
                                       hs.score.null_len + 1e-9),
                       hs.reads_right, hs.nreads, hs.interval,
                       hs.score.right_sure / (hs.score.right + hs.score.wrong +
                                              hs.score.null_len + 1e-9),
                       td_hscore_rmse(&hs.score));
                if (oracle && hs.rep.oracle_cost[1][0] > 0)
                    printf("%-11s   oracle: the answer costs %.0f (broken "
                           "face edges %.0f), the true heights %.0f (%.0f)"
                           ": %s\n",
                           "", hs.rep.oracle_cost[0][0],
                           hs.rep.oracle_cost[0][1], hs.rep.oracle_cost[1][0],
                           hs.rep.oracle_cost[1][1],
                           hs.rep.oracle_cost[0][0] >
                                   hs.rep.oracle_cost[1][0] + 1e-6
                               ? "the optimiser's error"
                               : "the model prefers the answer");
                if (oracle && hs.rep.oracle_cost[1][0] > 0) {
                    static const char *const part[TD_OT_N] = {
                        "",      "faces",  "folds", "nests", "cont",
                        "index", "labels", "known", "dirs",  "unary"};
                    int t;
                    printf("%-11s   parts (answer / truth):", "");
                    for (t = 1; t < TD_OT_N; t++)
                        printf(" %s %.0f/%.0f", part[t],
                               hs.rep.oracle_cost[0][t],
                               hs.rep.oracle_cost[1][t]);
                    printf("\n");
                }
                if (hs.oracle_ties)
                    print_ties(&hs.rep, obox, nties);
                if (logit && hs.rep.text)
                    printf("%s\n", hs.rep.text);
                fflush(stdout);
                td_label_report_free(&hs.rep);
            }
        td_grid_f32_free(src);
    }
    return 0;
}
