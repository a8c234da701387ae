/* pom_doe_results.c - the study's HDF5 results file (layout:
 * docs/results.md, "Results file"). Only the root rank's driving thread
 * touches it. */
#define _POSIX_C_SOURCE 200809L
#include "pom_doe_internal.h"
#include "pom_version.h"
#include "pom_h5.h"
#include "pom_math.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define FORMAT_NAME    "pomlab study results"
#define FORMAT_VERSION 1
#define ROWS_PER_CHUNK 256

struct pom_doe_results {
  hid_t file;     /* the open file */
  hid_t row_mem;  /* compound type of pom_doe_row in memory */
  hid_t row_file; /* packed compound type in the file */
  int n_candidates;
  long n_maneuvers;
  hid_t *rows; /* [n_candidates] open maneuvers datasets */
};

/* ---- the row type -------------------------------------------------------------- */
static pom_status row_types(hid_t *mem, hid_t *file, pom_error *err) {
  hsize_t three = 3;
  hid_t d3 = H5Tarray_create2(H5T_NATIVE_DOUBLE, 1, &three);
  hid_t i3 = H5Tarray_create2(H5T_NATIVE_INT32, 1, &three);
  hid_t l3 = H5Tarray_create2(H5T_NATIVE_INT64, 1, &three);
  hid_t str = H5Tcopy(H5T_C_S1);
  *mem = *file = -1;
  if (d3 < 0 || i3 < 0 || l3 < 0 || str < 0 || H5Tset_size(str, POM_DOE_REASON_LEN) < 0 ||
      H5Tset_strpad(str, H5T_STR_NULLTERM) < 0)
    goto fail;
  *mem = H5Tcreate(H5T_COMPOUND, sizeof(pom_doe_row));
  if (*mem < 0) goto fail;
  if (H5Tinsert(*mem, "done", HOFFSET(pom_doe_row, done), H5T_NATIVE_INT32) < 0 ||
      H5Tinsert(*mem, "status", HOFFSET(pom_doe_row, status), H5T_NATIVE_INT32) < 0 ||
      H5Tinsert(*mem, "reason", HOFFSET(pom_doe_row, reason), str) < 0)
    goto fail;
  /* every metric of the schema, in list order */
  const pom_dyn_metric_info *schema = pom_dyn_metric_schema();
  for (int j = 0; j < POM_DYN_N_METRICS; ++j) {
    const pom_dyn_metric_info *mi = &schema[j];
    hid_t type = mi->type == POM_DYN_TYPE_INT    ? (mi->count == 3 ? i3 : H5T_NATIVE_INT32)
                 : mi->type == POM_DYN_TYPE_LONG ? (mi->count == 3 ? l3 : H5T_NATIVE_INT64)
                                                 : (mi->count == 3 ? d3 : H5T_NATIVE_DOUBLE);
    if (H5Tinsert(*mem, mi->name, pom_doe_row_offset(j), type) < 0) goto fail;
  }
  *file = H5Tcopy(*mem);
  /* packed in the file: no padding bytes (whose contents are undefined) */
  if (*file < 0 || H5Tpack(*file) < 0) goto fail;
  H5Tclose(d3);
  H5Tclose(i3);
  H5Tclose(l3);
  H5Tclose(str);
  return POM_OK;
fail:;
  pom_status st = pom_h5_fail(err, __FILE__, __LINE__, "building the maneuver row type");
  if (*mem >= 0) H5Tclose(*mem);
  if (*file >= 0) H5Tclose(*file);
  *mem = *file = -1;
  if (d3 >= 0) H5Tclose(d3);
  if (i3 >= 0) H5Tclose(i3);
  if (l3 >= 0) H5Tclose(l3);
  if (str >= 0) H5Tclose(str);
  return st;
}

static pom_status results_alloc(pom_doe_results **out, const pom_doe_study *study, pom_error *err) {
  pom_doe_results *res = calloc(1, sizeof *res);
  if (!res) POM_FAIL(err, POM_ERR_NOMEM, "results: out of memory");
  res->file = res->row_mem = res->row_file = -1;
  res->n_candidates = study->n_candidates;
  res->n_maneuvers = study->maneuvers.count;
  res->rows = malloc((size_t)study->n_candidates * sizeof *res->rows);
  if (!res->rows) {
    free(res);
    POM_FAIL(err, POM_ERR_NOMEM, "results: out of memory");
  }
  for (int c = 0; c < study->n_candidates; ++c)
    res->rows[c] = -1;
  *out = res;
  return row_types(&res->row_mem, &res->row_file, err);
}

