/* test_dynamics_exact.c - the exact-constraint (rigid-joint, minimal
 * coordinate) dynamics path (docs/dynamics-exact.md section 7): mass matrix
 * against the kinetic energy of finite-differenced body motions,
 * velocity-product terms against the finite-difference rate of the mass
 * matrix, energy conservation and the audit, Euler/quaternion agreement,
 * convergence of the parasitic path to it as k_p grows, and the error paths. */
#include "check.h"
#include "dyn_test_util.h"
#include "dyn_internal.h"
#include "pom_kinematics.h"
#include "pom_math.h"
#include "pom_rng.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- set-up ---------------------------------------------------------------- */
typedef struct {
  pom_kin_arch arch;
  pom_kin_inertia in;
  pom_mechanism mech;
  pom_dyn_params par;
  double unit; /* actuator coordinate per metre of the linear designs: 1 (prismatic) or
                  1 / 0.015 rad per m (revolute: the 15 mm/rad lever of the isotropic
                  linear designs, so a 3 mm step becomes 0.2 rad) */
} setup_t;

static int setup_load(setup_t *s, const char *rel) {
  char path[512];
  snprintf(path, sizeof path, "%s/%s", POM_SOURCE_DIR, rel);
  pom_cfg *cfg = NULL;
  pom_error err;
  pom_error_clear(&err);
  memset(s, 0, sizeof *s);
  pom_dyn_params_defaults(&s->par);
  int ok = pom_cfg_load(&cfg, path, &err) == POM_OK &&
           pom_kin_arch_load(&s->arch, cfg, &err) == POM_OK &&
           pom_kin_inertia_load(&s->in, &s->arch, cfg, &err) == POM_OK &&
           pom_kin_mechanism_from(&s->mech, &s->arch, &s->in, &err) == POM_OK &&
           pom_dyn_params_load(&s->par, cfg, &err) == POM_OK;
  if (!ok) printf("loading %s: %s\n", rel, err.message);
  s->unit = pom_act_kind_desc(s->mech.actuator[0].kind)->angular ? 1.0 / 0.015 : 1.0;
  pom_cfg_destroy(cfg);
  return ok;
}

static pom_status run_build(run_t *r, const setup_t *s, const pom_dyn_params *p) {
  memset(r, 0, sizeof *r);
  pom_error_clear(&r->err);
  r->st = pom_dyn_model_create(&r->m, &s->mech, &s->arch, p, &r->err);
  if (r->st == POM_OK) r->st = pom_dyn_data_create(&r->d, r->m, &r->err);
  if (r->st == POM_OK) r->st = pom_dyn_trace_create(&r->tr, r->m, &r->err);
  if (r->st != POM_OK) printf("  build: %s\n", r->err.message);
  return r->st;
}

static pom_status run_setup(run_t *r, const setup_t *s, const pom_dyn_params *p,
                            const double target[3], const pom_dyn_initial *init) {
  if (run_build(r, s, p) != POM_OK) return r->st;
  r->st = pom_dyn_simulate_ex(r->m, r->d, target, init, &r->mt, r->tr, &r->err);
  if (r->st != POM_OK) printf("  run: %s\n", r->err.message);
  return r->st;
}

static void rotate_by(double out[9], const double w[3], double t, const double R[9]) {
  double n = pom_v3_norm(w), u[3], E[9];
  pom_v3_scale(u, 1.0 / n, w);
  pom_m3_axis_angle(E, u, n * t);
  pom_m3_mul(out, E, R);
}

/* State of the exact model with platform rotation R and angular velocity w. */
static void exact_state(const pom_dyn_model *m, double *y, const double R[9], const double w[3]) {
  int ori = 0, n_ori = 3, omega = 3;
  memset(y, 0, (size_t)m->n_states * sizeof(double));
  check_true(pom_dyn_exact_layout(m, &ori, &n_ori, &omega) == 1);
  if (n_ori == 4)
    pom_quat_from_matrix(y + ori, R);
  else
    (void)pom_euler_zyx_from_matrix(y + ori, R);
  memcpy(y + omega, w, 3 * sizeof(double));
}

/* Kinetic energy of the mechanism moving as R(t) = exp(t [w]) R, from central
 * differences of every body's CM position and rotation (body poses from
 * pom_kin_body_twists, tested on their own in test_kinematics). Idle-spin
 * bodies: the rotational energy of their spin-free motion, 1/2 I_t |w_perp|^2
 * with I_t the mean transverse moment (docs/dynamics-exact.md section 3). */
