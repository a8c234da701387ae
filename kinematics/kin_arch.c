/* kin_arch.c - an architecture instance from a config: the type from the
 * registry, its geometry from explicit points or dimensionless design
 * parameters plus a scale, and its limits (docs/kinematics.md 1-3,
 * docs/extending.md). Nothing here knows a particular architecture. */
#include "pom_kinematics.h"

#include "kin_internal.h"
#include "pom_math.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

void pom_kin_limits_defaults(pom_kin_arch *arch) {
  const pom_kin_arch_type *t = arch->type;
  arch->stroke = t ? t->default_stroke : 0.012;
  for (int k = 0; k < POM_KIN_LIM_KINDS; ++k)
    arch->limit_bound[k] = (t && k > 0 && t->limits[k].name) ? t->limits[k].def : 0.0;
}

/* ---- design parameters -> geometry ---------------------------------------- */
pom_status pom_kin_arch_from_design(pom_kin_arch *arch, const pom_kin_arch_type *type,
                                    const pom_kin_design *d, pom_error *err) {
  memset(arch, 0, sizeof *arch);
  if (!type) POM_FAIL(err, POM_ERR_ARG, "design: no architecture type");
  arch->type = type;
  arch->central_joint = !type->optional_central_joint;
  snprintf(arch->name, sizeof arch->name, "%s", type->name);
  pom_kin_limits_defaults(arch);
  if (!(d->scale > 0.0 && d->scale < INFINITY))
    POM_FAIL(err, POM_ERR_ARG, "design: the scale (%g m, %s) must be positive", d->scale,
             type->scale_key);
  for (int k = 0; k < type->n_params; ++k)
    if (!isfinite(d->x[k]))
      POM_FAIL(err, POM_ERR_ARG, "design: %s is not finite", type->params[k].key);
  arch->design = *d;
  arch->has_design = 1;
  POM_TRY(type->from_design(arch, d, err));
  return pom_kin_arch_finish(arch, err);
}

