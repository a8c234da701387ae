/* test_catalog.c - every architecture file of catalog/ (docs/catalog.md,
 * docs/architecture-files.md), found by pom_arch_catalog_each so that a new
 * file is checked without editing this test. Each file needs a run config:
 * configs/catalog/<stem>.cfg, else configs/<stem>.cfg (the three shipped
 * files), loaded with architecture = the file's name. Per file:
 *  - IK -> FK round trip at 1000 random orientations (ZYX angles within
 *    +-25 deg) that are reachable, away from singularities (1/kappa >= 0.05)
 *    and on home's side of the parallel singularities (det J of home's sign:
 *    the FK from home converges to home's assembly mode there). FK from home
 *    with residual tolerance 1e-14 (test_limb_table.c): bound 1e-10 rad.
 *  - J against central differences of the IK, q(Rot(e_k, +-h) R) (omega in
 *    the fixed frame), Richardson-extrapolated from h = 2e-5 and 1e-5 rad:
 *    the h^2 terms cancel, leaving ~h^4 |q^(5)| and rounding ~3 eps |q| / h
 *    ~ 3e-11 |q|. Measured: a plain central difference at h = 1e-5 misses by
 *    7e-7 of |J| on the coaxial 3-RRR, the extrapolation from h = 1e-4 by
 *    6.4e-7 on the tangential 3-RSS/S (near its leg singularities), and from
 *    h = 2e-5 by 1.0e-9 there (625 = 5^4 times less: truncation, not a
 *    wrong J). Bound 1e-7 of the largest |J| entry, as test_limb_table.c's
 *    AD-vs-differences check.
 *  - kappa of the home Jacobian against the home kappa of docs/catalog.md's
 *    summary table (computed independently by scripts/catalog_home.py and
 *    printed to 6 decimals): bound 1e-6, as that script's check(). */
#include "catalog_test_util.h"
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

static int n_files = 0;

/* docs/catalog.md's home kappa of the entry `id` (the summary table's last
 * column), or NAN. */
static double doc_kappa(const char *id) {
  char path[512], pat[80];
  snprintf(path, sizeof path, "%s/docs/catalog.md", POM_SOURCE_DIR);
  char *doc = slurp(path);
  if (!doc) return NAN;
  snprintf(pat, sizeof pat, " `%s` |", id);
  double k = NAN;
  for (char *line = doc; line && *line;) {
    char *nl = strchr(line, '\n');
    if (nl) *nl = '\0';
    if (strncmp(line, "| C", 3) == 0 && strstr(line, pat)) {
      char *bar = strrchr(line, '|');
      if (bar) *bar = '\0';
      bar = strrchr(line, '|');
      if (bar) k = strtod(bar + 1, NULL);
      break;
    }
    line = nl ? nl + 1 : NULL;
  }
  free(doc);
  return k;
}

