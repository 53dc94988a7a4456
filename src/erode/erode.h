/* erode.h: velocity-field hydraulic erosion (Fujita, Muraoka, Chiba, "An
 * erosion model based on simulated velocity fields for visually simulating
 * mountain scenery", §2; ALGORITHMS.md C1).
 *
 * Each step puts one water particle on every cell, traces every particle
 * independently over the terrain (acceleration toward the lowest steepest
 * neighbour, friction, projection onto the surface tangent, collision
 * energy), gathers the water W, mean velocity V and collision energy E of
 * every cell, then erodes (Kq Q + Ke e), transports up to Kc Q^m along V
 * and deposits the rest.  Results do not depend on the thread count: the
 * gathered fields are exact integer (fixed-point) sums.
 *
 * Units: heights in the DEM's height unit, horizontal distances in the same
 * unit through `cell` (the cell size); time in steps of dt. */
#ifndef TD_ERODE_H
#define TD_ERODE_H

#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct td_erode_step_stats {
    int step;            /* 1-based step just finished */
    double eroded;       /* volume removed (flow + collision), height*area */
    double eroded_flow;  /* of which by flow, Kq Q */
    double eroded_coll;  /* of which by collision, Ke e */
    double deposited;    /* volume deposited */
    double outflow;      /* sediment volume carried out of the grid */
    double moves;        /* particle moves (one dt update of one particle) */
    double particles;    /* particles traced */
    double drained;      /* particles that left the grid over an open edge */
} td_erode_step_stats;

/* Called after every step; dem is the current terrain on snapshot steps
 * (every snapshot_every steps) and NULL otherwise.  Return nonzero to stop
 * (the stage then fails with TD_ECANCEL). */
typedef int (*td_erode_step_fn)(const td_erode_step_stats *s,
                                const td_grid_f32 *dem, void *user);

/* Readings of what the paper leaves open (docs/erode.md, "Choices"). */
enum {
    TD_ERODE_ROUTE_DOWNHILL = 0, /* sediment goes along V only to a lower
                                    neighbour, else down the steepest
                                    descent, else it settles */
    TD_ERODE_ROUTE_PAPER = 1     /* along V to whichever neighbour, also
                                    uphill (the paper's words) */
};
enum {
    TD_ERODE_SPEED_MEAN = 0,  /* v in Q = C w v: mean speed of the visits */
    TD_ERODE_SPEED_VECTOR = 1 /* |mean velocity vector| (V as an array of
                                 vectors, literally) */
};
enum {
    TD_ERODE_DEPOSIT_PAPER = 0, /* S_I - Smax settles in the cell, all */
    TD_ERODE_DEPOSIT_LEVEL = 1  /* not the paper: no cell is dug below its
                                   lowest neighbour or raised past half-way
                                   to the lowest cell that fed it (the rest
                                   passes on); depressions fill to their
                                   spill level and spill over; a closed
                                   basin's sink spreads as a level lake.
                                   Resolution-independent (docs/erode.md) */
};

typedef struct td_erode_params {
    int steps;          /* repetitions of STEP2 (75) */
    double kq;          /* flow erosion Sq = Kq Q */
    double ke;          /* collision erosion Se = Ke e */
    double kc;          /* transport capacity Smax = Kc Q^m */
    double m;           /* exponent of the capacity */
    double alpha;       /* friction: 0 <= alpha <= 1 */
    double beta;        /* friction: beta > 0 */
    double gravity;     /* G */
    double dt;          /* time step of a particle move */
    double water;       /* water per cell: each particle's w (and m ~ w) */
    double c;           /* Q = C w v */
    double cell;        /* horizontal cell size in height units (1) */
    int max_moves;      /* moves per particle per step; 0: 2 (w + h) */
    double rest_accel;  /* ours: a particle below v_stop also rests where
                           its cell's acceleration is below this (a slope
                           too gentle to move it: it would creep there for
                           thousands of moves); 0: only where no
                           neighbour is lower, the paper (default 0) */
    double v_stop;      /* a particle with no lower neighbour stops below */
    int closed_edges;   /* 0: open edges drain; 1: the border is a wall */
    int route;          /* TD_ERODE_ROUTE_* (DOWNHILL) */
    int speed;          /* TD_ERODE_SPEED_* (MEAN) */
    int deposit;        /* TD_ERODE_DEPOSIT_* (PAPER) */
    int threads;        /* OpenMP threads; 0: the OpenMP default */
    int snapshot_every; /* pass the DEM to on_step every K steps; 0: never */
    td_erode_step_fn on_step; /* may be NULL */
    void *user;
} td_erode_params;

/* Totals over a run; residual = |eroded - deposited - outflow| / eroded
 * (0 when nothing was eroded), the largest per-step value in max_residual. */
typedef struct td_erode_stats {
    td_erode_step_stats total; /* sums over steps; total.step = steps run */
    double residual, max_residual;
    double path_mean;          /* mean particle path length, moves */
} td_erode_stats;

/* Optional output fields, caller-allocated with the DEM's size (any may be
 * NULL): water W and collision energy E of the last step, and the total
 * thickness of sediment deposited over the run. Nodata cells carry the
 * input's nodata value. */
typedef struct td_erode_fields {
    td_grid_f32 *water, *energy, *sediment;
} td_erode_fields;

/* The defaults documented in docs/erode.md. */
td_erode_params td_erode_defaults(void);

/* p's parameters carried from cell size p->cell to cell size `cell` (same
 * horizontal unit) so that the same terrain sampled at the other cell size
 * erodes alike (docs/erode.md, "Resolution").  With s = cell / p->cell:
 * dt * s, water * s^2, 1 - alpha := (1 - alpha) s, beta / s^2, C / s,
 * Kc / s, Ke / s^2, an explicit max_moves / s; G, Kq, m, v_stop unchanged.
 * Coarsening needs (1 - alpha) s <= 1: td_erode_check rejects the result
 * otherwise. */
td_erode_params td_erode_rescale(const td_erode_params *p, double cell);

/* Check p; 0 or TD_EINVAL with a message naming the parameter. */
int td_erode_check(const td_erode_params *p, td_ctx *cx);

/* Run p->steps steps of velocity-field erosion on `in` and write the eroded
 * terrain to `out` (caller-allocated, in's size; may not alias in).  Nodata
 * cells of `in` are walls and stay nodata.  fields and st may be NULL.
 * Progress: stage "erode", once per step.  Returns 0, TD_EINVAL (bad
 * parameters or sizes), TD_ENOMEM or TD_ECANCEL. */
int td_erode_run(const td_grid_f32 *in, const td_erode_params *p,
                 td_grid_f32 *out, td_erode_fields *fields,
                 td_erode_stats *st, td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
