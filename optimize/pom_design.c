/* pom_design.c - experimental designs in coded units (docs/optimize.md, section 1). */
#include "pom_design.h"

#include "pom_rng.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- options and names -------------------------------------------------- */
void pom_design_defaults(pom_design_options *opts) {
  memset(opts, 0, sizeof *opts);
  opts->kind = POM_DESIGN_CCD_FACE;
  opts->levels = 3;
  opts->center_points = 3;
  opts->replicates = 1;
  opts->lhs_points = 20;
  opts->lhs_candidates = 200;
  opts->seed = 2385;
}

const char *pom_design_kind_name(pom_design_kind kind) {
  switch (kind) {
  case POM_DESIGN_FULL_FACTORIAL:
    return "full_factorial";
  case POM_DESIGN_CCD_FACE:
    return "ccd_face";
  case POM_DESIGN_CCD_ROTATABLE:
    return "ccd_rotatable";
  case POM_DESIGN_BOX_BEHNKEN:
    return "box_behnken";
  case POM_DESIGN_LHS:
    return "lhs";
  }
  return "unknown";
}

void pom_design_destroy(pom_design *d) {
  if (!d) return;
  free(d->coded);
  free(d);
}

double pom_design_to_natural(double c, double alpha, double lo, double hi) {
  return 0.5 * (lo + hi) + 0.5 * (hi - lo) * c / alpha;
}

double pom_design_to_coded(double x, double alpha, double lo, double hi) {
  return alpha * (x - 0.5 * (lo + hi)) / (0.5 * (hi - lo));
}

void pom_design_decode(const pom_design *d, const double lo[], const double hi[],
                       double natural[]) {
  for (int r = 0; r < d->n; ++r)
    for (int j = 0; j < d->k; ++j)
      natural[r * d->k + j] = pom_design_to_natural(d->coded[r * d->k + j], d->alpha, lo[j], hi[j]);
}

/* ---- building blocks ---------------------------------------------------- */
/* Number of runs of one replicate (without centre runs). */
static long base_runs(int k, const pom_design_options *o) {
  switch (o->kind) {
  case POM_DESIGN_FULL_FACTORIAL: {
    long n = 1;
    for (int j = 0; j < k; ++j)
      n *= o->levels;
    return n;
  }
  case POM_DESIGN_CCD_FACE:
  case POM_DESIGN_CCD_ROTATABLE:
    return (1L << k) + 2L * k;
  case POM_DESIGN_BOX_BEHNKEN:
    return 4L * k * (k - 1) / 2;
  case POM_DESIGN_LHS:
    return o->lhs_points;
  }
  return 0;
}

/* levels^k grid, first factor varying slowest. */
static void fill_factorial(double *rows, int k, int levels) {
  long n = 1;
  for (int j = 0; j < k; ++j)
    n *= levels;
  for (long r = 0; r < n; ++r) {
    long idx = r;
    for (int j = k - 1; j >= 0; --j) {
      long lev = idx % levels;
      idx /= levels;
      rows[r * k + j] = -1.0 + 2.0 * (double)lev / (double)(levels - 1);
    }
  }
}

/* 2^k corners, then 2k axial runs at +-alpha. */
static void fill_ccd(double *rows, int k, double alpha) {
  fill_factorial(rows, k, 2);
  double *ax = rows + (1L << k) * k;
  for (int j = 0; j < k; ++j) {
    for (int s = 0; s < 2; ++s) {
      double *row = ax + (2 * j + s) * k;
      for (int m = 0; m < k; ++m)
        row[m] = 0.0;
      row[j] = s ? alpha : -alpha;
    }
  }
}

/* Box-Behnken for k = 3..5: a 2^2 factorial on every pair of factors with
 * the others at 0 (the published designs for these k are exactly this). */
static void fill_box_behnken(double *rows, int k) {
  long r = 0;
  for (int a = 0; a < k; ++a)
    for (int b = a + 1; b < k; ++b)
      for (int s = 0; s < 4; ++s) {
        double *row = rows + r * k;
        for (int m = 0; m < k; ++m)
          row[m] = 0.0;
        row[a] = (s & 2) ? 1.0 : -1.0;
        row[b] = (s & 1) ? 1.0 : -1.0;
        ++r;
      }
}

static double min_pair_distance2(const double *rows, int n, int k) {
  double best = DBL_MAX;
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b) {
      double d2 = 0.0;
      for (int m = 0; m < k; ++m) {
        double t = rows[a * k + m] - rows[b * k + m];
        d2 += t * t;
      }
      if (d2 < best) best = d2;
    }
  return best;
}

/* One random Latin hypercube: in every factor the n strata of width 2/n
 * each hold exactly one run, placed uniformly inside its stratum. */
