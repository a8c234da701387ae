/* test_capability.c - the capability envelope (docs/capability.md section 6):
 * the polytope algebra against brute force and a decoupled case, the rate
 * roots against a direct evaluation of the rigid terms, and the figures
 * against saturated bang-bang simulations through pom_dyn_simulate on the
 * shipped 3P-S-S/S (constant voltages from an open-loop controller). */
#include "check.h"
#include "dyn_test_util.h"
#include "pom_capability.h"
#include "pom_dyn_ctrl.h"
#include "pom_math.h"
#include "pom_rng.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- an open-loop controller: u = G q_set (the setpoint carries the voltage) ---- */
#define OPEN_GAIN 1e4 /* V per m of setpoint: 24 V = 2.4 mm, inside the 6 mm half-stroke */

static double open_law(const pom_dyn_controller *c, const pom_dyn_ctrl_input *in, const double *z,
                       double *zdot) {
  (void)z;
  (void)zdot;
  return c->gain[0] * in->target;
}
static int open_describe(const pom_dyn_controller *c, char *buf, size_t cap) {
  return snprintf(buf, cap, "u = %g q_set (open loop)", c->gain[0]);
}
static const pom_dyn_gain_desc open_gains[] = {{.key = "gain_V_per_m",
                                                .symbol = "G",
                                                .unit = "V/m",
                                                .meaning = "voltage per setpoint",
                                                .lo = 0.0,
                                                .hi = 1e9,
                                                .def = OPEN_GAIN,
                                                .offset = POM_DYN_CTRL_GAIN_SLOT(0)}};
static const pom_dyn_ctrl_type open_loop = {.name = "open_loop_test",
                                            .label = "open loop",
                                            .description = "constant voltages (test)",
                                            .n_gains = 1,
                                            .gains = open_gains,
                                            .law = open_law,
                                            .describe = open_describe};

/* ---- 1. the polytope algebra ------------------------------------------------------ */
static void random_unit(pom_rng *rng, double d[3]) {
  double v[3];
  do {
    for (int k = 0; k < 3; ++k)
      v[k] = pom_rng_normal(rng);
  } while (pom_v3_norm(v) < 1e-3);
  pom_v3_normalize(d, v);
}

