/* bench_quality: how well each scanner variant recovers the true contours
 * of generated sheets: the paper's methods against the improvements beside
 * them (spur rule, 5x5 bridging, gap joining).  Numbers for docs/scanner.md.
 *
 * For every sheet (hills terrain, 1000 x 800, line widths 2/4/6 px, 30
 * breaks of 1-4 px, 30 specks, 5 seeds; clean (noise 8) and rough (noise
 * 40 after a blur of 1 px, which leaves ragged edges and pinholes in the
 * ink)) and every variant it sums:
 * truth lines matched (coverage >= 99 %, mean distance <= 1.5 px), split
 * (in more than one traced piece), mixed traced lines, wrong closed flags,
 * and the total traced length coverage. */
#include "samples/gen/gen.h"
#include "scanner/scan.h"
#include "tests/util/match.h"

#include <stdio.h>
#include <string.h>

typedef struct variant {
    const char *name;
    td_spur_mode spur;
    int bridge, join;
} variant;

static const variant variants[] = {
    {"paper: spur paper, 5x5 bridge, no join", TD_SPUR_PAPER, 1, 0},
    {"spur length, 5x5 bridge, no join", TD_SPUR_LENGTH, 1, 0},
    {"spur paper, 5x5 bridge, join", TD_SPUR_PAPER, 1, 1},
    {"default: spur length, 5x5 bridge, join", TD_SPUR_LENGTH, 1, 1},
    {"spur length, no bridge, join", TD_SPUR_LENGTH, 0, 1},
};

typedef struct tally {
    long truth, matched, split, mixed, closed_wrong, noise;
    double cov;
    int n;
} tally;

static int one(const td_gen_params *gp, const variant *v, tally *t,
               td_ctx *cx)
{
    td_image *im = NULL;
    td_lines *truth = NULL;
    td_scan_params sp = td_scan_defaults();
    td_scan_result res;
    td_match_report r;
    int rc;
    sp.spur.mode = v->spur;
    sp.trace.bridge = v->bridge;
    sp.do_join = v->join;
    if ((rc = td_gen_sheet(gp, &im, &truth, NULL, cx)) != 0)
        return rc;
    if ((rc = td_scan(im, &sp, &res, cx)) == 0) {
        rc = td_match_lines(truth, res.lines, im->w, im->h, NULL, &r, NULL);
        t->truth += r.n_truth;
        t->matched += r.n_matched;
        t->split += r.n_split;
        t->mixed += r.n_mixed;
        t->closed_wrong += r.n_closed_wrong;
        t->noise += r.n_unmatched_traced;
        t->cov += r.cov_total;
        t->n++;
        td_scan_result_free(&res);
    }
    td_lines_free(truth);
    td_image_free(im);
    return rc;
}

int main(void)
{
    static const double widths[] = {2.0, 4.0, 6.0};
    size_t wi, vi, ni;
    td_ctx cx;
    td_ctx_init(&cx);
    printf("scan quality on generated sheets (1000x800 hills, 30 breaks of "
           "1-4 px, 30 specks, 5 seeds per row)\n");
    for (ni = 0; ni < 2; ni++)
    for (wi = 0; wi < 3; wi++) {
        printf("  line width %.0f px, %s\n", widths[wi],
               ni ? "rough (noise 40, blur 1)" : "clean (noise 8)");
        printf("    %-42s %9s %6s %6s %7s %6s %8s\n", "variant", "matched",
               "split", "mixed", "closed!", "noise", "coverage");
        for (vi = 0; vi < sizeof variants / sizeof *variants; vi++) {
            tally t;
            unsigned seed;
            memset(&t, 0, sizeof t);
            for (seed = 21; seed < 26; seed++) {
                td_gen_params gp = td_gen_defaults();
                gp.w = 1000;
                gp.h = 800;
                gp.seed = seed;
                gp.line_width = widths[wi];
                gp.breaks = 30;
                gp.break_min = 1;
                gp.break_max = 4;
                gp.noise = ni ? 40 : 8;
                gp.blur = ni ? 1.0 : 0.0;
                gp.specks = 30;
                if (one(&gp, &variants[vi], &t, &cx) != 0) {
                    printf("    failed: %s\n", td_errmsg(&cx));
                    td_ctx_clear(&cx);
                }
            }
            printf("    %-42s %4ld/%-4ld %6ld %6ld %7ld %6ld %8.4f\n",
                   variants[vi].name, t.matched, t.truth, t.split, t.mixed,
                   t.closed_wrong, t.noise, t.n ? t.cov / t.n : 0.0);
        }
    }
    return 0;
}
