/* pom_config.c - libconfig access with type, range and unknown-key checks. */
#define _XOPEN_SOURCE 700 /* realpath */
#include "pom_config.h"

#include <errno.h>
#include <libconfig.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#define MAX_INCLUDE_DEPTH 10 /* libconfig 1.5's own limit */
#define MAX_RENAMED       32 /* absolute @includes of one main file */
#define MAX_OVERRIDES     16 /* values set from the command line */
#define MAX_FILES         64 /* files read for one config (main + @includes), listed */

struct pom_cfg {
  config_t lc; /* parsed tree */
  char *path;  /* file path or name */
  char *dir;   /* folder for @include, NULL for strings */
  char *text;  /* raw text of the main file */
  /* absolute @includes as libconfig sees them (rewritten relative to dir)
   * and as the user wrote them, for messages */
  int n_renamed;
  char *renamed_from[MAX_RENAMED]; /* rewritten name, owned */
  char *renamed_to[MAX_RENAMED];   /* name as written, owned */
  /* settings given on the command line and the option that gave them */
  int n_overrides;
  const config_setting_t *override_setting[MAX_OVERRIDES];
  char override_origin[MAX_OVERRIDES][64];
  /* the main file and every @include read, as opened (owned) */
  int n_files;
  char *files[MAX_FILES];
};

/* ---- helpers ---------------------------------------------------------------- */
static char *dup_string(const char *s) {
  size_t n = strlen(s) + 1;
  char *d = malloc(n);
  if (d) memcpy(d, s, n);
  return d;
}

/* A file name as libconfig reports it -> as the user wrote it. */
static const char *shown_file(const pom_cfg *cfg, const char *f) {
  if (!f) return cfg->path;
  for (int k = 0; k < cfg->n_renamed; ++k)
    if (strcmp(f, cfg->renamed_from[k]) == 0) return cfg->renamed_to[k];
  return f;
}

static const char *setting_file(const pom_cfg *cfg, const config_setting_t *s) {
  return shown_file(cfg, s ? config_setting_source_file(s) : NULL);
}

/* The command-line option that set s, NULL when s comes from a file. */
static const char *override_origin(const pom_cfg *cfg, const config_setting_t *s) {
  for (int k = 0; s && k < cfg->n_overrides; ++k)
    if (cfg->override_setting[k] == s) return cfg->override_origin[k];
  return NULL;
}

static void mark_tree(config_setting_t *s, void *marker) {
  config_setting_set_hook(s, marker);
  if (config_setting_is_aggregate(s)) {
    int n = config_setting_length(s);
    for (int k = 0; k < n; ++k)
      mark_tree(config_setting_get_elem(s, (unsigned int)k), marker);
  }
}

/* Marks s and its parents as used. */
static void mark_used(const pom_cfg *cfg, config_setting_t *s) {
  for (config_setting_t *p = s; p; p = config_setting_parent(p))
    config_setting_set_hook(p, (void *)cfg);
}

static void value_text(const config_setting_t *s, char *buf, size_t cap) {
  switch (config_setting_type(s)) {
  case CONFIG_TYPE_INT:
  case CONFIG_TYPE_INT64:
    snprintf(buf, cap, "%lld", config_setting_get_int64(s));
    break;
  case CONFIG_TYPE_FLOAT: {
    /* shortest of %.15g / %.17g that reads back exactly */
    double v = config_setting_get_float(s);
    snprintf(buf, cap, "%.15g", v);
    if (strtod(buf, NULL) != v) snprintf(buf, cap, "%.17g", v);
  } break;
  case CONFIG_TYPE_BOOL:
    snprintf(buf, cap, "%s", config_setting_get_bool(s) ? "true" : "false");
    break;
  case CONFIG_TYPE_STRING:
    snprintf(buf, cap, "\"%s\"", config_setting_get_string(s));
    break;
  case CONFIG_TYPE_GROUP:
    snprintf(buf, cap, "{group}");
    break;
  case CONFIG_TYPE_ARRAY:
    snprintf(buf, cap, "[array of %d]", config_setting_length(s));
    break;
  case CONFIG_TYPE_LIST:
    snprintf(buf, cap, "(list of %d)", config_setting_length(s));
    break;
  default:
    snprintf(buf, cap, "?");
  }
}

static const char *type_name(int t) {
  switch (t) {
  case CONFIG_TYPE_GROUP:
    return "a group";
  case CONFIG_TYPE_INT:
  case CONFIG_TYPE_INT64:
    return "an integer";
  case CONFIG_TYPE_FLOAT:
    return "a real number";
  case CONFIG_TYPE_STRING:
    return "a string";
  case CONFIG_TYPE_BOOL:
    return "a boolean";
  case CONFIG_TYPE_ARRAY:
    return "an array";
  case CONFIG_TYPE_LIST:
    return "a list";
  default:
    return "nothing";
  }
}

/* The deepest existing group on the path of a (missing) dotted key, NULL
 * when none is (the root has no line). */
static const config_setting_t *nearest_parent(const pom_cfg *cfg, const char *key) {
  char path[512];
  snprintf(path, sizeof path, "%s", key);
  for (char *dot = strrchr(path, '.'); dot; dot = strrchr(path, '.')) {
    *dot = '\0';
    const config_setting_t *g = config_lookup(&cfg->lc, path);
    if (g && config_setting_source_line(g) > 0) return g;
  }
  return NULL;
}

