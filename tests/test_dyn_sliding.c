/* test_dyn_sliding.c - the energy of a chattering sliding mode against an
 * independent integration (docs/dynamics.md section 14, "A chattering
 * sliding mode: which energy"; issue 30 item 8).
 *
 * The 3-RRR of configs/3rrr.cfg with K_P, K_I and tau_D all x 1e3 (K_S K_P =
 * 1.5e8 V/rad, tau_D = 3 s) steps to (3, -2, 2.5) deg. The derivative term
 * dominates: after a start-up the loop slides on s = e + K_I z - tau_D q' = 0
 * (q' ~ e / tau_D) with the holding current against gravity. The start-up
 * (~2 ms) is a relay oscillation: s swings by ~1e-2 rad against a linear band
 * of 1.6e-7 rad, the drive switches between +-24 V, the coil current swings by
 * ~0.2 A (s'' ~ -tau_D K_t i' / J, L i' = +-24 V - R_c i: a relay on a double
 * integrator damped by R_c / L), faster and smaller until it reaches the band,
 * where the linear loop has the pole pair L M_q s^2 + R_c M_q s +
 * K_S K_P tau_D K_t = 0 at ~5.9e7 rad/s. The coil's R_c i^2 over this
 * oscillation is the energy in question: the rigid path spends 7.90e-4 J, the
 * parasitic one (k_p = 1e6) 6.67e-4 J.
 *
 * The reference: the rigid model's equations (mass matrix, gravity and
 * velocity terms and Jacobian from pom_dyn_exact_terms, re-evaluated every
 * 0.5 us at the current pose; coil, PID, saturation and energy written here)
 * integrated by classical RK4 with a fixed step that resolves every switching
 * and the fast pair (|lambda| h = 0.12) over the start-up window [0, T1].
 * Halving or doubling its step moves its window energy by < 2e-4 (relative).
 *
 * Checked: (1) the rigid path's energy over [0, T1] equals the reference's
 * within 0.5 % at rtol 1e-7 (measured 0.05 %) and 2 % at the shipped 1e-6
 * (0.65 %); (2) the parasitic path spends 0.23 x as much over the window at
 * the paper's k_p = 1e6 N/m (its stiffest joint mode, ~2e5 rad/s, lies inside the
 * relay oscillation's band: another system, not an integration error), more
 * as k_p grows (0.28, 0.56 at 1e8, 1e9) and still less than the rigid path;
 * (3) after T1 both paths spend the same energy within 0.5 % (measured
 * 0.02 %) and end at the same q within 1e-7 rad: the window holds the whole
 * difference. */
#include "check.h"
#include "dyn_internal.h"
#include "dyn_test_util.h"
#include "pom_math.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define T1 3e-3 /* s: the start-up window */

static const double target_deg[3] = {3.0, -2.0, 2.5};

typedef struct {
  pom_kin_arch arch;
  pom_mechanism mech;
  pom_dyn_params p; /* the 3-RRR with the gains x 1e3 */
  double target[3];
} setup_t;

static int setup(setup_t *s) {
  if (!load_shipped("3rrr.cfg", &s->arch, &s->mech, &s->p)) return 0;
  s->p.controller.kp *= 1e3;
  s->p.controller.ki *= 1e3;
  s->p.controller.kd *= 1e3;
  for (int a = 0; a < 3; ++a)
    s->target[a] = target_deg[a] * POM_DEG;
  return 1;
}

/* ---- the reference -------------------------------------------------------- */
typedef struct {
  double M[9], Minv[9], f[3], J[9], q[3]; /* the mechanics at the last evaluation */
  double G, kd, ki, lim, R, L, Kt, b;     /* coil and PID */
  const double *target;
} ref_model;

/* state: omega[3], theta[3] (rotation vector since the last evaluation, fixed
 * frame), dq[3] (actuator coordinates since it), i[3], z[3], E[3] (int u i) */
#define NX 18

static double ref_u_raw(const ref_model *r, const double *x, int a, double *qd_out) {
  double qd = pom_v3_dot(r->J + 3 * a, x);
  double q = r->q[a] + x[6 + a];
  if (qd_out) *qd_out = qd;
  return r->G * (r->target[a] - q + r->ki * x[12 + a] - r->kd * qd);
}

