/* kin_arch.c - architecture geometry from a config: explicit points or
 * dimensionless design parameters plus a scale (docs/kinematics.md 1-3). */
#include "pom_kinematics.h"

#include "kin_internal.h"
#include "pom_math.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

const char *pom_kin_arch_name(pom_arch_type type) {
  return type == POM_ARCH_3PSS ? "3PSS" : type == POM_ARCH_3SPS ? "3SPS" : "?";
}

void pom_kin_limits_defaults(pom_kin_arch *arch) {
  arch->stroke = 0.012;
  arch->cone_base_max = 0.5 * POM_PI;
  arch->cone_platform_max = 0.5 * POM_PI;
  arch->min_limb_distance = 0.0;
}

/* ---- design parameters -> points ------------------------------------------ */
/* Unit vector sin(lean)(cos(az) e_r + sin(az) e_t) + cos(lean) e_z of limb
 * frame (e_r, e_t). */
static void local_direction(double out[3], const double er[3], const double et[3], double lean,
                            double azimuth) {
  double s = sin(lean);
  for (int k = 0; k < 3; ++k)
    out[k] = s * (cos(azimuth) * er[k] + sin(azimuth) * et[k]);
  out[2] += cos(lean);
}

pom_status pom_kin_arch_from_design(pom_kin_arch *arch, pom_arch_type type, const pom_kin_design *d,
                                    pom_error *err) {
  memset(arch, 0, sizeof *arch);
  arch->type = type;
  snprintf(arch->name, sizeof arch->name, "%s", pom_kin_arch_name(type));
  pom_kin_limits_defaults(arch);
  if (!(d->scale > 0.0) || !(d->limb_length > 0.0))
    POM_FAIL(err, POM_ERR_ARG, "design: scale (%g m) and limb_length (%g) must be positive",
             d->scale, d->limb_length);
  const double r = d->scale;
  for (int i = 0; i < 3; ++i) {
    double phi = d->first_azimuth + 2.0 * POM_PI * i / 3.0;
    double er[3] = {cos(phi), sin(phi), 0.0}, et[3] = {-sin(phi), cos(phi), 0.0};
    double P[3] = {r * er[0], r * er[1], r * d->platform_height};
    double u[3];
    local_direction(u, er, et, d->limb_lean, d->limb_azimuth);
    pom_v3_copy(arch->platform_point[i], P);
    if (type == POM_ARCH_3PSS) {
      double L = r * d->limb_length;
      arch->link_length[i] = L;
      pom_v3_axpy(arch->slider_mid[i], P, -L, u); /* B = C - L l */
      local_direction(arch->slider_axis[i], er, et, d->actuator_tilt, d->actuator_azimuth);
    } else {
      double L0 = r * d->limb_length;
      arch->limb_length_mid[i] = L0;
      pom_v3_axpy(arch->base_point[i], P, -L0, u); /* A = B - L0 s */
      /* First U-joint axis: horizontal, perpendicular to the limb's horizontal
       * part, = unit(e_z x s) whenever the limb is not vertical. */
      for (int k = 0; k < 3; ++k)
        arch->ujoint_axis[i][k] = cos(d->limb_azimuth) * et[k] - sin(d->limb_azimuth) * er[k];
    }
  }
  arch->design = *d;
  arch->has_design = 1;
  return pom_kin_arch_finish(arch, err);
}

