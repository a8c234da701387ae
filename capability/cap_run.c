/* cap_run.c - the capability driver (docs/capability.md sections 4 and 5):
 * options, the rigid model, the envelope over the workspace grid and the
 * slews. */
#include "pom_capability.h"

#include "pom_dyn_freq.h"
#include "pom_dyn_rigid.h"
#include "pom_math.h"
#include "pom_progress.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- options --------------------------------------------------------------------- */
void pom_cap_defaults(pom_cap_opts *o) {
  memset(o, 0, sizeof *o);
  o->grid_points = 5;
  o->current_limit = 0.0;
  o->rate_directions = 200;
  o->slew_directions = 4;
  o->bandwidth_grid = 3;
  static const double amp_deg[] = {1.0, 3.0, 10.0, 30.0};
  o->n_amplitudes = 4;
  for (int k = 0; k < 4; ++k)
    o->amplitude[k] = amp_deg[k] * POM_DEG;
}

pom_status pom_cap_load(pom_cap_opts *o, const pom_cfg *cfg, pom_error *err) {
  long v;
  pom_cap_defaults(o);
  POM_TRY(
      pom_cfg_int_opt(cfg, "capability.grid_points", 1, POM_CAP_MAX_GRID, o->grid_points, &v, err));
  if (v % 2 == 0) {
    char text[32];
    snprintf(text, sizeof text, "%ld", v);
    return pom_cfg_error(cfg, "capability.grid_points", text, err,
                         "must be odd (home on the grid)");
  }
  o->grid_points = (int)v;
  POM_TRY(pom_cfg_real_opt(cfg, "capability.current_limit_A", 1.0, 0.0, 1e4, o->current_limit,
                           &o->current_limit, err));
  POM_TRY(
      pom_cfg_int_opt(cfg, "capability.rate_directions", 10, 100000, o->rate_directions, &v, err));
  o->rate_directions = (int)v;
  POM_TRY(pom_cfg_int_opt(cfg, "capability.slew_directions", 0, POM_CAP_MAX_DIRECTIONS,
                          o->slew_directions, &v, err));
  o->slew_directions = (int)v;
  POM_TRY(pom_cfg_int_opt(cfg, "capability.bandwidth_grid_points", 0, POM_CAP_MAX_GRID,
                          o->bandwidth_grid, &v, err));
  if (v > 0 && v % 2 == 0) {
    char text[32];
    snprintf(text, sizeof text, "%ld", v);
    return pom_cfg_error(cfg, "capability.bandwidth_grid_points", text, err,
                         "must be odd (home on the grid) or 0 (none)");
  }
  o->bandwidth_grid = (int)v;
  if (pom_cfg_has(cfg, "capability.slew_amplitudes_deg")) {
    POM_TRY(pom_cfg_reals_var(cfg, "capability.slew_amplitudes_deg", POM_CAP_MAX_AMPLITUDES - 1,
                              POM_DEG, 0.01, 85.0, o->amplitude, &o->n_amplitudes, err));
    for (int k = 1; k < o->n_amplitudes; ++k)
      if (!(o->amplitude[k] > o->amplitude[k - 1]))
        return pom_cfg_error(cfg, "capability.slew_amplitudes_deg", NULL, err,
                             "the amplitudes must be strictly ascending (entry %d, %.10g deg, is "
                             "not above %.10g deg)",
                             k + 1, o->amplitude[k] / POM_DEG, o->amplitude[k - 1] / POM_DEG);
  }
  return POM_OK;
}

/* ---- one pose ---------------------------------------------------------------------- */
/* Speed at which the velocity terms are evaluated for their quadratic form
 * (rad/s): large enough that h stands well above the rounding of f. */
#define CAP_H_PROBE 100.0