static void test_polytope(void) {
  printf("polytope: inscribed radius against 20000 random directions\n");
  pom_rng rng;
  pom_rng_seed(&rng, 20261128, 0);
  /* a general M (SPD), J and gravity */
  const double M[9] = {5.31e-6, 0.42e-6,  -0.17e-6, 0.42e-6, 4.77e-6,
                       0.33e-6, -0.17e-6, 0.33e-6,  7.385e-6};
  const double J[9] = {0.0151, -0.0032, 0.0071, 0.0044, 0.0139, -0.0062, -0.0081, 0.0052, 0.0122};
  const double g[3] = {0.0123, -0.0081, 0.0027};
  const double f_max = 9.12;
  double worst[3];
  double r = pom_cap_acc_inscribed(M, J, g, f_max, worst);
  double s_min = INFINITY;
  int below = 0;
  for (int k = 0; k < 20000; ++k) {
    double d[3];
    random_unit(&rng, d);
    double s = pom_cap_acc_along(M, J, g, f_max, d);
    below += s < r * (1 - 1e-12);
    s_min = fmin(s_min, s);
  }
  check_true(below == 0);
  /* the nearest of 20000 directions is ~0.013 rad from the facet normal:
   * s = r / cos(angle), within 1e-4 */
  check_rel(s_min, r, 1e-3);
  check_rel(pom_cap_acc_along(M, J, g, f_max, worst), r, 1e-12);

  printf("polytope: a decoupled case, B diagonal and no gravity: inscribed = axis minimum\n");
  const double Md[9] = {2.385e-6, 0, 0, 0, 3.17e-6, 0, 0, 0, 4.41e-6};
  const double Jd[9] = {0.015, 0, 0, 0, 0.0131, 0, 0, 0, 0.0172};
  const double g0[3] = {0, 0, 0};
  double axis_min = INFINITY;
  for (int k = 0; k < 3; ++k) {
    double e[3] = {0, 0, 0};
    e[k] = 1.0;
    double s = pom_cap_acc_along(Md, Jd, g0, f_max, e);
    check_rel(s, f_max * Jd[4 * k] / Md[4 * k], 1e-14); /* F J_k / I_k */
    axis_min = fmin(axis_min, s);
  }
  check_rel(pom_cap_acc_inscribed(Md, Jd, g0, f_max, NULL), axis_min, 1e-14);
  /* gravity beyond the effort: the pose cannot be held */
  const double g_big[3] = {0.2, 0, 0}; /* J^-T g = 13.3 N > 9.12 N */
  check_abs(pom_cap_acc_inscribed(Md, Jd, g_big, f_max, NULL), 0.0, 0.0);

  printf("rate: inscribed minimum against 20000 random directions\n");
  pom_cap_rate_model rm;
  memset(&rm, 0, sizeof rm);
  memcpy(rm.J, J, sizeof rm.J);
  memcpy(rm.gravity, g, sizeof g);
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j <= i; ++j)
        rm.H[k][3 * i + j] = rm.H[k][3 * j + i] = 1e-7 * (0.3 + k - 0.7 * i + 0.45 * j);
  rm.K = 3.8, rm.Rc = 10.0, rm.b = 0.098, rm.V = 24.0;
  double rw[3];
  double rr = pom_cap_rate_inscribed(&rm, 200, rw);
  double rmin = INFINITY;
  below = 0;
  for (int k = 0; k < 20000; ++k) {
    double d[3];
    random_unit(&rng, d);
    double s = pom_cap_rate_along(&rm, d, NULL);
    below += s < rr * (1 - 1e-9);
    rmin = fmin(rmin, s);
  }
  check_true(below == 0);
  check_rel(rmin, rr, 1e-3);
  /* the back-EMF limit alone: no h, no gravity, linear: V / ((R b / K + K) max_a |J_a d|) */
  pom_cap_rate_model lin = rm;
  lin.no_velocity_terms = 1;
  memset(lin.gravity, 0, sizeof lin.gravity);
  const double ex[3] = {1, 0, 0};
  double jmax = fmax(fabs(J[0]), fmax(fabs(J[3]), fabs(J[6])));
  check_rel(pom_cap_rate_along(&lin, ex, NULL), 24.0 / ((10.0 * 0.098 / 3.8 + 3.8) * jmax), 1e-14);
}

/* ---- 2. bang-bang simulations on the shipped 3P-S-S/S --------------------------- */
/* The rotation vector of the platform at trace sample k. */
static void rotvec_at(const pom_dyn_trace *tr, int k, double rv[3]) {
  double R[9];
  pom_quat_to_matrix(R, tr->quat + 4 * k);
  pom_m3_rotvec(rv, R);
}

/* Runs the open-loop voltages u from rest (w0 NULL) or from w0 at home for T
 * with samples every T/8; a(t) = 2 (rv(t) - w0 t) / t^2 at T/2 and T, then
 * Richardson: the initial angular acceleration (rad/s^2). */
static int initial_acceleration(const pom_mechanism *mech, const pom_kin_arch *arch,
                                const pom_dyn_params *p, const double u[3], const double *w0,
                                double T, double acc[3]) {
  pom_dyn_params q = *p;
  q.maneuver.horizon = T;
  q.maneuver.output_dt = T / 8;
  double target[3];
  for (int a = 0; a < 3; ++a)
    target[a] = u[a] / OPEN_GAIN;
  pom_dyn_initial init;
  memset(&init, 0, sizeof init);
  if (w0) memcpy(init.omega[mech->platform], w0, 3 * sizeof(double));
  run_t r;
  if (run_arch(&r, mech, arch, &q, target, &init) != POM_OK || r.tr->n < 9) {
    run_free(&r);
    return 0;
  }
  double a_half[3], a_full[3], rv[3];
  const double th = r.tr->t[4], tf = r.tr->t[8];
  check_rel(tf, T, 1e-12);
  rotvec_at(r.tr, 4, rv);
  for (int k = 0; k < 3; ++k)
    a_half[k] = 2.0 * (rv[k] - (w0 ? w0[k] : 0.0) * th) / (th * th);
  rotvec_at(r.tr, 8, rv);
  for (int k = 0; k < 3; ++k) {
    a_full[k] = 2.0 * (rv[k] - (w0 ? w0[k] : 0.0) * tf) / (tf * tf);
    acc[k] = 2.0 * a_half[k] - a_full[k];
  }
  run_free(&r);
  return 1;
}