static pom_status check_file(const char *path, void *user, pom_error *err) {
  (void)user;
  (void)err;
  ++n_files;
  char stem[128], name[128], id[128], cfg_path[512];
  const char *base = strrchr(path, '/');
  base = base ? base + 1 : path;
  size_t len = strlen(base);
  if (len < 6 || len - 5 >= sizeof stem) return POM_OK;
  memcpy(stem, base, len - 5);
  stem[len - 5] = '\0';
  char *arch_text = slurp(path);
  int have_name = arch_text && quoted(arch_text, "name", name, sizeof name);
  free(arch_text);
  if (!check_true(have_name)) {
    printf("%s: no name\n", path);
    return POM_OK;
  }
  /* the docs/catalog.md id: the stem, or the shipped files' entries */
  static const char *const alias[][2] = {
      {"3pss", "3pss_ref"}, {"3sps", "3ups_ref"}, {"3rrr", "agile_eye"}};
  snprintf(id, sizeof id, "%s", stem);
  for (size_t a = 0; a < sizeof alias / sizeof alias[0]; ++a)
    if (strcmp(stem, alias[a][0]) == 0) snprintf(id, sizeof id, "%s", alias[a][1]);

  snprintf(cfg_path, sizeof cfg_path, "%s/configs/catalog/%s.cfg", POM_SOURCE_DIR, stem);
  char *text = slurp(cfg_path);
  if (!text) {
    snprintf(cfg_path, sizeof cfg_path, "%s/configs/%s.cfg", POM_SOURCE_DIR, stem);
    text = slurp(cfg_path);
  }
  if (!check_true(text != NULL)) {
    printf("%s: no run config configs/catalog/%s.cfg\n", path, stem);
    return POM_OK;
  }
  /* architecture = the file's name */
  static char edited[1 << 17];
  char *at = strstr(text, "\narchitecture = \"");
  char *end = at ? strchr(at + 17, '"') : NULL;
  if (!check_true(at && end)) {
    free(text);
    return POM_OK;
  }
  snprintf(edited, sizeof edited, "%.*s\narchitecture = \"%s%s", (int)(at - text), text, name, end);
  free(text);
  pom_cfg *cfg = NULL;
  pom_error e;
  pom_error_clear(&e);
  pom_kin_arch g;
  if (pom_cfg_load_string(&cfg, edited, cfg_path, &e) != POM_OK ||
      pom_kin_arch_load(&g, cfg, &e) != POM_OK) {
    check_true(0);
    printf("%s with %s: %s\n", path, cfg_path, e.message);
    pom_cfg_destroy(cfg);
    return POM_OK;
  }
  pom_cfg_destroy(cfg);
  check_true(strcmp(pom_kin_arch_name(&g), name) == 0);

  /* home kappa */
  double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, q0[3], J0[9], kappa = NAN;
  if (check_true(pom_kin_inverse_jacobian(&g, I, q0, J0, NULL) == POM_OK))
    pom_kin_dexterity(J0, NULL, &kappa, NULL);
  double kdoc = doc_kappa(id);
  check_true(isfinite(kdoc));
  check_true(fabs(kappa - kdoc) <= 1e-6);

  /* round trip and J against differences */
  pom_rng rng;
  pom_rng_seed(&rng, 27u, 4u);
  const double h = 2e-5;
  const double unit[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  int used = 0, tries = 0, fk_fail = 0;
  double fk_worst = 0.0, j_worst = 0.0;
  while (used < 1000 && tries < 50000) {
    ++tries;
    double e3[3], R[9], q[3], J[9], dex;
    for (int k = 0; k < 3; ++k)
      e3[k] = pom_rng_range(&rng, -25.0, 25.0) * POM_DEG;
    pom_euler_zyx_to_matrix(R, e3);
    if (pom_kin_inverse_jacobian(&g, R, q, J, NULL) != POM_OK) continue;
    pom_kin_dexterity(J, NULL, NULL, &dex);
    if (dex < 0.05) continue;
    if (!(pom_m3_det(J) * g.home_det_sign > 0.0)) continue;
    ++used;
    double Rf[9], D[9], rv[3];
    pom_kin_fk_opts fo;
    pom_kin_fk_defaults(&fo);
    fo.residual_tol = 1e-14;
    pom_error fe;
    pom_error_clear(&fe);
    if (pom_kin_forward(&g, q, NULL, &fo, Rf, NULL, &fe) == POM_OK) {
      pom_m3_mult(D, Rf, R);
      pom_m3_rotvec(rv, D);
      double d = pom_v3_norm(rv);
      if (!(d <= fk_worst)) fk_worst = isnan(d) ? INFINITY : d;
    } else {
      ++fk_fail;
    }
    double jmax = 0.0, dmax = 0.0;
    int ok = 1;
    for (int k = 0; k < 3 && ok; ++k) {
      double d[2][3];
      for (int m = 0; m < 2 && ok; ++m) {
        double E[9], Rp[9], Rm[9], qp[3], qm[3], hm = m == 0 ? h : 0.5 * h;
        pom_m3_axis_angle(E, unit[k], hm);
        pom_m3_mul(Rp, E, R);
        pom_m3_axis_angle(E, unit[k], -hm);
        pom_m3_mul(Rm, E, R);
        ok = pom_kin_inverse(&g, Rp, qp, NULL) == POM_OK &&
             pom_kin_inverse(&g, Rm, qm, NULL) == POM_OK;
        for (int i = 0; i < 3 && ok; ++i)
          d[m][i] = (qp[i] - qm[i]) / (2.0 * hm);
      }
      for (int i = 0; i < 3 && ok; ++i) {
        /* Richardson: the h^2 terms of the two central differences cancel */
        double dr = (4.0 * d[1][i] - d[0][i]) / 3.0;
        jmax = fmax(jmax, fabs(J[3 * i + k]));
        dmax = fmax(dmax, fabs(dr - J[3 * i + k]));
      }
    }
    if (!check_true(ok)) continue;
    double rel = dmax / jmax;
    if (!(rel <= j_worst)) j_worst = isnan(rel) ? INFINITY : rel;
  }
  printf("%-20s %-16s home kappa %.9f (docs/catalog.md %.6f); %d poses of %d tries; "
         "FK from home: worst %.1e rad, %d failures; J vs central differences: worst %.1e of "
         "max |J|\n",
         base, name, kappa, kdoc, used, tries, fk_worst, fk_fail, j_worst);
  check_true(used == 1000);
  check_true(fk_fail == 0);
  check_true(fk_worst < 1e-10);
  check_true(j_worst < 1e-7);
  return POM_OK;
}

int main(void) {
  pom_error err;
  pom_error_clear(&err);
  if (!check_true(pom_arch_files_register_all(&err) == POM_OK)) printf("%s\n", err.message);
  const char *dir = pom_arch_catalog_dir();
  check_true(dir != NULL);
  if (dir && !check_true(pom_arch_catalog_each(dir, check_file, NULL, &err) == POM_OK))
    printf("%s\n", err.message);
  printf("%d catalog files\n", n_files);
  check_true(n_files >= 10);
  return check_summary("test_catalog");
}
