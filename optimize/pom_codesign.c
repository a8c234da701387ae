/* pom_codesign.c - co-design of geometry, actuator size and gains on the
 * closed-loop Monte-Carlo metrics: loading, the evaluation of a design, the
 * smooth quantile, the size law (docs/optimize.md section 11). */
#define _POSIX_C_SOURCE 200809L /* sysconf */
#include "codesign_internal.h"
#include "pom_arch.h"
#include "pom_dynamics.h"
#include "pom_kinematics.h"
#include "pom_math.h"

#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char *const groups[] = {"name",     "montecarlo", "uncertain",
                                     "codesign", "candidates", NULL};

const char *const *pom_cds_groups(void) {
  return groups;
}

double pom_cds_size_law(double nominal, double exponent, double s) {
  return nominal * pow(s, exponent);
}

/* ---- smooth quantile (section 11.3): core's, under the co-design's name -------------- */
double pom_cds_smooth_quantile(const double *t, int n, double p, double h, double *w) {
  return pom_smooth_quantile(t, n, p, h, w);
}

/* ---- loading ---------------------------------------------------------------------- */
static void folder_of(char *dir, size_t cap, const char *path) {
  snprintf(dir, cap, "%s", path);
  char *slash = strrchr(dir, '/');
  if (slash)
    slash[1] = '\0';
  else
    dir[0] = '\0';
}

static const char *const alg_names[] = {"slsqp", "mma", "cobyla", NULL};
static const char *const grad_names[] = {"central_difference", "sensitivity", NULL};

/* The keys the size law scales, by actuator kind (section 11.2). */
static pom_status sized_keys(pom_cds_candidate *cd, const pom_cfg *ccfg, const pom_cfg *cfg,
                             const char *where, pom_error *err) {
  cd->n_sized = 0;
  cd->rotary = pom_cfg_has(ccfg, "actuator.torque_constant_Nm_per_A");
  const char *kconst =
      cd->rotary ? "actuator.torque_constant_Nm_per_A" : "actuator.force_constant_N_per_A";
  struct {
    const char *key;
    double e;
    int required;
  } law[] = {
      {kconst, cd->rotary ? 2.0 : 1.0, 1}, {"actuator.resistance_ohm", -1.0, 1},
      {"actuator.inductance_H", 1.0, 1},   {"inertia.piston.mass_kg", 3.0, 0},
      {"inertia.rotor_mass_kg", 3.0, 0},   {"inertia.rotor_inertia_kgm2", 5.0, 0},
  };
  for (size_t i = 0; i < sizeof law / sizeof law[0]; ++i) {
    if (!pom_cfg_has(ccfg, law[i].key)) {
      if (law[i].required)
        return pom_cfg_error(cfg, where, cd->config, err,
                             "the size law needs '%s' in the config of candidate '%s'", law[i].key,
                             cd->name);
      continue;
    }
    pom_cds_sized_key *s = &cd->sized[cd->n_sized++];
    snprintf(s->key, sizeof s->key, "%s", law[i].key);
    s->exponent = law[i].e;
    POM_TRY(pom_cfg_real(ccfg, law[i].key, 1.0, -INFINITY, INFINITY, &s->nominal, err));
  }
  return POM_OK;
}

/* A `geometry.NAME` key the config leaves to its architecture's default (a
 * catalog file's design parameter): its value in config units. */
static int arch_default(const pom_cfg *ccfg, const char *key, double *x0) {
  if (strncmp(key, "geometry.", 9) != 0) return 0;
  pom_kin_arch arch;
  pom_error e;
  pom_error_clear(&e);
  if (pom_kin_arch_load(&arch, ccfg, &e) != POM_OK || !arch.has_design) return 0;
  for (int i = 0; i < arch.type->n_params; ++i) {
    const pom_kin_param_desc *d = &arch.type->params[i];
    if (d->key && strcmp(d->key, key + 9) == 0 && d->to_si > 0) {
      *x0 = arch.design.x[i] / d->to_si;
      return 1;
    }
  }
  return 0;
}

