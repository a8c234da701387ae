/* pom_config.c - libconfig access with type, range and unknown-key checks. */
#define _XOPEN_SOURCE 700 /* realpath */
#include "pom_config.h"

#include <libconfig.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct pom_cfg {
  config_t lc; /* parsed tree */
  char *path;  /* file path or name */
  char *dir;   /* folder for @include, NULL for strings */
  char *text;  /* raw text of the main file */
};

/* ---- helpers ---------------------------------------------------------------- */
static char *dup_string(const char *s) {
  size_t n = strlen(s) + 1;
  char *d = malloc(n);
  if (d) memcpy(d, s, n);
  return d;
}

static const char *setting_file(const pom_cfg *cfg, const config_setting_t *s) {
  const char *f = s ? config_setting_source_file(s) : NULL;
  return f ? f : cfg->path;
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

static config_setting_t *lookup(const pom_cfg *cfg, const char *key) {
  return config_lookup(&cfg->lc, key);
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
        pom_error_set(err, POM_ERR_CONFIG, __FILE__, __LINE__, "%s:%d: %s", f ? f : cfg->path,
                      config_error_line(&cfg->lc),
                      config_error_text(&cfg->lc) ? config_error_text(&cfg->lc) : "cannot read");
    return st;
  }
  return POM_OK;
}

/* 1 when a line of text is an @include of an absolute path. */
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

/* Copy of text with every absolute @include path made relative to dir (an
 * absolute folder is reached by one "../" per component of dir). */
static char *rewrite_absolute_includes(const char *text, const char *dir) {
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
      for (size_t k = 0; k < ups; ++k) {
        memcpy(out + w, "../", 3);
        w += 3;
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
  *out = NULL;
  pom_cfg *cfg = cfg_alloc(path);
  FILE *fp = NULL;
  if (!cfg) POM_FAIL(err, POM_ERR_NOMEM, "loading config '%s'", path);
  fp = fopen(path, "rb");
  if (!fp) POM_FAIL_GOTO(err, POM_ERR_IO, fail, "%s: cannot open config file", path);
  if (fseek(fp, 0, SEEK_END) != 0) POM_FAIL_GOTO(err, POM_ERR_IO, fail, "%s: cannot read", path);
  long n = ftell(fp);
  if (n < 0 || fseek(fp, 0, SEEK_SET) != 0)
    POM_FAIL_GOTO(err, POM_ERR_IO, fail, "%s: cannot read", path);
  cfg->text = malloc((size_t)n + 1);
  if (!cfg->text) POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "%s: out of memory", path);
  if (fread(cfg->text, 1, (size_t)n, fp) != (size_t)n)
    POM_FAIL_GOTO(err, POM_ERR_IO, fail, "%s: cannot read", path);
  cfg->text[n] = '\0';
  fclose(fp);
  fp = NULL;
  cfg->dir = dup_string(path);
  if (!cfg->dir) POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "%s: out of memory", path);
  char *slash = strrchr(cfg->dir, '/');
  if (slash) {
    slash[1] = '\0';
  } else {
    strcpy(cfg->dir, ".");
  }
  config_set_include_dir(&cfg->lc, cfg->dir);
  if (!has_absolute_include(cfg->text)) {
    POM_TRY_GOTO(finish_load(cfg, config_read_file(&cfg->lc, path), err), fail);
  } else {
    /* libconfig 1.5 prefixes the include folder even to absolute paths:
     * parse a copy whose absolute includes are rewritten relative to the
     * folder (same lines, so messages keep their line numbers). */
    char *parsed = rewrite_absolute_includes(cfg->text, cfg->dir);
    if (!parsed) POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "%s: out of memory", path);
    int ok = config_read_string(&cfg->lc, parsed);
    free(parsed);
    POM_TRY_GOTO(finish_load(cfg, ok, err), fail);
  }
  *out = cfg;
  return POM_OK;
fail:
  if (fp) fclose(fp);
  pom_cfg_destroy(cfg);
  return st;
}

pom_status pom_cfg_load_string(pom_cfg **out, const char *text, const char *name, pom_error *err) {
  pom_status st = POM_OK;
  *out = NULL;
  pom_cfg *cfg = cfg_alloc(name);
  if (!cfg) POM_FAIL(err, POM_ERR_NOMEM, "loading config '%s'", name);
  cfg->text = dup_string(text);
  if (!cfg->text) POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "%s: out of memory", name);
  POM_TRY_GOTO(finish_load(cfg, config_read_string(&cfg->lc, text), err), fail);
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
  free(cfg);
}

const char *pom_cfg_path(const pom_cfg *cfg) {
  return cfg->path;
}
const char *pom_cfg_text(const pom_cfg *cfg) {
  return cfg->text ? cfg->text : "";
}

int pom_cfg_has(const pom_cfg *cfg, const char *key) {
  return lookup(cfg, key) != NULL;
}

int pom_cfg_length(const pom_cfg *cfg, const char *key) {
  config_setting_t *s = lookup(cfg, key);
  if (!s || !config_setting_is_aggregate(s)) return 0;
  return config_setting_length(s);
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
  const char *v = config_setting_get_string(s);
  for (int k = 0; choices[k]; ++k) {
    if (strcmp(v, choices[k]) == 0) {
      *index = k;
      return POM_OK;
    }
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

pom_status pom_cfg_check_unknown(const pom_cfg *cfg, const char *const scopes[],
                                 const char *const known_top[], pom_error *err) {
  config_setting_t *root = config_root_setting(&cfg->lc);
  int n = config_setting_length(root);
  for (int k = 0; k < n; ++k) {
    config_setting_t *s = config_setting_get_elem(root, (unsigned int)k);
    const char *name = config_setting_name(s);
    if (known_top && !in_list(name, known_top))
      return setting_error(cfg, s, name, err,
                           "unknown top-level key (check its spelling against docs/config.md)");
    if (scopes && !in_list(name, scopes)) continue;
    POM_TRY(find_unused(cfg, s, err));
  }
  return POM_OK;
}
