/* pom_registry.c - the registry of named types shared by the architectures
 * (kinematics/kin_registry.c) and the controllers
 * (dynamics/dyn_ctrl_registry.c). */
#include "pom_registry.h"

#include <string.h>

static const char *name_of(const pom_registry *r, const void *type) {
  return *(const char *const *)(const void *)((const char *)type + r->name_offset);
}

int pom_registry_count(const pom_registry *r) {
  return r->n_builtin + r->n_user;
}

const void *pom_registry_at(const pom_registry *r, int k) {
  if (k < 0) return NULL;
  if (k < r->n_builtin) return r->builtin[k];
  k -= r->n_builtin;
  return k < r->n_user ? r->user[k] : NULL;
}

const void *pom_registry_find(const pom_registry *r, const char *name) {
  if (!name) return NULL;
  for (int k = 0; k < pom_registry_count(r); ++k) {
    const void *t = pom_registry_at(r, k);
    if (strcmp(name_of(r, t), name) == 0) return t;
  }
  return NULL;
}

pom_status pom_registry_add(pom_registry *r, const void *type, const char *what, pom_error *err) {
  const char *name = name_of(r, type);
  pthread_mutex_lock(&r->lock);
  pom_status st = POM_OK;
  if (pom_registry_find(r, name)) {
    st = POM_ERR_ARG;
  } else if (r->n_user >= POM_REGISTRY_MAX_USER) {
    st = POM_ERR_NOMEM;
  } else {
    r->user[r->n_user++] = type;
  }
  pthread_mutex_unlock(&r->lock);
  if (st == POM_ERR_ARG) POM_FAIL(err, st, "%s %s is registered already", what, name);
  if (st != POM_OK)
    POM_FAIL(err, st, "%s %s: the registry holds %d user types at most", what, name,
             POM_REGISTRY_MAX_USER);
  return POM_OK;
}