pom_status pom_cds_load(pom_cds_problem *pb, const pom_cfg *cfg, pom_error *err) {
  memset(pb, 0, sizeof *pb);
  snprintf(pb->source, sizeof pb->source, "%s", pom_cfg_path(cfg));
  const char *text = pom_cfg_text(cfg);
  pb->config_text = strdup(text ? text : "");
  if (!pb->config_text) POM_FAIL(err, POM_ERR_NOMEM, "codesign: out of memory");
  POM_TRY(pom_cfg_string(cfg, "name", pb->name, sizeof pb->name, err));
  POM_TRY(pom_doe_maneuvers_load(&pb->maneuvers, cfg, err));
  if (pb->maneuvers.space != POM_DOE_SPACE_ORIENTATION)
    return pom_cfg_error(cfg, "montecarlo.space", NULL, err,
                         "co-design compares architectures on the same platform motions: "
                         "space must be \"orientation\"");
  POM_TRY(pom_unc_load(&pb->uncertain, cfg, pb->maneuvers.seed, err));
  if (!pom_cfg_has(cfg, "codesign"))
    return pom_cfg_error(cfg, "codesign", NULL, err, "the codesign group is required");
  POM_TRY(pom_cfg_string_opt(cfg, "codesign.output", "results/codesign.h5", pb->output,
                             sizeof pb->output, err));
  const double deg = POM_PI / 180.0;
  POM_TRY(pom_cfg_real(cfg, "codesign.requirements.workspace_half_width_deg", deg, 0.5, 45.0,
                       &pb->ws_half_width, err));
  long g = 0;
  POM_TRY(pom_cfg_int_opt(cfg, "codesign.requirements.workspace_grid", 3, 21, 3, &g, err));
  if (g % 2 == 0)
    return pom_cfg_error(cfg, "codesign.requirements.workspace_grid", NULL, err,
                         "must be odd (the grid holds home)");
  pb->ws_grid = (int)g;
  POM_TRY(pom_cfg_real(cfg, "codesign.requirements.dexterity_min", 1.0, 0.0, 1.0,
                       &pb->dexterity_min, err));
  POM_TRY(pom_cfg_real(cfg, "codesign.requirements.envelope_radius_mm", 1e-3, 1.0, 1e4,
                       &pb->envelope, err));
  POM_TRY(
      pom_cfg_real(cfg, "codesign.requirements.time_max_ms", 1e-3, 0.1, 1e5, &pb->time_max, err));
  double ilim = 0;
  POM_TRY(pom_cfg_real(cfg, "codesign.requirements.current_limit_A", 1.0, 1e-3, 1e3, &ilim, err));
  POM_TRY(pom_cfg_real_opt(cfg, "codesign.objective.quantile", 1.0, 0.5, 0.999, 0.95, &pb->quantile,
                           err));
  POM_TRY(pom_cfg_real_opt(cfg, "codesign.objective.bandwidth_ms", 1e-3, 1e-3, 100.0, 1e-3,
                           &pb->bandwidth, err));
  int alg = 0, fb = 2, gs = 0;
  POM_TRY(pom_cfg_choice_opt(cfg, "codesign.optimizer.algorithm", alg_names, 0, &alg, err));
  POM_TRY(pom_cfg_choice_opt(cfg, "codesign.optimizer.fallback", alg_names, 2, &fb, err));
  if (fb != POM_CDS_ALG_COBYLA)
    return pom_cfg_error(cfg, "codesign.optimizer.fallback", NULL, err,
                         "the fallback must be derivative-free: \"cobyla\"");
  pb->alg = (pom_cds_alg)alg;
  pb->fallback = (pom_cds_alg)fb;
  long me = 0, st = 0, fp = 0, thr = 0, rc = 0, rs = 0;
  POM_TRY(pom_cfg_int_opt(cfg, "codesign.optimizer.max_evals", 2, 10000, 25, &me, err));
  POM_TRY(pom_cfg_real_opt(cfg, "codesign.optimizer.xtol_rel", 1.0, 0.0, 0.5, 1e-3, &pb->xtol_rel,
                           err));
  POM_TRY(pom_cfg_real_opt(cfg, "codesign.optimizer.gradient_step", 1.0, 1e-6, 0.2, 1e-2,
                           &pb->fd_step, err));
  POM_TRY(pom_cfg_int_opt(cfg, "codesign.optimizer.starts", 1, POM_CDS_MAX_STARTS, 2, &st, err));
  POM_TRY(pom_cfg_choice_opt(cfg, "codesign.optimizer.gradient", grad_names, 0, &gs, err));
  pb->grad = (pom_cds_grad_source)gs;
  pb->max_evals = (int)me;
  pb->starts = (int)st;
  POM_TRY(pom_cfg_int_opt(cfg, "codesign.front_points", 2, POM_CDS_MAX_FRONT, 4, &fp, err));
  pb->front_points = (int)fp;
  POM_TRY(pom_cfg_int_opt(cfg, "codesign.threads", 0, 256, 0, &thr, err));
  pb->threads = (int)thr;
  POM_TRY(pom_cfg_int_opt(cfg, "codesign.reevaluate.maneuvers", 1, 100000, pb->maneuvers.count, &rc,
                          err));
  POM_TRY(pom_cfg_int_opt(cfg, "codesign.reevaluate.seed", 0, INT64_MAX,
                          (long)(pb->maneuvers.seed + 1), &rs, err));
  if ((uint64_t)rs == pb->maneuvers.seed)
    return pom_cfg_error(cfg, "codesign.reevaluate.seed", NULL, err,
                         "the re-evaluation needs a fresh maneuver set: another seed than "
                         "montecarlo.seed");
  pb->reeval_count = rc;
  pb->reeval_seed = (uint64_t)rs;

  int nc = pom_cfg_length(cfg, "candidates");
  if (!pom_cfg_is_list(cfg, "candidates") || nc < 1 || nc > POM_CDS_MAX_CANDIDATES)
    return pom_cfg_error(cfg, "candidates", NULL, err, "a list of 1..%d candidates is required",
                         POM_CDS_MAX_CANDIDATES);
  pb->n_candidates = nc;
  char dir[POM_DOE_PATH_LEN];
  folder_of(dir, sizeof dir, pb->source);
  for (int c = 0; c < nc; ++c) {
    pom_cds_candidate *cd = &pb->cand[c];
    cd->current_limit0 = ilim;
    char k[160], file[POM_DOE_PATH_LEN];
    snprintf(k, sizeof k, "candidates.[%d].name", c);
    POM_TRY(pom_cfg_string(cfg, k, cd->name, sizeof cd->name, err));
    for (int d = 0; d < c; ++d)
      if (strcmp(pb->cand[d].name, cd->name) == 0)
        return pom_cfg_error(cfg, k, cd->name, err, "two candidates of one name");
    snprintf(k, sizeof k, "candidates.[%d].config", c);
    POM_TRY(pom_cfg_string(cfg, k, file, sizeof file, err));
    if (file[0] == '/')
      snprintf(cd->config, sizeof cd->config, "%s", file);
    else
      snprintf(cd->config, sizeof cd->config, "%s%s", dir, file);
    pom_cfg *ccfg = NULL;
    pom_status lst = pom_cfg_load(&ccfg, cd->config, err);
    if (lst != POM_OK) {
      pom_error_prefix(err, "%s: candidate '%s'", pom_cfg_path(cfg), cd->name);
      return lst;
    }
    pom_status s2 = sized_keys(cd, ccfg, cfg, k, err);
    pom_dyn_params prm;
    pom_dyn_params_defaults(&prm);
    if (s2 == POM_OK) s2 = pom_dyn_params_load(&prm, ccfg, err);
    cd->horizon = prm.maneuver.horizon;
    cd->voltage_limit0 = prm.actuator.voltage_limit;
    cd->coil_inductance = prm.scene.coil_inductance;
    snprintf(k, sizeof k, "candidates.[%d].variables", c);
    int nv = pom_cfg_length(cfg, k);
    if (s2 == POM_OK && (!pom_cfg_is_list(cfg, k) || nv < 1 || nv > POM_CDS_MAX_VARS))
      s2 = pom_cfg_error(cfg, k, NULL, err, "a list of 1..%d variables is required",
                         POM_CDS_MAX_VARS);
    for (int v = 0; v < nv && s2 == POM_OK; ++v) {
      pom_cds_var *var = &cd->var[v];
      char kk[200];
      snprintf(kk, sizeof kk, "%s.[%d].key", k, v);
      s2 = pom_cfg_string(cfg, kk, var->key, sizeof var->key, err);
      if (s2 != POM_OK) break;
      var->kind = strcmp(var->key, "size") == 0 ? POM_CDS_VAR_SIZE : POM_CDS_VAR_KEY;
      for (int w = 0; w < v && s2 == POM_OK; ++w)
        if (strcmp(cd->var[w].key, var->key) == 0)
          s2 = pom_cfg_error(cfg, kk, var->key, err, "the same variable twice");
      if (s2 != POM_OK) break;
      if (var->kind == POM_CDS_VAR_KEY) {
        for (int j = 0; j < cd->n_sized && s2 == POM_OK; ++j)
          if (strcmp(cd->sized[j].key, var->key) == 0)
            s2 = pom_cfg_error(cfg, kk, var->key, err,
                               "the size law sets this key: vary \"size\" instead");
        if (s2 == POM_OK && pom_cfg_has(ccfg, var->key))
          s2 = pom_cfg_real(ccfg, var->key, 1.0, -INFINITY, INFINITY, &var->x0, err);
        else if (s2 == POM_OK && !arch_default(ccfg, var->key, &var->x0))
          s2 = pom_cfg_error(cfg, kk, var->key, err,
                             "not a key of the config of candidate '%s' (%s) nor a design "
                             "parameter of its architecture",
                             cd->name, cd->config);
      } else {
        var->x0 = 1.0;
      }
      if (s2 != POM_OK) break;
      snprintf(kk, sizeof kk, "%s.[%d].min", k, v);
      s2 = pom_cfg_real(cfg, kk, 1.0, -INFINITY, INFINITY, &var->lo, err);
      if (s2 != POM_OK) break;
      snprintf(kk, sizeof kk, "%s.[%d].max", k, v);
      s2 = pom_cfg_real(cfg, kk, 1.0, -INFINITY, INFINITY, &var->hi, err);
      if (s2 != POM_OK) break;
      if (!(var->lo < var->hi)) {
        char val[64];
        snprintf(val, sizeof val, "%g", var->hi);
        s2 = pom_cfg_error(cfg, kk, val, err, "max must exceed min (%g)", var->lo);
        break;
      }
      snprintf(kk, sizeof kk, "%s.[%d].log", k, v);
      s2 = pom_cfg_bool_opt(cfg, kk, var->kind == POM_CDS_VAR_SIZE, &var->log, err);
      if (s2 == POM_OK && var->log && !(var->lo > 0)) {
        char val[64];
        snprintf(val, sizeof val, "%g", var->lo);
        snprintf(kk, sizeof kk, "%s.[%d].min", k, v);
        s2 = pom_cfg_error(cfg, kk, val, err, "a log variable needs min > 0");
      }
      if (s2 == POM_OK && (var->x0 < var->lo || var->x0 > var->hi)) {
        char val[64];
        snprintf(val, sizeof val, "%g", var->x0);
        snprintf(kk, sizeof kk, "%s.[%d].key", k, v);
        s2 = pom_cfg_error(cfg, kk, var->key, err,
                           "the config's value %s lies outside [%g, %g]: the co-design starts "
                           "from it",
                           val, var->lo, var->hi);
      }
    }
    cd->n_vars = nv;
    for (int j = 0; j < pb->uncertain.n && s2 == POM_OK; ++j) {
      const char *uk = pb->uncertain.param[j].key;
      cd->nominal_unc[j] = NAN;
      if (pom_cfg_has(ccfg, uk))
        s2 = pom_cfg_real(ccfg, uk, 1.0, -INFINITY, INFINITY, &cd->nominal_unc[j], err);
      else if (pb->uncertain.param[j].relative)
        s2 = pom_cfg_error(cfg, "uncertain", uk, err,
                           "relative = true needs the key in the config of candidate '%s'",
                           cd->name);
    }
    pom_cfg_destroy(ccfg);
    if (s2 != POM_OK) return s2;
  }
  static const char *const scopes[] = {"name", "montecarlo", "codesign", "candidates", NULL};
  return pom_cfg_check_unknown(cfg, scopes, groups, err);
}

