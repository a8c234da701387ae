/* pom_job_paths.c - the files a command reads and writes, checked before any
 * work (docs/results.md, "Output paths"). */
#define _XOPEN_SOURCE 700 /* realpath */
#include "pom_job.h"
#include "job_internal.h"
#include "pom_config.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define PATH_CAP 4200 /* resolved paths: PATH_MAX and a file name beyond it */

typedef struct {
  char *path;     /* as given (owned) */
  char *what;     /* description for messages (owned) */
  char *resolved; /* absolute, links followed as far as the path exists (owned) */
  int exists;     /* 1 when stat succeeded: dev and ino are valid */
  dev_t dev;
  ino_t ino;
} entry;

typedef struct {
  int n, cap;
  entry *e; /* [n] */
} entry_list;

struct pom_job_paths {
  char command[32];
  entry_list in, out;
  int nomem; /* 1 after a failed allocation: check reports it */
};

/* ---- messages ------------------------------------------------------------------------ */
pom_status pom_job_say(FILE *msg, pom_error *err, pom_status st, const char *command,
                       const char *fmt, ...) {
  char text[4096];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(text, sizeof text, fmt, ap);
  va_end(ap);
  if (msg)
    fprintf(msg, "pomlab%s%s: %s\n", command && command[0] ? " " : "", command ? command : "",
            text);
  if (err && st != POM_OK) pom_error_set(err, st, __FILE__, __LINE__, "%s", text);
  return st;
}

void pom_job_report_error(FILE *msg, const char *context, const pom_error *err) {
  if (!msg) return;
  if (err && err->message[0])
    fprintf(msg, "pomlab: %s: %s\n", context, err->message);
  else
    fprintf(msg, "pomlab: %s: %s\n", context, pom_strerror(err ? err->status : POM_ERR_INTERNAL));
}

const char *pom_job_duration_text(char *buf, size_t cap, double s) {
  if (!isfinite(s))
    snprintf(buf, cap, "unknown time");
  else if (s < 120.0)
    snprintf(buf, cap, "about %.2g s", s);
  else if (s < 7200.0)
    snprintf(buf, cap, "about %.2g min", s / 60.0);
  else if (s < 2.0 * 86400.0)
    snprintf(buf, cap, "about %.2g h", s / 3600.0);
  else
    snprintf(buf, cap, "about %.2g days", s / 86400.0);
  return buf;
}

const char *pom_job_bytes_text(char *buf, size_t cap, double bytes) {
  static const char *const units[] = {"bytes", "kB", "MB", "GB", "TB", "PB"};
  int u = 0;
  while (bytes >= 1000.0 && u < 5) {
    bytes /= 1000.0;
    ++u;
  }
  snprintf(buf, cap, u ? "%.3g %s" : "%.0f %s", bytes, units[u]);
  return buf;
}

/* ---- resolved paths --------------------------------------------------------------- */
/* Missing path components resolved lexically, at most (each one a level of
 * recursion with a few kB of stack); deeper paths are compared as given. */
#define MISSING_DEPTH_MAX 64

/* path made absolute, with symbolic links, "." and ".." resolved as far as
 * the path exists and the rest appended lexically; 0 on success. depth
 * counts the missing components already taken off. */
static int resolve_at(const char *path, char *out, size_t cap, int depth) {
  char abs[PATH_CAP];
  if (path[0] == '/') {
    snprintf(abs, sizeof abs, "%s", path);
  } else {
    char cwd[PATH_MAX];
    if (!getcwd(cwd, sizeof cwd)) return -1;
    snprintf(abs, sizeof abs, "%s/%s", cwd, path);
  }
  size_t n = strlen(abs);
  while (n > 1 && abs[n - 1] == '/')
    abs[--n] = '\0';
  char real[PATH_MAX];
  if (realpath(abs, real)) {
    snprintf(out, cap, "%s", real);
    return 0;
  }
  char *slash = strrchr(abs, '/');
  if (!slash) return -1;
  char base[PATH_CAP];
  snprintf(base, sizeof base, "%s", slash + 1);
  if (slash == abs)
    slash[1] = '\0'; /* the root */
  else
    *slash = '\0';
  if (depth >= MISSING_DEPTH_MAX || resolve_at(abs, out, cap, depth + 1) != 0) return -1;
  if (!base[0] || strcmp(base, ".") == 0) return 0;
  if (strcmp(base, "..") == 0) {
    char *up = strrchr(out, '/');
    if (up && up != out)
      *up = '\0';
    else
      snprintf(out, cap, "/");
    return 0;
  }
  size_t k = strlen(out);
  snprintf(out + k, cap - k, "%s%s", k > 0 && out[k - 1] == '/' ? "" : "/", base);
  return 0;
}

