/* dyn_exact_order.c - the BDF order the rigid path's drive mode allows
 * (docs/dynamics.md section 7, "Order and stability"). At rest at home the
 * linearized loop of each actuator-space mode (modal mass mu of the reflected
 * inertia J^-T M J^-1, bearing b, coil L and R_c, force constant K, the
 * controller's partials) has the characteristic polynomial
 *   [(L s + R_c)(mu s^2 + b s) + K^2 s - K (du/dq + du/dq_dot s)] (s - dz_dot/dz)
 *     - K du/dz (dz_dot/dq + dz_dot/dq_dot s) = 0,
 * whose lightly damped pair (the coil's ringing, -R_c/2L +- j sqrt((K^2 +
 * K G tau_D)/(mu L)) for the PID at high gain) leaves the A(alpha) sector of
 * BDF 3 once K_P is ~10x the shipped one: CVODE's steps at orders 3-5 are
 * then held by stability, not accuracy (1.5 M steps at 1e3 x K_P). The
 * maneuver is then integrated at order 2 (A-stable). Also the Newton
 * coefficient the drive voltage needs at high gain (pom_dyn_newton_coef). */
#include "dyn_internal.h"
#include "pom_dyn_print.h"
#include "pom_math.h"

#include <complex.h>
#include <math.h>
#include <string.h>

/* A(alpha) angles of BDF 1-5 (Hairer & Wanner, Solving ODEs II, section V.2,
 * Table 2.3): the sector |arg(-h lambda)| < alpha lies in the stability
 * region for every h > 0. */
static const double bdf_alpha_deg[5] = {90.0, 90.0, 86.03, 73.35, 51.84};

double pom_dyn_bdf_alpha_deg(int order) {
  return order >= 1 && order <= 5 ? bdf_alpha_deg[order - 1] : 0.0;
}

/* The order at and below which CVODE's stability limit detection is not
 * needed: orders 1 and 2 are A-stable. Above it the cap engages only when
 * the mode is outside BDF 3's sector: inside it (the shipped gains, 74-80
 * deg) CVODE's stability limit detection keeps orders 4-5 in check at a
 * lower cost than a cap at 3 (measured, docs/dynamics.md section 7). */
#define ORDER_A_STABLE 2
#define ORDER_GUARDED  3

#define ROOTS_MAX_DEG 6
#define ROOTS_ITER    200
#define ROOTS_RESID   1e-9

/* p(z) and p'(z) of c[0] z^n + ... + c[n] by Horner; *scale = sum |c_k| |z|^(n-k). */
static double complex horner(const double *c, int n, double complex z, double complex *dp,
                             double *scale) {
  double complex p = c[0], d = 0.0;
  double s = fabs(c[0]), az = cabs(z);
  for (int k = 1; k <= n; ++k) {
    d = d * z + p;
    p = p * z + c[k];
    s = s * az + fabs(c[k]);
  }
  if (dp) *dp = d;
  if (scale) *scale = s;
  return p;
}

int pom_dyn_poly_roots(const double *c, int n, double *re, double *im) {
  if (n < 1 || n > ROOTS_MAX_DEG || c[0] == 0.0) return 0;
  /* starting points on a circle of the roots' geometric mean radius,
   * |c_n / c_0|^(1/n) (1 when the constant term is 0), off the axes */
  double r0 = c[n] != 0.0 ? pow(fabs(c[n] / c[0]), 1.0 / n) : 1.0;
  double complex z[ROOTS_MAX_DEG];
  for (int k = 0; k < n; ++k)
    z[k] = r0 * cexp(I * (2.0 * POM_PI * k / n + 0.4));
  for (int it = 0; it < ROOTS_ITER; ++it) { /* Aberth-Ehrlich */
    double moved = 0.0;
    for (int k = 0; k < n; ++k) {
      double complex dp, p = horner(c, n, z[k], &dp, NULL);
      if (p == 0.0) continue;
      double complex ratio = p / dp, sum = 0.0;
      for (int j = 0; j < n; ++j)
        if (j != k) sum += 1.0 / (z[k] - z[j]);
      double complex w = ratio / (1.0 - ratio * sum);
      z[k] -= w;
      moved = fmax(moved, cabs(w) / fmax(cabs(z[k]), 1e-300));
    }
    if (moved < 1e-15) break;
  }
  int ok = 1;
  for (int k = 0; k < n; ++k) {
    for (int it = 0; it < 3; ++it) { /* Newton polish on the undeflated polynomial */
      double complex dp, p = horner(c, n, z[k], &dp, NULL);
      if (p == 0.0 || dp == 0.0) break;
      z[k] -= p / dp;
    }
    double scale;
    double complex p = horner(c, n, z[k], NULL, &scale);
    if (!(cabs(p) <= ROOTS_RESID * scale)) ok = 0;
    re[k] = creal(z[k]);
    im[k] = cimag(z[k]);
  }
  return ok;
}

