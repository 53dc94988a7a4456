/* vector_ogr.c: contour lines as GeoPackage, Shapefile and DXF through
 * GDAL/OGR's C API, and the by-extension front door td_vector_*_lines
 * (GeoJSON stays with topodig's own reader and writer, geojson_*.c).
 *
 * Written like every output: GDAL writes into a new private folder next
 * to the target (mkdtemp, so nothing planted there is followed), and the
 * finished files are renamed over the target (a Shapefile's .shp, .shx,
 * .dbf, .prj one after another, the .shp last).  GDAL's messages go into
 * the td_ctx, never to stderr. */
#include "src/io/io.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cpl_error.h>
#include <gdal.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

typedef enum { VF_GEOJSON, VF_GPKG, VF_SHP, VF_DXF, VF_OTHER } vformat;

static vformat format_of(const char *path)
{
    const char *dot = strrchr(path, '.');
    const char *slash = strrchr(path, '/');
    if (!dot || (slash && dot < slash))
        return VF_OTHER;
    if (!strcasecmp(dot, ".geojson") || !strcasecmp(dot, ".json"))
        return VF_GEOJSON;
    if (!strcasecmp(dot, ".gpkg"))
        return VF_GPKG;
    if (!strcasecmp(dot, ".shp"))
        return VF_SHP;
    if (!strcasecmp(dot, ".dxf"))
        return VF_DXF;
    return VF_OTHER;
}

static const char *driver_of(vformat f)
{
    return f == VF_GPKG ? "GPKG" : f == VF_SHP ? "ESRI Shapefile" : "DXF";
}

/* GDAL's last error as a message naming path, or a fallback. */
static int gdal_fail(td_ctx *cx, const char *path, const char *what)
{
    const char *m = CPLGetLastErrorMsg();
    return td_seterr(cx, TD_EIO, "%s: %s%s%s", path, what, m && *m ? ": " : "",
                     m && *m ? m : "");
}

static void gdal_init(void)
{
    static int done;
    if (!done) {
        GDALAllRegister();
        done = 1;
    }
}

/* ---- writing ---------------------------------------------------------- */

/* The layer's CRS for g: the EPSG code, else the pixel frame's (or the
 * unnamed scan CRS's) engineering CRS, as td_georef_crs_json names it. */
static OGRSpatialReferenceH make_srs(const td_georef *g)
{
    OGRSpatialReferenceH s = OSRNewSpatialReference(NULL);
    int real = g && g->valid && !g->pixel;
    char wkt[200];
    if (!s)
        return NULL;
    if (real && g->epsg > 0 && OSRImportFromEPSG(s, g->epsg) == OGRERR_NONE) {
        OSRSetAxisMappingStrategy(s, OAMS_TRADITIONAL_GIS_ORDER);
        return s;
    }
    snprintf(wkt, sizeof wkt, "LOCAL_CS[\"%s\",UNIT[\"%s\",1],AXIS[\"X\","
             "EAST],AXIS[\"Y\",NORTH]]",
             real ? "the scan's CRS (not named in it)" : TD_PIXEL_CRS,
             real ? "unknown" : "pixel");
    if (OSRSetFromUserInput(s, wkt) != OGRERR_NONE) {
        OSRDestroySpatialReference(s);
        return NULL;
    }
    return s;
}

typedef struct field {
    const char *name;
    OGRFieldType type;
    OGRFieldSubType sub;
} field;

static const field fields[] = {
    {"id", OFTInteger64, OFSTNone},
    {"height", OFTReal, OFSTNone},
    {"height_source", OFTString, OFSTNone},
    {"confidence", OFTReal, OFSTNone},
    {"height_reason", OFTString, OFSTNone},
    {"closed", OFTInteger, OFSTBoolean},
    {"edge", OFTInteger, OFSTBoolean},
    {"parent", OFTInteger64, OFSTNone},
    {"bridged", OFTInteger, OFSTNone},
    {"width", OFTReal, OFSTNone},
    {"depression", OFTInteger, OFSTBoolean},
    {"ink", OFTReal, OFSTNone},
    {"piece", OFTInteger, OFSTBoolean},
};
enum { NFIELDS = sizeof fields / sizeof fields[0] };

static int make_fields(OGRLayerH lyr)
{
    int i;
    for (i = 0; i < NFIELDS; i++) {
        OGRFieldDefnH d = OGR_Fld_Create(fields[i].name, fields[i].type);
        OGRErr e;
        OGR_Fld_SetSubType(d, fields[i].sub);
        e = OGR_L_CreateField(lyr, d, TRUE);
        OGR_Fld_Destroy(d);
        if (e != OGRERR_NONE)
            return -1;
    }
    return 0;
}

