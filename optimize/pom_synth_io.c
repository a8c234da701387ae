/* pom_synth_io.c - output of a synthesis run: the scaled geometry as a
 * config fragment and the HDF5 record (docs/optimize.md, section 7). */
#include "pom_synth.h"
#include "pom_version.h"

#include "pom_h5.h"
#include "pom_io.h"
#include "pom_math.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

pom_status pom_syn_write_geometry(const pom_syn_run *run, const char *path, pom_error *err) {
  const pom_kin_design *d = &run->scaled.design;
  if (!run->scaled_done)
    POM_FAIL(err, POM_ERR_ARG, "%s: this synthesis run has no scaled geometry to write", path);
  pom_io_file w;
  POM_TRY(pom_io_create(&w, path, err));
  FILE *f = w.f;
  fprintf(f,
          "# Geometry found by pomlab synth for \"%s\" (%s):\n"
          "# the %s optimum of the desirability (synthesis.write = \"%s\"), scaled so\n"
          "# the %.4g mm stroke covers a regular dexterous workspace of +-%.4g deg.\n"
          "# Overall desirability (true kinematics, base scale): %.4f surrogate\n"
          "# (%.4f on the surfaces)",
          run->pb->base.name, pom_kin_arch_name(&run->pb->base),
          run->written_direct ? "direct-search" : "surrogate", pom_syn_write_name(run->pb->write),
          run->pb->base.stroke * 1e3, run->pb->target_half_width / POM_DEG, run->d_confirmed,
          run->d_predicted);
  if (run->direct_done) fprintf(f, ", %.4f direct search", run->d_direct);
  fprintf(f, ".\n# Limits, workspace and inertia stay in the including config; this file\n"
             "# holds only the `geometry` group.\n");
  const pom_kin_arch_type *t = run->pb->base.type;
  fprintf(f, "geometry = {\n  mode = \"parameters\";\n");
  fprintf(f, "  %s = %.9g;\n", t->scale_key, d->scale * 1e3);
  for (int k = 0; k < t->n_params; ++k)
    fprintf(f, "  %s = %.9g;\n", t->params[k].key, d->x[k] / t->params[k].to_si);
  /* the modelling choice of the config, kept with the geometry it belongs to */
  if (t->optional_central_joint)
    fprintf(f, "  central_joint = %s;\n", run->scaled.central_joint ? "true" : "false");
  fprintf(f, "};\n");
  return pom_io_commit(&w, err);
}

/* ---- HDF5 ----------------------------------------------------------------- */
static pom_status write_fit(hid_t loc, const pom_rsm_fit *fit, const pom_rsm_check *chk,
                            int has_check, pom_error *err) {
  size_t p = (size_t)fit->p;
  POM_TRY(pom_h5_write_doubles(loc, "beta", 1, &p, fit->beta, err));
  POM_TRY(pom_h5_write_doubles(loc, "se", 1, &p, fit->se, err));
  POM_TRY(pom_h5_write_doubles(loc, "p_value", 1, &p, fit->p_value, err));
  POM_TRY(pom_h5_write_doubles(loc, "ci_half", 1, &p, fit->ci_half, err));
  char names[POM_RSM_MAX_TERMS][16];
  const char *np[POM_RSM_MAX_TERMS];
  for (int j = 0; j < fit->p; ++j) {
    pom_rsm_term_name(fit->k, j, names[j], sizeof names[j]);
    np[j] = names[j];
  }
  POM_TRY(pom_h5_write_strings(loc, "terms", p, np, 16, err));
  double anova[POM_RSM_N_ROWS * 5];
  for (int r = 0; r < POM_RSM_N_ROWS; ++r) {
    anova[5 * r + 0] = fit->anova[r].ss;
    anova[5 * r + 1] = fit->anova[r].df;
    anova[5 * r + 2] = fit->anova[r].ms;
    anova[5 * r + 3] = fit->anova[r].f;
    anova[5 * r + 4] = fit->anova[r].p;
  }
  size_t dims[2] = {POM_RSM_N_ROWS, 5};
  POM_TRY(pom_h5_write_doubles(loc, "anova", 2, dims, anova, err));
  static const char *const rows[POM_RSM_N_ROWS] = {
      "model", "linear", "square", "interaction", "residual", "lack_of_fit", "pure_error", "total"};
  POM_TRY(pom_h5_write_strings(loc, "anova_rows", POM_RSM_N_ROWS, rows, 16, err));
  POM_TRY(pom_h5_attr_string(loc, "anova_columns", "ss, df, ms, F, p", err));
  POM_TRY(pom_h5_attr_double(loc, "r2", fit->r2, err));
  POM_TRY(pom_h5_attr_double(loc, "r2_adj", fit->r2_adj, err));
  POM_TRY(pom_h5_attr_double(loc, "r2_pred", fit->r2_pred, err));
  POM_TRY(pom_h5_attr_double(loc, "press", fit->press, err));
  POM_TRY(pom_h5_attr_double(loc, "sigma", fit->sigma, err));
  POM_TRY(pom_h5_attr_int64(loc, "has_lack_of_fit", fit->has_lack_of_fit, err));
  if (has_check) {
    POM_TRY(pom_h5_attr_double(loc, "holdout_rmse", chk->rmse, err));
    POM_TRY(pom_h5_attr_double(loc, "holdout_max_abs", chk->max_abs, err));
    POM_TRY(pom_h5_attr_double(loc, "holdout_r2", chk->r2, err));
    POM_TRY(pom_h5_attr_double(loc, "holdout_within_pi", chk->within_pi, err));
  }
  return POM_OK;
}