pom_status pom_cap_rate_model_at(const pom_dyn_model *m, pom_dyn_data *d, const double R[9],
                                 double current_limit, pom_cap_rate_model *rm,
                                 pom_dyn_rigid_terms *rest, pom_error *err) {
  const pom_dyn_params *p = pom_dyn_model_params(m);
  pom_dyn_rigid_terms t;
  POM_TRY(pom_dyn_rigid_terms_at(m, d, R, NULL, &t, err));
  if (rest) *rest = t;
  memset(rm, 0, sizeof *rm);
  memcpy(rm->J, t.J, sizeof rm->J);
  memcpy(rm->gravity, t.gravity, sizeof rm->gravity);
  rm->K = p->actuator.force_constant;
  rm->Rc = p->actuator.resistance;
  rm->b = p->scene.bearing_friction ? p->actuator.bearing_friction : 0.0;
  rm->V = p->actuator.voltage_limit;
  rm->I_max = current_limit;
  /* the quadratic form of h: h(e_j) and h(e_j + e_l) at the probe speed */
  double hd[3][3], hs[3];
  for (int j = 0; j < 3; ++j) {
    double w[3] = {0.0, 0.0, 0.0};
    w[j] = CAP_H_PROBE;
    pom_dyn_rigid_terms tw;
    POM_TRY(pom_dyn_rigid_terms_at(m, d, R, w, &tw, err));
    for (int k = 0; k < 3; ++k)
      hd[j][k] = tw.velocity[k] / (CAP_H_PROBE * CAP_H_PROBE);
  }
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      rm->H[k][4 * j] = hd[j][k];
  for (int j = 0; j < 3; ++j)
    for (int l = j + 1; l < 3; ++l) {
      double w[3] = {0.0, 0.0, 0.0};
      w[j] = w[l] = CAP_H_PROBE;
      pom_dyn_rigid_terms tw;
      POM_TRY(pom_dyn_rigid_terms_at(m, d, R, w, &tw, err));
      for (int k = 0; k < 3; ++k) {
        hs[k] = tw.velocity[k] / (CAP_H_PROBE * CAP_H_PROBE);
        double off = 0.5 * (hs[k] - hd[j][k] - hd[l][k]);
        rm->H[k][3 * j + l] = rm->H[k][3 * l + j] = off;
      }
    }
  return POM_OK;
}

static pom_status pose_eval(const pom_dyn_model *m, pom_dyn_data *d, const pom_cap_opts *o,
                            double f_max, pom_cap_pose *pp, pom_error *err) {
  double R[9];
  pom_euler_zyx_to_matrix(R, pp->euler);
  pom_dyn_rigid_terms t;
  pom_cap_rate_model rm;
  POM_TRY(pom_cap_rate_model_at(m, d, R, o->current_limit, &rm, &t, err));
  memcpy(pp->q, t.q, sizeof pp->q);
  pp->acc_inscribed = pom_cap_acc_inscribed(t.M, t.J, t.gravity, f_max, pp->acc_worst_dir);
  pp->rate_inscribed = pom_cap_rate_inscribed(&rm, o->rate_directions, pp->rate_worst_dir);
  (void)pom_cap_rate_along(&rm, pp->rate_worst_dir, &pp->rate_binding);
  pom_cap_rate_model emf = rm;
  emf.no_velocity_terms = 1;
  pp->rate_emf_inscribed = pom_cap_rate_inscribed(&emf, o->rate_directions, NULL);
  for (int k = 0; k < 3; ++k) {
    double e[3] = {0.0, 0.0, 0.0}, me[3];
    e[k] = 1.0;
    pom_v3_scale(me, -1.0, e);
    pp->acc_axis[k] = fmin(pom_cap_acc_along(t.M, t.J, t.gravity, f_max, e),
                           pom_cap_acc_along(t.M, t.J, t.gravity, f_max, me));
    pp->rate_axis[k] = fmin(pom_cap_rate_along(&rm, e, NULL), pom_cap_rate_along(&rm, me, NULL));
    pp->rate_emf_axis[k] =
        fmin(pom_cap_rate_along(&emf, e, NULL), pom_cap_rate_along(&emf, me, NULL));
  }
  if (!isfinite(pp->acc_inscribed) || !isfinite(pp->rate_inscribed))
    POM_FAIL(err, POM_ERR_SINGULAR, "the Jacobian is singular or the rate unbounded");
  pp->ok = 1;
  return POM_OK;
}

