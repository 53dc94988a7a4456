/* ridges.c: the ridge/valley driver (orient -> curves -> points -> links
 * and trees), the links chained into paths, and their GeoJSON writer. */
#include "interp/homotopy_int.h"


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
