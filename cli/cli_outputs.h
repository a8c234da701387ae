/* cli_outputs.h - the files a command reads and writes, checked before any
 * work: no output may be the same file as an input (the config, a file it
 * includes, a candidate's config) or as another output of the run
 * (docs/results.md, "Output paths"). */
#ifndef POM_CLI_OUTPUTS_H
#define POM_CLI_OUTPUTS_H

#include <stddef.h>

typedef struct pom_cli_paths pom_cli_paths;

/* An empty list for `command` (its name in messages, e.g. "study"); NULL when
 * out of memory. */
pom_cli_paths *pom_cli_paths_create(const char *command);

/* Frees; NULL is allowed. */
void pom_cli_paths_destroy(pom_cli_paths *p);

/* Adds a config file read by the command and every file it @includes (the
 * file is loaded to list them; one that cannot be loaded adds itself only).
 * `what` describes it in messages ("the config", "candidate 'A''s config"). */
void pom_cli_paths_config(pom_cli_paths *p, const char *path, const char *what);

/* Adds a file the command will write; `what` describes it in messages
 * ("the results file (--out)"). An empty path is ignored. */
void pom_cli_paths_output(pom_cli_paths *p, const char *path, const char *what);

/* Refuses an output that is the same file as an input or as another output:
 * the same device and inode where both exist, else the same resolved path
 * (symbolic links, "." and ".." followed as far as the path exists). Prints
 * "pomlab COMMAND: ..." when `report` and returns 2; 1 when out of memory; 0
 * when every output is distinct. */
int pom_cli_paths_check(const pom_cli_paths *p, int report);

/* The check for a command of one config and one output (simulate --out,
 * tradeoff --csv, workspace --map): 0, or the exit code after printing. A
 * NULL or empty output passes. */
int pom_cli_check_output(const char *command, const char *cfg_path, const char *output,
                         const char *what);

/* The rule of a tabular file name (--tabular or study.tabular, named by
 * `origin`): FILE.csv, a regular file, not ending in _candidates.csv (the
 * name of the second table, FILE_candidates.csv). Then creates its folder
 * (as --out does) and checks that it can be written there. Prints
 * "pomlab COMMAND: ..." and returns 2 for a name against the rule, 1 for a
 * folder that cannot be created or written, 0 when fine; prints only when
 * `report`. */
int pom_cli_tabular_check(const char *command, const char *origin, const char *csv, int report);

/* mkdir -p of the folder part of path; 0 on success, else -1 with errno set
 * and the folder that failed in failed (capacity cap). */
int pom_cli_make_parent(const char *path, char *failed, size_t cap);

#endif
