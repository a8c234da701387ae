/* pom_doe_cfgtree.c - candidate configs: merge overrides into a base config
 * tree and write the result back as text (docs/results.md, "Candidates"). */
#include "study_internal.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- reading ------------------------------------------------------------- */
static pom_status tree_error(const config_t *tree, const char *name, pom_error *err) {
  const char *f = config_error_file(tree);
  POM_FAIL(err, POM_ERR_CONFIG, "%s:%d: %s", f ? f : name, config_error_line(tree),
           config_error_text(tree) ? config_error_text(tree) : "cannot read");
}

pom_status pom_doe_tree_read_file(config_t *tree, const char *path, pom_error *err) {
  char dir[POM_DOE_PATH_LEN];
  snprintf(dir, sizeof dir, "%s", path);
  char *slash = strrchr(dir, '/');
  if (slash)
    slash[1] = '\0';
  else
    snprintf(dir, sizeof dir, ".");
  config_set_include_dir(tree, dir);
  config_set_auto_convert(tree, 0);
  /* the file and its @includes checked as every config is (regular files of
   * bounded size: libconfig would wait on a FIFO or read a device forever);
   * the path comes from a config (a candidate's `config`): a config error */
  pom_cfg *check = NULL;
  pom_status st = pom_cfg_load(&check, path, err);
  pom_cfg_destroy(check);
  if (st != POM_OK) {
    if (err) err->status = POM_ERR_CONFIG;
    return POM_ERR_CONFIG;
  }
  if (!config_read_file(tree, path)) return tree_error(tree, path, err);
  return POM_OK;
}

pom_status pom_doe_tree_read_string(config_t *tree, const char *text, const char *name,
                                    const char *dir, pom_error *err) {
  config_set_include_dir(tree, dir ? dir : ".");
  config_set_auto_convert(tree, 0);
  if (!config_read_string(tree, text)) return tree_error(tree, name, err);
  return POM_OK;
}

/* ---- merging --------------------------------------------------------------- */
static pom_status copy_setting(config_setting_t *parent, const char *name,
                               const config_setting_t *src, pom_error *err) {
  int type = config_setting_type(src);
  config_setting_t *s = config_setting_add(parent, name, type);
  if (!s) POM_FAIL(err, POM_ERR_CONFIG, "cannot add setting '%s'", name ? name : "[element]");
  switch (type) {
  case CONFIG_TYPE_INT:
    config_setting_set_int(s, config_setting_get_int(src));
    break;
  case CONFIG_TYPE_INT64:
    config_setting_set_int64(s, config_setting_get_int64(src));
    break;
  case CONFIG_TYPE_FLOAT:
    config_setting_set_float(s, config_setting_get_float(src));
    break;
  case CONFIG_TYPE_BOOL:
    config_setting_set_bool(s, config_setting_get_bool(src));
    break;
  case CONFIG_TYPE_STRING:
    config_setting_set_string(s, config_setting_get_string(src));
    break;
  default: {
    int n = config_setting_length(src);
    for (int k = 0; k < n; ++k) {
      const config_setting_t *e = config_setting_get_elem(src, (unsigned int)k);
      POM_TRY(copy_setting(s, type == CONFIG_TYPE_GROUP ? config_setting_name(e) : NULL, e, err));
    }
  }
  }
  return POM_OK;
}

pom_status pom_doe_tree_merge(config_setting_t *dst, const config_setting_t *src, const char *where,
                              pom_error *err) {
  int n = config_setting_length(src);
  for (int k = 0; k < n; ++k) {
    const config_setting_t *s = config_setting_get_elem(src, (unsigned int)k);
    const char *name = config_setting_name(s);
    config_setting_t *d = config_setting_get_member(dst, name);
    if (config_setting_is_group(s)) {
      if (d && !config_setting_is_group(d))
        POM_FAIL(err, POM_ERR_CONFIG,
                 "%s: override '%s' is a group but the base config has a value there", where, name);
      if (!d) d = config_setting_add(dst, name, CONFIG_TYPE_GROUP);
      if (!d) POM_FAIL(err, POM_ERR_CONFIG, "%s: cannot add group '%s'", where, name);
      POM_TRY(pom_doe_tree_merge(d, s, where, err));
    } else {
      if (d && config_setting_is_group(d))
        POM_FAIL(err, POM_ERR_CONFIG,
                 "%s: override '%s' is a value but the base config has a group there", where, name);
      if (d && !config_setting_remove(dst, name))
        POM_FAIL(err, POM_ERR_CONFIG, "%s: cannot replace '%s'", where, name);
      POM_TRY(copy_setting(dst, name, s, err));
    }
  }
  return POM_OK;
}