/* Field values of l (by the layer's field order, found by name: a
 * Shapefile cuts names to 10 characters). */
static void set_fields(OGRFeatureH f, OGRFeatureDefnH d, const td_line *l)
{
    static const char *src[] = {"", "known", "label", "solved", "assumed"};
    int k[NFIELDS], i;
    for (i = 0; i < NFIELDS; i++) {
        char n[11];
        snprintf(n, sizeof n, "%s", fields[i].name);
        k[i] = OGR_FD_GetFieldIndex(d, fields[i].name);
        if (k[i] < 0)
            k[i] = OGR_FD_GetFieldIndex(d, n);
    }
    if (k[0] >= 0)
        OGR_F_SetFieldInteger64(f, k[0], l->id);
    if (k[1] >= 0 && l->has_height && isfinite(l->height))
        OGR_F_SetFieldDouble(f, k[1], l->height);
    if (l->hsource > TD_HS_NONE && l->hsource <= TD_HS_ASSUMED) {
        if (k[2] >= 0)
            OGR_F_SetFieldString(f, k[2], src[l->hsource]);
        if (k[3] >= 0)
            OGR_F_SetFieldDouble(f, k[3], l->confidence);
    }
    if (k[4] >= 0 && l->why && !l->has_height)
        OGR_F_SetFieldString(f, k[4], l->why);
    if (k[5] >= 0)
        OGR_F_SetFieldInteger(f, k[5], !!l->closed);
    if (k[6] >= 0)
        OGR_F_SetFieldInteger(f, k[6], !!l->edge);
    if (k[7] >= 0 && l->parent >= 0)
        OGR_F_SetFieldInteger64(f, k[7], l->parent);
    if (k[8] >= 0)
        OGR_F_SetFieldInteger(f, k[8], l->bridged);
    if (k[9] >= 0 && l->width > 0 && isfinite(l->width))
        OGR_F_SetFieldDouble(f, k[9], l->width);
    if (k[10] >= 0)
        OGR_F_SetFieldInteger(f, k[10], !!l->depression);
    if (k[11] >= 0 && l->ink > 0 && isfinite(l->ink))
        OGR_F_SetFieldDouble(f, k[11], l->ink);
    if (k[12] >= 0)
        OGR_F_SetFieldInteger(f, k[12], !!l->piece);
}

/* l's geometry in map coordinates (closed lines repeat their first point;
 * a one-point line is doubled); with z, every vertex at the line's height
 * (0 without one).  NULL on a non-finite coordinate. */
static OGRGeometryH make_geometry(const td_line *l, const td_georef *g,
                                  int z)
{
    OGRGeometryH geo = OGR_G_CreateGeometry(z ? wkbLineString25D
                                              : wkbLineString);
    double h = l->has_height && isfinite(l->height) ? l->height : 0.0;
    size_t i, n = l->n + (l->n == 1 || (l->closed && l->n >= 2));
    for (i = 0; geo && i < n; i++) {
        size_t k = i < l->n ? i : 0;
        double X, Y;
        td_georef_apply(g, l->xy[2 * k], l->xy[2 * k + 1], &X, &Y);
        if (!isfinite(X) || !isfinite(Y)) {
            OGR_G_DestroyGeometry(geo);
            return NULL;
        }
        if (z)
            OGR_G_AddPoint(geo, X, Y, h);
        else
            OGR_G_AddPoint_2D(geo, X, Y);
    }
    return geo;
}

static int write_features(OGRLayerH lyr, const void *data,
                          const td_georef *g, vformat fmt, const char *path,
                          td_ctx *cx)
{
    const td_lines *ls = data;
    OGRFeatureDefnH d = OGR_L_GetLayerDefn(lyr);
    int layer = OGR_FD_GetFieldIndex(d, "Layer");
    size_t i;
    for (i = 0; i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        OGRFeatureH f;
        OGRGeometryH geo;
        OGRErr e;
        if (l->n == 0)
            continue;
        if (!(geo = make_geometry(l, g, fmt == VF_DXF)))
            return td_seterr(cx, TD_EINVAL, "%s: line %ld has a non-finite "
                             "coordinate", path, l->id);
        f = OGR_F_Create(d);
        if (fmt == VF_DXF) {
            if (layer >= 0)
                OGR_F_SetFieldString(f, layer, l->has_height
                                     ? "contours" : "contours_unlabelled");
        } else {
            set_fields(f, d, l);
        }
        OGR_F_SetGeometryDirectly(f, geo);
        e = OGR_L_CreateFeature(lyr, f);
        OGR_F_Destroy(f);
        if (e != OGRERR_NONE)
            return gdal_fail(cx, path, "cannot write a line");
    }
    return 0;
}

