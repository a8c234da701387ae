/* cli_outputs.c - the files a command reads and writes, checked before any
 * work (docs/results.md, "Output paths"). */
#define _XOPEN_SOURCE 700 /* realpath */
#include "cli_outputs.h"
#include "pom_config.h"

#include <errno.h>
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

struct pom_cli_paths {
  char command[32];
  entry_list in, out;
  int nomem; /* 1 after a failed allocation: check reports it */
};

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
static int add(pom_cli_paths *p, entry_list *l, const char *path, const char *what) {
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

pom_cli_paths *pom_cli_paths_create(const char *command) {
  pom_cli_paths *p = calloc(1, sizeof *p);
  if (p) snprintf(p->command, sizeof p->command, "%s", command);
  return p;
}

void pom_cli_paths_destroy(pom_cli_paths *p) {
  if (!p) return;
  clear(&p->in);
  clear(&p->out);
  free(p);
}

void pom_cli_paths_config(pom_cli_paths *p, const char *path, const char *what) {
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

void pom_cli_paths_output(pom_cli_paths *p, const char *path, const char *what) {
  if (p) add(p, &p->out, path, what);
}

/* ---- the check ---------------------------------------------------------------------- */
static int same_file(const entry *a, const entry *b) {
  if (a->exists && b->exists) return a->dev == b->dev && a->ino == b->ino;
  return strcmp(a->resolved, b->resolved) == 0;
}

int pom_cli_paths_check(const pom_cli_paths *p, int report) {
  if (!p || p->nomem) {
    if (report)
      fprintf(stderr, "pomlab %s: out of memory while checking the output paths\n",
              p ? p->command : "");
    return 1;
  }
  for (int o = 0; o < p->out.n; ++o) {
    const entry *out = &p->out.e[o];
    for (int i = 0; i < p->in.n; ++i)
      if (same_file(out, &p->in.e[i])) {
        if (report)
          fprintf(stderr,
                  "pomlab %s: %s '%s' is the same file as %s '%s': writing it would destroy an "
                  "input; choose another path (nothing was done)\n",
                  p->command, out->what, out->path, p->in.e[i].what, p->in.e[i].path);
        return 2;
      }
    for (int k = 0; k < o; ++k)
      if (same_file(out, &p->out.e[k])) {
        if (report)
          fprintf(stderr,
                  "pomlab %s: %s '%s' is the same file as %s '%s': one would overwrite the other; "
                  "choose distinct paths (nothing was done)\n",
                  p->command, out->what, out->path, p->out.e[k].what, p->out.e[k].path);
        return 2;
      }
  }
  return 0;
}

int pom_cli_check_output(const char *command, const char *cfg_path, const char *output,
                         const char *what) {
  if (!output || !output[0]) return 0;
  pom_cli_paths *p = pom_cli_paths_create(command);
  pom_cli_paths_config(p, cfg_path, "the config");
  pom_cli_paths_output(p, output, what);
  int rc = pom_cli_paths_check(p, 1);
  pom_cli_paths_destroy(p);
  return rc;
}

/* ---- folders and tabular files ------------------------------------------------------ */
int pom_cli_make_parent(const char *path, char *failed, size_t cap) {
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

int pom_cli_tabular_check(const char *command, const char *origin, const char *csv, int report) {
  if (!csv || !csv[0]) return 0;
  const char *base = strrchr(csv, '/');
  base = base ? base + 1 : csv;
  if (!ends_with(base, ".csv") || strcmp(base, ".csv") == 0) {
    if (report)
      fprintf(stderr,
              "pomlab %s: %s '%s': expected a file name ending in .csv (FILE.csv; the candidates "
              "table is FILE_candidates.csv)\n",
              command, origin, csv);
    return 2;
  }
  if (ends_with(base, "_candidates.csv")) {
    if (report)
      fprintf(stderr,
              "pomlab %s: %s '%s': a name ending in _candidates.csv is the candidates table of "
              "another name (FILE.csv writes FILE.csv and FILE_candidates.csv); choose a name "
              "without that ending\n",
              command, origin, csv);
    return 2;
  }
  struct stat sb;
  if (stat(csv, &sb) == 0 && !S_ISREG(sb.st_mode)) {
    if (report)
      fprintf(stderr,
              "pomlab %s: %s '%s' is not a regular file: the tabular results are two files "
              "(FILE.csv and FILE_candidates.csv beside it), so they need a regular file's path\n",
              command, origin, csv);
    return 2;
  }
  /* the folder is made as the results file's is, and checked before the work */
  char failed[PATH_CAP];
  if (pom_cli_make_parent(csv, failed, sizeof failed) != 0) {
    if (report)
      fprintf(stderr, "pomlab %s: %s '%s': cannot create folder '%s': %s\n", command, origin, csv,
              failed, strerror(errno));
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
    if (report)
      fprintf(stderr, "pomlab %s: %s '%s': cannot write in folder '%s': %s\n", command, origin, csv,
              dir, strerror(errno));
    return 1;
  }
  return 0;
}