/* ---- the small-signal figures at one pose (docs/capability.md section 7) ----------- */
static pom_status pose_freq(const pom_dyn_model *m, pom_dyn_data *d, pom_cap_pose *pp,
                            pom_error *err) {
  pom_dyn_freq_figures F;
  POM_TRY(pom_dyn_freq_figures_at(m, d, pp->q, &F, err));
  memcpy(pp->bw_axis_hz, F.bandwidth_hz, sizeof pp->bw_axis_hz);
  pp->bw_worst_hz = F.bandwidth_worst_hz;
  pp->peak_db_worst = F.peak_db_worst;
  pp->pm_deg_min = pp->gm_db_min = INFINITY;
  for (int a = 0; a < F.n_actuators; ++a) {
    pp->pm_deg_min = fmin(pp->pm_deg_min, F.phase_margin_deg[a]);
    pp->gm_db_min = fmin(pp->gm_db_min, F.gain_margin_db[a]);
  }
  pp->mode_hz = F.n_modes > 0 ? F.mode_hz[0] : NAN;
  pp->mode_zeta = F.n_modes > 0 ? F.mode_zeta[0] : NAN;
  pp->freq_ok = 1;
  return POM_OK;
}

/* 1 when grid index i (0 .. n1 - 1) lies on the bandwidth sub-grid of nb
 * points per angle: half + round(k half / hb), k = -hb .. hb, symmetric
 * about home with both edges in. */
static int on_subgrid(int i, int n1, int nb) {
  if (nb <= 0) return 0;
  const int half = (n1 - 1) / 2, hb = (nb - 1) / 2;
  if (hb == 0 || nb >= n1) return nb >= n1 || i == half;
  for (int k = -hb; k <= hb; ++k)
    if (half + lround((double)k * half / hb) == i) return 1;
  return 0;
}

/* ---- one pose, any rotation --------------------------------------------------------- */
struct pom_cap_ctx {
  pom_dyn_model *m, *mf; /* rigid; the config's own (NULL: no small-signal figures) */
  pom_dyn_data *d, *df;
  pom_cap_opts o;
  double f_max;
};

static double effort_limit(const pom_dyn_params *p, const pom_cap_opts *o) {
  const double i_lim = p->actuator.voltage_limit / p->actuator.resistance;
  return p->actuator.force_constant *
         (o->current_limit > 0 ? fmin(o->current_limit, i_lim) : i_lim);
}

void pom_cap_ctx_destroy(pom_cap_ctx *c) {
  if (!c) return;
  pom_dyn_data_destroy(c->df);
  pom_dyn_model_destroy(c->mf);
  pom_dyn_data_destroy(c->d);
  pom_dyn_model_destroy(c->m);
  free(c);
}

pom_status pom_cap_ctx_create(pom_cap_ctx **out, const pom_kin_arch *arch,
                              const pom_mechanism *mech, const pom_dyn_params *p,
                              const pom_cap_opts *o, int with_freq, pom_error *err) {
  pom_status st = POM_OK;
  *out = NULL;
  pom_cap_ctx *c = calloc(1, sizeof *c);
  if (!c) POM_FAIL(err, POM_ERR_NOMEM, "allocating the capability context");
  c->o = *o;
  pom_dyn_params pr = *p;
  pr.joints.model = POM_JOINTS_RIGID;
  POM_TRY_GOTO(pom_dyn_model_create(&c->m, mech, arch, &pr, err), fail);
  POM_TRY_GOTO(pom_dyn_data_create(&c->d, c->m, err), fail);
  if (with_freq) {
    POM_TRY_GOTO(pom_dyn_model_create(&c->mf, mech, arch, p, err), fail);
    POM_TRY_GOTO(pom_dyn_data_create(&c->df, c->mf, err), fail);
  }
  c->f_max = effort_limit(&pr, o);
  *out = c;
  return POM_OK;
fail:
  pom_cap_ctx_destroy(c);
  return st;
}

pom_status pom_cap_pose_eval(pom_cap_ctx *c, const double R[9], pom_cap_pose *pp, pom_error *err) {
  memset(pp, 0, sizeof *pp);
  pp->bw_axis_hz[0] = pp->bw_axis_hz[1] = pp->bw_axis_hz[2] = NAN;
  pp->bw_worst_hz = pp->peak_db_worst = pp->pm_deg_min = pp->gm_db_min = NAN;
  pp->mode_hz = pp->mode_zeta = NAN;
  if (pom_euler_zyx_from_matrix(pp->euler, R) != POM_OK)
    POM_FAIL(err, POM_ERR_EULER_SINGULAR, "capability: the pose has pitch 90 deg");
  POM_TRY(pose_eval(c->m, c->d, &c->o, c->f_max, pp, err));
  if (c->mf) POM_TRY(pose_freq(c->mf, c->df, pp, err));
  return POM_OK;
}

