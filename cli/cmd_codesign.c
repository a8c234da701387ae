/* cmd_codesign.c - `pomlab codesign CFG`: each architecture at its best
 * (geometry, actuator size and gains on the closed-loop Monte-Carlo
 * metrics; docs/optimize.md section 11). Parses and calls. */
#include "cli_opts.h"
#include "pom_cli.h"
#include "pom_codesign.h"
#include "pom_io.h"
#include "pom_job.h"
#include "pom_progress.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* The bar (or its log lines), and in a log one line per finished
 * optimization: each takes seconds to minutes, so a log shows what the run
 * has done even when the bar's first line is not due yet. */
static void on_progress(void *user, const char *phase, long done, long total) {
  pom_progress *bar = user;
  bar->total = total;
  if (bar->enabled && bar->log_lines)
    fprintf(bar->out,
            "codesign: %s: an optimization finished (%ld of %ld budgeted evaluations, %.1f s)\n",
            phase, done, total, pom_progress_now() - bar->t_start);
  pom_progress_update(bar, done);
}

/* --slice CANDIDATE:V1:V2:N (variables 1-based, as listed in the file). */
static int parse_slice(const char *s, const pom_cds_problem *pb, int *c, int *v1, int *v2, int *n) {
  char buf[256];
  snprintf(buf, sizeof buf, "%s", s);
  char *p2 = strrchr(buf, ':');
  if (!p2) return 0;
  *p2++ = '\0';
  char *p1 = strrchr(buf, ':');
  if (!p1) return 0;
  *p1++ = '\0';
  char *p0 = strrchr(buf, ':');
  if (!p0) return 0;
  *p0++ = '\0';
  *c = -1;
  for (int k = 0; k < pb->n_candidates; ++k)
    if (strcmp(pb->cand[k].name, buf) == 0) *c = k;
  char *end = NULL;
  long a = strtol(p0, &end, 10);
  if (*end) return 0;
  long b = strtol(p1, &end, 10);
  if (*end) return 0;
  long m = strtol(p2, &end, 10);
  if (*end) return 0;
  *v1 = (int)a - 1;
  *v2 = (int)b - 1;
  *n = (int)m;
  return *c >= 0;
}

/* --sweep CANDIDATE:N. */
static int parse_sweep(const char *s, const pom_cds_problem *pb, int *c, int *n) {
  char buf[256];
  snprintf(buf, sizeof buf, "%s", s);
  char *p = strrchr(buf, ':');
  if (!p) return 0;
  *p++ = '\0';
  char *end = NULL;
  long m = strtol(p, &end, 10);
  if (end == p || *end || m < 2 || m > 200) return 0;
  *n = (int)m;
  *c = -1;
  for (int k = 0; k < pb->n_candidates; ++k)
    if (strcmp(pb->cand[k].name, buf) == 0) *c = k;
  return *c >= 0;
}

static void print_sweep_row(const char *key, double x, const pom_cds_problem *pb,
                            const pom_cds_figures *f) {
  printf("%-34s %12.6g %9.4f %9.4f %10.3f %10.5f %8.4f %8.4f %9.3f %3d %3d %s\n", key, x,
         1e3 * f->p95, 1e3 * f->p95_plain, 1e3 * f->energy, f->kin, f->i_peak, f->i_limit,
         1e3 * f->envelope, f->failed, f->unsettled, pom_cds_feasible(pb, f) ? "yes" : "no");
}

/* --sweep: every variable alone across its box, the others at the config's
 * design (docs/optimize.md 11.6). */