/* ---- candidate provenance ------------------------------------------------------ */
pom_status pom_doe_describe_dyn_params(hid_t g, const pom_dyn_params *par, pom_error *err) {
  POM_TRY(
      pom_h5_attr_string(g, "controller_form", pom_dyn_pid_form_name(par->controller.form), err));
  POM_TRY(pom_h5_attr_double(g, "controller_kp", par->controller.kp, err));
  POM_TRY(pom_h5_attr_double(g, "controller_ki", par->controller.ki, err));
  POM_TRY(pom_h5_attr_double(g, "controller_kd", par->controller.kd, err));
  POM_TRY(pom_h5_attr_string(g, "orientation", pom_dyn_orient_name(par->scene.orientation), err));
  POM_TRY(pom_h5_attr_string(g, "joints_model", pom_dyn_joint_model_name(par->joints.model), err));
  POM_TRY(pom_h5_attr_int64(g, "scene_gravity", par->scene.gravity, err));
  POM_TRY(pom_h5_attr_int64(g, "scene_bearing_friction", par->scene.bearing_friction, err));
  POM_TRY(pom_h5_attr_int64(g, "scene_coil_inductance", par->scene.coil_inductance, err));
  POM_TRY(pom_h5_attr_double(g, "solver_rtol", par->solver.rtol, err));
  POM_TRY(pom_h5_attr_double(g, "solver_atol_scale", par->solver.atol_scale, err));
  POM_TRY(pom_h5_attr_double(g, "solver_max_step_s", par->solver.max_step, err));
  POM_TRY(pom_h5_attr_int64(g, "solver_max_steps", par->solver.max_steps, err));
  POM_TRY(pom_h5_attr_double(g, "solver_max_wall_s", par->solver.max_wall, err));
  POM_TRY(pom_h5_attr_string(g, "solver_linear_solver",
                             pom_dyn_linsol_name(par->solver.linear_solver), err));
  POM_TRY(pom_h5_attr_double(g, "maneuver_horizon_s", par->maneuver.horizon, err));
  POM_TRY(pom_h5_attr_double(g, "maneuver_settle_band", par->maneuver.settle_band, err));
  return POM_OK;
}

/* ---- create -------------------------------------------------------------------- */
/* The candidates' actuator kind (the first one's; joint-space studies have
 * one kind, pom_doe_maneuvers_check_kinds). */
static pom_actuator_kind study_kind(const pom_doe_study *study) {
  return study->n_candidates > 0 ? study->candidates[0].eval.actuator_kind : POM_ACT_PRISMATIC;
}

static int pom_doe_kinds_mixed_study(const pom_doe_study *study) {
  for (int c = 1; c < study->n_candidates; ++c)
    if (study->candidates[c].eval.actuator_kind != study_kind(study)) return 1;
  return 0;
}
static pom_status write_montecarlo(hid_t file, const pom_doe_study *study, pom_error *err) {
  static const char *const spaces[] = {"joint", "orientation"};
  static const char *const dists[] = {"uniform", "normal"};
  const pom_doe_maneuvers *mv = &study->maneuvers;
  pom_status st = POM_OK;
  hid_t g = -1;
  double *buf = NULL;
  POM_TRY(pom_h5_create_group(&g, file, "montecarlo", err));
  POM_TRY_GOTO(pom_h5_attr_int64(g, "count", mv->count, err), done);
  POM_TRY_GOTO(pom_h5_attr_int64(g, "seed", (int64_t)mv->seed, err), done);
  POM_TRY_GOTO(pom_h5_attr_string(g, "space", spaces[mv->space], err), done);
  POM_TRY_GOTO(pom_h5_attr_string(g, "distribution", dists[mv->distribution], err), done);
  /* range and sigma in the actuators' SI unit (joint space has one kind);
   * range_m and sigma_m kept for prismatic studies */
  pom_actuator_kind kind = study_kind(study);
  POM_TRY_GOTO(pom_h5_attr_double(g, "range", mv->range, err), done);
  POM_TRY_GOTO(pom_h5_attr_double(g, "sigma", mv->sigma, err), done);
  POM_TRY_GOTO(pom_h5_attr_string(
                   g, "actuator_unit",
                   pom_doe_kinds_mixed_study(study) ? "mixed" : pom_act_units_of(kind)->si, err),
               done);
  if (kind == POM_ACT_PRISMATIC) {
    POM_TRY_GOTO(pom_h5_attr_double(g, "range_m", mv->range, err), done);
    POM_TRY_GOTO(pom_h5_attr_double(g, "sigma_m", mv->sigma, err), done);
  }
  POM_TRY_GOTO(pom_h5_attr_double(g, "tilt_max_rad", mv->tilt_max, err), done);
  POM_TRY_GOTO(pom_h5_attr_double(g, "torsion_max_rad", mv->torsion_max, err), done);
  /* the drawn maneuvers, common to every candidate */
  buf = malloc((size_t)mv->count * 3 * sizeof *buf);
  if (!buf) POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "results: out of memory");
  for (long k = 0; k < mv->count; ++k) {
    pom_doe_maneuver m;
    pom_doe_maneuver_draw(&m, mv, k);
    for (int i = 0; i < 3; ++i)
      buf[3 * k + i] = mv->space == POM_DOE_SPACE_JOINT ? m.q[i] : m.orient[i];
  }
  size_t dims[2] = {(size_t)mv->count, 3};
  const char *table = mv->space == POM_DOE_SPACE_JOINT ? "target" : "tilt_torsion";
  POM_TRY_GOTO(pom_h5_write_doubles(g, table, 2, dims, buf, err), done);
  hid_t ds = H5Dopen2(g, table, H5P_DEFAULT);
  if (ds < 0) {
    st = pom_h5_fail(err, __FILE__, __LINE__, "annotating the maneuver table");
    goto done;
  }
  st = pom_h5_attr_string(ds, "unit",
                          mv->space != POM_DOE_SPACE_JOINT
                              ? "rad: azimuth, tilt, torsion (R = Rz(a) Ry(t) Rz(s - a))"
                          : kind == POM_ACT_REVOLUTE ? "rad from mid-stroke, per actuator"
                                                     : "m from mid-stroke, per actuator",
                          err);
  H5Dclose(ds);