void pom_cds_clear(pom_cds_problem *pb) {
  free(pb->config_text);
  memset(pb, 0, sizeof *pb);
}

/* ---- one design as a config --------------------------------------------------------- */
static double var_size(const pom_cds_candidate *cd, const double *x) {
  for (int v = 0; v < cd->n_vars; ++v)
    if (cd->var[v].kind == POM_CDS_VAR_SIZE) return x[v];
  return 1.0;
}

/* The value the design gives key (config units), NaN when it sets none. */
static double design_value(const pom_cds_candidate *cd, const double *x, const char *key) {
  for (int v = 0; v < cd->n_vars; ++v)
    if (cd->var[v].kind == POM_CDS_VAR_KEY && strcmp(cd->var[v].key, key) == 0) return x[v];
  double s = var_size(cd, x);
  for (int j = 0; j < cd->n_sized; ++j)
    if (strcmp(cd->sized[j].key, key) == 0)
      return pom_cds_size_law(cd->sized[j].nominal, cd->sized[j].exponent, s);
  return NAN;
}

/* The value maneuver draws give the uncertain key j at design x: a relative
 * draw multiplies the design's value (or the config's when the design sets
 * none), an absolute one replaces it; config = the candidate's value of the
 * key when it is not an uncertain one's (NaN: take nominal_unc). */
static double drawn_value(const pom_cds_problem *pb, int c, const double *x, const double *draws,
                          int j, double config) {
  const pom_cds_candidate *cd = &pb->cand[c];
  const pom_unc_param *p = &pb->uncertain.param[j];
  if (!p->relative) return draws[j];
  double base = design_value(cd, x, p->key);
  if (!isfinite(base)) base = isfinite(config) ? config : cd->nominal_unc[j];
  return base * draws[j];
}

/* The value maneuver `draws` (NULL: none) give a key at design x, without
 * building anything: the uncertain group's draw, else the design's value,
 * else config (the candidate config's value). */
static double plant_value(const pom_cds_problem *pb, int c, const double *x, const double *draws,
                          const char *key, double config) {
  for (int j = 0; draws && j < pb->uncertain.n; ++j)
    if (strcmp(pb->uncertain.param[j].key, key) == 0)
      return drawn_value(pb, c, x, draws, j, config);
  double v = design_value(&pb->cand[c], x, key);
  return isfinite(v) ? v : config;
}

static pom_status set_num(pom_cfg *cfg, const char *key, double v, pom_error *err) {
  char text[64];
  snprintf(text, sizeof text, "%.17g", v);
  return pom_cfg_set_number(cfg, key, text, "the co-design", err);
}

/* The candidate's config at design x; draws (NULL: none) of the uncertain
 * keys; rigid or parasitic joints. */
