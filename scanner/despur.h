/* despur.h: removal of the whisker-like spurs Hilditch thinning leaves on
 * thick lines.  Paper 001 §2.2; ALGORITHMS.md A.3. */
#ifndef TD_DESPUR_H
#define TD_DESPUR_H

#include "src/core/core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    TD_SPUR_LENGTH = 0, /* default: a branch from an end point to the first
                           junction is a spur if its length along the
                           skeleton is <= max_len px; repeated for `rounds` */
    TD_SPUR_PAPER,      /* the paper's rule: pair every end point with its
                           nearest junction (straight distance) and erase the
                           branch between them, whatever its length; once */
    TD_SPUR_NONE
} td_spur_mode;

typedef struct td_despur_params {
    td_spur_mode mode;
    double max_len; /* TD_SPUR_LENGTH: longest spur in px along the skeleton
                       (default 10) */
    int rounds;     /* TD_SPUR_LENGTH: rounds (spurs of spurs), default 3 */
} td_despur_params;

typedef struct td_despur_stats {
    size_t endpoints, junctions; /* found before the first round */
    size_t spurs;                /* branches erased */
    size_t pixels;               /* pixels erased */
} td_despur_stats;

td_despur_params td_despur_defaults(void);

/* "paper" | "length" | "none" -> p->mode; TD_EINVAL otherwise. */
int td_despur_parse_mode(const char *s, td_despur_params *p, td_ctx *cx);

/* Remove spurs from a thinned skeleton (cells 0/1) in place; junction
 * corners left 2 px thick are re-thinned (td_thin_hilditch_near).
 * st may be NULL.  Returns 0, TD_ENOMEM or TD_ECANCEL. */
int td_despur(td_grid_u8 *skel, const td_despur_params *p,
              td_despur_stats *st, td_ctx *cx);

#ifdef __cplusplus
}
#endif
#endif
