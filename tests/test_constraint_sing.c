/* test_constraint_sing.c - the three singularities told apart
 * (docs/kinematics-tables.md 3.1), and the wrists without a central joint
 * (docs/catalog.md C13 3-RUU, C14 3-UPU):
 *  - each limb's constraint wrench, computed from its five joint screws at
 *    the pose (pom_limb_constraint), is a force through O: offset < 1e-12 of
 *    the scale at 200 random poses (the layout of section 2.5 makes it so
 *    at every pose, not only at home);
 *  - the smallest singular value of the unit forces against docs/catalog.md's
 *    independent figures (scripts/catalog_home.py's screw theory): 1.0000 at
 *    home, 0.8502 (C13) and 0.8618 (C14) at the rotation vector
 *    (0.25, -0.15, 0.2) rad, to the printed 5e-5;
 *  - the input-output relation is the 3-RRR's (C13, configs/3rrr.cfg's
 *    angles) and the 3-S-P-S's (C14, configs/3sps.cfg's points): q and J
 *    equal the hand-coded types' to 1e-12 at 200 random poses;
 *  - a constraint-singular pose (found by bisection of det of the forces
 *    along a rotation from home) is flagged "constraint", a pose halfway to
 *    it is not flagged at all; a geometry constraint-singular at home (the
 *    3-UPU with vertical limbs: every n_i horizontal) is refused;
 *  - a parallel singularity of the 3P-S-S/S (central joint: no constraint
 *    wrenches) is flagged "parallel" only; a limb that assembles without
 *    its Jacobian row is flagged "serial" with the pose unreachable. */
#include "check.h"
#include "pom_arch.h"
#include "pom_arch_file.h"
#include "pom_config.h"
#include "pom_kinematics.h"
#include "pom_limb.h"
#include "pom_math.h"
#include "pom_rng.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static int load(const char *rel, pom_kin_arch *arch) {
  char path[512];
  snprintf(path, sizeof path, "%s/configs/%s", POM_SOURCE_DIR, rel);
  pom_cfg *cfg = NULL;
  pom_error err;
  pom_error_clear(&err);
  int ok = pom_cfg_load(&cfg, path, &err) == POM_OK && pom_kin_arch_load(arch, cfg, &err) == POM_OK;
  if (!ok) printf("loading %s: %s\n", path, err.message);
  pom_cfg_destroy(cfg);
  return ok;
}

static void rotvec(double R[9], double x, double y, double z) {
  double v[3] = {x, y, z}, n = pom_v3_norm(v);
  if (n == 0.0) {
    pom_m3_identity(R);
    return;
  }
  pom_v3_scale(v, 1.0 / n, v);
  pom_m3_axis_angle(R, v, n);
}

static void random_rotation(pom_rng *g, double R[9], double half) {
  rotvec(R, pom_rng_range(g, -half, half), pom_rng_range(g, -half, half),
         pom_rng_range(g, -half, half));
}

/* the wrenches at random poses are forces through O; docs/catalog.md's figures */
static void wrenches(const pom_kin_arch *a, double sv_off_doc, pom_rng *g) {
  pom_kin_pose p;
  double R[9], worst = 0.0;
  rotvec(R, 0.0, 0.0, 0.0);
  pom_kin_pose_evaluate(a, R, &p, NULL);
  check_true(p.n_constraint == 3 && p.singular == 0);
  check_abs(p.constraint_sv, 1.0, 1e-12);
  rotvec(R, 0.25, -0.15, 0.2);
  pom_kin_pose_evaluate(a, R, &p, NULL);
  check_abs(p.constraint_sv, sv_off_doc, 5e-5);
  const double sv_off = p.constraint_sv;
  int n = 0;
  for (int k = 0; k < 1000 && n < 200; ++k) {
    random_rotation(g, R, 0.4);
    pom_kin_pose_evaluate(a, R, &p, NULL);
    if (!p.reachable) continue;
    ++n;
    check_true(p.n_constraint == 3);
    worst = fmax(worst, p.constraint_offset);
  }
  check_true(n == 200);
  check_abs(worst, 0.0, 1e-12 * a->design.scale);
  printf("%s: constraint forces' smallest singular value 1 at home, %.6f at (0.25, -0.15, 0.2) "
         "rad (docs %.4f); force lines from O: worst %.2g m at %d poses\n",
         a->name, sv_off, sv_off_doc, worst, n);
}

