/* pom_view_page.c - writes the page of `pomlab view`: the scene as JSON (shapes
 * of every body at home, body poses per frame from the platform rotation
 * through the architecture's kinematics, joints, actuators, a trace, a
 * workspace) between the page's script and style (view/viewer.js and
 * view/viewer.css, embedded at build time) and three.js, inlined (docs/view.md). */
#include "pom_view.h"

#include "pom_arch.h"
#include "pom_math.h"
#include "pom_shape.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The page's script and style (generated from view/ by embed.cmake). */
extern const unsigned char pom_view_js[];
extern const unsigned char pom_view_css[];

const char *pom_view_three_path(void) {
  const char *env = getenv("POM_THREE_JS");
  return env && env[0] ? env : "/usr/share/javascript/three/three.min.js";
}

/* ---- JSON helpers ------------------------------------------------------------ */
static void json_str(FILE *f, const char *s) {
  fputc('"', f);
  for (const unsigned char *p = (const unsigned char *)(s ? s : ""); *p; ++p) {
    if (*p == '"' || *p == '\\')
      fprintf(f, "\\%c", *p);
    else if (*p == '<') /* never "</script>" inside the scene */
      fputs("\\u003c", f);
    else if (*p < 0x20)
      fprintf(f, "\\u%04x", *p);
    else
      fputc(*p, f);
  }
  fputc('"', f);
}

static void json_num(FILE *f, double v) {
  if (isfinite(v))
    fprintf(f, "%.6g", v);
  else
    fputs("null", f);
}

static void json_vec(FILE *f, const double *v, int n) {
  fputc('[', f);
  for (int k = 0; k < n; ++k) {
    if (k) fputc(',', f);
    json_num(f, v[k]);
  }
  fputc(']', f);
}

/* ---- body poses -------------------------------------------------------------- */
/* Body poses at platform rotation R: pose[12 b ..] = R_b (row-major), t_b
 * with x = R_b x_home + t_b. Bodies the kinematics does not cover stay at
 * home. */
static pom_status body_poses(const pom_kin_arch *arch, const pom_mechanism *mech, const double R[9],
                             double *pose, pom_error *err) {
  pom_kin_twists tw;
  POM_TRY(pom_kin_body_twists(arch, R, NULL, &tw, err));
  for (int b = 0; b < mech->n_bodies; ++b) {
    double *p = pose + 12 * b, Rr[3];
    if (b >= tw.n_bodies) {
      memset(p, 0, 12 * sizeof *p);
      p[0] = p[4] = p[8] = 1.0;
      continue;
    }
    const pom_kin_body_twist *bt = &tw.body[b];
    memcpy(p, bt->R, 9 * sizeof *p);
    pom_m3_apply(Rr, bt->R, bt->ref_home);
    pom_v3_sub(p + 9, bt->ref, Rr);
  }
  return POM_OK;
}

static void write_shape(FILE *f, const pom_kin_shape *s) {
  fprintf(f, "{\"kind\":\"%s\",\"body\":%d", pom_kin_shape_kind_name(s->kind), s->body);
  switch (s->kind) {
  case POM_SHAPE_SEGMENT:
    fputs(",\"from\":", f);
    json_vec(f, s->from, 3);
    fputs(",\"to\":", f);
    json_vec(f, s->to, 3);
    break;
  case POM_SHAPE_ARC:
    fputs(",\"from\":", f);
    json_vec(f, s->from, 3);
    fputs(",\"to\":", f);
    json_vec(f, s->to, 3);
    fputs(",\"center\":", f);
    json_vec(f, s->center, 3);
    break;
  case POM_SHAPE_BOX:
    fputs(",\"center\":", f);
    json_vec(f, s->center, 3);
    fputs(",\"axis\":", f);
    json_vec(f, s->axis, 3);
    fputs(",\"axis2\":", f);
    json_vec(f, s->axis2, 3);
    fputs(",\"size\":", f);
    json_vec(f, s->size, 3);
    break;
  case POM_SHAPE_DISC:
    fputs(",\"center\":", f);
    json_vec(f, s->center, 3);
    fputs(",\"axis\":", f);
    json_vec(f, s->axis, 3);
    fputs(",\"thickness\":", f);
    json_num(f, s->thickness);
    break;
  }
  fputs(",\"radius\":", f);
  json_num(f, s->radius);
  fputc('}', f);
}

/* One mechanism: bodies, shapes, joints, actuators and its frames (the
 * trace's rotations, or the one rotation of the page). */