/* The files GDAL made in dir, renamed next to path: base.ext -> path's
 * stem + ext.  The file named like path goes last. */
static int move_out(const char *dir, const char *base, const char *path,
                    vformat fmt, td_ctx *cx)
{
    static const char *const shp[] = {".shx", ".dbf", ".prj", ".cpg", ".shp"};
    static const char *const one[] = {""};
    const char *const *ext = fmt == VF_SHP ? shp : one;
    size_t i, n = fmt == VF_SHP ? 5 : 1, stem = strlen(path) - 4;
    size_t bstem = strlen(base) - 4;
    for (i = 0; i < n; i++) {
        char from[PATH_MAX], to[PATH_MAX];
        int a, b;
        if (fmt == VF_SHP) {
            a = snprintf(from, sizeof from, "%s/%.*s%s", dir, (int)bstem,
                         base, ext[i]);
            b = snprintf(to, sizeof to, "%.*s%s", (int)stem, path, ext[i]);
        } else {
            a = snprintf(from, sizeof from, "%s/%s", dir, base);
            b = snprintf(to, sizeof to, "%s", path);
        }
        if (a < 0 || b < 0 || a >= (int)sizeof from || b >= (int)sizeof to)
            return td_seterr(cx, TD_EINVAL, "%s: path too long", path);
        if (access(from, F_OK) != 0)
            continue;
        if (fmt == VF_SHP && (i < n - 1) &&
            td_atomic_check_target(to, cx) != 0)
            return cx->code;
        if (rename(from, to) != 0)
            return td_seterr(cx, TD_EIO, "%s: cannot rename the finished "
                             "file into place: %s", to, strerror(errno));
    }
    return 0;
}

/* Remove dir and what GDAL left in it (a failed write). */
static void remove_tmpdir(const char *dir, const char *base)
{
    static const char *const ext[] = {"", ".shx", ".dbf", ".prj", ".cpg",
                                      ".shp", "-journal", "-wal", "-shm"};
    size_t i, bstem = strlen(base) > 4 ? strlen(base) - 4 : 0;
    char p[PATH_MAX];
    for (i = 0; i < sizeof ext / sizeof ext[0]; i++) {
        int a = snprintf(p, sizeof p, "%s/%s%s", dir, base, ext[i]);
        if (a > 0 && a < (int)sizeof p)
            unlink(p);
        a = snprintf(p, sizeof p, "%s/%.*s%s", dir, (int)bstem, base, ext[i]);
        if (a > 0 && a < (int)sizeof p)
            unlink(p);
    }
    rmdir(dir);
}

/* What one layer holds: its name and geometry type, its fields, its
 * features. */
typedef struct layer_spec {
    const char *name;
    OGRwkbGeometryType type;
    int (*fields)(OGRLayerH lyr);   /* NULL: none */
    int (*features)(OGRLayerH lyr, const void *data, const td_georef *g,
                    vformat fmt, const char *path, td_ctx *cx);
    const void *data;
} layer_spec;

static int write_ogr(const char *path, const layer_spec *L,
                     const td_georef *g, vformat fmt, td_ctx *cx)
{
    char dir[PATH_MAX], file[PATH_MAX];
    const char *slash = strrchr(path, '/'), *base = slash ? slash + 1 : path;
    GDALDriverH drv;
    GDALDatasetH ds = NULL;
    OGRSpatialReferenceH srs = NULL;
    OGRLayerH lyr;
    int rc;
    if ((rc = td_atomic_check_target(path, cx)) != 0)
        return rc;
    if (snprintf(dir, sizeof dir, "%s.tmp.XXXXXX", path) >= (int)sizeof dir)
        return td_seterr(cx, TD_EINVAL, "%s: path too long", path);
    if (!mkdtemp(dir))
        return td_seterr(cx, TD_EIO, "%s: cannot write here: %s", path,
                         strerror(errno));
    if (snprintf(file, sizeof file, "%s/%s", dir, base) >= (int)sizeof file) {
        rmdir(dir);
        return td_seterr(cx, TD_EINVAL, "%s: path too long", path);
    }
    gdal_init();
    CPLPushErrorHandler(CPLQuietErrorHandler);
    CPLErrorReset();
    rc = TD_EIO;
    if (!(drv = GDALGetDriverByName(driver_of(fmt)))) {
        rc = td_seterr(cx, TD_EIO, "%s: GDAL has no %s driver", path,
                       driver_of(fmt));
        goto done;
    }
    if (!(ds = GDALCreate(drv, file, 0, 0, 0, GDT_Unknown, NULL))) {
        rc = gdal_fail(cx, path, "cannot create");
        goto done;
    }
    srs = make_srs(g);
    lyr = GDALDatasetCreateLayer(ds, L->name, srs, L->type, NULL);
    if (!lyr || (fmt != VF_DXF && L->fields && L->fields(lyr) != 0)) {
        rc = gdal_fail(cx, path, "cannot make the layer");
        goto done;
    }
    if ((rc = L->features(lyr, L->data, g, fmt, path, cx)) != 0)
        goto done;
    CPLErrorReset();
    GDALClose(ds); /* flushes: a full disk shows here */
    ds = NULL;
    rc = CPLGetLastErrorType() >= CE_Failure
             ? gdal_fail(cx, path, "cannot finish") : 0;
    if (rc == 0)
        rc = move_out(dir, base, path, fmt, cx);
done:
    if (ds)
        GDALClose(ds);
    if (srs)
        OSRDestroySpatialReference(srs);
    CPLPopErrorHandler();
    remove_tmpdir(dir, base);
    return rc;
}