static int run_sweep(const pom_cds_problem *pb, int c, int n) {
  const pom_cds_candidate *cd = &pb->cand[c];
  pom_error err;
  pom_error_clear(&err);
  double x0[POM_CDS_MAX_VARS] = {0};
  for (int v = 0; v < cd->n_vars; ++v)
    x0[v] = cd->var[v].x0;
  pom_cds_figures f0;
  double *xs = calloc((size_t)cd->n_vars * (size_t)n, sizeof *xs);
  pom_cds_figures *figs = calloc((size_t)cd->n_vars * (size_t)n, sizeof *figs);
  if (!xs || !figs) {
    free(xs);
    free(figs);
    fprintf(stderr, "pomlab codesign: --sweep: out of memory\n");
    return 1;
  }
  pom_status st =
      pom_cds_evaluate(pb, c, x0, pb->maneuvers.seed, pb->maneuvers.count, 0, &f0, &err);
  if (st == POM_OK) st = pom_cds_sweep(pb, c, n, xs, figs, &err);
  if (st != POM_OK) {
    free(xs);
    free(figs);
    pom_cli_report("codesign", &err);
    return pom_cli_exit_code(st);
  }
  printf("sweep of %s: each variable alone across its box (%d points), the others at the "
         "config's design; %ld maneuvers (seed %llu), rigid\n",
         cd->name, n, pb->maneuvers.count, (unsigned long long)pb->maneuvers.seed);
  printf("%-34s %12s %9s %9s %10s %10s %8s %8s %9s %3s %3s %s\n", "variable", "value", "p95_ms",
         "p95os_ms", "energy_mJ", "kin_margin", "i_peak_A", "i_lim_A", "env_mm", "fai", "uns",
         "feasible");
  print_sweep_row("config_design", NAN, pb, &f0);
  for (int v = 0; v < cd->n_vars; ++v)
    for (int j = 0; j < n; ++j)
      print_sweep_row(cd->var[v].key, xs[v * n + j], pb, &figs[v * n + j]);
  free(xs);
  free(figs);
  return 0;
}

/* The files a co-design run writes (the results file and its temporary
 * copy, the figure and its copy, the resume journal, the lock) against those
 * it reads: 0, or 2 (same file, printed) / 1 (no memory). */
static int check_paths(const char *cfg_path, const pom_cds_problem *pb, const char *path,
                       const char *origin, const char *journal, const char *svg) {
  pom_job_paths *p = pom_job_paths_create("codesign");
  pom_job_paths_config(p, cfg_path, "the config");
  for (int c = 0; c < pb->n_candidates; ++c) {
    char what[POM_DOE_NAME_LEN + 32];
    snprintf(what, sizeof what, "the config of candidate '%s'", pb->cand[c].name);
    pom_job_paths_config(p, pb->cand[c].config, what);
  }
  char what[64], lock[1300], tmp[1300], svg_tmp[1300];
  snprintf(what, sizeof what, "the results file (%s)", origin);
  pom_job_paths_output(p, path, what);
  /* the names pom_cds_write_h5 and pom_io_create write before their rename,
   * and pom_io_lock_take's lock file */
  snprintf(tmp, sizeof tmp, "%s.tmp.%ld", path, (long)getpid());
  snprintf(svg_tmp, sizeof svg_tmp, "%s.tmp.%ld", svg, (long)getpid());
  snprintf(lock, sizeof lock, "%s.lock", path);
  pom_job_paths_output(p, tmp, "the results file's temporary copy");
  pom_job_paths_output(p, svg, "the figure");
  pom_job_paths_output(p, svg_tmp, "the figure's temporary copy");
  pom_job_paths_output(p, journal, "the resume journal");
  pom_job_paths_output(p, lock, "the lock file");
  int rc = pom_job_paths_check(p, stderr, NULL);
  pom_job_paths_destroy(p);
  return rc;
}