static pom_status write_mech(FILE *f, const pom_view_page *pg, int k, double *pose,
                             int *failed_frames, pom_error *err) {
  const pom_view_mech *vm = &pg->mech[k];
  const pom_mechanism *m = vm->mech;
  const pom_kin_arch *a = vm->arch;
  pom_kin_shape shape[POM_KIN_MAX_SHAPES];
  int n_shapes = 0;
  POM_TRY(pom_kin_body_shapes(a, m, shape, POM_KIN_MAX_SHAPES, &n_shapes, err));
  const pom_act_desc *u = pom_act_kind_desc(a->type->actuator);
  fputs("{\"label\":", f);
  json_str(f, vm->label);
  fputs(",\"arch\":", f);
  json_str(f, a->type->name);
  fputs(",\"arch_label\":", f);
  json_str(f, a->type->label);
  fprintf(f, ",\"actuator_unit\":\"%s\",\"actuator_display\":\"%s\",\"to_display\":%.9g", u->si,
          u->display, u->to_display);
  fputs(",\"scale\":", f);
  json_num(f, pom_kin_draw_scale(a, m));
  fprintf(f, ",\"platform\":%d,\"bodies\":[", m->platform);
  for (int b = 0; b < m->n_bodies; ++b) {
    if (b) fputc(',', f);
    json_str(f, m->body[b].name);
  }
  fputs("],\n\"shapes\":[", f);
  for (int s = 0; s < n_shapes; ++s) {
    if (s) fputs(",\n", f);
    write_shape(f, &shape[s]);
  }
  fputs("],\n\"joints\":[", f);
  for (int j = 0; j < m->n_joints; ++j) {
    const pom_mech_joint *jt = &m->joint[j];
    if (j) fputs(",\n", f);
    fputs("{\"name\":", f);
    json_str(f, jt->name);
    fprintf(f, ",\"type\":\"%s\",\"bodies\":[%d,%d],\"actuator\":%d,\"point\":",
            pom_joint_type_name(jt->type), jt->body[0], jt->body[1], jt->actuator);
    json_vec(f, jt->point, 3);
    fputs(",\"axis\":", f);
    json_vec(f, jt->axis, 3);
    fputs(",\"axis2\":", f);
    json_vec(f, jt->axis2, 3);
    fputc('}', f);
  }
  fputs("],\n\"frames\":[", f);
  /* frames: the trace's (first mechanism only) or the page's one rotation */
  int nf = k == 0 && pg->trace ? pg->trace->n : 1;
  int have = 0;
  for (int i = 0; i < nf; ++i) {
    const double *R = k == 0 && pg->trace ? pg->trace->R + 9 * i : pg->R;
    pom_error ferr;
    pom_error_clear(&ferr);
    pom_status st = body_poses(a, m, R, pose, &ferr);
    if (st != POM_OK) {
      if (!pg->trace) {
        if (err) *err = ferr;
        return st;
      }
      ++*failed_frames; /* keep the previous frame's bodies (or home) */
      if (!have) {
        double I[9];
        pom_m3_identity(I);
        POM_TRY(body_poses(a, m, I, pose, err));
      }
    }
    have = 1;
    if (i) fputs(",\n", f);
    json_vec(f, pose, 12 * m->n_bodies);
  }
  fputs("]}", f);
  return POM_OK;
}

static void write_trace(FILE *f, const pom_view_trace *tr, const pom_act_desc *u) {
  fputs("{\"source\":", f);
  json_str(f, tr->source);
  fprintf(f, ",\"unit\":\"%s\",\"to_display\":%.9g,\"target\":", u->display, u->to_display);
  json_vec(f, tr->target, 3);
  fputs(",\n\"t\":", f);
  json_vec(f, tr->t, tr->n);
  fputs(",\n\"q\":", f);
  json_vec(f, tr->q, 3 * tr->n);
  fputs(",\n\"u\":", f);
  json_vec(f, tr->voltage, 3 * tr->n);
  fputs(",\n\"err\":", f);
  json_vec(f, tr->pointing_error, tr->n);
  fputs("}", f);
}

static void write_workspace(FILE *f, const pom_view_workspace *w) {
  int n = w->n_tilt * w->n_azimuth;
  fprintf(f, "{\"n_tilt\":%d,\"n_azimuth\":%d,\"tilt_step\":%.9g,\"dexterity_min\":%.6g,",
          w->n_tilt, w->n_azimuth, w->tilt_step, w->dexterity_min);
  fputs("\"rdw_half_width\":", f);
  json_num(f, w->rdw_half_width);
  fputs(",\n\"dexterity\":", f);
  json_vec(f, w->dexterity, n);
  fputs(",\n\"state\":[", f);
  for (int k = 0; k < n; ++k)
    fprintf(f, "%s%d", k ? "," : "", w->state[k]);
  fputs("],\n\"outline\":", f);
  json_vec(f, w->outline, 3 * w->n_outline);
  const pom_view_capability *c = w->capability;
  if (c) {
    fputs(",\n\"capability\":{\"name\":", f);
    json_str(f, c->name);
    fputs(",\"unit\":", f);
    json_str(f, c->unit);
    fputs(",\"description\":", f);
    json_str(f, c->description);
    fputs(",\"joints\":", f);
    json_str(f, c->joints);
    fprintf(f,
            ",\"stride_tilt\":%d,\"stride_azimuth\":%d,\"n_tilt\":%d,\"n_azimuth\":%d,"
            "\"n_evaluated\":%d,\"n_failed\":%d,\"lo\":",
            c->stride_tilt, c->stride_azimuth, c->n_tilt, c->n_azimuth, c->n_evaluated,
            c->n_failed);
    json_num(f, c->lo);
    fputs(",\"hi\":", f);
    json_num(f, c->hi);
    fputs(",\n\"value\":", f);
    json_vec(f, c->value, c->n_tilt * c->n_azimuth);
    fputs("}", f);
  }
  fputs("}", f);
}

