/* test_arch_file.c - architecture files (docs/architecture-files.md): the
 * three catalog files carry the hand-coded types' descriptors (every field
 * of every parameter, limit kind, inertia group and value), and evaluated at
 * the shipped configs' designs and at random designs they reproduce the
 * hand-coded private geometry (kinematics/arch_3pss.c, arch_3sps.c,
 * arch_3rrr.c) to 1e-15 m or 1e-15 for unit axes: the same formulas in the
 * same order of operations, so the difference is a few ulps at most. Then
 * every kind of bad file: the message names file, line, key and value. */
#define _POSIX_C_SOURCE 200809L /* setenv */
#include "check.h"
#include "pom_arch.h"
#include "pom_arch_file.h"
#include "pom_config.h"
#include "pom_kinematics.h"
#include "pom_math.h"
#include "pom_rng.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <dirent.h>

static pom_arch_file *load_catalog(const char *file) {
  char path[512];
  pom_error err;
  pom_error_clear(&err);
  snprintf(path, sizeof path, "%s/catalog/%s", POM_SOURCE_DIR, file);
  pom_arch_file *f = NULL;
  if (pom_arch_file_load(&f, path, &err) != POM_OK) printf("loading %s: %s\n", path, err.message);
  check_true(f != NULL);
  return f;
}

/* ---- descriptors equal the hand-coded type's -------------------------------- */
static void same_descriptors(const pom_kin_arch_type *a, const pom_kin_arch_type *h) {
  check_true(a->actuator == h->actuator);
  check_true(strcmp(a->label, h->label) == 0);
  check_true(strcmp(a->scale_key, h->scale_key) == 0);
  check_true(strcmp(a->scale_meaning, h->scale_meaning) == 0);
  check_true(a->scale_sets_kinematics == h->scale_sets_kinematics);
  check_true(a->optional_central_joint == h->optional_central_joint);
  check_true(strcmp(a->unreachable, h->unreachable) == 0);
  check_rel(a->default_stroke, h->default_stroke, 1e-15);
  check_true(a->n_params == h->n_params);
  for (int k = 0; k < h->n_params && k < a->n_params; ++k) {
    const pom_kin_param_desc *p = &a->params[k], *q = &h->params[k];
    if (!check_true(strcmp(p->key, q->key) == 0)) printf("  %s != %s\n", p->key, q->key);
    check_true(strcmp(p->meaning, q->meaning) == 0);
    check_true(p->to_si == q->to_si && p->lo == q->lo && p->hi == q->hi);
    check_true(p->optional == q->optional && p->synth == q->synth && p->integer == q->integer);
    if (q->optional) check_true(p->def == q->def);
  }
  for (int k = 1; k < POM_KIN_LIM_KINDS; ++k) {
    const pom_kin_limit_desc *l = &a->limits[k], *m = &h->limits[k];
    check_true(!l->name == !m->name);
    if (!l->name || !m->name) continue;
    check_true(strcmp(l->name, m->name) == 0 && strcmp(l->key, m->key) == 0 &&
               strcmp(l->json, m->json) == 0 && strcmp(l->unit, m->unit) == 0);
    check_true(l->per_pair == m->per_pair && l->lower == m->lower && l->cls == m->cls);
    check_rel(l->to_display, m->to_display, 1e-15);
    check_true(l->lo == m->lo && l->hi == m->hi);
    check_abs(l->def, m->def, 1e-15);
  }
  check_true(a->n_inertia_bodies == h->n_inertia_bodies);
  for (int k = 0; k < h->n_inertia_bodies && k < a->n_inertia_bodies; ++k)
    check_true(strcmp(a->inertia_bodies[k].group, h->inertia_bodies[k].group) == 0 &&
               a->inertia_bodies[k].place == h->inertia_bodies[k].place);
  check_true(a->n_inertia_values == h->n_inertia_values);
  for (int k = 0; k < h->n_inertia_values && k < a->n_inertia_values; ++k) {
    const pom_kin_value_desc *v = &a->inertia_values[k], *w = &h->inertia_values[k];
    check_true(strcmp(v->key, w->key) == 0 && strcmp(v->meaning, w->meaning) == 0);
    check_true(v->to_si == w->to_si && v->lo == w->lo && v->hi == w->hi);
    check_true(v->optional == w->optional && (!w->optional || v->def == w->def));
  }
}

/* ---- geometry equals the hand-coded type's ----------------------------------- */
static void close3(const double *got, const double *want, double tol, const char *what, int i) {
  for (int c = 0; c < 3; ++c)
    if (!check_abs(got[c], want[c], tol)) printf("  %s, limb %d, component %d\n", what, i + 1, c);
}

