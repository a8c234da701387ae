/* pom_doe_results.c - the study's HDF5 results file (layout:
 * docs/results.md, "Results file"). Only the root rank's driving thread
 * touches it. */
#define _POSIX_C_SOURCE 200809L
#include "run_internal.h"
#include "pom_version.h"
#include "pom_dyn_ctrl.h"
#include "pom_dyn_params_schema.h"
#include "pom_h5.h"
#include "pom_io.h"
#include "pom_math.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

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
  /* the file's place (docs/results.md, "Writing safely") */
  char path[POM_DOE_PATH_LEN + 16];      /* the results file as asked for */
  char open_path[POM_DOE_PATH_LEN + 16]; /* the file open: path or path.partial */
  pom_io_lock lock;                      /* path.lock (pom_io_lock_take) */
  int resumed;                           /* 1: opened an existing file */
  int made;                              /* 1: open_path was made by this run (created or
                                            copied): removed again when start fails */
};

static pom_status close_hdf5(pom_doe_results *res, pom_error *err);

/* ---- exclusive use of a results path -------------------------------------------- */
void pom_doe_results_partial_path(char *buf, size_t cap, const char *path) {
  snprintf(buf, cap, "%s.partial", path);
}

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
  res->lock.fd = -1;
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
  const pom_doe_maneuvers *mv = &study->maneuvers;
  pom_status st = POM_OK;
  hid_t g = -1;
  double *buf = NULL;
  POM_TRY(pom_h5_create_group(&g, file, "montecarlo", err));
  POM_TRY_GOTO(pom_h5_attr_int64(g, "count", mv->count, err), done);
  POM_TRY_GOTO(pom_h5_attr_int64(g, "seed", (int64_t)mv->seed, err), done);
  POM_TRY_GOTO(
      pom_h5_attr_string(g, "space", pom_cfg_choice_name(pom_doe_space_names, (int)mv->space), err),
      done);
  POM_TRY_GOTO(pom_h5_attr_string(g, "distribution",
                                  pom_cfg_choice_name(pom_doe_dist_names, (int)mv->distribution),
                                  err),
               done);
  /* range and sigma in the actuators' SI unit (joint space has one kind);
   * range_m and sigma_m kept for prismatic studies */
  pom_actuator_kind kind = study_kind(study);
  POM_TRY_GOTO(pom_h5_attr_double(g, "range", mv->range, err), done);
  POM_TRY_GOTO(pom_h5_attr_double(g, "sigma", mv->sigma, err), done);
  POM_TRY_GOTO(pom_h5_attr_string(
                   g, "actuator_unit",
                   pom_doe_kinds_mixed_study(study) ? "mixed" : pom_act_kind_desc(kind)->si, err),
               done);
  if (pom_act_kind_desc(kind)->legacy_keys) {
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
  char joint_unit[64];
  snprintf(joint_unit, sizeof joint_unit, "%s from mid-stroke, per actuator",
           pom_act_kind_desc(kind)->si);
  st = pom_h5_attr_string(ds, "unit",
                          mv->space != POM_DOE_SPACE_JOINT
                              ? "rad: azimuth, tilt, torsion (R = Rz(a) Ry(t) Rz(s - a))"
                              : joint_unit,
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
  POM_TRY(pom_h5_attr_string(ds, "actuator_unit", pom_act_kind_desc(kind)->si, err));
  return pom_h5_attr_string(ds, "status_codes", legend, err);
}
/* Dataset access of a candidate's maneuver rows: a chunk cache of two
 * chunks instead of HDF5's 1 MB per dataset, so a study's memory does not
 * grow with its maneuvers (64 candidates x 1 MB otherwise); rows are written
 * in contiguous runs, so two chunks hold every chunk still being filled.
 * H5P_DEFAULT when the property list cannot be made. */
static hid_t rows_access(hid_t row_type) {
  hid_t dapl = H5Pcreate(H5P_DATASET_ACCESS);
  size_t bytes = 2 * ROWS_PER_CHUNK * H5Tget_size(row_type);
  if (dapl < 0) return H5P_DEFAULT;
  if (H5Pset_chunk_cache(dapl, 11, bytes, 1.0) < 0) {
    H5Pclose(dapl);
    return H5P_DEFAULT;
  }
  return dapl;
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
      pom_h5_attr_string(g, "actuator_unit", pom_act_kind_desc(cand->eval.actuator_kind)->si, err),
      done);
  for (int f = 0; f < cand->n_factors; ++f) {
    char an[POM_DOE_NAME_LEN + 16];
    snprintf(an, sizeof an, "factor:%s", cand->factor_key[f]);
    POM_TRY_GOTO(pom_h5_attr_double(g, an, cand->factor_value[f], err), done);
  }
  POM_TRY_GOTO(pom_h5_write_text(g, "config", cand->resolved ? cand->resolved : "", err), done);
  if (cand->eval.describe) POM_TRY_GOTO(cand->eval.describe(cand->eval.ctx, g, err), done);
  POM_TRY_GOTO(pom_doe_fidelity_describe(study, c, g, err), done);
  POM_TRY_GOTO(pom_doe_capability_describe(study, c, g, err), done);
  hsize_t n = (hsize_t)res->n_maneuvers;
  hsize_t chunk = n < ROWS_PER_CHUNK ? n : ROWS_PER_CHUNK;
  space = H5Screate_simple(1, &n, NULL);
  dcpl = H5Pcreate(H5P_DATASET_CREATE);
  /* every row's place is allocated when the file is created and reserved on
   * the disk by results_create (posix_fallocate: zeros, done = 0, without
   * writing them, which HDF5's fill would do at ~70 MB/s): writing rows then
   * never allocates, so a full disk shows at the start and cannot damage
   * the file's metadata later */
  if (space < 0 || dcpl < 0 || H5Pset_chunk(dcpl, 1, &chunk) < 0 ||
      H5Pset_alloc_time(dcpl, H5D_ALLOC_TIME_EARLY) < 0 ||
      H5Pset_fill_time(dcpl, H5D_FILL_TIME_NEVER) < 0) {
    st = pom_h5_fail(err, __FILE__, __LINE__, "creating the maneuvers dataset");
    goto done;
  }
  hid_t dapl = rows_access(res->row_file);
  res->rows[c] = H5Dcreate2(g, "maneuvers", res->row_file, space, H5P_DEFAULT, dcpl, dapl);
  /* the message first: the next HDF5 call clears the error stack */
  if (res->rows[c] < 0) st = pom_h5_fail(err, __FILE__, __LINE__, "creating the maneuvers dataset");
  if (dapl != H5P_DEFAULT) H5Pclose(dapl);
  if (st != POM_OK) goto done;
  POM_TRY_GOTO(describe_rows(res->rows[c], cand->eval.actuator_kind, err), done);
done:
  if (dcpl >= 0) H5Pclose(dcpl);
  if (space >= 0) H5Sclose(space);
  H5Gclose(g);
  return st;
}

