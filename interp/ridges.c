/* ridges.c: the ridge/valley driver (orient -> curves -> points -> links
 * and trees), the links chained into paths, and their GeoJSON writer. */
#include "homotopy_int.h"

#include "../src/imageio.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void td_ridges_free(td_ridges *r)
{
    size_t i;
    if (!r)
        return;
    for (i = 0; i < r->ncurve; i++)
        hm_curve_free(&r->curve[i]);
    free(r->curve);
    free(r->pt);
    free(r->link);
    free(r->cparent);
    free(r);
}

static int check_lines(const td_lines *ls, const td_homotopy_params *p,
                       td_ctx *cx)
{
    size_t i;
    if (!ls || ls->n == 0)
        return td_seterr(cx, TD_EINVAL, "no contour lines");
    if (!(p->spacing > 0) || !(p->smooth >= 0) || !(p->epsilon >= 0) ||
        !(p->link_factor > 0) || !(p->join_factor >= 1))
        return td_seterr(cx, TD_EINVAL, "homotopy: bad parameters");
    for (i = 0; i < ls->n; i++)
        if (!ls->v[i].has_height || !isfinite(ls->v[i].height))
            return td_seterr(cx, TD_EINVAL, "line %ld has no height (run "
                             "topodig label first)", ls->v[i].id);
    return 0;
}

/* Curves (in parallel, one line each) and their points. */
static int curves(td_ridges *r, const td_lines *ls, const int *orient,
                  const td_homotopy_params *p, td_ctx *cx)
{
    size_t i, cap = 0;
    long k;
    int rc = 0, bad = 0;
#pragma omp parallel for schedule(dynamic, 4) reduction(| : bad)
    for (k = 0; k < (long)ls->n; k++) /* independent: one line each */
        bad |= hm_curve_build(&ls->v[k], k, orient[k], p, &r->curve[k],
                              NULL) != 0;
    if (bad)
        return td_seterr(cx, TD_ENOMEM, "out of memory");
    for (i = 0; i < ls->n && rc == 0; i++)
        rc = hm_points(r, i, p, &cap, cx);
    return rc;
}

int hm_find(const td_lines *ls, int w, int h, const td_homotopy_params *p,
            td_ridges **out, td_contain *ct, int32_t *lab, td_ctx *cx)
{
    td_ridges *r = NULL;
    int *orient = NULL, rc;
    *out = NULL;
    if ((rc = check_lines(ls, p, cx)) != 0 ||
        (rc = td_check_dims(w, h, "sheet", cx)) != 0)
        return rc;
    rc = TD_ENOMEM;
    if (!(r = td_calloc(1, sizeof *r, cx)) ||
        !(r->curve = td_calloc(ls->n, sizeof *r->curve, cx)) ||
        !(r->cparent = td_malloc(ls->n * sizeof *r->cparent, cx)) ||
        !(orient = td_malloc(ls->n * sizeof *orient, cx)))
        goto fail;
    r->ncurve = ls->n;
    if ((rc = td_contain_build(ls, w, h, ct, cx)) != 0)
        goto fail;
    memcpy(r->cparent, ct->parent, ls->n * sizeof *r->cparent);
    hm_orient(ls, ct, orient);
    if ((rc = td_progress(cx, "ridges", 0.1)) != 0 ||
        (rc = curves(r, ls, orient, p, cx)) != 0 ||
        (rc = td_progress(cx, "ridges", 0.4)) != 0 ||
        (rc = hm_label(ct, w, h, 1.0, lab, cx)) != 0 ||
        (rc = td_progress(cx, "ridges", 0.7)) != 0 ||
        (rc = hm_link(r, ct, lab, w, h, p, cx)) != 0)
        goto fail;
    *out = r;
    r = NULL;
fail:
    td_ridges_free(r);
    free(orient);
    return rc;
}

int td_ridges_find(const td_lines *ls, int w, int h,
                   const td_homotopy_params *p, td_ridges **out, td_ctx *cx)
{
    td_contain ct;
    int32_t *lab = NULL;
    int rc;
    memset(&ct, 0, sizeof ct);
    *out = NULL;
    if ((rc = td_check_dims(w, h, "sheet", cx)) != 0)
        return rc;
    if (!(lab = td_malloc((size_t)w * h * sizeof *lab, cx)))
        return TD_ENOMEM;
    rc = hm_find(ls, w, h, p, out, &ct, lab, cx);
    td_contain_free(&ct);
    free(lab);
    return rc;
}

void td_rv_paths_free(td_rv_path *v, size_t n)
{
    size_t i;
    for (i = 0; v && i < n; i++)
        free(v[i].xyz);
    free(v);
}

