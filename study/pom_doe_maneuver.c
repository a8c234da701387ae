/* pom_doe_maneuver.c - maneuver sampling with common random numbers
 * (docs/results.md, "Maneuvers"). */
#include "pom_study.h"
#include "pom_kinematics.h"
#include "pom_math.h"
#include "pom_rng.h"

#include <math.h>
#include <string.h>

/* The paper's study: 1000 maneuvers within +-3 mm (docs/PARAMETERS.md, protocol). */
#define PAPER_MANEUVERS 1000
#define PAPER_RANGE_M   3.0e-3
#define DEFAULT_SEED    20120708u

void pom_doe_maneuvers_defaults(pom_doe_maneuvers *mv) {
  memset(mv, 0, sizeof *mv);
  mv->count = PAPER_MANEUVERS;
  mv->seed = DEFAULT_SEED;
  mv->space = POM_DOE_SPACE_JOINT;
  mv->distribution = POM_DOE_DIST_UNIFORM;
  mv->range = PAPER_RANGE_M;
  mv->sigma = 0.5 * PAPER_RANGE_M;
  mv->tilt_max = 10.0 * POM_DEG;
  mv->torsion_max = 5.0 * POM_DEG;
}

const char *const pom_doe_space_names[] = {"joint", "orientation", NULL};
const char *const pom_doe_dist_names[] = {"uniform", "normal", NULL};
_Static_assert(sizeof pom_doe_space_names / sizeof pom_doe_space_names[0] ==
                   POM_DOE_SPACE_ORIENTATION + 2,
               "pom_doe_space_names follows pom_doe_space");
_Static_assert(sizeof pom_doe_dist_names / sizeof pom_doe_dist_names[0] == POM_DOE_DIST_NORMAL + 2,
               "pom_doe_dist_names follows pom_doe_dist");

pom_status pom_doe_maneuvers_load(pom_doe_maneuvers *mv, const pom_cfg *cfg, pom_error *err) {
  pom_doe_maneuvers_defaults(mv);
  if (!pom_cfg_has(cfg, "montecarlo")) return POM_OK;
  long seed = 0;
  int space = 0, dist = 0;
  POM_TRY(pom_cfg_int_opt(cfg, "montecarlo.maneuvers", 1, 100000000L, mv->count, &mv->count, err));
  POM_TRY(
      pom_cfg_int_opt(cfg, "montecarlo.seed", 0, 9007199254740991L, (long)mv->seed, &seed, err));
  mv->seed = (uint64_t)seed;
  POM_TRY(pom_cfg_choice_opt(cfg, "montecarlo.space", pom_doe_space_names, 0, &space, err));
  POM_TRY(pom_cfg_choice_opt(cfg, "montecarlo.distribution", pom_doe_dist_names, 0, &dist, err));
  mv->space = (pom_doe_space)space;
  mv->distribution = (pom_doe_dist)dist;
  /* joint-space ranges in the display unit of an actuator kind: range_mm /
   * sigma_mm (prismatic) or range_deg / sigma_deg (revolute); which set was
   * given is checked against the candidates' actuator kind once they are
   * known (pom_doe_maneuvers_check_kinds) */
  const pom_act_desc *given = NULL;
  char range_key[64], sigma_key[64];
  for (int k = 0; k < POM_ACT_KINDS; ++k) {
    const pom_act_desc *d = pom_act_kind_desc((pom_actuator_kind)k);
    snprintf(range_key, sizeof range_key, "montecarlo.range%s", d->key_suffix);
    snprintf(sigma_key, sizeof sigma_key, "montecarlo.sigma%s", d->key_suffix);
    if (!pom_cfg_has(cfg, range_key) && !pom_cfg_has(cfg, sigma_key)) continue;
    if (given && strcmp(given->key_suffix, d->key_suffix) != 0) {
      char units[128] = "";
      size_t used = 0;
      for (int u = 0; u < POM_ACT_KINDS && used < sizeof units; ++u) {
        const pom_act_desc *du = pom_act_kind_desc((pom_actuator_kind)u);
        int w = snprintf(units + used, sizeof units - used, "%s%s %s", u ? ", " : "",
                         du->key_suffix, du->kind_name);
        used += w > 0 ? (size_t)w : 0;
      }
      return pom_cfg_error(cfg, pom_cfg_has(cfg, range_key) ? range_key : sigma_key, NULL, err,
                           "mixes units with montecarlo.range%s/sigma%s: give the range in the "
                           "candidates' actuator unit only (%s)",
                           given->key_suffix, given->key_suffix, units);
    }
    given = d;
  }
  if (given) {
    /* in SI from the display unit; the range defaults to 3 of it (the
     * paper's +-3 mm; +-3 deg) */
    const double to_si = 1.0 / given->to_display, hi = given->maneuver_range_max;
    mv->range_suffix = given->key_suffix;
    mv->range = 3.0 * to_si;
    mv->sigma = 0.5 * mv->range;
    snprintf(range_key, sizeof range_key, "montecarlo.range%s", given->key_suffix);
    snprintf(sigma_key, sizeof sigma_key, "montecarlo.sigma%s", given->key_suffix);
    POM_TRY(pom_cfg_real_opt(cfg, range_key, to_si, 1e-6, hi, mv->range, &mv->range, err));
    POM_TRY(pom_cfg_real_opt(cfg, sigma_key, to_si, 1e-6, hi, mv->sigma, &mv->sigma, err));
  }
  POM_TRY(pom_cfg_real_opt(cfg, "montecarlo.tilt_max_deg", POM_DEG, 1e-6, 89.0, mv->tilt_max,
                           &mv->tilt_max, err));
  POM_TRY(pom_cfg_real_opt(cfg, "montecarlo.torsion_max_deg", POM_DEG, 0.0, 179.0, mv->torsion_max,
                           &mv->torsion_max, err));
  if (mv->space == POM_DOE_SPACE_ORIENTATION && pom_cfg_has(cfg, "montecarlo.distribution"))
    return pom_cfg_error(cfg, "montecarlo.distribution", NULL, err,
                         "only applies to space = \"joint\" (orientation targets are uniform in "
                         "tilt cap and torsion)");
  return POM_OK;
}