static double fd_kinetic(const setup_t *s, const double R[9], const double w[3]) {
  const double h = 1e-6 / pom_v3_norm(w);
  double Rp[9], Rm[9];
  pom_kin_twists tp, tm;
  rotate_by(Rp, w, h, R);
  rotate_by(Rm, w, -h, R);
  if (pom_kin_body_twists(&s->arch, Rp, NULL, &tp, NULL) != POM_OK ||
      pom_kin_body_twists(&s->arch, Rm, NULL, &tm, NULL) != POM_OK)
    return NAN;
  double E = 0.0;
  for (int b = 1; b < s->mech.n_bodies; ++b) {
    const pom_mech_body *mb = &s->mech.body[b];
    double xp[3], xm[3], d[3], r[3], v[3], D[9], rv[3], wb[3], Ib[9], RI[9], Iw[3];
    pom_v3_sub(d, mb->cm, tp.body[b].ref_home);
    pom_m3_apply(r, tp.body[b].R, d);
    pom_v3_add(xp, tp.body[b].ref, r);
    pom_m3_apply(r, tm.body[b].R, d);
    pom_v3_add(xm, tm.body[b].ref, r);
    pom_v3_sub(v, xp, xm);
    pom_v3_scale(v, 0.5 / h, v);
    pom_m3_mult(D, tp.body[b].R, tm.body[b].R);
    pom_m3_rotvec(rv, D);
    pom_v3_scale(wb, 0.5 / h, rv);
    E += 0.5 * mb->mass * pom_v3_dot(v, v);
    if (tp.body[b].spin_free) {
      const double *ax = tp.body[b].spin_axis;
      pom_v3_axpy(wb, wb, -pom_v3_dot(wb, ax), ax);
      double It = s->arch.type == pom_kin_arch_type_find("3PSS")
                      ? 0.5 * (s->in.body[1].moments[0] + s->in.body[1].moments[1])
                      : NAN;
      E += 0.5 * It * pom_v3_dot(wb, wb);
    } else {
      double Rb[9];
      pom_m3_copy(Rb, tp.body[b].R); /* the midpoint rotation to O(h^2) */
      double Rm0[9];
      pom_m3_copy(Rm0, tm.body[b].R);
      for (int k = 0; k < 9; ++k)
        Rb[k] = 0.5 * (Rb[k] + Rm0[k]);
      pom_m3_mul(RI, Rb, mb->inertia);
      pom_m3_mult(Ib, RI, Rb);
      pom_m3_apply(Iw, Ib, wb);
      E += 0.5 * pom_v3_dot(wb, Iw);
    }
  }
  return E;
}

/* ---- 1. mass matrix -------------------------------------------------------- */
/* M symmetric positive definite; M = the Hessian of the kinetic energy in
 * omega, its entries recovered from KE(e_i) and KE(e_i + e_j) of the
 * finite-differenced body motions. Tolerance 1e-7 |M|: central differences
 * with |w| h = 1e-6 rad (truncation ~1e-12, rounding ~1e-10 relative) and the
 * O(h^2) midpoint rotation. */
static void test_mass_matrix(const setup_t *s) {
  run_t r;
  pom_dyn_params p = s->par;
  p.joints.model = POM_JOINTS_RIGID;
  if (run_build(&r, s, &p) != POM_OK) {
    check_true(0);
    return;
  }
  double *y = calloc((size_t)r.m->n_states, sizeof *y);
  double worst = 0.0, worst_sym = 0.0, min_eig = INFINITY;
  const double e[4][3] = {{0, 0, 0}, {0.07, -0.05, 0.02}, {-0.11, 0.04, 0.09}, {0.02, 0.13, -0.06}};
  for (int c = 0; c < 4; ++c) {
    double R[9], w0[3] = {0, 0, 0}, M[9];
    pom_euler_zyx_to_matrix(R, e[c]);
    exact_state(r.m, y, R, w0);
    const double *Mp = pom_dyn_exact_mass_matrix(r.m, r.d, y);
    if (!check_true(Mp != NULL)) break;
    memcpy(M, Mp, sizeof M);
    double nrm = 0.0;
    for (int k = 0; k < 9; ++k)
      nrm = fmax(nrm, fabs(M[k]));
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        worst_sym = fmax(worst_sym, fabs(M[3 * i + j] - M[3 * j + i]) / nrm);
    double ev[3], V[9];
    pom_m3_sym_eig(ev, V, M);
    min_eig = fmin(min_eig, ev[2] / ev[0]);
    double Kii[3];
    for (int i = 0; i < 3; ++i) {
      double w[3] = {0, 0, 0};
      w[i] = 1.0;
      Kii[i] = fd_kinetic(s, R, w);
      worst = fmax(worst, fabs(2.0 * Kii[i] - M[4 * i]) / nrm);
    }
    for (int i = 0; i < 3; ++i)
      for (int j = i + 1; j < 3; ++j) {
        double w[3] = {0, 0, 0};
        w[i] = w[j] = 1.0;
        double Mij = fd_kinetic(s, R, w) - Kii[i] - Kii[j];
        worst = fmax(worst, fabs(Mij - M[3 * i + j]) / nrm);
      }
  }
  check_abs(worst_sym, 0.0, 1e-14);
  check_true(min_eig > 0.0);
  check_abs(worst, 0.0, 1e-7);
  printf("%s: M symmetric to %.2g, smallest/largest eigenvalue %.3g, M vs kinetic energy %.2g\n",
         s->arch.name, worst_sym, min_eig, worst);
  free(y);
  run_free(&r);
}