static void ref_rhs(const ref_model *r, const double *x, double *f) {
  double F[3], tau[3];
  for (int a = 0; a < 3; ++a) {
    double qd;
    double ur = ref_u_raw(r, x, a, &qd);
    double u = fmax(-r->lim, fmin(r->lim, ur));
    double i = x[9 + a];
    F[a] = r->Kt * i - r->b * qd;
    f[6 + a] = qd;
    f[9 + a] = (u - r->R * i - r->Kt * qd) / r->L;
    f[12 + a] = r->target[a] - (r->q[a] + x[6 + a]);
    f[15 + a] = u * i;
  }
  pom_m3_tapply(tau, r->J, F); /* J^T F */
  for (int k = 0; k < 3; ++k)
    tau[k] += r->f[k];
  pom_m3_apply(f, r->Minv, tau);
  for (int k = 0; k < 3; ++k)
    f[3 + k] = x[k];
}

typedef struct {
  double energy;      /* sum int u i over [0, T] */
  double energy_a[3]; /* per actuator */
  double sat[3];      /* time with |u_raw| >= limit */
  double q[3];        /* at T */
  double omega_fast;  /* rad/s, the fastest pole pair of the linear band at home */
  long steps;
} ref_result;

/* RK4 with step h over [0, T]; the mechanics re-evaluated every `every`
 * steps at the current rotation and angular velocity. Returns 0 on success. */
static int reference(ref_result *out, const setup_t *s, double T, double h, int every) {
  run_t rr;
  memset(out, 0, sizeof *out);
  pom_dyn_params p = s->p;
  p.joints.model = POM_JOINTS_RIGID;
  pom_error err;
  pom_error_clear(&err);
  memset(&rr, 0, sizeof rr);
  if (pom_dyn_model_create(&rr.m, &s->mech, &s->arch, &p, &err) != POM_OK ||
      pom_dyn_data_create(&rr.d, rr.m, &err) != POM_OK) {
    printf("  reference model: %s\n", err.message);
    run_free(&rr);
    return 1;
  }
  const pom_dyn_actuator *ap = &p.actuator;
  ref_model r = {.G = ap->sensor_gain * p.controller.kp,
                 .kd = p.controller.kd,
                 .ki = p.controller.ki,
                 .lim = ap->voltage_limit,
                 .R = ap->resistance,
                 .L = ap->inductance,
                 .Kt = ap->force_constant,
                 .b = p.scene.bearing_friction ? ap->bearing_friction : 0.0,
                 .target = s->target};
  double Rot[9], x[NX] = {0};
  pom_m3_identity(Rot);
  long n = lround(T / h);
  int fail = 0;
  for (long k = 0; k < n && !fail; ++k) {
    if (k % every == 0) { /* fold theta into Rot, re-evaluate the mechanics */
      double th = pom_v3_norm(x + 3), dR[9], Rn[9];
      if (th > 0) {
        double axis[3];
        pom_v3_scale(axis, 1.0 / th, x + 3);
        pom_m3_axis_angle(dR, axis, th);
        pom_m3_mul(Rn, dR, Rot);
        memcpy(Rot, Rn, sizeof Rn);
      }
      if (pom_dyn_exact_terms(rr.m, rr.d, Rot, x, r.M, r.f, r.q, r.J) != 0 ||
          pom_m3_inverse(r.Minv, r.M, 0.0) != POM_OK) {
        fail = 1;
        break;
      }
      if (k == 0) {
        /* the fast pair at home: eigenvalues mu of M_q = J^-T M J^-1 */
        double Ji[9], T1m[9], Mq[9], ev[3], V[9];
        pom_m3_inverse(Ji, r.J, 0.0);
        pom_m3_mul(T1m, r.M, Ji);
        pom_m3_tmul(Mq, Ji, T1m);
        pom_m3_sym_eig(ev, V, Mq);
        double mu = fmin(ev[0], fmin(ev[1], ev[2]));
        out->omega_fast = sqrt(r.G * r.kd * r.Kt / (r.L * mu));
      }
      for (int a = 0; a < 3; ++a)
        x[3 + a] = x[6 + a] = 0.0;
    }
    double k1[NX], k2[NX], k3[NX], k4[NX], xt[NX];
    for (int a = 0; a < 3; ++a)
      if (fabs(ref_u_raw(&r, x, a, NULL)) >= r.lim) out->sat[a] += h;
    ref_rhs(&r, x, k1);
    for (int j = 0; j < NX; ++j)
      xt[j] = x[j] + 0.5 * h * k1[j];
    ref_rhs(&r, xt, k2);
    for (int j = 0; j < NX; ++j)
      xt[j] = x[j] + 0.5 * h * k2[j];
    ref_rhs(&r, xt, k3);
    for (int j = 0; j < NX; ++j)
      xt[j] = x[j] + h * k3[j];
    ref_rhs(&r, xt, k4);
    for (int j = 0; j < NX; ++j)
      x[j] += h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
    out->steps++;
  }
  for (int a = 0; a < 3; ++a) {
    out->energy_a[a] = x[15 + a];
    out->energy += x[15 + a];
    out->q[a] = r.q[a] + x[6 + a];
  }
  run_free(&rr);
  return fail;
}