static pom_status setting_error(const pom_cfg *cfg, const config_setting_t *s, const char *key,
                                pom_error *err, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;

static pom_status setting_error(const pom_cfg *cfg, const config_setting_t *s, const char *key,
                                pom_error *err, const char *fmt, ...) {
  char what[512], val[128];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(what, sizeof what, fmt, ap);
  va_end(ap);
  if (s) {
    value_text(s, val, sizeof val);
    const char *opt = override_origin(cfg, s);
    if (opt)
      return pom_error_set(err, POM_ERR_CONFIG, __FILE__, __LINE__,
                           "command line %s: key '%s' = %s: %s", opt, key, val, what);
    return pom_error_set(err, POM_ERR_CONFIG, __FILE__, __LINE__, "%s:%d: key '%s' = %s: %s",
                         setting_file(cfg, s), (int)config_setting_source_line(s), key, val, what);
  }
  /* A missing key: point at the group that should hold it, when it exists. */
  const config_setting_t *g = nearest_parent(cfg, key);
  if (g)
    return pom_error_set(err, POM_ERR_CONFIG, __FILE__, __LINE__, "%s:%d: key '%s': %s",
                         setting_file(cfg, g), (int)config_setting_source_line(g), key, what);
  return pom_error_set(err, POM_ERR_CONFIG, __FILE__, __LINE__, "%s: key '%s': %s", cfg->path, key,
                       what);
}

/* The setting at a dotted key ("group.sub.key", "list.[2].key"), NULL when
 * absent: groups walked by name with a plain comparison, elements by index.
 * libconfig's config_lookup finds the same setting, but its member search
 * compares names through a strchr per character (about 2 800 instructions
 * per key): with every catalog file read at each start that was a third of
 * a `pomlab model`'s start-up (bench/README.md, "Old vs new, 2026-11-29").
 * Any other path syntax (':' or '/' separators, empty parts, an index that
 * is not plain digits) goes to libconfig. */
static config_setting_t *lookup(const pom_cfg *cfg, const char *key) {
  if (!key[0] || strpbrk(key, ":/")) return config_lookup(&cfg->lc, key);
  config_setting_t *s = config_root_setting(&cfg->lc);
  for (const char *p = key;;) {
    const char *dot = strchr(p, '.');
    size_t n = dot ? (size_t)(dot - p) : strlen(p);
    config_setting_t *found = NULL;
    if (n >= 3 && p[0] == '[' && p[n - 1] == ']' && strspn(p + 1, "0123456789") == n - 2 &&
        n - 2 <= 9) {
      unsigned idx = 0;
      for (size_t i = 1; i < n - 1; ++i)
        idx = 10 * idx + (unsigned)(p[i] - '0');
      found = config_setting_get_elem(s, idx);
    } else {
      if (n == 0 || memchr(p, '[', n) || memchr(p, ']', n)) return config_lookup(&cfg->lc, key);
      if (config_setting_type(s) != CONFIG_TYPE_GROUP) return NULL;
      for (int i = 0, len = config_setting_length(s); i < len && !found; ++i) {
        config_setting_t *e = config_setting_get_elem(s, (unsigned)i);
        const char *name = config_setting_name(e);
        if (name && strncmp(name, p, n) == 0 && name[n] == '\0') found = e;
      }
    }
    if (!found || !dot) return found;
    s = found;
    p = dot + 1;
  }
}

static int is_number(const config_setting_t *s) {
  int t = config_setting_type(s);
  return t == CONFIG_TYPE_INT || t == CONFIG_TYPE_INT64 || t == CONFIG_TYPE_FLOAT;
}

static double number_of(const config_setting_t *s) {
  return config_setting_type(s) == CONFIG_TYPE_FLOAT ? config_setting_get_float(s)
                                                     : (double)config_setting_get_int64(s);
}

/* ---- load ------------------------------------------------------------------- */
static pom_status finish_load(pom_cfg *cfg, int ok, pom_error *err) {
  if (!ok) {
    const char *f = config_error_file(&cfg->lc);
    pom_status st =
        pom_error_set(err, POM_ERR_CONFIG, __FILE__, __LINE__, "%s:%d: %s", shown_file(cfg, f),
                      config_error_line(&cfg->lc),
                      config_error_text(&cfg->lc) ? config_error_text(&cfg->lc) : "cannot read");
    return st;
  }
  return POM_OK;
}

/* The file name of a line that is an @include (after its opening quote),
 * NULL for any other line. */
static const char *include_target(const char *line) {
  while (*line == ' ' || *line == '\t')
    ++line;
  if (strncmp(line, "@include", 8) != 0) return NULL;
  line += 8;
  while (*line == ' ' || *line == '\t')
    ++line;
  if (*line != '"') return NULL;
  return line + 1;
}

static int has_absolute_include(const char *text) {
  for (const char *line = text; line; line = strchr(line, '\n')) {
    if (*line == '\n') ++line;
    const char *t = include_target(line);
    if (t && *t == '/') return 1;
  }
  return 0;
}

/* Remembers that libconfig will call the absolute include `written` by the
 * name `rewritten` (both copied). */
static int add_renamed(pom_cfg *cfg, const char *rewritten, size_t n_rewritten, const char *written,
                       size_t n_written) {
  if (cfg->n_renamed == MAX_RENAMED) return 0; /* messages show the rewritten name */
  char *from = malloc(n_rewritten + 1), *to = malloc(n_written + 1);
  if (!from || !to) {
    free(from);
    free(to);
    return -1;
  }
  memcpy(from, rewritten, n_rewritten);
  from[n_rewritten] = '\0';
  memcpy(to, written, n_written);
  to[n_written] = '\0';
  cfg->renamed_from[cfg->n_renamed] = from;
  cfg->renamed_to[cfg->n_renamed] = to;
  ++cfg->n_renamed;
  return 0;
}

/* Copy of text with every absolute @include path made relative to dir (an
 * absolute folder is reached by one "../" per component of dir); each
 * rewritten name is remembered so that messages show the name as written. */
static char *rewrite_absolute_includes(pom_cfg *cfg, const char *text, const char *dir) {
  char absdir[4096];
  if (!realpath(dir, absdir)) snprintf(absdir, sizeof absdir, "%s", dir);
  size_t ups = 0;
  for (const char *c = absdir; *c; ++c)
    if (*c == '/' && c[1] != '\0' && c[1] != '/') ++ups;
  size_t n_inc = 0;
  for (const char *line = text; line; line = strchr(line + 1, '\n'))
    ++n_inc;
  size_t cap = strlen(text) + n_inc * (3 * ups + 1) + 1;
  char *out = malloc(cap);
  if (!out) return NULL;
  size_t w = 0;
  const char *p = text;
  while (*p) {
    const char *t = include_target(p);
    if (t && *t == '/') {
      memcpy(out + w, p, (size_t)(t - p));
      w += (size_t)(t - p);
      size_t name_at = w;
      for (size_t k = 0; k < ups; ++k) {
        memcpy(out + w, "../", 3);
        w += 3;
      }
      const char *close = strchr(t, '"');
      size_t n_written = close ? (size_t)(close - t) : strlen(t);
      size_t n_rewritten = (w - name_at) + n_written - 1;
      memcpy(out + w, t + 1, n_written - 1);
      if (add_renamed(cfg, out + name_at, n_rewritten, t, n_written) != 0) {
        free(out);
        return NULL;
      }
      p = t + 1; /* drop the leading slash */
    }
    const char *nl = strchr(p, '\n');
    size_t len = nl ? (size_t)(nl - p) + 1 : strlen(p);
    memcpy(out + w, p, len);
    w += len;
    p += len;
  }
  out[w] = '\0';
  return out;
}

/* What a path that is not a regular file is, for messages. */
static const char *file_kind(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

/* Opens a config file for reading: only a regular file of at most
 * POM_CFG_MAX_BYTES. The open does not wait for a writer (a FIFO would block
 * it), and *size gets the file's size. `shown` names it in messages. */
static pom_status open_config_file(const char *path, const char *shown, int *fd_out, off_t *size,
                                   pom_error *err) {
  *fd_out = -1;
  int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) POM_FAIL(err, POM_ERR_IO, "%s: cannot open config file: %s", shown, strerror(errno));
  struct stat sb;
  if (fstat(fd, &sb) != 0) {
    int e = errno;
    close(fd);
    POM_FAIL(err, POM_ERR_IO, "%s: cannot open config file: %s", shown, strerror(e));
  }
  if (S_ISDIR(sb.st_mode)) {
    close(fd);
    POM_FAIL(err, POM_ERR_IO, "%s: is a directory, not a config file", shown);
  }
  if (!S_ISREG(sb.st_mode)) {
    close(fd);
    POM_FAIL(err, POM_ERR_CONFIG, "%s: is %s, not a config file: a config must be a regular file",
             shown, file_kind(sb.st_mode));
  }
  if (sb.st_size > POM_CFG_MAX_BYTES) {
    close(fd);
    POM_FAIL(err, POM_ERR_CONFIG,
             "%s: %lld bytes, larger than a config file may be (at most %d bytes, %d MiB)", shown,
             (long long)sb.st_size, POM_CFG_MAX_BYTES, POM_CFG_MAX_BYTES >> 20);
  }
  /* reads stay non-blocking: a plain file ignores it, and a "regular" file of
   * the kernel's that would block (/proc/kmsg) fails its read with EAGAIN
   * instead of hanging (found by the fuzz targets, docs/fuzzing.md) */
  *fd_out = fd;
  *size = sb.st_size;
  return POM_OK;
}

/* Reads a whole config file (a regular file of at most POM_CFG_MAX_BYTES)
 * into *text, malloc'ed and NUL-terminated. `shown` names it in messages. */
static pom_status read_whole_file(const char *path, const char *shown, char **text,
                                  pom_error *err) {
  *text = NULL;
  int fd = -1;
  off_t size = 0;
  POM_TRY(open_config_file(path, shown, &fd, &size, err));
  FILE *fp = fdopen(fd, "rb");
  if (!fp) {
    int e = errno;
    close(fd);
    POM_FAIL(err, POM_ERR_IO, "%s: cannot open config file: %s", shown, strerror(e));
  }
  /* the size from fstat, plus room to see a file that grew past the bound */
  size_t cap = (size_t)size + 4096, n = 0;
  char *buf = malloc(cap);
  while (buf) {
    n += fread(buf + n, 1, cap - 1 - n, fp);
    if (n < cap - 1 || n > (size_t)POM_CFG_MAX_BYTES) break;
    char *grown = realloc(buf, 2 * cap);
    if (!grown) {
      free(buf);
      buf = NULL;
    } else {
      buf = grown;
      cap *= 2;
    }
  }
  int bad = buf && ferror(fp), read_errno = errno;
  fclose(fp);
  if (!buf) POM_FAIL(err, POM_ERR_NOMEM, "%s: out of memory", shown);
  if (bad) {
    free(buf);
    if (read_errno == EAGAIN || read_errno == EWOULDBLOCK)
      POM_FAIL(err, POM_ERR_CONFIG,
               "%s: reading it would block (a file of the kernel's, not a config file)", shown);
    POM_FAIL(err, POM_ERR_IO, "%s: cannot read: %s", shown, strerror(read_errno));
  }
  if (n > (size_t)POM_CFG_MAX_BYTES) {
    free(buf);
    POM_FAIL(err, POM_ERR_CONFIG,
             "%s: larger than a config file may be (at most %d bytes, %d MiB; it grew while "
             "read)",
             shown, POM_CFG_MAX_BYTES, POM_CFG_MAX_BYTES >> 20);
  }
  buf[n] = '\0';
  /* libconfig reads on past a NUL byte where pomlab's own scans of the text
   * stop: an @include after one would skip the checks of scan_file (a folder
   * named that way ends the process inside libconfig's scanner) */
  const char *nul = memchr(buf, '\0', n);
  if (nul) {
    int line = 1;
    for (const char *c = buf; c < nul; ++c)
      line += *c == '\n';
    size_t at = (size_t)(nul - buf);
    free(buf);
    POM_FAIL(err, POM_ERR_CONFIG, "%s:%d: byte %zu is a NUL: a config file is text", shown, line,
             at);
  }
  *text = buf;
  return POM_OK;
}

/* Adds a file read for this config to its list (pom_cfg_file). */
static pom_status add_file(pom_cfg *cfg, const char *path, pom_error *err) {
  if (cfg->n_files == MAX_FILES) return POM_OK; /* listed up to MAX_FILES */
  cfg->files[cfg->n_files] = dup_string(path);
  if (!cfg->files[cfg->n_files]) POM_FAIL(err, POM_ERR_NOMEM, "%s: out of memory", path);
  ++cfg->n_files;
  return POM_OK;
}

/* ---- nesting ------------------------------------------------------------------ */
/* The line where groups, lists and arrays first nest deeper than
 * POM_CFG_MAX_NESTING in text (strings and comments skipped), 0 when they
 * never do. libconfig 1.5's parser gives up near 9000 levels with "memory
 * exhausted", which names neither the line nor the rule. */
static int too_deep_line(const char *text) {
  int line = 1, depth = 0;
  for (const char *p = text; *p; ++p) {
    char c = *p;
    if (c == '\n') {
      ++line;
    } else if (c == '"') {
      for (++p; *p && *p != '"'; ++p) {
        if (*p == '\\' && p[1]) ++p;
        if (*p == '\n') ++line;
      }
      if (!*p) break;
    } else if (c == '#' || (c == '/' && p[1] == '/')) {
      while (p[1] && p[1] != '\n')
        ++p;
    } else if (c == '/' && p[1] == '*') {
      for (p += 2; *p && !(*p == '*' && p[1] == '/'); ++p)
        if (*p == '\n') ++line;
      if (!*p) break;
      ++p;
    } else if (c == '{' || c == '(' || c == '[') {
      if (++depth > POM_CFG_MAX_NESTING) return line;
    } else if (c == '}' || c == ')' || c == ']') {
      if (depth > 0) --depth;
    }
  }
  return 0;
}

/* ---- integers that libconfig 1.5 would not keep ------------------------------ */
/* libconfig 1.5 reads an integer without the L suffix into 32 bits, silently
 * wrapped or clamped (5000000000 becomes 705032704), and one with L into 64
 * bits, clamped. The literals are found in the text (strings and comments
 * skipped) before parsing, and refused after it with the key they belong
 * to. */
typedef struct {
  int found;
  int in_main;        /* 1: in the main file */
  char lc_file[1024]; /* else the file as libconfig names it */
  char file[512];     /* file as the user wrote it */
  int line;
  int index;        /* integer literals before it on its line (the settings' order) */
  char literal[64]; /* as written */
  int bits;         /* 32: needs the L suffix; 64: too large for any integer */
} int_problem;

/* Checks one integer literal [p, end) (sign, digits, suffix included). */
static int literal_overflows(const char *p, const char *end, int *bits) {
  char buf[80];
  size_t n = (size_t)(end - p);
  if (n >= sizeof buf) n = sizeof buf - 1; /* longer than any 64-bit literal: overflows */
  memcpy(buf, p, n);
  buf[n] = '\0';
  int is64 = n > 0 && buf[n - 1] == 'L';
  const char *digits = buf + (buf[0] == '-' || buf[0] == '+');
  int hex = digits[0] == '0' && (digits[1] == 'x' || digits[1] == 'X');
  errno = 0;
  if (hex) {
    unsigned long long v = strtoull(digits, NULL, 16);
    if (errno == ERANGE || (end - p) >= (long)sizeof buf) return *bits = 64, 1;
    if (!is64 && v > 0x7fffffffULL) return *bits = 32, 1;
    return 0;
  }
  long long v = strtoll(buf, NULL, 10);
  if (errno == ERANGE || (end - p) >= (long)sizeof buf) return *bits = 64, 1;
  if (!is64 && (v > 2147483647LL || v < -2147483648LL)) return *bits = 32, 1;
  return 0;
}

static int is_ident_char(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' ||
         c == '*' || c == '-';
}

static int is_digit(char c) {
  return c >= '0' && c <= '9';
}

/* Finds the first integer literal of text that overflows (fills prob). */
static void scan_integers(const char *text, int_problem *prob) {
  int line = 1, on_line = 0;
  const char *p = text;
  while (*p && !prob->found) {
    char c = *p;
    if (c == '\n') {
      ++line;
      on_line = 0;
      ++p;
    } else if (c == '"') { /* a string, with escapes */
      for (++p; *p && *p != '"'; ++p) {
        if (*p == '\\' && p[1]) ++p;
        if (*p == '\n') {
          ++line;
          on_line = 0;
        }
      }
      if (*p) ++p;
    } else if (c == '#' || (c == '/' && p[1] == '/') || c == '@') {
      while (*p && *p != '\n')
        ++p;
    } else if (c == '/' && p[1] == '*') {
      for (p += 2; *p && !(*p == '*' && p[1] == '/'); ++p)
        if (*p == '\n') {
          ++line;
          on_line = 0;
        }
      if (*p) p += 2;
    } else if ((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_' || c == '*') {
      while (is_ident_char(*p))
        ++p;
    } else if (is_digit(c) || ((c == '-' || c == '+') && is_digit(p[1]))) {
      const char *start = p;
      if (c == '-' || c == '+') ++p;
      int hex = p[0] == '0' && (p[1] == 'x' || p[1] == 'X');
      int real = 0;
      if (hex) {
        for (p += 2; is_digit(*p) || (*p >= 'a' && *p <= 'f') || (*p >= 'A' && *p <= 'F'); ++p)
          ;
      } else {
        while (is_digit(*p))
          ++p;
        if (*p == '.' || *p == 'e' || *p == 'E') { /* a real number */
          real = 1;
          while (is_digit(*p) || *p == '.' || *p == 'e' || *p == 'E' ||
                 ((*p == '-' || *p == '+') && (p[-1] == 'e' || p[-1] == 'E')))
            ++p;
        }
      }
      if (real) continue;
      if (*p == 'L') ++p;
      if (*p == 'L') ++p;
      int bits = 0;
      if (!literal_overflows(start, p, &bits)) {
        ++on_line;
      } else {
        prob->found = 1;
        prob->line = line;
        prob->index = on_line;
        prob->bits = bits;
        size_t n = (size_t)(p - start);
        if (n >= sizeof prob->literal) n = sizeof prob->literal - 1;
        memcpy(prob->literal, start, n);
        prob->literal[n] = '\0';
      }
    } else {
      ++p;
    }
  }
}

/* The integer setting of prob's literal: on prob's line of prob's file, the
 * one after prob->index others there (depth first is the order of the text,
 * so `b = 1; c = 5000000000;` names c, not b). *seen counts the integer
 * settings of that line met so far. */
static const config_setting_t *find_int_setting(const pom_cfg *cfg, const config_setting_t *s,
                                                const int_problem *prob, int *seen) {
  int t = config_setting_type(s);
  if ((t == CONFIG_TYPE_INT || t == CONFIG_TYPE_INT64) &&
      (int)config_setting_source_line(s) == prob->line) {
    const char *f = config_setting_source_file(s);
    int main_file = !f || strcmp(f, cfg->path) == 0;
    if ((prob->in_main ? main_file : (f && strcmp(f, prob->lc_file) == 0)) &&
        (*seen)++ == prob->index)
      return s;
  }
  if (config_setting_is_aggregate(s)) {
    int n = config_setting_length(s);
    for (int k = 0; k < n; ++k) {
      const config_setting_t *hit =
          find_int_setting(cfg, config_setting_get_elem(s, (unsigned int)k), prob, seen);
      if (hit) return hit;
    }
  }
  return NULL;
}

static void setting_path(const config_setting_t *s, char *buf, size_t cap);

static pom_status report_int_problem(const pom_cfg *cfg, const int_problem *prob, pom_error *err) {
  char key[512] = "", what[600];
  int seen = 0;
  const config_setting_t *s = find_int_setting(cfg, config_root_setting(&cfg->lc), prob, &seen);
  if (s) {
    char path[480];
    setting_path(s, path, sizeof path);
    snprintf(key, sizeof key, "key '%s' = ", path);
  }
  if (prob->bits == 32)
    snprintf(what, sizeof what,
             "%s: integers without the L suffix are 32-bit in libconfig and this one would be "
             "read as %lld; write %sL",
             prob->literal, s ? (long long)config_setting_get_int64(s) : 0LL, prob->literal);
  else
    snprintf(what, sizeof what, "%s: does not fit a 64-bit integer (at most 9223372036854775807)",
             prob->literal);
  return pom_error_set(err, POM_ERR_CONFIG, __FILE__, __LINE__, "%s:%d: %s%s", prob->file,
                       prob->line, key, what);
}

/* ---- @include targets ---------------------------------------------------------- */
/* libconfig 1.5 exits the process ("input in flex scanner failed") when an
 * @include names a folder, and resolves every relative include (nested ones
 * too) against the main file's folder. Each target is checked first, as the
 * user wrote it, and every included text is scanned for integers. */
static pom_status scan_file(pom_cfg *cfg, const char *lc_file, const char *shown, const char *text,
                            int depth, int_problem *prob, pom_error *err) {
  int deep = too_deep_line(text);
  if (deep)
    POM_FAIL(err, POM_ERR_CONFIG,
             "%s:%d: groups, lists and arrays nested deeper than %d levels (a config needs a "
             "few)",
             shown, deep, POM_CFG_MAX_NESTING);
  if (!prob->found) {
    scan_integers(text, prob);
    if (prob->found) {
      prob->in_main = depth == 0;
      snprintf(prob->lc_file, sizeof prob->lc_file, "%s", lc_file ? lc_file : "");
      snprintf(prob->file, sizeof prob->file, "%s", shown);
    }
  }
  int line = 0;
  for (const char *p = text; p; p = strchr(p, '\n')) {
    if (*p == '\n') ++p;
    ++line;
    const char *t = include_target(p);
    if (!t) continue;
    const char *close = strchr(t, '"');
    const char *nl = strchr(t, '\n');
    if (!close || (nl && close > nl)) continue; /* libconfig's own syntax error */
    char name[1024], resolved[2100];
    size_t n = (size_t)(close - t);
    if (n >= sizeof name)
      POM_FAIL(err, POM_ERR_CONFIG, "%s:%d: @include: file name longer than %zu characters", shown,
               line, sizeof name - 1);
    memcpy(name, t, n);
    name[n] = '\0';
    if (n == 0) POM_FAIL(err, POM_ERR_CONFIG, "%s:%d: @include \"\": empty file name", shown, line);
    if (name[0] == '/' && depth > 0)
      POM_FAIL(err, POM_ERR_CONFIG,
               "%s:%d: @include \"%s\": an absolute path is only allowed in the main config "
               "file; write it relative to %s",
               shown, line, name, cfg->dir ? cfg->dir : ".");
    if (depth + 1 > MAX_INCLUDE_DEPTH)
      POM_FAIL(err, POM_ERR_CONFIG,
               "%s:%d: @include \"%s\": includes nested deeper than %d (does a file include "
               "itself?)",
               shown, line, name, MAX_INCLUDE_DEPTH);
    const char *dir = cfg->dir ? cfg->dir : ".";
    size_t dl = strlen(dir);
    if (name[0] == '/')
      snprintf(resolved, sizeof resolved, "%s", name);
    else
      snprintf(resolved, sizeof resolved, "%s%s%s", dir, dl && dir[dl - 1] == '/' ? "" : "/", name);
    char *inc = NULL;
    pom_status st = read_whole_file(resolved, resolved, &inc, err);
    if (st != POM_OK) {
      pom_error_prefix(err, "%s:%d: @include \"%s\"", shown, line, name);
      return st;
    }
    st = add_file(cfg, resolved, err);
    if (st != POM_OK) {
      free(inc);
      return st;
    }
    /* the name libconfig will report for the included settings */
    const char *lc_name = NULL;
    for (int k = 0; k < cfg->n_renamed && !lc_name; ++k)
      if (depth == 0 && strcmp(cfg->renamed_to[k], name) == 0) lc_name = cfg->renamed_from[k];
    st = scan_file(cfg, lc_name ? lc_name : name, name, inc, depth + 1, prob, err);
    free(inc);
    POM_TRY(st);
  }
  return POM_OK;
}

static pom_cfg *cfg_alloc(const char *path) {
  pom_cfg *cfg = calloc(1, sizeof *cfg);
  if (!cfg) return NULL;
  config_init(&cfg->lc);
  config_set_auto_convert(&cfg->lc, 0);
  cfg->path = dup_string(path);
  if (!cfg->path) {
    pom_cfg_destroy(cfg);
    return NULL;
  }
  return cfg;
}

pom_status pom_cfg_load(pom_cfg **out, const char *path, pom_error *err) {
  pom_status st = POM_OK;
  if (!out || !path) POM_FAIL(err, POM_ERR_ARG, "pom_cfg_load: NULL argument");
  *out = NULL;
  char *parsed = NULL;
  pom_cfg *cfg = cfg_alloc(path);
  if (!cfg) POM_FAIL(err, POM_ERR_NOMEM, "loading config '%s'", path);
  POM_TRY_GOTO(read_whole_file(path, path, &cfg->text, err), fail);
  POM_TRY_GOTO(add_file(cfg, path, err), fail);
  cfg->dir = dup_string(path);
  if (!cfg->dir) POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "%s: out of memory", path);
  char *slash = strrchr(cfg->dir, '/');
  if (slash) {
    slash[1] = '\0';
  } else {
    strcpy(cfg->dir, ".");
  }
  config_set_include_dir(&cfg->lc, cfg->dir);
  if (has_absolute_include(cfg->text)) {
    /* libconfig 1.5 prefixes the include folder even to absolute paths:
     * parse a copy whose absolute includes are rewritten relative to the
     * folder (same lines, so messages keep their line numbers). */
    parsed = rewrite_absolute_includes(cfg, cfg->text, cfg->dir);
    if (!parsed) POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "%s: out of memory", path);
  }
  int_problem prob;
  memset(&prob, 0, sizeof prob);
  POM_TRY_GOTO(scan_file(cfg, NULL, path, cfg->text, 0, &prob, err), fail);
  if (parsed)
    POM_TRY_GOTO(finish_load(cfg, config_read_string(&cfg->lc, parsed), err), fail);
  else
    POM_TRY_GOTO(finish_load(cfg, config_read_file(&cfg->lc, path), err), fail);
  if (prob.found) POM_TRY_GOTO(report_int_problem(cfg, &prob, err), fail);
  free(parsed);
  *out = cfg;
  return POM_OK;
fail:
  free(parsed);
  pom_cfg_destroy(cfg);
  return st;
}

