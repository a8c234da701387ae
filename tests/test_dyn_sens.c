/* test_dyn_sens.c - forward sensitivities of one maneuver on the exact path
 * (dynamics/pom_dyn_sens.h, docs/optimize.md "Design gradients"): the
 * gradients of the energies, the final pointing error and the settling
 * times against central differences of whole simulations at a tight
 * tolerance, for parameters of the coil, the controller and the masses
 * (built here as perturbed pom_dyn_params and mechanisms: the dynamics
 * level knows no config); the refusal of a parasitic model; the plain runs
 * on the same data unchanged bit for bit after a sensitivity run. */
#include "check.h"
#include "dyn_test_util.h"
#include "pom_dyn_sens.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The tolerance both the sensitivity run and the differenced runs use: at
 * 1e-10 the whole-run differences of K_P are still 1 % off (their integration
 * error over 2H), at 1e-12 they agree with a Richardson pair to 1e-9. */
#define RTOL 1e-12
/* The relative step of the model differences inside the sensitivities
 * (docs/optimize.md: the saturation's narrow linear band makes a larger one
 * straddle it: 1e-4 gave 1.7e-3 on d energy / d R, 1e-5 1e-5, 3e-6 3e-6). */
#define HREL 3e-6

typedef enum { P_RESISTANCE, P_KP, P_TAU_D, P_FORCE_CONSTANT, P_LIMB_MASS, P_N } param_kind;
static const char *const param_name[P_N] = {"actuator.resistance", "controller.kp", "controller.kd",
                                            "actuator.force_constant", "mass of limb body 1"};

typedef struct {
  pom_kin_arch arch;
  pom_mechanism mech;
  pom_dyn_params p;
} design;

static double *param_ptr(design *x, param_kind k) {
  switch (k) {
  case P_RESISTANCE:
    return &x->p.actuator.resistance;
  case P_KP:
    return &x->p.controller.kp;
  case P_TAU_D:
    return &x->p.controller.kd;
  case P_FORCE_CONSTANT:
    return &x->p.actuator.force_constant;
  case P_LIMB_MASS:
    return &x->mech.body[x->mech.platform == 1 ? 2 : 1].mass;
  default:
    return NULL;
  }
}

static pom_dyn_model *build(const design *x) {
  pom_dyn_model *m = NULL;
  pom_error err;
  if (pom_dyn_model_create(&m, &x->mech, &x->arch, &x->p, &err) != POM_OK) {
    printf("  model: %s\n", err.message);
    return NULL;
  }
  return m;
}

/* One plain run of design x to target q. */
static pom_status plain(const design *x, const double q[3], pom_dyn_metrics *mt) {
  pom_dyn_model *m = build(x);
  pom_dyn_data *d = NULL;
  pom_error err;
  pom_status st = POM_ERR_ARG;
  if (m && pom_dyn_data_create(&d, m, &err) == POM_OK)
    st = pom_dyn_simulate(m, d, q, mt, NULL, &err);
  pom_dyn_data_destroy(d);
  pom_dyn_model_destroy(m);
  return st;
}

static double metric(const pom_dyn_metrics *mt, int k) {
  switch (k) {
  case 0:
    return mt->energy_total;
  case 1:
    return mt->energy[0];
  case 2:
    return mt->final_pointing_error;
  case 3:
    return mt->settling_time[0];
  case 4:
    return mt->settling_time[1];
  case 5:
    return mt->settling_time[2];
  case 6:
    return mt->pointing_settling_time;
  default:
    return NAN;
  }
}
static const pom_dyn_dmetric *dmetric(const pom_dyn_grad *g, int k) {
  switch (k) {
  case 0:
    return &g->energy_total;
  case 1:
    return &g->energy[0];
  case 2:
    return &g->final_pointing_error;
  case 3:
    return &g->settling_time[0];
  case 4:
    return &g->settling_time[1];
  case 5:
    return &g->settling_time[2];
  default:
    return &g->pointing_settling_time;
  }
}
static const char *const metric_name[7] = {
    "energy_total",     "energy[0]",        "final_pointing",   "settling_time[0]",
    "settling_time[1]", "settling_time[2]", "pointing_settling"};