static void test_bang_bang(void) {
  pom_kin_arch arch;
  pom_mechanism *mech = calloc(1, sizeof *mech);
  pom_dyn_params p;
  if (!check_true(mech && load_shipped("3pss.cfg", &arch, mech, &p))) {
    free(mech);
    return;
  }
  p.joints.model = POM_JOINTS_RIGID;
  p.scene.coil_inductance = 0; /* the current follows the voltage: the figure is from rest */
  p.solver.rtol = 1e-10;
  p.solver.atol_scale = 0.0;
  p.controller.type = &open_loop;
  p.controller.gain[0] = OPEN_GAIN;
  pom_dyn_model *m = NULL;
  pom_dyn_data *d = NULL;
  pom_error err;
  pom_error_clear(&err);
  if (!check_true(pom_dyn_model_create(&m, mech, &arch, &p, &err) == POM_OK &&
                  pom_dyn_data_create(&d, m, &err) == POM_OK)) {
    printf("  %s\n", err.message);
    goto done;
  }
  const double K = p.actuator.force_constant, Rc = p.actuator.resistance;
  const double V = p.actuator.voltage_limit, b = p.actuator.bearing_friction;
  const double f_max = K * V / Rc;
  double I3[9];
  pom_m3_identity(I3);
  pom_cap_rate_model rm;
  pom_dyn_rigid_terms t;
  if (!check_true(pom_cap_rate_model_at(m, d, I3, 0.0, &rm, &t, &err) == POM_OK)) goto done;
  double JiT[9], Ji[9];
  pom_m3_inverse(Ji, t.J, 0.0);
  pom_m3_transpose(JiT, Ji);
  for (int k = 0; k < 3; ++k) {
    double e[3] = {0, 0, 0};
    e[k] = 1.0;
    /* acceleration: the efforts F* = J^-T (M s e - g), one at the limit */
    double s = pom_cap_acc_along(t.M, t.J, t.gravity, f_max, e), Ms[3], F[3], u[3], acc[3];
    pom_m3_apply(Ms, t.M, e);
    for (int i = 0; i < 3; ++i)
      Ms[i] = s * Ms[i] - t.gravity[i];
    pom_m3_apply(F, JiT, Ms);
    double umax = 0;
    for (int a = 0; a < 3; ++a) {
      u[a] = Rc * F[a] / K;
      umax = fmax(umax, fabs(u[a]));
    }
    printf("bang-bang along %c: s_max = %.6g rad/s^2, voltages %.4g %.4g %.4g V\n", "xyz"[k], s,
           u[0], u[1], u[2]);
    check_rel(umax, V, 1e-12);
    if (check_true(initial_acceleration(mech, &arch, &p, u, NULL, 4e-4, acc))) {
      double dev[3];
      pom_v3_axpy(dev, acc, -s, e);
      printf("  simulated initial acceleration %.6g rad/s^2 (deviation %.2e of s_max)\n",
             pom_v3_dot(acc, e), pom_v3_norm(dev) / s);
      /* the Richardson remainder O((T/tau)^2) ~ 1e-4 at T = 0.4 ms, tau ~ 10 ms */
      check_true(pom_v3_norm(dev) / s < 5e-3);
    }

    /* steady rate: at w = s_r e the voltages u(s_r) hold w_dot = 0, one at V */
    int bind = -1;
    double sr = pom_cap_rate_along(&rm, e, &bind), w[3];
    pom_v3_scale(w, sr, e);
    pom_dyn_rigid_terms tw;
    if (!check_true(pom_dyn_rigid_terms_at(m, d, I3, w, &tw, &err) == POM_OK)) continue;
    double f[3], qd[3], uu[3], a_off[3], Fo[3], rhs[3];
    for (int i = 0; i < 3; ++i)
      f[i] = -(tw.gravity[i] + tw.velocity[i]);
    pom_m3_apply(F, JiT, f);
    pom_m3_apply(qd, tw.J, w);
    umax = 0;
    for (int a = 0; a < 3; ++a) {
      double i_a = (F[a] + b * qd[a]) / K;
      uu[a] = Rc * i_a + K * qd[a];
      umax = fmax(umax, fabs(uu[a]));
      Fo[a] = -K * K * qd[a] / Rc - b * qd[a]; /* the efforts with the voltages off */
    }
    printf("steady rate along %c: %.6g rad/s (actuator %d binds), voltages %.4g %.4g %.4g V\n",
           "xyz"[k], sr, bind + 1, uu[0], uu[1], uu[2]);
    check_rel(umax, V, 1e-9);
    /* the scale of w_dot: the deceleration with the voltages removed */
    double JF[3];
    pom_m3_tapply(JF, tw.J, Fo);
    for (int i = 0; i < 3; ++i)
      rhs[i] = tw.gravity[i] + tw.velocity[i] + JF[i];
    pom_m3_inverse(Ji, tw.M, 0.0);
    pom_m3_apply(a_off, Ji, rhs);
    const double scale = pom_v3_norm(a_off);
    if (check_true(initial_acceleration(mech, &arch, &p, uu, w, 2e-4, acc))) {
      printf("  simulated |w_dot| = %.3g rad/s^2 against %.3g with the voltages off\n",
             pom_v3_norm(acc), scale);
      check_true(pom_v3_norm(acc) < 5e-3 * scale);
    }
    /* 2 % less voltage does not hold the rate: the test can tell */
    double u98[3];
    pom_v3_scale(u98, 0.98, uu);
    if (check_true(initial_acceleration(mech, &arch, &p, u98, w, 2e-4, acc)))
      check_true(pom_v3_norm(acc) > 5e-3 * scale);
  }
done:
  pom_dyn_data_destroy(d);
  pom_dyn_model_destroy(m);
  free(mech);
}

