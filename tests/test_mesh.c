/* test_mesh.c: the solid of a DEM (src/mesh): closed and facing out
 * (every edge in exactly two triangles, in opposite directions), no
 * degenerate triangle, the volume it encloses against the integral of the
 * surface over the cells, holes without data walled, corner contacts
 * resolved, bad input refused; the files of every format (meshio.c). */
#include "tests/tt.h"
#include "src/mesh/mesh.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

typedef struct edge {
    uint32_t a, b; /* a < b */
    int fwd, back; /* directed a->b, b->a */
} edge;

static int by_edge(const void *x, const void *y)
{
    const edge *p = x, *q = y;
    if (p->a != q->a)
        return p->a < q->a ? -1 : 1;
    return p->b < q->b ? -1 : p->b > q->b;
}

/* Every edge twice, once each way; no triangle without area.  Returns
 * the number of bad edges. */
static size_t closed_check(const td_mesh *m, size_t *degenerate)
{
    edge *e = malloc(3 * m->nt * sizeof *e);
    size_t i, k, bad = 0, n = 0;
    *degenerate = 0;
    for (i = 0; i < m->nt; i++) {
        const float *p[3];
        double u[3], v[3], c[3];
        for (k = 0; k < 3; k++)
            p[k] = m->v + 3 * (size_t)m->t[3 * i + k];
        for (k = 0; k < 3; k++)
            u[k] = p[1][k] - p[0][k], v[k] = p[2][k] - p[0][k];
        c[0] = u[1] * v[2] - u[2] * v[1], c[1] = u[2] * v[0] - u[0] * v[2];
        c[2] = u[0] * v[1] - u[1] * v[0];
        if (!(c[0] * c[0] + c[1] * c[1] + c[2] * c[2] > 1e-12))
            (*degenerate)++;
        for (k = 0; k < 3; k++) {
            uint32_t a = m->t[3 * i + k], b = m->t[3 * i + (k + 1) % 3];
            e[n].a = a < b ? a : b, e[n].b = a < b ? b : a;
            e[n].fwd = a < b, e[n].back = a > b;
            n++;
        }
    }
    qsort(e, n, sizeof *e, by_edge);
    for (i = 0; i < n;) {
        size_t j = i;
        int f = 0, b = 0;
        while (j < n && e[j].a == e[i].a && e[j].b == e[i].b)
            f += e[j].fwd, b += e[j].back, j++;
        bad += !(f == 1 && b == 1);
        i = j;
    }
    free(e);
    return bad;
}

static double hill(int x, int y)
{
    double dx = (x - 100) / 60.0, dy = (y - 80) / 50.0;
    return 40 * exp(-(dx * dx + dy * dy)) + 0.05 * x;
}

/* A 200 x 160 hill with a round hole without data and the corners cut:
 * closed; its volume the sum over the quads of the two triangles' prisms
 * (written out here), and, with no hole, the integral of the hill. */
static void test_closed_volume(void)
{
    td_grid_f32 *g = td_grid_f32_new(200, 160, NULL);
    td_mesh_params p = td_mesh_defaults();
    td_mesh *m = NULL;
    size_t bad, deg;
    double lo = HUGE_VAL, want = 0, vol;
    int x, y, hole;
    g->has_nodata = 1, g->nodata = -9999;
    p.base = 5;
    for (hole = 1; hole >= 0; hole--) {
        lo = HUGE_VAL, want = 0;
        for (y = 0; y < 160; y++)
            for (x = 0; x < 200; x++) {
                int out = hole && ((hypot(x - 60, y - 50) < 12) ||
                                   x + y < 20 || (199 - x) + (159 - y) < 30);
                TD_AT(g, x, y) = out ? -9999.0f : (float)hill(x, y);
                if (!out)
                    lo = fmin(lo, TD_AT(g, x, y));
            }
        for (y = 0; y + 1 < 160; y++) /* quads: (A, D, C), (A, C, B) */
            for (x = 0; x + 1 < 200; x++) {
                float a = TD_AT(g, x, y), b = TD_AT(g, x + 1, y);
                float d = TD_AT(g, x, y + 1), c = TD_AT(g, x + 1, y + 1);
                if (a == -9999 || b == -9999 || c == -9999 || d == -9999)
                    continue;
                want += 0.5 * ((a + d + c) / 3.0 + (a + c + b) / 3.0) - lo + 5;
            }
        TT_CHECK(td_mesh_build(g, &p, &m, NULL) == 0);
        bad = closed_check(m, &deg);
        TT_CHECKF(bad == 0 && deg == 0, "hole %d: %zu open or doubled edges, "
                  "%zu degenerate triangles", hole, bad, deg);
        TT_CHECK(m->nwall > 0 && m->dropped == 0);
        vol = td_mesh_volume(m);
        TT_CHECKF(fabs(vol - want) < 1e-3 * want, "hole %d: volume %g, the "
                  "cells' prisms %g", hole, vol, want);
        if (!hole) { /* the integral of the hill over the quads' extent */
            double I = 0;
            int k;
            for (y = 0; y < 159; y++)
                for (x = 0; x < 199; x++)
                    for (k = 0; k < 16; k++) { /* 4 x 4 midpoints a cell */
                        double sx = x + (k % 4 + 0.5) / 4, sy = y + (k / 4 + 0.5) / 4;
                        double dx = (sx - 100) / 60.0, dy = (sy - 80) / 50.0;
                        I += (40 * exp(-(dx * dx + dy * dy)) + 0.05 * sx - lo +
                              5) / 16;
                    }
            TT_CHECKF(fabs(vol - I) < 1e-3 * I, "volume %g, the hill's "
                      "integral %g", vol, I);
        }
        td_mesh_free(m);
        m = NULL;
    }
    td_grid_f32_free(g);
}

