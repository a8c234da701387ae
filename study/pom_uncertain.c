/* pom_uncertain.c - distributions by their inverse CDF and the `uncertain`
 * group's per-maneuver draws (docs/results.md, section 10). */
#include "pom_study.h"
#include "pom_rng.h"

#include <gsl/gsl_cdf.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

/* Streams of the uncertain draws: far above any maneuver index, so the
 * maneuver targets (streams 0, 1, ...) are unchanged by an `uncertain`
 * group. */
#define UNC_STREAM 0x4000000000000000ULL

/* Smallest probability mass a truncation interval may hold. */
#define MIN_MASS 1e-12

/* ---- standard normal truncated to [za, zb] ------------------------------------ */
static double phi_lower(double z) {
  return isinf(z) ? (z < 0 ? 0.0 : 1.0) : gsl_cdf_ugaussian_P(z);
}
static double phi_upper(double z) {
  return isinf(z) ? (z < 0 ? 1.0 : 0.0) : gsl_cdf_ugaussian_Q(z);
}

/* Inverse CDF of the standard normal restricted to [za, zb]. In the upper
 * tail it works with Q = 1 - P, where P would have lost its digits. */
static double trunc_normal_z(double u, double za, double zb) {
  double z;
  if (za >= 0) {
    double qa = phi_upper(za), qb = phi_upper(zb);
    z = gsl_cdf_ugaussian_Qinv(qa - u * (qa - qb));
  } else {
    double pa = phi_lower(za), pb = phi_lower(zb);
    z = gsl_cdf_ugaussian_Pinv(pa + u * (pb - pa));
  }
  if (z < za) z = za;
  if (z > zb) z = zb;
  return z;
}

static double mass(double za, double zb) {
  return za >= 0 ? phi_upper(za) - phi_upper(zb) : phi_lower(zb) - phi_lower(za);
}

/* ---- the kinds -------------------------------------------------------------- */
static double q_uniform(const pom_dist *d, double u) {
  return d->p[0] + u * (d->p[1] - d->p[0]);
}

static double q_normal(const pom_dist *d, double u) {
  return d->p[0] + d->p[1] * gsl_cdf_ugaussian_Pinv(u);
}

static double q_trunc_normal(const pom_dist *d, double u) {
  double za = (d->p[2] - d->p[0]) / d->p[1], zb = (d->p[3] - d->p[0]) / d->p[1];
  double x = d->p[0] + d->p[1] * trunc_normal_z(u, za, zb);
  return x < d->p[2] ? d->p[2] : (x > d->p[3] ? d->p[3] : x);
}

static double q_lognormal(const pom_dist *d, double u) {
  double za = d->p[2] > 0 ? log(d->p[2] / d->p[0]) / d->p[1] : -INFINITY;
  double zb = isfinite(d->p[3]) ? log(d->p[3] / d->p[0]) / d->p[1] : INFINITY;
  double x = d->p[0] * exp(d->p[1] * trunc_normal_z(u, za, zb));
  return x < d->p[2] ? d->p[2] : (x > d->p[3] ? d->p[3] : x);
}

static const pom_dist_ops uniform_ops = {.name = "uniform", .quantile = q_uniform};
static const pom_dist_ops normal_ops = {.name = "normal", .quantile = q_normal};
static const pom_dist_ops trunc_normal_ops = {.name = "truncated_normal",
                                              .quantile = q_trunc_normal};
static const pom_dist_ops lognormal_ops = {.name = "lognormal", .quantile = q_lognormal};

const pom_dist_ops *const pom_dist_kinds[] = {&uniform_ops, &normal_ops, &trunc_normal_ops,
                                              &lognormal_ops, NULL};

double pom_dist_quantile(const pom_dist *d, double u) {
  if (!(u >= POM_DIST_U_MIN)) u = POM_DIST_U_MIN;
  if (u > POM_DIST_U_MAX) u = POM_DIST_U_MAX;
  return d->ops->quantile(d, u);
}

double pom_dist_u_from_bits(uint64_t bits) {
  return ((double)(bits >> 12) + 0.5) * 0x1.0p-52;
}

/* pom_dist_make, and in *bad the index in p[] of the parameter a failure is
 * about (the one whose key a config message names). */
