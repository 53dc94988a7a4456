/* mesh.h: a DEM as a closed solid for 3-D printers and viewers: the
 * surface on top, walls down the edges of the data (around holes too), a
 * flat base.  Pure stage: grid in, triangles out; the files are written
 * by meshio.c (through src/io's atomic files). */
#ifndef TD_MESH_H
#define TD_MESH_H

#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct td_mesh_params {
    int step;            /* a vertex every step cells (1) */
    double exaggeration; /* heights x this (1) */
    double cellsize;     /* cell size in height units (1) */
    double print_size;   /* > 0: scale so the longest side is this many
                            millimetres (0: map units) */
    double base;         /* thickness below the lowest point, in the
                            output's units; < 0: auto, a tenth of the
                            relief (at least a thousandth of the longest
                            side) (-1) */
    size_t max_triangles; /* refuse more (100000000) */
} td_mesh_params;

typedef struct td_mesh {
    float *v;            /* x, y, z per vertex (x east, y north, z up) */
    float *uv;           /* u, v per vertex: where on the DEM (0..1, v up) */
    size_t nv;
    uint32_t *t;         /* 3 vertices per triangle, counter-clockwise
                            seen from outside */
    size_t nt, ntop, nwall, nbase;
    size_t dropped;      /* quads left out where data met only at a corner */
    double volume_scale; /* output units per map unit (print_size) */
} td_mesh;

td_mesh_params td_mesh_defaults(void);

/* Build the solid of dem: a vertex at every step-th cell centre with data;
 * a quad of four such vertices is part of the top (two triangles); every
 * quad edge with no quad beside it gets a wall down to the base plane; the
 * base has a quad under every top quad.  Where two quads meet only at a
 * corner one of them is left out (counted in dropped), so every edge has
 * exactly two triangles, in opposite directions.  *out: td_mesh_free.
 * 0, TD_EINVAL (no quad with data, more than max_triangles: the message
 * names the --step that would do), TD_ENOMEM. */
int td_mesh_build(const td_grid_f32 *dem, const td_mesh_params *p,
                  td_mesh **out, td_ctx *cx);
void td_mesh_free(td_mesh *m);

/* What td_mesh_visit makes, without the arrays. */
typedef struct td_mesh_info {
    size_t nv, nt, ntop, nwall, nbase, dropped;
    double volume_scale;
    double lo[3], hi[3]; /* the solid's bounding box */
} td_mesh_info;

/* One triangle: its corners' positions, counter-clockwise from outside. */
typedef void (*td_mesh_tri_fn)(void *user, const float *a, const float *b,
                               const float *c);

/* The same solid as td_mesh_build, handed out one triangle at a time
 * (top quads row by row with their walls, then the base) with no vertex
 * or triangle arrays: memory is one byte per quad.  info gets the counts
 * (nt before the first call); fn may be NULL (counts only).  The same
 * errors as td_mesh_build. */
int td_mesh_visit(const td_grid_f32 *dem, const td_mesh_params *p,
                  td_mesh_info *info, td_mesh_tri_fn fn, void *user,
                  td_ctx *cx);

/* dem's solid straight to a binary STL at path (td_mesh_visit: no
 * triangle arrays), written under a temporary name and renamed; info
 * gets the counts and the box, *volume (may be NULL) the enclosed
 * volume.  0, the errors of td_mesh_visit, TD_EIO. */
int td_mesh_stream_stl(const char *path, const td_grid_f32 *dem,
                       const td_mesh_params *p, td_mesh_info *info,
                       double *volume, td_ctx *cx);

/* The volume the triangles enclose (divergence theorem; positive when
 * they face outwards). */
double td_mesh_volume(const td_mesh *m);

/* Write m to path, the format by its extension: .stl (binary), .obj
 * (with tex: texture coordinates, a .mtl and a PNG "<name>_texture.png"
 * beside it), .ply (binary), .glb (glTF 2.0, y up).  Each file written
 * under a temporary name and renamed.  0, TD_EINVAL (unknown extension,
 * a texture for another format), TD_EIO, TD_ENOMEM. */
int td_mesh_write(const char *path, const td_mesh *m, const td_image *tex,
                  td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