static int resolve(const char *path, char *out, size_t cap) {
  return resolve_at(path, out, cap, 0);
}

/* ---- lists -------------------------------------------------------------------------- */
static char *dup_text(const char *s) {
  size_t n = strlen(s) + 1;
  char *d = malloc(n);
  if (d) memcpy(d, s, n);
  return d;
}

/* Adds path to l; returns 1 when it was added, 0 when it was not (an input
 * listed already, or out of memory). Outputs are all kept: two of one path
 * are what the check refuses. */
static int add(pom_job_paths *p, entry_list *l, const char *path, const char *what) {
  if (!p || !path || !path[0]) return 0;
  char resolved[PATH_CAP];
  if (resolve(path, resolved, sizeof resolved) != 0)
    snprintf(resolved, sizeof resolved, "%s", path);
  for (int k = 0; k < l->n && l == &p->in; ++k)
    if (strcmp(l->e[k].resolved, resolved) == 0) return 0; /* listed once */
  if (l->n == l->cap) {
    int cap = l->cap ? 2 * l->cap : 16;
    entry *grown = realloc(l->e, (size_t)cap * sizeof *grown);
    if (!grown) {
      p->nomem = 1;
      return 0;
    }
    l->e = grown;
    l->cap = cap;
  }
  entry *e = &l->e[l->n];
  memset(e, 0, sizeof *e);
  e->path = dup_text(path);
  e->what = dup_text(what);
  e->resolved = dup_text(resolved);
  if (!e->path || !e->what || !e->resolved) {
    free(e->path);
    free(e->what);
    free(e->resolved);
    p->nomem = 1;
    return 0;
  }
  struct stat sb;
  if (stat(path, &sb) == 0) {
    e->exists = 1;
    e->dev = sb.st_dev;
    e->ino = sb.st_ino;
  }
  ++l->n;
  return 1;
}

static void clear(entry_list *l) {
  for (int k = 0; k < l->n; ++k) {
    free(l->e[k].path);
    free(l->e[k].what);
    free(l->e[k].resolved);
  }
  free(l->e);
}

pom_job_paths *pom_job_paths_create(const char *command) {
  pom_job_paths *p = calloc(1, sizeof *p);
  if (p) snprintf(p->command, sizeof p->command, "%s", command);
  return p;
}

void pom_job_paths_destroy(pom_job_paths *p) {
  if (!p) return;
  clear(&p->in);
  clear(&p->out);
  free(p);
}

void pom_job_paths_config(pom_job_paths *p, const char *path, const char *what) {
  /* a file listed already (every candidate of a sweep) is not loaded again */
  if (!add(p, &p->in, path, what)) return;
  pom_cfg *cfg = NULL;
  pom_error err;
  pom_error_clear(&err);
  if (pom_cfg_load(&cfg, path, &err) != POM_OK) return; /* the command reports it */
  char inc_what[300];
  snprintf(inc_what, sizeof inc_what, "a file included by %s", what);
  for (int k = 1; k < pom_cfg_n_files(cfg); ++k)
    add(p, &p->in, pom_cfg_file(cfg, k), inc_what);
  pom_cfg_destroy(cfg);
}

void pom_job_paths_output(pom_job_paths *p, const char *path, const char *what) {
  if (p) add(p, &p->out, path, what);
}

/* ---- the check ---------------------------------------------------------------------- */
static int same_file(const entry *a, const entry *b) {
  if (a->exists && b->exists) return a->dev == b->dev && a->ino == b->ino;
  return strcmp(a->resolved, b->resolved) == 0;
}

