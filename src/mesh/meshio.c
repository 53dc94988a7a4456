/* meshio.c: a td_mesh to the files 3-D printers and viewers open, chosen
 * by the extension: binary STL (slicers), Wavefront OBJ (+ MTL and a PNG
 * texture when one is given), binary PLY, glTF binary (.glb).  Each file
 * written to a temporary name and renamed (src/io's atomic helpers). */
#include "src/mesh/mesh.h"

#include "src/io/io.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

static void put32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v, p[1] = (uint8_t)(v >> 8);
    p[2] = (uint8_t)(v >> 16), p[3] = (uint8_t)(v >> 24);
}

static void putf(uint8_t *p, float f)
{
    uint32_t v;
    memcpy(&v, &f, 4);
    put32(p, v);
}

/* Records gathered into 1 MB blocks, one fwrite each. */
typedef struct obuf {
    FILE *f;
    uint8_t b[1 << 20];
    size_t n;
    int err;
} obuf;

static void ob_flush(obuf *o)
{
    if (o->n && fwrite(o->b, 1, o->n, o->f) != o->n)
        o->err = 1;
    o->n = 0;
}

/* Room for n more bytes (n <= 64). */
static uint8_t *ob_room(obuf *o, size_t n)
{
    uint8_t *p;
    if (o->n + n > sizeof o->b)
        ob_flush(o);
    p = o->b + o->n;
    o->n += n;
    return p;
}

static const float *vert(const td_mesh *m, size_t t, int k)
{
    return m->v + 3 * (size_t)m->t[3 * t + k];
}

/* One STL record: the unit normal, the corners, no attributes. */
static void stl_record(uint8_t *rec, const float *a, const float *b,
                       const float *d)
{
    float u[3], v[3], n[3], l;
    int k;
    for (k = 0; k < 3; k++)
        u[k] = b[k] - a[k], v[k] = d[k] - a[k];
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
    l = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    l = l > 0 ? 1.0f / l : 0.0f;
    for (k = 0; k < 3; k++) {
        putf(rec + 4 * k, n[k] * l);
        putf(rec + 12 + 4 * k, a[k]);
        putf(rec + 24 + 4 * k, b[k]);
        putf(rec + 36 + 4 * k, d[k]);
    }
    rec[48] = rec[49] = 0;
}

/* Binary STL: 80-byte header, the count, 50 bytes a triangle. */
static int write_stl(FILE *f, const td_mesh *m)
{
    uint8_t head[84] = "topodig mesh: binary STL";
    obuf *o = malloc(sizeof *o);
    size_t i;
    int rc;
    if (!o)
        return -1;
    o->f = f, o->n = 0, o->err = 0;
    put32(head + 80, (uint32_t)m->nt);
    memcpy(ob_room(o, 84), head, 84);
    for (i = 0; i < m->nt; i++)
        stl_record(ob_room(o, 50), vert(m, i, 0), vert(m, i, 1),
                   vert(m, i, 2));
    ob_flush(o);
    rc = o->err ? -1 : 0;
    free(o);
    return rc;
}

/* The STL stream's output: records go into one of two 8 MB blocks while a
 * writer thread writes the other, so encoding and the kernel's copy into
 * the page cache overlap. */
#define ABLOCK (8u << 20)

typedef struct abuf {
    FILE *f;
    uint8_t *blk[2], *out; /* out: the block being written, NULL: none */
    size_t n, out_n;
    int cur, quit, err, started;
    pthread_t th;
    pthread_mutex_t mu;
    pthread_cond_t cv;
} abuf;

static void *ab_writer(void *arg)
{
    abuf *a = arg;
    pthread_mutex_lock(&a->mu);
    for (;;) {
        while (!a->out && !a->quit)
            pthread_cond_wait(&a->cv, &a->mu);
        if (!a->out)
            break;
        {
            uint8_t *o = a->out;
            size_t n = a->out_n;
            int bad;
            pthread_mutex_unlock(&a->mu);
            bad = fwrite(o, 1, n, a->f) != n;
            pthread_mutex_lock(&a->mu);
            a->err |= bad;
            a->out = NULL;
            pthread_cond_broadcast(&a->cv);
        }
    }
    pthread_mutex_unlock(&a->mu);
    return NULL;
}