static pom_status dist_make(pom_dist *d, const char *name, const double p[4], int *bad,
                            pom_error *err) {
  *bad = 0;
  memset(d, 0, sizeof *d);
  for (int k = 0; pom_dist_kinds[k]; ++k)
    if (strcmp(pom_dist_kinds[k]->name, name) == 0) d->ops = pom_dist_kinds[k];
  if (!d->ops) POM_FAIL(err, POM_ERR_ARG, "unknown distribution '%s'", name);
  for (int k = 0; k < 4; ++k)
    d->p[k] = p[k];
  if (d->ops == &uniform_ops) {
    *bad = isfinite(p[0]) ? 1 : 0;
    if (!(p[0] < p[1]) || !isfinite(p[0]) || !isfinite(p[1]))
      POM_FAIL(err, POM_ERR_ARG, "uniform: needs finite min < max (found %g, %g)", p[0], p[1]);
    d->lo = p[0];
    d->hi = p[1];
    return POM_OK;
  }
  const int logn = d->ops == &lognormal_ops;
  *bad = isfinite(p[0]) ? 1 : 0;
  if (!(p[1] > 0) || !isfinite(p[0]) || !isfinite(p[1]))
    POM_FAIL(err, POM_ERR_ARG, "%s: needs a finite %s and %s > 0 (found %s = %g, %s = %g)", name,
             logn ? "median" : "mean", logn ? "sigma_ln" : "sd", logn ? "median" : "mean", p[0],
             logn ? "sigma_ln" : "sd", p[1]);
  if (d->ops == &trunc_normal_ops) {
    *bad = isfinite(p[2]) ? 3 : 2;
    if (!(p[2] < p[3]) || !isfinite(p[2]) || !isfinite(p[3]))
      POM_FAIL(err, POM_ERR_ARG, "truncated_normal: needs finite min < max (found %g, %g)", p[2],
               p[3]);
    *bad = 2;
    if (!(mass((p[2] - p[0]) / p[1], (p[3] - p[0]) / p[1]) > MIN_MASS))
      POM_FAIL(err, POM_ERR_ARG,
               "truncated_normal: [min, max] = [%g, %g] holds no probability of normal(%g, %g)",
               p[2], p[3], p[0], p[1]);
  } else if (d->ops == &lognormal_ops) {
    *bad = 0;
    if (!(p[0] > 0)) POM_FAIL(err, POM_ERR_ARG, "lognormal: median must be > 0 (found %g)", p[0]);
    if (isnan(d->p[2])) d->p[2] = 0.0;
    if (isnan(d->p[3])) d->p[3] = INFINITY;
    *bad = d->p[2] >= 0 ? 3 : 2;
    if (!(d->p[2] >= 0) || !(d->p[2] < d->p[3]))
      POM_FAIL(err, POM_ERR_ARG, "lognormal: needs 0 <= min < max (found %g, %g)", d->p[2],
               d->p[3]);
    double za = d->p[2] > 0 ? log(d->p[2] / p[0]) / p[1] : -INFINITY;
    double zb = isfinite(d->p[3]) ? log(d->p[3] / p[0]) / p[1] : INFINITY;
    *bad = 2;
    if (!(mass(za, zb) > MIN_MASS))
      POM_FAIL(err, POM_ERR_ARG, "lognormal: [min, max] = [%g, %g] holds no probability", d->p[2],
               d->p[3]);
  }
  d->lo = pom_dist_quantile(d, POM_DIST_U_MIN);
  d->hi = pom_dist_quantile(d, POM_DIST_U_MAX);
  return POM_OK;
}

pom_status pom_dist_make(pom_dist *d, const char *name, const double p[4], pom_error *err) {
  int bad = 0;
  return dist_make(d, name, p, &bad, err);
}

/* ---- config ---------------------------------------------------------------- */
/* The parameter keys of each kind (index into p[]; NULL = unused) and which
 * are optional. */
typedef struct {
  const char *key[4];
  int optional[4];
} kind_keys;

static const kind_keys keys_of[] = {
    {.key = {"min", "max", NULL, NULL}, .optional = {0, 0, 0, 0}},
    {.key = {"mean", "sd", NULL, NULL}, .optional = {0, 0, 0, 0}},
    {.key = {"mean", "sd", "min", "max"}, .optional = {0, 0, 0, 0}},
    {.key = {"median", "sigma_ln", "min", "max"}, .optional = {0, 0, 1, 1}},
};