/* ---- 2. velocity-product terms --------------------------------------------- */
/* With no gravity, no current and no friction, the generalized force is the
 * velocity-product term f_v = M omega_dot alone, and the power balance of the
 * kinetic energy 1/2 w^T M(R) w demands w . f_v = -1/2 w^T M_dot w, M_dot by a
 * central difference along R(t) = exp(t [w]) R (tolerance: 1e-6 of the
 * largest term, ~100x the difference error at |w| h = 1e-5 rad). The
 * components of f_v across w are checked against a full Lagrangian reference
 * in test 3 (energy conservation) and test 5 (convergence of the parasitic
 * path). */
static void test_velocity_products(const setup_t *s) {
  run_t r;
  pom_dyn_params p = s->par;
  p.joints.model = POM_JOINTS_RIGID;
  p.scene.gravity = 0;
  p.scene.bearing_friction = 0;
  if (run_build(&r, s, &p) != POM_OK) {
    check_true(0);
    return;
  }
  const int n = r.m->n_states;
  double *y = calloc((size_t)n, sizeof *y), *yd = calloc((size_t)n, sizeof *yd);
  double worst = 0.0;
  const double e[3][3] = {{0.07, -0.05, 0.02}, {-0.11, 0.04, 0.09}, {0.02, 0.13, -0.06}};
  const double wv[3][3] = {{3.1, -7.2, 2.4}, {-5.5, 1.3, 8.8}, {0.9, 4.4, -6.1}};
  for (int c = 0; c < 3; ++c) {
    double R[9], M[9], Mp[9], Mm[9], Rp[9], Rm[9];
    const double *w = wv[c];
    pom_euler_zyx_to_matrix(R, e[c]);
    exact_state(r.m, y, R, w);
    r.d->target[0] = r.d->target[1] = r.d->target[2] = 0.0;
    check_true(pom_dyn_eval(r.m, r.d, y, yd) == 0);
    memcpy(M, pom_dyn_exact_mass_matrix(r.m, r.d, y), sizeof M); /* M of the same state */
    int ori = 0, n_ori = 3, omega = 3;
    (void)pom_dyn_exact_layout(r.m, &ori, &n_ori, &omega);
    double fv[3];
    pom_m3_apply(fv, M, yd + omega);
    const double h = 1e-5 / pom_v3_norm(w);
    rotate_by(Rp, w, h, R);
    rotate_by(Rm, w, -h, R);
    exact_state(r.m, y, Rp, w);
    memcpy(Mp, pom_dyn_exact_mass_matrix(r.m, r.d, y), sizeof Mp);
    exact_state(r.m, y, Rm, w);
    memcpy(Mm, pom_dyn_exact_mass_matrix(r.m, r.d, y), sizeof Mm);
    double Md[9], Mdw[3];
    for (int k = 0; k < 9; ++k)
      Md[k] = (Mp[k] - Mm[k]) / (2 * h);
    pom_m3_apply(Mdw, Md, w);
    double lhs = pom_v3_dot(w, fv), rhs = -0.5 * pom_v3_dot(w, Mdw);
    worst = fmax(worst, fabs(lhs - rhs) / fmax(fabs(lhs), fabs(rhs)));
  }
  check_abs(worst, 0.0, 1e-6);
  printf("%s: power of the velocity-product terms vs -1/2 w^T M_dot w: %.2g\n", s->arch.name,
         worst);
  free(y);
  free(yd);
  run_free(&r);
}

/* ---- 3. energy conservation ------------------------------------------------ */
/* Sources and dissipation off (K_P = 0 so u = 0, K_m at its smallest 1e-6 N/A
 * so the coil exchanges ~1e-13 W, no bearing friction), gravity on: the
 * mechanism tumbles from a spin of the platform and its kinetic plus
 * gravitational energy must stay constant. Tolerance 1e-7 relative at rtol
 * 1e-10, atol_scale 1e-9 (measured 1e-8..1e-9, falling with the tolerances:
 * 1.3e-8 at rtol 1e-10, 1.5e-9 at 1e-12; with the shipped atol_scale 1e-6
 * the drift stays ~5e-7 whatever rtol, set by the absolute tolerances). */