/* q and J of a against the hand-coded h at random poses */
static void same_io(const pom_kin_arch *a, const pom_kin_arch *h, pom_rng *g) {
  double worst = 0.0, scale = 0.0;
  int n = 0;
  for (int k = 0; k < 1000 && n < 200; ++k) {
    double R[9], qa[3], qh[3], Ja[9], Jh[9];
    random_rotation(g, R, 0.4);
    if (pom_kin_inverse_jacobian(a, R, qa, Ja, NULL) != POM_OK) continue;
    if (!check_true(pom_kin_inverse_jacobian(h, R, qh, Jh, NULL) == POM_OK)) continue;
    ++n;
    for (int i = 0; i < 3; ++i)
      worst = fmax(worst, fabs(qa[i] - qh[i]));
    for (int i = 0; i < 9; ++i) {
      worst = fmax(worst, fabs(Ja[i] - Jh[i]));
      scale = fmax(scale, fabs(Jh[i]));
    }
  }
  check_true(n == 200);
  check_abs(worst, 0.0, 1e-12 * scale);
  printf("%s vs %s: q and J equal to %.2g (max |J| %.3g) at %d poses\n", a->name, h->name, worst,
         scale, n);
}

/* det of the unit constraint forces at R(t) = Rot(k, t), NaN unreachable */
static double force_det(const pom_kin_arch *a, const double k[3], double t) {
  double R[9], F[9], M[9];
  pom_m3_axis_angle(R, k, t);
  if (a->type->constraint(a, R, F, M) != 3) return NAN;
  return pom_m3_det(F);
}

/* A constraint-singular pose along a rotation from home, by bisection: the
 * torsion axis, then random axes (seeded) until the forces' det changes
 * sign before the limbs stop assembling. */
static void constraint_pose(const pom_kin_arch *a, pom_rng *g) {
  for (int ax = 0; ax < 200; ++ax) {
    double k[3] = {0.0, 0.0, 1.0};
    if (ax > 0) {
      pom_v3_set(k, pom_rng_range(g, -1, 1), pom_rng_range(g, -1, 1), pom_rng_range(g, -1, 1));
      if (!(pom_v3_normalize(k, k) > 0.1)) continue;
    }
    double t0 = 0.0, d0 = force_det(a, k, 0.0);
    for (double t = 0.01; t < 3.1; t += 0.01) {
      double d = force_det(a, k, t);
      if (!isfinite(d)) break;
      if ((d > 0.0) == (d0 > 0.0)) {
        t0 = t;
        continue;
      }
      double lo = t0, hi = t;
      for (int it = 0; it < 80; ++it) {
        double mid = 0.5 * (lo + hi), dm = force_det(a, k, mid);
        if ((dm > 0.0) == (d0 > 0.0))
          lo = mid;
        else
          hi = mid;
      }
      double R[9], Rh[9];
      pom_kin_pose p, ph;
      pom_m3_axis_angle(R, k, lo);
      pom_m3_axis_angle(Rh, k, 0.5 * lo);
      pom_kin_pose_evaluate(a, R, &p, NULL);
      pom_kin_pose_evaluate(a, Rh, &ph, NULL);
      char sb[80];
      check_true(p.reachable && (p.singular & POM_KIN_SING_CONSTRAINT));
      check_true(ph.reachable && ph.singular == 0 && ph.constraint_sv > 0.1);
      printf("%s: constraint singularity at %.9f rad about (%.2f, %.2f, %.2f): constraint sv "
             "%.2g, dexterity %.2g, flagged: %s; halfway: constraint sv %.4f, flagged: %s\n",
             a->name, lo, k[0], k[1], k[2], p.constraint_sv, p.dexterity,
             pom_kin_singular_text(p.singular, p.serial_limbs, sb, sizeof sb), ph.constraint_sv,
             ph.singular ? "yes" : "none");
      return;
    }
  }
  check_true(0); /* no constraint singularity found along the axes */
  printf("%s: no constraint singularity found\n", a->name);
}

/* the 3-RUU with base and platform axes horizontal (beta = gamma = 90 deg):
 * every w_i = e_z, every d_i horizontal, refused at home */
static void ruu_singular_geometry(const pom_kin_arch *a) {
  const pom_kin_arch_type *t = a->type;
  pom_kin_design d = a->design;
  int n = 0;
  for (int k = 0; k < t->n_params; ++k)
    if (strcmp(t->params[k].key, "base_cone_deg") == 0 ||
        strcmp(t->params[k].key, "platform_cone_deg") == 0) {
      d.x[k] = 0.5 * POM_PI;
      ++n;
    }
  if (!check_true(n == 2)) return;
  pom_kin_arch b;
  pom_error err;
  pom_error_clear(&err);
  pom_status st = pom_kin_arch_from_design(&b, t, &d, &err);
  check_true(st == POM_ERR_ARG && strstr(err.message, "constraint") != NULL);
  printf("3-RUU with horizontal base and platform axes: %s\n", err.message);
}