/* Data with one cell in six missing at random: quads meet at corners
 * only here and there; one of each such pair is left out and the solid
 * stays closed. */
static void test_corner_contacts(void)
{
    td_grid_f32 *g = td_grid_f32_new(40, 40, NULL);
    td_mesh_params p = td_mesh_defaults();
    td_mesh *m = NULL;
    size_t deg;
    int x, y;
    g->has_nodata = 1, g->nodata = -9999;
    uint64_t r = 99;
    for (y = 0; y < 40; y++)
        for (x = 0; x < 40; x++) {
            r ^= r << 13, r ^= r >> 7, r ^= r << 17;
            TD_AT(g, x, y) = r % 6 == 0 ? -9999.0f : (float)(x + y);
        }
    TT_CHECK(td_mesh_build(g, &p, &m, NULL) == 0);
    TT_CHECKF(m->dropped > 0, "%zu left out", m->dropped);
    TT_CHECK(closed_check(m, &deg) == 0 && deg == 0);
    TT_CHECK(td_mesh_volume(m) > 0);
    td_mesh_free(m);
    td_grid_f32_free(g);
}

static void test_bad(void)
{
    td_grid_f32 *g = td_grid_f32_new(50, 50, NULL), *one = td_grid_f32_new(1, 9, NULL);
    td_mesh_params p = td_mesh_defaults();
    td_mesh *m = NULL;
    td_ctx cx;
    int i;
    td_ctx_init(&cx);
    g->has_nodata = 1, g->nodata = -9999;
    for (i = 0; i < 2500; i++)
        TD_AT(g, i % 50, i / 50) = -9999;
    TT_CHECK(td_mesh_build(g, &p, &m, &cx) == TD_EINVAL && !m);
    TT_CHECK(td_mesh_build(one, &p, &m, &cx) == TD_EINVAL && !m);
    for (i = 0; i < 2500; i++)
        TD_AT(g, i % 50, i / 50) = (float)i;
    p.max_triangles = 1000; /* 50 x 50 needs ~5400 */
    td_ctx_clear(&cx);
    TT_CHECK(td_mesh_build(g, &p, &m, &cx) == TD_EINVAL && !m);
    TT_CHECKF(strstr(td_errmsg(&cx), "give --step ") != NULL, "%s",
              td_errmsg(&cx));
    /* the step it names does */
    p.step = atoi(strstr(td_errmsg(&cx), "give --step ") + 12);
    TT_CHECKF(p.step > 1 && td_mesh_build(g, &p, &m, &cx) == 0 &&
                  m->nt <= 1000, "--step %d", p.step);
    td_mesh_free(m);
    td_grid_f32_free(g), td_grid_f32_free(one);
}

static long fsize(const char *p)
{
    struct stat st;
    return stat(p, &st) == 0 ? (long)st.st_size : -1;
}

static uint32_t le32(const unsigned char *b)
{
    return b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 |
           (uint32_t)b[3] << 24;
}

/* The files (meshio.c) of a 6 x 5 ramp: STL 84 + 50 bytes a triangle
 * with the count and every normal of unit length; PLY's header counts and
 * size; glb's header, chunk lengths and counts; OBJ's v and f lines and,
 * with a texture, its .mtl and PNG beside it; refusals leave no file. */