/* A sweep's factor values, one column per factor (docs/results.md, section
 * 5): /factors [C][F] with the dotted keys, short labels and grid levels. */
static pom_status write_factors(hid_t file, const pom_doe_study *study, pom_error *err) {
  int nf = study->n_factors;
  if (nf == 0) return POM_OK;
  size_t nc = (size_t)study->n_candidates;
  double *v = malloc(nc * (size_t)nf * sizeof *v);
  char *keys = malloc((size_t)nf * (POM_DOE_NAME_LEN + 1));
  char *labels = malloc((size_t)nf * (POM_DOE_NAME_LEN + 1));
  double levels[POM_DOE_MAX_FACTORS];
  pom_status st = POM_OK;
  hid_t ds = -1;
  if (!v || !keys || !labels) POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "results: out of memory");
  keys[0] = labels[0] = '\0';
  for (int f = 0; f < nf; ++f) {
    strcat(keys, f ? "," : "");
    strcat(keys, study->factor_key[f]);
    strcat(labels, f ? "," : "");
    strcat(labels, study->factor_label[f]);
    levels[f] = (double)study->factor_levels[f];
  }
  for (size_t c = 0; c < nc; ++c)
    for (int f = 0; f < nf; ++f)
      v[c * (size_t)nf + (size_t)f] =
          f < study->candidates[c].n_factors ? study->candidates[c].factor_value[f] : NAN;
  size_t dims[2] = {nc, (size_t)nf};
  POM_TRY_GOTO(pom_h5_write_doubles(file, "factors", 2, dims, v, err), done);
  ds = H5Dopen2(file, "factors", H5P_DEFAULT);
  if (ds < 0) {
    st = pom_h5_fail(err, __FILE__, __LINE__, "annotating factors");
    goto done;
  }
  POM_TRY_GOTO(pom_h5_attr_string(ds, "keys", keys, err), done);
  POM_TRY_GOTO(pom_h5_attr_string(ds, "labels", labels, err), done);
  POM_TRY_GOTO(pom_h5_attr_doubles(ds, "levels", levels, (size_t)nf, err), done);
done:
  if (ds >= 0) H5Dclose(ds);
  free(v);
  free(keys);
  free(labels);
  return st;
}

/* The current time as ISO 8601 UTC. */
static void utc_now(char *buf, size_t cap) {
  time_t now = time(NULL);
  struct tm tmv;
  gmtime_r(&now, &tmv);
  strftime(buf, cap, "%Y-%m-%dT%H:%M:%SZ", &tmv);
}