static void test_energy(const setup_t *s, pom_orient_kind orient, double rtol) {
  pom_dyn_params p = s->par;
  p.joints.model = POM_JOINTS_RIGID;
  p.scene.orientation = orient;
  p.scene.bearing_friction = 0;
  p.controller.kp = 0.0;
  p.actuator.force_constant = 1e-6;
  p.solver.rtol = rtol;
  p.solver.atol_scale = 1e-9;
  p.maneuver.horizon = 0.05;
  pom_dyn_initial init;
  memset(&init, 0, sizeof init);
  pom_v3_set(init.omega[s->mech.platform], 4.1, -2.7, 6.3);
  double target[3] = {0, 0, 0};
  run_t r;
  if (run_setup(&r, s, &p, target, &init) != POM_OK) {
    check_true(0);
    run_free(&r);
    return;
  }
  double rel = fabs(r.mt.energy_stored_change) / r.mt.energy_balance_scale;
  check_abs(rel, 0.0, 1e-7);
  check_abs(r.mt.energy_balance_error, 0.0, 1e-7);
  check_abs(r.mt.max_deflection, 0.0, 0.0);
  /* the platform really moved: q changed by more than 10 um */
  check_true(fabs(r.mt.final_q[0]) + fabs(r.mt.final_q[1]) + fabs(r.mt.final_q[2]) > 1e-5);
  printf("%s %s: free motion, stored-energy change %.2g of %.3g J, %ld steps, rtol %g\n",
         s->arch.name, pom_dyn_orient_name(orient), rel, r.mt.energy_balance_scale, r.mt.steps,
         rtol);
  run_free(&r);
}

/* ---- 4. shipped maneuver: audit, Euler/quaternion, IK consistency ------------ */
/* The +-3 mm maneuver of the shipped config on the rigid path at rtol 1e-8:
 * the energy audit closes (1e-5 ~ steps x rtol, the accumulated local error
 * of ~1300 steps at rtol 1e-8; measured 2e-7..2e-6 depending on the step
 * sequence), Euler and quaternion agree (q to 1e-8 m, settling to
 * 1e-5 s, energies to 1e-5 relative: both integrate the same equations, so
 * they differ by the integration error), q equals IK of the platform
 * orientation exactly. */
static void test_maneuver(const setup_t *s) {
  double target[3] = {3e-3 * s->unit, -3e-3 * s->unit, 3e-3 * s->unit};
  pom_dyn_params p = s->par;
  p.joints.model = POM_JOINTS_RIGID;
  p.solver.rtol = 1e-8;
  p.solver.atol_scale = 1e-4;
  run_t re, rq;
  p.scene.orientation = POM_ORIENT_EULER_ZYX;
  pom_status st1 = run_setup(&re, s, &p, target, NULL);
  p.scene.orientation = POM_ORIENT_QUATERNION;
  pom_status st2 = run_setup(&rq, s, &p, target, NULL);
  if (!check_true(st1 == POM_OK && st2 == POM_OK)) {
    run_free(&re);
    run_free(&rq);
    return;
  }
  check_abs(re.mt.energy_balance_error, 0.0, 1e-5);
  check_abs(rq.mt.energy_balance_error, 0.0, 1e-5);
  double dq = 0.0;
  for (int k = 0; k < re.tr->n && k < rq.tr->n; ++k)
    for (int a = 0; a < 3; ++a)
      dq = fmax(dq, fabs(re.tr->q[3 * k + a] - rq.tr->q[3 * k + a]));
  check_abs(dq, 0.0, 1e-8 * s->unit);
  for (int a = 0; a < 3; ++a) {
    check_true(re.mt.settled[a] && rq.mt.settled[a]);
    check_abs(re.mt.settling_time[a], rq.mt.settling_time[a], 1e-5);
    check_rel(re.mt.energy[a], rq.mt.energy[a], 1e-5);
  }
  double R[9], x[3], q[3];
  check_true(pom_dyn_body_pose(re.m, re.d, s->mech.platform, R, x, NULL) == POM_OK);
  check_true(pom_kin_inverse(&s->arch, R, q, NULL) == POM_OK);
  for (int a = 0; a < 3; ++a)
    check_abs(re.mt.final_q[a], q[a], 1e-15);
  printf("%s rigid: execution %.4f ms, energy %.4f J, audit %.2g; Euler-quaternion |dq| %.2g m; "
         "%ld steps, %d states\n",
         s->arch.name, re.mt.execution_time * 1e3, re.mt.energy_total, re.mt.energy_balance_error,
         dq, re.mt.steps, pom_dyn_model_n_states(re.m));
  run_free(&re);
  run_free(&rq);
}

