/* test_dyn_validity.c - the parasitic model's indicator of its own rigid
 * limit (docs/dynamics.md section 13b, issue 30 item 4): rigid_limit_ratio =
 * 1 / (omega_low T_E)^2 is small where the parasitic 3P-S-S/S spends the
 * rigid model's energy and large where it does not. Independent truth: the
 * rigid path's energy on the same maneuver (itself checked against an
 * independent rigid reference, 261.586 J at voltage_limit_V = 1e5,
 * issue 30). */
#include "check.h"
#include "dyn_internal.h"
#include "dyn_test_util.h"
#include "pom_kinematics.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static const double target[3] = {3e-3, -3e-3, 3e-3}; /* m */

/* Runs configs/<file> with the joints model, voltage limit (V, <= 0 keeps
 * the file's) and k_p (N/m, <= 0 keeps the file's); the metrics into *mt. */
static pom_status run_cfg(const char *file, pom_dyn_metrics *mt, pom_joint_model joints,
                          double vlim, double kp) {
  pom_kin_arch arch;
  pom_mechanism mech;
  pom_dyn_params p;
  run_t r;
  memset(&r, 0, sizeof r);
  if (!load_shipped(file, &arch, &mech, &p)) return POM_ERR_ARG;
  p.joints.model = joints;
  if (vlim > 0) p.actuator.voltage_limit = vlim;
  if (kp > 0) p.joints.stiffness = kp;
  pom_status st = run_arch(&r, &mech, &arch, &p, target, NULL);
  *mt = r.mt;
  run_free(&r);
  return st;
}

static pom_status run_3pss(pom_dyn_metrics *mt, pom_joint_model joints, double vlim, double kp) {
  return run_cfg("3pss.cfg", mt, joints, vlim, kp);
}

/* The shipped setting: the drive does not outrun the joints (the ratio far
 * below its threshold; NaN on rigid joints), the energy within 0.5 % of the
 * rigid path's; but the joints' own motion dissipates 1.4 % of the drive's
 * mechanical work, above 2e-4: the rule flags it (pessimistically here: its
 * gap is 0.2 to 1.8 % over six targets and +2.6 % at k_p = 1e7, i.e. at the
 * 1 % level and not converged in k_p; docs/dynamics.md section 13b). */
static void test_shipped(void) {
  pom_dyn_metrics par, rig;
  check_true(run_3pss(&par, POM_JOINTS_PARASITIC, -1, -1) == POM_OK);
  check_true(run_3pss(&rig, POM_JOINTS_RIGID, -1, -1) == POM_OK);
  check_true(isnan(rig.rigid_limit_ratio) && !pom_dyn_rigid_limit_exceeded(&rig));
  double gap = par.energy_total / rig.energy_total - 1.0;
  printf("shipped: ratio %.4g, energy gap %.4f\n", par.rigid_limit_ratio, gap);
  check_true(fabs(gap) < 0.01);
  /* measured 3.23e-3: omega_low = sqrt(1e6 / 29.3 g) = 5842 rad/s (the
   * platform on its central joint), T_E = 3.0 ms of saturated drive */
  check_true(par.rigid_limit_ratio > 1e-3 &&
             par.rigid_limit_ratio < 0.5 * POM_DYN_RIGID_LIMIT_WARN);
  printf("shipped: joint dissipation share %.4g\n", par.joint_dissipation_share);
  check_true(isnan(rig.joint_dissipation_share));
  check_true(par.joint_dissipation_share > 5e-3 && par.joint_dissipation_share < 5e-2);
  check_true(pom_dyn_rigid_limit_exceeded(&par));
}

/* voltage_limit_V = 1e5 across k_p = 1e6 ... 1e10: the ratio falls as 1/k_p
 * (T_E, the ~20 us kick of the unsaturated loop, hardly moves), flags every
 * k_p whose energy is more than 1 % off the rigid one and clears the one
 * that is within it; where it is of order 1 or below, the gap falls with it. */