static pom_status design_config(pom_cfg **out, const pom_cds_problem *pb, int c, const double *x,
                                const double *draws, int parasitic, pom_error *err) {
  const pom_cds_candidate *cd = &pb->cand[c];
  pom_cfg *cfg = NULL;
  *out = NULL;
  POM_TRY(pom_cfg_load(&cfg, cd->config, err));
  pom_status st = POM_OK;
  for (int v = 0; v < cd->n_vars && st == POM_OK; ++v)
    if (cd->var[v].kind == POM_CDS_VAR_KEY) st = set_num(cfg, cd->var[v].key, x[v], err);
  double s = var_size(cd, x);
  for (int j = 0; j < cd->n_sized && st == POM_OK; ++j)
    st = set_num(cfg, cd->sized[j].key,
                 pom_cds_size_law(cd->sized[j].nominal, cd->sized[j].exponent, s), err);
  if (st == POM_OK)
    st = pom_cfg_set_string(cfg, "joints.model", parasitic ? "parasitic" : "rigid", "the co-design",
                            err);
  for (int j = 0; draws && j < pb->uncertain.n && st == POM_OK; ++j)
    st = set_num(cfg, pb->uncertain.param[j].key, drawn_value(pb, c, x, draws, j, NAN), err);
  if (st != POM_OK) {
    pom_cfg_destroy(cfg);
    return st;
  }
  *out = cfg;
  return POM_OK;
}

/* ---- kinematic margin and envelope (section 11.1) -------------------------------------- */
/* why (may be NULL, cap bytes) receives the term that sets the margin: the
 * pose and which stroke, limit or the dexterity floor, or an unreachable pose. */
static double kin_margin(const pom_cds_problem *pb, const pom_kin_arch *arch, char *why,
                         size_t cap) {
  const int g = pb->ws_grid;
  const double a = pb->ws_half_width;
  double m = -INFINITY;
  for (int i = 0; i < g; ++i)
    for (int j = 0; j < g; ++j)
      for (int k = 0; k < g; ++k) {
        double e[3] = {-a + 2 * a * i / (g - 1), -a + 2 * a * j / (g - 1),
                       -a + 2 * a * k / (g - 1)};
        double R[9];
        pom_euler_zyx_to_matrix(R, e);
        pom_kin_pose pose;
        pom_status st = pom_kin_pose_evaluate(arch, R, &pose, NULL);
        const double deg = 180.0 / 3.14159265358979323846;
        if (!pose.reachable || st == POM_ERR_NONFINITE) {
          if (why && 1.0 > m)
            snprintf(why, cap, "the pose (%.1f, %.1f, %.1f) deg is unreachable", deg * e[0],
                     deg * e[1], deg * e[2]);
          m = fmax(m, 1.0);
          continue;
        }
        for (int l = 0; l < 3; ++l) {
          double v = fabs(pose.q[l]) / (0.5 * arch->stroke) - 1.0;
          if (why && v > m)
            snprintf(why, cap,
                     "actuator %d needs %.0f %% of its half-stroke at (%.1f, %.1f, %.1f) deg",
                     l + 1, 100 * (v + 1), deg * e[0], deg * e[1], deg * e[2]);
          m = fmax(m, v);
        }
        for (int kind = 1; kind < POM_KIN_LIM_KINDS; ++kind) {
          const pom_kin_limit_desc *ld = &arch->type->limits[kind];
          double b = arch->limit_bound[kind];
          if (!ld->key || !(b > 0) || !isfinite(b)) continue;
          for (int mem = 0; mem < 3; ++mem) {
            double v = pose.limit[3 * kind + mem];
            if (!isfinite(v)) continue;
            double r = ld->lower ? 1.0 - v / b : v / b - 1.0;
            if (why && r > m)
              snprintf(why, cap, "%s of limb %d at %.0f %% of its bound at (%.1f, %.1f, %.1f) deg",
                       ld->key, mem + 1, 100 * v / b, deg * e[0], deg * e[1], deg * e[2]);
            m = fmax(m, r);
          }
        }
        if (pb->dexterity_min > 0) {
          double r = 1.0 - pose.dexterity / pb->dexterity_min;
          if (why && r > m)
            snprintf(why, cap, "1/kappa %.3f below the floor %.2f at (%.1f, %.1f, %.1f) deg",
                     pose.dexterity, pb->dexterity_min, deg * e[0], deg * e[1], deg * e[2]);
          m = fmax(m, r);
        }
      }
  return m;
}

static double envelope_of(const pom_mechanism *mech) {
  double r = 0.0;
  for (int j = 0; j < mech->n_joints; ++j)
    r = fmax(r, sqrt(pom_v3_dot(mech->joint[j].point, mech->joint[j].point)));
  return r;
}

/* ---- Monte-Carlo of one design -------------------------------------------------------- */
/* One maneuver's figures. */
typedef struct {
  double t, e, i_peak;
  int failed, settled;
} mv_out;

/* THE one rule for a maneuver that gives no figures (docs/optimize.md 11.1,
 * "A failed maneuver"): a design the model refuses (a value its own
 * validation rejects, a geometry that does not assemble), an unreachable
 * target, a failed simulation. It counts at the worst case the drive allows,
 * from the config, the size law and the maneuver's draws alone (nothing is
 * built): the time at the horizon; the energy at B = n V^2 T / R, every
 * coil stalled at the voltage limit for the whole horizon, which no maneuver
 * exceeds (up to the gravity drop, 11.1); the peak current at
 * sqrt(B / (2 L)), the coil's magnetic energy bound, or, for a quasi-static
 * coil (no bound without the mechanism), twice the size law's limit. Each
 * is continuous in the design, so a refused side of a box reads as the
 * worst time, energy and current, never as the best (11.10). */
static void failed_maneuver(const pom_cds_problem *pb, int c, const double *x, const double *draws,
                            mv_out *o) {
  const pom_cds_candidate *cd = &pb->cand[c];
  const double n_coils = 3.0;
  double v = plant_value(pb, c, x, draws, "actuator.voltage_limit_V", cd->voltage_limit0);
  double r = plant_value(pb, c, x, draws, "actuator.resistance_ohm", NAN);
  double l = plant_value(pb, c, x, draws, "actuator.inductance_H", NAN);
  memset(o, 0, sizeof *o);
  o->failed = 1;
  o->t = cd->horizon;
  o->e = n_coils * v * v * cd->horizon / r;
  o->i_peak = cd->coil_inductance && l > 0 ? sqrt(o->e / (2.0 * l))
                                           : 2.0 * cd->current_limit0 * pow(var_size(cd, x), 1.5);
}

/* One maneuver: design config (with draws), IK of the drawn orientation,
 * simulation with a trace (for the peak current). Until it succeeds, o holds
 * failed_maneuver's worst case. */