/* ---- 5. the parasitic path converges to the rigid one as k_p grows ---------- */
/* The shipped +-3 mm maneuver (paper gains, nearly bang-bang) at rtol 1e-8 on
 * the parasitic path with k_p = 1e6, 1e7, 1e8 N/m (linear and angular), the
 * parasitic damping scaled with sqrt(k_p) so the joint modes keep their
 * damping ratio, against the rigid path. The joint compliance perturbs the
 * motion by O(1/k_p): max |q_par(t) - q_rig(t)| must fall by >= 3x per decade
 * and >= 15x over two (measured 6.3x and 9.6x for the 3PSS; 3.8x and 4.9x for
 * the 3SPS, still pre-asymptotic at 1e6 where its energy is 50 % off; free
 * motion shows exactly 10x per decade), and the settling-time and energy errors by >= 10x over
 * the two decades (measured 18-31x; single decades are not monotone because
 * the saturated loop amplifies small differences into a different switching
 * sequence, ~1e-3 in energy, docs/dynamics.md section 7). At k_p = 1e8 the
 * settling times agree to 2e-3 and the energies to 2e-2 relative. 3PSS links
 * made axisymmetric so that both paths model the same physics (the rigid
 * path fixes the idle link spin; docs/dynamics-exact.md section 3). */
static void test_kp_convergence(const setup_t *s0) {
  setup_t s = *s0;
  if (s.arch.type == pom_kin_arch_type_find("3PSS")) {
    double t = 0.5 * (s.in.body[1].moments[0] + s.in.body[1].moments[1]);
    s.in.body[1].moments[0] = s.in.body[1].moments[1] = t;
    pom_error err;
    check_true(pom_kin_mechanism_from(&s.mech, &s.arch, &s.in, &err) == POM_OK);
  }
  double target[3] = {3e-3 * s.unit, -3e-3 * s.unit, 3e-3 * s.unit};
  pom_dyn_params p = s.par;
  p.solver.rtol = 1e-8;
  p.solver.atol_scale = 1e-4;
  run_t rr;
  p.joints.model = POM_JOINTS_RIGID;
  if (run_setup(&rr, &s, &p, target, NULL) != POM_OK) {
    check_true(0);
    run_free(&rr);
    return;
  }
  const double kps[3] = {1e6, 1e7, 1e8};
  double eq[3] = {0}, et[3] = {0}, ee[3] = {0};
  p.joints.model = POM_JOINTS_PARASITIC;
  for (int c = 0; c < 3; ++c) {
    run_t rp;
    p.joints.stiffness = p.joints.angular_stiffness = kps[c];
    p.joints.damping = p.joints.angular_damping = 200.0 * sqrt(kps[c] / 1e6);
    if (run_setup(&rp, &s, &p, target, NULL) != POM_OK) {
      check_true(0);
      run_free(&rp);
      break;
    }
    for (int k = 0; k < rp.tr->n && k < rr.tr->n; ++k)
      for (int a = 0; a < 3; ++a)
        eq[c] = fmax(eq[c], fabs(rp.tr->q[3 * k + a] - rr.tr->q[3 * k + a]));
    for (int a = 0; a < 3; ++a) {
      et[c] = fmax(et[c],
                   fabs(rp.mt.settling_time[a] - rr.mt.settling_time[a]) / rr.mt.settling_time[a]);
      ee[c] = fmax(ee[c], fabs(rp.mt.energy[a] - rr.mt.energy[a]) / fabs(rr.mt.energy[a]));
    }
    printf("%s k_p %.0e: max|dq| %.3g (m or rad), settling %.3g, energy %.3g (relative)\n",
           s.arch.name, kps[c], eq[c], et[c], ee[c]);
    run_free(&rp);
  }
  check_true(eq[0] >= 3 * eq[1] && eq[1] >= 3 * eq[2] && eq[0] >= 15 * eq[2]);
  check_true(et[0] >= 10 * et[2] || et[2] <= 1e-5);
  if (s.unit == 1.0) {
    check_true(ee[0] >= 10 * ee[2]);
  } else {
    /* 3-RRR (rotary coils): measured 2.85e-3, 1.13e-3, 3.4e-4 (8.5x over two
     * decades, monotone): the energy is already within 3e-3 at k_p = 1e6
     * (stiff revolute chains through O) and the switching sequence sets the
     * rest; required: monotone and < 1e-3 at 1e8 */
    check_true(ee[0] > ee[1] && ee[1] > ee[2]);
    check_abs(ee[2], 0.0, 1e-3);
  }
  check_abs(et[2], 0.0, 2e-3);
  check_abs(ee[2], 0.0, 2e-2);
  run_free(&rr);
}