/* See io.h. */
int td_vector_write_lines(const char *path, const td_lines *ls,
                          const td_georef *georef, td_ctx *cx)
{
    vformat f;
    if (!path || !ls)
        return td_seterr(cx, TD_EINVAL, "%s: no lines to write",
                         path ? path : "(null)");
    f = format_of(path);
    if (f == VF_GEOJSON)
        return td_geojson_write_lines(path, ls, georef, cx);
    if (f == VF_OTHER)
        return td_seterr(cx, TD_EINVAL, "%s: unknown vector format (use "
                         ".geojson, .gpkg, .shp or .dxf)", path);
    {
        const layer_spec L = {"contours", f == VF_DXF ? wkbLineString25D
                                                      : wkbLineString,
                              make_fields, write_features, ls};
        return write_ogr(path, &L, georef, f, cx);
    }
}

/* ---- 3-D paths (ridge and valley lines) ------------------------------ */

static int path_fields(OGRLayerH lyr)
{
    OGRFieldDefnH k = OGR_Fld_Create("kind", OFTString);
    OGRFieldDefnH t = OGR_Fld_Create("tree", OFTInteger64);
    OGRErr e1 = OGR_L_CreateField(lyr, k, TRUE);
    OGRErr e2 = OGR_L_CreateField(lyr, t, TRUE);
    OGR_Fld_Destroy(k);
    OGR_Fld_Destroy(t);
    return e1 == OGRERR_NONE && e2 == OGRERR_NONE ? 0 : -1;
}

static int path_features(OGRLayerH lyr, const void *data, const td_georef *g,
                         vformat fmt, const char *path, td_ctx *cx)
{
    const td_paths3 *P = data;
    OGRFeatureDefnH d = OGR_L_GetLayerDefn(lyr);
    int fk = OGR_FD_GetFieldIndex(d, fmt == VF_DXF ? "Layer" : "kind");
    int ft = OGR_FD_GetFieldIndex(d, "tree");
    size_t i, k;
    for (i = 0; i < P->n; i++) {
        const td_path3 *q = &P->v[i];
        OGRGeometryH geo = OGR_G_CreateGeometry(wkbLineString25D);
        OGRFeatureH f;
        OGRErr e;
        for (k = 0; k < q->n; k++) {
            double X, Y;
            td_georef_apply(g, q->xyz[3 * k], q->xyz[3 * k + 1], &X, &Y);
            OGR_G_AddPoint(geo, X, Y, q->xyz[3 * k + 2]);
        }
        f = OGR_F_Create(d);
        if (fk >= 0 && q->kind)
            OGR_F_SetFieldString(f, fk, q->kind);
        if (ft >= 0 && q->tree >= 0)
            OGR_F_SetFieldInteger64(f, ft, q->tree);
        OGR_F_SetGeometryDirectly(f, geo);
        e = OGR_L_CreateFeature(lyr, f);
        OGR_F_Destroy(f);
        if (e != OGRERR_NONE)
            return gdal_fail(cx, path, "cannot write a path");
    }
    return 0;
}

/* One path as a GeoJSON feature: [x, y, z] positions and the properties
 * kind, tree and heights. */
static void put_path(FILE *f, const td_path3 *q, const td_georef *g)
{
    size_t i;
    fprintf(f, "{\"type\":\"Feature\",\"properties\":{\"kind\":\"%s\","
            "\"tree\":", q->kind ? q->kind : "");
    if (q->tree >= 0)
        fprintf(f, "%ld", q->tree);
    else
        fputs("null", f);
    fputs(",\"heights\":[", f);
    for (i = 0; i < q->n; i++)
        fprintf(f, "%s%.10g", i ? "," : "", q->xyz[3 * i + 2]);
    fputs("]},\"geometry\":{\"type\":\"LineString\",\"coordinates\":[", f);
    for (i = 0; i < q->n; i++) {
        double x, y;
        td_georef_apply(g, q->xyz[3 * i], q->xyz[3 * i + 1], &x, &y);
        fprintf(f, "%s[%.10g,%.10g,%.10g]", i ? "," : "", x, y,
                q->xyz[3 * i + 2]);
    }
    fputs("]}}", f);
}