done:
  free(buf);
  H5Gclose(g);
  return st;
}

/* Units and descriptions of the row fields (from the metric schema, the
 * actuator coordinate resolved for the candidate's kind) and the meaning of
 * the status codes, as attributes of a maneuvers dataset (docs/results.md,
 * section 5). */
static pom_status describe_rows(hid_t ds, pom_actuator_kind kind, pom_error *err) {
  char units[4096], descr[8192];
  size_t nu = 0, nd = 0;
  nu += (size_t)snprintf(units, sizeof units,
                         "done 1 once computed; status pom_status code (0 ok); reason text");
  nd += (size_t)snprintf(descr, sizeof descr,
                         "done: 1 once computed; status: pom_status of the maneuver; reason: "
                         "failure reason");
  const pom_dyn_metric_info *schema = pom_dyn_metric_schema();
  for (int j = 0; j < POM_DYN_N_METRICS && nu < sizeof units && nd < sizeof descr; ++j) {
    const pom_dyn_metric_info *mi = &schema[j];
    nu += (size_t)snprintf(units + nu, sizeof units - nu, "; %s %s", mi->name,
                           pom_dyn_metric_unit(mi, kind));
    nd += (size_t)snprintf(descr + nd, sizeof descr - nd, "; %s%s: %s", mi->name,
                           mi->count == 3 ? "[3]" : "", mi->description);
  }
  if (nu < sizeof units)
    snprintf(units + nu, sizeof units - nu, "; target, final_q, max_abs_q: from mid-stroke");
    /* every code of pom_status.h, from its list */
#define LEGEND_ITEM(name, value, msg) #value " " msg "; "
  static const char legend[] = POM_STATUS_LIST(LEGEND_ITEM);
#undef LEGEND_ITEM
  POM_TRY(pom_h5_attr_string(ds, "units", units, err));
  POM_TRY(pom_h5_attr_string(ds, "descriptions", descr, err));
  POM_TRY(pom_h5_attr_string(ds, "actuator_unit", pom_act_units_of(kind)->si, err));
  return pom_h5_attr_string(ds, "status_codes", legend, err);
}

