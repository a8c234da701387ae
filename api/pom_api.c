/* pom_api.c - the flat entry layer: registries, kinematics, one maneuver and
 * studies composed from the module calls (docs/api.md). */
#define _POSIX_C_SOURCE 200809L /* open_memstream */
#include "pom_api.h"

#include "pom_arch.h"
#include "pom_arch_file.h"
#include "pom_run.h"
#include "pom_dyn_ctrl.h"
#include "pom_dyn_metrics_schema.h"
#include "pom_dynamics.h"
#include "pom_study.h"
#include "pom_h5.h"
#include "pom_job.h"
#include "pom_math.h"
#include "pom_pipeline.h"
#include "pom_version.h"

#include <gsl/gsl_errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- version and sizes ------------------------------------------------------- */
const char *pom_api_version(void) {
  return pom_version();
}

const char *pom_api_git_commit(void) {
  return pom_git_commit();
}

void pom_api_quiet_handlers(void) {
  gsl_set_error_handler_off();
  pom_h5_quiet();
}

size_t pom_api_struct_size(const char *name) {
  if (!name) return 0;
  if (strcmp(name, "pom_error") == 0) return sizeof(pom_error);
  if (strcmp(name, "pom_kin_pose") == 0) return sizeof(pom_kin_pose);
  if (strcmp(name, "pom_kin_fk_info") == 0) return sizeof(pom_kin_fk_info);
  if (strcmp(name, "pom_kin_ws_result") == 0) return sizeof(pom_kin_ws_result);
  if (strcmp(name, "pom_api_study_opts") == 0) return sizeof(pom_api_study_opts);
  return 0;
}

/* ---- registries ---------------------------------------------------------------- */
pom_status pom_api_register_architecture_files(pom_error *err) {
  pom_error local; /* err may be NULL: the status alone */
  pom_error_clear(&local);
  return pom_arch_files_register_all(err ? err : &local);
}

pom_status pom_api_arch_type_info(int k, const char **name, const char **label,
                                  const char **actuator_kind) {
  /* every output optional (NULL = not wanted); a file that fails to load is
   * reported by the calls that take an error (pom_api_arch_create, ...) */
  if (k == 0) {
    pom_error ignored;
    pom_error_clear(&ignored);
    (void)pom_arch_files_register_all(&ignored);
  }
  const pom_kin_arch_type *t = pom_kin_arch_type_at(k);
  if (!t) return POM_ERR_ARG;
  if (name) *name = pom_kin_type_name(t);
  if (label) *label = pom_kin_type_label(t);
  if (actuator_kind) *actuator_kind = pom_act_kind_desc(pom_kin_type_actuator(t))->kind_name;
  return POM_OK;
}

pom_status pom_api_ctrl_type_info(int k, const char **name, const char **label,
                                  const char **description) {
  const pom_dyn_ctrl_type *t = pom_dyn_ctrl_type_at(k);
  if (!t) return POM_ERR_ARG;
  if (name) *name = t->name;
  if (label) *label = t->label;
  if (description) *description = t->description;
  return POM_OK;
}

/* ---- kinematics ------------------------------------------------------------------ */
pom_status pom_api_arch_create(pom_kin_arch **out, const pom_cfg *cfg, pom_error *err) {
  if (!out || !cfg) POM_FAIL(err, POM_ERR_ARG, "pom_api_arch_create: NULL argument");
  *out = NULL;
  POM_TRY(pom_arch_files_register_all(err));
  pom_kin_arch *arch = calloc(1, sizeof *arch);
  if (!arch) POM_FAIL(err, POM_ERR_NOMEM, "pom_api_arch_create: out of memory");
  pom_status st = pom_kin_arch_load(arch, cfg, err);
  /* the overrides of the workspace groups are pom_api_workspace's to read */
  const char *const *const scopes[] = {pom_kin_arch_groups(), NULL};
  if (st == POM_OK) st = pom_api_check_keys(cfg, scopes, pom_kin_ws_groups(), err);
  if (st != POM_OK) {
    free(arch);
    return st;
  }
  *out = arch;
  return POM_OK;
}

void pom_api_arch_destroy(pom_kin_arch *arch) {
  free(arch);
}

const char *pom_api_arch_actuator_unit(const pom_kin_arch *arch, double *to_display) {
  if (!arch) return NULL;
  const pom_act_desc *u = pom_act_kind_desc(pom_kin_type_actuator(arch->type));
  if (to_display) *to_display = u->to_display;
  return u->si;
}