static int write_paths_geojson(const char *path, const td_paths3 *P,
                               const td_georef *g, td_ctx *cx)
{
    size_t i, tmpsize = strlen(path) + 32;
    char *tmp = td_malloc(tmpsize, cx), crs[320];
    FILE *f;
    int rc;
    if (!tmp)
        return TD_ENOMEM;
    if (!(f = td_atomic_open(path, tmp, tmpsize, cx))) {
        free(tmp);
        return cx && cx->code ? cx->code : TD_EIO;
    }
    td_georef_crs_json(g, crs, sizeof crs);
    fprintf(f, "{\"type\":\"FeatureCollection\",\n%s,\n\"features\":[\n", crs);
    for (i = 0; i < P->n; i++) {
        if (i)
            fputs(",\n", f);
        put_path(f, &P->v[i], g);
    }
    fputs("\n]}\n", f);
    rc = td_atomic_commit(f, tmp, path, cx);
    free(tmp);
    return rc;
}

/* See io.h. */
int td_vector_write_paths(const char *path, const td_paths3 *P,
                          const td_georef *georef, td_ctx *cx)
{
    size_t i, k;
    vformat f = format_of(path);
    for (i = 0; i < P->n; i++)
        for (k = 0; k < 3 * P->v[i].n; k++)
            if (!isfinite(P->v[i].xyz[k]))
                return td_seterr(cx, TD_EINVAL, "%s: a path has a "
                                 "non-finite coordinate", path);
    if (f == VF_GEOJSON)
        return write_paths_geojson(path, P, georef, cx);
    if (f == VF_OTHER)
        return td_seterr(cx, TD_EINVAL, "%s: unknown vector format (use "
                         ".geojson, .gpkg, .shp or .dxf)", path);
    {
        const layer_spec L = {"paths", wkbLineString25D, path_fields,
                              path_features, P};
        return write_ogr(path, &L, georef, f, cx);
    }
}

/* ---- reading ---------------------------------------------------------- */

/* The layer's frame as a georef: the pixel frame when its CRS is topodig's
 * (or a DXF, which has none: read as written); identity with the EPSG
 * code when it names one; else invalid (coordinates as they are). */
static void layer_frame(OGRLayerH lyr, td_georef *frame)
{
    OGRSpatialReferenceH s = OGR_L_GetSpatialRef(lyr);
    const char *name = s ? OSRGetName(s) : NULL;
    const char *auth = s ? OSRGetAuthorityName(s, NULL) : NULL;
    const char *code = s ? OSRGetAuthorityCode(s, NULL) : NULL;
    td_georef_init(frame);
    if (name && strstr(name, TD_PIXEL_CRS)) {
        td_georef_pixel_frame(frame);
    } else if (auth && code && !strcasecmp(auth, "EPSG")) {
        frame->valid = 1;
        frame->gt[5] = 1.0; /* identity */
        frame->epsg = atoi(code);
    }
}

/* Map -> pixel units: the pixel frame's inverse when the file is in it,
 * else the caller's real georef's inverse, else as they are. */
static int to_pixels(const td_georef *frame, const td_georef *g, double X,
                     double Y, double *x, double *y)
{
    if (frame->pixel) {
        *x = X;
        *y = -Y;
    } else if (g && g->valid && !g->pixel) {
        double a = g->gt[1], b = g->gt[2], c = g->gt[4], d = g->gt[5];
        double det = a * d - b * c;
        X -= g->gt[0];
        Y -= g->gt[3];
        *x = (d * X - b * Y) / det;
        *y = (-c * X + a * Y) / det;
    } else {
        *x = X;
        *y = Y;
    }
    return isfinite(*x) && isfinite(*y) && fabs(*x) < 1e9 && fabs(*y) < 1e9
               ? 0
               : -1;
}

static int field_index(OGRFeatureDefnH d, const char *name)
{
    char n[11];
    int k = OGR_FD_GetFieldIndex(d, name);
    snprintf(n, sizeof n, "%s", name);
    return k >= 0 ? k : OGR_FD_GetFieldIndex(d, n);
}

