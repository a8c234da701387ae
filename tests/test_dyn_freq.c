/* test_dyn_freq.c - the small-signal frequency response (docs/capability.md,
 * "Small-signal frequency response"; pom_dyn_freq.h):
 *   1. a decoupled single-axis case: the 3-RRR at home on rigid joints, gravity
 *      off, the limbs' inertia made negligible and the platform's isotropic, so
 *      that the reflected inertia J^-T M J^-1 = m_eff 1 and every actuator loop
 *      is the same SISO loop. Bandwidth (per axis and worst), crossover and
 *      margins match the analytic closed-loop and loop transfer functions of
 *      one actuator (coil + PID + m_eff) within 1 %;
 *   2. a general pose of the 3P-S-S/S on rigid joints with gravity: T_xx(jw)
 *      matches small sine sweeps of the setpoint simulated in the time domain
 *      (steady-state fit at the drive frequency) within 2 % in gain and 2 deg
 *      in phase at five frequencies;
 *   3. the figures of the three shipped configurations at home exist and are
 *      consistent (stable, DC gain 1, finite bandwidths; parasitic modes). */
#include "check.h"
#include "dyn_internal.h"
#include "dyn_test_util.h"
#include "pom_dyn_freq.h"
#include "pom_math.h"

#include <complex.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* ---- 1. the analytic single-axis loop ------------------------------------- */
typedef struct {
  double m, K, R, L, b, S, kp, ki, kd;
  int ideal;
} siso;

/* plant q/u = K / ((L s + R)(m s^2 + b s) + K^2 s) */
static double complex plant(const siso *p, double complex s) {
  return p->K / ((p->L * s + p->R) * (p->m * s * s + p->b * s) + p->K * p->K * s);
}
/* the PID: u = C_e e - C_d s q (derivative on the measured rate) */
static void pid(const siso *p, double complex s, double complex *ce, double complex *cd) {
  if (p->ideal) {
    *ce = p->S * p->kp * (1.0 + p->ki / s);
    *cd = p->S * p->kp * p->kd;
  } else {
    *ce = p->S * (p->kp + p->ki / s);
    *cd = p->S * p->kd;
  }
}
static double complex closed(const siso *p, double f) {
  double complex s = I * 2.0 * POM_PI * f, ce, cd, P = plant(p, s);
  pid(p, s, &ce, &cd);
  return ce * P / (1.0 + (ce + cd * s) * P);
}
static double complex loopg(const siso *p, double f) {
  double complex s = I * 2.0 * POM_PI * f, ce, cd;
  pid(p, s, &ce, &cd);
  return (ce + cd * s) * plant(p, s);
}
/* bisection in log f of g(f) - level between fa and fb */
static double bis(double (*g)(const siso *, double), const siso *p, double level, double fa,
                  double fb) {
  double ga = g(p, fa) - level;
  for (int i = 0; i < 200 && fb / fa - 1.0 > 1e-12; ++i) {
    double fm = sqrt(fa * fb), gm = g(p, fm) - level;
    if ((gm > 0) == (ga > 0))
      fa = fm, ga = gm;
    else
      fb = fm;
  }
  return sqrt(fa * fb);
}
static double g_closed(const siso *p, double f) {
  return cabs(closed(p, f));
}
static double g_loop(const siso *p, double f) {
  return cabs(loopg(p, f));
}
static double g_loop_im(const siso *p, double f) {
  return cimag(loopg(p, f));
}