#define CAP_RAD_TO_DEG (180.0 / POM_PI)
static const pom_cap_pose_figure pose_figures[] = {
    {"acc_inscribed", "deg/s^2", CAP_RAD_TO_DEG, 0,
     "angular acceleration from rest reachable in every direction"},
    {"rate_inscribed", "deg/s", CAP_RAD_TO_DEG, 0,
     "steady angular rate sustained in every direction"},
    {"rate_emf_inscribed", "deg/s", CAP_RAD_TO_DEG, 0,
     "steady rate against back-EMF alone (no velocity-product terms)"},
    {"bw_worst", "Hz", 1.0, 1, "-3 dB bandwidth of the closed loop in the worst direction"},
    {"pm_min", "deg", 1.0, 1, "smallest phase margin of the actuator loops"},
    {"mode", "Hz", 1.0, 1, "lowest parasitic joint mode"},
};

const pom_cap_pose_figure *pom_cap_pose_figures(int *n) {
  *n = (int)(sizeof pose_figures / sizeof pose_figures[0]);
  return pose_figures;
}

const pom_cap_pose_figure *pom_cap_pose_figure_find(const char *name) {
  int n;
  const pom_cap_pose_figure *t = pom_cap_pose_figures(&n);
  for (int k = 0; k < n; ++k)
    if (name && strcmp(t[k].name, name) == 0) return &t[k];
  return NULL;
}

double pom_cap_pose_figure_value(const pom_cap_pose_figure *f, const pom_cap_pose *pp) {
  const int k = (int)(f - pose_figures);
  if (!pp->ok || (f->freq && !pp->freq_ok)) return NAN;
  const double v[] = {pp->acc_inscribed, pp->rate_inscribed, pp->rate_emf_inscribed,
                      pp->bw_worst_hz,   pp->pm_deg_min,     pp->mode_hz};
  return v[k] * f->to_display;
}

/* ---- slews ------------------------------------------------------------------------- */
/* 1 when the rotation passes the workspace criteria of kin_workspace.c. */
static int pose_passes(const pom_kin_arch *arch, const pom_kin_ws_opts *ws, const double R[9]) {
  pom_kin_pose kp;
  pom_status st = pom_kin_pose_evaluate(arch, R, &kp, NULL);
  if (!kp.reachable || (st == POM_ERR_LIMIT && ws->check_limits)) return 0;
  return kp.dexterity >= ws->dexterity_min;
}

/* The largest angle about d (steps of ws->resolution, up to max_half_width)
 * whose every step passes. */
static double edge_along(const pom_kin_arch *arch, const pom_kin_ws_opts *ws, const double d[3]) {
  double edge = 0.0;
  for (int k = 1; k * ws->resolution <= ws->max_half_width + 1e-12; ++k) {
    double R[9];
    pom_m3_axis_angle(R, d, k * ws->resolution);
    if (!pose_passes(arch, ws, R)) break;
    edge = k * ws->resolution;
  }
  return edge;
}

static void slew_plan(const pom_kin_arch *arch, const pom_kin_ws_opts *ws, const pom_cap_opts *o,
                      int k, pom_cap_slew *s) {
  memset(s, 0, sizeof *s);
  double v[3] = {k == 0 || k == 3, k == 1 || k == 3, k == 2 || k == 3};
  pom_v3_normalize(s->dir, v);
  s->edge = edge_along(arch, ws, s->dir);
  for (int a = 0; a < o->n_amplitudes; ++a) {
    if (o->amplitude[a] < s->edge - 1e-12)
      s->amplitude[s->n++] = o->amplitude[a];
    else if (o->amplitude[a] > s->edge + 1e-12)
      s->n_beyond++;
  }
  if (s->edge > 0) s->amplitude[s->n++] = s->edge;
}