/* td_mesh_stream_stl (the CLI's STL, no triangle arrays) writes the
 * same bytes as td_mesh_build + td_mesh_write, with the same counts, box
 * and volume: the hill with its hole and cut corners, and a sheet with
 * cells missing at random (corner contacts), at steps 1 and 3. */
static void test_stream_stl(void)
{
    char dir[] = "/tmp/tdmeshXXXXXX", a[256], b[256];
    td_grid_f32 *g = td_grid_f32_new(200, 160, NULL);
    td_mesh_params p = td_mesh_defaults();
    unsigned seed = 7;
    int x, y, kind, step;
    TT_CHECK(mkdtemp(dir) != NULL);
    snprintf(a, sizeof a, "%s/built.stl", dir);
    snprintf(b, sizeof b, "%s/streamed.stl", dir);
    g->has_nodata = 1, g->nodata = -9999;
    p.base = 5;
    for (kind = 0; kind < 2; kind++)
        for (step = 1; step <= 3; step += 2) {
            td_mesh *m = NULL;
            td_mesh_info info;
            double vol = 0;
            FILE *fa, *fb;
            int same = 1, ca, cb;
            long k;
            for (y = 0; y < 160; y++)
                for (x = 0; x < 200; x++) {
                    int out = kind == 0 ? (hypot(x - 60, y - 50) < 12 ||
                                           x + y < 20)
                                        : (seed = seed * 1103515245u + 12345u,
                                           (seed >> 16) % 6 == 0);
                    TD_AT(g, x, y) = out ? -9999.0f : (float)hill(x, y);
                }
            p.step = step;
            TT_CHECK(td_mesh_build(g, &p, &m, NULL) == 0);
            TT_CHECK(m && td_mesh_write(a, m, NULL, NULL) == 0);
            TT_CHECK(td_mesh_stream_stl(b, g, &p, &info, &vol, NULL) == 0);
            fa = fopen(a, "rb"), fb = fopen(b, "rb");
            for (k = 0; fa && fb && same; k++) {
                ca = getc(fa), cb = getc(fb);
                same = ca == cb;
                if (ca == EOF || cb == EOF)
                    break;
            }
            TT_CHECKF(fa && fb && same, "kind %d step %d: the files differ "
                      "at byte %ld", kind, step, k);
            if (fa)
                fclose(fa);
            if (fb)
                fclose(fb);
            if (m) {
                size_t i;
                int c;
                double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL},
                       hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
                for (i = 0; i < m->nv; i++)
                    for (c = 0; c < 3; c++)
                        lo[c] = fmin(lo[c], m->v[3 * i + c]),
                        hi[c] = fmax(hi[c], m->v[3 * i + c]);
                TT_CHECKF(info.nv == m->nv && info.nt == m->nt &&
                              info.ntop == m->ntop && info.nwall == m->nwall &&
                              info.nbase == m->nbase &&
                              info.dropped == m->dropped,
                          "kind %d step %d: counts %zu/%zu vertices, %zu/%zu "
                          "triangles", kind, step, info.nv, m->nv, info.nt,
                          m->nt);
                TT_NEAR(vol, td_mesh_volume(m), 1e-9 * fabs(vol) + 1e-6);
                for (c = 0; c < 3; c++) {
                    TT_NEAR(info.lo[c], lo[c], 1e-3);
                    TT_NEAR(info.hi[c], hi[c], 1e-3);
                }
            }
            td_mesh_free(m);
        }
    unlink(a), unlink(b), rmdir(dir);
    td_grid_f32_free(g);
}