static void test_fast_drive(void) {
  pom_dyn_metrics rig;
  check_true(run_3pss(&rig, POM_JOINTS_RIGID, 1e5, -1) == POM_OK);
  check_rel(rig.energy_total, 261.586, 1e-4); /* the independent reference */
  const double kp[5] = {1e6, 1e7, 1e8, 1e9, 1e10};
  double ratio[5], gap[5];
  for (int i = 0; i < 5; ++i) {
    pom_dyn_metrics par;
    check_true(run_3pss(&par, POM_JOINTS_PARASITIC, 1e5, kp[i]) == POM_OK);
    ratio[i] = par.rigid_limit_ratio;
    gap[i] = fabs(par.energy_total / rig.energy_total - 1.0);
    printf("k_p %.0e: ratio %.4g, energy gap %.4f, deflection %.3g m\n", kp[i], ratio[i], gap[i],
           par.max_deflection);
    if (ratio[i] > POM_DYN_RIGID_LIMIT_WARN) check_true(pom_dyn_rigid_limit_exceeded(&par));
    /* the classification the warning makes: flagged <=> the energy is off */
    if (gap[i] > 0.01) check_true(pom_dyn_rigid_limit_exceeded(&par));
    if (ratio[i] < POM_DYN_RIGID_LIMIT_WARN) check_true(gap[i] < 0.01);
  }
  /* the case: 48 % less energy, flagged by far (measured 88.7) */
  check_true(gap[0] > 0.4 && ratio[0] > 10.0);
  for (int i = 1; i < 5; ++i) {
    /* ~1/k_p: a factor 10 per decade within a factor 4 (T_E moves with k_p:
     * 18, 18, 15, 25, 24 us measured) */
    check_true(ratio[i] < ratio[i - 1] / 2.5 && ratio[i] > ratio[i - 1] / 40.0);
    /* from a ratio of 1 down the gap closes as the ratio does; above it the
     * kick is over before any joint loads and the gap stays ~50 % (48, 48,
     * 51 % at ratio 89, 9.2, 1.3) */
    if (ratio[i - 1] < 2.0) check_true(gap[i] < gap[i - 1]);
    if (ratio[i] > 1.0) check_true(gap[i] > 0.4);
  }
  check_true(ratio[4] < POM_DYN_RIGID_LIMIT_WARN && gap[4] < 0.01);
}

/* configs/3sps.cfg at its 24 V across k_p = 1e6 ... 1e10: the drive is
 * slow (ratio <= 2.1e-3, never flagged by it) but the 448 g cylinders bounce
 * on their pivot springs, in the coordinate the loop senses; the energy is
 * +26, +7.9, +2.5, +0.5, +0.07 % off the rigid one, the share 9.0e-2,
 * 7.4e-3, 6.7e-4, 7.5e-5, 4.0e-5 (about 1/k_p down to the floor of the
 * angular joints, which keep 1e6 N m/rad). The rule flags every case more
 * than 1 % off and none within it: the threshold 2e-4 lies a factor 3.3
 * below the 2.5 % case and 2.7 above the 0.5 % one. On the old rule (the
 * ratio alone) the first three are not flagged. */
static void test_bouncing_joints(void) {
  pom_dyn_metrics rig;
  check_true(run_cfg("3sps.cfg", &rig, POM_JOINTS_RIGID, -1, -1) == POM_OK);
  check_true(isnan(rig.joint_dissipation_share));
  const double kp[5] = {1e6, 1e7, 1e8, 1e9, 1e10};
  double share[5], gap[5];
  for (int i = 0; i < 5; ++i) {
    pom_dyn_metrics par;
    check_true(run_cfg("3sps.cfg", &par, POM_JOINTS_PARASITIC, -1, kp[i]) == POM_OK);
    share[i] = par.joint_dissipation_share;
    gap[i] = fabs(par.energy_total / rig.energy_total - 1.0);
    printf("3S-P-S/S k_p %.0e: ratio %.3g, share %.3g, energy gap %.4f\n", kp[i],
           par.rigid_limit_ratio, share[i], gap[i]);
    /* the drive never outruns these joints: the ratio alone misses them */
    check_true(par.rigid_limit_ratio < POM_DYN_RIGID_LIMIT_WARN);
    if (gap[i] > 0.01) check_true(pom_dyn_rigid_limit_exceeded(&par));
    if (gap[i] < 0.01) check_true(!pom_dyn_rigid_limit_exceeded(&par));
    /* the envelope behind the threshold: gap <= 2.5 sqrt(share) (measured
     * at most 0.97 sqrt(share) here, 2.5 over the 45 cases of section 13b) */
    check_true(gap[i] <= 2.5 * sqrt(share[i]));
  }
  /* the case: +26 %, share 450 times the threshold */
  check_true(gap[0] > 0.2 && share[0] > 100 * POM_DYN_JOINT_SHARE_WARN);
  /* the margins of the threshold (a factor >= 2.5 each side) */
  check_true(share[2] > 2.5 * POM_DYN_JOINT_SHARE_WARN && gap[2] > 0.015);
  check_true(share[3] < POM_DYN_JOINT_SHARE_WARN / 2.5 && gap[3] < 0.008);
  /* the rigid limit: the share falls about as 1/k_p (a factor 6 to 14 per
   * decade) until the angular joints' floor */
  for (int i = 1; i < 4; ++i)
    check_true(share[i] < share[i - 1] / 6.0 && share[i] > share[i - 1] / 14.0);
}

int main(void) {
  test_shipped();
  test_fast_drive();
  test_bouncing_joints();
  return check_summary("test_dyn_validity");
}
