/* pom_version.h - program version and the git commit of the build, for
 * provenance in results files and --version. */
#ifndef POM_VERSION_H
#define POM_VERSION_H

/* Project version ("0.1.0"), static string. */
const char *pom_version(void);

/* Git commit the program was built from, with "-dirty" when the working tree
 * had uncommitted changes at build time; "unknown" outside a git checkout.
 * Static string, read at build time (not at configure time). */
const char *pom_git_commit(void);

/* The commit as an expression usable wherever a const char * is. */
#define POM_GIT_COMMIT pom_git_commit()

#endif