/* ---- the engine's paths ----------------------------------------------------- */
/* One maneuver of the setup over [0, horizon]: rigid, or parasitic at k_p
 * (linear and angular); coil 0 drops the coil's inductance. Returns 1 when it
 * ended POM_OK. */
static int path(pom_dyn_metrics *mt, const setup_t *s, int rigid, double kp, double rtol,
                double horizon, int coil) {
  pom_dyn_params p = s->p;
  p.joints.model = rigid ? POM_JOINTS_RIGID : POM_JOINTS_PARASITIC;
  if (!rigid) p.joints.stiffness = p.joints.angular_stiffness = kp;
  p.scene.coil_inductance = coil;
  p.solver.rtol = rtol;
  p.solver.max_steps = 2000000;
  p.maneuver.horizon = horizon;
  run_t r;
  pom_status st = run_arch(&r, &s->mech, &s->arch, &p, s->target, NULL);
  if (st == POM_OK) *mt = r.mt;
  run_free(&r);
  return st == POM_OK;
}

static void row(const char *what, const pom_dyn_metrics *w, const pom_dyn_metrics *full) {
  printf("  %-28s window %.4e J, after it %.4e J, total %.4e J, saturated %.3g/%.3g/%.3g ms, "
         "%ld steps\n",
         what, w->energy_total, full ? full->energy_total - w->energy_total : NAN,
         full ? full->energy_total : NAN, w->saturation_time[0] * 1e3, w->saturation_time[1] * 1e3,
         w->saturation_time[2] * 1e3, w->steps);
}

/* --study: the reference at three steps and the paths beside it (~45 s) */
static void study(const setup_t *s) {
  const double hs[] = {4e-9, 2e-9, 1e-9};
  for (int k = 0; k < 3; ++k) {
    ref_result ref;
    if (reference(&ref, s, T1, hs[k], (int)lround(5e-7 / hs[k])) == 0)
      printf("  reference h = %g s (|lambda| h = %.3f): window %.5e J, saturated %.3g/%.3g/%.3g "
             "ms\n",
             hs[k], ref.omega_fast * hs[k], ref.energy, ref.sat[0] * 1e3, ref.sat[1] * 1e3,
             ref.sat[2] * 1e3);
  }
  pom_dyn_metrics w, f;
  const double rtols[] = {1e-6, 1e-7};
  for (int k = 0; k < 2; ++k) {
    char what[64];
    snprintf(what, sizeof what, "rigid, rtol %g", rtols[k]);
    if (path(&w, s, 1, 0, rtols[k], T1, 1))
      row(what, &w, path(&f, s, 1, 0, rtols[k], 0.1, 1) ? &f : NULL);
  }
  const double kps[] = {1e6, 1e7, 1e8, 1e9, 3e9, 1e10};
  for (int k = 0; k < 6; ++k) {
    char what[64];
    snprintf(what, sizeof what, "parasitic k_p %g, rtol 1e-8", kps[k]);
    if (path(&w, s, 0, kps[k], 1e-8, T1, 1))
      row(what, &w, path(&f, s, 0, kps[k], 1e-8, 0.1, 1) ? &f : NULL);
  }
  if (path(&w, s, 1, 0, 1e-8, T1, 0))
    row("rigid, quasi-static coil", &w, path(&f, s, 1, 0, 1e-8, 0.1, 0) ? &f : NULL);
  if (path(&w, s, 0, 1e6, 1e-8, T1, 0))
    row("parasitic 1e6, quasi-static", &w, path(&f, s, 0, 1e6, 1e-8, 0.1, 0) ? &f : NULL);
}