int pom_doe_kinds_mixed(const pom_actuator_kind *kinds, int n) {
  for (int c = 1; c < n; ++c)
    if (kinds[c] != kinds[0]) return 1;
  return 0;
}

pom_status pom_doe_maneuvers_check_kinds(const pom_doe_maneuvers *mv,
                                         const pom_actuator_kind *kinds, int n, const pom_cfg *cfg,
                                         pom_error *err) {
  if (mv->space != POM_DOE_SPACE_JOINT || n < 1) return POM_OK;
  if (pom_doe_kinds_mixed(kinds, n)) {
    /* the count of each kind: "2 prismatic in m, 1 revolute in rad" */
    char counts[256] = "";
    size_t used = 0;
    for (int k = 0; k < POM_ACT_KINDS && used < sizeof counts; ++k) {
      const pom_act_desc *d = pom_act_kind_desc((pom_actuator_kind)k);
      int nk = 0;
      for (int c = 0; c < n; ++c)
        nk += kinds[c] == d->kind;
      int w = snprintf(counts + used, sizeof counts - used, "%s%d %s in %s", k ? ", " : "", nk,
                       d->kind_name, d->si);
      used += w > 0 ? (size_t)w : 0;
    }
    POM_FAIL(err, POM_ERR_CONFIG,
             "%s: key 'montecarlo.space': the candidates mix actuator kinds (%s), so joint-space "
             "targets would not mean the same motion for all: set montecarlo.space = "
             "\"orientation\" (targets drawn as platform orientations, mapped to each "
             "candidate's actuators by its inverse kinematics; docs/results.md section 1)",
             pom_cfg_path(cfg), counts);
  }
  /* the keys given must carry the kind's suffix; the default range is a
   * length, for kinds whose q is one */
  const pom_act_desc *d = pom_act_kind_desc(kinds[0]);
  const char *given = mv->range_suffix;
  if (given && strcmp(given, d->key_suffix) != 0) {
    char range_key[64], sigma_key[64];
    snprintf(range_key, sizeof range_key, "montecarlo.range%s", given);
    snprintf(sigma_key, sizeof sigma_key, "montecarlo.sigma%s", given);
    int range = pom_cfg_has(cfg, range_key);
    return pom_cfg_error(cfg, range ? range_key : sigma_key, NULL, err,
                         "the candidates' actuators are %s (q in %s): give the range in %s with "
                         "montecarlo.%s%s",
                         d->kind_name, d->si, d->display_words, range ? "range" : "sigma",
                         d->key_suffix);
  }
  if (!given && d->angular)
    POM_FAIL(err, POM_ERR_CONFIG,
             "%s: key 'montecarlo.range%s': missing: the candidates' actuators are %s and the "
             "default range (+-3 mm, the paper's) is for prismatic ones",
             pom_cfg_path(cfg), d->key_suffix, d->kind_name);
  return POM_OK;
}