static void same_dir(pom_limb_dir got, int a, int b, const char *what) {
  if (!check_true(got.a == a && got.b == b))
    printf("  %s: {%d, %d}, want {%d, %d}\n", what, got.a, got.b, a, b);
}

/* The design-independent part of the table: the rules of arch_3pss.c,
 * arch_3sps.c, arch_3rrr.c written as pom_limb.h's fields. */
static void check_rules(const pom_limb_table *t, const char *name, double scale) {
  const pom_limb_body *b0 = &t->body[0], *b1 = &t->body[1];
  if (strcmp(name, "3PSS") == 0) {
    /* piston: CM from B along d, z = d; link: CM a fraction of B -> C, z = B -> C */
    check_true(strcmp(b0->name, "piston") == 0 && strcmp(b1->name, "link") == 0);
    check_true(b0->model == POM_LIMB_MASS_GROUP && b0->group == 0 && b0->place == 1);
    check_true(b0->cm_from == 0);
    same_dir(b0->cm_dir, 0, -1, "piston cm_dir");
    same_dir(b0->z_dir, 0, -1, "piston z");
    same_dir(b0->x_dir, -1, -1, "piston x");
    check_true(b1->model == POM_LIMB_MASS_GROUP && b1->group == 1 && b1->place == 2);
    same_dir(b1->cm_dir, 1, 2, "link cm_dir");
    same_dir(b1->z_dir, 1, 2, "link z");
    check_true(strcmp(t->joint_name[0], "P") == 0 && strcmp(t->joint_name[1], "B") == 0 &&
               strcmp(t->joint_name[2], "C") == 0);
    for (int k = 1; k <= 3; ++k)
      check_true(t->measure[k].a == 1 && t->measure[k].b == 2);
    check_true(t->measure[1].kind == POM_LIMB_MEASURE_CONE_FIXED &&
               t->measure[2].kind == POM_LIMB_MEASURE_CONE_PLATFORM &&
               t->measure[3].kind == POM_LIMB_MEASURE_DISTANCE);
    check_true(t->central == 1);
  } else if (strcmp(name, "3SPS") == 0) {
    /* cylinder: CM from A toward B; piston: from B toward A; both z = A -> B, x = U axis 1 */
    check_true(strcmp(b0->name, "cylinder") == 0 && strcmp(b1->name, "piston") == 0);
    check_true(b0->group == 0 && b0->place == 1 && b0->cm_from == 0);
    same_dir(b0->cm_dir, 0, 2, "cylinder cm_dir");
    same_dir(b0->z_dir, 0, 2, "cylinder z");
    same_dir(b0->x_dir, 0, -1, "cylinder x");
    check_true(b1->group == 1 && b1->place == 1 && b1->cm_from == 2);
    same_dir(b1->cm_dir, 2, 0, "piston cm_dir");
    same_dir(b1->z_dir, 0, 2, "piston z");
    same_dir(b1->x_dir, 0, -1, "piston x");
    check_true(strcmp(t->joint_name[0], "A") == 0 && strcmp(t->joint_name[1], "P") == 0 &&
               strcmp(t->joint_name[2], "B") == 0);
    for (int k = 1; k <= 3; ++k)
      check_true(t->measure[k].a == 0 && t->measure[k].b == 2);
    check_true(t->central == 1);
  } else {
    /* arcs u -> w and w -> v at the link radius; density, section, elbow mass,
     * rotor mass, rotor inertia are inertia values 0..4 */
    check_true(strcmp(b0->name, "proximal") == 0 && strcmp(b1->name, "distal") == 0);
    check_true(b0->model == POM_LIMB_MASS_ARC && b1->model == POM_LIMB_MASS_ARC);
    check_true(b0->arc_a == 0 && b0->arc_b == 1 && b1->arc_a == 1 && b1->arc_b == 2);
    check_true(b0->v_density == 0 && b0->v_section == 1 && b1->v_density == 0 &&
               b1->v_section == 1);
    check_true(b0->v_point_mass == 3 && b0->point_joint == 0 && b0->v_rotor == 4 &&
               b0->rotor_joint == 0);
    check_true(b1->v_point_mass == 2 && b1->point_joint == 1 && b1->v_rotor == -1);
    check_true(strcmp(t->joint_name[0], "U") == 0 && strcmp(t->joint_name[1], "W") == 0 &&
               strcmp(t->joint_name[2], "V") == 0);
    check_true(t->measure[1].kind == POM_LIMB_MEASURE_AXIS_ANGLE && t->measure[1].a == 1 &&
               t->measure[1].b == -1 && t->measure[2].kind == POM_LIMB_MEASURE_NONE);
    check_true(t->central == -1);
    check_rel(t->arc_radius, scale, 1e-15);
  }
}