int main(int argc, char **argv) {
  setup_t s;
  if (!check_true(setup(&s))) return check_summary("test_dyn_sliding");
  if (argc > 1 && strcmp(argv[1], "--study") == 0) {
    study(&s);
    return 0;
  }
  /* the reference over the window: RK4, |lambda| h ~ 0.12, the mechanics
   * every 0.5 us (h = 4e-9, 2e-9, 1e-9: 1.59668e-4, 1.59697e-4, 1.59712e-4 J) */
  ref_result ref;
  if (!check_true(reference(&ref, &s, T1, 2e-9, 250) == 0))
    return check_summary("test_dyn_sliding");
  check_true(ref.omega_fast * 2e-9 < 0.2);
  printf("reference: fast pair %.3g rad/s, window energy %.5e J, saturated %.3g ms\n",
         ref.omega_fast, ref.energy, ref.sat[0] * 1e3);

  /* (1) the rigid path: within 0.5 % at rtol 1e-7 (measured 0.05 %), 2 % at
   * the shipped 1e-6 (0.8 %); its saturation time is not resolved (the
   * 9 MHz chatter), its energy is */
  pom_dyn_metrics w7, w6, full_rigid, w_p6, full_p6, w_p8, w_p9;
  if (check_true(path(&w7, &s, 1, 0, 1e-7, T1, 1))) check_rel(w7.energy_total, ref.energy, 5e-3);
  if (check_true(path(&w6, &s, 1, 0, 1e-6, T1, 1))) check_rel(w6.energy_total, ref.energy, 2e-2);

  /* (2) the parasitic path over the window: 0.23 x the rigid value at the
   * paper's k_p = 1e6 (another loop, not an integration error), rising with
   * k_p (0.28, 0.56 at 1e8, 1e9) and still below it */
  int ok6 = check_true(path(&w_p6, &s, 0, 1e6, 1e-8, T1, 1));
  int ok8 = check_true(path(&w_p8, &s, 0, 1e8, 1e-8, T1, 1));
  int ok9 = check_true(path(&w_p9, &s, 0, 1e9, 1e-8, T1, 1));
  if (ok6 && ok8 && ok9) {
    printf("parasitic window energy / reference: %.3f %.3f %.3f at k_p 1e6, 1e8, 1e9\n",
           w_p6.energy_total / ref.energy, w_p8.energy_total / ref.energy,
           w_p9.energy_total / ref.energy);
    check_true(w_p6.energy_total < 0.5 * ref.energy);
    check_true(w_p6.energy_total < w_p8.energy_total && w_p8.energy_total < w_p9.energy_total);
    check_true(w_p9.energy_total < 0.9 * ref.energy);
  }

  /* (3) after the window both paths slide with the same holding current:
   * the energy of (T1, 100 ms] agrees within 0.5 % (measured 0.02 %), so the
   * window holds the whole difference of the totals */
  if (check_true(path(&full_rigid, &s, 1, 0, 1e-7, 0.1, 1)) &&
      check_true(path(&full_p6, &s, 0, 1e6, 1e-8, 0.1, 1)) && ok6) {
    double after_rigid = full_rigid.energy_total - w7.energy_total;
    double after_p6 = full_p6.energy_total - w_p6.energy_total;
    printf("totals: rigid %.4e J, parasitic 1e6 %.4e J; after the window %.5e, %.5e J\n",
           full_rigid.energy_total, full_p6.energy_total, after_rigid, after_p6);
    check_rel(after_p6, after_rigid, 5e-3);
    for (int a = 0; a < 3; ++a)
      check_abs(full_p6.final_q[a], full_rigid.final_q[a], 1e-7);
  }
  return check_summary("test_dyn_sliding");
}