/* ---- 5b. first order in 1/k_p once the loop is slower than the joints ------ */
/* The shipped gains make the loop's velocity feedback K_m K_S K_P tau_D / R_c
 * = 3.2e4 N s/m (3SPS), which sees the parasitic joints' vibration velocity
 * (O(k_p^-1/2), not O(1/k_p)): the shipped-gain convergence above is slow for
 * the 3SPS up to k_p ~ 1e10 (docs/dynamics-exact.md section 9). With K_P
 * 100x lower the same maneuver still saturates (the +-3 mm step), but the
 * loop no longer amplifies the joint vibration, and the compliant model must
 * approach the rigid one as the static deflection does, O(1/k_p), with no
 * floor: any term the rigid path gets wrong or omits at speed (mass matrix,
 * velocity products, gravity, a lever arm) leaves a k_p-independent gap. The
 * test can fail that way: with the shipped 3PSS link (I_x != I_y, its spin
 * neglected by the rigid path, section 3) it measures 4.2e-7, 4.6e-7,
 * 4.6e-7 m and fails both checks. Measured (rtol 1e-9, damping scaled with
 * sqrt(k_p) as in test 5) at k_p = 1e8, 1e9, 1e10: 3PSS (axisymmetric link)
 * 9.4e-8, 9.4e-9, 9.3e-10 m; 3SPS 1.06e-6, 1.00e-7, 9.6e-9 m (10.6x and
 * 10.0x per decade). Required: >= 7x per decade (first order, margin
 * for the switching sequence) and < 3e-8 m at 1e10. */
static void test_kp_first_order(const setup_t *s0) {
  setup_t s = *s0;
  if (s.arch.type == pom_kin_arch_type_find("3PSS")) {
    double t = 0.5 * (s.in.body[1].moments[0] + s.in.body[1].moments[1]);
    s.in.body[1].moments[0] = s.in.body[1].moments[1] = t;
    pom_error err;
    check_true(pom_kin_mechanism_from(&s.mech, &s.arch, &s.in, &err) == POM_OK);
  }
  double target[3] = {3e-3 * s.unit, -3e-3 * s.unit, 3e-3 * s.unit};
  pom_dyn_params p = s.par;
  p.controller.kp = 0.01 * s.par.controller.kp;
  p.solver.rtol = 1e-9;
  p.solver.atol_scale = 1e-6;
  run_t rr;
  p.joints.model = POM_JOINTS_RIGID;
  if (run_setup(&rr, &s, &p, target, NULL) != POM_OK) {
    check_true(0);
    run_free(&rr);
    return;
  }
  /* The 3-RRR's angles are integrated to a floor of ~6e-8 rad at rtol 1e-9
   * (= 9e-10 m at the 15 mm/rad lever, the floor of the linear designs at
   * 1e10; it falls to 1e-8 rad at rtol 1e-11): its decades are taken one
   * lower, 1e7..1e9, where the measured gap is 5.7e-6, 5.7e-7, 5.7e-8 rad. */
  const double kps_lin[3] = {1e8, 1e9, 1e10}, kps_rot[3] = {1e7, 1e8, 1e9};
  const double *kps = s.unit == 1.0 ? kps_lin : kps_rot;
  double eq[3] = {0};
  p.joints.model = POM_JOINTS_PARASITIC;
  for (int c = 0; c < 3; ++c) {
    run_t rp;
    p.joints.stiffness = p.joints.angular_stiffness = kps[c];
    p.joints.damping = p.joints.angular_damping = 200.0 * sqrt(kps[c] / 1e6);
    if (run_setup(&rp, &s, &p, target, NULL) != POM_OK) {
      check_true(0);
      run_free(&rp);
      break;
    }
    for (int k = 0; k < rp.tr->n && k < rr.tr->n; ++k)
      for (int a = 0; a < 3; ++a)
        eq[c] = fmax(eq[c], fabs(rp.tr->q[3 * k + a] - rr.tr->q[3 * k + a]));
    printf("%s K_P/100, k_p %.0e: max|dq| %.3g (m or rad)\n", s.arch.name, kps[c], eq[c]);
    run_free(&rp);
  }
  check_true(eq[0] >= 7 * eq[1] && eq[1] >= 7 * eq[2]);
  check_abs(eq[2], 0.0, 3e-8 * s.unit);
  run_free(&rr);
}