/* Gradients of a shipped design against central differences of whole
 * runs with two steps (Richardson: the O(H^2) truncation of step H is
 * (D(H) - D(H/2)) * 4/3, and the answer D(H/2) + (D(H/2) - D(H))/3). */
static void test_against_fd(const char *file, const double q[3]) {
  design x;
  check_true(load_shipped(file, &x.arch, &x.mech, &x.p));
  x.p.joints.model = POM_JOINTS_RIGID;
  x.p.solver.rtol = RTOL;
  x.p.solver.max_steps = 2000000;
  pom_dyn_model *m = build(&x);
  check_true(m != NULL);
  if (!m) return;
  pom_dyn_data *d = NULL;
  pom_error err;
  check_true(pom_dyn_data_create(&d, m, &err) == POM_OK);
  pom_dyn_sens_spec sp;
  pom_dyn_sens_spec_defaults(&sp);
  sp.n = P_N;
  design xs[2][P_N];
  for (int j = 0; j < P_N; ++j) {
    double v = *param_ptr(&x, (param_kind)j);
    sp.step[j] = HREL * fabs(v);
    sp.scale[j] = fabs(v);
    for (int side = 0; side < 2; ++side) {
      xs[side][j] = x;
      *param_ptr(&xs[side][j], (param_kind)j) = v + (side ? -1 : 1) * sp.step[j];
      pom_dyn_model *mx = build(&xs[side][j]);
      if (side)
        sp.minus[j] = mx;
      else
        sp.plus[j] = mx;
      for (int a = 0; a < 3; ++a)
        (side ? sp.target_minus : sp.target_plus)[j][a] = q[a];
    }
  }
  pom_dyn_metrics mt;
  pom_dyn_grad g;
  pom_status st = pom_dyn_simulate_sens(m, d, q, &sp, &mt, &g, &err);
  check_true(st == POM_OK);
  if (st != POM_OK) printf("  sens: %s\n", err.message);
  printf("%s target (%g, %g, %g) mm: %ld steps, %ld sensitivity RHS\n", file, q[0] * 1e3,
         q[1] * 1e3, q[2] * 1e3, mt.steps, g.sens_rhs_evals);
  for (int j = 0; j < P_N; ++j) {
    double v = *param_ptr(&x, (param_kind)j);
    double D[2][7];
    int ok = 1;
    for (int r = 0; r < 2; ++r) {
      double H = (r ? 0.5e-3 : 1e-3) * fabs(v);
      pom_dyn_metrics mp, mm;
      design a = x, b = x;
      *param_ptr(&a, (param_kind)j) = v + H;
      *param_ptr(&b, (param_kind)j) = v - H;
      ok &= plain(&a, q, &mp) == POM_OK && plain(&b, q, &mm) == POM_OK;
      for (int k = 0; k < 7; ++k)
        D[r][k] = (metric(&mp, k) - metric(&mm, k)) / (2 * H);
    }
    check_true(ok);
    for (int k = 0; k < 7; ++k) {
      const pom_dyn_dmetric *dm = dmetric(&g, k);
      double fd = D[1][k] + (D[1][k] - D[0][k]) / 3.0;
      double trunc = fabs(D[1][k] - D[0][k]);
      double rel = fabs(dm->d[j] - fd) / fmax(fabs(fd), 1e-300);
      /* the error of the elasticity (p / M) dM/dp: a parameter that barely
       * moves a metric (K_P on the energy: 1e-4) has a tiny derivative whose
       * own relative error says nothing of the gradient's use */
      double el = fabs(dm->d[j] - fd) * fabs(v) / fmax(fabs(metric(&mt, k)), 1e-300);
      printf("  d %-18s / d %-24s sens %+.9e  fd %+.9e (rich. %.1e)  rel %.2e  elast. %.2e %s\n",
             metric_name[k], param_name[j], dm->d[j], fd, trunc, rel, el,
             dm->defined ? "" : pom_dyn_grad_why_text(dm->why));
      if (!dm->defined) continue;
      /* tolerances (docs/optimize.md): energies 1e-5, times 1e-4, the final
       * pointing error (a 1e-8 rad residual) 1e-3 */
      double tol = k <= 1 ? 1e-5 : k == 2 ? 1e-3 : 1e-4;
      check_true(el <= tol);
      check_true(trunc <= 0.1 * tol * fabs(metric(&mt, k)) / fabs(v) + 1e-300 || el <= tol);
    }
  }
  for (int j = 0; j < P_N; ++j) {
    pom_dyn_model_destroy((pom_dyn_model *)sp.plus[j]);
    pom_dyn_model_destroy((pom_dyn_model *)sp.minus[j]);
  }
  pom_dyn_data_destroy(d);
  pom_dyn_model_destroy(m);
}