/* the 3-UPU with vertical limbs: every n_i horizontal, refused at home */
static void singular_geometry(const pom_kin_arch *a) {
  const pom_kin_arch_type *t = a->type;
  pom_kin_design d = a->design;
  int lean = -1;
  for (int k = 0; k < t->n_params; ++k)
    if (strcmp(t->params[k].key, "limb_lean_deg") == 0) lean = k;
  if (!check_true(lean >= 0)) return;
  d.x[lean] = 0.0;
  pom_kin_arch b;
  pom_error err;
  pom_error_clear(&err);
  pom_status st = pom_kin_arch_from_design(&b, t, &d, &err);
  check_true(st == POM_ERR_ARG && strstr(err.message, "constraint") != NULL);
  printf("vertical 3-UPU limbs: %s\n", err.message);
}

/* a parallel singularity of a wrist with a central joint: "parallel" only */
static void parallel_only(const pom_kin_arch *a) {
  const double k[3] = {0.0, 0.0, 1.0};
  double lo = 0.0, hi = -1.0;
  for (double t = 0.02; t < 3.0; t += 0.02) {
    double R[9], J[9], q[3];
    pom_m3_axis_angle(R, k, t);
    if (pom_kin_inverse_jacobian(a, R, q, J, NULL) != POM_OK) break;
    if (pom_m3_det(J) * a->home_det_sign <= 0.0) {
      hi = t;
      break;
    }
    lo = t;
  }
  if (!check_true(hi > 0.0)) return;
  for (int it = 0; it < 80; ++it) {
    double mid = 0.5 * (lo + hi), R[9], J[9], q[3];
    pom_m3_axis_angle(R, k, mid);
    if (pom_kin_inverse_jacobian(a, R, q, J, NULL) == POM_OK &&
        pom_m3_det(J) * a->home_det_sign > 0.0)
      lo = mid;
    else
      hi = mid;
  }
  double R[9];
  pom_kin_pose p;
  pom_m3_axis_angle(R, k, lo);
  pom_kin_pose_evaluate(a, R, &p, NULL);
  check_true(p.reachable && p.singular == POM_KIN_SING_PARALLEL && p.n_constraint == 0);
  printf("%s: parallel singularity at torsion %.9f rad: dexterity %.2g, flagged parallel only\n",
         a->name, lo, p.dexterity);
}

/* a limb that assembles without its row: "serial" (a type whose limb 2
 * says so at every pose, built on the 3-RUU's) */
static int fake_limb(const pom_kin_arch *arch, int i, const double R[9], double *q, double row[3],
                     double *tr) {
  if (i == 1 && row) return 0;
  return pom_limb_ik(arch, i, R, q, row, tr);
}

static void serial(const pom_kin_arch *a) {
  pom_kin_arch_type t = *a->type;
  t.limb = fake_limb;
  pom_kin_arch b = *a;
  b.type = &t;
  double R[9];
  pom_kin_pose p;
  pom_m3_identity(R);
  check_true(pom_kin_pose_evaluate(&b, R, &p, NULL) == POM_ERR_UNREACHABLE);
  check_true(!p.reachable && p.unreachable_limb == 1 && p.singular == POM_KIN_SING_SERIAL &&
             p.serial_limbs == 2u);
  pom_kin_pose_evaluate(a, R, &p, NULL);
  check_true(p.singular == 0);
}

int main(void) {
  pom_error err;
  pom_error_clear(&err);
  if (!check_true(pom_arch_files_register_all(&err) == POM_OK)) printf("%s\n", err.message);
  pom_rng rng;
  pom_rng_seed(&rng, 27, 3);
  static pom_kin_arch ruu, upu, rrr, sps, pss;
  if (!check_true(load("catalog/3ruu_wrist.cfg", &ruu) && load("catalog/3upu_wrist.cfg", &upu) &&
                  load("3rrr.cfg", &rrr) && load("3sps.cfg", &sps) && load("3pss.cfg", &pss)))
    return check_summary("test_constraint_sing");
  check_true(ruu.type->constraint != NULL && pss.type->constraint == NULL);
  wrenches(&ruu, 0.8502, &rng);
  wrenches(&upu, 0.8618, &rng);
  same_io(&ruu, &rrr, &rng);
  same_io(&upu, &sps, &rng);
  constraint_pose(&upu, &rng);
  singular_geometry(&upu);
  ruu_singular_geometry(&ruu);
  parallel_only(&pss);
  serial(&ruu);
  return check_summary("test_constraint_sing");
}