/* ---- 6. error paths -------------------------------------------------------- */
static void test_errors(const setup_t *s3, const setup_t *u3) {
  pom_dyn_model *m = NULL;
  pom_error err;
  pom_error_clear(&err);
  pom_dyn_params p = s3->par;
  p.joints.model = POM_JOINTS_RIGID;
  check_true(pom_dyn_model_create(&m, &s3->mech, NULL, &p, &err) == POM_ERR_ARG && m == NULL);
  check_true(strstr(err.message, "needs the architecture") != NULL);
  check_true(pom_dyn_model_create(&m, &s3->mech, NULL, &p, &err) == POM_ERR_ARG);
  /* the architecture of another mechanism: a joint is violated */
  check_true(pom_dyn_model_create(&m, &s3->mech, &u3->arch, &p, &err) == POM_ERR_ARG);
  check_true(strstr(err.message, "joint") != NULL || strstr(err.message, "bodies") != NULL);
  pom_dyn_params q = p;
  q.scene.limb_inertia = POM_INERTIA_LUMPED;
  check_true(pom_dyn_model_create(&m, &s3->mech, &s3->arch, &q, &err) == POM_ERR_ARG);
  q = p;
  q.solver.rtol = -1.0;
  check_true(pom_dyn_model_create(&m, &s3->mech, &s3->arch, &q, &err) == POM_ERR_ARG);
  /* parasitic parameters without an arch: fine */
  q = s3->par;
  check_true(pom_dyn_model_create(&m, &s3->mech, NULL, &q, &err) == POM_OK);
  pom_dyn_model_destroy(m);
  m = NULL;
  /* config key */
  pom_cfg *cfg = NULL;
  pom_dyn_params c;
  pom_dyn_params_defaults(&c);
  check_true(c.joints.model == POM_JOINTS_PARASITIC);
  check_true(pom_cfg_load_string(&cfg, "joints = { model = \"rigid\"; };", "<t>", &err) == POM_OK);
  check_true(pom_dyn_params_load(&c, cfg, &err) == POM_OK && c.joints.model == POM_JOINTS_RIGID);
  pom_cfg_destroy(cfg);
  cfg = NULL;
  check_true(pom_cfg_load_string(&cfg, "joints = { model = \"stiff\"; };", "<t>", &err) == POM_OK);
  check_true(pom_dyn_params_load(&c, cfg, &err) != POM_OK &&
             strstr(err.message, "joints.model") != NULL);
  pom_cfg_destroy(cfg);
  check_true(strcmp(pom_dyn_joint_model_name(POM_JOINTS_RIGID), "rigid") == 0);
  /* a design with short, leaning links (tests/test_kinematics.c): the
   * maneuver to the stroke ends drives the rigid mechanism into a singular
   * pose. The dexterity floor (solver.min_dexterity, default 1e-3,
   * docs/dynamics-exact.md section 3) must stop it there with a status that
   * says so, within a few thousand steps; min_dexterity = 0 turns the floor
   * off and solver.max_steps bounds the run instead */
  check_true(p.solver.min_dexterity == 1e-3);
  for (int cz = 0; cz < 2; ++cz) { /* link length 1.8 r: out of reach; 2.0 r: locks singular */
    pom_kin_design dz = {
        0.012, {0.5 * POM_PI, 0.0, cz ? 2.0 : 1.8, 80.0 * POM_DEG, 60.0 * POM_DEG, 0.0, 0.0}};
    setup_t z = *s3;
    check_true(pom_kin_arch_from_design(&z.arch, pom_kin_arch_type_find("3PSS"), &dz, &err) ==
               POM_OK);
    check_true(pom_kin_mechanism_from(&z.mech, &z.arch, &z.in, &err) == POM_OK);
    for (int off = 0; off < 2; ++off) {
      pom_dyn_params pz = p;
      pz.maneuver.horizon = 0.03;
      if (off) {
        pz.solver.min_dexterity = 0.0;
        pz.solver.max_steps = 10000; /* ~0.1 s instead of the default's ~2 s */
      }
      double ends[3] = {6e-3, -6e-3, 6e-3};
      run_t rz;
      if (run_build(&rz, &z, &pz) != POM_OK) {
        run_free(&rz);
        continue;
      }
      pom_status st = pom_dyn_simulate(rz.m, rz.d, ends, &rz.mt, NULL, &rz.err);
      check_true(st != POM_OK && rz.mt.status == st && isnan(rz.mt.execution_time));
      const char *why = rz.mt.reason;
      printf("singular pose (%s): %s (%.3g s wall, %ld steps)\n", off ? "no floor" : "floor 1e-3",
             why, rz.mt.wall_time, (long)rz.mt.steps);
      if (!off) {
        /* the floor, or the assembly failure where that comes first */
        int stopped = st == POM_ERR_SINGULAR && strstr(why, "near-singular pose at t = ") &&
                      strstr(why, "< solver.min_dexterity = 0.001") != NULL;
        check_true(stopped || (st == POM_ERR_UNREACHABLE && strstr(why, "cannot be assembled")));
        check_true(rz.mt.steps < 5000 && rz.mt.wall_time < 1.0);
        if (stopped) {
          /* the stop pose: 1/kappa_2 of its J within the bound's factor 3 below
           * the bound the driver saw, which is below the floor */
          double R[9], qs[3], J[9], dex = NAN, bound = rz.d->out.dexterity_bound;
          rz.m->form->platform_rotation(rz.m, N_VGetArrayPointer(rz.d->y), R);
          check_true(pom_kin_inverse_jacobian(&z.arch, R, qs, J, NULL) == POM_OK);
          pom_kin_dexterity(J, NULL, NULL, &dex);
          check_true(bound < 1e-3 && dex <= bound * (1 + 1e-9) && dex >= bound / 3.0);
          printf("  stop pose: 3/kappa_F %.3g, 1/kappa_2 %.3g\n", bound, dex);
        }
      } else {
        /* no floor: the accidents of the integration end it, as before the floor
         * (1.8 r: the energy audit at the horizon; 2.0 r: max_steps) */
        check_true(strstr(why, "near-singular") == NULL);
        check_true(strstr(why, "rigid joints") != NULL ||
                   (cz == 0 && strstr(why, "energy audit does not close") != NULL));
        if (cz == 1) check_true(rz.mt.steps >= 10000);
      }
      run_free(&rz);
    }
  }
  /* a target far beyond the stroke: the rigid mechanism runs out of reach (3PSS
   * links cannot follow) or the run ends otherwise with a clear status, never NaN */
  run_t r;
  double far[3] = {0.2, -0.2, 0.2};
  p.maneuver.horizon = 0.02;
  if (run_build(&r, s3, &p) == POM_OK) {
    pom_status st = pom_dyn_simulate(r.m, r.d, far, &r.mt, r.tr, &r.err);
    check_true(st == POM_OK || r.mt.status == st);
    if (st != POM_OK) check_true(strlen(r.mt.reason) > 0 && isnan(r.mt.execution_time));
    printf("far target: %s %s\n", pom_strerror(st), r.mt.reason);
  }
  run_free(&r);
}