/* One LineString part as a new line with f's properties. */
static int add_part(td_lines *ls, OGRGeometryH part, OGRFeatureH f,
                    long id, const td_georef *frame, const td_georef *g,
                    const char *path, td_ctx *cx)
{
    OGRFeatureDefnH d = OGR_F_GetDefnRef(f);
    int n = OGR_G_GetPointCount(part), i, k, eq;
    td_line *l;
    if (n <= 0)
        return 0;
    if (!(l = td_lines_add(ls, cx)))
        return TD_ENOMEM;
    l->id = id;
    for (i = 0; i < n; i++) {
        double x, y;
        if (to_pixels(frame, g, OGR_G_GetX(part, i), OGR_G_GetY(part, i),
                      &x, &y) != 0)
            return td_seterr(cx, TD_EFORMAT, "%s: feature %ld has a "
                             "coordinate out of range", path, id);
        if (td_line_push(l, x, y, cx) != 0)
            return TD_ENOMEM;
    }
    eq = l->n >= 2 && l->xy[0] == l->xy[2 * l->n - 2] &&
         l->xy[1] == l->xy[2 * l->n - 1];
    k = field_index(d, "closed");
    l->closed = k >= 0 && OGR_F_IsFieldSetAndNotNull(f, k)
                    ? OGR_F_GetFieldAsInteger(f, k) != 0 : eq;
    if (eq && (l->closed || l->n == 2))
        l->n--;
    if ((k = field_index(d, "height")) >= 0) {
        if (OGR_F_IsFieldSetAndNotNull(f, k)) {
            l->has_height = 1;
            l->height = OGR_F_GetFieldAsDouble(f, k);
        }
    } else if ((k = field_index(d, "Layer")) >= 0 &&
               OGR_G_Is3D(part) &&
               strcmp(OGR_F_GetFieldAsString(f, k), "contours_unlabelled")) {
        l->has_height = 1; /* DXF: the polyline's elevation */
        l->height = OGR_G_GetZ(part, 0);
    }
    if (l->has_height && !isfinite(l->height))
        return td_seterr(cx, TD_EFORMAT, "%s: feature %ld has a non-finite "
                         "height", path, id);
    if ((k = field_index(d, "edge")) >= 0)
        l->edge = OGR_F_GetFieldAsInteger(f, k) != 0;
    if ((k = field_index(d, "parent")) >= 0 && OGR_F_IsFieldSetAndNotNull(f, k))
        l->parent = (long)OGR_F_GetFieldAsInteger64(f, k);
    if ((k = field_index(d, "bridged")) >= 0)
        l->bridged = OGR_F_GetFieldAsInteger(f, k);
    if ((k = field_index(d, "width")) >= 0 && OGR_F_IsFieldSetAndNotNull(f, k))
        l->width = OGR_F_GetFieldAsDouble(f, k);
    if ((k = field_index(d, "ink")) >= 0 && OGR_F_IsFieldSetAndNotNull(f, k)) {
        double v = OGR_F_GetFieldAsDouble(f, k);
        l->ink = isfinite(v) && v > 0 && v <= 1 ? v : 0.0;
    }
    if ((k = field_index(d, "depression")) >= 0)
        l->depression = l->closed && OGR_F_GetFieldAsInteger(f, k) != 0;
    if ((k = field_index(d, "piece")) >= 0)
        l->piece = !l->closed && OGR_F_GetFieldAsInteger(f, k) != 0;
    return 0;
}

static int read_features(OGRLayerH lyr, const td_georef *frame,
                         const td_georef *g, td_lines *ls, size_t *skipped,
                         const char *path, td_ctx *cx)
{
    OGRFeatureH f;
    long serial = 0;
    int rc = 0;
    OGR_L_ResetReading(lyr);
    while (rc == 0 && (f = OGR_L_GetNextFeature(lyr)) != NULL) {
        OGRGeometryH geo = OGR_F_GetGeometryRef(f);
        OGRFeatureDefnH d = OGR_F_GetDefnRef(f);
        int k = field_index(d, "id"), i;
        long id = k >= 0 && OGR_F_IsFieldSetAndNotNull(f, k)
                      ? (long)OGR_F_GetFieldAsInteger64(f, k) : serial;
        OGRwkbGeometryType t = geo ? wkbFlatten(OGR_G_GetGeometryType(geo))
                                   : wkbUnknown;
        serial++;
        if (t == wkbLineString) {
            rc = add_part(ls, geo, f, id, frame, g, path, cx);
        } else if (t == wkbMultiLineString) {
            for (i = 0; rc == 0 && i < OGR_G_GetGeometryCount(geo); i++)
                rc = add_part(ls, OGR_G_GetGeometryRef(geo, i), f, id, frame,
                              g, path, cx);
        } else {
            (*skipped)++;
        }
        OGR_F_Destroy(f);
    }
    return rc;
}

