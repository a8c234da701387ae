/* test_arch_file_e2e.c - the catalog files as registered architectures
 * (docs/architecture-files.md section 4): configs/3pss.cfg, 3sps.cfg and
 * 3rrr.cfg loaded with architecture = "3PSS-table" (...) give the
 * hand-coded type's inverse kinematics, Jacobian, limit values, body twists
 * and mechanism. Tolerance 1e-12 of each field's scale (the plan's
 * agreement bound for the tables, docs/kinematics-tables.md): the file
 * reproduces the private geometry to a few ulps (test_arch_file.c) and the
 * generic kernels are the hand-coded formulas in another order. */
#include "check.h"
#include "pom_arch.h"
#include "pom_arch_file.h"
#include "pom_config.h"
#include "pom_kinematics.h"
#include "pom_math.h"
#include "pom_rng.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static double worst[8];
static const char *const what[8] = {"q",       "J",         "limit values", "twist A",
                                    "twist B", "mech mass", "mech cm",      "mech inertia"};

static void record(int k, const double *a, const double *b, int n, double scale) {
  for (int c = 0; c < n; ++c) {
    double d = fabs(a[c] - b[c]) / scale;
    if (!(d <= worst[k])) worst[k] = isnan(d) ? INFINITY : d;
  }
}

/* The shipped config's text with architecture = arch_name and, central >
 * 0, its geometry.central_joint = false made true. */
static int load(pom_kin_arch *arch, pom_mechanism *mech, const char *cfg_file,
                const char *arch_name, int central) {
  static char text[1 << 16], edited[1 << 16];
  char path[512];
  snprintf(path, sizeof path, "%s/configs/%s", POM_SOURCE_DIR, cfg_file);
  FILE *fp = fopen(path, "rb");
  if (!fp) return 0;
  size_t n = fread(text, 1, sizeof text - 1, fp);
  fclose(fp);
  text[n] = '\0';
  const char *at = strstr(text, "architecture = \"");
  const char *end = at ? strchr(at + 16, '"') : NULL;
  const char *mode = strstr(text, "mode = \"parameters\";");
  if (!at || !end || !mode || mode < end) return 0;
  snprintf(edited, sizeof edited, "%.*sarchitecture = \"%s\"%.*s%s%s", (int)(at - text), text,
           arch_name, (int)(mode - end - 1), end + 1, "", mode);
  pom_cfg *cfg = NULL;
  pom_error err;
  pom_error_clear(&err);
  /* the config's own central_joint = false, made true */
  char *cj = central > 0 ? strstr(edited, "central_joint = false;") : NULL;
  if (cj) memcpy(cj, "central_joint = true; ", 22);
  if (pom_cfg_load_string(&cfg, edited, path, &err) != POM_OK) {
    printf("%s\n", err.message);
    return 0;
  }
  int ok = pom_kin_arch_load(arch, cfg, &err) == POM_OK &&
           pom_kin_mechanism_build(mech, arch, cfg, &err) == POM_OK;
  if (!ok) printf("%s (%s): %s\n", cfg_file, arch_name, err.message);
  pom_cfg_destroy(cfg);
  return ok;
}