/* Design d evaluated by the file (into the numeric table, through the
 * type's from_design) and by the hand-coded type; returns 0 when the
 * hand-coded type refuses the design (singular home: skipped). */
static int compare_at(const pom_arch_file *f, const pom_kin_arch_type *h, const pom_kin_design *d) {
  pom_kin_arch arch, ga;
  pom_error err;
  pom_error_clear(&err);
  if (pom_kin_arch_from_design(&arch, h, d, &err) != POM_OK) return 0;
  memset(&ga, 0, sizeof ga);
  ga.type = &f->type;
  if (!check_true(f->type.from_design(&ga, d, &err) == POM_OK)) {
    printf("  %s\n", err.message);
    return 0;
  }
  const pom_limb_table *tb = POM_LIMB_CTABLE(&ga);
  const double tol = 1e-15; /* m for points (~1e-2 m), 1 for unit axes: a few ulps */
  const char *name = h->name;
  check_rules(tb, name, d->scale);
  for (int i = 0; i < 3; ++i) {
    const pom_limb *L = &tb->limb[i];
    check_true(L->branch == 0.0 && L->kernel == 0 && L->length == 0.0);
    check_true(L->motor[0] == 0.0 && L->motor[1] == 0.0 && L->motor[2] == 0.0);
    if (strcmp(name, "3PSS") == 0) {
      const double *C = pom_kin_arch_points(&arch, "platform_points_m") + 3 * i;
      const double *B = pom_kin_arch_points(&arch, "slider_points_m") + 3 * i;
      const double *dd = pom_kin_arch_points(&arch, "slider_axes") + 3 * i;
      check_true(L->actuated == 0);
      check_true(L->joint[0].type == POM_LIMB_JOINT_P && L->joint[1].type == POM_LIMB_JOINT_S &&
                 L->joint[2].type == POM_LIMB_JOINT_S);
      close3(L->joint[0].point, B, tol, "3PSS slider point", i);
      close3(L->joint[0].axis, dd, tol, "3PSS slider axis", i);
      close3(L->joint[1].point, B, tol, "3PSS joint B", i);
      close3(L->joint[2].point, C, tol, "3PSS joint C", i);
    } else if (strcmp(name, "3SPS") == 0) {
      const double *B = pom_kin_arch_points(&arch, "platform_points_m") + 3 * i;
      const double *A = pom_kin_arch_points(&arch, "base_points_m") + 3 * i;
      const double *a1 = pom_kin_arch_points(&arch, "ujoint_axes") + 3 * i;
      double s[3], a2[3], mid[3];
      pom_v3_sub(s, B, A);
      double L0 = pom_v3_normalize(s, s);
      pom_v3_cross(a2, s, a1);
      pom_v3_normalize(a2, a2);
      pom_v3_axpy(mid, A, 0.5 * L0, s);
      check_true(L->actuated == 1);
      check_true(L->joint[0].type == POM_LIMB_JOINT_U && L->joint[1].type == POM_LIMB_JOINT_P &&
                 L->joint[2].type == POM_LIMB_JOINT_S);
      close3(L->joint[0].point, A, tol, "3SPS U-joint A", i);
      close3(L->joint[0].axis, a1, tol, "3SPS U axis 1", i);
      close3(L->joint[0].axis2, a2, tol, "3SPS U axis 2", i);
      close3(L->joint[1].point, mid, tol, "3SPS prismatic mid point", i);
      close3(L->joint[1].axis, s, tol, "3SPS limb axis", i);
      close3(L->joint[2].point, B, tol, "3SPS platform joint B", i);
    } else {
      const double *u = pom_kin_arch_points(&arch, "base_axes") + 3 * i;
      const double *w = pom_kin_arch_points(&arch, "elbow_axes") + 3 * i;
      const double *v = pom_kin_arch_points(&arch, "platform_axes") + 3 * i;
      check_true(L->actuated == 0);
      for (int j = 0; j < 3; ++j) {
        check_true(L->joint[j].type == POM_LIMB_JOINT_R);
        close3(L->joint[j].point, (const double[3]){0, 0, 0}, 0.0, "3RRR joint at O", i);
      }
      close3(L->joint[0].axis, u, tol, "3RRR base axis u", i);
      close3(L->joint[1].axis, w, tol, "3RRR elbow axis w", i);
      close3(L->joint[2].axis, v, tol, "3RRR platform axis v", i);
    }
  }
  return 1;
}