int pom_job_paths_check(const pom_job_paths *p, FILE *msg, pom_error *err) {
  if (!p || p->nomem) {
    pom_job_say(msg, err, POM_ERR_NOMEM, p ? p->command : "",
                "out of memory while checking the output paths");
    return 1;
  }
  for (int o = 0; o < p->out.n; ++o) {
    const entry *out = &p->out.e[o];
    for (int i = 0; i < p->in.n; ++i)
      if (same_file(out, &p->in.e[i])) {
        pom_job_say(msg, err, POM_ERR_CONFIG, p->command,
                    "%s '%s' is the same file as %s '%s': writing it would destroy an input; "
                    "choose another path (nothing was done)",
                    out->what, out->path, p->in.e[i].what, p->in.e[i].path);
        return 2;
      }
    for (int k = 0; k < o; ++k)
      if (same_file(out, &p->out.e[k])) {
        pom_job_say(msg, err, POM_ERR_CONFIG, p->command,
                    "%s '%s' is the same file as %s '%s': one would overwrite the other; choose "
                    "distinct paths (nothing was done)",
                    out->what, out->path, p->out.e[k].what, p->out.e[k].path);
        return 2;
      }
  }
  return 0;
}

int pom_job_check_output(const char *command, const char *cfg_path, const char *output,
                         const char *what, FILE *msg, pom_error *err) {
  if (!output || !output[0]) return 0;
  pom_job_paths *p = pom_job_paths_create(command);
  pom_job_paths_config(p, cfg_path, "the config");
  pom_job_paths_output(p, output, what);
  int rc = pom_job_paths_check(p, msg, err);
  pom_job_paths_destroy(p);
  return rc;
}

/* ---- folders and tabular files ------------------------------------------------------ */
int pom_job_make_parent(const char *path, char *failed, size_t cap) {
  char dir[PATH_CAP];
  snprintf(dir, sizeof dir, "%s", path);
  char *slash = strrchr(dir, '/');
  if (!slash || slash == dir) return 0;
  *slash = '\0';
  for (char *c = dir + 1;; ++c) {
    if (*c != '/' && *c != '\0') continue;
    char keep = *c;
    *c = '\0';
    if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
      int e = errno;
      snprintf(failed, cap, "%s", dir);
      errno = e;
      return -1;
    }
    struct stat sb;
    if (stat(dir, &sb) != 0 || !S_ISDIR(sb.st_mode)) {
      snprintf(failed, cap, "%s", dir);
      errno = ENOTDIR;
      return -1;
    }
    *c = keep;
    if (!keep) break;
  }
  return 0;
}

static int ends_with(const char *s, const char *suffix) {
  size_t n = strlen(s), k = strlen(suffix);
  return n >= k && strcmp(s + n - k, suffix) == 0;
}

int pom_job_tabular_check(const char *command, const char *origin, const char *csv, FILE *msg,
                          pom_error *err) {
  if (!csv || !csv[0]) return 0;
  const char *base = strrchr(csv, '/');
  base = base ? base + 1 : csv;
  if (!ends_with(base, ".csv") || strcmp(base, ".csv") == 0) {
    pom_job_say(msg, err, POM_ERR_CONFIG, command,
                "%s '%s': expected a file name ending in .csv (FILE.csv; the candidates table is "
                "FILE_candidates.csv)",
                origin, csv);
    return 2;
  }
  if (ends_with(base, "_candidates.csv")) {
    pom_job_say(msg, err, POM_ERR_CONFIG, command,
                "%s '%s': a name ending in _candidates.csv is the candidates table of another "
                "name (FILE.csv writes FILE.csv and FILE_candidates.csv); choose a name without "
                "that ending",
                origin, csv);
    return 2;
  }
  struct stat sb;
  if (stat(csv, &sb) == 0 && !S_ISREG(sb.st_mode)) {
    pom_job_say(msg, err, POM_ERR_CONFIG, command,
                "%s '%s' is not a regular file: the tabular results are two files "
                "(FILE.csv and FILE_candidates.csv beside it), so they need a regular file's path",
                origin, csv);
    return 2;
  }
  /* the folder is made as the results file's is, and checked before the work */
  char failed[PATH_CAP];
  if (pom_job_make_parent(csv, failed, sizeof failed) != 0) {
    pom_job_say(msg, err, POM_ERR_IO, command, "%s '%s': cannot create folder '%s': %s", origin,
                csv, failed, strerror(errno));
    return 1;
  }
  char dir[PATH_CAP];
  snprintf(dir, sizeof dir, "%s", csv);
  char *slash = strrchr(dir, '/');
  if (slash == dir)
    dir[1] = '\0';
  else if (slash)
    *slash = '\0';
  else
    snprintf(dir, sizeof dir, ".");
  if (access(dir, W_OK) != 0) {
    pom_job_say(msg, err, POM_ERR_IO, command, "%s '%s': cannot write in folder '%s': %s", origin,
                csv, dir, strerror(errno));
    return 1;
  }
  return 0;
}
