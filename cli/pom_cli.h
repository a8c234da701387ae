/* pom_cli.h - the pomlab command-line program: shared helpers for the
 * subcommands. Only cli/ prints or decides exit codes. */
#ifndef POM_CLI_H
#define POM_CLI_H

#include "pom_config.h"
#include "pom_status.h"

#include <stdio.h>

/* A subcommand: argv[0] is the subcommand name. Returns the process exit code
 * (0 ok, 1 runtime failure, 2 usage or config error). */
typedef int (*pom_cli_fn)(int argc, char **argv);

/* Prints "pomlab: <context>: <message>" on stderr for a failed status. */
void pom_cli_report(const char *context, const pom_error *err);

/* Exit code for a status: 2 for config/argument errors, 1 otherwise, 0 ok. */
int pom_cli_exit_code(pom_status st);

/* Parses "a,b,c" into n finite doubles; returns 0 on success, -1 on a
 * malformed list or a nan/inf value. */
int pom_cli_parse_list(const char *text, int n, double *out);

/* Parses a --threads value in [1, POM_API_THREADS_MAX] (the range of
 * study.threads and of the library's callers, pom_api.h); returns 0, or -1
 * after printing "pomlab COMMAND: ..." (nothing when command is NULL). */
int pom_cli_parse_threads(const char *command, const char *text, int *out);

/* Prints why two configs of a multi-config command (synth, tune) are
 * refused: both would write `output`. */
void pom_cli_refuse_shared_output(const char *command, const char *cfg_a, const char *cfg_b,
                                  const char *output);

/* Rejects unknown keys in the groups of `scopes` (a NULL-terminated array of
 * the libraries' NULL-terminated group lists: the groups the command's
 * libraries read) and any top-level name no command understands
 * (pom_api_known_groups, the list the C layer and Python check against too).
 * No command keeps a list of its own. */
pom_status pom_cli_check_unknown(const pom_cfg *cfg, const char *const *const scopes[],
                                 pom_error *err);

/* Loads a config file, reporting failures; returns NULL on error. */
pom_cfg *pom_cli_load_config(const char *path);

/* Subcommands, one file each (cli/cmd_<name>.c). */
/* The folder of the plotting scripts into buf: PREFIX/share/pomlab/scripts
 * beside an installed program, else the source tree's scripts/. Returns 0
 * when plot_study.py is there, -1 otherwise (buf then names the last place
 * tried). */
int pom_cli_scripts_dir(char *buf, size_t cap);

int pom_cmd_model(int argc, char **argv);
int pom_cmd_export(int argc, char **argv);
int pom_cmd_ik(int argc, char **argv);
int pom_cmd_fk(int argc, char **argv);
int pom_cmd_workspace(int argc, char **argv);
int pom_cmd_simulate(int argc, char **argv);
int pom_cmd_synth(int argc, char **argv);
int pom_cmd_tune(int argc, char **argv);
int pom_cmd_montecarlo(int argc, char **argv);
int pom_cmd_gradient(int argc, char **argv);
int pom_cmd_study(int argc, char **argv);
int pom_cmd_tradeoff(int argc, char **argv);
int pom_cmd_codesign(int argc, char **argv);
int pom_cmd_sensitivity(int argc, char **argv);
int pom_cmd_view(int argc, char **argv);
int pom_cmd_capability(int argc, char **argv);

#endif
