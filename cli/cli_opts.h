/* cli_opts.h - one option table per command: every option of a command is
 * one row (name, value kind, unit, help, and for a value that is also a
 * config key, that key), a generic parser reads argv against the table and
 * `--help` is generated from it (docs/extending.md, "A command").
 *
 * A value that sets a config key (.key) is not checked here: it goes through
 * pom_cfg_set_number / pom_cfg_set_string (pom_cli_opts_apply), the same
 * check as the key written in the file (its range, its choices), and the
 * error names the option. */
#ifndef POM_CLI_OPTS_H
#define POM_CLI_OPTS_H

#include "pom_config.h"

#include <stdio.h>

typedef enum {
  POM_OPT_FLAG,    /* no value: *flag = .set */
  POM_OPT_TEXT,    /* a string: *text = the value */
  POM_OPT_INT,     /* a whole number in [.lo, .hi] (.hi LONG_MAX: no limit): *ival or *lval */
  POM_OPT_THREADS, /* worker threads in [1, POM_API_THREADS_MAX] (study.threads' range): *ival */
  POM_OPT_NUMBER,  /* a config key's number: set by pom_cli_opts_apply (.key) */
  POM_OPT_CHOICE,  /* a config key's choice: set by pom_cli_opts_apply (.key) */
  POM_OPT_LIST,    /* the following arguments up to the next option: list[*count++] */
} pom_opt_kind;

typedef struct {
  const char *name; /* "--kp" (also taken as "--kp=X") */
  pom_opt_kind kind;
  const char *arg;   /* the value's name in --help: "X", "FILE" */
  const char *unit;  /* the value's unit in --help, or NULL */
  const char *key;   /* POM_OPT_NUMBER, POM_OPT_CHOICE: the config key it sets */
  const char *help;  /* one sentence; wrapped by --help */
  int *flag;         /* POM_OPT_FLAG */
  int set;           /* POM_OPT_FLAG: the value stored (1 for --json, 0 for --no-plots) */
  const char **text; /* POM_OPT_TEXT, NUMBER, CHOICE: the value as given (NULL when absent) */
  int *ival;         /* POM_OPT_INT (or lval), POM_OPT_THREADS */
  long *lval;        /* POM_OPT_INT when ival is NULL */
  long lo, hi;       /* POM_OPT_INT */
  const char **list; /* POM_OPT_LIST, at most .hi entries */
  int *count;        /* POM_OPT_LIST */
} pom_opt;

/* A command: its usage line, what it does, its options, what follows. */
typedef struct {
  const char *name;  /* "simulate" */
  const char *usage; /* "CONFIG --target q1,q2,q3 [options]" */
  const char *about; /* paragraph(s) before the options */
  const char *notes; /* paragraph(s) after them: units, exit status */
  const pom_opt *opts;
  int n_opts;
  const char **args; /* positional arguments (configs), at most max_args */
  int max_args;
  int *n_args; /* NULL when max_args is 1 */
} pom_cli_spec;

#define POM_CLI_N(table) ((int)(sizeof(table) / sizeof((table)[0])))

/* Parses argv[1..argc-1] against the table. Returns -1 to go on; otherwise
 * the exit code: 0 after printing --help (-h) on stdout, 2 after a usage
 * error (an unknown option, one without its value, a malformed value, an
 * extra argument) printed on stderr. quiet: print nothing (MPI ranks > 0). */
int pom_cli_opts_parse(const pom_cli_spec *spec, int argc, char **argv, int quiet);

/* The command's --help text. */
void pom_cli_opts_usage(const pom_cli_spec *spec, FILE *out);

/* Sets every POM_OPT_NUMBER and POM_OPT_CHOICE option given into cfg, in
 * the table's order, through the config's own checks; the error names the
 * option. */
pom_status pom_cli_opts_apply(const pom_cli_spec *spec, pom_cfg *cfg, pom_error *err);

#endif
