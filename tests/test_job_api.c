/* test_job_api.c - the flat C layer runs the program's job (job/pom_job.h,
 * issue 31 items 1 and 3): an output that is the config or another output is
 * refused with both paths named and nothing written; a cancel flag stops the
 * runs, keeps OUTPUT.partial, and resume finishes it.
 *
 * With arguments STUDY.cfg OUT.h5 OUT.json it runs that study file as
 * `pomlab study --out OUT.h5 --tabular OUT.csv --json --no-plots` would and
 * writes the JSON report to OUT.json (tests/test_job.py compares it with the
 * program's and the Python module's). */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */
#include "check.h"
#include "pom_api.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static int exists(const char *path) {
  struct stat sb;
  return stat(path, &sb) == 0;
}

/* The whole text of a file (malloc'd), NULL when unreadable. */
static char *slurp(const char *path) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  fseek(f, 0, SEEK_SET);
  char *s = malloc((size_t)n + 1);
  if (s && fread(s, 1, (size_t)n, f) != (size_t)n) n = 0;
  if (s) s[n] = '\0';
  fclose(f);
  return s;
}

static void copy_file(const char *from, const char *to) {
  char *s = slurp(from);
  FILE *f = fopen(to, "wb");
  if (s && f) fputs(s, f);
  if (f) fclose(f);
  free(s);
}

static pom_cfg *load(const char *path, long maneuvers) {
  pom_cfg *cfg = NULL;
  pom_error err;
  check_true(pom_cfg_load(&cfg, path, &err) == POM_OK);
  char n[32];
  snprintf(n, sizeof n, "%ld", maneuvers);
  if (cfg) check_true(pom_cfg_set_number(cfg, "montecarlo.maneuvers", n, "test", &err) == POM_OK);
  return cfg;
}

static void test_refusals(const char *dir) {
  char cfg_path[512], out[512], csv[512];
  snprintf(cfg_path, sizeof cfg_path, "%s/v.cfg", dir);
  copy_file(POM_SOURCE_DIR "/configs/3pss.cfg", cfg_path);
  char *before = slurp(cfg_path);
  pom_cfg *cfg = load(cfg_path, 2);
  pom_api_study_opts o;
  pom_api_study_defaults(&o);
  o.montecarlo = 1;
  o.threads = 1;
  pom_error err;
  long done = -1, total = -1;
  /* the results file over the config */
  o.output = cfg_path;
  check_true(pom_api_study_run(cfg, &o, &done, &total, &err) == POM_ERR_CONFIG);
  check_true(strstr(err.message, cfg_path) != NULL);
  check_true(strstr(err.message, "the config") != NULL);
  char *after = slurp(cfg_path);
  check_true(before && after && strcmp(before, after) == 0);
  free(after);
  /* the tabular file over the results file */
  snprintf(out, sizeof out, "%s/x.h5", dir);
  o.output = out;
  o.tabular = out;
  check_true(pom_api_study_run(cfg, &o, &done, &total, &err) == POM_ERR_CONFIG);
  check_true(strstr(err.message, out) != NULL);
  check_true(strstr(err.message, "one would overwrite the other") != NULL);
  check_true(!exists(out));
  /* the tabular name rule of the program */
  snprintf(csv, sizeof csv, "%s/x_candidates.csv", dir);
  o.tabular = csv;
  check_true(pom_api_study_run(cfg, &o, &done, &total, &err) == POM_ERR_CONFIG);
  check_true(strstr(err.message, "_candidates.csv") != NULL);
  check_true(!exists(out));
  /* a study file's summary over the config: summary.md named as an input */
  pom_cfg_destroy(cfg);
  free(before);
}

static void test_cancel(const char *dir) {
  char out[512], partial[600];
  snprintf(out, sizeof out, "%s/c.h5", dir);
  snprintf(partial, sizeof partial, "%s.partial", out);
  pom_cfg *cfg = load(POM_SOURCE_DIR "/configs/3pss.cfg", 64);
  volatile int stop = 1; /* set before the run: it stops after the first maneuvers */
  pom_api_study_opts o;
  pom_api_study_defaults(&o);
  o.montecarlo = 1;
  o.threads = 1;
  o.output = out;
  o.cancel = &stop;
  pom_error err;
  long done = -1, total = -1;
  check_true(pom_api_study_run(cfg, &o, &done, &total, &err) == POM_ERR_INTERRUPTED);
  check_true(done < total && total == 64);
  check_true(strstr(err.message, partial) != NULL);
  check_true(exists(partial) && !exists(out));
  /* resume finishes it */
  stop = 0;
  o.resume = 1;
  check_true(pom_api_study_run(cfg, &o, &done, &total, &err) == POM_OK);
  check_true(done == total && total == 64);
  check_true(exists(out) && !exists(partial));
  pom_cfg_destroy(cfg);
}

/* STUDY.cfg OUT.h5 OUT.json: the study through the C layer. */
static int run_study(const char *cfg_path, const char *out, const char *json_path) {
  pom_cfg *cfg = NULL;
  pom_error err;
  if (pom_cfg_load(&cfg, cfg_path, &err) != POM_OK) {
    fprintf(stderr, "test_job_api: %s\n", err.message);
    return 1;
  }
  char csv[1024];
  snprintf(csv, sizeof csv, "%.*s.csv", (int)strlen(out) - 3, out);
  pom_api_study_opts o;
  pom_api_study_defaults(&o);
  o.output = out;
  o.tabular = csv;
  o.summary = 1;
  char *json = NULL;
  long done = 0, total = 0;
  pom_status st = pom_api_study_run_json(cfg, &o, &done, &total, &json, &err);
  pom_cfg_destroy(cfg);
  if (st != POM_OK) {
    fprintf(stderr, "test_job_api: %s\n", err.message);
    return 1;
  }
  FILE *f = fopen(json_path, "w");
  if (f) {
    fputs(json, f);
    fclose(f);
  }
  pom_api_free(json);
  return f ? 0 : 1;
}

int main(int argc, char **argv) {
  pom_api_quiet_handlers();
  if (argc == 4) return run_study(argv[1], argv[2], argv[3]);
  char dir[] = "/tmp/pom_test_job_api_XXXXXX";
  if (!mkdtemp(dir)) return 1;
  test_refusals(dir);
  test_cancel(dir);
  char cmd[600];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
  if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", dir);
  return check_summary("test_job_api");
}