pom_status pom_cfg_load_string(pom_cfg **out, const char *text, const char *name, pom_error *err) {
  pom_status st = POM_OK;
  if (!out || !text || !name) POM_FAIL(err, POM_ERR_ARG, "pom_cfg_load_string: NULL argument");
  *out = NULL;
  pom_cfg *cfg = cfg_alloc(name);
  if (!cfg) POM_FAIL(err, POM_ERR_NOMEM, "loading config '%s'", name);
  cfg->text = dup_string(text);
  if (!cfg->text) POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "%s: out of memory", name);
  int_problem prob;
  memset(&prob, 0, sizeof prob);
  POM_TRY_GOTO(scan_file(cfg, NULL, name, text, 0, &prob, err), fail);
  POM_TRY_GOTO(finish_load(cfg, config_read_string(&cfg->lc, text), err), fail);
  if (prob.found) POM_TRY_GOTO(report_int_problem(cfg, &prob, err), fail);
  *out = cfg;
  return POM_OK;
fail:
  pom_cfg_destroy(cfg);
  return st;
}

void pom_cfg_destroy(pom_cfg *cfg) {
  if (!cfg) return;
  config_destroy(&cfg->lc);
  free(cfg->path);
  free(cfg->dir);
  free(cfg->text);
  for (int k = 0; k < cfg->n_renamed; ++k) {
    free(cfg->renamed_from[k]);
    free(cfg->renamed_to[k]);
  }
  for (int k = 0; k < cfg->n_files; ++k)
    free(cfg->files[k]);
  free(cfg);
}