/* Reserves disk blocks for every byte of the file written so far (the
 * rows' storage is allocated but not written: holes in a sparse file), so
 * that writing the rows cannot run out of space. */
static pom_status reserve_space(const char *path, pom_error *err) {
  int fd = open(path, O_RDWR | O_CLOEXEC);
  struct stat sb;
  if (fd < 0 || fstat(fd, &sb) != 0) {
    int e = errno;
    if (fd >= 0) close(fd);
    POM_FAIL(err, POM_ERR_IO, "cannot open '%s': %s", path, strerror(e));
  }
  int e = sb.st_size > 0 ? posix_fallocate(fd, 0, sb.st_size) : 0;
  close(fd);
  /* a file system without fallocate (EOPNOTSUPP, EINVAL) is written as it goes */
  if (e != 0 && e != EOPNOTSUPP && e != EINVAL)
    POM_FAIL(err, POM_ERR_IO, "cannot reserve %lld bytes for the rows in '%s': %s",
             (long long)sb.st_size, path, strerror(e));
  return POM_OK;
}

/* Creates res->open_path with the study's provenance and empty rows. */
static pom_status results_create(pom_doe_results *res, const pom_doe_study *study, pom_error *err) {
  pom_status st = POM_OK;
  hid_t g = -1;
  const char *path = res->open_path;
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
  POM_TRY_GOTO(pom_doe_uncertain_write(f, study, err), fail);
  POM_TRY_GOTO(pom_h5_create_group(&g, f, "candidates", err), fail);
  for (int c = 0; c < study->n_candidates; ++c)
    POM_TRY_GOTO(write_candidate(res, g, study, c, err), fail);
  H5Gclose(g);
  g = -1;
  POM_TRY_GOTO(write_factors(f, study, err), fail);
  POM_TRY_GOTO(pom_doe_results_flush(res, err), fail);
  POM_TRY_GOTO(reserve_space(path, err), fail);
  return POM_OK;
fail:
  if (g >= 0) H5Gclose(g);
  pom_error_prefix(err, "creating results file '%s'", path);
  return st;
}

/* ---- open for resume -------------------------------------------------------------- */
/* The rest of the maneuver protocol (space, distribution, sigma, tilt and
 * torsion limits) and the drawn table itself must match too: otherwise a
 * resumed file would mix maneuvers of two protocols. */