/* ---- checks and derived fields -------------------------------------------- */
pom_status pom_kin_arch_finish(pom_kin_arch *arch, pom_error *err) {
  if (!arch->type) POM_FAIL(err, POM_ERR_ARG, "architecture without a type");
  POM_TRY(arch->type->finish(arch, err));
  double J[9], q[3];
  pom_error e2;
  pom_error_clear(&e2);
  pom_status st =
      pom_kin_inverse_jacobian(arch, (const double[9]){1, 0, 0, 0, 1, 0, 0, 0, 1}, q, J, &e2);
  if (st != POM_OK) POM_FAIL(err, POM_ERR_ARG, "home pose: %s", e2.message);
  double det = pom_m3_det(J), sv[3];
  pom_kin_dexterity(J, sv, NULL, NULL);
  if (!(sv[2] > POM_KIN_HOME_MIN_COS * sv[0]))
    POM_FAIL(err, POM_ERR_ARG,
             "the Jacobian is singular at home (singular values %g, %g, %g %s/rad)", sv[0], sv[1],
             sv[2], pom_act_kind_desc(arch->type->actuator)->si);
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

static pom_status load_scale(const pom_kin_arch_type *t, const pom_cfg *cfg, int required,
                             double *scale, pom_error *err) {
  char key[128];
  snprintf(key, sizeof key, "geometry.%s", t->scale_key);
  if (required) return pom_cfg_real(cfg, key, 1e-3, 0.1, 1e4, scale, err);
  return pom_cfg_real_opt(cfg, key, 1e-3, 0.1, 1e4, 0.0, scale, err);
}

static pom_status load_design(pom_kin_design *d, const pom_kin_arch_type *t, const pom_cfg *cfg,
                              pom_error *err) {
  char key[128];
  memset(d, 0, sizeof *d);
  POM_TRY(load_scale(t, cfg, 1, &d->scale, err));
  for (int k = 0; k < t->n_params; ++k) {
    const pom_kin_param_desc *p = &t->params[k];
    snprintf(key, sizeof key, "geometry.%s", p->key);
    if (p->optional) {
      POM_TRY(pom_cfg_real_opt(cfg, key, p->to_si, p->lo, p->hi, p->def * p->to_si, &d->x[k], err));
    } else {
      POM_TRY(pom_cfg_real(cfg, key, p->to_si, p->lo, p->hi, &d->x[k], err));
    }
    double v = d->x[k] / p->to_si;
    if (p->integer && v != floor(v))
      return pom_cfg_error(cfg, key, NULL, err,
                           "expected a whole number in [%g, %g], not a fraction", p->lo, p->hi);
  }
  return POM_OK;
}

static pom_status load_points(const char *key, double pts[3][3], const pom_cfg *cfg,
                              pom_error *err) {
  char k[128];
  if (pom_cfg_has(cfg, key) && pom_cfg_length(cfg, key) != 3)
    return pom_cfg_error(cfg, key, NULL, err, "expected a list of 3 points ( [x,y,z], ... )");
  for (int i = 0; i < 3; ++i) {
    snprintf(k, sizeof k, "%s.[%d]", key, i);
    if (!pom_cfg_has(cfg, k))
      return pom_cfg_error(cfg, key, NULL, err,
                           "missing: expected a list of 3 points ( [x,y,z], [x,y,z], [x,y,z] )");
    POM_TRY(pom_cfg_reals(cfg, k, 3, 1.0, -1e3, 1e3, pts[i], err));
  }
  return POM_OK;
}

/* The names of the registered architectures, "3PSS, 3SPS, 3RRR". */
static void type_list(char *buf, size_t cap) {
  size_t used = 0;
  buf[0] = '\0';
  for (int k = 0; k < pom_kin_arch_type_count(); ++k) {
    int w = snprintf(buf + used, cap - used, "%s%s", k ? ", " : "", pom_kin_arch_type_at(k)->name);
    if (w < 0 || (size_t)w >= cap - used) return;
    used += (size_t)w;
  }
}

pom_status pom_kin_arch_load(pom_kin_arch *arch, const pom_cfg *cfg, pom_error *err) {
  static const char *const modes[] = {"parameters", "points", NULL};
  int mode = 0;
  char tname[64], name[64], key[128];
  pom_error sub;
  POM_TRY(pom_cfg_string(cfg, "architecture", tname, sizeof tname, err));
  const pom_kin_arch_type *type = pom_kin_arch_type_find(tname);
  if (!type) {
    char list[256], quoted[80];
    type_list(list, sizeof list);
    snprintf(quoted, sizeof quoted, "\"%s\"", tname);
    return pom_cfg_error(cfg, "architecture", quoted, err,
                         "unknown architecture; registered: %s (pomlab model "
                         "--list-architectures)",
                         list);
  }
  POM_TRY(pom_cfg_string_opt(cfg, "name", type->name, name, sizeof name, err));
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
    /* a type described by a file has its design parameters only */
    if (type->n_points == 0)
      return pom_cfg_error(cfg, "geometry.mode", NULL, err,
                           "architecture %s has no points form: give its design parameters "
                           "(mode = \"parameters\")",
                           type->name);
    memset(arch, 0, sizeof *arch);
    arch->type = type;
    arch->central_joint = !type->optional_central_joint;
    for (int k = 0; k < type->n_points; ++k) {
      const pom_kin_points_desc *pd = &type->points[k];
      double(*pts)[3] = (double(*)[3])(void *)((char *)arch->data + pd->offset);
      snprintf(key, sizeof key, "geometry.%s", pd->key);
      if (pd->optional && !pom_cfg_has(cfg, key)) continue;
      POM_TRY(load_points(key, pts, cfg, err));
    }
    /* the scale is optional here: it sizes the bodies of types whose
     * kinematics are angles only (the 3-RRR link radius) */
    POM_TRY(load_scale(type, cfg, 0, &arch->design.scale, err));
    pom_kin_limits_defaults(arch);
    if (pom_kin_arch_finish(arch, &sub) != POM_OK)
      return pom_cfg_error(cfg, "geometry", NULL, err, "degenerate geometry: %s", sub.message);
  }
  snprintf(arch->name, sizeof arch->name, "%s", name);
  /* a type whose central joint is a modelling choice reads it (the others'
   * joint O is their own: the key is then unknown) */
  if (type->optional_central_joint)
    POM_TRY(pom_cfg_bool_opt(cfg, "geometry.central_joint", 0, &arch->central_joint, err));

  /* limits (group optional, every key optional) */
  const pom_act_desc *u = pom_act_kind_desc(type->actuator);
  char stroke_key[64];
  const char *known[POM_KIN_LIM_KINDS + 1];
  int nk = 0;
  snprintf(stroke_key, sizeof stroke_key, "%s%s", u->range_word, u->key_suffix);
  known[nk++] = stroke_key;
  for (int k = 1; k < POM_KIN_LIM_KINDS; ++k)
    if (type->limits[k].name) known[nk++] = type->limits[k].key;
  known[nk] = NULL;
  POM_TRY(pom_kin_require_known_key(cfg, "limits", known, err));
  snprintf(key, sizeof key, "limits.%s", stroke_key);
  double to_si = 1.0 / u->to_display;
  POM_TRY(pom_cfg_real_opt(cfg, key, to_si, 0.01, u->range_max, arch->stroke, &arch->stroke, err));
  for (int k = 1; k < POM_KIN_LIM_KINDS; ++k) {
    const pom_kin_limit_desc *ld = &type->limits[k];
    if (!ld->name) continue;
    snprintf(key, sizeof key, "limits.%s", ld->key);
    POM_TRY(pom_cfg_real_opt(cfg, key, 1.0 / ld->to_display, ld->lo, ld->hi, arch->limit_bound[k],
                             &arch->limit_bound[k], err));
  }
  return POM_OK;
}

void pom_kin_local_direction(double out[3], const double er[3], const double et[3], double lean,
                             double azimuth) {
  double s = sin(lean);
  for (int k = 0; k < 3; ++k)
    out[k] = s * (cos(azimuth) * er[k] + sin(azimuth) * et[k]);
  out[2] += cos(lean);
}

const double *pom_kin_arch_points(const pom_kin_arch *arch, const char *key) {
  if (!arch || !arch->type || !key) return NULL;
  for (int k = 0; k < arch->type->n_points; ++k)
    if (strcmp(arch->type->points[k].key, key) == 0)
      return (const double *)(const void *)((const char *)arch->data +
                                            arch->type->points[k].offset);
  return NULL;
}

/* ---- config groups ------------------------------------------------------------ */
/* What pom_kin_arch_load reads (with the model's `name`), and with
 * pom_kin_inertia_load. */
static const char *const arch_groups[] = {"name", "architecture", "geometry", "limits", NULL};
static const char *const model_groups[] = {"name",   "architecture", "geometry",
                                           "limits", "inertia",      NULL};

const char *const *pom_kin_arch_groups(void) {
  return arch_groups;
}

const char *const *pom_kin_model_groups(void) {
  return model_groups;
}