/* The loop polynomial of one modal mass mu (descending coefficients into
 * c[0..5]); returns its degree. */
static int loop_polynomial(const pom_dyn_model *m, const pom_dyn_ctrl_partials *cp, int n_states,
                           double mu, double c[6]) {
  const pom_dyn_actuator *ap = &m->par.actuator;
  const double L = m->par.scene.coil_inductance ? ap->inductance : 0.0;
  const double R = ap->resistance, K = ap->force_constant;
  const double b = m->par.scene.bearing_friction ? ap->bearing_friction : 0.0;
  /* cubic (L s + R)(mu s^2 + b s) + (K^2 - K du/dq_dot) s - K du/dq */
  const double q[4] = {L * mu, L * b + R * mu, R * b + K * K - K * cp->du_dqd, -K * cp->du_dq};
  if (n_states == 0) {
    memcpy(c, q, sizeof q);
    return 3;
  }
  /* times (s - dz_dot/dz), minus K du/dz (dz_dot/dq + dz_dot/dq_dot s) */
  const double dz = cp->dzd_dz[0][0];
  c[0] = q[0];
  for (int k = 1; k < 4; ++k)
    c[k] = q[k] - dz * q[k - 1];
  c[4] = -dz * q[3];
  c[3] -= K * cp->du_dz[0] * cp->dzd_dqd[0];
  c[4] -= K * cp->du_dz[0] * cp->dzd_dq[0];
  return 4;
}

void pom_dyn_order_cap(pom_dyn_model *m, const double M[9], const double J[9]) {
  dyn_drive_mode *dm = &m->drive;
  memset(dm, 0, sizeof *dm);
  if (!m->ctrl_analytic || m->n_actuators != 3) return;
  double Minv[9], JMi[9], A[9];
  if (pom_m3_inverse(Minv, M, 1e-14) != POM_OK) return;
  /* A = J M^-1 J^T: its eigenvalues are the inverse modal masses */
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k)
      JMi[3 * r + k] = J[3 * r] * Minv[k] + J[3 * r + 1] * Minv[3 + k] + J[3 * r + 2] * Minv[6 + k];
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k)
      A[3 * r + k] =
          JMi[3 * r] * J[3 * k] + JMi[3 * r + 1] * J[3 * k + 1] + JMi[3 * r + 2] * J[3 * k + 2];
  double lam[3], V[9];
  pom_m3_sym_eig(lam, V, A);
  /* the controller's partials at rest at home, holding it (target 0) */
  const pom_dyn_ctrl_input in = {0.0, 0.0, 0.0, m->par.actuator.sensor_gain};
  const double z0[POM_DYN_CTRL_MAX_STATES] = {0.0};
  pom_dyn_ctrl_partials cp;
  m->ctrl->partials(&m->par.controller, &in, z0, &cp);
  double worst = -1.0;
  for (int k = 0; k < 3; ++k) {
    if (!(lam[k] > 0.0) || !isfinite(lam[k])) return;
    const double mu = 1.0 / lam[k];
    double c[6], re[6], im[6];
    int n = loop_polynomial(m, &cp, m->ctrl->n_states, mu, c);
    int lead = 0;
    while (lead < n && c[lead] == 0.0) /* the quasi-static coil drops s^3 */
      ++lead;
    while (n > lead && c[n] == 0.0) /* roots at 0 (no integral action): real */
      --n;
    if (n - lead < 1) continue;
    if (!pom_dyn_poly_roots(c + lead, n - lead, re, im)) return;
    for (int r = 0; r < n - lead; ++r) {
      if (!(im[r] > 1e-9 * hypot(re[r], im[r]))) continue; /* one of each pair, real roots out */
      const double ang = atan2(im[r], -re[r]) * 180.0 / POM_PI;
      if (ang > worst) {
        worst = ang;
        dm->oscillating = 1;
        dm->re = re[r], dm->im = im[r], dm->angle_deg = ang, dm->modal_mass = mu;
      }
    }
  }
  dm->analysed = 1;
  dm->stable_order = 5;
  if (dm->oscillating) {
    dm->stable_order = 0;
    for (int k = 5; k >= 1 && !dm->stable_order; --k)
      if (dm->angle_deg < bdf_alpha_deg[k - 1] || (k <= ORDER_A_STABLE && dm->re < 0.0))
        dm->stable_order = k;
  }
  if (dm->stable_order < ORDER_GUARDED && m->max_order > ORDER_A_STABLE)
    m->max_order = ORDER_A_STABLE;
}

