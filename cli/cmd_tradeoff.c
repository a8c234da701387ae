/* cmd_tradeoff.c - `pomlab tradeoff CFG`: speed against accuracy of the
 * dynamics engine across formulation, scene options, rtol, parasitic
 * stiffness and linear solver; table, CSV for the work-precision plot and a
 * recommendation (docs/tradeoff.md). */
#include "cli_opts.h"
#include "pom_job.h"
#include "pom_cli.h"
#include "pom_io.h"
#include "pom_run.h"
#include "pom_kinematics.h"
#include "pom_explore.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void progress(void *user, const pom_tradeoff_row *row, int done, int total) {
  (void)user;
  fprintf(stderr, "  [%2d/%2d] %-44s %9.3f ms  err %.2e  integ. %.2e%s\n", done, total, row->label,
          row->time * 1e3, row->err_max, row->int_max, row->failures ? "  FAILED" : "");
}

static void fmt_err(char *buf, size_t cap, double e) {
  if (isinf(e))
    snprintf(buf, cap, "%9s", "fail");
  else if (isnan(e))
    snprintf(buf, cap, "%9s", "n/a");
  else
    snprintf(buf, cap, "%9.2e", e);
}

static void print_table(const pom_tradeoff_result *res, double accuracy) {
  printf("%-44s %6s %10s %8s %9s %9s %9s %9s  %s\n", "setting", "states", "ms/man.", "steps",
         "settle", "energy", "traject.", "integ.", "");
  for (int r = 0; r < res->n_rows; ++r) {
    const pom_tradeoff_row *w = &res->row[r];
    char a[32], b[32], c[32], i[32];
    fmt_err(a, sizeof a, w->err_settle);
    fmt_err(b, sizeof b, w->err_energy);
    fmt_err(c, sizeof c, w->err_traj);
    fmt_err(i, sizeof i, w->int_max);
    const char *mark = r == res->recommended               ? "<= recommended"
                       : (r > 0 && w->err_max <= accuracy) ? "ok"
                                                           : "";
    printf("%-44s %6d %10.3f %8.0f %s %s %s %s  %s\n", w->label, w->n_states, w->time * 1e3,
           w->steps, a, b, c, i, mark);
    if (w->failures) printf("    failed: %s\n", w->reason);
    if (w->int_reason[0]) printf("    integ. n/a: %s\n", w->int_reason);
  }
}

/* The recommendation by the rule of docs/tradeoff.md section 9, with both
 * sets and their seeds named. */
static void print_recommendation(const pom_tradeoff_result *res, const pom_tradeoff_opts *o,
                                 uint64_t seed) {
  const pom_fidelity_result *f = &res->fidelity;
  if (!res->fidelity_ran) {
    printf("no recommendation (tradeoff.fidelity_maneuvers = 0)\n");
    return;
  }
  printf("recommendation rule: the cheapest rung of the ladder (rigid joints; quasi-static, then "
         "inductive coil; rtol 1e-3 down) whose worst execution-time and energy errors against "
         "the rigid reference (inductive coil, rtol %.0e) are <= %g %% / %g = %.3g %% on a "
         "selection set (maneuvers 0..%d of seed %llu, %d reachable) and <= %g %% on a validation "
         "set drawn from a different seed (maneuvers 0..%d of seed %llu, %d reachable)\n",
         o->reference_rtol, o->accuracy * 100.0, f->margin, o->accuracy / f->margin * 100.0,
         res->n_select_drawn - 1, (unsigned long long)seed, f->n_select, o->accuracy * 100.0,
         res->n_validation_drawn - 1, (unsigned long long)res->validation_seed, f->n_validate);
  if (f->met)
    printf("recommended for %g %% accuracy: %s (rung %d of the ladder; %.0f steps per maneuver "
           "against %.0f for the reference)\n",
           o->accuracy * 100.0, f->setting.label, f->rung + 1, f->steps, f->reference_steps);
  else
    printf("no setting of the ladder meets %g %% accuracy on both sets; the most accurate rung, "
           "%s, measured:\n",
           o->accuracy * 100.0, f->setting.label);
  printf("  selected on %d maneuvers: time error %.2e, energy error %.2e (<= %.2e asked)\n",
         f->n_select, f->select_time, f->select_energy, o->accuracy / f->margin);
  printf("  validated on %d other maneuvers (seed %llu): time error %.2e, energy error %.2e: "
         "the bound it claims%s\n",
         f->n_validate, (unsigned long long)res->validation_seed, f->bound_time, f->bound_energy,
         f->met ? "" : " (above the accuracy asked)");
  if (res->recommended >= 0) {
    const pom_tradeoff_row *w = &res->row[res->recommended];
    printf("  in the table: '%s', %.3f ms per maneuver (%.2fx the config's own setting); its "
           "integration error there: settle %.2e, energy %.2e, trajectory %.2e\n",
           w->label, w->time * 1e3, w->time / res->row[1].time, w->int_settle, w->int_energy,
           w->int_traj);
  }
  if (f->failure[0]) printf("  a rejected rung failed a maneuver: %s\n", f->failure);
}

