/* pom_config.h - validated access to libconfig files.
 *
 * Every getter takes a dotted key ("actuator.resistance_ohm", list elements as
 * "candidates.[0].name"), checks type and range, converts to SI with the given
 * factor and marks the setting as used. After all consumers have read their
 * keys, pom_cfg_check_unknown() rejects every setting nobody asked for.
 * Every message names file, line, key, the value found and what was expected.
 * Ranges are given in the config's own unit (the unit in the key name); the
 * factor converts the checked value to SI. */
#ifndef POM_CONFIG_H
#define POM_CONFIG_H

#include "pom_status.h"

#include <stddef.h>

typedef struct pom_cfg pom_cfg;

/* Largest config file, main or included (bytes): the shipped ones are a few
 * KB; a larger one is refused before it is read (docs/config.md). */
#define POM_CFG_MAX_BYTES (16 << 20)

/* Deepest nesting of groups, lists and arrays in one file: the shipped
 * configs need four; deeper is refused before libconfig parses it. */
#define POM_CFG_MAX_NESTING 64

/* Loads and parses a config file (with @include resolved relative to the
 * file's folder). The file and every include must be regular files of at
 * most POM_CFG_MAX_BYTES (a FIFO, a device, a folder are refused, naming the
 * file). On failure *out is NULL and err names file, line and the parse
 * error. The caller owns *out. */
pom_status pom_cfg_load(pom_cfg **out, const char *path, pom_error *err);

/* Same from a string; name is used in messages (e.g. "<test>"). */
pom_status pom_cfg_load_string(pom_cfg **out, const char *text, const char *name, pom_error *err);

/* Frees; NULL is allowed. */
void pom_cfg_destroy(pom_cfg *cfg);

/* Path given at load (or the name for strings). */
const char *pom_cfg_path(const pom_cfg *cfg);

/* The raw text of the main file, as read (for provenance in results files). */
const char *pom_cfg_text(const pom_cfg *cfg);

/* The files read for a config loaded with pom_cfg_load: k = 0 the main
 * file, then every @include as opened (at most 64 listed); NULL past the
 * end. For outputs that must not overwrite an input. */
int pom_cfg_n_files(const pom_cfg *cfg);
const char *pom_cfg_file(const pom_cfg *cfg, int k);

/* 1 when the key exists (does not mark it used). */
int pom_cfg_has(const pom_cfg *cfg, const char *key);

/* 1 when the setting at key is a list ( ... ), 0 otherwise or when absent. */
int pom_cfg_is_list(const pom_cfg *cfg, const char *key);

/* Number of elements of a list/array/group at key, 0 when absent. */
int pom_cfg_length(const pom_cfg *cfg, const char *key);

/* Name of member k (0-based) of the group at key, NULL when key is not a
 * group or k is out of range (does not mark it used). The name lives as
 * long as cfg. */
const char *pom_cfg_member_name(const pom_cfg *cfg, const char *key, int k);

/* Marks a key (and everything below it) as used without reading it. */
void pom_cfg_mark_used(const pom_cfg *cfg, const char *key);

/* Required real (an integer literal is accepted). min/max in config units,
 * inclusive; out = value * to_si. */
pom_status pom_cfg_real(const pom_cfg *cfg, const char *key, double to_si, double min, double max,
                        double *out, pom_error *err);
/* Optional real: absent -> *out = dflt_si (already SI). */
pom_status pom_cfg_real_opt(const pom_cfg *cfg, const char *key, double to_si, double min,
                            double max, double dflt_si, double *out, pom_error *err);

/* Array of exactly n reals, each checked against [min, max], times to_si. */
pom_status pom_cfg_reals(const pom_cfg *cfg, const char *key, int n, double to_si, double min,
                         double max, double *out, pom_error *err);
/* Array of 1..max_n reals; *n_out receives the count. */
pom_status pom_cfg_reals_var(const pom_cfg *cfg, const char *key, int max_n, double to_si,
                             double min, double max, double *out, int *n_out, pom_error *err);

/* Required / optional integer in [min, max]. */
pom_status pom_cfg_int(const pom_cfg *cfg, const char *key, long min, long max, long *out,
                       pom_error *err);
pom_status pom_cfg_int_opt(const pom_cfg *cfg, const char *key, long min, long max, long dflt,
                           long *out, pom_error *err);

/* Required / optional boolean (true/false). */
pom_status pom_cfg_bool(const pom_cfg *cfg, const char *key, int *out, pom_error *err);
pom_status pom_cfg_bool_opt(const pom_cfg *cfg, const char *key, int dflt, int *out,
                            pom_error *err);

/* Required / optional string copied into buf (size cap, NUL-terminated). */
pom_status pom_cfg_string(const pom_cfg *cfg, const char *key, char *buf, size_t cap,
                          pom_error *err);
pom_status pom_cfg_string_opt(const pom_cfg *cfg, const char *key, const char *dflt, char *buf,
                              size_t cap, pom_error *err);