const char *pom_cfg_path(const pom_cfg *cfg) {
  return cfg->path;
}
const char *pom_cfg_text(const pom_cfg *cfg) {
  return cfg->text ? cfg->text : "";
}

int pom_cfg_n_files(const pom_cfg *cfg) {
  return cfg->n_files;
}

const char *pom_cfg_file(const pom_cfg *cfg, int k) {
  return k >= 0 && k < cfg->n_files ? cfg->files[k] : NULL;
}

int pom_cfg_has(const pom_cfg *cfg, const char *key) {
  return lookup(cfg, key) != NULL;
}

int pom_cfg_is_list(const pom_cfg *cfg, const char *key) {
  config_setting_t *s = lookup(cfg, key);
  return s && config_setting_is_list(s);
}

int pom_cfg_length(const pom_cfg *cfg, const char *key) {
  config_setting_t *s = lookup(cfg, key);
  if (!s || !config_setting_is_aggregate(s)) return 0;
  return config_setting_length(s);
}

const char *pom_cfg_member_name(const pom_cfg *cfg, const char *key, int k) {
  config_setting_t *s = lookup(cfg, key);
  if (!s || !config_setting_is_group(s) || k < 0 || k >= config_setting_length(s)) return NULL;
  return config_setting_name(config_setting_get_elem(s, (unsigned int)k));
}