/* Hand the current block to the writer (after it finished the last). */
static void ab_flush(abuf *a)
{
    if (!a->n)
        return;
    pthread_mutex_lock(&a->mu);
    while (a->out)
        pthread_cond_wait(&a->cv, &a->mu);
    a->out = a->blk[a->cur];
    a->out_n = a->n;
    pthread_cond_broadcast(&a->cv);
    pthread_mutex_unlock(&a->mu);
    a->cur ^= 1;
    a->n = 0;
}

static uint8_t *ab_room(abuf *a, size_t n)
{
    uint8_t *p;
    if (a->n + n > ABLOCK)
        ab_flush(a);
    p = a->blk[a->cur] + a->n;
    a->n += n;
    return p;
}

static int ab_open(abuf *a, FILE *f)
{
    memset(a, 0, sizeof *a);
    a->f = f;
    if (!(a->blk[0] = malloc(ABLOCK)) || !(a->blk[1] = malloc(ABLOCK))) {
        free(a->blk[0]);
        return -1;
    }
    pthread_mutex_init(&a->mu, NULL);
    pthread_cond_init(&a->cv, NULL);
    a->started = pthread_create(&a->th, NULL, ab_writer, a) == 0;
    if (!a->started) {
        free(a->blk[0]), free(a->blk[1]);
        return -1;
    }
    return 0;
}

/* Write what is left, stop the writer; -1 when any write failed. */
static int ab_close(abuf *a)
{
    ab_flush(a);
    pthread_mutex_lock(&a->mu);
    while (a->out)
        pthread_cond_wait(&a->cv, &a->mu);
    a->quit = 1;
    pthread_cond_broadcast(&a->cv);
    pthread_mutex_unlock(&a->mu);
    pthread_join(a->th, NULL);
    pthread_mutex_destroy(&a->mu);
    pthread_cond_destroy(&a->cv);
    free(a->blk[0]), free(a->blk[1]);
    return a->err ? -1 : 0;
}

/* The STL stream: records, the volume and the box. */
typedef struct stlsink {
    abuf o;
    const td_mesh_info *info; /* the count, known at the first triangle */
    int started, too_many;
    double vol;
} stlsink;


static void stl_tri(void *user, const float *a, const float *b, const float *c)
{
    stlsink *s = user;
    if (!s->started) { /* the header: 80 bytes, the count */
        uint8_t *h = ab_room(&s->o, 84);
        s->too_many = s->info->nt > UINT32_MAX; /* more than STL counts */
        memset(h, 0, 84);
        memcpy(h, "topodig mesh: binary STL", 24);
        put32(h + 80, (uint32_t)s->info->nt);
        s->started = 1;
    }
    stl_record(ab_room(&s->o, 50), a, b, c);
    s->vol += (double)a[0] * ((double)b[1] * c[2] - (double)b[2] * c[1]) -
              (double)a[1] * ((double)b[0] * c[2] - (double)b[2] * c[0]) +
              (double)a[2] * ((double)b[0] * c[1] - (double)b[1] * c[0]);
}

/* See mesh.h. */
int td_mesh_stream_stl(const char *path, const td_grid_f32 *dem,
                       const td_mesh_params *p, td_mesh_info *info,
                       double *volume, td_ctx *cx)
{
    stlsink *s = calloc(1, sizeof *s);
    char tmp[4096];
    FILE *f;
    int rc;
    if (!s)
        return td_seterr(cx, TD_ENOMEM, "mesh: out of memory");
    s->info = info;
    if (!(f = td_atomic_open(path, tmp, sizeof tmp, cx))) {
        free(s);
        return cx && cx->code ? cx->code : TD_EIO;
    }
    if (ab_open(&s->o, f) != 0) {
        td_atomic_abort(f, tmp);
        free(s);
        return td_seterr(cx, TD_ENOMEM, "mesh: out of memory");
    }
    rc = td_mesh_visit(dem, p, info, stl_tri, s, cx);
    if (ab_close(&s->o) != 0 && rc == 0)
        rc = td_seterr(cx, TD_EIO, "%s: write failed", path);
    if (rc == 0 && s->too_many)
        rc = td_seterr(cx, TD_EINVAL, "%s: %zu triangles, more than an STL "
                       "holds (give --step)", path, info->nt);
    if (rc != 0) {
        td_atomic_abort(f, tmp);
        free(s);
        return rc;
    }
    if (volume)
        *volume = s->vol / 6;
    free(s);
    return td_atomic_commit(f, tmp, path, cx);
}

