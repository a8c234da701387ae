/* cli_opts.c - the generic option parser and the generated --help of the
 * commands' option tables (cli_opts.h). */
#include "cli_opts.h"

#include "pom_cli.h"

#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>

/* The row of arg ("--kp" or "--kp=X": *inline_val then points after '='). */
static const pom_opt *find(const pom_cli_spec *spec, const char *arg, const char **inline_val) {
  *inline_val = NULL;
  for (int k = 0; k < spec->n_opts; ++k) {
    const pom_opt *o = &spec->opts[k];
    size_t n = strlen(o->name);
    if (strncmp(arg, o->name, n) != 0) continue;
    if (arg[n] == '\0') return o;
    if (arg[n] == '=' && o->kind != POM_OPT_FLAG && o->kind != POM_OPT_LIST) {
      *inline_val = arg + n + 1;
      return o;
    }
  }
  return NULL;
}

static int usage_error(const pom_cli_spec *spec, int quiet, const char *what, const char *arg) {
  if (quiet) return 2;
  fprintf(stderr, "pomlab %s: %s '%s'\n\n", spec->name, what, arg);
  pom_cli_opts_usage(spec, stderr);
  return 2;
}

/* Stores the value of o; 0, or 2 after printing why. */
static int store(const pom_cli_spec *spec, const pom_opt *o, const char *v, int quiet) {
  switch (o->kind) {
  case POM_OPT_TEXT:
  case POM_OPT_NUMBER:
  case POM_OPT_CHOICE:
    *o->text = v;
    return 0;
  case POM_OPT_THREADS:
    return pom_cli_parse_threads(quiet ? NULL : spec->name, v, o->ival) ? 2 : 0;
  case POM_OPT_INT: {
    char *end = NULL;
    errno = 0;
    long n = strtol(v, &end, 10);
    if (end == v || *end || errno || n < o->lo || n > o->hi) {
      if (quiet) return 2;
      if (o->hi == LONG_MAX)
        fprintf(stderr, "pomlab %s: %s expects a whole number >= %ld, got '%s'\n", spec->name,
                o->name, o->lo, v);
      else
        fprintf(stderr, "pomlab %s: %s expects a whole number in [%ld, %ld], got '%s'\n",
                spec->name, o->name, o->lo, o->hi, v);
      return 2;
    }
    if (o->ival)
      *o->ival = (int)n;
    else
      *o->lval = n;
    return 0;
  }
  default:
    return 0;
  }
}

int pom_cli_opts_parse(const pom_cli_spec *spec, int argc, char **argv, int quiet) {
  int n_args = 0;
  for (int k = 1; k < argc; ++k) {
    const char *a = argv[k], *v = NULL;
    if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
      if (!quiet) pom_cli_opts_usage(spec, stdout);
      return 0;
    }
    if (a[0] != '-' || a[1] == '\0') {
      if (n_args >= spec->max_args && spec->max_args > 1) {
        if (!quiet) fprintf(stderr, "pomlab %s: at most %d configs\n", spec->name, spec->max_args);
        return 2;
      }
      if (n_args >= spec->max_args) return usage_error(spec, quiet, "unexpected argument", a);
      spec->args[n_args++] = a;
      if (spec->n_args) *spec->n_args = n_args;
      continue;
    }
    const pom_opt *o = find(spec, a, &v);
    if (!o) return usage_error(spec, quiet, "unknown option", a);
    if (o->kind == POM_OPT_FLAG) {
      *o->flag = o->set;
    } else if (o->kind == POM_OPT_LIST) {
      if (k + 1 >= argc || argv[k + 1][0] == '-')
        return usage_error(spec, quiet, "incomplete option", a);
      while (k + 1 < argc && argv[k + 1][0] != '-') {
        if (*o->count >= o->hi) {
          if (!quiet)
            fprintf(stderr, "pomlab %s: %s takes at most %ld values\n", spec->name, o->name, o->hi);
          return 2;
        }
        o->list[(*o->count)++] = argv[++k];
      }
    } else {
      if (!v && k + 1 >= argc) return usage_error(spec, quiet, "incomplete option", a);
      int rc = store(spec, o, v ? v : argv[++k], quiet);
      if (rc) return rc;
    }
  }
  return -1;
}

/* Prints text from column `col` (already reached), wrapped at 80 columns
 * with continuation lines indented to `indent`. */
static void wrap(FILE *out, const char *text, int col, int indent) {
  const char *p = text;
  while (*p) {
    size_t w = strcspn(p, " ");
    if (col > indent && col + 1 + (int)w > 80) {
      fprintf(out, "\n%*s", indent, "");
      col = indent;
    } else if (col > indent) {
      fputc(' ', out);
      ++col;
    }
    fprintf(out, "%.*s", (int)w, p);
    col += (int)w;
    p += w;
    while (*p == ' ')
      ++p;
  }
  fputc('\n', out);
}

void pom_cli_opts_usage(const pom_cli_spec *spec, FILE *out) {
  fprintf(out, "usage: pomlab %s %s\n\n%s\n\n", spec->name, spec->usage, spec->about);
  int width = 6; /* "--help" */
  for (int k = 0; k < spec->n_opts; ++k) {
    const pom_opt *o = &spec->opts[k];
    int w = (int)strlen(o->name) + (o->arg ? 1 + (int)strlen(o->arg) : 0);
    if (w > width && w <= 24) width = w;
  }
  for (int k = 0; k < spec->n_opts; ++k) {
    const pom_opt *o = &spec->opts[k];
    char left[128], help[1024];
    snprintf(left, sizeof left, "%s%s%s", o->name, o->arg ? " " : "", o->arg ? o->arg : "");
    int n = snprintf(help, sizeof help, "%s%s%s%s", o->unit ? "[" : "", o->unit ? o->unit : "",
                     o->unit ? "] " : "", o->help);
    if (o->key && n < (int)sizeof help)
      snprintf(help + n, sizeof help - (size_t)n, "; sets %s, checked as in the file", o->key);
    if ((int)strlen(left) > width)
      fprintf(out, "  %s\n%*s", left, width + 3, "");
    else
      fprintf(out, "  %-*s ", width, left);
    wrap(out, help, width + 3, width + 3);
  }
  fprintf(out, "  %-*s this text\n", width, "--help");
  if (spec->notes) fprintf(out, "\n%s\n", spec->notes);
}

pom_status pom_cli_opts_apply(const pom_cli_spec *spec, pom_cfg *cfg, pom_error *err) {
  for (int k = 0; k < spec->n_opts; ++k) {
    const pom_opt *o = &spec->opts[k];
    if ((o->kind != POM_OPT_NUMBER && o->kind != POM_OPT_CHOICE) || !*o->text) continue;
    POM_TRY(o->kind == POM_OPT_NUMBER ? pom_cfg_set_number(cfg, o->key, *o->text, o->name, err)
                                      : pom_cfg_set_string(cfg, o->key, *o->text, o->name, err));
  }
  return POM_OK;
}
