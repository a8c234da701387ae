/* kin_shape.c - drawable shapes of a mechanism's bodies: the type's own
 * (pom_arch.h `shapes`) and, for the bodies it leaves out, shapes derived
 * from the joint points (docs/view.md section 3). */
#include "pom_shape.h"

#include "pom_arch.h"
#include "pom_math.h"

#include <math.h>
#include <string.h>

/* Fractions of the drawing scale of the derived shapes: rod radius, disc
 * thickness (of its radius), slider rod length, fallback cube edge. */
#define ROD_RADIUS     0.045
#define DISC_THICKNESS 0.08
#define SLIDER_LENGTH  0.6
#define CUBE_EDGE      0.15
/* Two joint points closer than this fraction of the scale are one point. */
#define SAME_POINT 1e-6

const char *pom_kin_shape_kind_name(pom_kin_shape_kind kind) {
  switch (kind) {
  case POM_SHAPE_SEGMENT:
    return "segment";
  case POM_SHAPE_BOX:
    return "box";
  case POM_SHAPE_ARC:
    return "arc";
  case POM_SHAPE_DISC:
    return "disc";
  }
  return "?";
}

double pom_kin_draw_scale(const pom_kin_arch *arch, const pom_mechanism *mech) {
  double s = arch ? arch->design.scale : 0.0;
  if (!(s > 0.0) && mech)
    for (int j = 0; j < mech->n_joints; ++j)
      s = fmax(s, pom_v3_norm(mech->joint[j].point));
  return s > 1e-3 ? s : 1e-3;
}

/* ---- derived shapes ------------------------------------------------------------ */
static void shape_init(pom_kin_shape *s, pom_kin_shape_kind kind, int body) {
  memset(s, 0, sizeof *s);
  s->kind = kind;
  s->body = body;
}

/* The distinct joint points of body b (up to cap), and the first prismatic
 * joint touching it (-1 when none). */
static int body_points(const pom_mechanism *m, int b, double tol, double pts[][3], int cap,
                       int *prismatic) {
  int n = 0;
  *prismatic = -1;
  for (int j = 0; j < m->n_joints; ++j) {
    const pom_mech_joint *jt = &m->joint[j];
    if (jt->body[0] != b && jt->body[1] != b) continue;
    if (jt->type == POM_JOINT_PRISMATIC && *prismatic < 0) *prismatic = j;
    int seen = 0;
    for (int k = 0; k < n && !seen; ++k) {
      double d[3];
      pom_v3_sub(d, pts[k], jt->point);
      seen = pom_v3_norm(d) <= tol;
    }
    if (!seen && n < cap) pom_v3_copy(pts[n++], jt->point);
  }
  return n;
}

/* The hinge axes of body b's revolute joints (up to cap), in joint order:
 * when the joints of a body coincide (a spherical linkage, every axis
 * through one point), the axes, not the points, say where the body is. */
static int body_hinges(const pom_mechanism *m, int b, double axes[][3], int cap) {
  int n = 0;
  for (int j = 0; j < m->n_joints && n < cap; ++j) {
    const pom_mech_joint *jt = &m->joint[j];
    if ((jt->body[0] == b || jt->body[1] == b) && jt->type == POM_JOINT_REVOLUTE)
      pom_v3_copy(axes[n++], jt->axis);
  }
  return n;
}

/* The platform: a disc through its joint points away from O (normal of
 * their plane, or e_z); when they are all at O, through the points at the
 * drawing scale along its hinge axes (a spherical linkage's platform); else
 * a disc about O. */
static void derive_platform(const pom_mechanism *m, int b, double scale, pom_kin_shape *s) {
  double pts[POM_MECH_MAX_JOINTS][3], far[POM_MECH_MAX_JOINTS][3];
  int prismatic, n = body_points(m, b, SAME_POINT * scale, pts, POM_MECH_MAX_JOINTS, &prismatic);
  int nf = 0;
  for (int k = 0; k < n; ++k)
    if (pom_v3_norm(pts[k]) > SAME_POINT * scale) pom_v3_copy(far[nf++], pts[k]);
  if (nf == 0) {
    double axes[POM_MECH_MAX_JOINTS][3];
    int na = body_hinges(m, b, axes, POM_MECH_MAX_JOINTS);
    for (int k = 0; k < na && na >= 2; ++k)
      pom_v3_axpy(far[nf++], pts[0], scale, axes[k]);
  }
  shape_init(s, POM_SHAPE_DISC, b);
  pom_v3_set(s->axis, 0.0, 0.0, 1.0);
  s->radius = 0.5 * scale;
  if (nf > 0) {
    for (int k = 0; k < nf; ++k)
      pom_v3_axpy(s->center, s->center, 1.0 / nf, far[k]);
    double r = 0.0;
    for (int k = 0; k < nf; ++k) {
      double d[3];
      pom_v3_sub(d, far[k], s->center);
      r = fmax(r, pom_v3_norm(d));
    }
    if (r > SAME_POINT * scale) s->radius = r;
    if (nf >= 3) {
      double e1[3], e2[3], nrm[3];
      pom_v3_sub(e1, far[1], far[0]);
      pom_v3_sub(e2, far[2], far[0]);
      pom_v3_cross(nrm, e1, e2);
      if (pom_v3_normalize(nrm, nrm) > 0.0) {
        if (nrm[2] < 0.0) pom_v3_scale(nrm, -1.0, nrm);
        pom_v3_copy(s->axis, nrm);
      }
    }
  }
  s->thickness = DISC_THICKNESS * s->radius;
}

/* A limb body: the segment between its farthest joint points; when its
 * joints meet in one point, the arc between two of its hinge axes there; a
 * slider rod ending at its joint; a segment to its CM; or a small cube. */