/* ---- checks and derived fields -------------------------------------------- */
pom_status pom_kin_arch_finish(pom_kin_arch *arch, pom_error *err) {
  if (arch->type != POM_ARCH_3PSS && arch->type != POM_ARCH_3SPS)
    POM_FAIL(err, POM_ERR_ARG, "unknown architecture type %d", (int)arch->type);
  for (int i = 0; i < 3; ++i) {
    const double *P = arch->platform_point[i];
    double h = hypot(P[0], P[1]);
    if (!(h > 0.0)) POM_FAIL(err, POM_ERR_ARG, "limb %d: platform point lies on the z axis", i + 1);
    pom_v3_set(arch->radial_dir[i], P[0] / h, P[1] / h, 0.0);
    double l[3];
    if (arch->type == POM_ARCH_3PSS) {
      double n = pom_v3_normalize(arch->slider_axis[i], arch->slider_axis[i]);
      if (!(n > 0.0)) POM_FAIL(err, POM_ERR_ARG, "limb %d: slider axis has zero length", i + 1);
      pom_v3_sub(l, P, arch->slider_mid[i]);
      double L = pom_v3_normalize(arch->limb_dir_home[i], l);
      if (!(L > 0.0))
        POM_FAIL(err, POM_ERR_ARG, "limb %d: slider point B coincides with platform point C",
                 i + 1);
      arch->link_length[i] = L;
      double c = pom_v3_dot(arch->limb_dir_home[i], arch->slider_axis[i]);
      /* l.d = 0 is the IK singularity (the two IK roots meet): no home branch. */
      if (fabs(c) < POM_KIN_HOME_MIN_COS)
        POM_FAIL(err, POM_ERR_ARG,
                 "limb %d: link is perpendicular to its slider axis at home (cos = %.3g): "
                 "the home pose is singular",
                 i + 1, c);
      arch->branch_sign[i] = c > 0.0 ? 1.0 : -1.0;
    } else {
      pom_v3_sub(l, P, arch->base_point[i]);
      double L0 = pom_v3_normalize(arch->limb_dir_home[i], l);
      if (!(L0 > 0.0))
        POM_FAIL(err, POM_ERR_ARG, "limb %d: ground point A coincides with platform point B",
                 i + 1);
      arch->limb_length_mid[i] = L0;
      /* U-joint axis: made perpendicular to the limb (Gram-Schmidt). */
      double *a = arch->ujoint_axis[i];
      pom_v3_axpy(a, a, -pom_v3_dot(a, arch->limb_dir_home[i]), arch->limb_dir_home[i]);
      double n = pom_v3_normalize(a, a);
      if (!(n > POM_KIN_HOME_MIN_COS))
        POM_FAIL(err, POM_ERR_ARG,
                 "limb %d: U-joint axis is zero or parallel to the limb (a vertical limb needs "
                 "explicit geometry.ujoint_axes)",
                 i + 1);
      arch->branch_sign[i] = 1.0;
    }
  }
  double J[9], q[3];
  pom_error e2;
  pom_error_clear(&e2);
  pom_status st =
      pom_kin_inverse_jacobian(arch, (const double[9]){1, 0, 0, 0, 1, 0, 0, 0, 1}, q, J, &e2);
  if (st != POM_OK) POM_FAIL(err, POM_ERR_ARG, "home pose: %s", e2.message);
  double det = pom_m3_det(J), sv[3];
  pom_kin_dexterity(J, sv, NULL, NULL);
  if (!(sv[2] > POM_KIN_HOME_MIN_COS * sv[0]))
    POM_FAIL(err, POM_ERR_ARG, "the Jacobian is singular at home (singular values %g, %g, %g m)",
             sv[0], sv[1], sv[2]);
  arch->home_det_sign = det > 0.0 ? 1.0 : -1.0;
  return POM_OK;
}

/* ---- config --------------------------------------------------------------- */
pom_status pom_kin_require_known_key(const pom_cfg *cfg, const char *group,
                                     const char *const known[], pom_error *err) {
  if (!pom_cfg_has(cfg, group)) return POM_OK;
  char key[256], list[512] = "";
  size_t used = 0;
  for (int k = 0; known[k]; ++k) {
    snprintf(key, sizeof key, "%s.%s", group, known[k]);
    if (pom_cfg_has(cfg, key)) return POM_OK;
    int w = snprintf(list + used, sizeof list - used, "%s%s", k ? ", " : "", known[k]);
    if (w > 0 && (size_t)w < sizeof list - used) used += (size_t)w;
  }
  return pom_cfg_error(cfg, group, NULL, err,
                       "holds no known key (unknown or misspelt keys?); expected some of: %s",
                       list);
}

static pom_status load_design(pom_kin_design *d, pom_arch_type type, const pom_cfg *cfg,
                              pom_error *err) {
  memset(d, 0, sizeof *d);
  POM_TRY(pom_cfg_real(cfg, "geometry.platform_radius_mm", 1e-3, 0.1, 1e4, &d->scale, err));
  POM_TRY(pom_cfg_real_opt(cfg, "geometry.first_azimuth_deg", POM_DEG, -360.0, 360.0, 0.5 * POM_PI,
                           &d->first_azimuth, err));
  POM_TRY(pom_cfg_real_opt(cfg, "geometry.platform_height", 1.0, -10.0, 10.0, 0.0,
                           &d->platform_height, err));
  POM_TRY(pom_cfg_real(cfg, "geometry.limb_length", 1.0, 0.1, 100.0, &d->limb_length, err));
  POM_TRY(pom_cfg_real(cfg, "geometry.limb_lean_deg", POM_DEG, 0.0, 180.0, &d->limb_lean, err));
  POM_TRY(pom_cfg_real(cfg, "geometry.limb_azimuth_deg", POM_DEG, -360.0, 360.0, &d->limb_azimuth,
                       err));
  if (type == POM_ARCH_3PSS) {
    POM_TRY(pom_cfg_real_opt(cfg, "geometry.actuator_tilt_deg", POM_DEG, 0.0, 180.0, 0.0,
                             &d->actuator_tilt, err));
    POM_TRY(pom_cfg_real_opt(cfg, "geometry.actuator_azimuth_deg", POM_DEG, -360.0, 360.0, 0.0,
                             &d->actuator_azimuth, err));
  }
  return POM_OK;
}