/* The shipped designs' normal maneuvers never meet the dexterity floor: 20
 * maneuvers of each architecture on the exact path as the studies run it
 * (rigid joints, quasi-static coil; targets = IK of platform orientations
 * within 8 deg of home per ZYX angle, the architectures study's range) end
 * POM_OK at the default floor. Over the studies the bound stays >= 0.95
 * (1/kappa_2 >= 0.67, docs/dynamics-exact.md section 3). */
static void test_dexterity_floor_normal(const setup_t *s) {
  pom_dyn_params p = s->par;
  p.joints.model = POM_JOINTS_RIGID;
  p.scene.coil_inductance = 0;
  check_true(p.solver.min_dexterity == 1e-3);
  pom_rng rng;
  pom_rng_seed(&rng, 20120708, 3);
  run_t r;
  if (run_build(&r, s, &p) != POM_OK) {
    run_free(&r);
    return;
  }
  int ok = 0;
  long steps = 0;
  for (int n = 0; n < 20; ++n) {
    double e[3], R[9], q[3];
    for (int k = 0; k < 3; ++k)
      e[k] = pom_rng_range(&rng, -8.0, 8.0) * POM_DEG;
    pom_euler_zyx_to_matrix(R, e);
    if (!check_true(pom_kin_inverse(&s->arch, R, q, NULL) == POM_OK)) continue;
    pom_status st = pom_dyn_simulate(r.m, r.d, q, &r.mt, NULL, &r.err);
    ok += st == POM_OK;
    steps += r.mt.steps;
    if (!check_true(st == POM_OK)) printf("  maneuver %d: %s\n", n, r.mt.reason);
  }
  printf("%s dexterity floor: %d of 20 maneuvers ok (%ld steps)\n", s->arch.name, ok, steps);
  run_free(&r);
}

int main(void) {
  setup_t s3, u3, r3;
  if (!setup_load(&s3, "configs/3pss.cfg") || !setup_load(&u3, "configs/3sps.cfg") ||
      !setup_load(&r3, "configs/3rrr.cfg")) {
    check_true(0);
    return check_summary("test_dynamics_exact");
  }
  test_mass_matrix(&s3);
  test_mass_matrix(&u3);
  test_velocity_products(&s3);
  test_velocity_products(&u3);
  test_energy(&s3, POM_ORIENT_EULER_ZYX, 1e-10);
  test_energy(&u3, POM_ORIENT_QUATERNION, 1e-10);
  test_maneuver(&s3);
  test_maneuver(&u3);
  test_kp_convergence(&s3);
  test_kp_convergence(&u3);
  test_kp_first_order(&s3);
  test_kp_first_order(&u3);
  /* the 3-RRR spherical wrist with rotary actuators: the same families */
  test_mass_matrix(&r3);
  test_velocity_products(&r3);
  test_energy(&r3, POM_ORIENT_EULER_ZYX, 1e-10);
  test_energy(&r3, POM_ORIENT_QUATERNION, 1e-10);
  test_maneuver(&r3);
  test_kp_convergence(&r3);
  test_kp_first_order(&r3);
  test_dexterity_floor_normal(&s3);
  test_dexterity_floor_normal(&u3);
  test_dexterity_floor_normal(&r3);
  test_errors(&s3, &u3);
  return check_summary("test_dynamics_exact");
}
