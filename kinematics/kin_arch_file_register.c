/* kin_arch_file_register.c - architecture files made architectures: the
 * numerics' operations (kinematics/pom_limb.h, pom_limb_type_ops) added to
 * a loaded file's type, then pom_kin_arch_register; and a process's
 * catalog plus $POMLAB_ARCHITECTURES registered once
 * (docs/architecture-files.md section 4). Kept apart from kin_arch_file.c:
 * the loader and the evaluation need nothing of the numerics. */
#define _POSIX_C_SOURCE 200809L /* getenv */
#include "pom_arch_file.h"

#include "pom_limb.h"

#include <stdlib.h>

pom_status pom_arch_file_register(pom_arch_file *f, pom_error *err) {
  pom_limb_type_ops(&f->type);
  return pom_kin_arch_register(&f->type, err);
}

/* The files registered for the process: they must outlive every use. */
static pom_arch_file_set registered;
static int registered_done;

pom_status pom_arch_files_register_all(pom_error *err) {
  if (registered_done) return POM_OK;
  pom_arch_file_set set;
  POM_TRY(
      pom_arch_file_set_load(&set, pom_arch_catalog_dir(), getenv("POMLAB_ARCHITECTURES"), err));
  for (int k = 0; k < set.n; ++k) {
    pom_status st = pom_arch_file_register(set.file[k], err);
    if (st != POM_OK) {
      pom_error_prefix(err, "%s", set.file[k]->path);
      /* those registered before stay (the registry holds them): keep them */
      for (int j = k; j < set.n; ++j)
        pom_arch_file_destroy(set.file[j]);
      set.n = k;
      registered = set;
      registered_done = 1;
      return st;
    }
  }
  registered = set;
  registered_done = 1;
  return POM_OK;
}