/* The design of a shipped config (as the hand-coded type loads it). */
static void config_design(const char *cfg_file, pom_kin_design *d) {
  char path[512];
  pom_cfg *cfg = NULL;
  pom_kin_arch arch;
  pom_error err;
  pom_error_clear(&err);
  snprintf(path, sizeof path, "%s/configs/%s", POM_SOURCE_DIR, cfg_file);
  check_true(pom_cfg_load(&cfg, path, &err) == POM_OK);
  check_true(pom_kin_arch_load(&arch, cfg, &err) == POM_OK);
  check_true(arch.has_design);
  *d = arch.design;
  pom_cfg_destroy(cfg);
}

static void check_type(const char *file, const char *hand, const char *cfg_file) {
  pom_arch_file *f = load_catalog(file);
  const pom_kin_arch_type *h = pom_kin_arch_type_find(hand);
  if (!f || !h) return;
  same_descriptors(&f->type, h);
  check_true(pom_arch_file_of(&f->type) == f);
  check_true(pom_arch_file_of(h) == NULL);
  pom_kin_design d;
  config_design(cfg_file, &d);
  check_true(compare_at(f, h, &d) == 1);
  /* random designs within every parameter's range */
  pom_rng rng;
  pom_rng_seed(&rng, 20261129u, 27u);
  int compared = 0;
  for (int n = 0; n < 200; ++n) {
    pom_kin_design r = d;
    r.scale = d.scale * (0.5 + pom_rng_uniform(&rng));
    for (int k = 0; k < h->n_params; ++k) {
      const pom_kin_param_desc *p = &h->params[k];
      double v = p->lo + (p->hi - p->lo) * pom_rng_uniform(&rng);
      if (p->integer) v = v < 0.0 ? -1.0 : 1.0;
      r.x[k] = v * p->to_si;
    }
    compared += compare_at(f, h, &r);
  }
  /* most random designs are assemblable at home (the rest are skipped) */
  if (!check_true(compared >= 20)) printf("  %s: only %d designs compared\n", hand, compared);
  pom_arch_file_destroy(f);
}

/* ---- bad files ------------------------------------------------------------------ */
static char *read_text(const char *path) {
  FILE *fp = fopen(path, "rb");
  if (!fp) return NULL;
  char *buf = calloc(1, 1 << 16);
  size_t n = buf ? fread(buf, 1, (1 << 16) - 1, fp) : 0;
  (void)n;
  fclose(fp);
  return buf;
}

/* The catalog's 3pss.arch with `from` replaced by `to` (once), loaded: the
 * failure's message must hold every string of want (NULL-terminated). */
static void bad_file_nth(const char *base_file, int nth, const char *from, const char *to,
                         const char *const want[]) {
  char path[512], out[512];
  snprintf(path, sizeof path, "%s/%s", POM_SOURCE_DIR, base_file);
  char *text = read_text(path);
  check_true(text != NULL);
  if (!text) return;
  char *at = strstr(text, from);
  for (int k = 1; k < nth && at; ++k)
    at = strstr(at + 1, from);
  if (!check_true(at != NULL)) {
    printf("  '%s' not in %s\n", from, base_file);
    free(text);
    return;
  }
  snprintf(out, sizeof out, "test_arch_file_bad.arch");
  FILE *fp = fopen(out, "wb");
  check_true(fp != NULL);
  if (!fp) {
    free(text);
    return;
  }
  fwrite(text, 1, (size_t)(at - text), fp);
  fputs(to, fp);
  fputs(at + strlen(from), fp);
  check_true(fclose(fp) == 0);
  free(text);
  pom_arch_file *f = NULL;
  pom_error err;
  pom_error_clear(&err);
  pom_status st = pom_arch_file_load(&f, out, &err);
  check_true(st == POM_ERR_CONFIG && f == NULL);
  for (int k = 0; want[k]; ++k)
    if (!check_true(strstr(err.message, want[k]) != NULL))
      printf("  replacing '%s': message \"%s\" lacks \"%s\"\n", from, err.message, want[k]);
  pom_arch_file_destroy(f);
  remove(out);
}

static void bad_file(const char *base_file, const char *from, const char *to,
                     const char *const want[]) {
  bad_file_nth(base_file, 1, from, to, want);
}

/* A variant that loads: the stored branch and the footprint point reach
 * the table. */
