/* dyn_validity.c - how far a parasitic-joint maneuver is from its rigid
 * limit (docs/dynamics.md section 13b): rigid_limit_ratio =
 * 1 / (omega_low T_E)^2, omega_low the lowest joint frequency of the
 * parasitic springs and T_E = (int P dt)^2 / int P^2 dt the duration over
 * which the drive spends its energy (P = sum |u i|, the drive's electrical
 * power at the accepted steps). A drive that spends its energy in less than
 * a joint period moves the actuated body before the springs load the rest:
 * the parasitic model is then not at its rigid limit. Second component,
 * joint_dissipation_share = energy_parasitic / int sum max(0, effort q_dot) dt:
 * the share of the mechanical work the drive puts in that the joints' own
 * motion (oscillations about their quasi-static deflection) dissipates; it
 * vanishes as 1/k_p in the rigid limit and catches joints that bounce under
 * a slow drive (the 3S-P-S/S cylinders), which the ratio does not. */
#include "dyn_internal.h"

#include <math.h>

/* Sum over the actuators of |u i| (W) at the outputs just evaluated. */
static double drive_power(const pom_dyn_model *m, const pom_dyn_data *d) {
  double p = 0.0;
  for (int a = 0; a < m->n_actuators; ++a)
    p += fabs(d->out.voltage[a] * d->out.current[a]);
  return p;
}

/* Sum over the actuators of max(0, effort q_dot) (W): the mechanical power
 * the drive puts into the mechanism (what it takes back is not counted). */
static double drive_mech_power(const pom_dyn_model *m, const pom_dyn_data *d) {
  double p = 0.0;
  for (int a = 0; a < m->n_actuators; ++a)
    p += fmax(0.0, d->out.effort[a] * d->out.q_dot[a]);
  return p;
}

/* The lowest joint frequency (rad/s): over the joints with linear springs
 * (k_p), sqrt(k_p (1/m0 + 1/m1)) with the masses of the two sides (the
 * ground and a pinned body's translation immovable); INFINITY without any. */
static double joint_omega_low(const pom_dyn_model *m) {
  double w = INFINITY;
  for (int j = 0; j < m->n_joints; ++j) {
    const dyn_joint *jt = &m->joint[j];
    if (jt->n_lin == 0 && !jt->distance) continue;
    double mobility = 0.0; /* 1/kg */
    for (int s = 0; s < 2; ++s) {
      int b = jt->slot[s];
      if (b >= 0 && !m->body[b].pinned) mobility += 1.0 / m->body[b].mass;
    }
    if (mobility > 0.0) w = fmin(w, sqrt(m->par.joints.stiffness * mobility));
  }
  return w;
}

void pom_dyn_validity_begin(const pom_dyn_model *m, pom_dyn_data *d) {
  dyn_validity *v = &d->validity;
  v->on = m->form->parasitic_springs;
  v->omega_low = v->on ? joint_omega_low(m) : NAN;
  v->t_prev = d->t;
  v->p_prev = drive_power(m, d);
  v->pm_prev = drive_mech_power(m, d);
  v->e1 = v->e2 = v->w_mech = 0.0;
}

void pom_dyn_validity_step(const pom_dyn_model *m, pom_dyn_data *d, double t) {
  dyn_validity *v = &d->validity;
  if (!v->on) return;
  double p = drive_power(m, d), h = t - v->t_prev;
  v->e1 += 0.5 * (p + v->p_prev) * h;
  v->e2 += 0.5 * (p * p + v->p_prev * v->p_prev) * h;
  double pm = drive_mech_power(m, d);
  v->w_mech += 0.5 * (pm + v->pm_prev) * h;
  v->t_prev = t, v->p_prev = p, v->pm_prev = pm;
}

double pom_dyn_validity_ratio(const pom_dyn_model *m, const pom_dyn_data *d) {
  const dyn_validity *v = &d->validity;
  (void)m;
  if (!v->on) return NAN;
  /* no drive power, or no spring: nothing runs ahead of the joints */
  if (!(v->e2 > 0.0) || !isfinite(v->omega_low)) return 0.0;
  double t_e = v->e1 * v->e1 / v->e2;
  return 1.0 / (v->omega_low * t_e * v->omega_low * t_e);
}

double pom_dyn_validity_share(const pom_dyn_model *m, const pom_dyn_data *d,
                              double energy_parasitic) {
  const dyn_validity *v = &d->validity;
  (void)m;
  if (!v->on) return NAN;
  return v->w_mech > 0.0 ? energy_parasitic / v->w_mech : 0.0;
}

int pom_dyn_rigid_limit_flag(double rigid_limit_ratio, double joint_dissipation_share) {
  if (rigid_limit_ratio > POM_DYN_RIGID_LIMIT_WARN ||
      joint_dissipation_share > POM_DYN_JOINT_SHARE_WARN)
    return 1;
  return isnan(rigid_limit_ratio) && isnan(joint_dissipation_share) ? -1 : 0;
}

int pom_dyn_rigid_limit_exceeded(const pom_dyn_metrics *mt) {
  return mt && pom_dyn_rigid_limit_flag(mt->rigid_limit_ratio, mt->joint_dissipation_share) == 1;
}