static pom_status check_protocol(hid_t file, const pom_doe_study *study, const char *path,
                                 pom_error *err) {
  const pom_doe_maneuvers *mv = &study->maneuvers;
  pom_status st = POM_OK;
  hid_t mc = -1;
  double *have = NULL;
  char space[32] = "", dist[32] = "";
  double sigma = NAN, tilt = NAN, torsion = NAN;
  POM_TRY(pom_h5_open_group(&mc, file, "montecarlo", err));
  POM_TRY_GOTO(pom_h5_read_attr_string(mc, "space", space, sizeof space, err), done);
  POM_TRY_GOTO(pom_h5_read_attr_string(mc, "distribution", dist, sizeof dist, err), done);
  /* "sigma" (any actuator kind); files written before it have only sigma_m */
  POM_TRY_GOTO(
      pom_h5_read_attr_double(mc, H5Aexists(mc, "sigma") > 0 ? "sigma" : "sigma_m", &sigma, err),
      done);
  POM_TRY_GOTO(pom_h5_read_attr_double(mc, "tilt_max_rad", &tilt, err), done);
  POM_TRY_GOTO(pom_h5_read_attr_double(mc, "torsion_max_rad", &torsion, err), done);
  if (strcmp(space, pom_cfg_choice_name(pom_doe_space_names, (int)mv->space)) != 0 ||
      strcmp(dist, pom_cfg_choice_name(pom_doe_dist_names, (int)mv->distribution)) != 0 ||
      sigma != mv->sigma || tilt != mv->tilt_max || torsion != mv->torsion_max)
    POM_FAIL_GOTO(err, POM_ERR_ARG, done,
                  "'%s' holds another study (maneuvers drawn in %s space, %s, sigma %.6g mm, "
                  "tilt %.6g deg, torsion %.6g deg; this one: %s, %s, %.6g mm, %.6g deg, %.6g "
                  "deg): remove it or choose another output",
                  path, space, dist, sigma * 1e3, tilt / POM_DEG, torsion / POM_DEG,
                  pom_cfg_choice_name(pom_doe_space_names, (int)mv->space),
                  pom_cfg_choice_name(pom_doe_dist_names, (int)mv->distribution), mv->sigma * 1e3,
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

/* The first key whose value differs between two resolved configs, as
 * "key 'K' (V1 in the file, V2 now)" in key (falls back to "text differs"). */
static void config_key_change(const char *stored, const char *current, char *key, size_t key_cap,
                              char *was, char *now, size_t val_cap) {
  pom_cfg *a = NULL, *b = NULL;
  pom_error e;
  char name[256];
  snprintf(key, key_cap, "the config text differs");
  if (pom_cfg_load_string(&a, stored, "stored", &e) == POM_OK &&
      pom_cfg_load_string(&b, current, "current", &e) == POM_OK &&
      pom_cfg_diff(a, b, name, sizeof name, was, now, val_cap))
    snprintf(key, key_cap, "key '%s' (%s in the file, %s now)", name, was, now);
  pom_cfg_destroy(a);
  pom_cfg_destroy(b);
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
  /* name what changed, as the config says it */
  char changed[256];
  changed[0] = '\0';
  if (nc != study->n_candidates)
    snprintf(changed, sizeof changed, "the number of candidates (%lld in the file, %d now)",
             (long long)nc, study->n_candidates);
  else if (nm != study->maneuvers.count && study->uncertain.design)
    snprintf(changed, sizeof changed,
             "the runs of the sensitivity design (keys 'sensitivity.samples', 'trajectories' "
             "or 'maneuvers'; %lld in the file, %ld now)",
             (long long)nm, study->maneuvers.count);
  else if (nm != study->maneuvers.count)
    snprintf(changed, sizeof changed, "key 'montecarlo.maneuvers' (%lld in the file, %ld now)",
             (long long)nm, study->maneuvers.count);
  else if ((uint64_t)seed != study->maneuvers.seed)
    snprintf(changed, sizeof changed, "key 'montecarlo.seed' (%lld in the file, %llu now)",
             (long long)seed, (unsigned long long)study->maneuvers.seed);
  else if (range != study->maneuvers.range)
    snprintf(changed, sizeof changed,
             "the target range, key 'montecarlo.range_mm' or 'range_deg' (%.9g in the file, "
             "%.9g now, SI)",
             range, study->maneuvers.range);
  if (changed[0])
    POM_FAIL(err, POM_ERR_ARG,
             "'%s' holds another study (%lld candidates x %lld maneuvers, seed %lld; this one has "
             "%d x %ld, seed %llu); changed: %s; remove it or choose another output",
             path, (long long)nc, (long long)nm, (long long)seed, study->n_candidates,
             study->maneuvers.count, (unsigned long long)study->maneuvers.seed, changed);
  POM_TRY(check_protocol(res->file, study, path, err));
  POM_TRY(pom_doe_uncertain_check(res->file, study, path, err));
  for (int c = 0; c < study->n_candidates; ++c) {
    char name[48];
    snprintf(name, sizeof name, "candidates/%d", c);
    POM_TRY_GOTO(pom_h5_open_group(&g, res->file, name, err), done);
    POM_TRY_GOTO(pom_h5_read_text(g, "config", &text, err), done);
    /* a renamed candidate is another one in every table and in /ranking */
    char stored_name[POM_DOE_NAME_LEN];
    POM_TRY_GOTO(pom_h5_read_attr_string(g, "name", stored_name, sizeof stored_name, err), done);
    if (strcmp(stored_name, study->candidates[c].name) != 0)
      POM_FAIL_GOTO(err, POM_ERR_ARG, done,
                    "'%s': candidate %d was run as '%s' and is named '%s' now; changed: its "
                    "name; remove the file or choose another output",
                    path, c, stored_name, study->candidates[c].name);
    const char *want = study->candidates[c].resolved ? study->candidates[c].resolved : "";
    if (strcmp(text, want) != 0) {
      char key[256], was[128], now[128];
      config_key_change(text, want, key, sizeof key, was, now, sizeof was);
      POM_FAIL_GOTO(err, POM_ERR_ARG, done,
                    "'%s': candidate %d ('%s') was run with a different configuration; changed: "
                    "%s; remove the file or choose another output",
                    path, c, study->candidates[c].name, key);
    }
    hid_t dapl = rows_access(res->row_file);
    res->rows[c] = H5Dopen2(g, "maneuvers", dapl);
    if (res->rows[c] < 0)
      st = pom_h5_fail(err, __FILE__, __LINE__, "opening the maneuvers dataset");
    if (dapl != H5P_DEFAULT) H5Pclose(dapl);
    if (st != POM_OK) goto done;
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

/* Opens res->open_path for resume: it must hold this study. */
static pom_status results_open(pom_doe_results *res, const pom_doe_study *study, pom_error *err) {
  const char *path = res->open_path;
  POM_TRY(pom_h5_open_file(&res->file, path, 1, err));
  return check_identity(res, study, path, err);
}

pom_status pom_doe_results_mark_resumed(pom_doe_results *res, pom_error *err) {
  /* rows from here on come from this program: say so next to the creator's
   * version and commit */
  char when[64];
  utc_now(when, sizeof when);
  POM_TRY(pom_h5_attr_string(res->file, "last_resumed_utc", when, err));
  POM_TRY(pom_h5_attr_string(res->file, "last_resumed_version", POM_VERSION, err));
  POM_TRY(pom_h5_attr_string(res->file, "last_resumed_git_commit", POM_GIT_COMMIT, err));
  return POM_OK;
}

static pom_status results_start(pom_doe_results **out, const char *path, const pom_doe_study *study,
                                int resume, int rows_only, pom_error *err) {
  pom_status st = POM_OK;
  pom_doe_results *res = NULL;
  *out = NULL;
  POM_TRY_GOTO(results_alloc(&res, study, err), fail);
  if (strlen(path) >= POM_DOE_PATH_LEN)
    POM_FAIL_GOTO(err, POM_ERR_ARG, fail, "results path longer than %d characters: '%s'",
                  POM_DOE_PATH_LEN - 1, path);
  snprintf(res->path, sizeof res->path, "%s", path);
  /* nothing is opened before the lock is held */
  POM_TRY_GOTO(pom_io_lock_take(&res->lock, path, err), fail);
  char partial[sizeof res->open_path];
  pom_doe_results_partial_path(partial, sizeof partial, path);
  /* an unfinished run (path.partial) first, else a finished file */
  const char *existing = access(partial, F_OK) == 0              ? partial
                         : !rows_only && access(path, F_OK) == 0 ? path
                                                                 : NULL;
  /* the finished file is never written: every run works in PATH.partial */
  snprintf(res->open_path, sizeof res->open_path, "%s", partial);
  if (resume && existing) {
    res->resumed = 1;
    /* a finished file is resumed from a copy, replaced by rename at the end */
    if (existing == path) {
      res->made = 1;
      POM_TRY_GOTO(pom_io_copy(path, partial, err), fail);
    }
    POM_TRY_GOTO(results_open(res, study, err), fail);
  } else {
    /* a new run never touches the finished file: it replaces it by rename
     * once every maneuver is done */
    res->made = 1;
    POM_TRY_GOTO(results_create(res, study, err), fail);
  }
  *out = res;
  return POM_OK;
fail:
  /* a file made here holds no row: remove it, so that nothing half-made is
   * left to resume (a full disk while the file is created) */
  if (res && res->made) {
    close_hdf5(res, NULL);
    unlink(res->open_path);
  }
  pom_doe_results_close(res, NULL);
  return st;
}

pom_status pom_doe_results_start(pom_doe_results **out, const char *path,
                                 const pom_doe_study *study, int resume, pom_error *err) {
  return results_start(out, path, study, resume, 0, err);
}

pom_status pom_doe_results_start_rows(pom_doe_results **out, const char *path,
                                      const pom_doe_study *study, int resume, pom_error *err) {
  return results_start(out, path, study, resume, 1, err);
}

int pom_doe_results_resumed(const pom_doe_results *res) {
  return res->resumed;
}

const char *pom_doe_results_open_path(const pom_doe_results *res) {
  return res->open_path;
}

/* ---- stored rows, checked on resume ------------------------------------------------ */
int pom_doe_results_check_row(const pom_doe_study *study, int c, long k, const pom_doe_row *row,
                              char *why, size_t cap) {
  if (row->done == 0) return 0; /* computed again anyway */
  if (row->done != 1) {
    snprintf(why, cap, "done = %d", (int)row->done);
    return -1;
  }
  /* what the statistics would carry: finite and in range */
  if (pom_doe_row_check_metrics(row, why, cap) != 0) return -1;
  if (strcmp(pom_status_name((pom_status)row->status), "POM_UNKNOWN") == 0) {
    snprintf(why, cap, "status = %d is no pomlab status", (int)row->status);
    return -1;
  }
  if (memchr(row->reason, '\0', sizeof row->reason) == NULL ||
      (row->status == POM_OK) != (row->reason[0] == '\0')) {
    snprintf(why, cap, "status %d does not match its reason", (int)row->status);
    return -1;
  }
  /* the target is the one maneuver k gives this candidate (unit k of a
   * sensitivity design runs maneuver k modulo the maneuvers per sample) */
  long man = k;
  if (study->uncertain.n > 0) {
    double u[POM_UNC_MAX];
    pom_unc_unit(&study->uncertain, k, &man, u);
  }
  pom_doe_maneuver mv;
  pom_doe_maneuver_draw(&mv, &study->maneuvers, man);
  double want[3];
  int drawn = 1;
  if (study->maneuvers.space == POM_DOE_SPACE_ORIENTATION) {
    const pom_doe_evaluator *ev = &study->candidates[c].eval;
    pom_error e;
    pom_error_clear(&e);
    drawn = ev->targets(ev->ctx, &mv, want, &e) == POM_OK;
  } else {
    memcpy(want, mv.q, sizeof want);
  }
  int same = 1;
  for (int i = 0; i < 3; ++i)
    same &= drawn ? row->target[i] == want[i] : isnan(row->target[i]);
  if (!same || (!drawn && row->status == POM_OK)) {
    snprintf(why, cap, "target (%.6g, %.6g, %.6g) is not maneuver %ld's (seed %llu)",
             row->target[0], row->target[1], row->target[2], man,
             (unsigned long long)study->maneuvers.seed);
    return -1;
  }
  return 0;
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
  int64_t *counts = malloc(nc * 5 * sizeof *counts);
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
    counts[5 * c + 0] = rep->cand[c].n_done;
    counts[5 * c + 1] = rep->cand[c].n_done - rep->cand[c].n_failed;
    counts[5 * c + 2] = rep->cand[c].n_failed;
    counts[5 * c + 3] = rep->cand[c].n_unsettled;
    counts[5 * c + 4] = rep->cand[c].n_censored; /* of the primary time metric */
  }
  POM_TRY_GOTO(pom_h5_write_int64_table(g, "counts", nc, 5, counts, err), done);
  hid_t ds = H5Dopen2(g, "counts", H5P_DEFAULT);
  if (ds < 0) {
    st = pom_h5_fail(err, __FILE__, __LINE__, "annotating counts");
    goto done;
  }
  st = pom_h5_attr_string(ds, "columns", "done,ok,failed,unsettled,censored", err);
  H5Dclose(ds);
done:
  if (g >= 0) H5Gclose(g);
  free(buf);
  free(counts);
  return st;
}

#define PAIRED_COLUMNS 15

static pom_status write_comparisons(hid_t file, const pom_doe_report *rep, pom_error *err) {
  pom_status st = POM_OK;
  hid_t g = -1;
  size_t n = (size_t)rep->n_comparisons;
  double *buf = malloc((n ? n : 1) * PAIRED_COLUMNS * sizeof *buf);
  if (!buf) POM_FAIL(err, POM_ERR_NOMEM, "results: out of memory");
  POM_TRY_GOTO(replace_group(&g, file, "comparison", err), done);
  for (size_t j = 0; j < n; ++j) {
    const pom_doe_comparison *c = &rep->cmp[j];
    double *r = buf + PAIRED_COLUMNS * j;
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
    r[11] = c->test.tie_fraction;
    r[12] = c->p_holm;
    r[13] = (double)c->censored_a; /* time: censored values of a among the pairs */
    r[14] = (double)c->censored_b;
  }
  size_t dims[2] = {n, PAIRED_COLUMNS};
  POM_TRY_GOTO(pom_h5_write_doubles(g, "paired", 2, dims, buf, err), done);
  POM_TRY_GOTO(
      pom_h5_attr_string(g, "columns",
                         "a,b,metric(0=execution_time s,1=energy J),n,mean_diff(a-b),"
                         "ci_low,ci_high,wilcoxon_w_plus,wilcoxon_p,n_nonzero,"
                         "win_fraction(a<b),tie_fraction(a==b),holm_p,censored_a,censored_b",
                         err),
      done);
  POM_TRY_GOTO(pom_h5_attr_string(g, "pairs",
                                  rep->all_pairs ? "every pair"
                                                 : "the best candidate of each metric (a) against "
                                                   "each other one (b)",
                                  err),
               done);
  double fr[2 * 5];
  for (int m = 0; m < 2; ++m) {
    fr[5 * m + 0] = (double)rep->friedman[m].n_blocks;
    fr[5 * m + 1] = rep->friedman[m].k;
    fr[5 * m + 2] = rep->friedman[m].statistic;
    fr[5 * m + 3] = rep->friedman[m].p;
    fr[5 * m + 4] = m == POM_DOE_METRIC_TIME ? (double)rep->friedman_censored : 0.0;
  }
  size_t fdims[2] = {2, 5};
  POM_TRY_GOTO(pom_h5_write_doubles(g, "friedman", 2, fdims, fr, err), done);
  hid_t ds = H5Dopen2(g, "friedman", H5P_DEFAULT);
  if (ds < 0) {
    st = pom_h5_fail(err, __FILE__, __LINE__, "annotating friedman");
    goto done;
  }
  st = pom_h5_attr_string(ds, "columns", "n_maneuvers,k_candidates,chi_square,p,n_censored", err);
  if (st == POM_OK) st = pom_h5_attr_string(ds, "rows", "execution_time,energy", err);
  H5Dclose(ds);
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
  /* the competing candidates only (study.capability_require excludes the others) */
  size_t nr = (size_t)rep->n_ranked;
  for (size_t c = 0; c < nr; ++c)
    buf[c] = rep->rank_time[c];
  POM_TRY_GOTO(pom_h5_write_int64s(g, "execution_time", nr, buf, err), done);
  for (size_t c = 0; c < nr; ++c)
    buf[c] = rep->rank_energy[c];
  POM_TRY_GOTO(pom_h5_write_int64s(g, "energy", nr, buf, err), done);
  if (study->n_requirements > 0) { /* the excluded ones, in index order */
    for (size_t c = nr; c < nc; ++c)
      buf[c - nr] = rep->rank_time[c];
    POM_TRY_GOTO(pom_h5_write_int64s(g, "excluded", nc - nr, buf, err), done);
  }
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

/* Main effects, the common-maneuver means and the Pareto front (for the
 * figures of many candidates). */
static pom_status write_effects(hid_t file, const pom_doe_report *rep, pom_error *err) {
  pom_status st = POM_OK;
  hid_t g = -1;
  size_t n = (size_t)rep->n_effects, nc = (size_t)rep->n_candidates;
  double *buf = malloc((n > nc ? n : nc) * 11 * sizeof *buf + sizeof *buf);
  if (!buf) POM_FAIL(err, POM_ERR_NOMEM, "results: out of memory");
  POM_TRY_GOTO(replace_group(&g, file, "effects", err), done);
  for (size_t j = 0; j < n; ++j) {
    const pom_doe_effect *e = &rep->effects[j];
    double *r = buf + 11 * j;
    r[0] = e->factor;
    r[1] = e->level;
    r[2] = e->lo;
    r[3] = e->hi;
    r[4] = e->n_candidates;
    r[5] = e->metric;
    r[6] = (double)e->n;
    r[7] = e->mean;
    r[8] = e->ci_low;
    r[9] = e->ci_high;
    r[10] = (double)e->n_censored;
  }
  size_t dims[2] = {n, 11};
  POM_TRY_GOTO(pom_h5_write_doubles(g, "main", 2, dims, buf, err), done);
  POM_TRY_GOTO(pom_h5_attr_string(g, "columns",
                                  "factor,level,lo,hi,n_candidates,metric(0=execution_time s,"
                                  "1=energy J),n_maneuvers,mean,ci_low,ci_high,n_censored",
                                  err),
               done);
  for (size_t c = 0; c < nc; ++c) {
    buf[4 * c + 0] = rep->mean_time[c];
    buf[4 * c + 1] = rep->mean_energy[c];
    buf[4 * c + 2] = rep->pareto[c];
    buf[4 * c + 3] = (double)rep->censored_common[c];
  }
  if (rep->n_cap_effects > 0) { /* the capability figures' main effects (study.capability) */
    size_t ne = (size_t)rep->n_cap_effects;
    double *cb = malloc(ne * 10 * sizeof *cb);
    if (!cb) POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "results: out of memory");
    for (size_t j = 0; j < ne; ++j) {
      const pom_doe_cap_effect *e = &rep->cap_effects[j];
      double *r = cb + 10 * j;
      r[0] = e->factor;
      r[1] = e->level;
      r[2] = e->lo;
      r[3] = e->hi;
      r[4] = e->n_candidates;
      r[5] = e->figure;
      r[6] = e->n;
      r[7] = e->mean;
      r[8] = e->min;
      r[9] = e->max;
    }
    size_t edims[2] = {ne, 10};
    st = pom_h5_write_doubles(g, "capability", 2, edims, cb, err);
    free(cb);
    if (st != POM_OK) goto done;
    char figs[256];
    pom_cap_figure_list(figs, sizeof figs);
    POM_TRY_GOTO(pom_h5_attr_string(g, "capability_columns",
                                    "factor,level,lo,hi,n_candidates,figure,n_computed,mean,min,"
                                    "max (SI; figure indexes capability_figures)",
                                    err),
                 done);
    POM_TRY_GOTO(pom_h5_attr_string(g, "capability_figures", figs, err), done);
  }
  size_t cdims[2] = {nc, 4};
  POM_TRY_GOTO(pom_h5_write_doubles(g, "common_means", 2, cdims, buf, err), done);
  hid_t ds = H5Dopen2(g, "common_means", H5P_DEFAULT);
  if (ds < 0) {
    st = pom_h5_fail(err, __FILE__, __LINE__, "annotating common_means");
    goto done;
  }
  st = pom_h5_attr_string(ds, "columns", "execution_time_s,energy_J,pareto,censored", err);
  H5Dclose(ds);
done:
  if (g >= 0) H5Gclose(g);
  free(buf);
  return st;
}

static pom_status write_report(pom_doe_results *res, const pom_doe_study *study,
                               const pom_doe_report *rep, pom_error *err) {
  pom_h5_quiet();
  /* a resumed study may use other levels than the run that created the file */
  POM_TRY(pom_h5_attr_double(res->file, "alpha", study->alpha, err));
  POM_TRY(pom_h5_attr_double(res->file, "confidence", study->confidence, err));
  /* the primary time metric of the comparisons, Friedman, ranking, effects */
  POM_TRY(pom_h5_attr_string(res->file, "time_metric",
                             study->time_metric == POM_DOE_TIME_POINTING ? "pointing_settling_time"
                                                                         : "execution_time",
                             err));
  POM_TRY(write_statistics(res->file, rep, err));
  POM_TRY(write_comparisons(res->file, rep, err));
  hid_t g = -1;
  POM_TRY(pom_h5_open_group(&g, res->file, "comparison", err));
  pom_status st = pom_h5_attr_double(g, "confidence", study->confidence, err);
  if (st == POM_OK) st = pom_h5_attr_double(g, "alpha", study->alpha, err);
  H5Gclose(g);
  POM_TRY(st);
  POM_TRY(write_ranking(res->file, study, rep, err));
  POM_TRY(write_effects(res->file, rep, err));
  return pom_doe_results_flush(res, err);
}

/* Closes the HDF5 side of res. */
static pom_status close_hdf5(pom_doe_results *res, pom_error *err) {
  pom_h5_quiet();
  for (int c = 0; c < res->n_candidates; ++c)
    if (res->rows && res->rows[c] >= 0) H5Dclose(res->rows[c]);
  if (res->row_mem >= 0) H5Tclose(res->row_mem);
  if (res->row_file >= 0) H5Tclose(res->row_file);
  pom_status st = pom_h5_close_file(res->file, err);
  res->file = res->row_mem = res->row_file = -1;
  if (res->rows)
    for (int c = 0; c < res->n_candidates; ++c)
      res->rows[c] = -1;
  return st;
}

/* Frees res after closing it; releases the lock. */
static void results_free(pom_doe_results *res) {
  pom_io_lock_release(&res->lock);
  free(res->rows);
  free(res);
}

pom_status pom_doe_results_end(pom_doe_results *res, const pom_doe_study *study,
                               const pom_doe_report *rep, int complete, pom_error *err) {
  if (!res) return POM_OK;
  char tmp[sizeof res->path + 32];
  snprintf(tmp, sizeof tmp, "%s.tmp.%ld", res->path, (long)getpid());
  /* the rows are complete in open_path (every step flushed them); from here
   * on it is only read: the report goes into a copy, so a failure (a full
   * disk) cannot damage the rows */
  pom_status st = close_hdf5(res, err);
  if (st == POM_OK) st = pom_io_sync(res->open_path, err); /* durable before the report */
  if (st == POM_OK) {
    st = pom_io_copy(res->open_path, tmp, err);
    if (st == POM_OK) st = pom_h5_open_file(&res->file, tmp, 1, err);
    if (st == POM_OK) st = write_report(res, study, rep, err);
    if (res->file >= 0) {
      pom_status cst = close_hdf5(res, st == POM_OK ? err : NULL);
      if (st == POM_OK) st = cst;
    }
    if (st == POM_OK) st = pom_io_sync(tmp, err);
    /* promoted only when every write and the close succeeded */
    const char *dest = complete ? res->path : res->open_path;
    if (st == POM_OK && rename(tmp, dest) != 0)
      st = pom_error_set(err, POM_ERR_IO, __FILE__, __LINE__, "cannot rename '%s' to '%s': %s", tmp,
                         dest, strerror(errno));
    if (st == POM_OK) st = pom_io_sync_folder(dest, err);
    if (st == POM_OK && complete) {
      unlink(res->open_path);
      st = pom_io_sync_folder(res->open_path, err);
    } else if (st != POM_OK) {
      unlink(tmp);
      pom_error_prefix(err,
                       "the report was not written; every finished maneuver is kept in '%s' "
                       "(resume it once the cause is fixed)",
                       res->open_path);
    }
  }
  results_free(res);
  return st;
}

pom_status pom_doe_results_close_rows(pom_doe_results *res, pom_error *err) {
  return close_hdf5(res, err);
}

pom_status pom_doe_results_drop_rows(pom_doe_results *res, pom_error *err) {
  if (unlink(res->open_path) != 0)
    POM_FAIL(err, POM_ERR_IO, "cannot remove '%s': %s", res->open_path, strerror(errno));
  return pom_io_sync_folder(res->open_path, err);
}

pom_status pom_doe_results_close(pom_doe_results *res, pom_error *err) {
  if (!res) return POM_OK;
  pom_status st = close_hdf5(res, err);
  results_free(res);
  return st;
}