static void test_files(void)
{
    char dir[] = "/tmp/tdmeshXXXXXX", p[256], line[256];
    td_grid_f32 *g = td_grid_f32_new(6, 5, NULL);
    td_image *tex = td_image_new(6, 5, 3, NULL);
    td_mesh_params mp = td_mesh_defaults();
    td_mesh *m = NULL;
    unsigned char b[128];
    FILE *f;
    long nv = 0, nf = 0, vt = 0;
    size_t i;
    int x, y;
    TT_CHECK(mkdtemp(dir) != NULL);
    for (y = 0; y < 5; y++)
        for (x = 0; x < 6; x++)
            TD_AT(g, x, y) = (float)(x + 2 * y);
    TT_CHECK(td_mesh_build(g, &mp, &m, NULL) == 0);
    snprintf(p, sizeof p, "%s/m.stl", dir);
    TT_CHECK(td_mesh_write(p, m, NULL, NULL) == 0);
    TT_CHECK(fsize(p) == 84 + 50 * (long)m->nt);
    f = fopen(p, "rb");
    TT_CHECK(f && fread(b, 1, 84, f) == 84 && le32(b + 80) == m->nt);
    for (i = 0; f && i < m->nt; i++) { /* unit normals, facing out */
        float n[3];
        TT_CHECK(fread(b, 1, 50, f) == 50);
        memcpy(n, b, 12);
        TT_NEAR(n[0] * n[0] + n[1] * n[1] + n[2] * n[2], 1.0, 1e-5);
    }
    if (f)
        fclose(f);
    snprintf(p, sizeof p, "%s/m.ply", dir);
    TT_CHECK(td_mesh_write(p, m, NULL, NULL) == 0 && (f = fopen(p, "rb")));
    if (f) {
        long hdr = 0, ev = -1, ef = -1;
        while (fgets(line, sizeof line, f)) {
            hdr += (long)strlen(line);
            sscanf(line, "element vertex %ld", &ev);
            sscanf(line, "element face %ld", &ef);
            if (!strcmp(line, "end_header\n"))
                break;
        }
        fclose(f);
        TT_CHECK(ev == (long)m->nv && ef == (long)m->nt);
        TT_CHECK(fsize(p) == hdr + 12 * ev + 13 * ef);
    }
    snprintf(p, sizeof p, "%s/m.glb", dir);
    TT_CHECK(td_mesh_write(p, m, NULL, NULL) == 0 && (f = fopen(p, "rb")));
    if (f) {
        char json[2048];
        uint32_t jl;
        TT_CHECK(fread(b, 1, 20, f) == 20);
        jl = le32(b + 12);
        TT_CHECK(!memcmp(b, "glTF", 4) && le32(b + 4) == 2 &&
                 le32(b + 8) == (uint32_t)fsize(p) && !memcmp(b + 16, "JSON", 4));
        TT_CHECK(jl < sizeof json && fread(json, 1, jl, f) == jl);
        json[jl < sizeof json ? jl : 0] = 0;
        snprintf(line, sizeof line, "\"count\":%zu,\"type\":\"VEC3\"", m->nv);
        TT_CHECKF(strstr(json, line) != NULL, "%s", json);
        snprintf(line, sizeof line, "\"count\":%zu,\"type\":\"SCALAR\"",
                 3 * m->nt);
        TT_CHECK(strstr(json, line) != NULL);
        TT_CHECK(fread(b, 1, 8, f) == 8 && le32(b) == 12 * (m->nv + m->nt) &&
                 !memcmp(b + 4, "BIN", 3));
        fclose(f);
    }
    snprintf(p, sizeof p, "%s/m.obj", dir);
    TT_CHECK(td_mesh_write(p, m, tex, NULL) == 0 && (f = fopen(p, "r")));
    while (f && fgets(line, sizeof line, f)) {
        nv += !strncmp(line, "v ", 2);
        vt += !strncmp(line, "vt ", 3);
        nf += !strncmp(line, "f ", 2);
    }
    if (f)
        fclose(f);
    TT_CHECK(nv == (long)m->nv && vt == (long)m->nv && nf == (long)m->nt);
    snprintf(p, sizeof p, "%s/m.mtl", dir);
    TT_CHECK(fsize(p) > 0);
    snprintf(p, sizeof p, "%s/m_texture.png", dir);
    TT_CHECK(fsize(p) > 0);
    snprintf(p, sizeof p, "%s/x.dae", dir); /* refusals: no file */
    TT_CHECK(td_mesh_write(p, m, NULL, NULL) == TD_EINVAL && fsize(p) < 0);
    snprintf(p, sizeof p, "%s/x.stl", dir);
    TT_CHECK(td_mesh_write(p, m, tex, NULL) == TD_EINVAL && fsize(p) < 0);
    snprintf(p, sizeof p, "%s/no/such/x.stl", dir);
    TT_CHECK(td_mesh_write(p, m, NULL, NULL) != 0 && fsize(p) < 0);
    {
        static const char *const names[] = {"m.stl", "m.ply", "m.glb", "m.obj",
                                            "m.mtl", "m_texture.png"};
        for (i = 0; i < 6; i++) {
            snprintf(p, sizeof p, "%s/%s", dir, names[i]);
            unlink(p);
        }
        rmdir(dir);
    }
    td_mesh_free(m);
    td_image_free(tex);
    td_grid_f32_free(g);
}

int main(void)
{
    TT_RUN(test_closed_volume);
    TT_RUN(test_corner_contacts);
    TT_RUN(test_bad);
    TT_RUN(test_files);
    TT_RUN(test_stream_stl);
    return tt_summary();
}