static void branch_and_motor(void) {
  char path[512];
  snprintf(path, sizeof path, "%s/catalog/3pss.arch", POM_SOURCE_DIR);
  char *text = read_text(path);
  char *at = text ? strstr(text, "branch = \"home\";") : NULL;
  check_true(at != NULL);
  if (!at) {
    free(text);
    return;
  }
  FILE *fp = fopen("test_arch_file_var.arch", "wb");
  check_true(fp != NULL);
  if (!fp) {
    free(text);
    return;
  }
  fwrite(text, 1, (size_t)(at - text), fp);
  fputs("branch = -1; motor = \"B + 0.25*r*d\";", fp);
  fputs(at + strlen("branch = \"home\";"), fp);
  check_true(fclose(fp) == 0);
  free(text);
  pom_arch_file *f = NULL;
  pom_error err;
  pom_error_clear(&err);
  if (!check_true(pom_arch_file_load(&f, "test_arch_file_var.arch", &err) == POM_OK)) {
    printf("  %s\n", err.message);
    return;
  }
  pom_kin_design d;
  config_design("3pss.cfg", &d);
  pom_limb_table t;
  check_true(pom_arch_file_eval(f, &d, &t, &err) == POM_OK);
  for (int i = 0; i < 3; ++i) {
    const pom_limb_joint *P = &t.limb[i].joint[0];
    double want[3];
    pom_v3_axpy(want, P->point, 0.25 * d.scale, P->axis);
    check_true(t.limb[i].branch == -1.0);
    close3(t.limb[i].motor, want, 1e-17, "motor", i);
  }
  pom_arch_file_destroy(f);
  remove("test_arch_file_var.arch");
}

#define WANT(...) ((const char *const[]){__VA_ARGS__, NULL})