void pom_cfg_mark_used(const pom_cfg *cfg, const char *key) {
  config_setting_t *s = lookup(cfg, key);
  if (!s) return;
  mark_tree(s, (void *)cfg);
  mark_used(cfg, s);
}

int pom_cfg_line(const pom_cfg *cfg, const char *key) {
  config_setting_t *s = lookup(cfg, key);
  return s ? (int)config_setting_source_line(s) : 0;
}

pom_status pom_cfg_error(const pom_cfg *cfg, const char *key, const char *value_txt, pom_error *err,
                         const char *fmt, ...) {
  char what[512];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(what, sizeof what, fmt, ap);
  va_end(ap);
  config_setting_t *s = lookup(cfg, key);
  char val[128];
  if (value_txt) {
    snprintf(val, sizeof val, "%s", value_txt);
  } else if (s) {
    value_text(s, val, sizeof val);
  } else {
    snprintf(val, sizeof val, "(absent)");
  }
  const char *opt = override_origin(cfg, s);
  if (opt)
    return pom_error_set(err, POM_ERR_CONFIG, __FILE__, __LINE__,
                         "command line %s: key '%s' = %s: %s", opt, key, val, what);
  const config_setting_t *at = s ? s : nearest_parent(cfg, key);
  if (!at)
    return pom_error_set(err, POM_ERR_CONFIG, __FILE__, __LINE__, "%s: key '%s' = %s: %s",
                         cfg->path, key, val, what);
  return pom_error_set(err, POM_ERR_CONFIG, __FILE__, __LINE__, "%s:%d: key '%s' = %s: %s",
                       setting_file(cfg, at), (int)config_setting_source_line(at), key, val, what);
}