static void derive_limb(const pom_mechanism *m, int b, double scale, pom_kin_shape *s) {
  double pts[POM_MECH_MAX_JOINTS][3];
  double tol = SAME_POINT * scale;
  int prismatic, n = body_points(m, b, tol, pts, POM_MECH_MAX_JOINTS, &prismatic);
  shape_init(s, POM_SHAPE_SEGMENT, b);
  s->radius = ROD_RADIUS * scale;
  if (n >= 2) {
    double best = -1.0;
    for (int i = 0; i < n; ++i)
      for (int k = i + 1; k < n; ++k) {
        double d[3];
        pom_v3_sub(d, pts[i], pts[k]);
        if (pom_v3_norm(d) > best) {
          best = pom_v3_norm(d);
          pom_v3_copy(s->from, pts[i]);
          pom_v3_copy(s->to, pts[k]);
        }
      }
    return;
  }
  double axes[POM_MECH_MAX_JOINTS][3];
  int na = n == 1 ? body_hinges(m, b, axes, POM_MECH_MAX_JOINTS) : 0;
  if (na >= 2) {
    /* hinges through one point: the arc on the sphere of the drawing scale
     * from its first axis to the next one that is not parallel to it */
    for (int k = 1; k < na; ++k) {
      double c[3];
      pom_v3_cross(c, axes[0], axes[k]);
      if (pom_v3_norm(c) <= SAME_POINT) continue;
      shape_init(s, POM_SHAPE_ARC, b);
      s->radius = ROD_RADIUS * scale;
      pom_v3_copy(s->center, pts[0]);
      pom_v3_axpy(s->from, pts[0], scale, axes[0]);
      pom_v3_axpy(s->to, pts[0], scale, axes[k]);
      return;
    }
  }
  if (n == 1 && prismatic >= 0) {
    /* the body slides along the axis: a rod behind its joint */
    const pom_mech_joint *jt = &m->joint[prismatic];
    double sign = jt->body[1] == b ? -1.0 : 1.0;
    pom_v3_copy(s->to, pts[0]);
    pom_v3_axpy(s->from, pts[0], sign * SLIDER_LENGTH * scale, jt->axis);
    return;
  }
  double d[3];
  if (n == 1) {
    pom_v3_sub(d, m->body[b].cm, pts[0]);
    if (pom_v3_norm(d) > tol) {
      pom_v3_copy(s->from, pts[0]);
      pom_v3_axpy(s->to, pts[0], 2.0, d);
      return;
    }
  }
  shape_init(s, POM_SHAPE_BOX, b);
  pom_v3_copy(s->center, n == 1 ? pts[0] : m->body[b].cm);
  pom_v3_set(s->axis, 1.0, 0.0, 0.0);
  pom_v3_set(s->axis2, 0.0, 1.0, 0.0);
  pom_v3_set(s->size, CUBE_EDGE * scale, CUBE_EDGE * scale, CUBE_EDGE * scale);
}

/* ---- checks ------------------------------------------------------------------ */
static int finite_v(const double *v, int n) {
  for (int k = 0; k < n; ++k)
    if (!isfinite(v[k])) return 0;
  return 1;
}

static pom_status check_shape(const pom_kin_arch_type *t, const pom_mechanism *m,
                              const pom_kin_shape *s, int k, pom_error *err) {
  if (s->body < 0 || s->body >= m->n_bodies)
    POM_FAIL(err, POM_ERR_ARG, "architecture %s: shape %d names body %d of %d", t->name, k, s->body,
             m->n_bodies);
  if ((unsigned)s->kind >= POM_SHAPE_KINDS)
    POM_FAIL(err, POM_ERR_ARG, "architecture %s: shape %d has unknown kind %d", t->name, k,
             (int)s->kind);
  if (!finite_v(s->from, 3) || !finite_v(s->to, 3) || !finite_v(s->center, 3) ||
      !finite_v(s->axis, 3) || !finite_v(s->axis2, 3) || !finite_v(s->size, 3) ||
      !isfinite(s->radius) || !isfinite(s->thickness))
    POM_FAIL(err, POM_ERR_NONFINITE, "architecture %s: shape %d (%s) holds NaN or Inf", t->name, k,
             pom_kin_shape_kind_name(s->kind));
  return POM_OK;
}

/* ---- public ------------------------------------------------------------------ */
pom_status pom_kin_body_shapes(const pom_kin_arch *arch, const pom_mechanism *mech,
                               pom_kin_shape *shape, int cap, int *n, pom_error *err) {
  const pom_kin_arch_type *t = arch->type;
  *n = 0;
  if (!t) POM_FAIL(err, POM_ERR_ARG, "shapes: architecture without a type");
  double scale = pom_kin_draw_scale(arch, mech);
  int count = 0;
  if (t->shapes) {
    count = t->shapes(arch, mech, shape, cap);
    if (count < 0 || count > cap)
      POM_FAIL(err, POM_ERR_ARG, "architecture %s: its shapes do not fit in %d", t->name, cap);
    for (int k = 0; k < count; ++k)
      POM_TRY(check_shape(t, mech, &shape[k], k, err));
  }
  for (int b = 1; b < mech->n_bodies; ++b) {
    int has = 0;
    for (int k = 0; k < count && !has; ++k)
      has = shape[k].body == b;
    if (has) continue;
    if (count >= cap) POM_FAIL(err, POM_ERR_ARG, "shapes: more than %d", cap);
    if (b == mech->platform)
      derive_platform(mech, b, scale, &shape[count++]);
    else
      derive_limb(mech, b, scale, &shape[count++]);
  }
  *n = count;
  return POM_OK;
}