static pom_status run_maneuver(const pom_cds_problem *pb, int c, const double *x, uint64_t seed,
                               long k, int parasitic, mv_out *o, pom_error *err) {
  double draws[POM_UNC_MAX];
  pom_unc unc = pb->uncertain;
  unc.seed = seed;
  if (unc.n > 0) pom_unc_draws(&unc, k, draws);
  failed_maneuver(pb, c, x, unc.n > 0 ? draws : NULL, o);
  pom_cfg *cfg = NULL;
  POM_TRY(design_config(&cfg, pb, c, x, unc.n > 0 ? draws : NULL, parasitic, err));
  pom_doe_evaluator ev;
  pom_status st = pom_doe_dyn_evaluator_create(&ev, cfg, NULL, err);
  pom_cfg_destroy(cfg);
  if (st != POM_OK) return st;
  pom_doe_maneuvers mvs = pb->maneuvers;
  mvs.seed = seed;
  pom_doe_maneuver mv;
  pom_doe_maneuver_draw(&mv, &mvs, k);
  double q[3];
  const pom_doe_dyn_base *base = ev.ctx;
  double horizon = base->params.maneuver.horizon;
  pom_error e2;
  pom_error_clear(&e2);
  if (ev.targets(ev.ctx, &mv, q, &e2) != POM_OK) {
    pom_doe_evaluator_clear(&ev);
    return POM_OK;
  }
  void *worker = NULL;
  pom_dyn_trace *tr = NULL;
  st = ev.worker_create(&worker, ev.ctx, err);
  if (st == POM_OK) st = pom_dyn_trace_create(&tr, base->model, err);
  if (st == POM_OK) {
    pom_dyn_metrics mt;
    pom_status rs = pom_dyn_simulate(base->model, worker, q, &mt, tr, &e2);
    if (rs == POM_OK) {
      pom_actuator_kind kind;
      if (pom_doe_mech_actuator_kind(&base->mech, &kind, &e2) == POM_OK)
        rs = pom_doe_check_final_stroke_kind(&mt, base->arch.stroke, kind, &e2);
    }
    if (rs == POM_OK && mt.status == POM_OK) {
      o->failed = 0;
      o->settled = isfinite(mt.pointing_settling_time);
      o->t = o->settled ? mt.pointing_settling_time : horizon;
      o->e = mt.energy_total;
      o->i_peak = 0.0;
      for (int s = 0; s < tr->n; ++s)
        for (int a = 0; a < tr->n_actuators; ++a)
          o->i_peak = fmax(o->i_peak, fabs(tr->current[3 * s + a]));
    }
  }
  pom_dyn_trace_destroy(tr);
  if (worker) ev.worker_destroy(worker);
  pom_doe_evaluator_clear(&ev);
  return st;
}

/* A batch of maneuvers over designs: job j = (design j / n, maneuver k0 + j % n). */
typedef struct {
  const pom_cds_problem *pb;
  int c;
  const double *xs; /* [n_designs][POM_CDS_MAX_VARS] */
  uint64_t seed;
  long k0; /* the first maneuver of the set (0: the whole set) */
  long n;
  int parasitic;
  long n_jobs;
  mv_out *out;
  pthread_mutex_t lock;
  long next;
  pom_status status;
  pom_error err;
  int have_build_err; /* a design failed to build: the first message */
  pom_error build_err;
} batch;

static void *batch_worker(void *arg) {
  batch *b = arg;
  for (;;) {
    pthread_mutex_lock(&b->lock);
    long j = b->status == POM_OK ? b->next++ : b->n_jobs;
    pthread_mutex_unlock(&b->lock);
    if (j >= b->n_jobs) break;
    pom_error e;
    pom_error_clear(&e);
    pom_status st = run_maneuver(b->pb, b->c, b->xs + (j / b->n) * POM_CDS_MAX_VARS, b->seed,
                                 b->k0 + j % b->n, b->parasitic, &b->out[j], &e);
    if (st == POM_ERR_NOMEM) {
      pthread_mutex_lock(&b->lock);
      if (b->status == POM_OK) {
        b->status = st;
        b->err = e;
      }
      pthread_mutex_unlock(&b->lock);
    } else if (st != POM_OK) {
      /* a design the model refuses (a value its own validation rejects, a
       * geometry that does not assemble): the maneuver fails, the design is
       * infeasible, the search goes on; run_maneuver left the worst case of
       * failed_maneuver in out[j] (at 0 the refused side of a box looked
       * like the best objective, section 11.10) */
      pthread_mutex_lock(&b->lock);
      if (!b->have_build_err) {
        b->have_build_err = 1;
        b->build_err = e;
      }
      pthread_mutex_unlock(&b->lock);
    }
  }
  return NULL;
}

static int n_threads(const pom_cds_problem *pb) {
  int t = pb->threads;
  if (t <= 0) {
    long nc = 2;
#ifdef _SC_NPROCESSORS_ONLN
    nc = sysconf(_SC_NPROCESSORS_ONLN);
#endif
    t = nc > 0 ? (int)nc : 1;
  }
  return t > 64 ? 64 : t;
}

void pom_cds_static_figures(const pom_cds_problem *pb, int c, const double *x, pom_cds_figures *f) {
  f->i_limit = pb->cand[c].current_limit0 * pow(var_size(&pb->cand[c], x), 1.5);
  /* kinematics and envelope of the nominal design (no draws) */
  /* a design that does not build has no workspace and no envelope */
  f->kin = 1.0;
  f->envelope = 1e3 * pb->envelope;
  pom_cfg *cfg = NULL;
  pom_error ek;
  pom_error_clear(&ek);
  if (design_config(&cfg, pb, c, x, NULL, 0, &ek) == POM_OK) {
    pom_kin_arch arch;
    if (pom_kin_arch_load(&arch, cfg, &ek) == POM_OK) {
      f->kin = kin_margin(pb, &arch, NULL, 0);
      pom_mechanism mech;
      pom_kin_inertia in;
      if (pom_kin_inertia_load(&in, &arch, cfg, &ek) == POM_OK &&
          pom_kin_mechanism_from(&mech, &arch, &in, &ek) == POM_OK)
        f->envelope = envelope_of(&mech);
    }
    pom_cfg_destroy(cfg);
  }
}

/* THE one aggregation of a design's maneuvers into its figures (both
 * sources: the plain runs of evaluate_many and the sensitivity runs of
 * pom_cds_sens_maneuvers, docs/optimize.md 11.5): a failed maneuver at its
 * worst case (failed_maneuver), the smooth and the order-statistic
 * quantile of the times, the mean energy, the largest peak, the static
 * figures. t: scratch of n. */