static pom_status write_candidate(pom_doe_results *res, hid_t parent, const pom_doe_study *study,
                                  int c, pom_error *err) {
  const pom_doe_candidate *cand = &study->candidates[c];
  pom_status st = POM_OK;
  hid_t g = -1, space = -1, dcpl = -1;
  char name[32];
  snprintf(name, sizeof name, "%d", c);
  POM_TRY(pom_h5_create_group(&g, parent, name, err));
  POM_TRY_GOTO(pom_h5_attr_string(g, "name", cand->name, err), done);
  POM_TRY_GOTO(pom_h5_attr_string(g, "source", cand->source, err), done);
  POM_TRY_GOTO(pom_h5_attr_int64(g, "index", c, err), done);
  POM_TRY_GOTO(
      pom_h5_attr_string(g, "actuator_unit", pom_act_units_of(cand->eval.actuator_kind)->si, err),
      done);
  for (int f = 0; f < cand->n_factors; ++f) {
    char an[POM_DOE_NAME_LEN + 16];
    snprintf(an, sizeof an, "factor:%s", cand->factor_key[f]);
    POM_TRY_GOTO(pom_h5_attr_double(g, an, cand->factor_value[f], err), done);
  }
  POM_TRY_GOTO(pom_h5_write_text(g, "config", cand->resolved ? cand->resolved : "", err), done);
  if (cand->eval.describe) POM_TRY_GOTO(cand->eval.describe(cand->eval.ctx, g, err), done);
  hsize_t n = (hsize_t)res->n_maneuvers;
  hsize_t chunk = n < ROWS_PER_CHUNK ? n : ROWS_PER_CHUNK;
  space = H5Screate_simple(1, &n, NULL);
  dcpl = H5Pcreate(H5P_DATASET_CREATE);
  if (space < 0 || dcpl < 0 || H5Pset_chunk(dcpl, 1, &chunk) < 0) {
    st = pom_h5_fail(err, __FILE__, __LINE__, "creating the maneuvers dataset");
    goto done;
  }
  res->rows[c] = H5Dcreate2(g, "maneuvers", res->row_file, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  if (res->rows[c] < 0) {
    st = pom_h5_fail(err, __FILE__, __LINE__, "creating the maneuvers dataset");
    goto done;
  }
  POM_TRY_GOTO(describe_rows(res->rows[c], cand->eval.actuator_kind, err), done);
done:
  if (dcpl >= 0) H5Pclose(dcpl);
  if (space >= 0) H5Sclose(space);
  H5Gclose(g);
  return st;
}

/* The current time as ISO 8601 UTC. */
static void utc_now(char *buf, size_t cap) {
  time_t now = time(NULL);
  struct tm tmv;
  gmtime_r(&now, &tmv);
  strftime(buf, cap, "%Y-%m-%dT%H:%M:%SZ", &tmv);
}

pom_status pom_doe_results_create(pom_doe_results **out, const char *path,
                                  const pom_doe_study *study, pom_error *err) {
  pom_status st = POM_OK;
  pom_doe_results *res = NULL;
  hid_t g = -1;
  *out = NULL;
  POM_TRY_GOTO(results_alloc(&res, study, err), fail);
  POM_TRY_GOTO(pom_h5_create_file(&res->file, path, err), fail);
  char created[64];
  utc_now(created, sizeof created);
  hid_t f = res->file;
  POM_TRY_GOTO(pom_h5_attr_string(f, "format", FORMAT_NAME, err), fail);
  POM_TRY_GOTO(pom_h5_attr_int64(f, "format_version", FORMAT_VERSION, err), fail);
  POM_TRY_GOTO(pom_h5_attr_string(f, "program", "pomlab", err), fail);
  POM_TRY_GOTO(pom_h5_attr_string(f, "version", POM_VERSION, err), fail);
  POM_TRY_GOTO(pom_h5_attr_string(f, "git_commit", POM_GIT_COMMIT, err), fail);
  POM_TRY_GOTO(pom_h5_attr_string(f, "created_utc", created, err), fail);
  POM_TRY_GOTO(pom_h5_attr_string(f, "study_name", study->name, err), fail);
  POM_TRY_GOTO(pom_h5_attr_string(f, "study_source", study->source, err), fail);
  POM_TRY_GOTO(pom_h5_attr_int64(f, "n_candidates", study->n_candidates, err), fail);
  POM_TRY_GOTO(pom_h5_attr_int64(f, "n_maneuvers", study->maneuvers.count, err), fail);
  POM_TRY_GOTO(pom_h5_attr_double(f, "alpha", study->alpha, err), fail);
  POM_TRY_GOTO(pom_h5_attr_double(f, "confidence", study->confidence, err), fail);
  POM_TRY_GOTO(pom_h5_write_text(f, "study_config", study->config_text, err), fail);
  POM_TRY_GOTO(write_montecarlo(f, study, err), fail);
  POM_TRY_GOTO(pom_h5_create_group(&g, f, "candidates", err), fail);
  for (int c = 0; c < study->n_candidates; ++c)
    POM_TRY_GOTO(write_candidate(res, g, study, c, err), fail);
  H5Gclose(g);
  g = -1;
  POM_TRY_GOTO(pom_doe_results_flush(res, err), fail);
  *out = res;
  return POM_OK;
fail:
  if (g >= 0) H5Gclose(g);
  pom_error_prefix(err, "creating results file '%s'", path);
  pom_doe_results_close(res, NULL);
  return st;
}

/* ---- open for resume -------------------------------------------------------------- */
/* The rest of the maneuver protocol (space, distribution, sigma, tilt and
 * torsion limits) and the drawn table itself must match too: otherwise a
 * resumed file would mix maneuvers of two protocols. */
static pom_status check_protocol(hid_t file, const pom_doe_study *study, const char *path,
                                 pom_error *err) {
  static const char *const spaces[] = {"joint", "orientation"};
  static const char *const dists[] = {"uniform", "normal"};
  const pom_doe_maneuvers *mv = &study->maneuvers;
  pom_status st = POM_OK;
  hid_t mc = -1;
  double *have = NULL;
  char space[32] = "", dist[32] = "";
  double sigma = NAN, tilt = NAN, torsion = NAN;
  POM_TRY(pom_h5_open_group(&mc, file, "montecarlo", err));
  POM_TRY_GOTO(pom_h5_read_attr_string(mc, "space", space, sizeof space, err), done);
  POM_TRY_GOTO(pom_h5_read_attr_string(mc, "distribution", dist, sizeof dist, err), done);
  POM_TRY_GOTO(pom_h5_read_attr_double(mc, "sigma_m", &sigma, err), done);
  POM_TRY_GOTO(pom_h5_read_attr_double(mc, "tilt_max_rad", &tilt, err), done);
  POM_TRY_GOTO(pom_h5_read_attr_double(mc, "torsion_max_rad", &torsion, err), done);
  if (strcmp(space, spaces[mv->space]) != 0 || strcmp(dist, dists[mv->distribution]) != 0 ||
      sigma != mv->sigma || tilt != mv->tilt_max || torsion != mv->torsion_max)
    POM_FAIL_GOTO(err, POM_ERR_ARG, done,
                  "'%s' holds another study (maneuvers drawn in %s space, %s, sigma %.6g mm, "
                  "tilt %.6g deg, torsion %.6g deg; this one: %s, %s, %.6g mm, %.6g deg, %.6g "
                  "deg): remove it or choose another output",
                  path, space, dist, sigma * 1e3, tilt / POM_DEG, torsion / POM_DEG,
                  spaces[mv->space], dists[mv->distribution], mv->sigma * 1e3,
                  mv->tilt_max / POM_DEG, mv->torsion_max / POM_DEG);
  /* the stored maneuvers are the ones this program draws (same generator) */
  size_t n = (size_t)mv->count * 3;
  have = malloc(n * sizeof *have);
  if (!have) POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "results: out of memory");
  POM_TRY_GOTO(pom_h5_read_doubles(mc, mv->space == POM_DOE_SPACE_JOINT ? "target" : "tilt_torsion",
                                   n, have, err),
               done);
  for (long k = 0; k < mv->count; ++k) {
    pom_doe_maneuver m;
    pom_doe_maneuver_draw(&m, mv, k);
    const double *want = mv->space == POM_DOE_SPACE_JOINT ? m.q : m.orient;
    if (memcmp(have + 3 * k, want, 3 * sizeof *want) != 0)
      POM_FAIL_GOTO(err, POM_ERR_ARG, done,
                    "'%s': maneuver %ld stored in the file differs from the one drawn now (seed "
                    "%llu): remove the file or choose another output",
                    path, k, (unsigned long long)mv->seed);
  }
done:
  free(have);
  H5Gclose(mc);
  return st;
}

