/* grad_test_util.h - helpers shared by the design-gradient test programs:
 * a shipped config's text, and that config loaded with another solver
 * rtol (POM_SOURCE_DIR from the build). */
#ifndef POM_GRAD_TEST_UTIL_H
#define POM_GRAD_TEST_UTIL_H

#include "pom_config.h"

#include <stdio.h>
#include <string.h>

/* configs/<file> of the source tree read into text (cap bytes, NUL
 * terminated) and its path into path (512 bytes); 0 when unreadable. */
static inline int shipped_text(const char *file, char *text, size_t cap, char path[512]) {
  snprintf(path, 512, "%s/configs/%s", POM_SOURCE_DIR, file);
  FILE *f = fopen(path, "rb");
  if (!f) return 0;
  size_t n = fread(text, 1, cap - 1, f);
  fclose(f);
  text[n] = '\0';
  return 1;
}

/* configs/<file> loaded with its solver line "rtol = 1.0e-6;" replaced by
 * rtol (a literal of 5 characters, e.g. "1e-12"); NULL (the reason
 * printed) when the file, the line or the load fails. */
static inline pom_cfg *shipped_with_rtol(const char *file, const char *rtol) {
  static char text[1 << 16];
  char path[512];
  if (!shipped_text(file, text, sizeof text, path)) return NULL;
  char *r = strstr(text, "rtol = 1.0e-6;");
  if (!r || strlen(rtol) != 5) return NULL;
  char rep[15];
  snprintf(rep, sizeof rep, "rtol = %s; ", rtol); /* the same 14 characters */
  memcpy(r, rep, 14);
  pom_cfg *cfg = NULL;
  pom_error err;
  if (pom_cfg_load_string(&cfg, text, path, &err) != POM_OK) {
    printf("config: %s\n", err.message);
    return NULL;
  }
  return cfg;
}

/* The line at *p (its newline kept, cut to cap - 1 bytes) into line, *p
 * moved past it; returns the line past its leading blanks. */
static inline const char *next_line(const char **p, char *line, size_t cap) {
  const char *nl = strchr(*p, '\n');
  size_t len = nl ? (size_t)(nl - *p + 1) : strlen(*p);
  snprintf(line, cap, "%.*s", (int)(len < cap ? len : cap - 1), *p);
  *p += len;
  return line + strspn(line, " \t");
}

#endif