static void figures_of(const pom_cds_problem *pb, int c, const double *x, const mv_out *o, long n,
                       double *t, pom_cds_figures *f) {
  memset(f, 0, sizeof *f);
  double esum = 0;
  for (long k = 0; k < n; ++k) {
    /* a failed maneuver at its worst case (failed_maneuver) */
    t[k] = o[k].t;
    esum += o[k].e;
    if (o[k].failed) ++f->failed;
    if (!o[k].settled) ++f->unsettled;
    f->i_peak = fmax(f->i_peak, o[k].i_peak);
  }
  f->n = (int)n;
  f->simulations = n;
  f->energy = esum / (double)n;
  f->p95 = pom_cds_smooth_quantile(t, (int)n, pb->quantile, pb->bandwidth, NULL);
  /* order statistic: the ceil(p n)-th smallest */
  double *srt = malloc((size_t)n * sizeof *srt);
  if (srt) {
    memcpy(srt, t, (size_t)n * sizeof *srt);
    for (long i = 1; i < n; ++i)
      for (long j = i; j > 0 && srt[j - 1] > srt[j]; --j) {
        double tmp = srt[j];
        srt[j] = srt[j - 1];
        srt[j - 1] = tmp;
      }
    long r = (long)ceil(pb->quantile * (double)n) - 1;
    f->p95_plain = srt[r < 0 ? 0 : r];
    free(srt);
  }
  pom_cds_static_figures(pb, c, x, f);
}

/* Figures of n_designs designs (xs rows of POM_CDS_MAX_VARS) on maneuvers
 * k0..k0+n-1 of one set; peaks (NULL: not wanted) receives every
 * maneuver's sampled peak current, [n_designs][n]. */
static pom_status evaluate_many(const pom_cds_problem *pb, int c, const double *xs, int n_designs,
                                uint64_t seed, long k0, long n, int parasitic, int strict,
                                pom_cds_figures *figs, double *peaks, pom_error *err) {
  batch b;
  memset(&b, 0, sizeof b);
  b.pb = pb;
  b.c = c;
  b.xs = xs;
  b.seed = seed;
  b.k0 = k0;
  b.n = n;
  b.parasitic = parasitic;
  b.n_jobs = n * n_designs;
  b.out = calloc((size_t)b.n_jobs, sizeof *b.out);
  double *t = malloc((size_t)n * sizeof *t);
  if (!b.out || !t) {
    free(b.out);
    free(t);
    POM_FAIL(err, POM_ERR_NOMEM, "codesign: out of memory");
  }
  pthread_mutex_init(&b.lock, NULL);
  int nt = n_threads(pb);
  if (nt > b.n_jobs) nt = (int)b.n_jobs;
  pthread_t th[64];
  int started = 0;
  for (int i = 1; i < nt; ++i)
    if (pthread_create(&th[i], NULL, batch_worker, &b) == 0)
      ++started;
    else
      break;
  batch_worker(&b);
  for (int i = 1; i <= started; ++i)
    pthread_join(th[i], NULL);
  pthread_mutex_destroy(&b.lock);
  pom_status st = b.status;
  if (st != POM_OK) *err = b.err;
  for (int d = 0; d < n_designs && st == POM_OK; ++d) {
    const mv_out *o = b.out + (long)d * n;
    figures_of(pb, c, xs + d * POM_CDS_MAX_VARS, o, n, t, &figs[d]);
    for (long k = 0; peaks && k < n; ++k)
      peaks[(long)d * n + k] = o[k].i_peak;
  }
  if (st == POM_OK && strict && b.have_build_err && n_designs == 1 && figs[0].failed == (int)n) {
    /* a single design none of whose maneuvers could even be built: say why */
    *err = b.build_err;
    st = b.build_err.status != POM_OK ? b.build_err.status : POM_ERR_CONFIG;
  }
  free(b.out);
  free(t);
  return st;
}

pom_status pom_cds_evaluate(const pom_cds_problem *pb, int c, const double *x, uint64_t seed,
                            long n, int parasitic, pom_cds_figures *out, pom_error *err) {
  double xs[POM_CDS_MAX_VARS] = {0};
  memcpy(xs, x, sizeof(double) * (size_t)pb->cand[c].n_vars);
  return evaluate_many(pb, c, xs, 1, seed, 0, n, parasitic, 1, out, NULL, err);
}

pom_status pom_cds_evaluate_many(const pom_cds_problem *pb, int c, const double *xs, int n_designs,
                                 uint64_t seed, long n, int parasitic, pom_cds_figures *figs,
                                 pom_error *err) {
  return evaluate_many(pb, c, xs, n_designs, seed, 0, n, parasitic, 0, figs, NULL, err);
}

pom_status pom_cds_evaluate_peaks(const pom_cds_problem *pb, int c, const double *xs, int n_designs,
                                  uint64_t seed, long k0, long n, pom_cds_figures *figs,
                                  double *peaks, pom_error *err) {
  return evaluate_many(pb, c, xs, n_designs, seed, k0, n, 0, 0, figs, peaks, err);
}

pom_status pom_cds_rdw_deg(const pom_cds_problem *pb, int c, const double *x, double *deg,
                           pom_error *err) {
  pom_cfg *cfg = NULL;
  POM_TRY(design_config(&cfg, pb, c, x, NULL, 0, err));
  pom_kin_arch arch;
  pom_kin_ws_opts o;
  pom_status st = pom_kin_arch_load(&arch, cfg, err);
  if (st == POM_OK) st = pom_kin_ws_load(&o, cfg, err);
  pom_cfg_destroy(cfg);
  if (st != POM_OK) return st;
  o.dexterity_min = pb->dexterity_min;
  o.check_limits = 1;
  pom_kin_ws_result r;
  st = pom_kin_workspace(&arch, &o, &r, err);
  if (st == POM_OK) *deg = r.half_width * 180.0 / POM_PI;
  return st;
}

int pom_cds_rdw_below(const pom_cds_problem *pb, const pom_cds_point *p) {
  /* rdw_deg is a multiple of the resolution taken to degrees: 1e-9 deg of
   * slack for the rounding of that product and of the requirement's own */
  return !(p->rdw_deg >= pb->ws_half_width * 180.0 / POM_PI - 1e-9);
}

