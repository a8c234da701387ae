/* catalog_test_util.h - what the tests that loop over catalog/ share: a
 * file's text and a quoted value of a config line (test_catalog,
 * test_catalog_energy, test_mjcf) and the kinematics tests that load a
 * config (test_kin_modes, test_agile_sing). Header-only, for tests. */
#ifndef CATALOG_TEST_UTIL_H
#define CATALOG_TEST_UTIL_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The text of path (up to 128 KiB), malloc'ed; NULL when it cannot be read. */
static inline char *slurp(const char *path) {
  FILE *fp = fopen(path, "rb");
  if (!fp) return NULL;
  static char buf[1 << 17];
  size_t n = fread(buf, 1, sizeof buf - 1, fp);
  fclose(fp);
  buf[n] = '\0';
  char *s = malloc(n + 1);
  if (s) memcpy(s, buf, n + 1);
  return s;
}

/* The quoted value after a line `key = "` of text, into out; 0 when absent. */
static inline int quoted(const char *text, const char *key, char *out, size_t cap) {
  char pat[64];
  snprintf(pat, sizeof pat, "\n%s = \"", key);
  const char *at = strstr(text, pat);
  if (!at) return 0;
  at += strlen(pat);
  const char *end = strchr(at, '"');
  if (!end || (size_t)(end - at) >= cap) return 0;
  memcpy(out, at, (size_t)(end - at));
  out[end - at] = '\0';
  return 1;
}

/* The config POM_SOURCE_DIR/rel loaded into arch, with its architecture name
 * replaced by arch_name when not NULL (a hand-coded type run as its table);
 * 0, with the reason printed, when it cannot be. Needs pom_config.h and
 * pom_kinematics.h included first, and POM_SOURCE_DIR defined. */
#if defined(POM_SOURCE_DIR) && defined(POM_KINEMATICS_H)
static inline int load_config_arch(const char *rel, const char *arch_name, pom_kin_arch *arch) {
  char path[512];
  snprintf(path, sizeof path, "%s/%s", POM_SOURCE_DIR, rel);
  FILE *f = fopen(path, "rb");
  static char text[1 << 16], edited[(1 << 16) + 256];
  size_t n = f ? fread(text, 1, sizeof text - 1, f) : 0;
  if (f) fclose(f);
  text[n] = '\0';
  snprintf(edited, sizeof edited, "%s", text);
  if (arch_name) {
    char *at = strstr(text, "\narchitecture = \"");
    char *end = at ? strchr(at + 17, '"') : NULL;
    if (!at || !end) return 0;
    snprintf(edited, sizeof edited, "%.*s\narchitecture = \"%s%s", (int)(at - text), text,
             arch_name, end);
  }
  pom_cfg *cfg = NULL;
  pom_error e;
  pom_error_clear(&e);
  int ok = pom_cfg_load_string(&cfg, edited, path, &e) == POM_OK &&
           pom_kin_arch_load(arch, cfg, &e) == POM_OK;
  if (!ok) printf("%s: %s\n", rel, e.message);
  pom_cfg_destroy(cfg);
  return ok;
}
#endif

#endif