/* Normal(0, sigma) truncated to [-range, range] by rejection: the number of
 * draws depends only on the stream, so it stays reproducible. */
static double truncated_normal(pom_rng *rng, double sigma, double range) {
  for (;;) {
    double x = sigma * pom_rng_normal(rng);
    if (fabs(x) <= range) return x;
  }
}

void pom_doe_maneuver_draw(pom_doe_maneuver *out, const pom_doe_maneuvers *mv, long k) {
  pom_rng rng;
  memset(out, 0, sizeof *out);
  out->index = k;
  pom_rng_seed(&rng, mv->seed, (uint64_t)k);
  pom_m3_identity(out->R);
  if (mv->space == POM_DOE_SPACE_JOINT) {
    for (int i = 0; i < 3; ++i)
      out->q[i] = mv->distribution == POM_DOE_DIST_UNIFORM
                      ? pom_rng_range(&rng, -mv->range, mv->range)
                      : truncated_normal(&rng, mv->sigma, mv->range);
    return;
  }
  /* tilt-and-torsion angles: azimuth uniform, tilt uniform over the spherical
   * cap (cos t uniform), torsion uniform; R = Rz(a) Ry(t) Rz(s - a) */
  double a = pom_rng_range(&rng, -POM_PI, POM_PI);
  double ct = pom_rng_range(&rng, cos(mv->tilt_max), 1.0);
  double t = acos(ct);
  double s = pom_rng_range(&rng, -mv->torsion_max, mv->torsion_max);
  out->orient[0] = a;
  out->orient[1] = t;
  out->orient[2] = s;
  const double ez[3] = {0, 0, 1}, ey[3] = {0, 1, 0};
  double Rz1[9], Ry[9], Rz2[9], tmp[9];
  pom_m3_axis_angle(Rz1, ez, a);
  pom_m3_axis_angle(Ry, ey, t);
  pom_m3_axis_angle(Rz2, ez, s - a);
  pom_m3_mul(tmp, Rz1, Ry);
  pom_m3_mul(out->R, tmp, Rz2);
}

void pom_doe_maneuver_targets(double (*q)[3], int *n_out, const pom_doe_maneuvers *mv,
                              uint64_t seed, int n, const pom_kin_arch *arch) {
  pom_doe_maneuvers m = *mv;
  m.seed = seed;
  int kept = 0;
  for (int k = 0; k < n; ++k) {
    pom_doe_maneuver man;
    pom_doe_maneuver_draw(&man, &m, k);
    double t[3];
    memcpy(t, man.q, sizeof t);
    if (m.space == POM_DOE_SPACE_ORIENTATION) {
      pom_error e;
      pom_error_clear(&e);
      if (pom_kin_inverse(arch, man.R, t, &e) != POM_OK) continue;
    }
    int inside = 1;
    for (int i = 0; i < 3; ++i)
      inside &= fabs(t[i]) <= 0.5 * arch->stroke;
    if (!inside) continue;
    memcpy(q[kept++], t, sizeof t);
  }
  *n_out = kept;
}
