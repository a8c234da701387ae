/* dyn_diagnose.c - what a maneuver that reached solver.max_steps was held
 * up by (docs/dynamics.md section 14, "Ranges"): on the rigid path the drive
 * mode against the BDF order's stability sector or the step size
 * (dyn_exact_order.c); the stiffest joint mode of the parasitic springs
 * against the step size; or the tolerance. */
#include "dyn_internal.h"
#include "pom_math.h"

#include <math.h>
#include <stdio.h>

/* A mode is taken as what limits the step when it oscillates (damping ratio
 * below 1: an overdamped spring is a fast real pole, which BDF steps over)
 * and the steps resolve it, and no more: omega h in [DIAG_OMEGA_H_LO,
 * DIAG_OMEGA_H_HI) (between 2 and ~100 steps per period; measured 0.5-2.1 on
 * the runs that stop at k_p 1e10-1e12, docs/dynamics.md section 14). A step
 * that does not resolve it has omega h >> 1; a step far below the mode's
 * needs (omega h << 1) is held down by something else: the tolerance. */
#define DIAG_OMEGA_H_LO 0.05
#define DIAG_OMEGA_H_HI 3.0

/* Mobility of one side of a joint along a force at lever rho (1/kg): 1/m
 * (0 for a body pinned to its pivot) plus |rho|^2 / I_min, an upper bound of
 * the inverse effective mass; 0 for the ground. */
static double side_mobility(const pom_dyn_model *m, const dyn_joint *jt, int side) {
  if (jt->slot[side] < 0) return 0.0;
  const dyn_body *b = &m->body[jt->slot[side]];
  const double i_min = fmin(b->principal[0], fmin(b->principal[1], b->principal[2]));
  const double r2 = pom_v3_dot(jt->rho[side], jt->rho[side]);
  return (b->pinned ? 0.0 : 1.0 / b->mass) + (i_min > 0.0 ? r2 / i_min : 0.0);
}

/* Inverse smallest principal moment of one side (1/(kg m^2)); 0 for the ground. */
static double side_rot_mobility(const pom_dyn_model *m, const dyn_joint *jt, int side) {
  if (jt->slot[side] < 0) return 0.0;
  const dyn_body *b = &m->body[jt->slot[side]];
  const double i_min = fmin(b->principal[0], fmin(b->principal[1], b->principal[2]));
  return i_min > 0.0 ? 1.0 / i_min : 0.0;
}

/* ---- the stiffest oscillating joint mode ----------------------------------- */
double pom_dyn_stiffest_joint_mode(const pom_dyn_model *m, int *joint, int *angular, double *zeta) {
  const pom_dyn_joints *jp = &m->par.joints;
  double w_max = 0.0;
  int j_max = -1, a_max = 0;
  double z_max = 0.0;
  if (m->form != &pom_dyn_form_parasitic) goto out;
  for (int j = 0; j < m->n_joints; ++j) {
    const dyn_joint *jt = &m->joint[j];
    if (jt->n_lin > 0 || jt->distance) {
      const double mob = side_mobility(m, jt, 0) + side_mobility(m, jt, 1);
      const double w = sqrt(jp->stiffness * mob);
      if (w > w_max && jp->damping * w / (2.0 * jp->stiffness) < 1.0) {
        w_max = w, j_max = j, a_max = 0;
        z_max = jp->damping * w / (2.0 * jp->stiffness); /* c / (2 sqrt(k m_eff)) */
      }
    }
    if (jt->n_ang > 0) {
      const double mob = side_rot_mobility(m, jt, 0) + side_rot_mobility(m, jt, 1);
      const double w = sqrt(jp->angular_stiffness * mob);
      if (w > w_max && jp->angular_damping * w / (2.0 * jp->angular_stiffness) < 1.0) {
        w_max = w, j_max = j, a_max = 1;
        z_max = jp->angular_damping * w / (2.0 * jp->angular_stiffness);
      }
    }
  }
out:
  if (joint) *joint = j_max;
  if (angular) *angular = a_max;
  if (zeta) *zeta = z_max;
  return w_max;
}

/* ---- the message ------------------------------------------------------------ */
void pom_dyn_max_steps_reason(const pom_dyn_model *m, double t, char *buf, size_t n) {
  const pom_dyn_solver *s = &m->par.solver;
  const double h_mean = t / (double)s->max_steps;
  int j = -1, ang = 0;
  double zeta = 0.0;
  const double w = pom_dyn_stiffest_joint_mode(m, &j, &ang, &zeta);
  /* short enough for the maneuver's reason (256 characters) */
  int len =
      snprintf(buf, n, "CVODE reached solver.max_steps = %ld at t = %.3g s (mean step %.2g s)",
               s->max_steps, t, h_mean);
  if (len < 0 || (size_t)len >= n) return;
  const dyn_drive_mode *dm = &m->drive;
  const double wd = dm->oscillating ? hypot(dm->re, dm->im) : 0.0;
  if (dm->analysed && dm->oscillating && m->max_order > dm->stable_order &&
      !s->stability_limit_detection)
    /* the order in use can leave the drive mode's sector and nothing guards
     * it (with the detection on, orders 4-5 outside it cost 1.0-1.3x:
     * docs/dynamics.md section 7): stability holds the steps */
    snprintf(buf + len, n - (size_t)len,
             ": the drive mode (coil and controller loop) at %.2g rad/s lies %.2f deg from the "
             "negative real axis, outside BDF order %d's stability sector (%.2f deg); set "
             "solver.max_order = %d",
             wd, dm->angle_deg, m->max_order, pom_dyn_bdf_alpha_deg(m->max_order),
             dm->stable_order > 2 ? dm->stable_order : 2);
  else if (dm->analysed && dm->oscillating && wd * h_mean >= DIAG_OMEGA_H_LO &&
           wd * h_mean < DIAG_OMEGA_H_HI)
    /* A-stable or inside the sector: the error test resolves the ringing */
    snprintf(buf + len, n - (size_t)len,
             ": the steps resolve the drive mode (coil and controller loop, omega ~ %.2g rad/s, "
             "damping ratio %.2g, BDF order <= %d) ringing after saturation exits, omega x step "
             "%.2g; lower controller.kp, loosen solver.rtol or raise solver.max_steps",
             wd, -dm->re / wd, m->max_order, wd * h_mean);
  else if (j >= 0 && w * h_mean >= DIAG_OMEGA_H_LO && w * h_mean < DIAG_OMEGA_H_HI)
    snprintf(buf + len, n - (size_t)len,
             ": joint %d (%s) at joints.%s = %g has omega ~ %.2g rad/s (damping ratio %.2g), "
             "omega x step %.2g; lower it or raise solver.max_steps",
             j + 1, m->joint[j].distance ? "rod" : pom_joint_type_name(m->joint[j].type),
             ang ? "angular_stiffness_Nm_per_rad" : "stiffness_N_per_m",
             ang ? m->par.joints.angular_stiffness : m->par.joints.stiffness, w, zeta, w * h_mean);
  else
    snprintf(buf + len, n - (size_t)len,
             ": the error test at solver.rtol = %g (atol_scale %g%s) sets the step; loosen "
             "solver.rtol or raise solver.max_steps",
             s->rtol, s->atol_scale, s->atol_scale > 0.0 ? "" : ": natural sizes");
}