/* Every metric of the schema is a field of the stored rows (a file written
 * by a pomlab with fewer metrics cannot be completed). */
static pom_status check_fields(hid_t ds, const char *path, pom_error *err) {
  hid_t type = H5Dget_type(ds);
  if (type < 0) POM_H5_FAIL(err, "reading the maneuvers row type");
  pom_status st = POM_OK;
  const pom_dyn_metric_info *schema = pom_dyn_metric_schema();
  for (int j = 0; j < POM_DYN_N_METRICS && st == POM_OK; ++j)
    if (H5Tget_member_index(type, schema[j].name) < 0)
      st = pom_error_set(err, POM_ERR_ARG, __FILE__, __LINE__,
                         "'%s' was written by a pomlab without the metric '%s': it cannot be "
                         "resumed; remove it or choose another output",
                         path, schema[j].name);
  H5Tclose(type);
  return st;
}

/* The study identity: maneuvers and resolved candidate configs. */
static pom_status check_identity(pom_doe_results *res, const pom_doe_study *study, const char *path,
                                 pom_error *err) {
  int64_t nc = 0, nm = 0, seed = 0;
  char fmt[64];
  pom_status st = POM_OK;
  hid_t mc = -1, g = -1;
  char *text = NULL;
  if (H5Aexists(res->file, "format") <= 0) /* another program's HDF5 file */
    POM_FAIL(err, POM_ERR_ARG, "'%s' is not a pomlab study results file", path);
  POM_TRY(pom_h5_read_attr_string(res->file, "format", fmt, sizeof fmt, err));
  if (strcmp(fmt, FORMAT_NAME) != 0)
    POM_FAIL(err, POM_ERR_ARG, "'%s' is not a pomlab study results file", path);
  int64_t version = 0;
  POM_TRY(pom_h5_read_attr_int64(res->file, "format_version", &version, err));
  if (version != FORMAT_VERSION)
    POM_FAIL(err, POM_ERR_ARG,
             "'%s' has results format version %lld, this program writes version %d: it cannot "
             "resume it",
             path, (long long)version, FORMAT_VERSION);
  POM_TRY(pom_h5_read_attr_int64(res->file, "n_candidates", &nc, err));
  POM_TRY(pom_h5_read_attr_int64(res->file, "n_maneuvers", &nm, err));
  POM_TRY(pom_h5_open_group(&mc, res->file, "montecarlo", err));
  st = pom_h5_read_attr_int64(mc, "seed", &seed, err);
  double range = NAN;
  /* "range" (any actuator kind); files written before it have only range_m */
  if (st == POM_OK)
    st = pom_h5_read_attr_double(mc, H5Aexists(mc, "range") > 0 ? "range" : "range_m", &range, err);
  H5Gclose(mc);
  POM_TRY(st);
  if (nc != study->n_candidates || nm != study->maneuvers.count ||
      (uint64_t)seed != study->maneuvers.seed || range != study->maneuvers.range)
    POM_FAIL(err, POM_ERR_ARG,
             "'%s' holds another study (%lld candidates x %lld maneuvers, seed %lld; this one has "
             "%d x %ld, seed %llu): remove it or choose another output",
             path, (long long)nc, (long long)nm, (long long)seed, study->n_candidates,
             study->maneuvers.count, (unsigned long long)study->maneuvers.seed);
  POM_TRY(check_protocol(res->file, study, path, err));
  for (int c = 0; c < study->n_candidates; ++c) {
    char name[48];
    snprintf(name, sizeof name, "candidates/%d", c);
    POM_TRY_GOTO(pom_h5_open_group(&g, res->file, name, err), done);
    POM_TRY_GOTO(pom_h5_read_text(g, "config", &text, err), done);
    const char *want = study->candidates[c].resolved ? study->candidates[c].resolved : "";
    if (strcmp(text, want) != 0)
      POM_FAIL_GOTO(err, POM_ERR_ARG, done,
                    "'%s': candidate %d ('%s') was run with a different configuration: remove the "
                    "file or choose another output",
                    path, c, study->candidates[c].name);
    res->rows[c] = H5Dopen2(g, "maneuvers", H5P_DEFAULT);
    if (res->rows[c] < 0) {
      st = pom_h5_fail(err, __FILE__, __LINE__, "opening the maneuvers dataset");
      goto done;
    }
    POM_TRY_GOTO(check_fields(res->rows[c], path, err), done);
    free(text);
    text = NULL;
    H5Gclose(g);
    g = -1;
  }
done:
  free(text);
  if (g >= 0) H5Gclose(g);
  return st;
}