static void bad_files(void) {
  const char *F = "test_arch_file_bad.arch:";
  /* an unknown name in an expression: file, line, key, value, column, token */
  bad_file("catalog/3pss.arch", "B = \"C - r*L*l\"", "B = \"C - r*LL*l\"",
           WANT(F, "key 'limbs.let.B' = \"C - r*LL*l\"", "column 7: unknown name (at 'LL')"));
  /* a type error */
  bad_file("catalog/3pss.arch", "C = \"r*er + r*h*ez\"", "C = \"r*er + h\"",
           WANT("key 'limbs.let.C'", "a vector plus a scalar"));
  /* a scalar where a point is needed */
  bad_file("catalog/3pss.arch", "point = \"C\"; }", "point = \"r\"; }",
           WANT("key 'limbs.joints.[2].point' = \"r\"", "expected a vector expression"));
  /* two actuated joints */
  bad_file("catalog/3pss.arch", "type = \"S\"; point = \"B\";",
           "type = \"S\"; point = \"B\"; actuated = true;",
           WANT("key 'limbs.joints.[1].actuated' = true",
                "the actuated joint of a linear actuator is prismatic, not spherical"));
  /* no actuated joint */
  bad_file("catalog/3pss.arch", "axis = \"d\"; actuated = true;", "axis = \"d\";",
           WANT("key 'limbs.joints'", "exactly one joint of a limb is actuated"));
  /* a spherical joint with an axis, a universal joint without its second */
  bad_file("catalog/3pss.arch", "type = \"S\"; point = \"C\";",
           "type = \"S\"; point = \"C\"; axis = \"d\";",
           WANT("key 'limbs.joints.[2].axis'", "a spherical joint (S) has no axis"));
  bad_file("catalog/3sps.arch", "axis = \"s\"; actuated", "axis = \"s\"; axis2 = \"a2\"; actuated",
           WANT("key 'limbs.joints.[1].axis2'", "only a universal joint (U) has a second axis"));
  /* an unknown joint type and an unknown top-level key */
  bad_file("catalog/3pss.arch", "type = \"P\";", "type = \"Q\";",
           WANT("key 'limbs.joints.[0].type' = \"Q\""));
  bad_file("catalog/3pss.arch", "central_joint = \"S\";", "central_joint = \"S\";\nfoo = 1;",
           WANT("key 'foo' = 1", "unknown top-level key"));
  /* a symbol that shadows a function or a limb variable, a taken let name */
  bad_file("catalog/3pss.arch", "symbol = \"lean\"", "symbol = \"sin\"",
           WANT("key 'parameters.[3].symbol' = \"sin\"", "reserved"));
  bad_file("catalog/3pss.arch", "symbol = \"laz\"", "symbol = \"eta\"",
           WANT("key 'parameters.[4].symbol' = \"eta\"", "the limb variables"));
  bad_file("catalog/3pss.arch", "d = \"sin(tilt)", "L = \"sin(tilt)",
           WANT("key 'limbs.let.L'", "already defined"));
  /* limbs: a list of 2, an unknown symmetry */
  bad_file("catalog/3pss.arch", "symmetry = \"C3\";", "symmetry = \"C4\";",
           WANT("key 'limbs.symmetry' = \"C4\""));
  /* the list form: 2 tables; limbs whose joint types differ */
  bad_file("tests/arch_per_limb.arch", "limbs = (\n  { azimuth",
           "limbs = (\n  { azimuth = \"0\"; }, { azimuth",
           WANT("key 'limbs' = (list of 4)", "exactly 3"));
  bad_file_nth("tests/arch_per_limb.arch", 3, "{ name = \"B\"; type = \"S\"; point = \"B\"; }",
               "{ name = \"B\"; type = \"R\"; point = \"B\"; axis = \"d\"; }",
               WANT("key 'limbs.[2].joints.[1].type' = \"R\"", "the same joint types"));
  /* the format version, the actuator kind, a parameter's unit */
  bad_file("catalog/3pss.arch", "format = 1;", "format = 2;",
           WANT("key 'format' = 2", "reads architecture format 1"));
  bad_file("catalog/3pss.arch", "actuator = \"linear\";", "actuator = \"hydraulic\";",
           WANT("key 'actuator' = \"hydraulic\"", "\"linear\" or \"rotary\""));
  bad_file("catalog/3pss.arch", "key = \"limb_length\"", "key = \"limb_length_mm\"",
           WANT("key 'parameters.[2].key' = \"limb_length_mm\"", "a ratio to the scale"));
  /* a default outside its range */
  bad_file("catalog/3pss.arch", "default = 90.0; range = [-360.0, 360.0]",
           "default = 900.0; range = [-360.0, 360.0]",
           WANT("key 'parameters.[0].default' = 900", "out of range"));
  /* limits: a distance with a degree key, joints out of order */
  bad_file("catalog/3pss.arch", "key = \"min_limb_distance_mm\"", "key = \"min_limb_distance_deg\"",
           WANT("key 'limits.[2].key'", "ends in _mm"));
  bad_file("catalog/3pss.arch", "frame = \"fixed\"; joints = [2, 3]",
           "frame = \"fixed\"; joints = [3, 2]", WANT("key 'limits.[0].joints'", "joints a < b"));
  /* bodies: one only, an unknown inertia value */
  bad_file("catalog/3rrr.arch", "mass = \"elbow_mass_kg\"", "mass = \"elbow_mas_kg\"",
           WANT("key 'bodies.[1].point_mass.mass' = \"elbow_mas_kg\"",
                "not one of the inertia_values keys"));
  bad_file("catalog/3rrr.arch", "arc_radius = \"r\";", "",
           WANT("key 'arc_radius'", "arc bodies need their radius"));
  bad_file("catalog/3pss.arch", "along = [1]; axis = [1]", "along = [2]; axis = [1]",
           WANT("key 'bodies.[0].along' = [array of 1]", "joint 2 is spherical: it has no axis"));
  bad_file("catalog/3pss.arch", "between = [2, 3]", "between = [1]",
           WANT("key 'bodies.[1].between'", "a fraction lies between two joints"));
  /* a chain no kernel solves: P-S-S actuated at its second joint */
  bad_file("catalog/3pss.arch", "{ name = \"B\"; type = \"S\"; point = \"B\"; }",
           "{ name = \"B\"; type = \"P\"; point = \"B\"; axis = \"d\"; }",
           WANT("key 'limbs.joints'", "no inverse-kinematics kernel solves this chain"));
  /* the arm-angle limit (Orbita's gamma): a misspelt measure, a key in mm, a
   * range beyond a turn, a default outside it, a prismatic or spherical
   * joint, on a linear architecture */
  bad_file("catalog/orbita3d.arch", "measure = \"arm_angle\"; joint = 2; bound = \"lower\"",
           "measure = \"arm_angel\"; joint = 2; bound = \"lower\"",
           WANT(F, "key 'limits.[1].measure' = \"arm_angel\""));
  bad_file("catalog/orbita3d.arch", "key = \"max_arm_angle_deg\"", "key = \"max_arm_angle_mm\"",
           WANT(F, "key 'limits.[2].key'", "a arm_angle limit's key ends in _deg"));
  bad_file_nth("catalog/orbita3d.arch", 2, "range = [0.0, 360.0]", "range = [0.0, 400.0]",
               WANT(F, "key 'limits.[2].range'", "an arm angle lies in [0, 360] deg"));
  bad_file("catalog/orbita3d.arch", "default = 175.0", "default = 375.0",
           WANT(F, "key 'limits.[2].default' = 375", "out of range"));
  bad_file("catalog/orbita3d.arch", "measure = \"arm_angle\"; joint = 2; bound = \"upper\"",
           "measure = \"arm_angle\"; joint = 4; bound = \"upper\"",
           WANT(F, "key 'limits.[2].joint' = 4"));
  bad_file("catalog/3pss.arch", "measure = \"distance\"; joints = [2, 3]",
           "measure = \"arm_angle\"; joint = 1", WANT(F, "key 'limits.[2].key'", "ends in _deg"));
  bad_file("catalog/3pss.arch",
           "key = \"min_limb_distance_mm\"; json = \"limb_distance_mm\";\n    measure = "
           "\"distance\"; joints = [2, 3]",
           "key = \"min_limb_distance_deg\"; json = \"limb_distance_mm\";\n    measure = "
           "\"arm_angle\"; joint = 1",
           WANT(F, "key 'limits.[2].joint' = 1", "joint 1 is prismatic"));
  bad_file("catalog/3pss.arch",
           "key = \"min_limb_distance_mm\"; json = \"limb_distance_mm\";\n    measure = "
           "\"distance\"; joints = [2, 3]",
           "key = \"min_limb_distance_deg\"; json = \"limb_distance_mm\";\n    measure = "
           "\"arm_angle\"; joint = 2",
           WANT(F, "key 'limits.[2].joint' = 2", "joint 2 is spherical"));
  /* a syntax error inside a file that libconfig reads: line of the parse error */
  bad_file("catalog/3pss.arch", "format = 1;", "format = = 1;", WANT("test_arch_file_bad.arch:"));
}