static void compare(const char *cfg_file, const char *hand, const char *table, int central) {
  pom_kin_arch h, g;
  static pom_mechanism mh, mg;
  memset(worst, 0, sizeof worst);
  if (!check_true(load(&h, &mh, cfg_file, hand, central))) return;
  if (!check_true(load(&g, &mg, cfg_file, table, central))) return;
  check_true(strcmp(pom_kin_arch_name(&g), table) == 0);
  check_true(pom_arch_file_of(g.type) != NULL);
  const double len = h.design.scale;
  pom_rng rng;
  pom_rng_seed(&rng, 27u, 1u);
  int n_ok = 0;
  for (int n = 0; n < 200; ++n) {
    double e[3], R[9], w[3];
    for (int k = 0; k < 3; ++k) {
      e[k] = (2.0 * pom_rng_uniform(&rng) - 1.0) * 20.0 * POM_DEG;
      w[k] = (2.0 * pom_rng_uniform(&rng) - 1.0) * 5.0;
    }
    pom_euler_zyx_to_matrix(R, e);
    pom_kin_pose ph, pg;
    pom_status sh = pom_kin_pose_evaluate(&h, R, &ph, NULL);
    pom_status sg = pom_kin_pose_evaluate(&g, R, &pg, NULL);
    check_true(ph.reachable == pg.reachable && (sh == POM_OK) == (sg == POM_OK));
    if (!ph.reachable || !pg.reachable) continue;
    ++n_ok;
    double qs = pom_kin_type_actuator(h.type) == POM_ACT_REVOLUTE ? 1.0 : len;
    record(0, pg.q, ph.q, 3, qs);
    record(1, pg.J, ph.J, 9, qs);
    record(2, pg.limit + 3, ph.limit + 3, 9, fmax(len, 1.0));
    check_true(pg.violations == ph.violations);
    pom_kin_twists th, tg;
    memset(&th, 0, sizeof th);
    memset(&tg, 0, sizeof tg);
    if (pom_kin_body_twists(&h, R, w, &th, NULL) != POM_OK ||
        pom_kin_body_twists(&g, R, w, &tg, NULL) != POM_OK)
      continue;
    for (int b = 2; b < 8; ++b) {
      record(3, tg.body[b].A, th.body[b].A, 9, len);
      record(4, tg.body[b].B, th.body[b].B, 9, 1.0);
    }
  }
  check_true(n_ok > 100);
  check_true(g.central_joint == h.central_joint &&
             g.central_joint == (central > 0 || strstr(table, "3RRR") == NULL));
  check_true(mg.n_bodies == mh.n_bodies && mg.n_joints == mh.n_joints &&
             mg.n_actuators == mh.n_actuators);
  double ms = 0.0, is = 0.0;
  for (int b = 0; b < mh.n_bodies; ++b) {
    ms = fmax(ms, mh.body[b].mass);
    for (int k = 0; k < 9; ++k)
      is = fmax(is, fabs(mh.body[b].inertia[k]));
  }
  for (int b = 0; b < mh.n_bodies && b < mg.n_bodies; ++b) {
    check_true(strcmp(mg.body[b].name, mh.body[b].name) == 0);
    record(5, &mg.body[b].mass, &mh.body[b].mass, 1, ms);
    record(6, mg.body[b].cm, mh.body[b].cm, 3, len);
    record(7, mg.body[b].inertia, mh.body[b].inertia, 9, is);
  }
  for (int j = 0; j < mh.n_joints && j < mg.n_joints; ++j) {
    const pom_mech_joint *a = &mg.joint[j], *b = &mh.joint[j];
    check_true(strcmp(a->name, b->name) == 0 && a->type == b->type && a->body[0] == b->body[0] &&
               a->body[1] == b->body[1] && a->actuator == b->actuator);
    for (int c = 0; c < 3; ++c)
      check_abs(a->point[c], b->point[c], 1e-12 * len);
  }
  printf("%s as %s (central %d): %d poses; worst relative differences:", cfg_file, table, central,
         n_ok);
  for (int k = 0; k < 8; ++k) {
    printf(" %s %.1e%s", what[k], worst[k], k < 7 ? "," : "\n");
    check_true(worst[k] <= 1e-12);
  }
}

int main(void) {
  pom_error err;
  pom_error_clear(&err);
  if (!check_true(pom_arch_files_register_all(&err) == POM_OK)) printf("%s\n", err.message);
  check_true(pom_kin_arch_type_find("3PSS-table") && pom_kin_arch_type_find("3SPS-table") &&
             pom_kin_arch_type_find("3RRR-table"));
  check_true(pom_arch_files_register_all(&err) == POM_OK); /* once: the second call does nothing */
  compare("3pss.cfg", "3PSS", "3PSS-table", 0);
  compare("3sps.cfg", "3SPS", "3SPS-table", 0);
  compare("3rrr.cfg", "3RRR", "3RRR-table", 0);
  compare("3rrr.cfg", "3RRR", "3RRR-table", 1);
  return check_summary("test_arch_file_e2e");
}