pom_status pom_doe_results_open(pom_doe_results **out, const char *path, const pom_doe_study *study,
                                pom_error *err) {
  pom_status st = POM_OK;
  pom_doe_results *res = NULL;
  *out = NULL;
  POM_TRY_GOTO(results_alloc(&res, study, err), fail);
  POM_TRY_GOTO(pom_h5_open_file(&res->file, path, 1, err), fail);
  POM_TRY_GOTO(check_identity(res, study, path, err), fail);
  /* rows from here on come from this program: say so next to the creator's
   * version and commit */
  char when[64];
  utc_now(when, sizeof when);
  POM_TRY_GOTO(pom_h5_attr_string(res->file, "last_resumed_utc", when, err), fail);
  POM_TRY_GOTO(pom_h5_attr_string(res->file, "last_resumed_version", POM_VERSION, err), fail);
  POM_TRY_GOTO(pom_h5_attr_string(res->file, "last_resumed_git_commit", POM_GIT_COMMIT, err), fail);
  *out = res;
  return POM_OK;
fail:
  pom_doe_results_close(res, NULL);
  return st;
}

/* ---- rows ---------------------------------------------------------------------------- */
static pom_status row_io(pom_doe_results *res, int c, long first, long n, pom_doe_row *rows,
                         int write, pom_error *err) {
  if (c < 0 || c >= res->n_candidates || first < 0 || n < 0 || first + n > res->n_maneuvers)
    POM_FAIL(err, POM_ERR_ARG, "rows [%ld, %ld) of candidate %d are outside the study", first,
             first + n, c);
  if (n == 0) return POM_OK;
  pom_h5_quiet();
  hid_t fs = H5Dget_space(res->rows[c]);
  hsize_t start = (hsize_t)first, count = (hsize_t)n;
  hid_t ms = H5Screate_simple(1, &count, NULL);
  herr_t r = -1;
  if (fs >= 0 && ms >= 0 &&
      H5Sselect_hyperslab(fs, H5S_SELECT_SET, &start, NULL, &count, NULL) >= 0) {
    r = write ? H5Dwrite(res->rows[c], res->row_mem, ms, fs, H5P_DEFAULT, rows)
              : H5Dread(res->rows[c], res->row_mem, ms, fs, H5P_DEFAULT, rows);
  }
  if (ms >= 0) H5Sclose(ms);
  if (fs >= 0) H5Sclose(fs);
  if (r < 0) POM_H5_FAIL(err, write ? "writing maneuver rows" : "reading maneuver rows");
  return POM_OK;
}

pom_status pom_doe_results_write_rows(pom_doe_results *res, int c, long first, long n,
                                      const pom_doe_row *rows, pom_error *err) {
  return row_io(res, c, first, n, (pom_doe_row *)rows, 1, err);
}

pom_status pom_doe_results_read(pom_doe_results *res, int c, long first, long n, pom_doe_row *rows,
                                pom_error *err) {
  return row_io(res, c, first, n, rows, 0, err);
}

pom_status pom_doe_results_flush(pom_doe_results *res, pom_error *err) {
  pom_h5_quiet();
  if (H5Fflush(res->file, H5F_SCOPE_GLOBAL) < 0) POM_H5_FAIL(err, "flushing the results file");
  return POM_OK;
}

