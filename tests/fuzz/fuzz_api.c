/* fuzz_api.c - libFuzzer target: the flat C layer's config-and-override path
 * (api/pom_api.h), as python/pomlab drives it: bytes -> a config text
 * (pom_cfg_load_string) and overrides (pom_cfg_set_number /
 * pom_cfg_set_string) -> pom_api_arch_create and pom_api_sim_create, with
 * their checks of unknown keys, unknown top-level names and overrides nobody
 * read. Nothing is simulated or written (docs/fuzzing.md).
 *
 * Input: the config text, then optionally a line "#%overrides" (a libconfig
 * comment, so a seed stays a config file) and one override a line,
 * "KEY = VALUE": a VALUE in double quotes is set as a string, any other as
 * a number. A config text holding a NUL byte cannot be given to the C layer
 * as a string: it goes through pom_cfg_load, which must refuse it. A text
 * has no folder: its @include resolves from the working folder (the fuzz
 * build's; fuzz_config covers the includes). */
#define _XOPEN_SOURCE 700 /* strndup */
#include "fuzz_common.h"
#include "pom_api.h"
#include "pom_config.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static const char *input_path;

#define MAX_OVERRIDE_LINES 20 /* more than the config takes (16): that refusal too */

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc;
  (void)argv;
  input_path = pom_fuzz_setup();
  if (!input_path) abort();
  pom_api_quiet_handlers();
  return 0;
}

/* The text before the overrides' line, and where the overrides start
 * (size when there are none). */
static size_t split(const uint8_t *data, size_t size, size_t *overrides) {
  static const char mark[] = "#%overrides\n";
  const size_t n = sizeof mark - 1;
  for (size_t k = 0; k + n <= size; ++k)
    if ((k == 0 || data[k - 1] == '\n') && memcmp(data + k, mark, n) == 0) {
      *overrides = k + n;
      return k;
    }
  *overrides = size;
  return size;
}

static char *trim(char *s) {
  while (*s == ' ' || *s == '\t')
    ++s;
  size_t n = strlen(s);
  while (n > 0 && (s[n - 1] == ' ' || s[n - 1] == '\t' || s[n - 1] == '\r'))
    s[--n] = '\0';
  return s;
}

/* Applies the override lines; the first refusal ends them (its status). */
static pom_status apply_overrides(pom_cfg *cfg, const uint8_t *p, size_t size, pom_error *err) {
  int lines = 0;
  for (size_t k = 0; k < size && lines < MAX_OVERRIDE_LINES;) {
    size_t e = k;
    while (e < size && p[e] != '\n')
      ++e;
    /* a line holding a NUL byte is no C string: a binding refuses it
     * before the library (python/pomlab), so it is skipped here */
    if (!memchr(p + k, '\0', e - k)) {
      char *line = strndup((const char *)p + k, e - k);
      if (!line) return POM_ERR_NOMEM;
      char *eq = strchr(line, '=');
      if (eq) {
        *eq = '\0';
        char *key = trim(line), *value = trim(eq + 1);
        size_t n = strlen(value);
        char origin[64];
        snprintf(origin, sizeof origin, "override %d", ++lines);
        pom_status st;
        if (n >= 2 && value[0] == '"' && value[n - 1] == '"') {
          value[n - 1] = '\0';
          st = pom_cfg_set_string(cfg, key, value + 1, origin, err);
          pom_fuzz_check_failure(st, err, "pom_cfg_set_string");
        } else {
          st = pom_cfg_set_number(cfg, key, value, origin, err);
          pom_fuzz_check_failure(st, err, "pom_cfg_set_number");
        }
        if (st != POM_OK) {
          free(line);
          return st;
        }
      }
      free(line);
    }
    k = e + 1;
  }
  return POM_OK;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  if (pom_fuzz_refused(data, size)) return -1; /* not added to the corpus */
  size_t at = 0, n_text = split(data, size, &at);
  pom_error err;
  pom_error_clear(&err);
  pom_cfg *cfg = NULL;
  pom_status st;
  if (memchr(data, '\0', n_text)) {
    /* only a file can hold it, and the loader must refuse it */
    if (pom_fuzz_write(input_path, data, n_text) != 0) abort();
    st = pom_cfg_load(&cfg, input_path, &err);
    if (st == POM_OK) {
      fprintf(stderr, "fuzz: a config holding a NUL byte was accepted\n");
      abort();
    }
    pom_fuzz_check_failure(st, &err, "pom_cfg_load");
    return 0;
  }
  char *text = strndup((const char *)data, n_text);
  if (!text) abort();
  st = pom_cfg_load_string(&cfg, text, "fuzz.cfg", &err);
  free(text);
  pom_fuzz_check_failure(st, &err, "pom_cfg_load_string");
  if (st != POM_OK) return 0;
  st = apply_overrides(cfg, data + at, size - at, &err);
  if (st == POM_OK) {
    pom_kin_arch *arch = NULL;
    pom_status ast = pom_api_arch_create(&arch, cfg, &err);
    pom_fuzz_check_failure(ast, &err, "pom_api_arch_create");
    if ((ast == POM_OK) != (arch != NULL)) abort();
    if (arch && !pom_api_arch_actuator_unit(arch, NULL)) abort();
    pom_api_arch_destroy(arch);
  }
  if (st == POM_OK) {
    pom_api_sim *sim = NULL;
    st = pom_api_sim_create(&sim, cfg, 0, &err);
    pom_fuzz_check_failure(st, &err, "pom_api_sim_create");
    if ((st == POM_OK) != (sim != NULL)) abort();
    /* a built simulation has a finite stroke and a status to report */
    if (sim && !(isfinite(pom_api_sim_half_stroke(sim)) && pom_api_sim_half_stroke(sim) >= 0.0)) {
      fprintf(stderr, "fuzz: a simulation was built with a half stroke of %g\n",
              pom_api_sim_half_stroke(sim));
      abort();
    }
    pom_api_sim_destroy(sim);
  }
  pom_cfg_destroy(cfg);
  return 0;
}
