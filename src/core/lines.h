/* lines.h: contour polylines in memory and their GeoJSON form.
 *
 * Coordinates are in pixel units of the scan: x = column + 0.5, y = row + 0.5
 * for a pixel centre (x right, y down).  A closed line does NOT repeat its
 * first point in memory; the GeoJSON writer repeats it, as GeoJSON requires. */
#ifndef TD_LINES_H
#define TD_LINES_H

#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

struct td_georef;

/* Where a line's height came from (the labeller, scanner/label.h). */
typedef enum td_hsource {
    TD_HS_NONE = 0, /* not labelled by the solver (input, or no height) */
    TD_HS_KNOWN,    /* a known point (--known) lies on the line */
    TD_HS_LABEL,    /* a height label read from the sheet */
    TD_HS_SOLVED,   /* implied by the other evidence through the topology */
    TD_HS_ASSUMED   /* only a default (summits rise) decided it */
} td_hsource;

typedef struct td_line {
    double *xy;       /* x0,y0,x1,y1,...: n points */
    size_t n, cap;
    long id;          /* stable id, 0-based order of creation */
    int closed;       /* first and last point are joined */
    int edge;         /* a point lies on the sheet's border pixels */
    int bridged;      /* gaps bridged inside this line */
    int has_height;
    double height;
    long parent;      /* id of the enclosing line, -1 when none/unknown */
    double width;     /* ink width in px measured from the mask (the scanner,
                         scanner/width.h), 0 when not measured */
    unsigned char junc; /* the tracer (cut): bit 0 the first point, bit 1
                           the last ends next to a skeleton junction */
    int hsource;       /* td_hsource */
    double confidence; /* 0..1 that the height is right (with hsource) */
    const char *why;   /* static text: why the height is null, or NULL */
} td_line;

typedef struct td_lines {
    td_line *v;
    size_t n, cap;
} td_lines;

/* An empty set; free with td_lines_free (NULL is a no-op). */
td_lines *td_lines_new(td_ctx *cx);
void td_lines_free(td_lines *ls);

/* Append an empty line (id = its index, parent -1); returns it or NULL.
 * The pointer is valid until the next td_lines_add. */
td_line *td_lines_add(td_lines *ls, td_ctx *cx);
/* Append a point to a line; 0 or TD_ENOMEM. */
int td_line_push(td_line *l, double x, double y, td_ctx *cx);
/* Reverse a line's point order in place. */
void td_line_reverse(td_line *l);
/* Remove line i (order of the others kept; ids unchanged). */
void td_lines_remove(td_lines *ls, size_t i);
/* Length of the polyline (closing segment included when closed). */
double td_line_length(const td_line *l);

/* Append a copy of l to ls: its points and every property (id
 * included; td_lines_add's own id is overwritten).  0 or TD_ENOMEM. */
int td_lines_append_copy(td_lines *ls, const td_line *l, td_ctx *cx);

/* A new set with copies of every line of ls (free with td_lines_free);
 * NULL with the error in cx. */
td_lines *td_lines_copy(const td_lines *ls, td_ctx *cx);

/* Signed area of l taken as a closed polygon (shoelace, pixel units): > 0
 * when its points run clockwise on the screen (y down). */
double td_line_signed_area(const td_line *l);

/* Even-odd test of (x,y) against l taken as a closed polygon. */
int td_line_encloses(const td_line *l, double x, double y);

/* Write lines as a GeoJSON FeatureCollection of LineStrings, atomically.
 * Properties: id, height (null unless has_height), closed, edge, parent
 * (null when -1), bridged, width (px, only when measured, > 0), and when the
 * labeller set them height_source ("known", "label", "solved", "assumed"),
 * confidence (0..1) and height_reason (why the height is null).  When georef is valid, coordinates are mapped
 * through it and its EPSG code (if known) is named in a "crs" member, which
 * GDAL/OGR and QGIS read.  Returns 0 or an error naming the file. */
int td_geojson_write_lines(const char *path, const td_lines *ls,
                           const struct td_georef *georef, td_ctx *cx);

/* Read a GeoJSON FeatureCollection of LineString (and MultiLineString,
 * one line per part) features, as written by td_geojson_write_lines or
 * edited in QGIS: properties id, height (number or null), closed, edge,
 * parent, width are read when present (missing id: the feature's index; missing
 * closed: first point == last point, the repeated last point dropped).
 * When georef is valid, coordinates are map coordinates and are mapped back
 * to pixel units through its inverse.  Other geometry types are skipped
 * and counted in *skipped (may be NULL).  *out gets a new td_lines.
 * Errors name the file and the byte offset of bad JSON. */
int td_geojson_read_lines(const char *path, const struct td_georef *georef,
                          td_lines **out, size_t *skipped, td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