/* Binary little-endian PLY. */
static int write_ply(FILE *f, const td_mesh *m)
{
    obuf *o = malloc(sizeof *o);
    size_t i;
    int k, rc;
    if (!o)
        return -1;
    o->f = f, o->n = 0, o->err = 0;
    fprintf(f, "ply\nformat binary_little_endian 1.0\ncomment topodig mesh\n"
            "element vertex %zu\nproperty float x\nproperty float y\n"
            "property float z\nelement face %zu\nproperty list uchar int "
            "vertex_indices\nend_header\n", m->nv, m->nt);
    for (i = 0; i < m->nv; i++) {
        uint8_t *rec = ob_room(o, 12);
        for (k = 0; k < 3; k++)
            putf(rec + 4 * k, m->v[3 * i + k]);
    }
    for (i = 0; i < m->nt; i++) {
        uint8_t *rec = ob_room(o, 13);
        rec[0] = 3;
        for (k = 0; k < 3; k++)
            put32(rec + 1 + 4 * k, m->t[3 * i + k]);
    }
    ob_flush(o);
    rc = o->err ? -1 : 0;
    free(o);
    return rc;
}

/* Wavefront OBJ; with mtl (the material file's name) texture coordinates
 * and the material. */
static int write_obj(FILE *f, const td_mesh *m, const char *mtl)
{
    size_t i;
    fprintf(f, "# topodig mesh: %zu vertices, %zu triangles\n", m->nv, m->nt);
    if (mtl)
        fprintf(f, "mtllib %s\nusemtl dem\n", mtl);
    for (i = 0; i < m->nv; i++)
        fprintf(f, "v %.7g %.7g %.7g\n", m->v[3 * i], m->v[3 * i + 1],
                m->v[3 * i + 2]);
    for (i = 0; mtl && i < m->nv; i++)
        fprintf(f, "vt %.6f %.6f\n", m->uv[2 * i], m->uv[2 * i + 1]);
    for (i = 0; i < m->nt; i++) {
        uint32_t a = m->t[3 * i] + 1, b = m->t[3 * i + 1] + 1,
                 c = m->t[3 * i + 2] + 1;
        if (mtl)
            fprintf(f, "f %u/%u %u/%u %u/%u\n", a, a, b, b, c, c);
        else
            fprintf(f, "f %u %u %u\n", a, b, c);
    }
    return ferror(f) ? -1 : 0;
}

/* glTF 2.0 binary: one mesh, positions (y up: x, z, -y) and indices. */
static int write_glb(FILE *f, const td_mesh *m)
{
    char json[1024];
    uint8_t h[12], ch[8];
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL,
                                                           -HUGE_VAL, -HUGE_VAL};
    size_t lv = 12 * m->nv, li = 12 * m->nt, jl, i, pad;
    int k;
    for (i = 0; i < m->nv; i++) {
        double p[3] = {m->v[3 * i], m->v[3 * i + 2], -m->v[3 * i + 1]};
        for (k = 0; k < 3; k++)
            lo[k] = fmin(lo[k], p[k]), hi[k] = fmax(hi[k], p[k]);
    }
    jl = (size_t)snprintf(json, sizeof json,
        "{\"asset\":{\"version\":\"2.0\",\"generator\":\"topodig\"},"
        "\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},"
        "\"indices\":1}]}],\"buffers\":[{\"byteLength\":%zu}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":%zu,"
        "\"target\":34962},{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":"
        "%zu,\"target\":34963}],\"accessors\":[{\"bufferView\":0,"
        "\"componentType\":5126,\"count\":%zu,\"type\":\"VEC3\",\"min\":"
        "[%.9g,%.9g,%.9g],\"max\":[%.9g,%.9g,%.9g]},{\"bufferView\":1,"
        "\"componentType\":5125,\"count\":%zu,\"type\":\"SCALAR\"}]}",
        lv + li, lv, lv, li, m->nv, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2],
        3 * m->nt);
    pad = (4 - jl % 4) % 4;
    memcpy(h, "glTF", 4);
    put32(h + 4, 2);
    put32(h + 8, (uint32_t)(12 + 8 + jl + pad + 8 + lv + li));
    put32(ch, (uint32_t)(jl + pad));
    memcpy(ch + 4, "JSON", 4);
    if (fwrite(h, 1, 12, f) != 12 || fwrite(ch, 1, 8, f) != 8 ||
        fwrite(json, 1, jl, f) != jl || fwrite("   ", 1, pad, f) != pad)
        return -1;
    put32(ch, (uint32_t)(lv + li));
    memcpy(ch + 4, "BIN\0", 4);
    if (fwrite(ch, 1, 8, f) != 8)
        return -1;
    {
        obuf *o = malloc(sizeof *o);
        int rc;
        if (!o)
            return -1;
        o->f = f, o->n = 0, o->err = 0;
        for (i = 0; i < m->nv; i++) {
            uint8_t *r = ob_room(o, 12);
            putf(r, m->v[3 * i]), putf(r + 4, m->v[3 * i + 2]);
            putf(r + 8, -m->v[3 * i + 1]);
        }
        for (i = 0; i < m->nt; i++) {
            uint8_t *r = ob_room(o, 12);
            for (k = 0; k < 3; k++)
                put32(r + 4 * k, m->t[3 * i + k]);
        }
        ob_flush(o);
        rc = o->err ? -1 : 0;
        free(o);
        return rc;
    }
}

