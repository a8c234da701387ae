/* pom_version.c - version strings; the commit comes from a header generated
 * at build time (cmake/pom_version.cmake). */
#include "pom_version.h"

#include "pom_version_gen.h"

const char *pom_version(void) {
  return POM_VERSION;
}

const char *pom_git_commit(void) {
  return POM_GIT_COMMIT_STRING;
}
