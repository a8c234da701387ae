/* study_internal.h - helpers shared by the files of study/ (not public). */
#ifndef POM_STUDY_INTERNAL_H
#define POM_STUDY_INTERNAL_H

#include "pom_study.h"

#include <libconfig.h>

/* ---- config trees (pom_doe_cfgtree.c) ---- */
/* Parses a libconfig file, @include resolved relative to the file. */
pom_status pom_doe_tree_read_file(config_t *tree, const char *path, pom_error *err);
/* Parses text; @include resolved relative to dir (NULL = current folder). */
pom_status pom_doe_tree_read_string(config_t *tree, const char *text, const char *name,
                                    const char *dir, pom_error *err);
/* Merges group src into group dst: groups recursively, everything else
 * replaced. `where` names src in messages. */
pom_status pom_doe_tree_merge(config_setting_t *dst, const config_setting_t *src, const char *where,
                              pom_error *err);
/* Sets the dotted key (groups created as needed) to a number; an existing
 * integer setting takes only integral values. */
pom_status pom_doe_tree_set_number(config_t *tree, const char *key, double value, pom_error *err);
/* Serializes a tree to libconfig text that reads back to identical values
 * (reals with round-trip precision). *text is malloc'ed. */
pom_status pom_doe_tree_write(const config_t *tree, char **text, pom_error *err);

/* ---- keys of a study (pom_doe_evaluator.c) ---- */
/* A sweep factor or uncertain key (`what` = where the config gives it, e.g.
 * "uncertain.[0].key") must be "group.name": POM_ERR_CONFIG naming file,
 * line, what and the key otherwise. */
pom_status pom_doe_check_dotted(const pom_cfg *cfg, const char *what, const char *key,
                                pom_error *err);
/* The same, and its group must be one that candidate cand's evaluator reads
 * (pom_doe_evaluator_reads): a key the model never reads changes nothing. */
pom_status pom_doe_check_model_key(const pom_cfg *cfg, const char *what, const char *key,
                                   const pom_doe_candidate *cand, pom_error *err);

/* "a, b, c": the groups eval reads, for messages (cap bytes). */
void pom_doe_evaluator_group_list(char *buf, size_t cap, const pom_doe_evaluator *eval);

/* ---- uncertain parameters (pom_doe_uncertain.c) ---- */
/* Nominal values of the study's uncertain keys per candidate, and the check
 * that both ends of every distribution give a valid candidate (messages
 * name the study file cfg). */
pom_status pom_doe_uncertain_prepare(pom_doe_study *study, const pom_cfg *cfg, pom_error *err);

/* ---- study.capability (pom_doe_capability.c) ---- */
/* Reads study.capability, study.capability_grid_points and
 * study.capability_require (docs/config.md). */
pom_status pom_doe_capability_load(pom_doe_study *study, const pom_cfg *cfg, pom_error *err);
#endif