/* ---- 3. the driver on the shipped 3-RRR: figures consistent ------------------------- */
static void test_run(void) {
  printf("run: 3rrr, 3 x 3 x 3 poses, one slew direction\n");
  pom_kin_arch arch;
  pom_mechanism *mech = calloc(1, sizeof *mech);
  pom_dyn_params p;
  if (!check_true(mech && load_shipped("3rrr.cfg", &arch, mech, &p))) {
    free(mech);
    return;
  }
  pom_kin_ws_opts ws;
  pom_kin_ws_defaults(&ws);
  ws.resolution = 2.0 * POM_DEG;
  pom_cap_opts o;
  pom_cap_defaults(&o);
  o.grid_points = 3;
  o.slew_directions = 1;
  o.n_amplitudes = 1;
  o.amplitude[0] = 10.0 * POM_DEG;
  pom_cap_result r;
  pom_error err;
  pom_error_clear(&err);
  if (check_true(pom_cap_run(&arch, &ws, mech, &p, &o, &r, &err) == POM_OK)) {
    check_true(r.n_poses == 27 && r.home == 13);
    const pom_cap_pose *h = &r.pose[r.home];
    for (int k = 0; k < 3; ++k) {
      check_true(h->acc_inscribed <= h->acc_axis[k] * (1 + 1e-12));
      check_true(h->rate_inscribed <= h->rate_axis[k] * (1 + 1e-9));
      check_true(h->rate_inscribed <= h->rate_emf_inscribed);
    }
    check_true(r.pose[r.worst_acc].acc_inscribed <= h->acc_inscribed);
    check_true(r.slew[0].n == 2 && r.slew[0].status[0] == POM_OK);
    /* a 10 deg slew's peak rate stays far below the steady-rate limit */
    check_true(r.slew[0].peak_rate[0] > 0 && r.slew[0].peak_rate[0] < h->rate_inscribed);
  } else {
    printf("  %s\n", err.message);
  }
  pom_cap_result_free(&r);
  free(mech);
}

int main(void) {
  test_polytope();
  test_bang_bang();
  test_run();
  return check_summary("test_capability");
}
