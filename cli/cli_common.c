/* cli_common.c - helpers shared by the subcommands. */
#include "pom_cli.h"

#include "pom_api.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- config groups ------------------------------------------------------- */
pom_status pom_cli_check_unknown(const pom_cfg *cfg, const char *const *const scopes[],
                                 pom_error *err) {
  pom_cfg_groups own, known;
  pom_cfg_groups_init(&own);
  for (int k = 0; scopes && scopes[k]; ++k)
    POM_TRY(pom_cfg_groups_add(&own, scopes[k], err));
  POM_TRY(pom_api_known_groups(&known, err));
  return pom_cfg_check_unknown(cfg, own.name, known.name, err);
}

void pom_cli_report(const char *context, const pom_error *err) {
  if (err && err->message[0]) {
    fprintf(stderr, "pomlab: %s: %s\n", context, err->message);
  } else {
    fprintf(stderr, "pomlab: %s: %s\n", context,
            pom_strerror(err ? err->status : POM_ERR_INTERNAL));
  }
}

int pom_cli_exit_code(pom_status st) {
  if (st == POM_OK) return 0;
  if (st == POM_ERR_CONFIG || st == POM_ERR_ARG) return 2;
  return 1;
}

int pom_cli_parse_list(const char *text, int n, double *out) {
  const char *p = text;
  for (int k = 0; k < n; ++k) {
    char *end = NULL;
    errno = 0;
    double v = strtod(p, &end);
    if (end == p || errno != 0 || !isfinite(v)) return -1; /* nan/inf are usage errors */
    out[k] = v;
    p = end;
    if (k < n - 1) {
      if (*p != ',') return -1;
      ++p;
    }
  }
  return *p == '\0' ? 0 : -1;
}

int pom_cli_parse_threads(const char *command, const char *text, int *out) {
  char *end = NULL;
  errno = 0;
  long v = strtol(text, &end, 10);
  if (end == text || *end || errno != 0 || v < 1 || v > POM_API_THREADS_MAX) {
    if (command)
      fprintf(stderr, "pomlab %s: --threads '%s': expected an integer in [1, %d]\n", command, text,
              POM_API_THREADS_MAX);
    return -1;
  }
  *out = (int)v;
  return 0;
}

void pom_cli_refuse_shared_output(const char *command, const char *cfg_a, const char *cfg_b,
                                  const char *output) {
  fprintf(stderr,
          "pomlab %s: %s and %s would both write %s (the file name comes from the config's "
          "`name`): give them distinct names; nothing was written\n",
          command, cfg_a, cfg_b, output);
}

pom_cfg *pom_cli_load_config(const char *path) {
  pom_error err;
  pom_error_clear(&err);
  pom_cfg *cfg = NULL;
  if (pom_cfg_load(&cfg, path, &err) != POM_OK) {
    pom_cli_report("config", &err);
    return NULL;
  }
  return cfg;
}