static pom_status write_opt(hid_t loc, const pom_opt_result *r, pom_error *err) {
  POM_TRY(pom_h5_attr_int64(loc, "evals_global", r->evals_global, err));
  POM_TRY(pom_h5_attr_int64(loc, "evals_local", r->evals_local, err));
  POM_TRY(pom_h5_attr_string(loc, "result_global", pom_opt_result_name(r->result_global), err));
  POM_TRY(pom_h5_attr_string(loc, "result_local", pom_opt_result_name(r->result_local), err));
  POM_TRY(pom_h5_attr_double(loc, "wall_time_s", r->wall_time, err));
  return POM_OK;
}

/* One stage: bounds, design, responses, surfaces and the stage's own optimum. */
static pom_status write_stage(hid_t loc, const pom_syn_run *run, pom_error *err) {
  const pom_syn_problem *pb = run->pb;
  size_t k = (size_t)pb->n_vars, nr = POM_SYN_N_RESP;
  hid_t g = -1;
  pom_status st = POM_OK;
  const char *rn[POM_SYN_N_RESP];
  for (size_t r = 0; r < nr; ++r)
    rn[r] = pom_syn_resp_name((pom_syn_resp)r);
  POM_TRY(pom_h5_write_doubles(loc, "lower_bounds", 1, &k, pb->lo, err));
  POM_TRY(pom_h5_write_doubles(loc, "upper_bounds", 1, &k, pb->hi, err));

  POM_TRY(pom_h5_create_group(&g, loc, "design", err));
  size_t dx[2] = {(size_t)run->n_runs, k}, dr[2] = {(size_t)run->n_runs, nr};
  POM_TRY_GOTO(pom_h5_attr_string(g, "kind", pom_design_kind_name(run->design->kind), err), out);
  POM_TRY_GOTO(pom_h5_attr_double(g, "alpha", run->design->alpha, err), out);
  POM_TRY_GOTO(pom_h5_attr_int64(g, "degenerate_runs", run->n_degenerate, err), out);
  POM_TRY_GOTO(pom_h5_attr_double(g, "time_s", run->design_time, err), out);
  POM_TRY_GOTO(pom_h5_write_doubles(g, "coded", 2, dx, run->design->coded, err), out);
  POM_TRY_GOTO(pom_h5_write_doubles(g, "natural", 2, dx, run->x, err), out);
  POM_TRY_GOTO(pom_h5_write_doubles(g, "responses", 2, dr, run->resp, err), out);
  if (run->n_holdout > 0) {
    size_t hx[2] = {(size_t)run->n_holdout, k}, hr[2] = {(size_t)run->n_holdout, nr};
    POM_TRY_GOTO(pom_h5_write_doubles(g, "holdout_natural", 2, hx, run->holdout_x, err), out);
    POM_TRY_GOTO(pom_h5_write_doubles(g, "holdout_responses", 2, hr, run->holdout_resp, err), out);
  }
  H5Gclose(g);
  g = -1;

  hid_t fits = -1;
  POM_TRY(pom_h5_create_group(&fits, loc, "fits", err));
  for (size_t r = 0; r < nr; ++r) {
    if (!run->fitted[r]) continue;
    POM_TRY_GOTO(pom_h5_create_group(&g, fits, rn[r], err), out_fits);
    POM_TRY_GOTO(write_fit(g, &run->fit[r], &run->check[r], run->n_holdout > 0, err), out_fits);
    H5Gclose(g);
    g = -1;
  }
out_fits:
  H5Gclose(fits);
  if (st != POM_OK) goto out;

  POM_TRY_GOTO(pom_h5_create_group(&g, loc, "stage_optimum", err), out);
  POM_TRY_GOTO(pom_h5_write_doubles(g, "x", 1, &k, run->stage_x_opt, err), out);
  POM_TRY_GOTO(pom_h5_attr_double(g, "desirability_predicted", run->stage_d_predicted, err), out);
  POM_TRY_GOTO(pom_h5_attr_double(g, "desirability_confirmed", run->stage_d_confirmed, err), out);
  POM_TRY_GOTO(write_opt(g, &run->surrogate, err), out);
out:
  if (g >= 0) H5Gclose(g);
  return st;
}