/* The Newton solve of a BDF step stops when its weighted correction falls
 * below the coefficient (CVODE's default POM_DYN_NEWTON_COEF_DEFAULT) times
 * the error test's bound: each state may keep an error of about that
 * fraction of its tolerance. The drive voltage reads the mechanical states
 * through the controller's partials and J; the voltage their absolute
 * tolerances move, u_tol = sum |du/dq| |J| atol_angle + |du/dq_dot| |J|
 * atol_rate + |du/dz| atol_ctrl, is 0.03-0.06 V with the shipped gains but
 * 330-630 V at 1e4 x K_P: the Newton error then throws the voltage across
 * its limit, each such step starts the lightly damped drive mode ringing
 * through the saturation and the error test resolves the ringing (docs/
 * dynamics.md section 7, "Newton accuracy at high gain"). The coefficient
 * is lowered until the tolerated Newton error moves the voltage by at most
 * NEWTON_VOLTAGE_SHARE of its limit (a tenth; shares 1, 0.3, 0.03, 0.01
 * measured against it in docs/dynamics.md section 7). */
#define NEWTON_VOLTAGE_SHARE 0.1

void pom_dyn_newton_coef(pom_dyn_model *m, const double J[9], double atol_angle, double atol_rate,
                         double atol_ctrl) {
  m->newton_coef = m->newton_voltage = 0.0;
  if (!m->ctrl_analytic || !m->ctrl->partials) return;
  const pom_dyn_ctrl_input in = {0.0, 0.0, 0.0, m->par.actuator.sensor_gain};
  const double z0[POM_DYN_CTRL_MAX_STATES] = {0.0};
  pom_dyn_ctrl_partials cp;
  m->ctrl->partials(&m->par.controller, &in, z0, &cp);
  double worst = 0.0;
  for (int a = 0; a < m->n_actuators && a < 3; ++a) {
    const double lever = fabs(J[3 * a]) + fabs(J[3 * a + 1]) + fabs(J[3 * a + 2]);
    double u = fabs(cp.du_dq) * lever * atol_angle + fabs(cp.du_dqd) * lever * atol_rate;
    if (m->ctrl->n_states > 0) u += fabs(cp.du_dz[0]) * atol_ctrl;
    worst = fmax(worst, u);
  }
  m->newton_voltage = worst;
  const double c = NEWTON_VOLTAGE_SHARE * m->par.actuator.voltage_limit / worst;
  if (isfinite(c) && c < POM_DYN_NEWTON_COEF_DEFAULT) m->newton_coef = c;
}

int pom_dyn_drive_mode_light(const pom_dyn_model *m, double *omega, double *zeta) {
  if (!m) return 0;
  const dyn_drive_mode *dm = &m->drive;
  if (!dm->analysed || !dm->oscillating || !(dm->angle_deg > bdf_alpha_deg[ORDER_GUARDED - 1]))
    return 0;
  const double w = hypot(dm->re, dm->im);
  if (omega) *omega = w;
  if (zeta) *zeta = -dm->re / w;
  return 1;
}
