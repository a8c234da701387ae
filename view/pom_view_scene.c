/* pom_view_scene.c - what the page of `pomlab view` draws besides the
 * mechanisms (docs/view.md): a maneuver's trace read from the HDF5 file of
 * `pomlab simulate --out` and sampled into platform rotations and a pointing
 * error, and the workspace's pointing directions coloured by dexterity with
 * the regular dexterous workspace outlined. */
#include "pom_view.h"

#include "pom_arch.h"
#include "pom_dyn_metrics_schema.h"
#include "pom_h5.h"
#include "pom_math.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- the trace ------------------------------------------------------------------ */
void pom_view_trace_file_free(pom_view_trace_file *tf) {
  free(tf->t);
  free(tf->q);
  free(tf->voltage);
  free(tf->quat);
  memset(tf, 0, sizeof *tf);
}

/* Rows of dataset `name` of g with `cols` columns; -1 when absent or shaped
 * otherwise. */
static long dataset_rows(hid_t g, const char *name, int cols) {
  if (!pom_h5_exists(g, name)) return -1;
  hid_t d = H5Dopen2(g, name, H5P_DEFAULT);
  if (d < 0) return -1;
  hid_t s = H5Dget_space(d);
  hsize_t dims[2] = {0, 0};
  int rank = s >= 0 ? H5Sget_simple_extent_ndims(s) : -1;
  if (rank >= 1 && rank <= 2) H5Sget_simple_extent_dims(s, dims, NULL);
  if (s >= 0) H5Sclose(s);
  H5Dclose(d);
  if (rank == 1 && cols == 1) return (long)dims[0];
  if (rank == 2 && (int)dims[1] == cols) return (long)dims[0];
  return -1;
}

/* The setpoints: the metric `target` of the file's metrics group, when there. */
static void read_target(hid_t file, pom_view_trace_file *tf) {
  hid_t m = -1;
  pom_error err;
  pom_error_clear(&err);
  if (!pom_h5_exists(file, "metrics") || pom_h5_open_group(&m, file, "metrics", &err) != POM_OK)
    return;
  char key[96];
  pom_dyn_metric_json_key(pom_dyn_metric(POM_DYN_METRIC_target), key, sizeof key);
  if (H5Aexists(m, key) > 0) {
    hid_t a = H5Aopen(m, key, H5P_DEFAULT);
    if (a >= 0) {
      hid_t s = H5Aget_space(a);
      if (s >= 0 && H5Sget_simple_extent_npoints(s) == 3 &&
          H5Aread(a, H5T_NATIVE_DOUBLE, tf->target) >= 0)
        tf->has_target = 1;
      if (s >= 0) H5Sclose(s);
      H5Aclose(a);
    }
  }
  H5Gclose(m);
}

pom_status pom_view_trace_file_read(pom_view_trace_file *tf, const char *path, pom_error *err) {
  hid_t file = -1, g = -1;
  pom_status st = POM_OK;
  memset(tf, 0, sizeof *tf);
  POM_TRY(pom_h5_open_file(&file, path, 0, err));
  pom_error nerr;
  pom_error_clear(&nerr);
  if (pom_h5_open_group(&g, file, "trace", &nerr) != POM_OK)
    POM_FAIL_GOTO(err, POM_ERR_IO, done,
                  "'%s' has no group 'trace' (write it with pomlab simulate CONFIG --target ... "
                  "--out FILE.h5)",
                  path);
  if (pom_h5_read_attr_string(file, "name", tf->name, sizeof tf->name, &nerr) != POM_OK)
    tf->name[0] = '\0';
  long n = dataset_rows(g, "t", 1);
  if (n < 1 || dataset_rows(g, "q", 3) != n || dataset_rows(g, "voltage", 3) != n ||
      dataset_rows(g, "quat", 4) != n)
    POM_FAIL_GOTO(err, POM_ERR_IO, done,
                  "'%s': trace/t, q, voltage and quat must exist with the same number of rows "
                  "(quat with 4 columns)",
                  path);
  tf->n = (int)n;
  size_t un = (size_t)n;
  tf->t = malloc(un * sizeof *tf->t);
  tf->q = malloc(3 * un * sizeof *tf->q);
  tf->voltage = malloc(3 * un * sizeof *tf->voltage);
  tf->quat = malloc(4 * un * sizeof *tf->quat);
  if (!tf->t || !tf->q || !tf->voltage || !tf->quat)
    POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "no memory for the trace of %ld samples", n);
  POM_TRY_GOTO(pom_h5_read_doubles(g, "t", un, tf->t, err), done);
  POM_TRY_GOTO(pom_h5_read_doubles(g, "q", 3 * un, tf->q, err), done);
  POM_TRY_GOTO(pom_h5_read_doubles(g, "voltage", 3 * un, tf->voltage, err), done);
  POM_TRY_GOTO(pom_h5_read_doubles(g, "quat", 4 * un, tf->quat, err), done);
  read_target(file, tf);