/* ---- scalar getters ----------------------------------------------------------- */
static pom_status check_real(const pom_cfg *cfg, const config_setting_t *s, const char *key,
                             double to_si, double min, double max, double *out, pom_error *err) {
  if (!is_number(s))
    return setting_error(cfg, s, key, err, "expected a real number in [%g, %g], found %s", min, max,
                         type_name(config_setting_type(s)));
  double v = number_of(s);
  if (!isfinite(v) || v < min || v > max)
    return setting_error(cfg, s, key, err, "out of range: expected a value in [%g, %g]", min, max);
  *out = v * to_si;
  return POM_OK;
}

pom_status pom_cfg_real(const pom_cfg *cfg, const char *key, double to_si, double min, double max,
                        double *out, pom_error *err) {
  config_setting_t *s = lookup(cfg, key);
  if (!s)
    return setting_error(cfg, NULL, key, err, "missing: expected a real number in [%g, %g]", min,
                         max);
  mark_used(cfg, s);
  return check_real(cfg, s, key, to_si, min, max, out, err);
}

pom_status pom_cfg_real_opt(const pom_cfg *cfg, const char *key, double to_si, double min,
                            double max, double dflt_si, double *out, pom_error *err) {
  config_setting_t *s = lookup(cfg, key);
  if (!s) {
    *out = dflt_si;
    return POM_OK;
  }
  mark_used(cfg, s);
  return check_real(cfg, s, key, to_si, min, max, out, err);
}

pom_status pom_cfg_reals_var(const pom_cfg *cfg, const char *key, int max_n, double to_si,
                             double min, double max, double *out, int *n_out, pom_error *err) {
  config_setting_t *s = lookup(cfg, key);
  if (!s)
    return setting_error(cfg, NULL, key, err, "missing: expected an array of up to %d reals",
                         max_n);
  mark_used(cfg, s);
  mark_tree(s, (void *)cfg);
  int t = config_setting_type(s);
  if (t != CONFIG_TYPE_ARRAY && t != CONFIG_TYPE_LIST)
    return setting_error(cfg, s, key, err, "expected an array [a, b, ...] of reals, found %s",
                         type_name(t));
  int n = config_setting_length(s);
  if (n < 1 || n > max_n)
    return setting_error(cfg, s, key, err, "expected 1 to %d elements, found %d", max_n, n);
  for (int k = 0; k < n; ++k) {
    config_setting_t *e = config_setting_get_elem(s, (unsigned int)k);
    char ekey[256];
    snprintf(ekey, sizeof ekey, "%s[%d]", key, k);
    POM_TRY(check_real(cfg, e, ekey, to_si, min, max, &out[k], err));
  }
  *n_out = n;
  return POM_OK;
}

pom_status pom_cfg_reals(const pom_cfg *cfg, const char *key, int n, double to_si, double min,
                         double max, double *out, pom_error *err) {
  int got = 0;
  config_setting_t *s = lookup(cfg, key);
  if (s && config_setting_is_aggregate(s) && config_setting_length(s) != n) {
    mark_used(cfg, s);
    return setting_error(cfg, s, key, err, "expected exactly %d reals, found %d elements", n,
                         config_setting_length(s));
  }
  return pom_cfg_reals_var(cfg, key, n, to_si, min, max, out, &got, err);
}

static pom_status check_int(const pom_cfg *cfg, const config_setting_t *s, const char *key,
                            long min, long max, long *out, pom_error *err) {
  int t = config_setting_type(s);
  if (t != CONFIG_TYPE_INT && t != CONFIG_TYPE_INT64)
    return setting_error(cfg, s, key, err, "expected an integer in [%ld, %ld], found %s", min, max,
                         type_name(t));
  long long v = config_setting_get_int64(s);
  if (v < min || v > max)
    return setting_error(cfg, s, key, err, "out of range: expected an integer in [%ld, %ld]", min,
                         max);
  *out = (long)v;
  return POM_OK;
}

pom_status pom_cfg_int(const pom_cfg *cfg, const char *key, long min, long max, long *out,
                       pom_error *err) {
  config_setting_t *s = lookup(cfg, key);
  if (!s)
    return setting_error(cfg, NULL, key, err, "missing: expected an integer in [%ld, %ld]", min,
                         max);
  mark_used(cfg, s);
  return check_int(cfg, s, key, min, max, out, err);
}

pom_status pom_cfg_int_opt(const pom_cfg *cfg, const char *key, long min, long max, long dflt,
                           long *out, pom_error *err) {
  config_setting_t *s = lookup(cfg, key);
  if (!s) {
    *out = dflt;
    return POM_OK;
  }
  mark_used(cfg, s);
  return check_int(cfg, s, key, min, max, out, err);
}

static pom_status check_bool(const pom_cfg *cfg, const config_setting_t *s, const char *key,
                             int *out, pom_error *err) {
  if (config_setting_type(s) != CONFIG_TYPE_BOOL)
    return setting_error(cfg, s, key, err, "expected true or false, found %s",
                         type_name(config_setting_type(s)));
  *out = config_setting_get_bool(s) ? 1 : 0;
  return POM_OK;
}

pom_status pom_cfg_bool(const pom_cfg *cfg, const char *key, int *out, pom_error *err) {
  config_setting_t *s = lookup(cfg, key);
  if (!s) return setting_error(cfg, NULL, key, err, "missing: expected true or false");
  mark_used(cfg, s);
  return check_bool(cfg, s, key, out, err);
}

pom_status pom_cfg_bool_opt(const pom_cfg *cfg, const char *key, int dflt, int *out,
                            pom_error *err) {
  config_setting_t *s = lookup(cfg, key);
  if (!s) {
    *out = dflt;
    return POM_OK;
  }
  mark_used(cfg, s);
  return check_bool(cfg, s, key, out, err);
}

static pom_status check_string(const pom_cfg *cfg, const config_setting_t *s, const char *key,
                               char *buf, size_t cap, pom_error *err) {
  if (config_setting_type(s) != CONFIG_TYPE_STRING)
    return setting_error(cfg, s, key, err, "expected a string, found %s",
                         type_name(config_setting_type(s)));
  const char *v = config_setting_get_string(s);
  if (strlen(v) >= cap)
    return setting_error(cfg, s, key, err, "string too long (at most %zu characters)", cap - 1);
  memcpy(buf, v, strlen(v) + 1);
  return POM_OK;
}

pom_status pom_cfg_string(const pom_cfg *cfg, const char *key, char *buf, size_t cap,
                          pom_error *err) {
  config_setting_t *s = lookup(cfg, key);
  if (!s) return setting_error(cfg, NULL, key, err, "missing: expected a string");
  mark_used(cfg, s);
  return check_string(cfg, s, key, buf, cap, err);
}

pom_status pom_cfg_string_opt(const pom_cfg *cfg, const char *key, const char *dflt, char *buf,
                              size_t cap, pom_error *err) {
  config_setting_t *s = lookup(cfg, key);
  if (!s) {
    if (strlen(dflt) >= cap) return setting_error(cfg, NULL, key, err, "default too long");
    memcpy(buf, dflt, strlen(dflt) + 1);
    return POM_OK;
  }
  mark_used(cfg, s);
  return check_string(cfg, s, key, buf, cap, err);
}