static pom_status load_points(pom_kin_arch *arch, const char *key, double pts[3][3], double to_si,
                              const pom_cfg *cfg, pom_error *err) {
  char k[128];
  if (pom_cfg_has(cfg, key) && pom_cfg_length(cfg, key) != 3)
    return pom_cfg_error(cfg, key, NULL, err, "expected a list of 3 points ( [x,y,z], ... )");
  (void)arch;
  for (int i = 0; i < 3; ++i) {
    snprintf(k, sizeof k, "%s.[%d]", key, i);
    if (!pom_cfg_has(cfg, k))
      return pom_cfg_error(cfg, key, NULL, err,
                           "missing: expected a list of 3 points ( [x,y,z], [x,y,z], [x,y,z] )");
    POM_TRY(pom_cfg_reals(cfg, k, 3, to_si, -1e3, 1e3, pts[i], err));
  }
  return POM_OK;
}

pom_status pom_kin_arch_load(pom_kin_arch *arch, const pom_cfg *cfg, pom_error *err) {
  static const char *const archs[] = {"3PSS", "3SPS", NULL};
  static const char *const modes[] = {"parameters", "points", NULL};
  int a = 0, mode = 0;
  char name[64];
  pom_error sub;
  POM_TRY(pom_cfg_choice(cfg, "architecture", archs, &a, err));
  pom_arch_type type = a == 0 ? POM_ARCH_3PSS : POM_ARCH_3SPS;
  POM_TRY(pom_cfg_string_opt(cfg, "name", archs[a], name, sizeof name, err));
  if (!pom_cfg_has(cfg, "geometry"))
    return pom_cfg_error(cfg, "geometry", NULL, err, "missing: expected a group { mode = ...; }");
  POM_TRY(pom_cfg_choice(cfg, "geometry.mode", modes, &mode, err));
  pom_error_clear(&sub);
  if (mode == 0) {
    pom_kin_design d;
    POM_TRY(load_design(&d, type, cfg, err));
    if (pom_kin_arch_from_design(arch, type, &d, &sub) != POM_OK)
      return pom_cfg_error(cfg, "geometry", NULL, err, "degenerate design: %s", sub.message);
  } else {
    memset(arch, 0, sizeof *arch);
    arch->type = type;
    if (type == POM_ARCH_3PSS) {
      POM_TRY(load_points(arch, "geometry.platform_points_m", arch->platform_point, 1.0, cfg, err));
      POM_TRY(load_points(arch, "geometry.slider_points_m", arch->slider_mid, 1.0, cfg, err));
      POM_TRY(load_points(arch, "geometry.slider_axes", arch->slider_axis, 1.0, cfg, err));
    } else {
      POM_TRY(load_points(arch, "geometry.platform_points_m", arch->platform_point, 1.0, cfg, err));
      POM_TRY(load_points(arch, "geometry.base_points_m", arch->base_point, 1.0, cfg, err));
      if (pom_cfg_has(cfg, "geometry.ujoint_axes")) {
        POM_TRY(load_points(arch, "geometry.ujoint_axes", arch->ujoint_axis, 1.0, cfg, err));
      } else {
        /* default: unit(e_z x s) of the home limb direction s */
        for (int i = 0; i < 3; ++i) {
          double s[3], ez[3] = {0, 0, 1};
          pom_v3_sub(s, arch->platform_point[i], arch->base_point[i]);
          pom_v3_cross(arch->ujoint_axis[i], ez, s);
        }
      }
    }
    pom_kin_limits_defaults(arch);
    if (pom_kin_arch_finish(arch, &sub) != POM_OK)
      return pom_cfg_error(cfg, "geometry", NULL, err, "degenerate geometry: %s", sub.message);
  }
  snprintf(arch->name, sizeof arch->name, "%s", name);

  /* limits (group optional, every key optional) */
  static const char *const limit_keys[] = {"stroke_mm", "cone_base_max_deg",
                                           "cone_platform_max_deg", "min_limb_distance_mm", NULL};
  POM_TRY(pom_kin_require_known_key(cfg, "limits", limit_keys, err));
  POM_TRY(pom_cfg_real_opt(cfg, "limits.stroke_mm", 1e-3, 0.01, 1000.0, 0.012, &arch->stroke, err));
  POM_TRY(pom_cfg_real_opt(cfg, "limits.cone_base_max_deg", POM_DEG, 0.0, 180.0,
                           arch->cone_base_max, &arch->cone_base_max, err));
  POM_TRY(pom_cfg_real_opt(cfg, "limits.cone_platform_max_deg", POM_DEG, 0.0, 180.0,
                           arch->cone_platform_max, &arch->cone_platform_max, err));
  POM_TRY(pom_cfg_real_opt(cfg, "limits.min_limb_distance_mm", 1e-3, 0.0, 1e4,
                           arch->min_limb_distance, &arch->min_limb_distance, err));
  return POM_OK;
}