static void random_lhs(double *rows, int n, int k, pom_rng *rng, int *perm) {
  for (int m = 0; m < k; ++m) {
    for (int i = 0; i < n; ++i)
      perm[i] = i;
    for (int i = n - 1; i > 0; --i) {
      int j = (int)(pom_rng_uniform(rng) * (double)(i + 1));
      int t = perm[i];
      perm[i] = perm[j];
      perm[j] = t;
    }
    for (int i = 0; i < n; ++i)
      rows[i * k + m] = -1.0 + 2.0 * ((double)perm[i] + pom_rng_uniform(rng)) / (double)n;
  }
}

static pom_status fill_lhs(double *rows, int n, int k, const pom_design_options *o,
                           pom_error *err) {
  pom_status st = POM_OK;
  double *trial = malloc(sizeof(double) * (size_t)n * (size_t)k);
  int *perm = malloc(sizeof(int) * (size_t)n);
  if (!trial || !perm) POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "LHS of %d runs: out of memory", n);
  pom_rng rng;
  pom_rng_seed(&rng, o->seed, 0);
  double best = -1.0;
  for (int c = 0; c < o->lhs_candidates; ++c) {
    random_lhs(trial, n, k, &rng, perm);
    double d2 = n > 1 ? min_pair_distance2(trial, n, k) : 0.0;
    if (d2 > best) {
      best = d2;
      memcpy(rows, trial, sizeof(double) * (size_t)n * (size_t)k);
    }
  }
done:
  free(trial);
  free(perm);
  return st;
}

/* ---- create ------------------------------------------------------------- */
pom_status pom_design_create(pom_design **out, int k, const pom_design_options *o, pom_error *err) {
  pom_status st = POM_OK;
  pom_design *d = NULL;
  *out = NULL;
  if (k < 1 || k > POM_DESIGN_MAX_FACTORS)
    POM_FAIL(err, POM_ERR_ARG, "design: %d factors, expected 1..%d", k, POM_DESIGN_MAX_FACTORS);
  if (o->replicates < 1 || o->center_points < 0)
    POM_FAIL(err, POM_ERR_ARG, "design: replicates %d (>= 1) and centre points %d (>= 0)",
             o->replicates, o->center_points);
  switch (o->kind) {
  case POM_DESIGN_FULL_FACTORIAL:
    if (o->levels < 2 || pow((double)o->levels, (double)k) > 1e6)
      POM_FAIL(err, POM_ERR_ARG, "full factorial: %d levels for %d factors (>= 2, <= 1e6 runs)",
               o->levels, k);
    break;
  case POM_DESIGN_CCD_FACE:
  case POM_DESIGN_CCD_ROTATABLE:
    if (k < 2) POM_FAIL(err, POM_ERR_ARG, "central composite design: %d factors, expected >= 2", k);
    break;
  case POM_DESIGN_BOX_BEHNKEN:
    if (k < 3 || k > 5)
      POM_FAIL(err, POM_ERR_ARG,
               "Box-Behnken design: %d factors, expected 3..5 (larger k needs the published "
               "incomplete-block tables, not implemented)",
               k);
    break;
  case POM_DESIGN_LHS:
    if (o->lhs_points < 2 || o->lhs_points > 100000 || o->lhs_candidates < 1)
      POM_FAIL(err, POM_ERR_ARG, "Latin hypercube: %d points (2..100000), %d candidates (>= 1)",
               o->lhs_points, o->lhs_candidates);
    break;
  default:
    POM_FAIL(err, POM_ERR_ARG, "design: unknown kind %d", (int)o->kind);
  }

  long nb = base_runs(k, o);
  long n = nb * o->replicates + o->center_points;
  d = calloc(1, sizeof *d);
  if (!d) POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "design: out of memory");
  d->kind = o->kind;
  d->k = k;
  d->n = (int)n;
  d->alpha = 1.0;
  d->coded = calloc((size_t)n * (size_t)k, sizeof(double)); /* centre runs stay 0 */
  if (!d->coded) POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "design of %ld runs: out of memory", n);

  switch (o->kind) {
  case POM_DESIGN_FULL_FACTORIAL:
    fill_factorial(d->coded, k, o->levels);
    break;
  case POM_DESIGN_CCD_FACE:
    fill_ccd(d->coded, k, 1.0);
    break;
  case POM_DESIGN_CCD_ROTATABLE:
    /* Rotatability: alpha^4 = number of factorial runs (docs/optimize.md 1.2). */
    d->alpha = pow(pow(2.0, (double)k), 0.25);
    fill_ccd(d->coded, k, d->alpha);
    break;
  case POM_DESIGN_BOX_BEHNKEN:
    fill_box_behnken(d->coded, k);
    break;
  case POM_DESIGN_LHS:
    POM_TRY_GOTO(fill_lhs(d->coded, (int)nb, k, o, err), fail);
    break;
  }
  for (int rep = 1; rep < o->replicates; ++rep)
    memcpy(d->coded + (size_t)rep * (size_t)nb * (size_t)k, d->coded,
           sizeof(double) * (size_t)nb * (size_t)k);
  *out = d;
  return POM_OK;
fail:
  pom_design_destroy(d);
  return st;
}