pom_status pom_dist_load(pom_dist *d, const pom_cfg *cfg, const char *key, pom_error *err) {
  const char *names[8];
  int n = 0, kind = 0;
  for (; pom_dist_kinds[n]; ++n)
    names[n] = pom_dist_kinds[n]->name;
  names[n] = NULL;
  char k[256];
  snprintf(k, sizeof k, "%s.dist", key);
  POM_TRY(pom_cfg_choice(cfg, k, names, &kind, err));
  double p[4] = {NAN, NAN, NAN, NAN};
  for (int j = 0; j < 4; ++j) {
    const char *pk = keys_of[kind].key[j];
    if (!pk) continue;
    snprintf(k, sizeof k, "%s.%s", key, pk);
    if (keys_of[kind].optional[j])
      POM_TRY(pom_cfg_real_opt(cfg, k, 1.0, -1e300, 1e300, NAN, &p[j], err));
    else
      POM_TRY(pom_cfg_real(cfg, k, 1.0, -1e300, 1e300, &p[j], err));
  }
  pom_error e;
  pom_error_clear(&e);
  int bad = 0;
  if (dist_make(d, names[kind], p, &bad, &e) != POM_OK) {
    /* the message names the parameter that breaks the rule, not `dist` */
    const char *pk = keys_of[kind].key[bad] ? keys_of[kind].key[bad] : "dist";
    snprintf(k, sizeof k, "%s.%s", key, pk);
    return pom_cfg_error(cfg, k, NULL, err, "%s", e.message);
  }
  return POM_OK;
}

pom_status pom_unc_load(pom_unc *unc, const pom_cfg *cfg, uint64_t seed, pom_error *err) {
  memset(unc, 0, sizeof *unc);
  unc->seed = seed;
  if (!pom_cfg_has(cfg, "uncertain")) return POM_OK;
  int n = pom_cfg_length(cfg, "uncertain");
  /* a group { key = ...; } read as a list would say "uncertain.[0].key missing" */
  if (!pom_cfg_is_list(cfg, "uncertain"))
    return pom_cfg_error(cfg, "uncertain", NULL, err,
                         "expected a list in parentheses, ( { key = \"group.key\"; dist = "
                         "\"normal\"; mean = ...; sd = ...; }, ... ), of 1 to %d groups",
                         POM_UNC_MAX);
  if (n < 1 || n > POM_UNC_MAX)
    return pom_cfg_error(cfg, "uncertain", NULL, err,
                         "expected a list of 1 to %d groups ( { key = \"group.key\"; dist = "
                         "\"normal\"; mean = ...; sd = ...; } )",
                         POM_UNC_MAX);
  for (int j = 0; j < n; ++j) {
    pom_unc_param *p = &unc->param[j];
    char k[64];
    snprintf(k, sizeof k, "uncertain.[%d].key", j);
    POM_TRY(pom_cfg_string(cfg, k, p->key, sizeof p->key, err));
    if (!strchr(p->key, '.'))
      return pom_cfg_error(cfg, k, NULL, err, "expected a dotted key \"group.key\"");
    for (int i = 0; i < j; ++i)
      if (strcmp(unc->param[i].key, p->key) == 0)
        return pom_cfg_error(cfg, k, NULL, err, "the key is uncertain twice");
    snprintf(k, sizeof k, "uncertain.[%d].relative", j);
    POM_TRY(pom_cfg_bool_opt(cfg, k, 0, &p->relative, err));
    /* what a model-based controller believes: the nominal value (default)
     * or the drawn one (docs/control.md section 1) */
    static const char *const sees[] = {"nominal", "drawn", NULL};
    snprintf(k, sizeof k, "uncertain.[%d].controller", j);
    POM_TRY(pom_cfg_choice_opt(cfg, k, sees, 0, &p->controller_drawn, err));
    snprintf(k, sizeof k, "uncertain.[%d]", j);
    POM_TRY(pom_dist_load(&p->dist, cfg, k, err));
  }
  unc->n = n;
  return POM_OK;
}

/* ---- draws ------------------------------------------------------------------ */
void pom_unc_unit(const pom_unc *unc, long k, long *maneuver, double *u) {
  if (unc->design) {
    long row = k / unc->per_row;
    *maneuver = k % unc->per_row;
    for (int j = 0; j < unc->n; ++j)
      u[j] = unc->design[row * unc->n + j];
    return;
  }
  *maneuver = k;
  pom_rng rng;
  pom_rng_seed(&rng, unc->seed, UNC_STREAM + (uint64_t)k);
  for (int j = 0; j < unc->n; ++j)
    u[j] = pom_dist_u_from_bits(pom_rng_next(&rng));
}

void pom_unc_draws(const pom_unc *unc, long k, double *x) {
  double u[POM_UNC_MAX];
  long m;
  pom_unc_unit(unc, k, &m, u);
  for (int j = 0; j < unc->n; ++j)
    x[j] = pom_dist_quantile(&unc->param[j].dist, u[j]);
}
