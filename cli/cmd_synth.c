/* cmd_synth.c - `pomlab synth CFG [CFG ...]`: kinematic synthesis of one or
 * more architectures (docs/optimize.md), side by side when several. */
#include "cli_opts.h"
#include "cli_kin.h"
#include "pom_job.h"
#include "pom_cli.h"
#include "pom_pipeline.h"
#include "pom_math.h"
#include "pom_progress.h"
#include "pom_opt_print.h"
#include "pom_synth.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_CFGS 4

int pom_cmd_synth(int argc, char **argv) {
  const char *cfg_paths[MAX_CFGS];
  int ncfg = 0, json = 0, no_direct = 0, quiet = 0;
  const char *prefix = "results/synth_";
  const pom_opt opts[] = {
      {.name = "--out",
       .kind = POM_OPT_TEXT,
       .arg = "PREFIX",
       .help = "output path prefix (its folder must exist)",
       .text = &prefix},
      {.name = "--no-direct",
       .kind = POM_OPT_FLAG,
       .help = "skip the direct NLopt search on the true kinematics "
               "(synthesis.direct.enabled = false)",
       .flag = &no_direct,
       .set = 1},
      {.name = "--json",
       .kind = POM_OPT_FLAG,
       .help = "JSON on stdout (variables and responses in their config units)",
       .flag = &json,
       .set = 1},
      {.name = "--quiet",
       .kind = POM_OPT_FLAG,
       .help = "no progress bar",
       .flag = &quiet,
       .set = 1},
  };
  const pom_cli_spec spec = {
      .name = "synth",
      .usage = "CFG [CFG ...] [--out PREFIX] [--no-direct] [--json] [--quiet]",
      .about = "Kinematic synthesis by response surfaces and desirability (docs/optimize.md).\n"
               "Each CFG needs architecture, geometry (mode = \"parameters\"), limits, workspace\n"
               "and synthesis groups. Writes PREFIX<name>.geometry.cfg (the scaled geometry, a\n"
               "`geometry` group for simulate/montecarlo/study) and PREFIX<name>.h5 (design,\n"
               "fits, optimum, confirmation). PREFIX defaults to results/synth_.",
      .notes = "With synthesis.capability_require the scaled optimum (then the other one) is\n"
               "checked against the capability floor on the config's full model (inertia,\n"
               "actuator, controller groups; docs/optimize.md 6b).\n"
               "Exit status: 0 ok; 1 a run failed, a file cannot be written or no optimum\n"
               "meets synthesis.capability_require (the files are written); 2 usage or config\n"
               "error.",
      .opts = opts,
      .n_opts = POM_CLI_N(opts),
      .args = cfg_paths,
      .max_args = MAX_CFGS,
      .n_args = &ncfg};
  int prc = pom_cli_opts_parse(&spec, argc, argv, 0);
  if (prc >= 0) return prc;
  if (ncfg == 0) {
    pom_cli_opts_usage(&spec, stderr);
    return 2;
  }

  /* the geometry, the workspace and the synthesis; inertia etc. belong to
   * other commands */
  const char *const *const scopes[] = {pom_kin_arch_groups(), pom_kin_ws_groups(), pom_syn_groups(),
                                       NULL};
  /* with a capability floor the model's groups are read too, so checked */
  const char *const *const cap_scopes[] = {pom_kin_model_groups(), pom_kin_ws_groups(),
                                           pom_syn_groups(),       pom_dyn_param_groups(),
                                           pom_cap_groups(),       NULL};
  pom_cfg *cfgs[MAX_CFGS] = {NULL};
  pom_syn_problem *pbs = calloc(MAX_CFGS, sizeof *pbs);
  pom_syn_run *runs[MAX_CFGS] = {NULL};
  char paths[MAX_CFGS][2][512];
  int code = 0;
  pom_error err;
  pom_error_clear(&err);
  if (!pbs) {
    fprintf(stderr, "pomlab synth: out of memory\n");
    return 1;
  }
  for (int c = 0; c < ncfg; ++c) {
    cfgs[c] = pom_cli_load_config(cfg_paths[c]);
    if (!cfgs[c]) {
      code = 2;
      goto out;
    }
    pom_status st = pom_syn_load(&pbs[c], cfgs[c], &err);
    if (st == POM_OK) {
      /* inertia etc. belong to other commands: accept but do not check them */
      st = pom_cli_check_unknown(cfgs[c], pbs[c].cap.n > 0 ? cap_scopes : scopes, &err);
    }
    if (st != POM_OK) {
      pom_cli_report("synth", &err);
      code = pom_cli_exit_code(st);
      goto out;
    }
    if (no_direct && pbs[c].write == POM_SYN_WRITE_DIRECT) {
      fprintf(stderr, "pomlab synth: --no-direct contradicts synthesis.write = \"direct\" in %s\n",
              cfg_paths[c]);
      code = 2;
      goto out;
    }
    if (no_direct) pbs[c].direct = 0;
    char name[256]; /* the whole name, file-name safe (no truncation) */
    pom_pipeline_stem(name, sizeof name, pbs[c].base.name);
    snprintf(paths[c][0], sizeof paths[c][0], "%s%s.geometry.cfg", prefix, name);
    snprintf(paths[c][1], sizeof paths[c][1], "%s%s.h5", prefix, name);
    /* two configs of one name would write the same files, the second over
     * the first: refused before any work */
    for (int d = 0; d < c; ++d)
      if (strcmp(paths[d][0], paths[c][0]) == 0) {
        pom_cli_refuse_shared_output("synth", cfg_paths[d], cfg_paths[c], paths[c][0]);
        code = 2;
        goto out;
      }
  }
  /* no output may overwrite a config or a file it includes */
  pom_job_paths *pp = pom_job_paths_create("synth");
  for (int c = 0; c < ncfg; ++c)
    pom_job_paths_config(pp, cfg_paths[c], "the config");
  for (int c = 0; c < ncfg; ++c) {
    pom_job_paths_output(pp, paths[c][0], "the geometry file (--out PREFIX + name)");
    pom_job_paths_output(pp, paths[c][1], "the synthesis record (--out PREFIX + name)");
  }
  code = pom_job_paths_check(pp, stderr, NULL);
  pom_job_paths_destroy(pp);
  if (code) goto out;
  for (int c = 0; c < ncfg; ++c) {
    pom_status st = pom_syn_begin(&runs[c], &pbs[c], &err);
    if (st == POM_OK) {
      pom_progress bar;
      char label[48];
      snprintf(label, sizeof label, "design %s", pom_kin_arch_name(&pbs[c].base));
      pom_progress_init(&bar, quiet ? NULL : stderr, label, runs[c]->n_runs, 0, 0);
      int remaining = 1;
      while (st == POM_OK && remaining > 0) {
        st = pom_syn_step(runs[c], &remaining, &err);
        pom_progress_update(&bar, runs[c]->next);
      }
      pom_progress_finish(&bar, runs[c]->next);
    }
    if (st == POM_OK) st = pom_syn_finish(runs[c], &err);
    if (st == POM_OK) st = pom_syn_write_geometry(runs[c], paths[c][0], &err);
    if (st == POM_OK) st = pom_syn_write_h5(runs[c], paths[c][1], pom_cfg_text(cfgs[c]), &err);
    if (st != POM_OK) {
      pom_cli_report("synth", &err);
      code = pom_cli_exit_code(st);
      goto out;
    }
    if (!json)
      pom_syn_report_text(stdout, runs[c], paths[c][0], paths[c][1]);
    else
      pom_syn_fit_warnings(stderr, runs[c]);
    if (runs[c]->n_cap_checks > 0 && !runs[c]->cap_met) {
      /* the floor holds for no optimum: the files are written for
       * inspection, and the exit status says it */
      char why[1024];
      pom_syn_cap_failure(runs[c], why, sizeof why);
      fprintf(stderr, "pomlab synth: %s: no optimum meets synthesis.capability_require: %s\n",
              cfg_paths[c], why);
      code = 1;
    }
  }
  if (json)
    pom_syn_report_json(stdout, runs, ncfg, paths);
  else if (ncfg > 1)
    pom_syn_compare_text(stdout, runs, ncfg);
out:
  for (int c = 0; c < MAX_CFGS; ++c) {
    pom_syn_destroy(runs[c]);
    pom_cfg_destroy(cfgs[c]);
  }
  free(pbs);
  return code;
}
