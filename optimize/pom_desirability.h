/* pom_desirability.h - Derringer-Suich desirability functions for
 * multiple-response optimization (docs/optimize.md, section 3).
 *
 * Each response y_i gets an individual desirability d_i in [0, 1]; the
 * overall desirability is the weighted geometric mean
 * D = prod d_i^(r_i / sum r), r_i the importances. */
#ifndef POM_DESIRABILITY_H
#define POM_DESIRABILITY_H

#include "pom_status.h"

typedef enum {
  POM_DESIR_MAXIMIZE = 0, /* d = 0 below low, 1 above high, ((y-low)/(high-low))^s between */
  POM_DESIR_MINIMIZE = 1, /* d = 1 below low, 0 above high, ((high-y)/(high-low))^s between */
  POM_DESIR_TARGET = 2    /* 0 outside [low, high]; ((y-low)/(target-low))^s below target,
                             ((high-y)/(high-target))^t above */
} pom_desir_goal;

/* One response's desirability, in the response's own unit. */
typedef struct {
  pom_desir_goal goal;
  double low;        /* lower bound L */
  double target;     /* target T (POM_DESIR_TARGET only) */
  double high;       /* upper bound U */
  double shape_low;  /* exponent s (> 0) on the rising side (default 1) */
  double shape_high; /* exponent t (> 0) on the falling side of a target (default 1) */
  double importance; /* r_i > 0 in the overall geometric mean (default 1) */
} pom_desir_spec;

/* A spec with the given goal and bounds, shapes and importance 1. */
pom_desir_spec pom_desir_make(pom_desir_goal goal, double low, double target, double high);

/* Checks low < high (low < target < high for a target), positive shapes and
 * importance, finite numbers. `what` names the response in the message. */
pom_status pom_desir_validate(const pom_desir_spec *s, const char *what, pom_error *err);

/* Individual desirability d in [0, 1]; a non-finite y gives 0. */
double pom_desir_individual(const pom_desir_spec *s, double y);

/* Overall desirability of m responses y[m] with specs[m]; the individual
 * values go to d[m] when d is not NULL. */
double pom_desir_overall(int m, const pom_desir_spec specs[], const double y[], double d[]);

#endif
