/* erode.c: a velocity-field erosion run with its files: the eroded DEM,
 * the fields, snapshots every K steps and the per-step mass log (erode
 * CLI, batches). */
#include "src/pipeline/pipeline.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct run_state {
    const td_erode_files *o;
    const td_georef *geo;
    td_erode_step_stats *log;
    int nlog;
    td_ctx *cx;
    double z; /* heights in the model x z = heights in the files */
} run_state;

/* g's cells with data times z, in place. */
static void scale_heights(td_grid_f32 *g, double z)
{
    int x, y;
    for (y = 0; y < g->h; y++)
        for (x = 0; x < g->w; x++) {
            float *v = &TD_AT(g, x, y);
            if (!(g->has_nodata && *v == g->nodata))
                *v = (float)(*v * z);
        }
}

/* A copy of g with its heights times z. */
static td_grid_f32 *scaled_copy(const td_grid_f32 *g, double z, td_ctx *cx)
{
    td_grid_f32 *c = td_grid_f32_new(g->w, g->h, cx);
    int y;
    if (!c)
        return NULL;
    c->nodata = g->nodata, c->has_nodata = g->has_nodata;
    for (y = 0; y < g->h; y++)
        memcpy(&TD_AT(c, 0, y), &TD_AT(g, 0, y), (size_t)g->w * sizeof(float));
    scale_heights(c, z);
    return c;
}

/* OUT-stem_stepNNNN.ext */
static void snapshot_path(const char *out, int step, char *buf, size_t n)
{
    const char *slash = strrchr(out, '/'), *dot = strrchr(out, '.');
    if (!dot || (slash && dot < slash))
        dot = out + strlen(out);
    snprintf(buf, n, "%.*s_step%04d%s", (int)(dot - out), out, step, dot);
}

static int on_step(const td_erode_step_stats *s, const td_grid_f32 *dem,
                   void *user)
{
    run_state *o = user;
    if (o->o->mass_log) {
        td_erode_step_stats *l = realloc(o->log, (size_t)(o->nlog + 1) *
                                                     sizeof *l);
        if (!l)
            return td_seterr(o->cx, TD_ENOMEM, "out of memory"), 1;
        o->log = l;
        o->log[o->nlog++] = *s;
    }
    if (dem) {
        char path[4096];
        td_grid_f32 *c = o->z != 1 ? scaled_copy(dem, o->z, o->cx) : NULL;
        int bad;
        if (o->z != 1 && !c)
            return 1;
        snapshot_path(o->o->out, s->step, path, sizeof path);
        bad = td_dem_write(path, c ? c : dem, o->geo, o->cx) != 0;
        td_grid_f32_free(c);
        if (bad)
            return 1;
    }
    return 0;
}

static int write_mass_log(const run_state *o, td_ctx *cx)
{
    char tmp[4200];
    FILE *f;
    int k;
    if (strlen(o->o->mass_log) > 4000)
        return td_seterr(cx, TD_EINVAL, "--mass-log: path too long");
    if (!(f = td_atomic_open(o->o->mass_log, tmp, sizeof tmp, cx)))
        return TD_EIO;
    fputs("step,eroded,eroded_flow,eroded_collision,deposited,outflow,"
          "residual,moves,particles,drained\n", f);
    for (k = 0; k < o->nlog; k++) {
        const td_erode_step_stats *s = &o->log[k];
        double r = s->eroded > 0 ? (s->eroded - s->deposited - s->outflow) /
                                       s->eroded : 0.0;
        fprintf(f, "%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.3g,%.0f,%.0f,%.0f\n",
                s->step, s->eroded, s->eroded_flow, s->eroded_coll,
                s->deposited, s->outflow, r, s->moves, s->particles,
                s->drained);
    }
    return td_atomic_commit(f, tmp, o->o->mass_log, cx);
}

static int write_outputs(const run_state *R, const td_grid_f32 *out,
                         const td_erode_fields *f, const td_georef *geo,
                         td_ctx *cx)
{
    const td_erode_files *o = R->o;
    /* the secondary outputs first: when one fails, the main output (new
       or old) is left as it was */
    int rc = 0;
    if (o->water)
        rc = td_dem_write(o->water, f->water, geo, cx);
    if (rc == 0 && o->energy)
        rc = td_dem_write(o->energy, f->energy, geo, cx);
    if (rc == 0 && o->sediment)
        rc = td_dem_write(o->sediment, f->sediment, geo, cx);
    if (rc == 0 && o->mass_log)
        rc = write_mass_log(R, cx);
    if (rc == 0)
        rc = td_dem_write(o->out, out, geo, cx);
    return rc;
}

/* Allocate out and the requested fields with in's size and nodata. */
static int alloc_grids(const td_erode_files *o, const td_grid_f32 *in,
                       td_grid_f32 **out, td_erode_fields *f, td_ctx *cx)
{
    if (!(*out = td_grid_f32_new(in->w, in->h, cx)) ||
        (o->water && !(f->water = td_grid_f32_new(in->w, in->h, cx))) ||
        (o->energy && !(f->energy = td_grid_f32_new(in->w, in->h, cx))) ||
        (o->sediment && !(f->sediment = td_grid_f32_new(in->w, in->h, cx))))
        return TD_ENOMEM;
    (*out)->nodata = in->nodata;
    (*out)->has_nodata = in->has_nodata;
    return 0;
}

/* See pipeline.h. */
int td_pipeline_erode(const td_grid_f32 *in, const td_georef *geo,
                      const td_erode_params *p, const td_erode_files *files,
                      td_erode_stats *st, td_ctx *cx)
{
    td_grid_f32 *out = NULL;
    td_erode_fields f = {NULL, NULL, NULL};
    td_erode_params q = *p;
    run_state R = {files, geo, NULL, 0, cx, 1.0};
    td_grid_f32 *scaled = NULL;
    int rc;
    q.on_step = on_step;
    q.user = &R;
    if (files->cell_units > 0 && files->cell_units != 1) {
        R.z = files->cell_units;
        q.cell = 1;
        if (!(scaled = scaled_copy(in, 1.0 / R.z, cx)))
            return TD_ENOMEM;
    }
    rc = alloc_grids(files, in, &out, &f, cx);
    if (rc == 0)
        rc = td_erode_run(scaled ? scaled : in, &q, out, &f, st, cx);
    if (rc == 0 && R.z != 1) {
        scale_heights(out, R.z);
        if (f.sediment)
            scale_heights(f.sediment, R.z);
    }
    td_grid_f32_free(scaled);
    if (rc == 0)
        rc = write_outputs(&R, out, &f, geo, cx);
    td_grid_f32_free(out);
    td_grid_f32_free(f.water);
    td_grid_f32_free(f.energy);
    td_grid_f32_free(f.sediment);
    free(R.log);
    return rc;
}
