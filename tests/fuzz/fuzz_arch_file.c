/* fuzz_arch_file.c - libFuzzer target: bytes -> an architecture file
 * (docs/architecture-files.md) -> pom_arch_file_load (libconfig, the
 * loader's checks and the expression compiler, core/pom_expr.h), then, for
 * a file that loads, pom_arch_file_eval at a design made of every
 * parameter's default (else the middle of its range) and at its range's
 * ends. A failure must carry a message; an evaluation that succeeds must
 * give finite points and unit axes (docs/fuzzing.md). */
#include "fuzz_common.h"
#include "pom_arch_file.h"
#include "pom_math.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static const char *input_path;

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc;
  (void)argv;
  input_path = pom_fuzz_setup();
  if (!input_path) abort();
  return 0;
}

static int finite3(const double v[3]) {
  return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

static void check_geometry(const pom_limb_table *g) {
  for (int i = 0; i < 3; ++i) {
    if (!finite3(g->limb[i].motor)) abort();
    for (int j = 0; j < 3; ++j) {
      const pom_limb_joint *J = &g->limb[i].joint[j];
      if (!finite3(J->point)) abort();
      if (J->type != POM_LIMB_JOINT_S && fabs(pom_v3_norm(J->axis) - 1.0) > 1e-12) abort();
      if (pom_v3_norm(J->axis2) != 0.0 && fabs(pom_v3_norm(J->axis2) - 1.0) > 1e-12) abort();
    }
  }
  if (!isfinite(g->arc_radius)) abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  if (pom_fuzz_refused(data, size)) return -1; /* not added to the corpus */
  if (pom_fuzz_write(input_path, data, size) != 0) abort();
  pom_error err;
  pom_error_clear(&err);
  pom_arch_file *f = NULL;
  pom_status st = pom_arch_file_load(&f, input_path, &err);
  pom_fuzz_check_failure(st, &err, "pom_arch_file_load");
  if (st != POM_OK) {
    if (f) abort();
    return 0;
  }
  pom_limb_table *g = malloc(sizeof *g);
  if (!g) abort();
  for (int end = -1; end <= 1; ++end) {
    pom_kin_design d;
    memset(&d, 0, sizeof d);
    d.scale = 0.0123;
    for (int k = 0; k < f->type.n_params; ++k) {
      const pom_kin_param_desc *p = &f->type.params[k];
      double v = end < 0 ? p->lo : end > 0 ? p->hi : (p->optional ? p->def : 0.5 * (p->lo + p->hi));
      d.x[k] = v * p->to_si;
    }
    pom_error_clear(&err);
    st = pom_arch_file_eval(f, &d, g, &err);
    pom_fuzz_check_failure(st, &err, "pom_arch_file_eval");
    if (st == POM_OK) check_geometry(g);
  }
  free(g);
  pom_arch_file_destroy(f);
  return 0;
}
