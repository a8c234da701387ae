/* kin_arch_catalog.c - where architecture files are found: the shipped
 * catalog folder, a folder's *.arch files in name order, and a process's
 * set of files (pom_arch_file.h, docs/architecture-files.md section 4). */
#define _DEFAULT_SOURCE /* DIR, struct dirent, readlink */
#include "pom_arch_file.h"

#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---- discovery ------------------------------------------------------------------------ */
#ifndef POM_CATALOG_SOURCE_DIR
#define POM_CATALOG_SOURCE_DIR "catalog"
#endif

static int is_dir(const char *path) {
  struct stat sb;
  return path && path[0] && stat(path, &sb) == 0 && S_ISDIR(sb.st_mode);
}

/* The installed layout: PREFIX/bin/program -> PREFIX/share/pomlab/catalog. */
static int installed_dir(char *buf, size_t cap) {
  char exe[4096];
  ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (n <= 0 || (size_t)n >= sizeof exe - 1) return 0;
  exe[n] = '\0';
  char *slash = strrchr(exe, '/');
  if (!slash) return 0;
  *slash = '\0';
  snprintf(buf, cap, "%s/../share/pomlab/catalog", exe);
  return is_dir(buf);
}

const char *pom_arch_catalog_dir(void) {
  static _Thread_local char found[4200];
  const char *env = getenv("POMLAB_CATALOG");
  if (env && env[0]) return env;
  if (installed_dir(found, sizeof found)) return found;
  if (is_dir(POM_CATALOG_SOURCE_DIR)) return POM_CATALOG_SOURCE_DIR;
  return NULL;
}

static int name_cmp(const void *a, const void *b) {
  return strcmp(*(const char *const *)a, *(const char *const *)b);
}

pom_status pom_arch_catalog_each(const char *dir,
                                 pom_status (*fn)(const char *path, void *user, pom_error *err),
                                 void *user, pom_error *err) {
  enum { MAX_FILES = 64 };
  char names[MAX_FILES][256];
  const char *sorted[MAX_FILES];
  int n = 0;
  DIR *dp = opendir(dir);
  if (!dp)
    POM_FAIL(err, POM_ERR_IO, "%s: cannot open the architecture catalog: %s", dir, strerror(errno));
  for (struct dirent *e = readdir(dp); e; e = readdir(dp)) {
    size_t len = strlen(e->d_name);
    if (len < 6 || len >= sizeof names[0] || strcmp(e->d_name + len - 5, ".arch") != 0) continue;
    if (n == MAX_FILES) {
      closedir(dp);
      POM_FAIL(err, POM_ERR_ARG, "%s: more than %d architecture files", dir, MAX_FILES);
    }
    snprintf(names[n], sizeof names[n], "%s", e->d_name);
    sorted[n] = names[n];
    ++n;
  }
  closedir(dp);
  qsort(sorted, (size_t)n, sizeof sorted[0], name_cmp);
  for (int k = 0; k < n; ++k) {
    char path[4400];
    snprintf(path, sizeof path, "%s/%s", dir, sorted[k]);
    POM_TRY(fn(path, user, err));
  }
  return POM_OK;
}

/* ---- a process's files ------------------------------------------------------------------ */
static pom_status set_add(const char *path, void *user, pom_error *err) {
  pom_arch_file_set *set = user;
  if (set->n == POM_AF_MAX_FILES)
    POM_FAIL(err, POM_ERR_ARG, "%s: more than %d architecture files", path, POM_AF_MAX_FILES);
  pom_arch_file *f = NULL;
  POM_TRY(pom_arch_file_load(&f, path, err));
  for (int k = 0; k < set->n; ++k)
    if (strcmp(set->file[k]->name, f->name) == 0) {
      pom_status st = pom_error_set(err, POM_ERR_ARG, __FILE__, __LINE__,
                                    "%s: architecture name \"%s\" is already given by %s", path,
                                    f->name, set->file[k]->path);
      pom_arch_file_destroy(f);
      return st;
    }
  set->file[set->n++] = f;
  return POM_OK;
}

pom_status pom_arch_file_set_load(pom_arch_file_set *set, const char *catalog_dir,
                                  const char *extra, pom_error *err) {
  memset(set, 0, sizeof *set);
  pom_status st = POM_OK;
  if (catalog_dir) st = pom_arch_catalog_each(catalog_dir, set_add, set, err);
  for (const char *p = extra; st == POM_OK && p && *p;) {
    const char *colon = strchr(p, ':');
    size_t n = colon ? (size_t)(colon - p) : strlen(p);
    char path[4096];
    if (n >= sizeof path) {
      st = pom_error_set(err, POM_ERR_ARG, __FILE__, __LINE__,
                         "an architecture path of %zu characters is too long", n);
      break;
    }
    memcpy(path, p, n);
    path[n] = '\0';
    if (n > 0)
      st = is_dir(path) ? pom_arch_catalog_each(path, set_add, set, err) : set_add(path, set, err);
    p = colon ? colon + 1 : p + n;
  }
  if (st != POM_OK) pom_arch_file_set_free(set);
  return st;
}

void pom_arch_file_set_free(pom_arch_file_set *set) {
  for (int k = 0; k < set->n; ++k)
    pom_arch_file_destroy(set->file[k]);
  set->n = 0;
}