static void test_single_axis(void) {
  printf("single axis: 3-RRR at home, rigid, gravity off, platform inertia reflected\n");
  pom_kin_arch arch;
  pom_mechanism mech;
  pom_dyn_params p;
  check_true(load_shipped("3rrr.cfg", &arch, &mech, &p));
  p.joints.model = POM_JOINTS_RIGID;
  p.scene.gravity = 0;
  /* limbs negligible, the platform a sphere about its centre of mass */
  for (int k = 1; k < mech.n_bodies; ++k) {
    if (k == mech.platform) continue;
    mech.body[k].mass *= 1e-9;
    for (int i = 0; i < 9; ++i)
      mech.body[k].inertia[i] *= 1e-9;
  }
  pom_mech_body *pb = &mech.body[mech.platform];
  double I0 = (pb->inertia[0] + pb->inertia[4] + pb->inertia[8]) / 3.0;
  pom_m3_identity(pb->inertia);
  for (int i = 0; i < 9; i += 4)
    pb->inertia[i] = I0;
  pb->mass *= 1e-9;
  pom_dyn_model *m = NULL;
  pom_dyn_data *d = NULL;
  pom_error err;
  pom_error_clear(&err);
  check_true(pom_dyn_model_create(&m, &mech, &arch, &p, &err) == POM_OK);
  check_true(pom_dyn_data_create(&d, m, &err) == POM_OK);
  /* the reflected inertia J^-T M J^-1 (kg m^2 per rad of the actuator) */
  double R[9], w[3] = {0, 0, 0}, M[9], f[3], q[3], J[9], Ji[9], T1[9], Mq[9];
  pom_m3_identity(R);
  check_true(pom_dyn_exact_terms(m, d, R, w, M, f, q, J) == 0);
  check_true(pom_m3_inverse(Ji, J, 1e-14) == POM_OK);
  pom_m3_mul(T1, M, Ji);
  pom_m3_tmul(Mq, Ji, T1);
  double meff = (Mq[0] + Mq[4] + Mq[8]) / 3.0, off = 0.0;
  for (int i = 0; i < 9; ++i)
    off = fmax(off, fabs(Mq[i] - (i % 4 == 0 ? meff : 0.0)));
  printf("  m_eff %.6g kg m^2, largest departure from m_eff 1: %.3g\n", meff, off / meff);
  check_true(off / meff < 1e-6); /* decoupled: the premise of the analytic comparison */
  const pom_dyn_actuator *ap = &p.actuator;
  siso s = {meff,
            ap->force_constant,
            ap->resistance,
            ap->inductance,
            p.scene.bearing_friction ? ap->bearing_friction : 0.0,
            ap->sensor_gain,
            p.controller.kp,
            p.controller.ki,
            p.controller.kd,
            p.controller.form == POM_PID_IDEAL};
  /* analytic figures: -3 dB below |T(0)| = 1, |L| = 1, arg L = -180 deg */
  double fa = 1e-3, bw = NAN, fc = NAN, fx = NAN;
  for (double fb = fa * 1.05; fb < 1e6; fa = fb, fb *= 1.05) {
    if (isnan(bw) && g_closed(&s, fb) < 1.0 / sqrt(2.0))
      bw = bis(g_closed, &s, 1.0 / sqrt(2.0), fa, fb);
    if (isnan(fc) && g_loop(&s, fa) > 1.0 && g_loop(&s, fb) <= 1.0)
      fc = bis(g_loop, &s, 1.0, fa, fb);
    if (!isnan(fc) && isnan(fx) && fb > fc && (g_loop_im(&s, fa) > 0) != (g_loop_im(&s, fb) > 0) &&
        creal(loopg(&s, fb)) < 0)
      fx = bis(g_loop_im, &s, 0.0, fa, fb);
  }
  double pm = 180.0 + carg(loopg(&s, fc)) * 180.0 / POM_PI;
  double gm = isnan(fx) ? INFINITY : -20.0 * log10(cabs(loopg(&s, fx)));
  printf("  analytic: bandwidth %.6g Hz, crossover %.6g Hz, PM %.6g deg, GM %.6g dB\n", bw, fc, pm,
         gm);
  pom_dyn_freq_figures F;
  double q0[3] = {0, 0, 0};
  check_true(pom_dyn_freq_figures_at(m, d, q0, &F, &err) == POM_OK);
  printf("  linearized: bandwidth %.6g %.6g %.6g worst %.6g Hz\n", F.bandwidth_hz[0],
         F.bandwidth_hz[1], F.bandwidth_hz[2], F.bandwidth_worst_hz);
  for (int e = 0; e < 3; ++e)
    check_rel(F.bandwidth_hz[e], bw, 0.01);
  check_rel(F.bandwidth_worst_hz, bw, 0.01);
  for (int a = 0; a < 3; ++a) {
    printf("  loop %d: crossover %.6g Hz, PM %.6g deg, GM %.6g dB\n", a + 1, F.crossover_hz[a],
           F.phase_margin_deg[a], F.gain_margin_db[a]);
    check_rel(F.crossover_hz[a], fc, 0.01);
    check_rel(F.phase_margin_deg[a], pm, 0.01);
    if (isfinite(gm))
      check_rel(F.gain_margin_db[a], gm, 0.01);
    else
      check_true(isinf(F.gain_margin_db[a]));
  }
  /* the Bode data against the analytic T and L at a few frequencies */
  double fr[4] = {3.7, 41.0, 170.0, 950.0}, mag[4], ph[4];
  check_true(pom_dyn_freq_response(m, d, q0, POM_DYN_FREQ_AXIS, 1, fr, 4, mag, ph, &err) == POM_OK);
  for (int i = 0; i < 4; ++i) {
    double complex t = closed(&s, fr[i]);
    check_abs(mag[i], 20.0 * log10(cabs(t)), 0.01 * 8.686); /* 1 % in gain */
    check_abs(remainder(ph[i] - carg(t) * 180.0 / POM_PI, 360.0), 0.0, 0.5);
  }
  check_true(pom_dyn_freq_response(m, d, q0, POM_DYN_FREQ_LOOP, 2, fr, 4, mag, ph, &err) == POM_OK);
  for (int i = 0; i < 4; ++i) {
    double complex l = loopg(&s, fr[i]);
    printf("  L at %g Hz: %.6g dB %.4f deg, analytic %.6g dB %.4f deg\n", fr[i], mag[i], ph[i],
           20.0 * log10(cabs(l)), carg(l) * 180.0 / POM_PI);
    check_abs(mag[i], 20.0 * log10(cabs(l)), 0.01 * 8.686);
    check_abs(remainder(ph[i] - carg(l) * 180.0 / POM_PI, 360.0), 0.0, 0.5);
  }
  pom_dyn_data_destroy(d);
  pom_dyn_model_destroy(m);
}

