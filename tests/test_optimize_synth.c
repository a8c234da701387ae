/* test_optimize_synth.c - kinematic synthesis on problems with known answers. */
#include "check.h"
#include "pom_math.h"
#include "pom_synth.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

/* 3SPS with the limb purely tangential (azimuth 90 deg) and the platform
 * points in the plane of O: J row i = r (-s_z e_t + s_t e_z), so the singular
 * values at home are sqrt(3/2) r cos(lean) (twice) and sqrt(3) r sin(lean),
 * and the home dexterity is isotropic at tan(lean) = 1/sqrt(2)
 * (docs/optimize.md 8). */
static const char *base_3sps =
    "name = \"t3sps\"; architecture = \"3SPS\";\n"
    "geometry = { mode = \"parameters\"; platform_radius_mm = 15.0; first_azimuth_deg = 90.0;\n"
    "  platform_height = 0.0; limb_length = 7.0; limb_lean_deg = 35.0; limb_azimuth_deg = 90.0; "
    "};\n"
    "limits = { stroke_mm = 12.0; cone_base_max_deg = 45.0; cone_platform_max_deg = 60.0;\n"
    "  min_limb_distance_mm = 5.0; };\n"
    "workspace = { dexterity_min = 0.3; resolution_deg = 1.0; max_half_width_deg = 30.0; };\n";

static double home_dexterity(double lean) {
  double a = sqrt(1.5) * cos(lean), b = sqrt(3.0) * sin(lean);
  return fmin(a, b) / fmax(a, b);
}

static pom_status load(pom_syn_problem *pb, const char *synth_group, pom_error *err) {
  char text[4096];
  snprintf(text, sizeof text, "%s%s", base_3sps, synth_group);
  pom_cfg *cfg = NULL;
  pom_status st = pom_cfg_load_string(&cfg, text, "<test>", err);
  if (st == POM_OK) st = pom_syn_load(pb, cfg, err);
  pom_cfg_destroy(cfg);
  return st;
}

/* Maximize the home dexterity over the lean (and a limb length that does not
 * change it): the optimum is the isotropic lean atan(1/sqrt 2). */