/* A parasitic model is refused; a plain run on the same data after a
 * sensitivity run is the run before it bit for bit. */
static void test_refusal_and_plain(void) {
  design x;
  check_true(load_shipped("3sps.cfg", &x.arch, &x.mech, &x.p));
  const double q[3] = {1e-3, -2e-3, 0.5e-3};
  pom_error err;
  pom_dyn_metrics a, b, c;
  pom_dyn_grad g;
  x.p.joints.model = POM_JOINTS_PARASITIC;
  pom_dyn_model *mp = build(&x);
  pom_dyn_data *dp = NULL;
  check_true(mp && pom_dyn_data_create(&dp, mp, &err) == POM_OK);
  pom_dyn_sens_spec sp;
  pom_dyn_sens_spec_defaults(&sp);
  sp.n = 1;
  sp.step[0] = 1e-3;
  sp.plus[0] = sp.minus[0] = mp;
  check_true(pom_dyn_simulate_sens(mp, dp, q, &sp, &a, &g, &err) == POM_ERR_ARG);
  check_true(strstr(err.message, "rigid") != NULL);
  pom_dyn_data_destroy(dp);
  pom_dyn_model_destroy(mp);

  x.p.joints.model = POM_JOINTS_RIGID;
  design xp = x, xm = x;
  xp.p.actuator.resistance *= 1 + 1e-5;
  xm.p.actuator.resistance *= 1 - 1e-5;
  pom_dyn_model *m = build(&x), *m1 = build(&xp), *m2 = build(&xm);
  pom_dyn_data *d = NULL;
  check_true(m && m1 && m2 && pom_dyn_data_create(&d, m, &err) == POM_OK);
  if (!d) return;
  sp.step[0] = 1e-5 * x.p.actuator.resistance;
  sp.scale[0] = x.p.actuator.resistance;
  sp.plus[0] = m1;
  sp.minus[0] = m2;
  memcpy(sp.target_plus[0], q, sizeof q);
  memcpy(sp.target_minus[0], q, sizeof q);
  check_true(pom_dyn_simulate(m, d, q, &a, NULL, &err) == POM_OK);
  check_true(pom_dyn_simulate_sens(m, d, q, &sp, &b, &g, &err) == POM_OK);
  check_true(g.energy_total.defined && isfinite(g.energy_total.d[0]));
  check_true(pom_dyn_simulate(m, d, q, &c, NULL, &err) == POM_OK);
  a.wall_time = c.wall_time = 0.0;
  check_true(memcmp(&a, &c, sizeof a) == 0);
  /* the sensitivity run's own metrics agree with the plain run's within the
   * integration tolerance (its steps differ: the restarts at the band) */
  check_rel(b.energy_total, a.energy_total, 1e-4);
  pom_dyn_data_destroy(d);
  pom_dyn_model_destroy(m);
  pom_dyn_model_destroy(m1);
  pom_dyn_model_destroy(m2);
}

int main(void) {
  test_refusal_and_plain();
  const double q1[3] = {3e-3, -3e-3, 3e-3};
  test_against_fd("3pss.cfg", q1);
  return check_summary("test_dyn_sens");
}