const char *pom_api_arch_limit_key(const pom_kin_arch *arch, int kind, double *to_display) {
  if (!arch || kind < 1 || kind >= POM_KIN_LIM_KINDS) return NULL;
  const pom_kin_limit_desc *ld = &arch->type->limits[kind];
  if (!ld->name) return NULL;
  if (to_display) *to_display = ld->to_display;
  return ld->json;
}

pom_status pom_api_workspace(const pom_kin_arch *arch, const pom_cfg *cfg, pom_kin_ws_result *res,
                             double out[3], pom_error *err) {
  if (!arch || !cfg || !res || !out) POM_FAIL(err, POM_ERR_ARG, "pom_api_workspace: NULL argument");
  pom_kin_ws_opts o;
  pom_kin_ws_defaults(&o);
  POM_TRY(pom_kin_ws_load(&o, cfg, err));
  const char *const *const scopes[] = {pom_kin_arch_groups(), pom_kin_ws_groups(), NULL};
  POM_TRY(pom_api_check_keys(cfg, scopes, NULL, err));
  POM_TRY(pom_kin_workspace(arch, &o, res, err));
  if (res->half_width < 0.0)
    POM_FAIL(err, POM_ERR_UNREACHABLE, "workspace: the home pose itself fails (%s)",
             pom_strerror(res->fail_status));
  double region = o.gci_half_width > 0.0 ? o.gci_half_width : res->half_width;
  out[2] = region;
  return pom_kin_gci(arch, region, o.resolution, o.check_limits, &out[0], &out[1], err);
}

/* ---- one maneuver ------------------------------------------------------------------ */
struct pom_api_sim {
  pom_kin_arch arch;       /* the geometry */
  pom_mechanism mech;      /* bodies, joints, actuators at home */
  pom_dyn_params par;      /* the dynamics groups of the config */
  pom_dyn_model *model;    /* built once */
  pom_dyn_data *data;      /* state and scratch of the runs */
  pom_dyn_trace *trace;    /* traces of the last run; NULL when not asked */
  pom_dyn_metrics metrics; /* metrics of the last run */
  int ran;                 /* 1 once a maneuver ran */
};

pom_status pom_api_sim_create(pom_api_sim **out, const pom_cfg *cfg, int traces, pom_error *err) {
  if (!out || !cfg) POM_FAIL(err, POM_ERR_ARG, "pom_api_sim_create: NULL argument");
  POM_TRY(pom_arch_files_register_all(err));
  *out = NULL;
  pom_status st = POM_OK;
  pom_api_sim *s = calloc(1, sizeof *s);
  if (!s) POM_FAIL(err, POM_ERR_NOMEM, "pom_api_sim_create: out of memory");
  POM_TRY_GOTO(pom_kin_arch_load(&s->arch, cfg, err), fail);
  POM_TRY_GOTO(pom_kin_mechanism_build(&s->mech, &s->arch, cfg, err), fail);
  pom_dyn_params_defaults(&s->par);
  POM_TRY_GOTO(pom_dyn_params_load(&s->par, cfg, err), fail);
  /* every group `pomlab simulate` reads, checked as it checks them */
  const char *const *const scopes[] = {pom_kin_model_groups(), pom_dyn_param_groups(), NULL};
  POM_TRY_GOTO(pom_api_check_keys(cfg, scopes, NULL, err), fail);
  POM_TRY_GOTO(pom_dyn_model_create(&s->model, &s->mech, &s->arch, &s->par, err), fail);
  POM_TRY_GOTO(pom_dyn_data_create(&s->data, s->model, err), fail);
  if (traces) POM_TRY_GOTO(pom_dyn_trace_create(&s->trace, s->model, err), fail);
  *out = s;
  return POM_OK;
fail:
  pom_api_sim_destroy(s);
  return st;
}

void pom_api_sim_destroy(pom_api_sim *sim) {
  if (!sim) return;
  pom_dyn_trace_destroy(sim->trace);
  pom_dyn_data_destroy(sim->data);
  pom_dyn_model_destroy(sim->model);
  free(sim);
}

pom_status pom_api_sim_run(pom_api_sim *sim, const double target[3], pom_error *err) {
  if (!sim || !target) POM_FAIL(err, POM_ERR_ARG, "pom_api_sim_run: NULL argument");
  const pom_act_desc *u = pom_act_kind_desc(pom_kin_type_actuator(sim->arch.type));
  double half = 0.5 * sim->arch.stroke;
  for (int a = 0; a < 3; ++a)
    if (!isfinite(target[a]) || (half > 0 && !(fabs(target[a]) <= half)))
      POM_FAIL(err, POM_ERR_ARG,
               "target q%d = %.10g %s is outside the stroke +-%.10g %s (limits.%s%s = %.10g)",
               a + 1, target[a], u->si, half, u->si, u->range_word, u->key_suffix,
               sim->arch.stroke * u->to_display);
  sim->ran = 1;
  return pom_dyn_simulate(sim->model, sim->data, target, &sim->metrics, sim->trace, err);
}