static void test_known_optimum(void) {
  static pom_syn_problem pb;
  pom_error err;
  pom_error_clear(&err);
  const char *synth =
      "synthesis = {\n"
      "  variables = ( { name = \"limb_lean_deg\"; min = 20.0; max = 55.0; },\n"
      "                { name = \"limb_length\"; min = 5.0; max = 9.0; } );\n"
      "  design = { kind = \"ccd_rotatable\"; center_points = 1; };\n"
      "  holdout_points = 6;\n"
      "  region_half_width_deg = 0.25; region_resolution_deg = 1.0;\n"
      "  goals = ( { response = \"min_dexterity\"; goal = \"maximize\"; low = 0.3; high = 1.0; } "
      ");\n"
      "  optimizer = { global = \"direct_l\"; global_max_evals = 2000; local = \"bobyqa\"; };\n"
      "  direct = { enabled = true; global = \"direct_l\"; global_max_evals = 60; local = "
      "\"bobyqa\";\n"
      "             local_max_evals = 60; local_xtol_rel = 1e-7; };\n"
      "  target_half_width_deg = 10.0; scale_min_mm = 2.0; scale_max_mm = 100.0;\n"
      "  scale_rel_tol = 1e-4; refine_stages = 1; refine_shrink = 0.4;\n"
      "};\n";
  pom_status st = load(&pb, synth, &err);
  check_true(st == POM_OK);
  if (st != POM_OK) {
    printf("load: %s\n", err.message);
    return;
  }
  /* The region is one cell: its midpoint is home, so min dexterity = GCI =
     the analytic home dexterity. */
  const double leans[3] = {23.85, 35.0, 51.3};
  for (int i = 0; i < 3; ++i) {
    double x[2] = {leans[i] * POM_DEG, 7.0}, resp[POM_SYN_N_RESP];
    int deg = 1;
    check_true(pom_syn_evaluate(&pb, x, resp, &deg, &err) == POM_OK && deg == 0);
    /* 1e-7: closed-form singular values, see below */
    check_abs(resp[POM_SYN_RESP_MIN_DEXTERITY], home_dexterity(x[0]), 1e-7);
    check_abs(resp[POM_SYN_RESP_GCI], home_dexterity(x[0]), 1e-7);
    check_abs(resp[POM_SYN_RESP_UNREACHABLE], 0.0, 0.0);
  }
  pom_syn_run *run = NULL;
  check_true(pom_syn_begin(&run, &pb, &err) == POM_OK);
  check_true(run->n_runs == 4 + 4 + 1);
  st = pom_syn_finish(run, &err);
  check_true(st == POM_OK);
  if (st != POM_OK) printf("finish: %s\n", err.message);
  const double lean_opt = atan(1.0 / sqrt(2.0));
  /* Direct optimization on the true kinematics finds the isotropic lean; the
     dexterity has a kink there, so BOBYQA's xtol 1e-7 gives ~1e-6 rad. */
  check_abs(run->x_direct[0], lean_opt, 1e-4);
  check_abs(run->direct_resp[POM_SYN_RESP_MIN_DEXTERITY], 1.0, 1e-4);
  /* The quadratic surface cannot follow the kink exactly: its optimum lies
     within a few degrees, and the confirmation is the true value there. */
  check_abs(run->x_opt[0], lean_opt, 4.0 * POM_DEG);
  /* the kinematics module computes singular values in closed form (roots of
     the cubic of J^T J): near-repeated roots lose about half the digits */
  check_abs(run->confirmed[POM_SYN_RESP_MIN_DEXTERITY], home_dexterity(run->x_opt[0]), 1e-7);
  check_true(run->d_direct >= run->d_confirmed);
  /* synthesis.write defaults to the surrogate: its optimum is the one scaled,
     and the run says whether the direct search did better */
  check_true(run->direct_better == (run->d_direct > run->d_confirmed));
  check_true(!run->written_direct && run->scaled_done);
  for (int i = 0; i < 2; ++i) {
    check_true(run->x_written[i] == run->x_opt[i]);
    check_true(run->scaled.design.x[pb.var[i]] == run->x_opt[i]);
  }
  /* "best" scales the direct optimum when it is the better one (here: the
     exact isotropic lean against the quadratic's approximation) */
  {
    static pom_syn_problem best;
    best = pb;
    best.write = POM_SYN_WRITE_BEST;
    pom_syn_run *rb = NULL;
    check_true(pom_syn_begin(&rb, &best, &err) == POM_OK);
    check_true(rb && pom_syn_finish(rb, &err) == POM_OK);
    if (rb) {
      check_true(rb->direct_better && rb->written_direct);
      check_true(rb->d_written == rb->d_direct);
      for (int i = 0; i < 2; ++i)
        check_true(rb->scaled.design.x[pb.var[i]] == rb->x_direct[i]);
      check_abs(rb->scaled.design.x[pb.var[0]], lean_opt, 1e-4);
    }
    pom_syn_destroy(rb);
  }
  check_true(run->fitted[POM_SYN_RESP_MIN_DEXTERITY] && run->n_holdout == 6);
  /* The held-out check compares each held-out run with the surface at the
     same natural point: coded through the design's own alpha (sqrt 2 for
     this rotatable CCD), not the unit cube. */
  {
    const pom_rsm_fit *fm = &run->fit[POM_SYN_RESP_MIN_DEXTERITY];
    double ss = 0.0;
    for (int i = 0; i < run->n_holdout; ++i) {
      double uc[2];
      for (int j = 0; j < 2; ++j)
        uc[j] = pom_design_to_coded(run->holdout_x[2 * i + j], sqrt(2.0), pb.lo[j], pb.hi[j]);
      double e = run->holdout_resp[i * POM_SYN_N_RESP + POM_SYN_RESP_MIN_DEXTERITY] -
                 pom_rsm_predict(fm, uc, NULL);
      ss += e * e;
    }
    check_rel(run->check[POM_SYN_RESP_MIN_DEXTERITY].rmse, sqrt(ss / run->n_holdout), 1e-12);
  }
  /* one refinement stage: a box 0.4 times as wide inside the first, about the
     first optimum; the best confirmed stage is kept */
  check_true(run->refined != NULL && run->refined->refined == NULL);
  if (run->refined) {
    const pom_syn_problem *sub = run->refined->pb;
    for (int i = 0; i < 2; ++i) {
      check_rel(sub->hi[i] - sub->lo[i], 0.4 * (pb.hi[i] - pb.lo[i]), 1e-12);
      check_true(sub->lo[i] >= pb.lo[i] && sub->hi[i] <= pb.hi[i]);
      check_true(run->stage_x_opt[i] >= sub->lo[i] - 1e-12 &&
                 run->stage_x_opt[i] <= sub->hi[i] + 1e-12);
    }
    check_true(run->d_confirmed >= run->stage_d_confirmed);
    check_true(run->d_confirmed >= run->refined->stage_d_confirmed);
    check_true(run->true_evals == 2 * (9 + 6 + 1));
  }

  /* Scaling: the radius found covers the target; 0.2 % larger does not. */
  pom_kin_arch arch;
  pom_kin_ws_result ws;
  check_true(pom_syn_arch(&pb, run->x_opt, run->scale, &arch, &err) == POM_OK);
  check_true(pom_kin_workspace(&arch, &pb.ws, &ws, &err) == POM_OK);
  /* (1e-9 of a grid step: the workspace is k * step, the target 10 steps) */
  const double slack = 1e-9 * pb.ws.resolution;
  check_true(ws.half_width >= pb.target_half_width - slack);
  check_true(pom_syn_arch(&pb, run->x_opt, run->scale * 1.002, &arch, &err) == POM_OK);
  check_true(pom_kin_workspace(&arch, &pb.ws, &ws, &err) == POM_OK);
  check_true(ws.half_width < pb.target_half_width - slack);
  check_abs(run->scaled_resp[POM_SYN_RESP_RDW], pb.target_half_width, slack);
  /* A target between grid steps (9.3 deg, step 1 deg) is covered only by the
     10 deg cube: the scaled geometry never has less than the target. */
  pom_syn_problem pb93 = pb;
  pb93.target_half_width = 9.3 * POM_DEG;
  double scale93 = 0.0;
  int evals93 = 0;
  check_true(pom_syn_scale(&pb93, run->x_opt, &scale93, &evals93, &err) == POM_OK);
  check_true(pom_syn_arch(&pb, run->x_opt, scale93, &arch, &err) == POM_OK);
  check_true(pom_kin_workspace(&arch, &pb.ws, &ws, &err) == POM_OK);
  check_true(ws.half_width >= pb93.target_half_width);

  /* Output files: the fragment loads back as the same geometry. */
  /* names unique per process: several build trees may run the suite at once */
  char geo[128], h5[128];
  unsigned long tag = (unsigned long)time(NULL) ^ (unsigned long)(uintptr_t)&tag;
  snprintf(geo, sizeof geo, "/tmp/pomlab_test_synth_%lx.geometry.cfg", tag);
  snprintf(h5, sizeof h5, "/tmp/pomlab_test_synth_%lx.h5", tag);
  /* a refinement stage is not scaled: nothing to write (was all zeros) */
  check_true(run->refined && !run->refined->scaled_done &&
             pom_syn_write_geometry(run->refined, geo, &err) == POM_ERR_ARG);
  check_true(pom_syn_write_geometry(run, geo, &err) == POM_OK);
  check_true(pom_syn_write_h5(run, h5, "text", &err) == POM_OK);
  char text[2048];
  snprintf(text, sizeof text, "architecture = \"3SPS\";\n@include \"%s\"\n", geo);
  pom_cfg *cfg = NULL;
  pom_kin_arch back;
  check_true(pom_cfg_load_string(&cfg, text, "<back>", &err) == POM_OK);
  check_true(pom_kin_arch_load(&back, cfg, &err) == POM_OK);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      check_abs(pom_kin_arch_points(&back, "base_points_m")[3 * i + j],
                pom_kin_arch_points(&run->scaled, "base_points_m")[3 * i + j], 1e-9);
  pom_cfg_destroy(cfg);
  remove(geo);
  remove(h5);
  pom_syn_destroy(run);
}

