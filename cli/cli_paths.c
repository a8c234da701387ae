/* cli_paths.c - where the program finds its plotting scripts: next to the
 * installed executable (PREFIX/bin/pomlab -> PREFIX/share/pomlab/scripts),
 * else in the source tree it was built from (a build tree). */
#define _DEFAULT_SOURCE /* readlink */
#include "pom_cli.h"

#include <stdio.h>
#include <string.h>
#include <unistd.h>

/* Set by cli/CMakeLists.txt: the scripts folder relative to the folder of the
 * installed program, and the source tree. */
#ifndef POM_SCRIPTS_REL
#define POM_SCRIPTS_REL "../share/pomlab/scripts"
#endif

/* The folder of the running executable (from /proc/self/exe) into buf; 0 on
 * success. */
static int exe_dir(char *buf, size_t cap) {
  ssize_t n = readlink("/proc/self/exe", buf, cap - 1);
  if (n <= 0 || (size_t)n >= cap - 1) return -1;
  buf[n] = '\0';
  char *slash = strrchr(buf, '/');
  if (!slash) return -1;
  *slash = '\0';
  return 0;
}

int pom_cli_scripts_dir(char *buf, size_t cap) {
  char dir[4096], probe[4400];
  if (exe_dir(dir, sizeof dir) == 0) {
    snprintf(probe, sizeof probe, "%s/%s/plot_study.py", dir, POM_SCRIPTS_REL);
    if (access(probe, R_OK) == 0) {
      snprintf(buf, cap, "%s/%s", dir, POM_SCRIPTS_REL);
      return 0;
    }
  }
  snprintf(probe, sizeof probe, "%s/scripts/plot_study.py", POM_SOURCE_DIR);
  snprintf(buf, cap, "%s/scripts", POM_SOURCE_DIR);
  return access(probe, R_OK) == 0 ? 0 : -1;
}
