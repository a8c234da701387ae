/* pom_design.h - experimental designs for response-surface studies: full
 * factorial, central composite (face-centred and rotatable), Box-Behnken and
 * maximin Latin hypercube (derivations and tables: docs/optimize.md, section 1).
 *
 * A design is a table of n runs by k factors in coded units. Every design but
 * the rotatable CCD lies in the cube [-1, 1]^k; the rotatable CCD reaches
 * +-alpha on its axial runs. pom_design_decode() maps the design's extreme
 * coded value (1, or alpha) onto the bounds of each factor, so no run ever
 * leaves the design-parameter box of the config (an "inscribed" design). */
#ifndef POM_DESIGN_H
#define POM_DESIGN_H

#include "pom_status.h"

#include <stdint.h>

#define POM_DESIGN_MAX_FACTORS 8 /* largest k of any design */

typedef enum {
  POM_DESIGN_FULL_FACTORIAL = 0, /* levels^k grid */
  POM_DESIGN_CCD_FACE = 1,       /* central composite, axial runs at +-1 */
  POM_DESIGN_CCD_ROTATABLE = 2,  /* central composite, alpha = (2^k)^(1/4) */
  POM_DESIGN_BOX_BEHNKEN = 3,    /* 3-level, 2^2 factorials on factor pairs, k = 3..5 */
  POM_DESIGN_LHS = 4             /* Latin hypercube, maximin over random candidates */
} pom_design_kind;

/* Options of a design. Set with pom_design_defaults(), then change fields. */
typedef struct {
  pom_design_kind kind;
  int levels;         /* full factorial: levels per factor, >= 2 (default 3) */
  int center_points;  /* runs at the centre added once (default 3 for every kind, LHS too:
                         set 0 for a pure Latin hypercube) */
  int replicates;     /* the whole design (without the centre runs) repeated, >= 1 (default 1) */
  int lhs_points;     /* LHS: number of runs (default 20) */
  int lhs_candidates; /* LHS: random hypercubes drawn; the one with the largest
                         smallest pairwise distance is kept (default 200) */
  uint64_t seed;      /* LHS: seed of the generator (default 2385) */
} pom_design_options;

/* A design in coded units. */
typedef struct {
  pom_design_kind kind;
  int k;         /* factors */
  int n;         /* runs */
  double alpha;  /* largest |coded value| (1, or the CCD axial distance) */
  double *coded; /* [n * k] row-major, run r factor j at coded[r * k + j] */
} pom_design;

/* Defaults described in pom_design_options. */
void pom_design_defaults(pom_design_options *opts);

/* Builds the design for k factors. POM_ERR_ARG for k outside the kind's range
 * (1..POM_DESIGN_MAX_FACTORS; Box-Behnken 3..5) or bad options. The caller
 * owns *out and frees it with pom_design_destroy(). */
pom_status pom_design_create(pom_design **out, int k, const pom_design_options *opts,
                             pom_error *err);

/* Frees; NULL allowed. */
void pom_design_destroy(pom_design *d);

/* Natural value of coded value c of a factor with bounds [lo, hi]: the coded
 * range [-alpha, alpha] maps onto [lo, hi]. */
double pom_design_to_natural(double c, double alpha, double lo, double hi);

/* Inverse of pom_design_to_natural. */
double pom_design_to_coded(double x, double alpha, double lo, double hi);

/* The whole design in natural units: natural[r * k + j] for bounds lo[j], hi[j]. */
void pom_design_decode(const pom_design *d, const double lo[], const double hi[], double natural[]);

/* Name of a kind ("ccd_rotatable"), never NULL. */
const char *pom_design_kind_name(pom_design_kind kind);

#endif