static pom_status write_body(hid_t file, const pom_syn_run *run, const char *config_text,
                             pom_error *err) {
  const pom_syn_problem *pb = run->pb;
  size_t k = (size_t)pb->n_vars, nr = POM_SYN_N_RESP;
  hid_t g = -1;
  pom_status st = POM_OK;
  const char *vn[POM_SYN_N_VARS], *rn[POM_SYN_N_RESP];
  for (size_t i = 0; i < k; ++i)
    vn[i] = pom_syn_var_name(pb, (int)i);
  for (size_t r = 0; r < nr; ++r)
    rn[r] = pom_syn_resp_name((pom_syn_resp)r);

  POM_TRY(pom_h5_attr_string(file, "program", "pomlab synth " POM_VERSION, err));
  POM_TRY(pom_h5_attr_string(file, "git_commit", POM_GIT_COMMIT, err));
  POM_TRY(pom_h5_attr_string(file, "architecture", pom_kin_arch_name(&pb->base), err));
  POM_TRY(pom_h5_attr_string(file, "name", pb->base.name, err));
  POM_TRY(pom_h5_attr_string(file, "units",
                             "variables and responses in SI (angles in rad, ratios to the "
                             "platform radius); names carry the config units",
                             err));
  if (config_text) POM_TRY(pom_h5_write_text(file, "config", config_text, err));
  POM_TRY(pom_h5_write_strings(file, "variables", k, vn, 32, err));
  POM_TRY(pom_h5_write_strings(file, "responses", nr, rn, 32, err));
  POM_TRY(write_stage(file, run, err));

  /* best optimum over the stages, and its confirmation */
  POM_TRY_GOTO(pom_h5_create_group(&g, file, "optimum", err), out);
  POM_TRY_GOTO(pom_h5_write_doubles(g, "x", 1, &k, run->x_opt, err), out);
  POM_TRY_GOTO(pom_h5_write_doubles(g, "predicted", 1, &nr, run->predicted, err), out);
  POM_TRY_GOTO(pom_h5_write_doubles(g, "confirmed", 1, &nr, run->confirmed, err), out);
  POM_TRY_GOTO(pom_h5_attr_double(g, "desirability_predicted", run->d_predicted, err), out);
  POM_TRY_GOTO(pom_h5_attr_double(g, "desirability_confirmed", run->d_confirmed, err), out);
  POM_TRY_GOTO(pom_h5_attr_int64(g, "best_stage", run->best_stage, err), out);
  POM_TRY_GOTO(pom_h5_attr_int64(g, "true_evaluations", run->true_evals, err), out);
  POM_TRY_GOTO(pom_h5_attr_double(g, "time_total_s", run->surrogate_time, err), out);
  H5Gclose(g);
  g = -1;

  if (run->direct_done) {
    POM_TRY_GOTO(pom_h5_create_group(&g, file, "direct", err), out);
    POM_TRY_GOTO(pom_h5_write_doubles(g, "x", 1, &k, run->x_direct, err), out);
    POM_TRY_GOTO(pom_h5_write_doubles(g, "responses", 1, &nr, run->direct_resp, err), out);
    POM_TRY_GOTO(pom_h5_attr_double(g, "desirability", run->d_direct, err), out);
    POM_TRY_GOTO(write_opt(g, &run->direct, err), out);
    H5Gclose(g);
    g = -1;
  }

  if (run->scaled_done) {
    POM_TRY_GOTO(pom_h5_create_group(&g, file, "scaled", err), out);
    POM_TRY_GOTO(pom_h5_attr_double(g, "platform_radius_m", run->scale, err), out);
    POM_TRY_GOTO(
        pom_h5_attr_string(g, "optimum", run->written_direct ? "direct" : "surrogate", err), out);
    POM_TRY_GOTO(pom_h5_attr_string(g, "write", pom_syn_write_name(pb->write), err), out);
    POM_TRY_GOTO(pom_h5_attr_double(g, "desirability_base_scale", run->d_written, err), out);
    POM_TRY_GOTO(pom_h5_write_doubles(g, "x", 1, &k, run->x_written, err), out);
    POM_TRY_GOTO(pom_h5_attr_double(g, "target_half_width_rad", pb->target_half_width, err), out);
    POM_TRY_GOTO(pom_h5_attr_int64(g, "bisection_evals", run->scale_evals, err), out);
    POM_TRY_GOTO(pom_h5_write_doubles(g, "responses", 1, &nr, run->scaled_resp, err), out);
    size_t d33[2] = {3, 3};
    const pom_kin_arch_type *t = pb->base.type;
    for (int ps = 0; ps < t->n_points; ++ps) {
      const double *pts =
          (const double *)(const void *)((const char *)run->scaled.data + t->points[ps].offset);
      POM_TRY_GOTO(pom_h5_write_doubles(g, t->points[ps].key, 2, d33, pts, err), out);
    }
    H5Gclose(g);
    g = -1;
  }

  if (run->n_cap_checks > 0) { /* the capability floor (synthesis.capability_require) */
    const pom_syn_cap *c = &pb->cap;
    POM_TRY_GOTO(pom_h5_create_group(&g, file, "capability", err), out);
    POM_TRY_GOTO(pom_h5_attr_int64(g, "met", run->cap_met, err), out);
    POM_TRY_GOTO(pom_h5_attr_int64(g, "switched", run->cap_switched, err), out);
    POM_TRY_GOTO(pom_h5_attr_int64(g, "grid_points", c->grid, err), out);
    char text[POM_SYN_MAX_CAP_REQUIRE][96];
    const char *req[POM_SYN_MAX_CAP_REQUIRE];
    for (int j = 0; j < c->n; ++j) {
      pom_cap_requirement_text(text[j], sizeof text[j], &c->req[j]);
      req[j] = text[j];
    }
    POM_TRY_GOTO(pom_h5_write_strings(g, "requirements", (size_t)c->n, req, 96, err), out);
    /* per check (rows, in the order checked): direct (1) or surrogate (0),
       platform radius (m), all met, then per requirement its figure's value
       (SI) and met (1/0) */
    size_t cols = 3 + 2 * (size_t)c->n, rows = (size_t)run->n_cap_checks;
    double tab[2 * (3 + 2 * POM_SYN_MAX_CAP_REQUIRE)];
    for (size_t i = 0; i < rows; ++i) {
      const pom_syn_cap_check *ck = &run->cap_check[i];
      double *r = tab + i * cols;
      r[0] = ck->direct;
      r[1] = ck->scale;
      r[2] = ck->all_met;
      for (int j = 0; j < c->n; ++j) {
        r[3 + 2 * j] = ck->value[c->req[j].figure];
        r[4 + 2 * j] = ck->met[j];
      }
    }
    size_t dims[2] = {rows, cols};
    POM_TRY_GOTO(pom_h5_write_doubles(g, "checks", 2, dims, tab, err), out);
    POM_TRY_GOTO(pom_h5_attr_string(g, "checks_columns",
                                    "direct (1) or surrogate (0), platform_radius_m, met, then per "
                                    "requirement: value (SI), met",
                                    err),
                 out);
    H5Gclose(g);
    g = -1;
  }

  if (run->refined) {
    hid_t rg = -1;
    POM_TRY_GOTO(pom_h5_create_group(&rg, file, "refine", err), out);
    int s = 1;
    for (const pom_syn_run *r = run->refined; r && st == POM_OK; r = r->refined, ++s) {
      char name[32];
      snprintf(name, sizeof name, "stage_%d", s);
      st = pom_h5_create_group(&g, rg, name, err);
      if (st == POM_OK) st = write_stage(g, r, err);
      if (g >= 0) H5Gclose(g);
      g = -1;
    }
    H5Gclose(rg);
  }
out:
  if (g >= 0) H5Gclose(g);
  return st;
}

pom_status pom_syn_write_h5(const pom_syn_run *run, const char *path, const char *config_text,
                            pom_error *err) {
  hid_t file = -1;
  POM_TRY(pom_h5_create_file(&file, path, err));
  pom_status st = write_body(file, run, config_text, err);
  pom_error sub;
  pom_error_clear(&sub);
  pom_status cst = pom_h5_close_file(file, &sub);
  if (st == POM_OK && cst != POM_OK) {
    if (err) *err = sub;
    st = cst;
  }
  if (st != POM_OK) pom_error_prefix(err, "writing %s", path);
  return st;
}