/* String that must be one of choices (NULL-terminated array); *index gets its
 * position. The optional form leaves *index = dflt when absent. */
pom_status pom_cfg_choice(const pom_cfg *cfg, const char *key, const char *const choices[],
                          int *index, pom_error *err);
pom_status pom_cfg_choice_opt(const pom_cfg *cfg, const char *key, const char *const choices[],
                              int dflt, int *index, pom_error *err);

/* Name of choice `index` of a NULL-terminated choices table (the inverse of
 * pom_cfg_choice), "?" when index is outside the table.
 *
 * The one parse/name pair of every enum read from a config: a table of its
 * names in the order of its values (index = value, checked by a static
 * assert beside the table), pom_cfg_choice / pom_cfg_choice_opt to read it
 * and pom_cfg_choice_name to write it; pom_cfg_choice_index parses a name
 * that does not come from a config (a command-line option). */
const char *pom_cfg_choice_name(const char *const choices[], int index);

/* Position of `name` in a NULL-terminated choices table, -1 when absent (or
 * when name is NULL). */
int pom_cfg_choice_index(const char *const choices[], const char *name);

/* ---- config groups ------------------------------------------------------ */
#define POM_CFG_MAX_GROUPS 32

/* A NULL-terminated list of top-level config names assembled from the lists
 * each library exports (pom_kin_model_groups(), pom_dyn_param_groups(),
 * ...): a command checks unknown keys in the groups its libraries read
 * without keeping a list of its own. Plain data; `name` is usable as the
 * scopes or known_top argument of pom_cfg_check_unknown. */
typedef struct {
  const char *name[POM_CFG_MAX_GROUPS + 1]; /* static strings, NULL after the last */
  int n;
} pom_cfg_groups;

/* Empties g. */
void pom_cfg_groups_init(pom_cfg_groups *g);

/* Appends the names of the NULL-terminated list `names` not yet in g (NULL
 * adds nothing). POM_ERR_INTERNAL beyond POM_CFG_MAX_GROUPS names. */
pom_status pom_cfg_groups_add(pom_cfg_groups *g, const char *const *names, pom_error *err);

/* Rejects settings that nobody read. Only settings under the top-level names
 * listed in `scopes` (NULL-terminated; NULL pointer = everything) are
 * checked, plus any top-level name not in `known_top` (NULL-terminated list of
 * every top-level name any pomlab command understands; NULL = skip that
 * check). The message names file, line and key. */
pom_status pom_cfg_check_unknown(const pom_cfg *cfg, const char *const scopes[],
                                 const char *const known_top[], pom_error *err);

/* Rejects values set by pom_cfg_set_number / pom_cfg_set_string (overrides)
 * that nobody read: under a top-level name of `scopes` (NULL = every name)
 * as an unknown key, elsewhere as a group this command does not read
 * (naming the groups it does); those under a top-level name of `skip`
 * (NULL = none) are left to a later check. Call it once every reader has
 * run: a command-line value or a binding's override that changes nothing is
 * an error, like a misspelt key in a file. */
pom_status pom_cfg_check_overrides(const pom_cfg *cfg, const char *const scopes[],
                                   const char *const skip[], pom_error *err);

/* Sets `key` (dotted; missing groups are created, an existing value is
 * replaced) to the number written in `text`, as if the file said so: an
 * integer (64-bit, refused when it does not fit) or a finite real. The
 * getters then check it like any other value, and their messages name the
 * command-line option `origin` (e.g. "--seed") instead of a file line.
 * Call it after load and before the getters. A key that is not a dotted
 * config name ("", "controller. kp", "a..b") is refused (POM_ERR_CONFIG,
 * naming it). */
pom_status pom_cfg_set_number(pom_cfg *cfg, const char *key, const char *text, const char *origin,
                              pom_error *err);

/* pom_cfg_set_number for a string value (a choice such as
 * controller.type = "pid"), checked by the getters like a file's. */
pom_status pom_cfg_set_string(pom_cfg *cfg, const char *key, const char *text, const char *origin,
                              pom_error *err);

/* Compares two configs setting by setting. Returns 1 when they differ, with
 * the first differing key ("controller.kp") and its value in each
 * ("(absent)" when missing) written to key / value_a / value_b (capacities
 * key_cap and value_cap); 0 when every setting is the same. */
int pom_cfg_diff(const pom_cfg *a, const pom_cfg *b, char *key, size_t key_cap, char *value_a,
                 char *value_b, size_t value_cap);

/* Source line of a key (0 when unknown), for callers' own messages. */
int pom_cfg_line(const pom_cfg *cfg, const char *key);

/* Fills err with "FILE:LINE: key 'KEY' = VALUE: MESSAGE" for a semantic error
 * found by the caller (value_text may be NULL). Returns POM_ERR_CONFIG. */
pom_status pom_cfg_error(const pom_cfg *cfg, const char *key, const char *value_text,
                         pom_error *err, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;

#endif