pom_status pom_doe_results_read_rows(const char *path, int c, long first, long n, pom_doe_row *rows,
                                     pom_error *err) {
  pom_status st = POM_OK;
  hid_t file = -1, ds = -1, mem = -1, ftype = -1;
  POM_TRY(pom_h5_open_file(&file, path, 0, err));
  POM_TRY_GOTO(row_types(&mem, &ftype, err), done);
  char name[64];
  snprintf(name, sizeof name, "candidates/%d/maneuvers", c);
  ds = H5Dopen2(file, name, H5P_DEFAULT);
  if (ds < 0) {
    st = pom_h5_fail(err, __FILE__, __LINE__, "opening the maneuvers dataset");
    goto done;
  }
  hid_t fs = H5Dget_space(ds);
  hsize_t start = (hsize_t)first, count = (hsize_t)n;
  hid_t ms = H5Screate_simple(1, &count, NULL);
  herr_t r = -1;
  if (fs >= 0 && ms >= 0 &&
      H5Sselect_hyperslab(fs, H5S_SELECT_SET, &start, NULL, &count, NULL) >= 0)
    r = H5Dread(ds, mem, ms, fs, H5P_DEFAULT, rows);
  if (ms >= 0) H5Sclose(ms);
  if (fs >= 0) H5Sclose(fs);
  if (r < 0) st = pom_h5_fail(err, __FILE__, __LINE__, "reading maneuver rows");
done:
  if (ds >= 0) H5Dclose(ds);
  if (mem >= 0) H5Tclose(mem);
  if (ftype >= 0) H5Tclose(ftype);
  pom_h5_close_file(file, NULL);
  return st;
}

/* ---- report ------------------------------------------------------------------------------ */
static pom_status replace_group(hid_t *g, hid_t file, const char *name, pom_error *err) {
  if (pom_h5_exists(file, name) && H5Ldelete(file, name, H5P_DEFAULT) < 0)
    POM_H5_FAIL(err, "replacing the report");
  return pom_h5_create_group(g, file, name, err);
}

static const char *const stats_columns = "n,max,mean,min,sigma,median,p05,p25,p75,p95";

static pom_status write_statistics(hid_t file, const pom_doe_report *rep, pom_error *err) {
  pom_status st = POM_OK;
  hid_t g = -1;
  size_t nc = (size_t)rep->n_candidates;
  double *buf = malloc(nc * POM_DOE_STATS_FIELDS * sizeof *buf);
  int64_t *counts = malloc(nc * 4 * sizeof *counts);
  if (!buf || !counts) POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "results: out of memory");
  POM_TRY_GOTO(replace_group(&g, file, "statistics", err), done);
  /* one table per reduced metric of the schema */
  for (int m = 0; m < POM_DYN_N_STATS; ++m) {
    const pom_dyn_metric_info *mi = pom_dyn_stat_metric(m);
    for (size_t c = 0; c < nc; ++c)
      pom_doe_stats_flatten(buf + c * POM_DOE_STATS_FIELDS, &rep->cand[c].stat[m]);
    size_t dims[2] = {nc, POM_DOE_STATS_FIELDS};
    POM_TRY_GOTO(pom_h5_write_doubles(g, mi->stat_name, 2, dims, buf, err), done);
    hid_t ds = H5Dopen2(g, mi->stat_name, H5P_DEFAULT);
    if (ds < 0) {
      st = pom_h5_fail(err, __FILE__, __LINE__, "annotating statistics");
      goto done;
    }
    st = pom_h5_attr_string(ds, "columns", stats_columns, err);
    if (st == POM_OK)
      st = pom_h5_attr_string(ds, "unit",
                              mi->unit == POM_DYN_UNIT_ACTUATOR
                                  ? "actuator unit of each candidate (its actuator_unit)"
                                  : pom_dyn_metric_unit(mi, POM_ACT_PRISMATIC),
                              err);
    if (st == POM_OK) st = pom_h5_attr_string(ds, "metric", mi->name, err);
    if (st == POM_OK)
      st = pom_h5_attr_string(
          ds, "reduction",
          mi->combine == POM_DYN_COMBINE_NONE
              ? pom_dyn_reduce_name(mi->reduce)
              : (mi->combine == POM_DYN_COMBINE_SUM ? "sum over actuators" : "max over actuators"),
          err);
    H5Dclose(ds);
    if (st != POM_OK) goto done;
  }
  for (size_t c = 0; c < nc; ++c) {
    counts[4 * c + 0] = rep->cand[c].n_done;
    counts[4 * c + 1] = rep->cand[c].n_done - rep->cand[c].n_failed;
    counts[4 * c + 2] = rep->cand[c].n_failed;
    counts[4 * c + 3] = rep->cand[c].n_unsettled;
  }
  POM_TRY_GOTO(pom_h5_write_int64_table(g, "counts", nc, 4, counts, err), done);
  hid_t ds = H5Dopen2(g, "counts", H5P_DEFAULT);
  if (ds < 0) {
    st = pom_h5_fail(err, __FILE__, __LINE__, "annotating counts");
    goto done;
  }
  st = pom_h5_attr_string(ds, "columns", "done,ok,failed,unsettled", err);
  H5Dclose(ds);