/* path with its extension replaced by ext (".mtl"); malloc'd. */
static char *sibling(const char *path, const char *ext)
{
    const char *dot = strrchr(path, '.'), *slash = strrchr(path, '/');
    size_t n = dot && (!slash || dot > slash) ? (size_t)(dot - path)
                                              : strlen(path);
    char *s = malloc(n + strlen(ext) + 1);
    if (s)
        memcpy(s, path, n), strcpy(s + n, ext);
    return s;
}

/* The OBJ's material and texture files beside it. */
static int write_material(const char *path, const td_image *tex,
                          char **mtl_name, td_ctx *cx)
{
    char *mtl = sibling(path, ".mtl"), *png = sibling(path, "_texture.png");
    char tmp[4096];
    const char *pb;
    FILE *f = NULL;
    int rc = 0;
    if (!mtl || !png) {
        rc = td_seterr(cx, TD_ENOMEM, "out of memory");
        goto done;
    }
    if ((rc = td_png_write(png, tex, cx)) != 0)
        goto done;
    if (!(f = td_atomic_open(mtl, tmp, sizeof tmp, cx))) {
        rc = cx && cx->code ? cx->code : TD_EIO;
        goto done;
    }
    pb = strrchr(png, '/') ? strrchr(png, '/') + 1 : png;
    fprintf(f, "# topodig mesh\nnewmtl dem\nKa 1 1 1\nKd 1 1 1\nKs 0 0 0\n"
            "map_Kd %s\n", pb);
    if ((rc = td_atomic_commit(f, tmp, mtl, cx)) != 0)
        goto done;
    *mtl_name = strdup(strrchr(mtl, '/') ? strrchr(mtl, '/') + 1 : mtl);
    if (!*mtl_name)
        rc = td_seterr(cx, TD_ENOMEM, "out of memory");
done:
    free(mtl), free(png);
    return rc;
}

/* See mesh.h. */
int td_mesh_write(const char *path, const td_mesh *m, const td_image *tex,
                  td_ctx *cx)
{
    const char *ext = strrchr(path, '.');
    char tmp[4096], *mtl = NULL;
    FILE *f;
    int fmt, rc;
    if (!ext)
        ext = "";
    fmt = !strcasecmp(ext, ".stl") ? 0 : !strcasecmp(ext, ".obj") ? 1
        : !strcasecmp(ext, ".ply") ? 2 : !strcasecmp(ext, ".glb") ? 3 : -1;
    if (fmt < 0)
        return td_seterr(cx, TD_EINVAL, "%s: not a mesh format this writes "
                         "(.stl, .obj, .ply, .glb)", path);
    if (tex && fmt != 1)
        return td_seterr(cx, TD_EINVAL, "%s: a texture goes with .obj only",
                         path);
    if (tex && (rc = write_material(path, tex, &mtl, cx)) != 0)
        return rc;
    if (!(f = td_atomic_open(path, tmp, sizeof tmp, cx))) {
        free(mtl);
        return cx && cx->code ? cx->code : TD_EIO;
    }
    rc = fmt == 0 ? write_stl(f, m) : fmt == 1 ? write_obj(f, m, mtl)
       : fmt == 2 ? write_ply(f, m) : write_glb(f, m);
    free(mtl);
    if (rc != 0) {
        td_atomic_abort(f, tmp);
        return td_seterr(cx, TD_EIO, "%s: write failed", path);
    }
    return td_atomic_commit(f, tmp, path, cx);
}