static pom_status check_choice(const pom_cfg *cfg, const config_setting_t *s, const char *key,
                               const char *const choices[], int *index, pom_error *err) {
  char list[512] = "";
  size_t used = 0;
  for (int k = 0; choices[k]; ++k) {
    int w = snprintf(list + used, sizeof list - used, "%s\"%s\"", k ? ", " : "", choices[k]);
    if (w < 0 || (size_t)w >= sizeof list - used) break;
    used += (size_t)w;
  }
  if (config_setting_type(s) != CONFIG_TYPE_STRING)
    return setting_error(cfg, s, key, err, "expected one of %s, found %s", list,
                         type_name(config_setting_type(s)));
  int k = pom_cfg_choice_index(choices, config_setting_get_string(s));
  if (k >= 0) {
    *index = k;
    return POM_OK;
  }
  return setting_error(cfg, s, key, err, "expected one of %s", list);
}

pom_status pom_cfg_choice(const pom_cfg *cfg, const char *key, const char *const choices[],
                          int *index, pom_error *err) {
  config_setting_t *s = lookup(cfg, key);
  if (!s) return setting_error(cfg, NULL, key, err, "missing: expected a string choice");
  mark_used(cfg, s);
  return check_choice(cfg, s, key, choices, index, err);
}

pom_status pom_cfg_choice_opt(const pom_cfg *cfg, const char *key, const char *const choices[],
                              int dflt, int *index, pom_error *err) {
  config_setting_t *s = lookup(cfg, key);
  if (!s) {
    *index = dflt;
    return POM_OK;
  }
  mark_used(cfg, s);
  return check_choice(cfg, s, key, choices, index, err);
}

const char *pom_cfg_choice_name(const char *const choices[], int index) {
  if (!choices || index < 0) return "?";
  for (int k = 0; choices[k]; ++k)
    if (k == index) return choices[k];
  return "?";
}

int pom_cfg_choice_index(const char *const choices[], const char *name) {
  if (!choices || !name) return -1;
  for (int k = 0; choices[k]; ++k)
    if (strcmp(choices[k], name) == 0) return k;
  return -1;
}

/* ---- config groups ------------------------------------------------------ */
void pom_cfg_groups_init(pom_cfg_groups *g) {
  memset(g, 0, sizeof *g);
}

pom_status pom_cfg_groups_add(pom_cfg_groups *g, const char *const *names, pom_error *err) {
  for (int k = 0; names && names[k]; ++k) {
    if (pom_cfg_choice_index(g->name, names[k]) >= 0) continue;
    if (g->n >= POM_CFG_MAX_GROUPS)
      POM_FAIL(err, POM_ERR_INTERNAL, "more than %d config groups", POM_CFG_MAX_GROUPS);
    g->name[g->n++] = names[k];
    g->name[g->n] = NULL;
  }
  return POM_OK;
}

/* ---- unknown keys ------------------------------------------------------------- */
static void setting_path(const config_setting_t *s, char *buf, size_t cap) {
  if (!s || config_setting_is_root(s)) {
    buf[0] = '\0';
    return;
  }
  char parent[512];
  setting_path(config_setting_parent(s), parent, sizeof parent);
  const char *name = config_setting_name(s);
  if (name) {
    snprintf(buf, cap, "%s%s%s", parent, parent[0] ? "." : "", name);
  } else {
    snprintf(buf, cap, "%s%s[%d]", parent, parent[0] ? "." : "", config_setting_index(s));
  }
}

static pom_status find_unused(const pom_cfg *cfg, config_setting_t *s, pom_error *err) {
  /* An unread group or list is reported by its first member, which names the
   * misspelt key rather than its (legitimate) parent. */
  if (config_setting_get_hook(s) != (void *)cfg && !config_setting_is_array(s) &&
      config_setting_is_aggregate(s) && config_setting_length(s) > 0)
    return find_unused(cfg, config_setting_get_elem(s, 0), err);
  if (config_setting_get_hook(s) != (void *)cfg) {
    char path[512];
    setting_path(s, path, sizeof path);
    return setting_error(cfg, s, path, err,
                         "unknown key (not used by this command; check its spelling against "
                         "docs/config.md)");
  }
  if (config_setting_is_group(s) || config_setting_is_list(s)) {
    int n = config_setting_length(s);
    for (int k = 0; k < n; ++k)
      POM_TRY(find_unused(cfg, config_setting_get_elem(s, (unsigned int)k), err));
  }
  return POM_OK;
}

static int in_list(const char *name, const char *const list[]) {
  for (int k = 0; list[k]; ++k)
    if (strcmp(name, list[k]) == 0) return 1;
  return 0;
}

/* The first override at or below s (NULL when none): a group an override
 * made is reported by the value that made it. */
static config_setting_t *override_below(const pom_cfg *cfg, config_setting_t *s) {
  if (override_origin(cfg, s)) return s;
  if (!config_setting_is_group(s)) return NULL;
  int n = config_setting_length(s);
  for (int k = 0; k < n; ++k) {
    config_setting_t *o = override_below(cfg, config_setting_get_elem(s, (unsigned int)k));
    if (o) return o;
  }
  return NULL;
}

pom_status pom_cfg_check_unknown(const pom_cfg *cfg, const char *const scopes[],
                                 const char *const known_top[], pom_error *err) {
  if (!cfg) POM_FAIL(err, POM_ERR_ARG, "pom_cfg_check_unknown: NULL argument");
  config_setting_t *root = config_root_setting(&cfg->lc);
  int n = config_setting_length(root);
  for (int k = 0; k < n; ++k) {
    config_setting_t *s = config_setting_get_elem(root, (unsigned int)k);
    const char *name = config_setting_name(s);
    config_setting_t *o = config_setting_source_line(s) == 0 ? override_below(cfg, s) : NULL;
    if (known_top && !in_list(name, known_top) && o) {
      char path[512];
      setting_path(o, path, sizeof path);
      return setting_error(cfg, o, path, err,
                           "unknown top-level key '%s' (check its spelling against "
                           "docs/config.md)",
                           name);
    }
    if (known_top && !in_list(name, known_top))
      return setting_error(cfg, s, name, err,
                           "unknown top-level key (check its spelling against docs/config.md)");
    if (scopes && !in_list(name, scopes)) continue;
    POM_TRY(find_unused(cfg, s, err));
  }
  return POM_OK;
}

pom_status pom_cfg_check_overrides(const pom_cfg *cfg, const char *const scopes[],
                                   const char *const skip[], pom_error *err) {
  if (!cfg) POM_FAIL(err, POM_ERR_ARG, "pom_cfg_check_overrides: NULL argument");
  for (int k = 0; k < cfg->n_overrides; ++k) {
    const config_setting_t *s = cfg->override_setting[k];
    if (!s || config_setting_get_hook(s) == (void *)cfg) continue;
    char path[512], top[512], list[512];
    setting_path(s, path, sizeof path);
    snprintf(top, sizeof top, "%s", path);
    char *dot = strchr(top, '.');
    if (dot) *dot = '\0';
    if (skip && in_list(top, skip)) continue;
    if (!scopes || in_list(top, scopes))
      return setting_error(cfg, s, path, err,
                           "unknown key (not used by this command; check its spelling against "
                           "docs/config.md)");
    list[0] = '\0';
    for (int j = 0; scopes[j]; ++j) {
      size_t used = strlen(list);
      snprintf(list + used, sizeof list - used, "%s%s", j ? ", " : "", scopes[j]);
    }
    return setting_error(cfg, s, path, err,
                         "not read by this command: it reads the groups %s, not '%s'", list, top);
  }
  return POM_OK;
}

/* ---- values from the command line ---------------------------------------------- */
/* Drops the origins of a setting about to be removed (its address may be
 * reused). */
static void forget_override(pom_cfg *cfg, const config_setting_t *s) {
  for (int k = 0; k < cfg->n_overrides; ++k)
    if (cfg->override_setting[k] == s) cfg->override_setting[k] = NULL;
}

