/* erode_int.h: what src/erode/erode.c (driver, erosion, transport) and
 * src/erode/erode_particles.c (the particles' velocity field) share.  Not public. */
#ifndef TD_ERODE_INT_H
#define TD_ERODE_INT_H

#include "src/erode/erode.h"

/* Fixed-point scale of the gathered velocity and energy sums: integer sums
 * are exact and order-free, so any thread count gives the same bytes. */
#define ER_FX 4294967296.0

/* Per cell, from the terrain of this step: the acceleration a (toward the
 * lowest steepest lower neighbour, 0 when there is none) and the height
 * gradient g (for the tangent plane). */
typedef struct er_surf {
    float ax, ay, az, gx, gy;
    int32_t wall; /* nodata: particles never enter it */
} er_surf;

/* Per cell and thread: particle visits and fixed-point sums of the visiting
 * particles' horizontal velocity, horizontal speed and collision energy. */
typedef struct er_acc {
    int64_t n, vx, vy, sp, e;
} er_acc;

typedef struct er_state {
    int w, h, nthreads;
    size_t n;
    double *T;        /* heights (double inside the stage) */
    uint8_t *wall;    /* 1 = nodata cell */
    er_surf *surf;    /* n */
    er_acc *acc;      /* n * nthreads; acc[0..n) holds the reduced sums */
    double *sq, *se, *smax, *sin, *dep, *dep_total;
    double *snd;      /* lowest height of a cell that sent sediment here */
    double *fill;     /* TD_ERODE_DEPOSIT_LEVEL: T with depressions filled */
    int32_t *ord, *par, *heap; /* flood: pop rank, parent (-2 out), heap */
    int32_t *recv;    /* receiver of the sediment: index, -1 none, -2 out */
    int32_t *indeg, *queue;
} er_state;

/* STEP2-1 (erode_particles.c): fill s->surf from s->T; trace one particle from
 * every non-wall cell and leave the gathered sums in s->acc[0..n).  *moves
 * and *drained get the particle moves and the particles that left the grid. */
void er_surface(er_state *s, const td_erode_params *p);
void er_velocity_field(er_state *s, const td_erode_params *p, int64_t *moves,
                       int64_t *drained);

#endif
