/* pom_uncertain.h - probability distributions of uncertain inputs and the
 * per-maneuver draws of a study's `uncertain` group (docs/results.md,
 * section 10).
 *
 * A distribution is an op table whose one operation is the inverse CDF: a
 * value is drawn by mapping a uniform u in (0, 1) through it, so Monte-Carlo
 * draws, Sobol/Saltelli designs and Morris grids all go through the same
 * code. Draws of maneuver k come from a generator seeded by (study seed, k)
 * on a stream of their own, so every candidate sees the same draws and the
 * maneuver targets are those of a study without uncertainty. */
#ifndef POM_UNCERTAIN_H
#define POM_UNCERTAIN_H

#include "pom_config.h"
#include "pom_status.h"

#include <stdint.h>

/* ---- distributions --------------------------------------------------------- */
typedef struct pom_dist pom_dist;

/* What a distribution kind does. */
typedef struct {
  const char *name; /* config name: "uniform", "normal", ... */
  /* Inverse CDF at u in (0, 1). */
  double (*quantile)(const pom_dist *d, double u);
} pom_dist_ops;

/* One distribution. p[] meaning by kind (config units):
 * uniform (min, max); normal (mean, sd); truncated_normal (mean, sd, min,
 * max); lognormal (median, sigma_ln, min, max) with optional truncation
 * bounds (min = 0, max = inf when absent). */
struct pom_dist {
  const pom_dist_ops *ops;
  double p[4];   /* parameters, above */
  double lo, hi; /* smallest and largest value a draw can take */
};

/* Every registered kind, NULL-terminated (uniform, normal,
 * truncated_normal, lognormal). */
extern const pom_dist_ops *const pom_dist_kinds[];

/* Smallest and largest u a draw uses: draws map 52 random bits to the
 * centres (m + 1/2) 2^-52 (exact doubles), so no draw is 0 or 1. */
#define POM_DIST_U_MIN 0x1.0p-53
#define POM_DIST_U_MAX (1.0 - 0x1.0p-53)

/* Value of d at u; u is clamped into [POM_DIST_U_MIN, POM_DIST_U_MAX]. */
double pom_dist_quantile(const pom_dist *d, double u);

/* A uniform in (0, 1), never 0 or 1, from 64 random bits. */
double pom_dist_u_from_bits(uint64_t bits);

/* Builds a distribution of kind `name` from its parameters (NAN = absent
 * for the optional lognormal bounds); POM_ERR_ARG with a message when the
 * parameters are inconsistent. */
pom_status pom_dist_make(pom_dist *d, const char *name, const double p[4], pom_error *err);

/* Reads a distribution from the group at key (`dist` and its parameters,
 * docs/results.md section 10); messages name file, line and key. */
pom_status pom_dist_load(pom_dist *d, const pom_cfg *cfg, const char *key, pom_error *err);

/* ---- the `uncertain` group ------------------------------------------------- */
#define POM_UNC_MAX     16 /* uncertain parameters at most */
#define POM_UNC_KEY_LEN 64

typedef struct {
  char key[POM_UNC_KEY_LEN]; /* dotted numeric config key, e.g. "actuator.resistance_ohm" */
  pom_dist dist;             /* of the value (config units), or of the factor when relative */
  int relative;              /* 1: value = candidate's nominal value x draw */
  int controller_drawn;      /* 1: a model-based controller's own model takes the draw too; 0
                                (default, `controller = "nominal"`): it keeps the nominal value */
} pom_unc_param;

/* The uncertain parameters of a study and where unit k's draws come from. */
typedef struct {
  int n; /* parameters (0 = no uncertainty) */
  pom_unc_param param[POM_UNC_MAX];
  uint64_t seed; /* study seed (montecarlo.seed) */
  /* Design mode (pomlab sensitivity): unit k uses design row k / per_row
   * and maneuver k % per_row instead of random draws. */
  const double *design; /* [design_rows][n] u values in (0, 1), not owned; NULL = random */
  long design_rows;
  long per_row; /* maneuvers per design row */
} pom_unc;

/* Reads the optional `uncertain` list of cfg (absent: n = 0). seed is the
 * study seed. Only the distributions are checked here; the keys are checked
 * against each candidate by pom_doe_uncertain_check (pom_doe.h). */
pom_status pom_unc_load(pom_unc *unc, const pom_cfg *cfg, uint64_t seed, pom_error *err);

/* Unit k's maneuver index and u values u[n] in (0, 1): random mode, the
 * maneuver is k and u comes from a generator seeded by (seed, stream of
 * the uncertain draws + k); design mode, as said above. */
void pom_unc_unit(const pom_unc *unc, long k, long *maneuver, double *u);

/* Draws (distribution values) of unit k: x[n]. */
void pom_unc_draws(const pom_unc *unc, long k, double *x);

#endif