static void slew_run(const pom_dyn_model *m, pom_dyn_data *d, pom_cap_slew *s, int j) {
  double R[9];
  pom_dyn_rigid_terms t;
  pom_dyn_metrics mt;
  pom_error e;
  pom_error_clear(&e);
  pom_m3_axis_angle(R, s->dir, s->amplitude[j]);
  s->slew_time[j] = s->peak_rate[j] = NAN;
  s->status[j] = pom_dyn_rigid_terms_at(m, d, R, NULL, &t, &e);
  if (s->status[j] != POM_OK) return;
  s->status[j] = pom_dyn_simulate(m, d, t.q, &mt, NULL, &e);
  s->slew_time[j] = mt.pointing_settling_time;
  s->peak_rate[j] = mt.peak_angular_rate;
}

/* ---- driver ------------------------------------------------------------------------ */
void pom_cap_result_free(pom_cap_result *r) {
  if (!r) return;
  free(r->pose);
  r->pose = NULL;
}

pom_status pom_cap_write_bode(const char *path, const pom_kin_arch *arch, const pom_mechanism *mech,
                              const pom_dyn_params *p, const double q_pose[3], double f_lo,
                              double f_hi, int per_decade, pom_error *err) {
  pom_dyn_model *m = NULL;
  pom_dyn_data *d = NULL;
  FILE *f = NULL;
  pom_status st = POM_OK;
  POM_TRY_GOTO(pom_dyn_model_create(&m, mech, arch, p, err), done);
  POM_TRY_GOTO(pom_dyn_data_create(&d, m, err), done);
  f = fopen(path, "w");
  if (!f) POM_FAIL_GOTO(err, POM_ERR_IO, done, "cannot write '%s': %s", path, strerror(errno));
  POM_TRY_GOTO(pom_dyn_freq_json(f, m, d, q_pose, f_lo, f_hi, per_decade, err), done);
done:
  if (f && (ferror(f) | fclose(f)) && st == POM_OK)
    st = pom_error_set(err, POM_ERR_IO, __FILE__, __LINE__, "writing '%s' failed", path);
  pom_dyn_data_destroy(d);
  pom_dyn_model_destroy(m);
  return st;
}

/* The small-signal figures at pose k (once), the worst over the workspace
 * updated; a failure is counted, its first status kept. */
static void freq_at(const pom_dyn_model *m, pom_dyn_data *d, pom_cap_result *r, int k) {
  pom_cap_pose *pp = &r->pose[k];
  if (pp->freq_ok || !pp->ok) return;
  pom_error e;
  pom_error_clear(&e);
  pom_status st = pose_freq(m, d, pp, &e);
  if (st != POM_OK) {
    if (r->n_freq_failed++ == 0) r->freq_status = st;
    return;
  }
  r->n_freq++;
  if (isfinite(pp->bw_worst_hz) &&
      (r->worst_bw < 0 || pp->bw_worst_hz < r->pose[r->worst_bw].bw_worst_hz)) {
    r->worst_bw = k;
    r->bw_worst_hz = pp->bw_worst_hz;
  }
  if (!isnan(pp->pm_deg_min) &&
      (r->worst_pm < 0 || pp->pm_deg_min < r->pose[r->worst_pm].pm_deg_min)) {
    r->worst_pm = k;
    r->pm_worst_deg = pp->pm_deg_min;
  }
}

