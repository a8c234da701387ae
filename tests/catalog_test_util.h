/* catalog_test_util.h - what the tests that loop over catalog/ share: a
 * file's text and a quoted value of a config line (test_catalog,
 * test_catalog_energy, test_mjcf). Header-only, for tests. */
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

#endif