int pom_cds_design_keys(const pom_cds_candidate *cd, const double *x,
                        const char *key[POM_CDS_MAX_KEYS], double value[POM_CDS_MAX_KEYS],
                        double dvalue_dx[POM_CDS_MAX_KEYS][POM_CDS_MAX_VARS]) {
  int n = 0, vs = -1;
  for (int v = 0; v < cd->n_vars; ++v) {
    if (cd->var[v].kind == POM_CDS_VAR_SIZE) {
      vs = v;
      continue;
    }
    key[n] = cd->var[v].key;
    value[n] = x[v];
    for (int w = 0; w < POM_CDS_MAX_VARS; ++w)
      dvalue_dx[n][w] = w == v ? 1.0 : 0.0;
    ++n;
  }
  double s = vs >= 0 ? x[vs] : 1.0;
  for (int j = 0; j < cd->n_sized; ++j) {
    key[n] = cd->sized[j].key;
    value[n] = pom_cds_size_law(cd->sized[j].nominal, cd->sized[j].exponent, s);
    for (int w = 0; w < POM_CDS_MAX_VARS; ++w)
      dvalue_dx[n][w] = 0.0;
    /* d(nominal s^e)/ds = e nominal s^(e - 1) */
    if (vs >= 0)
      dvalue_dx[n][vs] =
          cd->sized[j].exponent * cd->sized[j].nominal * pow(s, cd->sized[j].exponent - 1.0);
    ++n;
  }
  return n;
}

double pom_cds_dx_du(const pom_cds_var *v, double x) {
  if (v->log) return x * log(10.0) * (log10(v->hi) - log10(v->lo));
  return v->hi - v->lo;
}

/* ---- sensitivities (section 11.5, gradient = "sensitivity") -------------------------- */
/* The directions of the sensitivity parameters, one per design variable v
 * (docs/optimize.md 11.5, 12.1): dirs[v][m] = d(plant value of key m)/dx_v =
 * factor_m dvalue_m/dx_v (factor: the relative draw, 0 for an absolute one)
 * over the np keys (the nd design keys, then the uncertain keys the design
 * does not set, which no direction moves); an inactive variable (fixed in
 * this optimization) gets a zero direction. */
static void sens_dirs(int n_vars, const int *active, int nd, int np, const double *factor,
                      double dvdx[POM_CDS_MAX_KEYS][POM_CDS_MAX_VARS], double *dirs) {
  for (int v = 0; v < n_vars; ++v)
    for (int m = 0; m < np; ++m)
      dirs[v * np + m] = m < nd && (!active || active[v]) ? factor[m] * dvdx[m][v] : 0.0;
}

/* The maneuvers of pom_cds_sens_maneuvers: *good = 0 (why) when one has no
 * figures or no time or energy derivative; POM_OK unless out of memory. */
static pom_status sens_runs(const pom_cds_problem *pb, const pom_cds_candidate *cd, pom_grad **gr,
                            uint64_t seed, long n, int nd, int np, int nv, const int *active,
                            const double *value, double dvdx[POM_CDS_MAX_KEYS][POM_CDS_MAX_VARS],
                            const int *unc_slot, double *t, double *e,
                            double (*dt)[POM_CDS_MAX_VARS], double (*de)[POM_CDS_MAX_VARS],
                            pom_cds_sens_peak *peak, mv_out *o, int *good, char *why,
                            size_t why_cap, pom_error *err) {
  double dirs[POM_CDS_MAX_VARS * POM_GRAD_MAX_PARAMS];
  pom_error e2;
  pom_error_clear(&e2);
  *good = 0;
  pom_doe_maneuvers mvs = pb->maneuvers;
  mvs.seed = seed;
  pom_unc unc = pb->uncertain;
  unc.seed = seed;
  for (long k = 0; k < n; ++k) {
    double draws[POM_UNC_MAX], vals[POM_GRAD_MAX_PARAMS], factor[POM_GRAD_MAX_PARAMS];
    if (unc.n > 0) pom_unc_draws(&unc, k, draws);
    for (int m = 0; m < np; ++m) {
      vals[m] = m < nd ? value[m] : NAN;
      factor[m] = 1.0;
    }
    for (int j = 0; j < unc.n; ++j) {
      const pom_unc_param *p = &unc.param[j];
      int m = unc_slot[j];
      if (p->relative) {
        double base = m < nd ? value[m] : cd->nominal_unc[j];
        vals[m] = base * draws[j];
        factor[m] = draws[j]; /* d(base x draw)/d(base) */
      } else {
        vals[m] = draws[j];
        factor[m] = 0.0; /* the draw replaces the design's value */
      }
    }
    sens_dirs(nv, active, nd, np, factor, dvdx, dirs);
    pom_status st = pom_grad_set_point(*gr, vals, dirs, &e2);
    pom_doe_maneuver mv;
    pom_doe_maneuver_draw(&mv, &mvs, k);
    pom_dyn_metrics mt;
    pom_dyn_grad g;
    memset(&mt, 0, sizeof mt);
    if (st == POM_OK) st = pom_grad_maneuver_orientation(*gr, mv.R, &mt, &g, &e2);
    if (st == POM_ERR_NOMEM) {
      *err = e2;
      return st;
    }
    if (st != POM_OK || mt.status != POM_OK) {
      snprintf(why, why_cap, "maneuver %ld failed in the sensitivity run: %s", k,
               st != POM_OK ? e2.message : pom_status_name(mt.status));
      return POM_OK;
    }
    if (!isfinite(mt.peak_current)) {
      snprintf(why, why_cap, "maneuver %ld: no peak current located", k);
      return POM_OK;
    }
    double horizon = pom_grad_params(*gr)->maneuver.horizon;
    int settled = isfinite(mt.pointing_settling_time);
    const pom_dyn_dmetric *gt = &g.pointing_settling_time, *ge = &g.energy_total;
    if ((settled && !gt->defined) || !ge->defined) {
      snprintf(why, why_cap, "maneuver %ld: %s %s", k, settled && !gt->defined ? "time" : "energy",
               pom_dyn_grad_why_text(settled && !gt->defined ? gt->why : ge->why));
      return POM_OK;
    }
    t[k] = settled ? mt.pointing_settling_time : horizon;
    e[k] = mt.energy_total;
    o[k].t = t[k];
    o[k].e = e[k];
    o[k].i_peak = mt.peak_current; /* located (>= the plain run's sampled peak) */
    o[k].settled = settled;
    o[k].failed = 0;
    /* the parameters are the design variables themselves (their
     * directions carry the size law's tangent and the draws) */
    for (int v = 0; v < POM_CDS_MAX_VARS; ++v) {
      /* an unsettled maneuver counts the horizon: no derivative */
      dt[k][v] = v < nv && settled ? gt->d[v] : 0.0;
      de[k][v] = v < nv ? ge->d[v] : 0.0;
    }
    const pom_dyn_dmetric *gp = &g.peak_current;
    peak->value[k] = mt.peak_current;
    peak->defined[k] = gp->defined;
    peak->why[k] = gp->why;
    for (int v = 0; v < POM_CDS_MAX_VARS; ++v)
      peak->d[k][v] = v < nv && peak->defined[k] ? gp->d[v] : 0.0;
  }
  *good = 1;
  return POM_OK;
}

