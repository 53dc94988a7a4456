/* gen_int.h: internals shared by the generator's files (not public).
 *
 * A small seeded random generator (splitmix64): the state lives in a struct
 * the caller owns, so every random choice follows from td_gen_params.seed
 * and nothing is global. */
#ifndef TD_GEN_INT_H
#define TD_GEN_INT_H

#include <math.h>
#include <stdint.h>

typedef struct td_rng {
    uint64_t s;
} td_rng;

/* A generator seeded from seed and a stream number, so independent choices
 * (terrain, breaks, specks, noise) do not shift when one of them changes. */
static inline td_rng td_rng_make(unsigned seed, unsigned stream)
{
    td_rng r;
    r.s = ((uint64_t)seed << 32) ^ ((uint64_t)stream * 0x9E3779B97F4A7C15ull) ^
          0xD1B54A32D192ED03ull;
    return r;
}

static inline uint64_t td_rng_u64(td_rng *r)
{
    uint64_t z = (r->s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* Uniform in [0,1). */
static inline double td_rng_unit(td_rng *r)
{
    return (double)(td_rng_u64(r) >> 11) * (1.0 / 9007199254740992.0);
}

/* Uniform in [a,b). */
static inline double td_rng_range(td_rng *r, double a, double b)
{
    return a + (b - a) * td_rng_unit(r);
}

/* Uniform integer in [0,n), n > 0. */
static inline uint64_t td_rng_below(td_rng *r, uint64_t n)
{
    return td_rng_u64(r) % n;
}

#include "samples/gen/gen.h"

/* Ink layers are 8-bit coverage maps (0 none .. 255 full), w x h, stride w.
 * Draw segment (x0,y0)-(x1,y1) with radius r = width/2 + 0.5: a pixel whose
 * centre is at distance d gets coverage clamp(r - d, 0, 1), kept as the
 * maximum over everything drawn. */
void td_gen_draw_seg(uint8_t *lay, int w, int h, double x0, double y0,
                     double x1, double y1, double r);

/* The contour interval of truth lines: p->interval when > 0, else the
 * smallest difference between the heights of lines near in order. */
double td_gen_line_interval(const td_lines *lines, const td_gen_params *p);

/* The ink width line l is drawn with: p->index_width for an index contour
 * (height base + 5k * interval) when index_width > 0, else line_width. */
double td_gen_width_of(const td_line *l, const td_gen_params *p,
                       double interval);

/* Specks: p->specks blobs of 1..6 px at full coverage, each at least 4 px
 * from any coverage already in lay and 15 px from any break's middle. */
void td_gen_specks(uint8_t *lay, const td_gen_params *p, const td_gen_break *br,
                   size_t nbr);

/* The colour sheet's distractors over im (RGB): a blue river and black
 * text-like words, the words kept 4 px away from coverage in contours and
 * 15 px from breaks.  scratch is a zeroed w x h layer. */
void td_gen_distractors(td_image *im, const uint8_t *contours, uint8_t *scratch,
                        const td_gen_params *p, const td_gen_break *br,
                        size_t nbr);

/* The printed map's plates (samples/gen/print.c) into im (RGB, w x h),
 * contours the contour plate's coverage. */
int td_gen_print_plates(td_image *im, const uint8_t *contours,
                        const td_gen_params *p, const td_gen_break *br,
                        size_t nbr, td_ctx *cx);

/* Print ink colour col over im (RGB) with coverage lay: inks are filters
 * (coverage a of ink k turns v into v (1 - a (1 - k/255))). */
void td_gen_overprint(td_image *im, const uint8_t *lay, const uint8_t *col);

/* The drainage area, cells, from which tdgen --streams draws a stream:
 * (min(w, h) / 14)^2. */
double td_gen_stream_area(const td_gen_params *p);

/* With p->streams: the streams of the surface dem (the sheet's size) in
 * blue over im (RGB; overprinted with p->print, else painted), see
 * samples/gen/streams.c.  Returns 0, TD_EINVAL (sizes), TD_ENOMEM. */
int td_gen_streams(const td_gen_params *p, const td_grid_f32 *dem, td_image *im,
                   td_ctx *cx);

/* What the scanner does to a rendered sheet, in place: with p->print the
 * paper's ageing and colour fringing; blur (p->blur) and noise (p->noise);
 * with p->print JPEG at quality 75. */
int td_gen_scan_effects(td_image *im, const td_gen_params *p, td_ctx *cx);

/* td_gen_render without td_gen_scan_effects (labels are cut in first). */
int td_gen_render_clean(const td_lines *lines, const td_gen_params *p,
                        td_image **sheet, td_ctx *cx);

/* Paint colour col (channels of im) over im with coverage lay. */
void td_gen_composite(td_image *im, const uint8_t *lay, const uint8_t *col);

/* Separable Gaussian blur of every channel, in place. */
int td_gen_blur(td_image *im, double sigma, td_ctx *cx);

/* Add Gaussian noise of sd grey levels (seeded), rounding and clamping. */
void td_gen_noise(td_image *im, double sd, unsigned seed);

#ifndef TD_PI
#define TD_PI 3.14159265358979323846
#endif

#endif