const char *pom_api_sim_name(const pom_api_sim *sim) {
  return sim ? sim->arch.name : NULL;
}

double pom_api_sim_half_stroke(const pom_api_sim *sim) {
  return sim ? 0.5 * sim->arch.stroke : NAN;
}

pom_status pom_api_sim_status(const pom_api_sim *sim, const char **reason) {
  if (!sim) {
    if (reason) *reason = "no simulation (NULL)";
    return POM_ERR_ARG;
  }
  if (reason) *reason = sim->ran ? sim->metrics.reason : "no maneuver run";
  return sim->ran ? sim->metrics.status : POM_ERR_ARG;
}

int pom_api_metric_count(void) {
  return POM_DYN_N_METRICS;
}

const char *pom_api_metric_key(int j, char *buf, size_t cap) {
  if (j < 0 || j >= POM_DYN_N_METRICS || !buf || cap == 0) return NULL;
  return pom_dyn_metric_json_key(pom_dyn_metric(j), buf, cap);
}

int pom_api_metric_width(int j) {
  return j < 0 || j >= POM_DYN_N_METRICS ? 0 : pom_dyn_metric(j)->count;
}

int pom_api_metric_is_integer(int j) {
  return j >= 0 && j < POM_DYN_N_METRICS && pom_dyn_metric(j)->type != POM_DYN_TYPE_DOUBLE;
}

int pom_api_sim_metric(const pom_api_sim *sim, int j, double v[3]) {
  if (!sim || !v || j < 0 || j >= POM_DYN_N_METRICS) return 0;
  const pom_dyn_metric_info *mi = pom_dyn_metric(j);
  for (int k = 0; k < mi->count; ++k)
    v[k] = sim->ran ? pom_dyn_metric_value(&sim->metrics, mi, k) : NAN;
  return mi->count;
}

int pom_api_sim_samples(const pom_api_sim *sim) {
  return sim && sim->trace && sim->ran ? sim->trace->n : 0;
}

const double *pom_api_sim_trace(const pom_api_sim *sim, const char *name, int *width) {
  if (!sim || !sim->trace || !name) return NULL;
  const pom_dyn_trace *tr = sim->trace;
  const struct {
    const char *name;
    const double *data;
    int width;
  } cols[] = {{.name = "t", .data = tr->t, .width = 1},
              {.name = "q", .data = tr->q, .width = 3},
              {.name = "q_dot", .data = tr->q_dot, .width = 3},
              {.name = "current", .data = tr->current, .width = 3},
              {.name = "voltage", .data = tr->voltage, .width = 3},
              {.name = "energy", .data = tr->energy, .width = 3},
              {.name = "euler_zyx", .data = tr->euler_zyx, .width = 3},
              {.name = "quat", .data = tr->quat, .width = 4},
              {.name = "deflection", .data = tr->deflection, .width = 1}};
  for (size_t k = 0; k < sizeof cols / sizeof cols[0]; ++k)
    if (strcmp(cols[k].name, name) == 0) {
      if (width) *width = cols[k].width;
      return cols[k].data;
    }
  return NULL;
}

/* ---- Monte-Carlo runs and studies ---------------------------------------------------- */
void pom_api_study_defaults(pom_api_study_opts *o) {
  if (!o) return;
  memset(o, 0, sizeof *o);
  o->output = "";
  o->tabular = "";
}

void pom_api_free(void *p) {
  free(p);
}

pom_status pom_api_study_run(const pom_cfg *cfg, const pom_api_study_opts *o, long *done,
                             long *total, pom_error *err) {
  return pom_api_study_run_json(cfg, o, done, total, NULL, err);
}