done:
  if (g >= 0) H5Gclose(g);
  pom_error cerr;
  pom_error_clear(&cerr);
  pom_h5_close_file(file, &cerr);
  if (st != POM_OK) pom_view_trace_file_free(tf);
  return st;
}

void pom_view_trace_sample(pom_view_frames *fr, const pom_view_trace_file *tf,
                           const pom_kin_arch *arch, int max_frames, pom_view_trace *vt,
                           const char *source) {
  int m = tf->n < max_frames ? tf->n : max_frames;
  fr->n = m;
  fr->warning[0] = '\0';
  double Rlast[9], Rt[9];
  double qn[4];
  memcpy(qn, tf->quat + 4 * (tf->n - 1), sizeof qn);
  pom_quat_to_matrix(Rlast, qn);
  memcpy(Rt, Rlast, sizeof Rt);
  if (tf->has_target) {
    pom_error err;
    pom_error_clear(&err);
    if (pom_kin_forward(arch, tf->target, Rlast, NULL, Rt, NULL, &err) != POM_OK) {
      snprintf(fr->warning, sizeof fr->warning,
               "the target's orientation is unknown (%s): the pointing error is measured from "
               "the last sample",
               err.message);
      memcpy(Rt, Rlast, sizeof Rt);
    }
  }
  const double nt[3] = {Rt[2], Rt[5], Rt[8]};
  for (int k = 0; k < m; ++k) {
    long i = m > 1 ? lround((double)k * (tf->n - 1) / (m - 1)) : 0;
    double qq[4];
    memcpy(qq, tf->quat + 4 * i, sizeof qq);
    double nq = sqrt(qq[0] * qq[0] + qq[1] * qq[1] + qq[2] * qq[2] + qq[3] * qq[3]);
    for (int a = 0; a < 4; ++a)
      qq[a] = nq > 0.0 ? qq[a] / nq : (a == 0);
    double *R = fr->R + 9 * k;
    pom_quat_to_matrix(R, qq);
    fr->t[k] = tf->t[i];
    for (int a = 0; a < 3; ++a) {
      fr->q[3 * k + a] = tf->q[3 * i + a];
      fr->u[3 * k + a] = tf->voltage[3 * i + a];
    }
    const double n[3] = {R[2], R[5], R[8]};
    fr->err[k] = pom_kin_angle_between(n, nt);
  }
  memset(vt, 0, sizeof *vt);
  vt->n = m;
  vt->t = fr->t;
  vt->R = fr->R;
  vt->q = fr->q;
  vt->voltage = fr->u;
  vt->pointing_error = fr->err;
  for (int a = 0; a < 3; ++a)
    vt->target[a] = tf->has_target ? tf->target[a] : tf->q[3 * (tf->n - 1) + a];
  vt->source = source;
}