pom_status pom_cds_sens_maneuvers(const pom_cds_problem *pb, int c, const double *x,
                                  const int *active, uint64_t seed, long n, pom_grad **gr,
                                  double *t, double *e, double (*dt)[POM_CDS_MAX_VARS],
                                  double (*de)[POM_CDS_MAX_VARS], pom_cds_sens_peak *peak,
                                  pom_cds_figures *fig, int *ok, char *why, size_t why_cap,
                                  pom_error *err) {
  const pom_cds_candidate *cd = &pb->cand[c];
  const char *key[POM_GRAD_MAX_PARAMS];
  double value[POM_CDS_MAX_KEYS];
  double dvdx[POM_CDS_MAX_KEYS][POM_CDS_MAX_VARS];
  *ok = 0;
  if (pb->maneuvers.space != POM_DOE_SPACE_ORIENTATION) {
    snprintf(why, why_cap, "joint-space maneuvers (the sensitivities follow orientation targets)");
    return POM_OK;
  }
  int nd = pom_cds_design_keys(cd, x, key, value, dvdx);
  const int nv = cd->n_vars;
  double dirs[POM_CDS_MAX_VARS * POM_GRAD_MAX_PARAMS];
  /* the uncertain keys: one the design sets scales (relative) or replaces
   * (absolute) that key's value; any other is one more parameter, moved to
   * its drawn value per maneuver (its derivative unused) */
  int unc_slot[POM_UNC_MAX];
  int np = nd;
  for (int j = 0; j < pb->uncertain.n; ++j) {
    unc_slot[j] = -1;
    for (int m = 0; m < nd; ++m)
      if (strcmp(key[m], pb->uncertain.param[j].key) == 0) unc_slot[j] = m;
    if (unc_slot[j] >= 0) continue;
    if (np >= POM_GRAD_MAX_PARAMS) {
      snprintf(why, why_cap, "%d design and uncertain keys exceed the %d parameters of a run",
               np + 1, POM_GRAD_MAX_PARAMS);
      return POM_OK;
    }
    unc_slot[j] = np;
    key[np++] = pb->uncertain.param[j].key;
  }
  pom_error e2;
  pom_error_clear(&e2);
  if (!*gr) {
    pom_cfg *cfg = NULL;
    pom_status st = design_config(&cfg, pb, c, x, NULL, 0, &e2);
    if (st == POM_OK) {
      pom_grad_options go;
      pom_grad_options_defaults(&go);
      go.rigid_joints =
          1; /* the optimization set is rigid (design_config's text does not say so) */
      go.peak_current = 0; /* turned on per call below, when the caller asks */
      double one[POM_GRAD_MAX_PARAMS];
      for (int m = 0; m < np; ++m)
        one[m] = 1.0;
      sens_dirs(nv, active, nd, np, one, dvdx, dirs);
      st = pom_grad_create_dirs(gr, cfg, key, np, dirs, nv, &go, &e2);
      pom_cfg_destroy(cfg);
    }
    if (st == POM_ERR_NOMEM) {
      *err = e2;
      return st;
    }
    if (st != POM_OK) {
      *gr = NULL;
      snprintf(why, why_cap, "the sensitivity engine refuses the design: %s", e2.message);
      return POM_OK;
    }
  }
  /* the peak is always watched: it is the point's current figure */
  pom_grad_watch_peak_current(*gr, 1);
  mv_out *o = malloc((size_t)n * sizeof *o);
  if (!o) POM_FAIL(err, POM_ERR_NOMEM, "codesign: out of memory");
  int good = 0;
  pom_status st = sens_runs(pb, cd, gr, seed, n, nd, np, nv, active, value, dvdx, unc_slot, t, e,
                            dt, de, peak, o, &good, why, why_cap, err);
  if (st == POM_OK && good) {
    figures_of(pb, c, x, o, n, t, fig);
    *ok = 1;
  }
  free(o);
  return st;
}

/* ---- why a design misses the requirements (report) ------------------------------------ */
void pom_cds_infeasible_reason(const pom_cds_problem *pb, int c, const double *x,
                               const pom_cds_figures *f, char *why, size_t cap) {
  size_t n = 0;
  why[0] = '\0';
#define ADD(...)                                                                                   \
  do {                                                                                             \
    if (n < cap) n += (size_t)snprintf(why + n, cap - n, __VA_ARGS__);                             \
  } while (0)
  if (f->kin > 1e-6) {
    char k[200] = "the design does not build";
    pom_cfg *cfg = NULL;
    pom_error ek;
    pom_error_clear(&ek);
    if (design_config(&cfg, pb, c, x, NULL, 0, &ek) == POM_OK) {
      pom_kin_arch arch;
      if (pom_kin_arch_load(&arch, cfg, &ek) == POM_OK) (void)kin_margin(pb, &arch, k, sizeof k);
      pom_cfg_destroy(cfg);
    }
    ADD("%sworkspace +-%.0f deg (margin %+.3f): %s", n ? "; " : "",
        pb->ws_half_width * 180.0 / 3.14159265358979323846, f->kin, k);
  }
  if (f->failed == 0 && f->i_peak > f->i_limit * (1 + 1e-6))
    ADD("%speak current %.2f A above the size law's limit %.2f A", n ? "; " : "", f->i_peak,
        f->i_limit);
  if (f->envelope > pb->envelope * (1 + 1e-6))
    ADD("%senvelope %.0f mm above %.0f mm", n ? "; " : "", 1e3 * f->envelope, 1e3 * pb->envelope);
  if (f->failed > 0)
    ADD("%s%d of %d maneuvers failed (each counted at the horizon and the drive's worst energy "
        "and current)",
        n ? "; " : "", f->failed, f->n);
  if (f->p95 > pb->time_max * (1 + 1e-6))
    ADD("%sp95 %.1f ms above the %.0f ms bound", n ? "; " : "", 1e3 * f->p95, 1e3 * pb->time_max);
  if (!n) ADD("no constraint is violated by more than 1e-6 at the figures kept");
#undef ADD
}