/* A design that cannot be evaluated: the 3-RRR with links too short to join
 * u and v (the square root of a negative number), then elbow = 0. */
static void bad_designs(void) {
  pom_arch_file *f = load_catalog("3rrr.arch");
  if (!f) return;
  pom_kin_design d;
  config_design("3rrr.cfg", &d);
  pom_limb_table g;
  pom_error err;
  pom_error_clear(&err);
  pom_kin_design e = d;
  e.x[1] = e.x[2] = 10.0 * POM_DEG; /* alpha1 = alpha2 = 10 deg: u-v is 90 deg at home */
  check_true(pom_arch_file_eval(f, &e, &g, &err) == POM_ERR_ARG);
  check_true(strstr(err.message, "3rrr.arch:") != NULL);
  check_true(strstr(err.message, "key 'limbs.let.c'") != NULL);
  check_true(strstr(err.message, "(limb 1): not finite at this design") != NULL);
  e = d;
  e.x[6] = 0.0; /* elbow */
  check_true(pom_arch_file_eval(f, &e, &g, &err) == POM_ERR_ARG);
  check_true(strstr(err.message, "key 'limbs.let.c'") != NULL);
  pom_arch_file_destroy(f);
  /* a missing file */
  pom_arch_file *none = NULL;
  check_true(pom_arch_file_load(&none, "no/such/file.arch", &err) != POM_OK && none == NULL);
  check_true(strstr(err.message, "no/such/file.arch") != NULL);
}

/* An arm-angle limit on a 3-RRR whose actuated axes are not on the z axis
 * (the Agile Eye's): the file loads, the design is refused naming the file,
 * the limit's line and key, the limb and its axis. */
static void arm_angle_not_coaxial(void) {
  char path[512];
  snprintf(path, sizeof path, "%s/catalog/3rrr.arch", POM_SOURCE_DIR);
  char *text = read_text(path);
  char *at = text ? strstr(text, "measure = \"axis_angle\"") : NULL;
  if (!check_true(at != NULL)) {
    free(text);
    return;
  }
  const char *out = "test_arch_file_arm.arch";
  FILE *fp = fopen(out, "wb");
  if (!check_true(fp != NULL)) {
    free(text);
    return;
  }
  fwrite(text, 1, (size_t)(at - text), fp);
  fputs("measure = \"arm_angle\"", fp);
  fputs(at + strlen("measure = \"axis_angle\""), fp);
  check_true(fclose(fp) == 0);
  free(text);
  pom_arch_file *f = NULL;
  pom_error err;
  pom_error_clear(&err);
  check_true(pom_arch_file_load(&f, out, &err) == POM_OK);
  if (f) {
    pom_kin_design d;
    config_design("3rrr.cfg", &d);
    pom_limb_table g;
    check_true(pom_arch_file_eval(f, &d, &g, &err) == POM_ERR_ARG);
    check_true(strstr(err.message, "test_arch_file_arm.arch:93:") != NULL);
    check_true(strstr(err.message, "key 'limits.[0].measure' = \"arm_angle\" (limb 1)") != NULL);
    if (!check_true(strstr(err.message, "needs coaxial actuators") != NULL))
      printf("  message: %s\n", err.message);
  }
  pom_arch_file_destroy(f);
  remove(out);
}

/* The list form (one table per limb, tests/arch_per_limb.arch) evaluates as
 * the C3 form: limb i's azimuth written as phi1 + 2*pi*i/3 is the C3 rule's
 * phi1 + 2 pi i / 3 in the same order of operations, so exactly. */