/* ---- the workspace ---------------------------------------------------------------- */
pom_status pom_view_workspace_compute(const pom_kin_arch *arch, const pom_kin_ws_opts *ws,
                                      pom_view_ws_grid *g, pom_view_workspace *w, pom_error *err) {
  memset(w, 0, sizeof *w);
  w->n_tilt = POM_VIEW_WS_TILT_STEPS + 1;
  w->n_azimuth = POM_VIEW_WS_AZIMUTHS;
  w->tilt_step = 0.5 * POM_PI / POM_VIEW_WS_TILT_STEPS;
  for (int it = 0; it < w->n_tilt; ++it)
    for (int ia = 0; ia < w->n_azimuth; ++ia) {
      double t = it * w->tilt_step, a = 2.0 * POM_PI * ia / (w->n_azimuth - 1);
      double e1[3] = {a, t, 0.0}, e2[3] = {-a, 0.0, 0.0}, R1[9], R2[9], R[9];
      pom_euler_zyx_to_matrix(R1, e1); /* Rz(a) Ry(t) */
      pom_euler_zyx_to_matrix(R2, e2); /* Rz(-a) */
      pom_m3_mul(R, R1, R2);
      pom_kin_pose pose;
      pom_kin_pose_evaluate(arch, R, &pose, NULL);
      int k = it * w->n_azimuth + ia;
      g->dex[k] = pose.reachable ? pose.dexterity : 0.0;
      g->state[k] = !pose.reachable ? 2 : (ws->check_limits && pose.violations) ? 1 : 0;
    }
  w->dexterity = g->dex;
  w->state = g->state;
  w->dexterity_min = ws->dexterity_min;
  pom_kin_ws_result res;
  POM_TRY(pom_kin_workspace(arch, ws, &res, err));
  w->rdw_half_width = res.half_width;
  w->outline = g->outline;
  if (res.half_width > 0.0) {
    /* the square |theta|, |phi| <= a at psi = 0, walked round */
    double a = res.half_width;
    const double corner[5][2] = {{-a, -a}, {a, -a}, {a, a}, {-a, a}, {-a, -a}};
    int n = 0;
    for (int side = 0; side < 4; ++side)
      for (int k = 0; k < POM_VIEW_WS_OUTLINE; ++k) {
        double f = (double)k / POM_VIEW_WS_OUTLINE;
        double e[3] = {0.0, corner[side][0] + f * (corner[side + 1][0] - corner[side][0]),
                       corner[side][1] + f * (corner[side + 1][1] - corner[side][1])};
        double R[9];
        pom_euler_zyx_to_matrix(R, e);
        g->outline[3 * n] = R[2];
        g->outline[3 * n + 1] = R[5];
        g->outline[3 * n + 2] = R[8];
        ++n;
      }
    w->n_outline = n;
  }
  return POM_OK;
}

/* ---- the workspace coloured by a capability figure ------------------------------- */
/* R = Rz(a) Ry(t) Rz(-a): pointing direction (sin t cos a, sin t sin a, cos t). */
static void tilt_rotation(double R[9], double t, double a) {
  double e1[3] = {a, t, 0.0}, e2[3] = {-a, 0.0, 0.0}, R1[9], R2[9];
  pom_euler_zyx_to_matrix(R1, e1);
  pom_euler_zyx_to_matrix(R2, e2);
  pom_m3_mul(R, R1, R2);
}

pom_status pom_view_capability_compute(const pom_kin_arch *arch, const pom_mechanism *mech,
                                       const pom_dyn_params *p, const pom_cap_opts *o,
                                       const pom_cap_pose_figure *f, pom_view_workspace *w,
                                       pom_view_cap_grid *g, pom_view_capability *c,
                                       pom_error *err) {
  memset(c, 0, sizeof *c);
  c->name = f->name;
  c->unit = f->unit;
  c->description = f->description;
  c->joints = !f->freq ? NULL : p->joints.model == POM_JOINTS_RIGID ? "rigid" : "parasitic";
  c->stride_tilt = f->freq ? 2 : 1;
  c->stride_azimuth = f->freq ? 3 : 1;
  c->n_tilt = (w->n_tilt - 1) / c->stride_tilt + 1;
  c->n_azimuth = (w->n_azimuth - 1) / c->stride_azimuth + 1;
  c->value = g->value;
  c->lo = c->hi = NAN;
  pom_cap_ctx *ctx = NULL;
  POM_TRY(pom_cap_ctx_create(&ctx, arch, mech, p, o, f->freq, err));
  double home = NAN;
  int have_home = 0;
  for (int it = 0; it < c->n_tilt; ++it)
    for (int ia = 0; ia < c->n_azimuth; ++ia) {
      const int wt = it * c->stride_tilt, wa = ia * c->stride_azimuth;
      double *v = &g->value[it * c->n_azimuth + ia];
      *v = NAN;
      if (w->state[wt * w->n_azimuth + wa] != 0) continue;
      if (wt == 0 && have_home) { /* every azimuth at tilt 0 is home */
        *v = home;
        continue;
      }
      double R[9];
      tilt_rotation(R, wt * w->tilt_step, 2.0 * POM_PI * wa / (w->n_azimuth - 1));
      pom_cap_pose pp;
      pom_error pe;
      pom_error_clear(&pe);
      if (pom_cap_pose_eval(ctx, R, &pp, &pe) != POM_OK) {
        c->n_failed++;
      } else {
        *v = pom_cap_pose_figure_value(f, &pp);
        c->n_evaluated++;
      }
      if (wt == 0) home = *v, have_home = 1;
      if (isfinite(*v)) {
        c->lo = isnan(c->lo) ? *v : fmin(c->lo, *v);
        c->hi = isnan(c->hi) ? *v : fmax(c->hi, *v);
      }
    }
  pom_cap_ctx_destroy(ctx);
  w->capability = c;
  return POM_OK;
}
