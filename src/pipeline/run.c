/* run.c: a scanned sheet -> traced lines -> heights -> DEM in memory, the
 * pipeline of `topodig run` and of a batch's per-sheet job: the same
 * stages and checks as scan, label (crossings, index widths) and interp. */
#include "src/pipeline/pipeline.h"

#include "scanner/widecut.h"

#include <stdlib.h>
#include <string.h>

/* See pipeline.h. */
td_run_params td_run_defaults(void)
{
    td_run_params p;
    memset(&p, 0, sizeof p);
    p.scan = td_scan_defaults();
    p.read_labels = 1;
    p.read_streams = 1;
    p.walls_back = 1;
    p.bridge = -1;
    p.label = td_label_defaults();
    p.interp = td_interp_defaults();
    return p;
}

/* Scan; keeps only the lines (the image and the scanner's grids are freed
 * before interpolation so they never share the peak). */
static int do_scan(const char *path, const td_run_params *p, td_run_result *r,
                   td_ctx *cx)
{
    td_image *im = NULL;
    td_scan_result res;
    td_scan_params sp = p->scan;
    double t0 = td_now();
    int rc;
    memset(&res, 0, sizeof res);
    if ((rc = td_image_read(path, &im, &r->geo, cx)) != 0)
        return rc;
    r->w = im->w;
    r->h = im->h;
    sp.join.record = p->read_labels; /* where the labels are */
    sp.skel_bits = p->steps;
    if ((rc = td_scan(im, &sp, &res, cx)) == 0 && p->read_labels) {
        double t1 = td_now();
        td_ocr_params op = td_ocr_defaults();
        op.ink = &res.palette; /* labels on a tint read in the ink */
        rc = td_ocr_scan_labels(im, res.lines, &res.join, NULL, &op, &r->reads,
                                &r->nreads, cx);
        if (rc == 0) {
            td_ocr_drop_digits(res.lines, r->reads, r->nreads);
            td_ocr_drop_dots(res.lines, res.join.text, r->reads, r->nreads);
        }
        r->ocr_secs = td_now() - t1;
    }
    if (rc == 0 && p->read_streams)
        rc = td_streams_vees(im, &res.palette, res.lines, res.join.cross_at,
                             res.join.cross_joins, &r->vees, &r->nvees, cx);
    if (rc == 0) {
        r->lines = res.lines;
        res.lines = NULL;
        r->walls = res.walls;
        res.walls = NULL;
        r->skel = res.skel_bits;
        res.skel_bits = NULL;
        r->traced = r->lines->n;
        r->pal = res.palette;
    }
    td_scan_result_free(&res);
    if (p->keep_scan && rc == 0)
        r->scan = im;
    else
        td_image_free(im);
    r->secs[0] = td_now() - t0;
    return rc;
}

/* What label checks before it solves and after: crossings (counted and
 * warned), index widths against heights. */
static int checks(td_run_result *r, const td_label_params *lp, td_ctx *cx)
{
    td_crossing *v = NULL;
    int rc = td_contain_crossings(r->lines, &v, &r->ncross, cx);
    free(v);
    if (rc == 0 && lp->index_every > 0)
        rc = td_label_check_index(r->lines, lp, &r->checks, cx);
    return rc;
}

/* The labeller refused (its error in cx): on_refused sees the lines, all
 * without a height (td_label_auto), and the labels read; the labeller's
 * error stands. */
static int refused(const td_run_params *p, td_run_result *r, td_ctx *cx)
{
    char msg[sizeof cx->msg];
    snprintf(msg, sizeof msg, "%s", td_errmsg(cx));
    p->on_refused(r, p->user);
    return td_seterr(cx, TD_EINVAL, "%s", msg);
}

/* Label; then the callback sees every line, and the lines left without a
 * height are dropped. */