/* ---- 2. sine sweeps in the time domain ------------------------------------ */
typedef struct {
  double q0[3], dq[3], w;
} sine_path;

static void sine_setpoint(void *ctx, double t, double *target) {
  const sine_path *sp = ctx;
  for (int a = 0; a < 3; ++a)
    target[a] = sp->q0[a] + sp->dq[a] * sin(sp->w * t);
}

/* least squares of y = c0 + c1 t + a sin wt + b cos wt over samples i0..n-1;
 * returns the complex amplitude a - j b ... as b + j a over sin: y ~ Im(Z e^{jwt}) */
static double complex fit_sine(const double *t, const double *y, int i0, int n, double w) {
  double A[16] = {0}, r[4] = {0};
  for (int i = i0; i < n; ++i) {
    double b[4] = {1.0, t[i] - t[i0], sin(w * t[i]), cos(w * t[i])};
    for (int j = 0; j < 4; ++j) {
      r[j] += b[j] * y[i];
      for (int k = 0; k < 4; ++k)
        A[4 * j + k] += b[j] * b[k];
    }
  }
  /* Gaussian elimination (4 x 4, symmetric positive definite) */
  for (int j = 0; j < 4; ++j)
    for (int i = j + 1; i < 4; ++i) {
      double l = A[4 * i + j] / A[4 * j + j];
      for (int k = j; k < 4; ++k)
        A[4 * i + k] -= l * A[4 * j + k];
      r[i] -= l * r[j];
    }
  double x[4];
  for (int i = 3; i >= 0; --i) {
    double acc = r[i];
    for (int k = i + 1; k < 4; ++k)
      acc -= A[4 * i + k] * x[k];
    x[i] = acc / A[4 * i + i];
  }
  /* a sin + b cos = Im((a + j b) e^{jwt}) */
  return x[2] + I * x[3];
}