/* Region responses against the kinematics module's own GCI, and the
 * footprint against the ground points. */
static void test_responses(void) {
  static pom_syn_problem pb;
  pom_error err;
  const char *synth = "synthesis = { variables = ( { name = \"limb_lean_deg\"; min = 20.0; "
                      "max = 55.0; } ); goals = ( { response = \"gci\"; goal = \"maximize\"; "
                      "low = 0.0; high = 1.0; } ); region_half_width_deg = 8.0; "
                      "region_resolution_deg = 2.0; };\n";
  check_true(load(&pb, synth, &err) == POM_OK);
  double x[1] = {41.3 * POM_DEG}, resp[POM_SYN_N_RESP], gci = 0.0, usable = 0.0;
  pom_kin_arch arch;
  check_true(pom_syn_arch(&pb, x, pb.base.design.scale, &arch, &err) == POM_OK);
  check_true(pom_syn_responses(&pb, &arch, resp, &err) == POM_OK);
  check_true(pom_kin_gci(&arch, pb.region_half_width, pb.region_resolution, 1, &gci, &usable,
                         &err) == POM_OK);
  check_rel(resp[POM_SYN_RESP_GCI], gci, 1e-12);
  double r = 0.0;
  for (int i = 0; i < 3; ++i)
    r = fmax(r, hypot(pom_kin_arch_points(&arch, "base_points_m")[3 * i],
                      pom_kin_arch_points(&arch, "base_points_m")[3 * i + 1]));
  check_rel(resp[POM_SYN_RESP_FOOTPRINT], r / arch.design.scale, 1e-14);
  /* A region of +-20 deg reaches beyond the stroke on about 9 % of its
     measure: the GCI is the mean over the usable poses only, and the
     violation fractions are the rest (same midpoint rule, 1e-12 for the
     summation order). */
  static pom_syn_problem wide;
  wide = pb;
  wide.region_half_width = 20.0 * POM_DEG;
  check_true(pom_syn_responses(&wide, &arch, resp, &err) == POM_OK);
  check_true(pom_kin_gci(&arch, wide.region_half_width, wide.region_resolution, 1, &gci, &usable,
                         &err) == POM_OK);
  check_true(usable > 0.5 && usable < 0.99);
  check_rel(resp[POM_SYN_RESP_GCI], gci, 1e-12);
  check_abs(resp[POM_SYN_RESP_STROKE] + resp[POM_SYN_RESP_CONE] + resp[POM_SYN_RESP_INTERFERENCE] +
                resp[POM_SYN_RESP_UNREACHABLE],
            1.0 - usable, 1e-12);
  /* a vertical limb (lean 0) cannot turn the platform about z: degenerate */
  double x0[1] = {0.0};
  int deg = 0;
  check_true(pom_syn_evaluate(&pb, x0, resp, &deg, &err) == POM_OK);
  check_true(deg == 1 && resp[POM_SYN_RESP_RDW] == 0.0 && resp[POM_SYN_RESP_UNREACHABLE] == 1.0);
}