static pom_status write_csv(const char *path, const pom_tradeoff_result *res, pom_error *err) {
  pom_io_file out;
  POM_TRY(pom_io_create(&out, path, err));
  FILE *f = out.f;
  fprintf(f, "label,family,n_states,time_s,steps,err_settle,err_energy,err_traj,err_max,int_settle,"
             "int_energy,int_traj,int_max,failures,recommended\n");
  for (int r = 0; r < res->n_rows; ++r) {
    const pom_tradeoff_row *w = &res->row[r];
    fprintf(f, "\"%s\",%s,%d,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%d,%d\n", w->label,
            w->family, w->n_states, w->time, w->steps, w->err_settle, w->err_energy, w->err_traj,
            w->err_max, w->int_settle, w->int_energy, w->int_traj, w->int_max, w->failures,
            r == res->recommended);
  }
  return pom_io_commit(&out, err);
}

int pom_cmd_tradeoff(int argc, char **argv) {
  const char *cfg_path = NULL, *csv = NULL, *accuracy_text = NULL;
  const char *maneuvers = NULL, *repeats = NULL;
  double accuracy = -1.0;
  int quiet = 0;
  /* --accuracy is not tradeoff.accuracy_percent's value: it takes a '%' sign
   * and any percentage in (0, 100] (the key's range starts at 1e-6 %) */
  const pom_opt options[] = {
      {.name = "--accuracy",
       .kind = POM_OPT_TEXT,
       .arg = "X%",
       .unit = "%",
       .help = "accuracy for the recommendation (default tradeoff.accuracy_percent, 1 %); the % "
               "sign is optional",
       .text = &accuracy_text},
      {.name = "--maneuvers",
       .kind = POM_OPT_NUMBER,
       .arg = "N",
       .key = "tradeoff.maneuvers",
       .help = "maneuvers, 1..16",
       .text = &maneuvers},
      {.name = "--repeats",
       .kind = POM_OPT_NUMBER,
       .arg = "N",
       .key = "tradeoff.repeats",
       .help = "timing repeats",
       .text = &repeats},
      {.name = "--csv",
       .kind = POM_OPT_TEXT,
       .arg = "FILE",
       .help = "write the table as CSV (for scripts/plot_tradeoff.py)",
       .text = &csv},
      {.name = "--quiet",
       .kind = POM_OPT_FLAG,
       .help = "no progress lines on stderr",
       .flag = &quiet,
       .set = 1},
  };
  const pom_cli_spec spec = {
      .name = "tradeoff",
      .usage = "CONFIG [options]",
      .about =
          "Runs the configured mechanism over a fixed set of maneuvers (montecarlo seed,\n"
          "maneuvers 0..n-1) at many settings - rtol, parasitic stiffness, linear solver,\n"
          "scene options - and compares each with a tight reference (tradeoff.reference:\n"
          "rigid joints at rtol 1e-10 by default, or parasitic joints at k_p 1e9 N/m):\n"
          "wall time per maneuver (median of repeats) against the worst relative error in\n"
          "execution (settling) time, expended energy and trajectory. Column integ.: the\n"
          "integration error alone, the worst of the three against the row's own model\n"
          "integrated at tradeoff.reference_rtol. Recommends the cheapest setting of a ladder\n"
          "(rigid joints, quasi-static then inductive coil, rtol 1e-3 down) within the accuracy\n"
          "divided by a margin on tradeoff.fidelity_maneuvers maneuvers of the montecarlo seed,\n"
          "validated within the accuracy on as many of another seed (docs/tradeoff.md 9).",
      .notes = "Wall times in ms per maneuver; errors are relative (1 = 100 %). There is no\n"
               "--json: the CSV is the machine-readable output (docs/tradeoff.md).\n"
               "Plot: /usr/bin/python3 scripts/plot_tradeoff.py OUT.png NAME=FILE.csv [...]\n"
               "Exit status: 0 ok; 1 a run failed or the CSV cannot be written; 2 usage or\n"
               "config error.",
      .opts = options,
      .n_opts = POM_CLI_N(options),
      .args = &cfg_path,
      .max_args = 1};
  int prc = pom_cli_opts_parse(&spec, argc, argv, 0);
  if (prc >= 0) return prc;
  if (accuracy_text) {
    char *end = NULL;
    accuracy = strtod(accuracy_text, &end);
    if (end == accuracy_text || (*end && strcmp(end, "%") != 0) ||
        !(accuracy > 0 && accuracy <= 100)) {
      fprintf(stderr, "pomlab tradeoff: --accuracy '%s': expected a percentage in (0, 100]\n",
              accuracy_text);
      return 2;
    }
    accuracy *= 1e-2;
  }
  if (!cfg_path) {
    pom_cli_opts_usage(&spec, stderr);
    return 2;
  }
  pom_cfg *cfg = pom_cli_load_config(cfg_path);
  if (!cfg) return 2;
  /* the table must not overwrite the config or a file it includes */
  int path_rc = pom_job_check_output("tradeoff", cfg_path, csv, "the table (--csv)", stderr, NULL);
  if (path_rc) {
    pom_cfg_destroy(cfg);
    return path_rc;
  }
  pom_error err;
  pom_error_clear(&err);
  pom_kin_arch arch;
  pom_mechanism mech;
  pom_dyn_params params;
  pom_doe_maneuvers mv;
  pom_tradeoff_opts opts;
  pom_tradeoff_result *res = NULL;
  pom_status st = POM_OK;
  const char *stage = "config";
  /* the model's groups, the maneuvers' and tradeoff's */
  const char *const *const scopes[] = {pom_kin_model_groups(), pom_dyn_param_groups(),
                                       pom_doe_montecarlo_groups(), pom_tradeoff_groups(), NULL};
  pom_dyn_params_defaults(&params);
  pom_tradeoff_defaults(&opts);
  if ((st = pom_cli_opts_apply(&spec, cfg, &err)) != POM_OK || /* --maneuvers, --repeats */
      (st = pom_kin_arch_load(&arch, cfg, &err)) != POM_OK ||
      (st = pom_kin_mechanism_build(&mech, &arch, cfg, &err)) != POM_OK ||
      (st = pom_dyn_params_load(&params, cfg, &err)) != POM_OK ||
      (st = pom_doe_maneuvers_load(&mv, cfg, &err)) != POM_OK ||
      (st = pom_tradeoff_load(&opts, cfg, &err)) != POM_OK ||
      (st = pom_cli_check_unknown(cfg, scopes, &err)) != POM_OK)
    goto done;
  /* the maneuvers' range in the actuators' unit, as montecarlo and study
   * check it (a mm range is no range for revolute actuators) */
  pom_actuator_kind kind = POM_ACT_PRISMATIC;
  if ((st = pom_doe_mech_actuator_kind(&mech, &kind, &err)) != POM_OK ||
      (st = pom_doe_maneuvers_check_kinds(&mv, &kind, 1, cfg, &err)) != POM_OK)
    goto done;
  const pom_act_desc *unit = pom_act_kind_desc(kind);
  if (accuracy > 0) opts.accuracy = accuracy;
  res = calloc(1, sizeof *res);
  if (!res) {
    st = pom_error_set(&err, POM_ERR_NOMEM, __FILE__, __LINE__, "allocating the result");
    goto done;
  }
  stage = "tradeoff";
  if (!quiet)
    fprintf(stderr, "pomlab tradeoff: %s, %d maneuvers x %d repeats\n", arch.name, opts.maneuvers,
            opts.repeats);
  st =
      pom_tradeoff_run(&arch, &mech, &params, &mv, &opts, res, quiet ? NULL : progress, NULL, &err);
  if (st != POM_OK) goto done;
  printf("%s: %d maneuvers (montecarlo seed %llu), times = median of %d repeats; errors = worst "
         "relative to the reference (model + integration error)\n"
         "integ. = the worst of the three against the row's own model at rtol %.0e (integration "
         "error alone; %d distinct models)\n",
         arch.name, res->n_maneuvers, (unsigned long long)mv.seed, opts.repeats,
         opts.reference_rtol, res->n_models);
  for (int k = 0; k < res->n_maneuvers; ++k)
    printf("maneuver %d: targets %.4f, %.4f, %.4f %s\n", k, res->targets[k][0] * unit->to_display,
           res->targets[k][1] * unit->to_display, res->targets[k][2] * unit->to_display,
           unit->display);
  print_table(res, opts.accuracy);
  print_recommendation(res, &opts, mv.seed);
  if (csv) {
    stage = "csv";
    st = write_csv(csv, res, &err);
  }
done:
  if (st != POM_OK) pom_cli_report(stage, &err);
  free(res);
  pom_cfg_destroy(cfg);
  return pom_cli_exit_code(st);
}