static void test_sine_sweep(const char *file, int rigid, int axis, int nfr, const double *fr,
                            double horizon) {
  printf("sine sweeps: %s, %s joints, gravity, a general pose, axis %d\n", file,
         rigid ? "rigid" : "parasitic", axis);
  pom_kin_arch arch;
  pom_mechanism mech;
  pom_dyn_params p;
  check_true(load_shipped(file, &arch, &mech, &p));
  p.joints.model = rigid ? POM_JOINTS_RIGID : POM_JOINTS_PARASITIC;
  p.solver.rtol = 1e-8;
  p.solver.atol_scale = 0.0; /* natural sizes: 1e-11 rad on the orientation */
  p.maneuver.horizon = horizon;
  p.maneuver.output_dt = 2e-5;
  pom_dyn_model *m = NULL;
  pom_dyn_data *d = NULL;
  pom_dyn_trace *tr = NULL;
  pom_error err;
  pom_error_clear(&err);
  check_true(pom_dyn_model_create(&m, &mech, &arch, &p, &err) == POM_OK);
  check_true(pom_dyn_data_create(&d, m, &err) == POM_OK);
  check_true(pom_dyn_trace_create(&tr, m, &err) == POM_OK);
  /* the pose: ZYX (0.061, -0.043, 0.052) rad */
  const double eul[3] = {0.061, -0.043, 0.052}, amp = 1e-4;
  double R0[9], q0[3], J[9];
  pom_euler_zyx_to_matrix(R0, eul);
  check_true(pom_kin_inverse_jacobian(&arch, R0, q0, J, &err) == POM_OK);

  double mag[8], ph[8];
  check_true(pom_dyn_freq_response(m, d, q0, POM_DYN_FREQ_AXIS, axis, fr, nfr, mag, ph, &err) ==
             POM_OK);
  sine_path sp;
  for (int a = 0; a < 3; ++a) {
    sp.q0[a] = q0[a];
    sp.dq[a] = J[3 * a + axis] * amp;
  }
  double *ty = calloc((size_t)tr->capacity, sizeof *ty);
  check_true(ty != NULL);
  for (int k = 0; k < nfr; ++k) {
    sp.w = 2.0 * POM_PI * fr[k];
    pom_dyn_set_setpoint_path(d, sine_setpoint, &sp);
    pom_dyn_metrics mt;
    pom_status st = pom_dyn_simulate(m, d, q0, &mt, tr, &err);
    pom_dyn_set_setpoint_path(d, NULL, NULL);
    check_true(st == POM_OK);
    if (st != POM_OK) {
      printf("  %s\n", err.message);
      continue;
    }
    /* platform rotation about x relative to the pose */
    for (int i = 0; i < tr->n; ++i) {
      double R[9], D[9], rv[3];
      pom_euler_zyx_to_matrix(R, tr->euler_zyx + 3 * i);
      pom_m3_mult(D, R, R0);
      pom_m3_rotvec(rv, D);
      ty[i] = rv[axis] / amp;
    }
    /* steady state: whole periods after 0.1 s (the transients of the
     * step from home decay with tau < 5 ms) */
    const double P = 1.0 / fr[k];
    double t_from = p.maneuver.horizon - P * floor((p.maneuver.horizon - 0.1) / P);
    int i0 = 0;
    while (i0 < tr->n && tr->t[i0] < t_from - 1e-12)
      ++i0;
    double complex Z = fit_sine(tr->t, ty, i0, tr->n, sp.w);
    double gain_db = 20.0 * log10(cabs(Z)), phase = carg(Z) * 180.0 / POM_PI;
    printf("  %6.1f Hz: simulated %8.4f dB %8.3f deg, linearized %8.4f dB %8.3f deg (%ld steps)\n",
           fr[k], gain_db, phase, mag[k], ph[k], mt.steps);
    check_rel(cabs(Z), pow(10.0, mag[k] / 20.0), 0.02);
    check_abs(remainder(phase - ph[k], 360.0), 0.0, 2.0);
  }
  free(ty);
  pom_dyn_trace_destroy(tr);
  pom_dyn_data_destroy(d);
  pom_dyn_model_destroy(m);
}