static void test_config_errors(void) {
  static pom_syn_problem pb;
  pom_error err;
  pom_error_clear(&err);
  check_true(load(&pb, "", &err) == POM_ERR_CONFIG);
  check_true(strstr(err.message, "synthesis") != NULL);
  check_true(load(&pb,
                  "synthesis = { variables = ( { name = \"actuator_tilt_deg\"; min = 0.0; "
                  "max = 10.0; } ); goals = ( { response = \"gci\"; goal = \"maximize\"; "
                  "low = 0.0; high = 1.0; } ); };\n",
                  &err) == POM_ERR_CONFIG);
  check_true(strstr(err.message, "3SPS") != NULL);
  check_true(load(&pb,
                  "synthesis = { variables = ( { name = \"limb_length\"; min = 5.0; max = 4.0; "
                  "} ); goals = ( { response = \"gci\"; goal = \"maximize\"; low = 0.0; "
                  "high = 1.0; } ); };\n",
                  &err) == POM_ERR_CONFIG);
  check_true(load(&pb,
                  "synthesis = { variables = ( { name = \"limb_length\"; min = 5.0; max = 8.0; "
                  "} ); goals = ( { response = \"gci\"; goal = \"target\"; low = 0.0; "
                  "target = 2.0; high = 1.0; } ); };\n",
                  &err) == POM_ERR_CONFIG);
  /* writing the direct optimum needs the direct search */
  check_true(load(&pb,
                  "synthesis = { variables = ( { name = \"limb_length\"; min = 5.0; max = 8.0; "
                  "} ); goals = ( { response = \"gci\"; goal = \"maximize\"; low = 0.0; "
                  "high = 1.0; } ); direct = { enabled = false; }; write = \"direct\"; };\n",
                  &err) == POM_ERR_CONFIG);
  check_true(strstr(err.message, "synthesis.write") != NULL);
  check_true(load(&pb,
                  "synthesis = { variables = ( { name = \"limb_length\"; min = 5.0; max = 8.0; "
                  "} ); goals = ( { response = \"gci\"; goal = \"maximize\"; low = 0.0; "
                  "high = 1.0; } ); write = \"newest\"; };\n",
                  &err) == POM_ERR_CONFIG);
}

int main(void) {
  test_responses();
  test_config_errors();
  test_known_optimum();
  return check_summary("test_optimize_synth");
}