static int push_xyz(td_rv_path *q, size_t *cap, const td_rv_point *pt,
                    td_ctx *cx)
{
    if (q->n == *cap) {
        size_t nc = *cap * 2 + 8;
        void *t = realloc(q->xyz, nc * 3 * sizeof *q->xyz);
        if (!t)
            return td_seterr(cx, TD_ENOMEM, "out of memory");
        q->xyz = t, *cap = nc;
    }
    q->xyz[3 * q->n] = pt->x, q->xyz[3 * q->n + 1] = pt->y;
    q->xyz[3 * q->n++ + 2] = pt->z;
    return 0;
}

/* One chain from point a along next[] while the points have one link in. */
static int chain(const td_ridges *r, const long *next, const int *indeg,
                 size_t a, td_rv_path *q, td_ctx *cx)
{
    size_t cap = 0;
    int rc;
    memset(q, 0, sizeof *q);
    q->kind = r->pt[a].kind, q->tree = r->pt[a].tree;
    if ((rc = push_xyz(q, &cap, &r->pt[a], cx)) != 0)
        return rc;
    do {
        a = r->link[next[a]].b;
        if ((rc = push_xyz(q, &cap, &r->pt[a], cx)) != 0)
            return rc;
    } while (indeg[a] == 1 && next[a] >= 0);
    return 0;
}

int td_ridges_paths(const td_ridges *r, td_rv_path **out, size_t *n,
                    td_ctx *cx)
{
    long *next = td_malloc((r->npt + 1) * sizeof *next, cx);
    int *indeg = td_calloc(r->npt + 1, sizeof *indeg, cx), rc = 0;
    td_rv_path *v = td_calloc(r->nlink + 1, sizeof *v, cx);
    size_t i, k = 0;
    *out = NULL, *n = 0;
    if (!next || !indeg || !v) {
        rc = TD_ENOMEM;
        goto fail;
    }
    for (i = 0; i < r->npt; i++)
        next[i] = -1;
    for (i = 0; i < r->nlink; i++) {
        next[r->link[i].a] = (long)i;
        indeg[r->link[i].b]++;
    }
    for (i = 0; i < r->npt && rc == 0; i++)
        if (next[i] >= 0 && indeg[i] != 1)
            rc = chain(r, next, indeg, i, &v[k++], cx);
    if (rc == 0) {
        *out = v, *n = k;
        v = NULL;
    }
fail:
    td_rv_paths_free(v, k);
    free(next);
    free(indeg);
    return rc;
}

static const char *kind_name(int k)
{
    return k == TD_RV_RIDGE ? "ridge" : k == TD_RV_VALLEY ? "valley"
                                                          : "inflection";
}

static void put_path(FILE *f, const td_rv_path *q, const td_georef *g)
{
    size_t i;
    fprintf(f, "{\"type\":\"Feature\",\"properties\":{\"kind\":\"%s\","
            "\"tree\":", kind_name(q->kind));
    if (q->tree >= 0)
        fprintf(f, "%ld", q->tree);
    else
        fputs("null", f);
    fputs(",\"heights\":[", f);
    for (i = 0; i < q->n; i++)
        fprintf(f, "%s%.10g", i ? "," : "", q->xyz[3 * i + 2]);
    fputs("]},\"geometry\":{\"type\":\"LineString\",\"coordinates\":[", f);
    for (i = 0; i < q->n; i++) {
        double x = q->xyz[3 * i], y = q->xyz[3 * i + 1];
        if (g && g->valid)
            td_georef_apply(g, x, y, &x, &y);
        fprintf(f, "%s[%.10g,%.10g,%.10g]", i ? "," : "", x, y,
                q->xyz[3 * i + 2]);
    }
    fputs("]}}", f);
}

int td_geojson_write_paths(const char *path, const td_rv_path *v, size_t n,
                           const td_georef *georef, td_ctx *cx)
{
    size_t i, tmpsize = strlen(path) + 32;
    char *tmp = td_malloc(tmpsize, cx);
    FILE *f;
    if (!tmp)
        return TD_ENOMEM;
    if (!(f = td_atomic_open(path, tmp, tmpsize, cx))) {
        free(tmp);
        return cx && cx->code ? cx->code : TD_EIO;
    }
    fputs("{\"type\":\"FeatureCollection\",\n\"features\":[\n", f);
    for (i = 0; i < n; i++) {
        for (size_t k = 0; k < 3 * v[i].n; k++)
            if (!isfinite(v[i].xyz[k])) {
                td_atomic_abort(f, tmp);
                free(tmp);
                return td_seterr(cx, TD_EINVAL, "%s: a path has a "
                                 "non-finite coordinate", path);
            }
        if (i)
            fputs(",\n", f);
        put_path(f, &v[i], georef);
    }
    fputs("\n]}\n", f);
    i = (size_t)td_atomic_commit(f, tmp, path, cx);
    free(tmp);
    return (int)i;
}