/* ---- 2b. the output map: Euler angles and quaternions agree ---------------- */
static void test_orientation_maps(void) {
  pom_kin_arch arch;
  pom_mechanism mech;
  pom_dyn_params p;
  check_true(load_shipped("3sps.cfg", &arch, &mech, &p));
  const double eul[3] = {-0.047, 0.071, 0.036};
  double R0[9], q0[3], bw[2][4], fr[3] = {7.3, 48.0, 410.0}, mag[2][3], ph[2][3];
  pom_euler_zyx_to_matrix(R0, eul);
  pom_error err;
  pom_error_clear(&err);
  check_true(pom_kin_inverse(&arch, R0, q0, &err) == POM_OK);
  for (int k = 0; k < 2; ++k) {
    p.scene.orientation = k ? POM_ORIENT_QUATERNION : POM_ORIENT_EULER_ZYX;
    pom_dyn_model *m = NULL;
    pom_dyn_data *d = NULL;
    pom_dyn_freq_figures F;
    check_true(pom_dyn_model_create(&m, &mech, &arch, &p, &err) == POM_OK);
    check_true(pom_dyn_data_create(&d, m, &err) == POM_OK);
    check_true(pom_dyn_freq_figures_at(m, d, q0, &F, &err) == POM_OK);
    check_true(pom_dyn_freq_response(m, d, q0, POM_DYN_FREQ_AXIS, 2, fr, 3, mag[k], ph[k], &err) ==
               POM_OK);
    for (int e = 0; e < 3; ++e)
      bw[k][e] = F.bandwidth_hz[e];
    bw[k][3] = F.bandwidth_worst_hz;
    pom_dyn_data_destroy(d);
    pom_dyn_model_destroy(m);
  }
  printf("3S-P-S/S parasitic at a general pose: bandwidth x %.6g y %.6g z %.6g worst %.6g Hz "
         "(Euler), %.6g %.6g %.6g %.6g (quaternion)\n",
         bw[0][0], bw[0][1], bw[0][2], bw[0][3], bw[1][0], bw[1][1], bw[1][2], bw[1][3]);
  /* the same physics in other coordinates: equal up to the Newton and
   * rounding errors */
  for (int e = 0; e < 4; ++e)
    check_rel(bw[1][e], bw[0][e], 1e-6);
  for (int i = 0; i < 3; ++i) {
    check_abs(mag[1][i], mag[0][i], 1e-6);
    check_abs(ph[1][i], ph[0][i], 1e-5);
  }
}

/* ---- 3. the shipped configurations ---------------------------------------- */
static void test_shipped(const char *file) {
  pom_kin_arch arch;
  pom_mechanism mech;
  pom_dyn_params p;
  check_true(load_shipped(file, &arch, &mech, &p));
  pom_dyn_model *m = NULL;
  pom_dyn_data *d = NULL;
  pom_error err;
  pom_error_clear(&err);
  check_true(pom_dyn_model_create(&m, &mech, &arch, &p, &err) == POM_OK);
  check_true(pom_dyn_data_create(&d, m, &err) == POM_OK);
  double q[3] = {0, 0, 0};
  pom_dyn_freq_figures F;
  check_true(pom_dyn_freq_figures_at(m, d, q, &F, &err) == POM_OK);
  printf("%s at home: bandwidth x %.4g y %.4g z %.4g worst %.4g Hz along (%.3f %.3f %.3f); "
         "peak %.3g dB\n",
         file, F.bandwidth_hz[0], F.bandwidth_hz[1], F.bandwidth_hz[2], F.bandwidth_worst_hz,
         F.worst_dir[0], F.worst_dir[1], F.worst_dir[2], F.peak_db_worst);
  for (int a = 0; a < 3; ++a)
    printf("  loop %d: crossover %.5g Hz, PM %.4g deg, GM %.4g dB\n", a + 1, F.crossover_hz[a],
           F.phase_margin_deg[a], F.gain_margin_db[a]);
  printf("  %d parasitic modes:", F.n_modes);
  for (int k = 0; k < F.n_modes; ++k)
    printf(" %.4g Hz (zeta %.3f)", F.mode_hz[k], F.mode_zeta[k]);
  printf("\n");
  check_true(F.stable == 1);
  for (int e = 0; e < 3; ++e) {
    check_rel(F.dc_gain[e], 1.0, 1e-3);
    check_true(isfinite(F.bandwidth_hz[e]) && F.bandwidth_worst_hz <= F.bandwidth_hz[e] * 1.000001);
  }
  check_true(F.n_modes > 0); /* the shipped scenes have parasitic joints */
  /* the slowest pole is the PID integral's, ~K_I for the ideal form's high
   * gain (not an idle link spin, which the deflation leaves out) */
  check_rel(F.slowest_pole_hz, p.controller.ki / (2.0 * POM_PI), 0.01);
  pom_dyn_data_destroy(d);
  pom_dyn_model_destroy(m);
}

int main(void) {
  test_single_axis();
  const double fr[5] = {10.0, 31.0, 57.0, 120.0, 330.0};
  test_sine_sweep("3pss.cfg", 1, 0, 5, fr, 0.5);
  const double fr2[2] = {57.0, 330.0};
  test_sine_sweep("3pss.cfg", 0, 1, 2, fr2, 0.15);
  test_orientation_maps();
  test_shipped("3pss.cfg");
  test_shipped("3sps.cfg");
  test_shipped("3rrr.cfg");
  return check_summary("test_dyn_freq");
}