static pom_status set_override(pom_cfg *cfg, const char *key, int type, long long iv, double rv,
                               const char *sv, const char *origin, pom_error *err);

/* A key an override may set: names as libconfig spells them (a letter or
 * '*', then letters, digits, '-', '_', '*'), joined by single dots. */
static pom_status check_override_key(const char *key, const char *origin, pom_error *err) {
  size_t n = strlen(key);
  int ok = n > 0 && n < 512;
  for (const char *c = key, *start = key; ok && c <= key + n; ++c) {
    if (*c == '.' || *c == '\0') {
      ok = c > start; /* no empty name */
      start = c + 1;
    } else if (c == start) {
      ok = (*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || *c == '*';
    } else {
      ok = (*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || is_digit(*c) || *c == '-' ||
           *c == '_' || *c == '*';
    }
  }
  if (!ok)
    POM_FAIL(err, POM_ERR_CONFIG,
             "command line %s: key '%s': not a config key (names of letters, digits, '-' and "
             "'_', starting with a letter, joined by single dots: \"controller.kp\")",
             origin, key);
  return POM_OK;
}

pom_status pom_cfg_set_number(pom_cfg *cfg, const char *key, const char *text, const char *origin,
                              pom_error *err) {
  if (!cfg || !key || !text || !origin)
    POM_FAIL(err, POM_ERR_ARG, "pom_cfg_set_number: NULL argument");
  POM_TRY(check_override_key(key, origin, err));
  /* the number as written: an integer (64-bit, never wrapped) or a real */
  const char *d = text + (text[0] == '-' || text[0] == '+');
  int integer = is_digit(d[0]);
  for (const char *c = d; *c && integer; ++c)
    integer = is_digit(*c);
  long long iv = 0;
  double rv = 0.0;
  char *end = NULL;
  errno = 0;
  if (integer) {
    iv = strtoll(text, &end, 10);
    if (errno == ERANGE)
      POM_FAIL(err, POM_ERR_CONFIG,
               "command line %s: key '%s' = %s: does not fit a 64-bit integer (at most "
               "9223372036854775807)",
               origin, key, text);
  } else {
    rv = strtod(text, &end);
    if (end == text || *end != '\0' || !isfinite(rv))
      POM_FAIL(err, POM_ERR_CONFIG, "command line %s: key '%s' = '%s': expected a number", origin,
               key, text);
  }
  return set_override(cfg, key, integer ? CONFIG_TYPE_INT64 : CONFIG_TYPE_FLOAT, iv, rv, NULL,
                      origin, err);
}

pom_status pom_cfg_set_string(pom_cfg *cfg, const char *key, const char *text, const char *origin,
                              pom_error *err) {
  if (!cfg || !key || !text || !origin)
    POM_FAIL(err, POM_ERR_ARG, "pom_cfg_set_string: NULL argument");
  return set_override(cfg, key, CONFIG_TYPE_STRING, 0, 0.0, text, origin, err);
}

/* Sets key (dotted, groups created) to one value of the given type, as
 * an override from `origin`. */
static pom_status set_override(pom_cfg *cfg, const char *key, int type, long long iv, double rv,
                               const char *sv, const char *origin, pom_error *err) {
  POM_TRY(check_override_key(key, origin, err));
  if (cfg->n_overrides == MAX_OVERRIDES)
    POM_FAIL(err, POM_ERR_ARG, "command line %s: more than %d values set on the command line",
             origin, MAX_OVERRIDES);
  /* the groups on the way, created when absent */
  config_setting_t *parent = config_root_setting(&cfg->lc);
  char path[512];
  snprintf(path, sizeof path, "%s", key);
  char *name = path;
  for (char *dot = strchr(name, '.'); dot; dot = strchr(name, '.')) {
    *dot = '\0';
    config_setting_t *g = config_setting_get_member(parent, name);
    if (!g) g = config_setting_add(parent, name, CONFIG_TYPE_GROUP);
    if (!g || !config_setting_is_group(g))
      return setting_error(cfg, g, path, err,
                           "command line %s sets '%s' below it: expected a group", origin, key);
    *dot = '.';
    parent = g;
    name = dot + 1;
  }
  config_setting_t *old = config_setting_get_member(parent, name);
  if (old) {
    forget_override(cfg, old);
    config_setting_remove(parent, name);
  }
  config_setting_t *s = config_setting_add(parent, name, type);
  int ok = s && (type == CONFIG_TYPE_INT64   ? config_setting_set_int64(s, iv)
                 : type == CONFIG_TYPE_FLOAT ? config_setting_set_float(s, rv)
                                             : config_setting_set_string(s, sv));
  if (!ok) POM_FAIL(err, POM_ERR_NOMEM, "command line %s: cannot set key '%s'", origin, key);
  cfg->override_setting[cfg->n_overrides] = s;
  snprintf(cfg->override_origin[cfg->n_overrides], sizeof cfg->override_origin[0], "%s", origin);
  ++cfg->n_overrides;
  return POM_OK;
}

/* ---- comparing two configs -------------------------------------------------------- */
/* The first difference below a and b (same path); 1 when one is found. */
static int diff_settings(const config_setting_t *a, const config_setting_t *b, char *key,
                         size_t key_cap, char *va, char *vb, size_t val_cap) {
  int ta = config_setting_type(a), tb = config_setting_type(b);
  int agg_a = config_setting_is_aggregate(a), agg_b = config_setting_is_aggregate(b);
  if (!agg_a || !agg_b || ta != tb) {
    value_text(a, va, val_cap);
    value_text(b, vb, val_cap);
    if (ta == tb && strcmp(va, vb) == 0) return 0;
    setting_path(a, key, key_cap);
    return 1;
  }
  int na = config_setting_length(a), nb = config_setting_length(b);
  if (ta == CONFIG_TYPE_GROUP) {
    /* members by name, either side */
    for (int side = 0; side < 2; ++side) {
      const config_setting_t *x = side ? b : a, *y = side ? a : b;
      int nx = side ? nb : na;
      for (int k = 0; k < nx; ++k) {
        const config_setting_t *e = config_setting_get_elem(x, (unsigned int)k);
        const config_setting_t *f = config_setting_get_member(y, config_setting_name(e));
        if (!f) {
          setting_path(e, key, key_cap);
          value_text(e, side ? vb : va, val_cap);
          snprintf(side ? va : vb, val_cap, "(absent)");
          return 1;
        }
        if (!side && diff_settings(e, f, key, key_cap, va, vb, val_cap)) return 1;
      }
    }
    return 0;
  }
  for (int k = 0; k < na && k < nb; ++k)
    if (diff_settings(config_setting_get_elem(a, (unsigned int)k),
                      config_setting_get_elem(b, (unsigned int)k), key, key_cap, va, vb, val_cap))
      return 1;
  if (na == nb) return 0;
  setting_path(a, key, key_cap);
  value_text(a, va, val_cap);
  value_text(b, vb, val_cap);
  return 1;
}

int pom_cfg_diff(const pom_cfg *a, const pom_cfg *b, char *key, size_t key_cap, char *value_a,
                 char *value_b, size_t value_cap) {
  key[0] = value_a[0] = value_b[0] = '\0';
  return diff_settings(config_root_setting(&a->lc), config_root_setting(&b->lc), key, key_cap,
                       value_a, value_b, value_cap);
}