done:
  if (g >= 0) H5Gclose(g);
  free(buf);
  free(counts);
  return st;
}

static pom_status write_comparisons(hid_t file, const pom_doe_report *rep, pom_error *err) {
  pom_status st = POM_OK;
  hid_t g = -1;
  size_t n = (size_t)rep->n_comparisons;
  double *buf = malloc((n ? n : 1) * 11 * sizeof *buf);
  if (!buf) POM_FAIL(err, POM_ERR_NOMEM, "results: out of memory");
  POM_TRY_GOTO(replace_group(&g, file, "comparison", err), done);
  for (size_t j = 0; j < n; ++j) {
    const pom_doe_comparison *c = &rep->cmp[j];
    double *r = buf + 11 * j;
    r[0] = c->a;
    r[1] = c->b;
    r[2] = c->metric;
    r[3] = (double)c->test.n;
    r[4] = c->test.mean_diff;
    r[5] = c->test.ci_low;
    r[6] = c->test.ci_high;
    r[7] = c->test.wilcoxon_w;
    r[8] = c->test.wilcoxon_p;
    r[9] = (double)c->test.n_nonzero;
    r[10] = c->test.win_fraction;
  }
  size_t dims[2] = {n, 11};
  POM_TRY_GOTO(pom_h5_write_doubles(g, "paired", 2, dims, buf, err), done);
  POM_TRY_GOTO(pom_h5_attr_string(g, "columns",
                                  "a,b,metric(0=execution_time s,1=energy J),n,mean_diff(a-b),"
                                  "ci_low,ci_high,wilcoxon_w_plus,wilcoxon_p,n_nonzero,"
                                  "win_fraction(a<b)",
                                  err),
               done);
done:
  if (g >= 0) H5Gclose(g);
  free(buf);
  return st;
}

static pom_status write_ranking(hid_t file, const pom_doe_study *study, const pom_doe_report *rep,
                                pom_error *err) {
  pom_status st = POM_OK;
  hid_t g = -1;
  size_t nc = (size_t)rep->n_candidates;
  int64_t *buf = malloc(nc * sizeof *buf);
  const char **names = malloc(nc * sizeof *names);
  if (!buf || !names) POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "results: out of memory");
  POM_TRY_GOTO(replace_group(&g, file, "ranking", err), done);
  for (size_t c = 0; c < nc; ++c)
    buf[c] = rep->rank_time[c];
  POM_TRY_GOTO(pom_h5_write_int64s(g, "execution_time", nc, buf, err), done);
  for (size_t c = 0; c < nc; ++c)
    buf[c] = rep->rank_energy[c];
  POM_TRY_GOTO(pom_h5_write_int64s(g, "energy", nc, buf, err), done);
  for (size_t c = 0; c < nc; ++c)
    names[c] = study->candidates[c].name;
  POM_TRY_GOTO(pom_h5_write_strings(g, "candidate_names", nc, names, POM_DOE_NAME_LEN, err), done);
  POM_TRY_GOTO(pom_h5_attr_string(g, "rank_by",
                                  study->rank_by == POM_DOE_RANK_TIME ? "execution_time" : "energy",
                                  err),
               done);
  POM_TRY_GOTO(pom_h5_attr_string(g, "order", "candidate indices, lowest mean first", err), done);
done:
  if (g >= 0) H5Gclose(g);
  free(buf);
  free(names);
  return st;
}

pom_status pom_doe_results_write_report(pom_doe_results *res, const pom_doe_study *study,
                                        const pom_doe_report *rep, pom_error *err) {
  pom_h5_quiet();
  /* a resumed study may use other levels than the run that created the file */
  POM_TRY(pom_h5_attr_double(res->file, "alpha", study->alpha, err));
  POM_TRY(pom_h5_attr_double(res->file, "confidence", study->confidence, err));
  POM_TRY(write_statistics(res->file, rep, err));
  POM_TRY(write_comparisons(res->file, rep, err));
  hid_t g = -1;
  POM_TRY(pom_h5_open_group(&g, res->file, "comparison", err));
  pom_status st = pom_h5_attr_double(g, "confidence", study->confidence, err);
  if (st == POM_OK) st = pom_h5_attr_double(g, "alpha", study->alpha, err);
  H5Gclose(g);
  POM_TRY(st);
  POM_TRY(write_ranking(res->file, study, rep, err));
  return pom_doe_results_flush(res, err);
}

pom_status pom_doe_results_close(pom_doe_results *res, pom_error *err) {
  if (!res) return POM_OK;
  pom_h5_quiet();
  for (int c = 0; c < res->n_candidates; ++c)
    if (res->rows && res->rows[c] >= 0) H5Dclose(res->rows[c]);
  if (res->row_mem >= 0) H5Tclose(res->row_mem);
  if (res->row_file >= 0) H5Tclose(res->row_file);
  pom_status st = pom_h5_close_file(res->file, err);
  free(res->rows);
  free(res);
  return st;
}