static void per_limb_form(void) {
  char path[512];
  pom_error err;
  pom_error_clear(&err);
  snprintf(path, sizeof path, "%s/tests/arch_per_limb.arch", POM_SOURCE_DIR);
  pom_arch_file *a = NULL, *b = load_catalog("3pss.arch");
  if (pom_arch_file_load(&a, path, &err) != POM_OK) printf("%s\n", err.message);
  check_true(a != NULL && a->per_limb == 1);
  if (!a || !b) {
    pom_arch_file_destroy(a);
    pom_arch_file_destroy(b);
    return;
  }
  check_true(b->per_limb == 0);
  pom_kin_design d;
  config_design("3pss.cfg", &d);
  pom_limb_table ga, gb;
  check_true(pom_arch_file_eval(a, &d, &ga, &err) == POM_OK);
  check_true(pom_arch_file_eval(b, &d, &gb, &err) == POM_OK);
  for (int i = 0; i < 3; ++i) {
    check_true(ga.limb[i].actuated == gb.limb[i].actuated);
    for (int j = 0; j < 3; ++j) {
      close3(ga.limb[i].joint[j].point, gb.limb[i].joint[j].point, 0.0, "list-form point", i);
      close3(ga.limb[i].joint[j].axis, gb.limb[i].joint[j].axis, 0.0, "list-form axis", i);
    }
  }
  pom_arch_file_destroy(a);
  pom_arch_file_destroy(b);
}

/* Discovery: the catalog folder, the extra list, a name given twice. */
static void discovery(void) {
  char cat[512], extra[1200];
  pom_error err;
  pom_error_clear(&err);
  snprintf(cat, sizeof cat, "%s/catalog", POM_SOURCE_DIR);
  unsetenv("POMLAB_CATALOG");
  const char *dir = pom_arch_catalog_dir();
  check_true(dir && strcmp(dir, cat) == 0); /* a build tree: the source tree's */
  setenv("POMLAB_CATALOG", "/some/where", 1);
  check_true(strcmp(pom_arch_catalog_dir(), "/some/where") == 0);
  unsetenv("POMLAB_CATALOG");
  pom_arch_file_set set;
  check_true(pom_arch_file_set_load(&set, cat, NULL, &err) == POM_OK);
  /* every *.arch of the folder, in file-name order: 3pss.arch first, then
   * 3pss_flat.arch, ... (docs/catalog.md section 2.1) */
  int n_arch = 0;
  DIR *d = opendir(cat);
  for (struct dirent *e = d ? readdir(d) : NULL; e; e = readdir(d)) {
    size_t len = strlen(e->d_name);
    n_arch += len > 5 && strcmp(e->d_name + len - 5, ".arch") == 0;
  }
  if (d) closedir(d);
  check_true(n_arch >= 3 && set.n == n_arch);
  int shipped = 0;
  for (int k = 0; k < set.n; ++k)
    shipped += strcmp(set.file[k]->name, "3PSS-table") == 0 ||
               strcmp(set.file[k]->name, "3RRR-table") == 0 ||
               strcmp(set.file[k]->name, "3SPS-table") == 0;
  check_true(shipped == 3 && set.n > 0 && strcmp(set.file[0]->name, "3PSS-table") == 0);
  pom_arch_file_set_free(&set);
  snprintf(extra, sizeof extra, "%s/tests/arch_per_limb.arch::", POM_SOURCE_DIR);
  check_true(pom_arch_file_set_load(&set, cat, extra, &err) == POM_OK);
  check_true(set.n == n_arch + 1 && strcmp(set.file[n_arch]->name, "3PSS-per-limb") == 0);
  pom_arch_file_set_free(&set);
  check_true(set.n == 0);
  /* the catalog twice: the second 3pss.arch names the first */
  check_true(pom_arch_file_set_load(&set, cat, cat, &err) == POM_ERR_ARG && set.n == 0);
  check_true(strstr(err.message, "architecture name \"3PSS-table\" is already given by") != NULL);
  check_true(pom_arch_file_set_load(&set, NULL, "no/such.arch", &err) != POM_OK && set.n == 0);
  check_true(strstr(err.message, "no/such.arch") != NULL);
  check_true(pom_arch_file_set_load(&set, "no/such/folder", NULL, &err) == POM_ERR_IO);
  check_true(strstr(err.message, "no/such/folder: cannot open the architecture catalog") != NULL);
}

int main(void) {
  check_type("3pss.arch", "3PSS", "3pss.cfg");
  check_type("3sps.arch", "3SPS", "3sps.cfg");
  check_type("3rrr.arch", "3RRR", "3rrr.cfg");
  per_limb_form();
  branch_and_motor();
  discovery();
  bad_files();
  bad_designs();
  arm_angle_not_coaxial();
  return check_summary("test_arch_file");
}