pom_status pom_api_study_run_json(const pom_cfg *cfg, const pom_api_study_opts *o, long *done,
                                  long *total, char **json, pom_error *err) {
  if (json) *json = NULL;
  if (!cfg || !o) POM_FAIL(err, POM_ERR_ARG, "pom_api_study_run: NULL argument");
  POM_TRY(pom_arch_files_register_all(err));
  if (!o->output || !o->output[0])
    POM_FAIL(err, POM_ERR_ARG, "pom_api_study_run: a results file (output) is required");
  POM_TRY(pom_api_check_threads(o->threads, "pom_api_study_opts.threads", err));
  pom_error_clear(err);
  pom_status st = POM_OK;
  pom_doe_study study;
  memset(&study, 0, sizeof study);
  char *text = NULL;
  size_t text_len = 0;
  FILE *report = NULL;
  if (o->montecarlo) {
    const char *const *const own[] = {pom_doe_montecarlo_groups(), NULL};
    if (pom_cfg_has(cfg, "candidates") || pom_cfg_has(cfg, "study"))
      POM_FAIL(err, POM_ERR_CONFIG, "%s is a study file: run it as a study", pom_cfg_path(cfg));
    POM_TRY_GOTO(pom_doe_study_single(&study, cfg, pom_doe_dyn_evaluator_create, NULL, err), done);
    POM_TRY_GOTO(pom_api_check_keys(cfg, own, NULL, err), done);
  } else {
    POM_TRY_GOTO(pom_doe_study_load(&study, cfg, pom_pipeline_evaluator_create, NULL, err), done);
    const char *const *const own[] = {pom_doe_study_groups(), NULL};
    POM_TRY_GOTO(pom_api_check_keys(cfg, own, NULL, err), done);
  }
  /* the program's job, its rules and its files (job/pom_job.h) */
  pom_job_options jo;
  pom_job_options_defaults(&jo);
  jo.command = o->montecarlo ? "montecarlo" : "study";
  jo.cfg_path = pom_cfg_path(cfg);
  jo.run.threads = o->threads;
  jo.run.resume = o->resume;
  jo.run.output = o->output;
  jo.tabular = o->tabular ? o->tabular : "";
  jo.output_key = "output";
  jo.tabular_key = "tabular";
  jo.pipeline = !o->montecarlo;
  jo.json = 1;
  jo.summary = o->summary != 0;
  jo.plots = o->plots != 0;
  jo.quiet = 1;
  jo.cancel = o->cancel;
  if (json) {
    report = open_memstream(&text, &text_len);
    if (!report)
      POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "pom_api_study_run: no memory for the report");
  }
  jo.out = report;
  pom_job_result res;
  memset(&res, 0, sizeof res);
  st = pom_job_run(&study, &jo, &res, err);
  if (report) {
    fclose(report);
    report = NULL;
  }
  if (done) *done = res.done;
  if (total) *total = res.total;
  if (st == POM_OK && res.interrupted)
    POM_FAIL_GOTO(err, POM_ERR_INTERRUPTED, done,
                  "interrupted after %ld of %ld candidate-maneuvers; every finished one is in %s; "
                  "continue with resume",
                  res.done, res.total, res.results);
  if (st == POM_OK && json) {
    *json = text;
    text = NULL;
  }
done:
  if (report) fclose(report);
  free(text);
  pom_doe_study_clear(&study);
  return st;
}

pom_status pom_api_gradient_json(const pom_cfg *cfg, const char *const *keys, int n, long maneuvers,
                                 char **json, pom_error *err) {
  if (!json) POM_FAIL(err, POM_ERR_ARG, "pom_api_gradient_json: NULL argument");
  *json = NULL;
  if (!cfg || !keys) POM_FAIL(err, POM_ERR_ARG, "pom_api_gradient_json: NULL argument");
  if (maneuvers < 0)
    POM_FAIL(err, POM_ERR_ARG, "pom_api_gradient_json: maneuvers = %ld (0 = the config's)",
             maneuvers);
  POM_TRY(pom_arch_files_register_all(err));
  pom_grad *g = NULL;
  pom_grad_mc_result r;
  memset(&r, 0, sizeof r);
  pom_status st = pom_grad_create(&g, cfg, keys, n, NULL, err);
  pom_grad_mc_options o;
  pom_grad_mc_options_defaults(&o);
  o.count = maneuvers;
  if (st == POM_OK) st = pom_grad_montecarlo(g, &o, &r, err);
  char *text = NULL;
  size_t len = 0;
  if (st == POM_OK) {
    FILE *f = open_memstream(&text, &len);
    if (!f) {
      st = pom_error_set(err, POM_ERR_NOMEM, __FILE__, __LINE__, "gradient: out of memory");
    } else {
      pom_grad_mc_json(f, pom_cfg_path(cfg), g, &r, NULL);
      if (fclose(f) != 0) {
        free(text);
        text = NULL;
        st = pom_error_set(err, POM_ERR_NOMEM, __FILE__, __LINE__, "gradient: out of memory");
      }
    }
  }
  pom_grad_mc_free(&r);
  pom_grad_destroy(g);
  *json = text;
  return st;
}
