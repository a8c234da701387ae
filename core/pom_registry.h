/* pom_registry.h - a registry of named types (architectures, controllers):
 * the library's built-ins, a const array, then the ones a program registers
 * at run time. Lookups are not locked: a program registers its types before
 * any thread reads the registry (docs/extending.md sections 2 and 8). */
#ifndef POM_REGISTRY_H
#define POM_REGISTRY_H

#include "pom_status.h"

#include <pthread.h>
#include <stddef.h>

#define POM_REGISTRY_MAX_USER 16 /* types a program may register */

typedef struct {
  const void *const *builtin; /* [n_builtin] the library's types */
  int n_builtin;
  size_t name_offset;                      /* byte offset of the type's `const char *name` */
  const void *user[POM_REGISTRY_MAX_USER]; /* registered types, written under lock */
  int n_user;
  pthread_mutex_t lock;
} pom_registry;

/* A registry over a const array of type pointers whose type has a `name`
 * member: POM_REGISTRY_INIT(builtin, offsetof(my_type, name)). */
#define POM_REGISTRY_INIT(builtin_, name_offset_)                                                  \
  {                                                                                                \
    (const void *const *)(builtin_), (int)(sizeof(builtin_) / sizeof((builtin_)[0])),              \
        (name_offset_), {0}, 0, PTHREAD_MUTEX_INITIALIZER                                          \
  }

/* Number of types (built-ins first), the k-th (NULL out of range), the one
 * named `name` (NULL when none or name is NULL). */
int pom_registry_count(const pom_registry *r);
const void *pom_registry_at(const pom_registry *r, int k);
const void *pom_registry_find(const pom_registry *r, const char *name);

/* Adds a type whose table the caller has checked: POM_ERR_ARG when its name
 * is taken, POM_ERR_NOMEM when the registry is full; `what` names the kind
 * in the message ("architecture", "controller"). */
pom_status pom_registry_add(pom_registry *r, const void *type, const char *what, pom_error *err);

#endif