/* 1 when the layer has points and none with Y > 0: a file without a CRS
 * in the pixel frame (Y = -row), not pixel units y down. */
static int all_y_negative(OGRLayerH lyr)
{
    OGREnvelope e;
    return OGR_L_GetExtent(lyr, &e, TRUE) == OGRERR_NONE && e.MaxY <= 0.0 &&
           e.MinY < 0.0;
}

/* Does the GeoJSON file name a CRS (a "crs" member in its first 64 KB,
 * where writers put it)? */
static int names_crs(const char *path)
{
    char buf[65536];
    size_t n;
    FILE *f = fopen(path, "rb");
    if (!f)
        return 0;
    n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = '\0';
    return strstr(buf, "\"crs\"") != NULL;
}

/* Open path's layer (the one named `name` when given and present, else
 * the first) and its frame: the layer's CRS, or the pixel frame when it
 * names none, no real georef maps it and every Y is <= 0 (a DXF or a
 * GeoJSON without a CRS, in the pixel frame).  GDAL's own messages are
 * silenced first thing (the caller pops the handler, whatever happens). */
static int open_layer(const char *path, const char *name, const td_georef *g,
                      GDALDatasetH *ds, OGRLayerH *lyr, td_georef *fr,
                      td_ctx *cx)
{
    int rc;
    *ds = NULL;
    td_georef_init(fr);
    CPLPushErrorHandler(CPLQuietErrorHandler);
    if ((rc = td_check_input(path, cx)) != 0)
        return rc;
    gdal_init();
    CPLErrorReset();
    *ds = GDALOpenEx(path, GDAL_OF_VECTOR | GDAL_OF_READONLY, NULL, NULL, NULL);
    if (!*ds)
        return gdal_fail(cx, path, "not a readable vector file");
    *lyr = name ? GDALDatasetGetLayerByName(*ds, name) : NULL;
    if (!*lyr && !(*lyr = GDALDatasetGetLayer(*ds, 0)))
        return td_seterr(cx, TD_EFORMAT, "%s: no layer", path);
    layer_frame(*lyr, fr);
    if (format_of(path) == VF_GEOJSON && !names_crs(path))
        td_georef_init(fr); /* OGR says WGS 84 for GeoJSON without one */
    if (!fr->valid && !(g && g->valid && !g->pixel) && all_y_negative(*lyr))
        td_georef_pixel_frame(fr);
    return 0;
}

/* After open_layer: close, restore GDAL's error handler, hand out the
 * skipped count and the frame (or clear it). */
static void close_layer(GDALDatasetH ds, size_t *skipped, size_t sk,
                        td_georef *frame, td_georef *fr)
{
    if (ds)
        GDALClose(ds);
    CPLPopErrorHandler();
    if (skipped)
        *skipped = sk;
    if (frame)
        *frame = *fr;
    else
        td_georef_clear(fr);
}

static int read_ogr(const char *path, const td_georef *g, td_lines **out,
                    size_t *skipped, td_georef *frame, td_ctx *cx)
{
    GDALDatasetH ds;
    OGRLayerH lyr;
    td_georef fr;
    size_t sk = 0;
    int rc;
    if ((rc = open_layer(path, "contours", g, &ds, &lyr, &fr, cx)) != 0)
        goto done;
    if (!(*out = td_lines_new(cx))) {
        rc = TD_ENOMEM;
        goto done;
    }
    if ((rc = read_features(lyr, &fr, g, *out, &sk, path, cx)) != 0) {
        td_lines_free(*out);
        *out = NULL;
    }
done:
    close_layer(ds, skipped, sk, frame, &fr);
    return rc;
}

/* See io.h. */
int td_vector_read_lines(const char *path, const td_georef *georef,
                         td_lines **out, size_t *skipped, td_georef *frame,
                         td_ctx *cx)
{
    vformat f;
    if (!path || !out)
        return td_seterr(cx, TD_EINVAL, "no vector file name given");
    *out = NULL;
    if (frame)
        td_georef_init(frame);
    f = format_of(path);
    if (f == VF_GEOJSON || f == VF_OTHER)
        return td_geojson_read_lines_frame(path, georef, out, skipped, frame,
                                           cx);
    return read_ogr(path, georef, out, skipped, frame, cx);
}

/* ---- 3-D lines --------------------------------------------------------- */

/* Part `part` of feature f appended to *ls with a height per vertex in *z:
 * the geometry's z when it is 3-D, else the feature's "heights" list (one
 * per vertex), else its "height", else NaN. */