pom_status pom_doe_tree_set_number(config_t *tree, const char *key, double value, pom_error *err) {
  char path[256];
  if (strlen(key) >= sizeof path) POM_FAIL(err, POM_ERR_CONFIG, "key '%s' too long", key);
  snprintf(path, sizeof path, "%s", key);
  config_setting_t *g = config_root_setting(tree);
  char *part = path;
  for (;;) {
    char *dot = strchr(part, '.');
    if (!dot) break;
    *dot = '\0';
    config_setting_t *next = config_setting_get_member(g, part);
    if (!next) next = config_setting_add(g, part, CONFIG_TYPE_GROUP);
    if (!next || !config_setting_is_group(next))
      POM_FAIL(err, POM_ERR_CONFIG, "key '%s': '%s' is not a group in the base config", key, part);
    g = next;
    part = dot + 1;
  }
  if (!*part) POM_FAIL(err, POM_ERR_CONFIG, "key '%s': empty name", key);
  config_setting_t *s = config_setting_get_member(g, part);
  if (!s) {
    s = config_setting_add(g, part, CONFIG_TYPE_FLOAT);
    if (!s) POM_FAIL(err, POM_ERR_CONFIG, "key '%s': cannot add", key);
  }
  switch (config_setting_type(s)) {
  case CONFIG_TYPE_FLOAT:
    config_setting_set_float(s, value);
    return POM_OK;
  case CONFIG_TYPE_INT:
  case CONFIG_TYPE_INT64:
    if (value != floor(value) || fabs(value) > 9.0e15)
      POM_FAIL(err, POM_ERR_CONFIG, "key '%s' is an integer in the base config; %.17g is not", key,
               value);
    if (config_setting_type(s) == CONFIG_TYPE_INT && fabs(value) < 2147483647.0)
      config_setting_set_int(s, (int)value);
    else
      config_setting_set_int64(s, (long long)value);
    return POM_OK;
  default:
    POM_FAIL(err, POM_ERR_CONFIG, "key '%s' is not a number in the base config", key);
  }
}

/* ---- writing --------------------------------------------------------------- */
typedef struct {
  char *buf;
  size_t len, cap;
  int failed;
} text_buf;

static void put(text_buf *t, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

static void put(text_buf *t, const char *fmt, ...) {
  if (t->failed) return;
  for (;;) {
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(t->buf + t->len, t->cap - t->len, fmt, ap);
    va_end(ap);
    if (n < 0) {
      t->failed = 1;
      return;
    }
    if ((size_t)n < t->cap - t->len) {
      t->len += (size_t)n;
      return;
    }
    size_t cap = 2 * t->cap + (size_t)n + 64;
    char *b = realloc(t->buf, cap);
    if (!b) {
      t->failed = 1;
      return;
    }
    t->buf = b;
    t->cap = cap;
  }
}

/* Shortest %.Ng (N = 15..17) that reads back exactly, always with a '.' or an
 * exponent so libconfig reads it as a real. */
static void put_real(text_buf *t, double v) {
  char s[64];
  for (int prec = 15; prec <= 17; ++prec) {
    snprintf(s, sizeof s, "%.*g", prec, v);
    if (strtod(s, NULL) == v) break;
  }
  if (!strpbrk(s, ".eE")) strncat(s, ".0", sizeof s - strlen(s) - 1);
  put(t, "%s", s);
}

static void put_string(text_buf *t, const char *s) {
  put(t, "\"");
  for (const unsigned char *p = (const unsigned char *)s; *p; ++p) {
    switch (*p) {
    case '"':
      put(t, "\\\"");
      break;
    case '\\':
      put(t, "\\\\");
      break;
    case '\n':
      put(t, "\\n");
      break;
    case '\t':
      put(t, "\\t");
      break;
    case '\r':
      put(t, "\\r");
      break;
    case '\f':
      put(t, "\\f");
      break;
    default:
      if (*p < 0x20)
        put(t, "\\x%02x", *p);
      else
        put(t, "%c", *p);
    }
  }
  put(t, "\"");
}

static void put_value(text_buf *t, const config_setting_t *s, int indent);

static void put_members(text_buf *t, const config_setting_t *g, int indent) {
  int n = config_setting_length(g);
  for (int k = 0; k < n; ++k) {
    const config_setting_t *e = config_setting_get_elem(g, (unsigned int)k);
    put(t, "%*s%s = ", indent, "", config_setting_name(e));
    put_value(t, e, indent);
    put(t, ";\n");
  }
}

static void put_value(text_buf *t, const config_setting_t *s, int indent) {
  int type = config_setting_type(s);
  switch (type) {
  case CONFIG_TYPE_INT:
    put(t, "%d", config_setting_get_int(s));
    break;
  case CONFIG_TYPE_INT64:
    put(t, "%lldL", config_setting_get_int64(s));
    break;
  case CONFIG_TYPE_FLOAT:
    put_real(t, config_setting_get_float(s));
    break;
  case CONFIG_TYPE_BOOL:
    put(t, "%s", config_setting_get_bool(s) ? "true" : "false");
    break;
  case CONFIG_TYPE_STRING:
    put_string(t, config_setting_get_string(s));
    break;
  case CONFIG_TYPE_GROUP:
    put(t, "{\n");
    put_members(t, s, indent + 2);
    put(t, "%*s}", indent, "");
    break;
  case CONFIG_TYPE_ARRAY:
  case CONFIG_TYPE_LIST: {
    int n = config_setting_length(s);
    put(t, "%s", type == CONFIG_TYPE_ARRAY ? "[" : "(");
    for (int k = 0; k < n; ++k) {
      if (k) put(t, ", ");
      put_value(t, config_setting_get_elem(s, (unsigned int)k), indent + 2);
    }
    put(t, "%s", type == CONFIG_TYPE_ARRAY ? "]" : ")");
    break;
  }
  default:
    put(t, "0");
  }
}

pom_status pom_doe_tree_write(const config_t *tree, char **text, pom_error *err) {
  text_buf t = {NULL, 0, 0, 0};
  t.cap = 4096;
  t.buf = malloc(t.cap);
  if (!t.buf) POM_FAIL(err, POM_ERR_NOMEM, "writing a config: out of memory");
  t.buf[0] = '\0';
  put_members(&t, config_root_setting(tree), 0);
  if (t.failed) {
    free(t.buf);
    *text = NULL;
    POM_FAIL(err, POM_ERR_NOMEM, "writing a config: out of memory");
  }
  *text = t.buf;
  return POM_OK;
}