static int do_label(const td_run_params *p, td_run_result *r, td_ctx *cx)
{
    td_label_params lp = p->label;
    double t0 = td_now();
    size_t i;
    int rc, tree = lp.method == TD_LABEL_TREE;
    lp.labels = r->reads;
    lp.nlabels = tree ? 0 : r->nreads;
    lp.vees = r->vees;
    lp.nvees = tree ? 0 : r->nvees;
    lp.walls = r->walls;
    lp.skeleton = r->skel;
    lp.colour = r->pal.n > 0; /* gap_pairs < 0: on for colour scans */
    lp.w = r->w;
    lp.h = r->h;
    if (lp.nknown == 0 && lp.nlabels == 0)
        return td_seterr(cx, TD_EINVAL, "no heights to start from: %s; give "
                         "--known X,Y,H (a point on a contour, or a spot "
                         "height)%s", !p->read_labels ? "--labels none"
                         : "no printed height label could be read",
                         lp.interval > 0 ? "" : " and --interval I");
    if (!(lp.interval > 0) && (tree || lp.nlabels == 0))
        return td_seterr(cx, TD_EINVAL, "no interval: give --interval I%s",
                         tree ? "" : " (no printed labels to infer it from)");
    if ((rc = td_label_auto(r->lines, &lp, &r->rep, cx)) == TD_EINVAL &&
        p->on_refused)
        return refused(p, r, cx);
    if (rc != 0 ||
        (!tree && (rc = td_label_close_gaps(r->lines, r->reads, r->nreads,
                                            &r->rep.gaps_closed, cx)) != 0))
        return rc;
    if (!(lp.interval > 0))
        lp.interval = r->rep.interval;
    if ((rc = checks(r, &lp, cx)) != 0)
        return rc;
    if (p->walls_back) { /* the cut stretches whose sides agree */
        long nr = td_walls_restore(r->lines, r->walls, cx);
        if (nr < 0)
            return (int)nr;
        r->walls_back = (size_t)nr;
    }
    /* lines cut where two contours ran as one */
    r->traced = r->lines->n - r->walls_back;
    r->bridge =
        p->bridge >= 0 ? p->bridge : td_label_bridge_reach(r->rep.spacing);
    if (!tree && r->bridge > 0 &&
        (rc = td_label_close_breaks(r->lines, r->w, r->h, r->bridge, r->reads,
                                    r->nreads, &r->breaks_closed, cx)) != 0)
        return rc;
    if (p->on_labelled && (rc = p->on_labelled(r, p->user)) != 0)
        return rc;
    td_image_free(r->scan); /* the pictures are drawn */
    r->scan = NULL;
    for (i = r->lines->n; i-- > 0;)
        if (!r->lines->v[i].has_height) {
            td_lines_remove(r->lines, i);
            r->dropped++;
        }
    td_lines_free(r->walls);
    r->walls = NULL;
    free(r->skel);
    r->skel = NULL;
    r->secs[1] = td_now() - t0;
    if (r->lines->n == 0)
        return td_seterr(cx, TD_EINVAL, "no traced line could be labelled "
                         "from the known points");
    return 0;
}

static int do_interp(const td_run_params *p, td_run_result *r, td_ctx *cx)
{
    td_interp_params ip = p->interp;
    double t0 = td_now();
    int rc;
    ip.interval = r->rep.interval > 0 ? r->rep.interval : p->label.interval;
    ip.hstats = &r->hs;
    ip.undetermined = &r->undetermined;
    /* the lines go once they are rasterised: the run's peak is here */
    if ((rc = td_interp_lines_take(&r->lines, r->w, r->h, &ip, &r->dem,
                                   cx)) != 0)
        return rc;
    td_georef_scale(&r->geo, ip.step);
    r->secs[2] = td_now() - t0;
    return 0;
}

/* See pipeline.h. */
int td_pipeline_run(const char *path, const td_run_params *p,
                    td_run_result *r, td_ctx *cx)
{
    int rc;
    memset(r, 0, sizeof *r);
    td_georef_init(&r->geo);
    if ((rc = do_scan(path, p, r, cx)) == 0 &&
        (rc = do_label(p, r, cx)) == 0)
        rc = do_interp(p, r, cx);
    return rc;
}

/* See pipeline.h. */
void td_run_result_free(td_run_result *r)
{
    if (!r)
        return;
    td_grid_f32_free(r->dem);
    td_lines_free(r->lines);
    td_lines_free(r->walls);
    free(r->skel);
    td_label_report_free(&r->rep);
    td_label_report_free(&r->checks);
    td_image_free(r->scan);
    free(r->reads);
    free(r->vees);
    td_georef_clear(&r->geo);
    memset(r, 0, sizeof *r);
}