static int add_part_z(td_lines *ls, double **z, size_t *nz, size_t *cz,
                      OGRGeometryH part, OGRFeatureH f, long id,
                      const td_georef *frame, const td_georef *g,
                      const char *path, td_ctx *cx)
{
    OGRFeatureDefnH d = OGR_F_GetDefnRef(f);
    int n = OGR_G_GetPointCount(part), i, k, nl = 0;
    const double *list = NULL;
    double one = NAN;
    td_line *l;
    if (n <= 0)
        return 0;
    if ((k = field_index(d, "heights")) >= 0 &&
        OGR_F_IsFieldSetAndNotNull(f, k))
        list = OGR_F_GetFieldAsDoubleList(f, k, &nl);
    if ((k = field_index(d, "height")) >= 0 &&
        OGR_F_IsFieldSetAndNotNull(f, k))
        one = OGR_F_GetFieldAsDouble(f, k);
    if (!(l = td_lines_add(ls, cx)))
        return TD_ENOMEM;
    l->id = id;
    if (*nz + (size_t)n > *cz) {
        size_t nc = *cz ? 2 * *cz : 1024;
        double *t;
        while (nc < *nz + (size_t)n)
            nc *= 2;
        if (!(t = realloc(*z, nc * sizeof *t)))
            return td_seterr(cx, TD_ENOMEM, "out of memory");
        *z = t, *cz = nc;
    }
    for (i = 0; i < n; i++) {
        double x, y, h = OGR_G_Is3D(part) ? OGR_G_GetZ(part, i)
                         : list && nl == n ? list[i] : one;
        if (to_pixels(frame, g, OGR_G_GetX(part, i), OGR_G_GetY(part, i),
                      &x, &y) != 0 || isinf(h) || fabs(h) > 1e12)
            return td_seterr(cx, TD_EFORMAT, "%s: feature %ld has a "
                             "coordinate or height out of range", path, id);
        if (td_line_push(l, x, y, cx) != 0)
            return TD_ENOMEM;
        (*z)[(*nz)++] = h;
    }
    return 0;
}

/* See io.h. */
int td_vector_read_lines_z(const char *path, const td_georef *georef,
                           const char *kind, td_lines **out, double **z,
                           size_t *skipped, td_georef *frame, td_ctx *cx)
{
    GDALDatasetH ds;
    OGRLayerH lyr;
    OGRFeatureH f;
    td_georef fr;
    size_t sk = 0, nz = 0, cz = 0;
    long serial = 0;
    int rc = 0;
    *out = NULL, *z = NULL;
    if ((rc = open_layer(path, NULL, georef, &ds, &lyr, &fr, cx)) != 0)
        goto done;
    if (!(*out = td_lines_new(cx))) {
        rc = TD_ENOMEM;
        goto done;
    }
    OGR_L_ResetReading(lyr);
    while (rc == 0 && (f = OGR_L_GetNextFeature(lyr)) != NULL) {
        OGRGeometryH geo = OGR_F_GetGeometryRef(f);
        OGRwkbGeometryType t = geo ? wkbFlatten(OGR_G_GetGeometryType(geo))
                                   : wkbUnknown;
        int i, k = kind ? field_index(OGR_F_GetDefnRef(f), "kind") : -1;
        if (k >= 0 && OGR_F_IsFieldSetAndNotNull(f, k) &&
            strcmp(OGR_F_GetFieldAsString(f, k), kind))
            t = wkbUnknown; /* another kind of line: skipped */
        if (t == wkbLineString) {
            rc = add_part_z(*out, z, &nz, &cz, geo, f, serial, &fr, georef,
                            path, cx);
        } else if (t == wkbPolygon && OGR_G_GetGeometryCount(geo) > 0) {
            /* the outer ring, as a closed line (holes: not read) */
            rc = add_part_z(*out, z, &nz, &cz, OGR_G_GetGeometryRef(geo, 0),
                            f, serial, &fr, georef, path, cx);
            if (rc == 0) {
                td_line *l = &(*out)->v[(*out)->n - 1];
                if (l->n >= 2 && l->xy[0] == l->xy[2 * l->n - 2] &&
                    l->xy[1] == l->xy[2 * l->n - 1])
                    l->n--, nz--;
                l->closed = 1;
            }
        } else if (t == wkbMultiLineString) {
            for (i = 0; rc == 0 && i < OGR_G_GetGeometryCount(geo); i++)
                rc = add_part_z(*out, z, &nz, &cz, OGR_G_GetGeometryRef(geo, i),
                                f, serial, &fr, georef, path, cx);
        } else {
            sk++;
        }
        serial++;
        OGR_F_Destroy(f);
    }
    if (rc) {
        td_lines_free(*out);
        free(*z);
        *out = NULL, *z = NULL;
    }
done:
    close_layer(ds, skipped, sk, frame, &fr);
    return rc;
}