/* Copies the file at path into out; POM_ERR_IO when it cannot be read. */
static pom_status copy_file(FILE *out, const char *path, pom_error *err) {
  FILE *in = fopen(path, "rb");
  if (!in)
    POM_FAIL(err, POM_ERR_IO,
             "cannot read three.js from '%s' (install Debian's libjs-three, or set POM_THREE_JS "
             "to a three.min.js of release r111 or later)",
             path);
  char buf[65536];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, in)) > 0)
    fwrite(buf, 1, n, out);
  int bad = ferror(in);
  fclose(in);
  if (bad) POM_FAIL(err, POM_ERR_IO, "reading three.js from '%s' failed", path);
  return POM_OK;
}

/* ---- the page ---------------------------------------------------------------- */
pom_status pom_view_write(FILE *out, const pom_view_page *pg, pom_error *err) {
  if (pg->n_mechs < 1 || pg->n_mechs > POM_VIEW_MAX_MECHS)
    POM_FAIL(err, POM_ERR_ARG, "view: %d mechanisms (1 to %d)", pg->n_mechs, POM_VIEW_MAX_MECHS);
  if (pg->trace && (pg->trace->n < 1 || pg->trace->n > POM_VIEW_MAX_FRAMES))
    POM_FAIL(err, POM_ERR_ARG, "view: %d trace frames (1 to %d)", pg->trace->n,
             POM_VIEW_MAX_FRAMES);
  const char *three = pg->three_path ? pg->three_path : pom_view_three_path();
  double *pose = malloc(12 * POM_MECH_MAX_BODIES * sizeof *pose);
  if (!pose) POM_FAIL(err, POM_ERR_NOMEM, "view: no memory for body poses");
  pom_status st = POM_OK;
  int failed = 0;
  fputs("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>", out);
  for (const char *p = pg->title ? pg->title : "pomlab view"; *p; ++p)
    if (*p == '<')
      fputs("&lt;", out);
    else if (*p == '&')
      fputs("&amp;", out);
    else
      fputc(*p, out);
  fputs("</title>\n<!-- written by pomlab view (docs/view.md); self-contained: needs no network "
        "-->\n<style>\n",
        out);
  fputs((const char *)pom_view_css, out);
  fputs("</style></head><body>\n"
        "<div id=\"status\" data-ready=\"0\" data-bodies=\"0\" data-errors=\"0\" "
        "data-webgl=\"0\" data-frames=\"0\" data-frame=\"0\"></div>\n"
        "<script type=\"application/json\" id=\"pom-scene\">\n{\"title\":",
        out);
  json_str(out, pg->title);
  fputs(",\"euler_deg\":", out);
  json_vec(out, pg->euler_deg, 3);
  fprintf(out, ",\"frame\":%d,\n\"mechs\":[\n", pg->frame);
  for (int k = 0; k < pg->n_mechs && st == POM_OK; ++k) {
    if (k) fputs(",\n", out);
    st = write_mech(out, pg, k, pose, &failed, err);
  }
  if (st == POM_OK) {
    fprintf(out, "],\n\"failed_frames\":%d", failed);
    if (pg->trace) {
      fputs(",\n\"trace\":", out);
      write_trace(out, pg->trace, pom_act_kind_desc(pg->mech[0].arch->type->actuator));
    }
    if (pg->workspace) {
      fputs(",\n\"workspace\":", out);
      write_workspace(out, pg->workspace);
    }
    fputs("}\n</script>\n"
          "<!-- three.js r111 (https://threejs.org), Copyright 2010-2019 three.js authors,\n"
          "     MIT licence: Permission is hereby granted, free of charge, to any person\n"
          "     obtaining a copy of this software and associated documentation files (the\n"
          "     \"Software\"), to deal in the Software without restriction, including without\n"
          "     limitation the rights to use, copy, modify, merge, publish, distribute,\n"
          "     sublicense, and/or sell copies of the Software, and to permit persons to whom\n"
          "     the Software is furnished to do so, subject to the following conditions: The\n"
          "     above copyright notice and this permission notice shall be included in all\n"
          "     copies or substantial portions of the Software. THE SOFTWARE IS PROVIDED\n"
          "     \"AS IS\", WITHOUT WARRANTY OF ANY KIND, EXPRESS OR IMPLIED. Inlined from\n"
          "     Debian's libjs-three. -->\n<script>\n",
          out);
    st = copy_file(out, three, err);
  }
  if (st == POM_OK) {
    fputs("\n</script>\n<script>\n", out);
    fputs((const char *)pom_view_js, out);
    fputs("\n</script>\n</body></html>\n", out);
  }
  free(pose);
  return st;
}