pom_status pom_cap_run(const pom_kin_arch *arch, const pom_kin_ws_opts *ws,
                       const pom_mechanism *mech, const pom_dyn_params *p, const pom_cap_opts *o,
                       pom_cap_result *r, pom_error *err) {
  pom_status st = POM_OK;
  pom_dyn_model *m = NULL, *mf = NULL;
  pom_dyn_data *d = NULL, *df = NULL;
  memset(r, 0, sizeof *r);
  const double t0 = pom_progress_now();
  pom_kin_ws_opts wso = *ws;
  wso.progress = NULL;
  pom_kin_ws_result wr;
  POM_TRY(pom_kin_workspace(arch, &wso, &wr, err));
  if (wr.half_width < 0)
    POM_FAIL(err, POM_ERR_UNREACHABLE,
             "the home pose fails the workspace criteria: no workspace to evaluate");
  r->half_width = wr.half_width;
  const int n1 = o->grid_points, half = (n1 - 1) / 2;
  r->step = half > 0 ? wr.half_width / half : 0.0;
  r->n_poses = n1 * n1 * n1;
  r->kind = p->actuator.kind;
  r->pose = calloc((size_t)r->n_poses, sizeof *r->pose);
  if (!r->pose) POM_FAIL(err, POM_ERR_NOMEM, "allocating %d poses", r->n_poses);
  for (int k = 0; k < r->n_poses; ++k) {
    pom_cap_pose *pp = &r->pose[k];
    pp->bw_axis_hz[0] = pp->bw_axis_hz[1] = pp->bw_axis_hz[2] = NAN;
    pp->bw_worst_hz = pp->peak_db_worst = pp->pm_deg_min = pp->gm_db_min = NAN;
    pp->mode_hz = pp->mode_zeta = NAN;
  }
  r->worst_bw = r->worst_pm = -1;
  r->freq_joints = p->joints.model;
  r->bw_worst_hz = r->pm_worst_deg = NAN;

  pom_dyn_params pr = *p;
  pr.joints.model = POM_JOINTS_RIGID;
  POM_TRY_GOTO(pom_dyn_model_create(&m, mech, arch, &pr, err), done);
  POM_TRY_GOTO(pom_dyn_data_create(&d, m, err), done);
  if (o->bandwidth_grid > 0) {
    POM_TRY_GOTO(pom_dyn_model_create(&mf, mech, arch, p, err), done);
    POM_TRY_GOTO(pom_dyn_data_create(&df, mf, err), done);
  }
  r->f_max = effort_limit(&pr, o);

  int n_slews = 0;
  r->n_dirs = o->slew_directions;
  for (int k = 0; k < r->n_dirs; ++k) {
    slew_plan(arch, ws, o, k, &r->slew[k]);
    n_slews += r->slew[k].n;
  }
  int n_sub = 0;
  for (int i = 0; i < n1; ++i)
    n_sub += on_subgrid(i, n1, o->bandwidth_grid);
  const long n_freq = (long)n_sub * n_sub * n_sub;
  const long total = r->n_poses + n_freq + n_slews;
  long done = 0;
  r->home = r->worst_acc = r->worst_rate = -1;
  for (int i = 0; i < n1; ++i)
    for (int j = 0; j < n1; ++j)
      for (int l = 0; l < n1; ++l) {
        const int k = (i * n1 + j) * n1 + l;
        pom_cap_pose *pp = &r->pose[k];
        pp->euler[0] = (i - half) * r->step;
        pp->euler[1] = (j - half) * r->step;
        pp->euler[2] = (l - half) * r->step;
        if (i == half && j == half && l == half) r->home = k;
        pom_error pe;
        pom_error_clear(&pe);
        int ok = pose_eval(m, d, o, r->f_max, pp, &pe) == POM_OK;
        if (o->progress) o->progress(o->progress_user, ++done, total);
        if (!ok && k == r->home) {
          if (err) *err = pe;
          st = pe.status;
          goto done;
        }
        if (!ok) continue; /* not evaluated (ok = 0) */
        if (r->worst_acc < 0 || pp->acc_inscribed < r->pose[r->worst_acc].acc_inscribed)
          r->worst_acc = k;
        if (r->worst_rate < 0 || pp->rate_inscribed < r->pose[r->worst_rate].rate_inscribed)
          r->worst_rate = k;
      }
  /* the small-signal figures on the sub-grid, then at the worst envelope poses */
  if (mf) {
    for (int i = 0; i < n1; ++i)
      for (int j = 0; j < n1; ++j)
        for (int l = 0; l < n1; ++l) {
          const int nb = o->bandwidth_grid;
          if (!on_subgrid(i, n1, nb) || !on_subgrid(j, n1, nb) || !on_subgrid(l, n1, nb)) continue;
          freq_at(mf, df, r, (i * n1 + j) * n1 + l);
          if (o->progress) o->progress(o->progress_user, ++done, total);
        }
    if (r->worst_acc >= 0) freq_at(mf, df, r, r->worst_acc);
    if (r->worst_rate >= 0) freq_at(mf, df, r, r->worst_rate);
  }
  for (int k = 0; k < r->n_dirs; ++k)
    for (int j = 0; j < r->slew[k].n; ++j) {
      slew_run(m, d, &r->slew[k], j);
      if (o->progress) o->progress(o->progress_user, ++done, total);
    }
done:
  r->wall_time = pom_progress_now() - t0;
  pom_dyn_data_destroy(df);
  pom_dyn_model_destroy(mf);
  pom_dyn_data_destroy(d);
  pom_dyn_model_destroy(m);
  return st;
}