int pom_cmd_codesign(int argc, char **argv) {
  const char *cfg_path = NULL, *out = NULL, *slice = NULL, *effic = NULL, *sweep = NULL,
             *gradient = NULL;
  int quiet = 0, resume = 0, threads = -1;
  const pom_opt opts[] = {
      {.name = "--out",
       .kind = POM_OPT_TEXT,
       .arg = "FILE.h5",
       .help = "results file (default codesign.output); beside it FILE.svg (the fronts) and, "
               "while it runs, FILE.h5.journal (the resume journal)",
       .text = &out},
      {.name = "--resume",
       .kind = POM_OPT_FLAG,
       .help = "continue an interrupted run from its journal: finished optimizations are "
               "taken from it, the rest run",
       .flag = &resume,
       .set = 1},
      {.name = "--threads",
       .kind = POM_OPT_INT,
       .arg = "N",
       .help = "threads for the maneuvers (0 = all cores; default codesign.threads)",
       .ival = &threads,
       .lo = 0,
       .hi = 256},
      {.name = "--gradient",
       .kind = POM_OPT_CHOICE,
       .arg = "SOURCE",
       .key = "codesign.optimizer.gradient",
       .help = "the gradient source, \"central_difference\" or \"sensitivity\" (default "
               "codesign.optimizer.gradient; docs/optimize.md 11.5)",
       .text = &gradient},
      {.name = "--slice",
       .kind = POM_OPT_TEXT,
       .arg = "CAND:V1:V2:N",
       .help = "instead of the co-design: the grid-slice check of candidate CAND over its "
               "variables V1 and V2 (1-based) on an N x N grid against the optimizer",
       .text = &slice},
      {.name = "--sweep",
       .kind = POM_OPT_TEXT,
       .arg = "CAND:N",
       .help = "instead of the co-design: each variable of candidate CAND alone at N points "
               "across its box, the others at the config's design; the objective and "
               "every constraint's figure per point",
       .text = &sweep},
      {.name = "--efficiency",
       .kind = POM_OPT_TEXT,
       .arg = "CAND:BUDGET",
       .help = "instead of the co-design: the time optimum of candidate CAND by the "
               "gradient-based algorithm and by COBYLA (BUDGET evaluations); for each, the "
               "simulations and CPU until it first came within 0.5 % of the better final "
               "objective and of COBYLA's",
       .text = &effic},
      {.name = "--quiet",
       .kind = POM_OPT_FLAG,
       .help = "no progress on stderr",
       .flag = &quiet,
       .set = 1},
  };
  const pom_cli_spec spec = {
      .name = "codesign",
      .usage =
          "CFG [--out FILE.h5] [--resume] [--threads N] [--gradient SOURCE]\n"
          "       [--slice CAND:V1:V2:N] [--sweep CAND:N] [--efficiency CAND:BUDGET] [--quiet]",
      .about = "Co-designs each candidate architecture: its geometry, an actuator size (one coil\n"
               "family scaled by size) and its controller gains, on robust statistics of the\n"
               "closed-loop Monte-Carlo metrics (smooth p95 pointing time, mean energy) under\n"
               "one requirement set; a time-energy front per candidate by epsilon-constraint,\n"
               "each optimum re-evaluated on a fresh maneuver set and on the parasitic model,\n"
               "and the candidates ranked at their best (docs/optimize.md section 11).",
      .notes = "Exit status: 0 ok; 1 a run or a write failed (the journal keeps the finished\n"
               "optimizations: --resume); 2 usage or config error (also an output - the\n"
               "results file, the figure, the journal, the lock - that is the same file as\n"
               "an input or as another output; nothing is done).",
      .opts = opts,
      .n_opts = POM_CLI_N(opts),
      .args = &cfg_path,
      .max_args = 1,
      .n_args = NULL};
  int prc = pom_cli_opts_parse(&spec, argc, argv, 0);
  if (prc >= 0) return prc;
  if (!cfg_path) {
    pom_cli_opts_usage(&spec, stderr);
    return 2;
  }
  pom_cfg *cfg = pom_cli_load_config(cfg_path);
  if (!cfg) return 2;
  pom_cds_problem *pb = calloc(1, sizeof *pb);
  pom_cds_result *res = calloc(1, sizeof *res);
  pom_error err;
  pom_error_clear(&err);
  int code = 0;
  if (!pb || !res) {
    fprintf(stderr, "pomlab codesign: out of memory\n");
    code = 1;
    goto done;
  }
  pom_status st = pom_cli_opts_apply(&spec, cfg, &err);
  if (st == POM_OK) st = pom_cds_load(pb, cfg, &err);
  if (st != POM_OK) {
    pom_cli_report("codesign", &err);
    code = pom_cli_exit_code(st);
    goto done;
  }
  if (threads >= 0) pb->threads = threads;
  if (sweep) {
    int c = 0, n = 0;
    if (!parse_sweep(sweep, pb, &c, &n)) {
      fprintf(stderr,
              "pomlab codesign: --sweep '%s': expected CANDIDATE:N with a candidate of %s "
              "and 2..200 points\n",
              sweep, cfg_path);
      code = 2;
      goto done;
    }
    code = run_sweep(pb, c, n);
    goto done;
  }
  if (slice) {
    int c = 0, v1 = 0, v2 = 0, n = 0;
    if (!parse_slice(slice, pb, &c, &v1, &v2, &n)) {
      fprintf(stderr,
              "pomlab codesign: --slice '%s': expected CANDIDATE:V1:V2:N with a "
              "candidate of %s\n",
              slice, cfg_path);
      code = 2;
      goto done;
    }
    pom_cds_slice sl;
    st = pom_cds_grid_slice(pb, c, v1, v2, n, &sl, &err);
    if (st != POM_OK) {
      pom_cli_report("codesign", &err);
      code = pom_cli_exit_code(st);
      goto done;
    }
    const pom_cds_candidate *cd = &pb->cand[c];
    printf("grid slice of %s over %s x %s (%d x %d, others at the config's design)\n", cd->name,
           cd->var[v1].key, cd->var[v2].key, n, n);
    printf("grid best      p95 %.4f ms at %.6g, %.6g (%ld simulations)%s\n", 1e3 * sl.grid_best,
           sl.grid_x1, sl.grid_x2, sl.grid_simulations,
           sl.grid_feasible ? "" : " (no feasible grid point)");
    printf("optimizer best p95 %.4f ms at %.6g, %.6g (%ld simulations)\n", 1e3 * sl.opt_best,
           sl.opt_x1, sl.opt_x2, sl.opt_simulations);
    printf("optimizer / grid = %.5f\n", sl.opt_best / sl.grid_best);
    goto done;
  }
  if (effic) {
    char name[256];
    snprintf(name, sizeof name, "%s", effic);
    char *colon = strrchr(name, ':');
    char *end = NULL;
    long budget = colon ? strtol(colon + 1, &end, 10) : 0;
    int c = -1;
    if (colon) *colon = '\0';
    for (int k = 0; k < pb->n_candidates; ++k)
      if (strcmp(pb->cand[k].name, name) == 0) c = k;
    if (c < 0 || !end || *end || budget < 2 || budget > 100000) {
      fprintf(stderr,
              "pomlab codesign: --efficiency '%s': expected CANDIDATE:BUDGET with a "
              "candidate of %s and a budget of 2..100000 evaluations\n",
              effic, cfg_path);
      code = 2;
      goto done;
    }
    pom_cds_efficiency ef;
    st = pom_cds_efficiency_run(pb, c, (int)budget, 0.005, &ef, &err);
    if (st != POM_OK) {
      pom_cli_report("codesign", &err);
      code = pom_cli_exit_code(st);
      goto done;
    }
    printf("efficiency, time optimum of %s from the config's design (%ld maneuvers per "
           "evaluation)\n",
           pb->cand[c].name, pb->maneuvers.count);
    printf("gradient-based: p95 %.4f ms, %ld simulations (%ld evaluations), %.2f s CPU%s\n",
           1e3 * ef.grad_best, ef.grad_sims, ef.grad.evaluations, ef.grad.cpu,
           ef.grad.fallback_used ? ", COBYLA fallback included" : "");
    if (pb->grad == POM_CDS_GRAD_SENS) {
      const pom_cds_point *gp = &ef.grad;
      printf("  of which %ld maneuvers ran with sensitivities (p = %d), %ld plain, %ld in "
             "differences; %ld gradient evaluations fell back to differences%s%s\n",
             gp->sens_runs, gp->sens_params, gp->simulations - gp->sens_runs - gp->fallback_sims,
             gp->fallback_sims, gp->sens_fallbacks, gp->sens_fallbacks ? ", last: " : "",
             gp->sens_fallbacks ? gp->sens_why : "");
      printf("  current rows (one per maneuver and point): %ld from the peak current's "
             "derivative, %ld by differences of that maneuver, %ld held (more than 20 %% from "
             "active)%s%s\n",
             gp->peak_rows, gp->peak_fallbacks, gp->peak_held,
             gp->peak_fallbacks ? "; last difference: " : "",
             gp->peak_fallbacks ? gp->peak_why : "");
      if (isfinite(ef.sens_cost))
        printf("  a sensitivity run cost %.2f plain runs of CPU here (%.2f s in %ld sensitivity "
               "runs; COBYLA's plain runs %.2f s in %ld)\n",
               ef.sens_cost, gp->cpu_sens, gp->sens_runs, ef.dfree.cpu, ef.dfree.simulations);
    }
    printf("COBYLA:         p95 %.4f ms, %ld simulations (%ld evaluations), %.2f s CPU\n",
           1e3 * ef.dfree_best, ef.dfree.simulations, ef.dfree.evaluations, ef.dfree.cpu);
    if (!isfinite(ef.target)) {
      printf("no feasible point in either run: no target to reach\n");
      goto done;
    }
    /* section 11.8: each method counted until it first came within 0.5 %
     * of the same target, from its own record */
    const double sc = ef.sens_cost;
    for (int t = 0; t < 2; ++t) {
      const double target = t == 0 ? ef.target : ef.dfree_best;
      const pom_cds_reach *rg = t == 0 ? &ef.grad_to_target : &ef.grad_to_dfree;
      const pom_cds_reach *rd = t == 0 ? &ef.dfree_to_target : &ef.dfree_to_dfree;
      if (t == 1 && (!isfinite(target) || target == ef.target)) break; /* the same */
      if (t == 0)
        printf("to within 0.5 %% of the common target, the better final objective: p95 %.4f ms "
               "(%s)\n",
               1e3 * target, target == ef.grad_best ? "gradient-based" : "COBYLA");
      else
        printf("to within 0.5 %% of COBYLA's final objective: p95 %.4f ms\n", 1e3 * target);
      for (int m = 0; m < 2; ++m) {
        const pom_cds_reach *r = m == 0 ? rg : rd;
        const char *who = m == 0 ? "gradient-based:" : "COBYLA:        ";
        if (r->reached == 1)
          printf("  %s %ld simulations, %.2f s CPU", who, r->sims, r->cpu);
        else
          printf("  %s %s within its %ld simulations (%.2f s CPU)", who,
                 r->reached == 0 ? "not" : "unknown whether (record full)", r->sims, r->cpu);
        if (r->sens_runs > 0)
          printf("; %ld with sensitivities, %ld plain: %.0f plain-run equivalents", r->sens_runs,
                 r->sims - r->sens_runs,
                 (double)(r->sims - r->sens_runs) + sc * (double)r->sens_runs);
        printf("\n");
      }
      if (rg->reached == 1 && rd->reached != -1) {
        const char *gt = rd->reached == 1 ? "" : "> ";
        double eq = (double)(rg->sims - rg->sens_runs) + sc * (double)rg->sens_runs;
        printf("  COBYLA / gradient-based: %s%.2f in simulations", gt,
               (double)rd->sims / (double)rg->sims);
        if (rg->sens_runs > 0 && isfinite(sc))
          printf(", %s%.2f in plain-run equivalents", gt, (double)rd->sims / eq);
        printf(", %s%.2f in CPU\n", gt, rd->cpu / rg->cpu);
      } else if (rg->reached != 1 && rd->reached == 1) {
        printf("  the gradient-based run did not reach it: COBYLA / gradient-based < %.2f in "
               "simulations, < %.2f in CPU\n",
               (double)rd->sims / (double)rg->sims, rd->cpu / rg->cpu);
      }
    }
    goto done;
  }
  const char *path = out ? out : pb->output;
  char journal[1200], svg[1200];
  snprintf(journal, sizeof journal, "%s.journal", path);
  snprintf(svg, sizeof svg, "%s", path);
  size_t L = strlen(svg);
  if (L > 3 && strcmp(svg + L - 3, ".h5") == 0) svg[L - 3] = '\0';
  strncat(svg, ".svg", sizeof svg - strlen(svg) - 1);
  /* outputs never overwrite inputs, as a study's (docs/results.md,
   * "Writing safely"; the study's check, job/pom_job.h): every file this
   * run writes against the codesign file, every candidate's config and the
   * files they include, before the lock or the journal is touched */
  code = check_paths(cfg_path, pb, path, out ? "--out" : "codesign.output", journal, svg);
  if (code) goto done;
  /* one run per output, as a study (docs/optimize.md 11.7): the lock is
   * taken before the journal is touched and held until the files are
   * written; a second run on the same output is refused, nothing changed */
  pom_io_lock lock = {.fd = -1};
  st = pom_io_lock_take(&lock, path, &err);
  if (st != POM_OK) {
    pom_cli_report("codesign", &err);
    code = pom_cli_exit_code(st);
    goto done;
  }
  pom_progress bar;
  pom_progress_init(&bar, quiet ? NULL : stderr, "codesign", 1, 0, 0);
  st = pom_cds_run(pb, journal, resume, on_progress, &bar, res, &err);
  pom_progress_finish(&bar, bar.total);
  if (st == POM_OK) st = pom_cds_write_h5(pb, res, path, &err);
  if (st == POM_OK) st = pom_cds_write_svg(pb, res, svg, &err);
  if (st != POM_OK) {
    pom_io_lock_release(&lock);
    pom_cli_report("codesign", &err);
    if (access(journal, F_OK) == 0)
      fprintf(stderr, "pomlab codesign: the finished optimizations are kept in '%s' (--resume)\n",
              journal);
    code = pom_cli_exit_code(st);
    goto done;
  }
  unlink(journal); /* finished: the results file holds everything */
  pom_io_lock_release(&lock);
  pom_cds_report_text(stdout, pb, res);
  printf("Results: %s; figure: %s\n", path, svg);
done:
  if (pb) pom_cds_clear(pb);
  free(pb);
  free(res);
  pom_cfg_destroy(cfg);
  return code;
}
