/* kin_mjcf.c - a mechanism as a MuJoCo MJCF model (pom_mjcf.h,
 * docs/export.md): a spanning tree of the joints from the ground, the
 * joints it leaves out as connect constraints, motors on the actuated
 * joints. */
#include "pom_mjcf.h"

#include "pom_arch.h"
#include "pom_math.h"
#include "pom_shape.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <string.h>

/* Segments an arc shape is drawn with (MJCF has no torus). */
#define ARC_PIECES 8

/* ---- the tree ------------------------------------------------------------------ */
/* How well joint j closes a loop as connect constraints: 0 never (a slide,
 * an actuated joint), 1 a universal (needs its cross as a body), 2 a hinge
 * (two connects), 3 a ball (one connect). The tree takes the joints in
 * this order, so the loops close at the best joints. */
static int cut_rank(const pom_mech_joint *jt) {
  if (jt->actuator >= 0 || jt->type == POM_JOINT_PRISMATIC) return 0;
  if (jt->type == POM_JOINT_UNIVERSAL) return 1;
  if (jt->type == POM_JOINT_REVOLUTE) return 2;
  return 3;
}

static int find_root(int *up, int b) {
  while (up[b] != b)
    b = up[b] = up[up[b]];
  return b;
}

pom_status pom_mjcf_tree_build(const pom_mechanism *m, pom_mjcf_tree *t, pom_error *err) {
  memset(t, 0, sizeof *t);
  int used[POM_MECH_MAX_JOINTS] = {0}, in[POM_MECH_MAX_BODIES] = {0}, up[POM_MECH_MAX_BODIES];
  for (int b = 0; b < m->n_bodies; ++b) {
    t->parent[b] = -1;
    t->parent_joint[b] = -1;
    up[b] = b;
  }
  /* a spanning tree (Kruskal): the joints by cut_rank, then index */
  for (int rank = 0; rank <= 3; ++rank)
    for (int j = 0; j < m->n_joints; ++j) {
      const pom_mech_joint *jt = &m->joint[j];
      if (cut_rank(jt) != rank) continue;
      int a = find_root(up, jt->body[0]), b = find_root(up, jt->body[1]);
      if (a == b) continue;
      up[a] = b;
      used[j] = 1;
    }
  /* its parents: breadth first from the ground */
  int queue[POM_MECH_MAX_BODIES], head = 0, tail = 0;
  in[0] = 1;
  queue[tail++] = 0;
  while (head < tail) {
    int b = queue[head++];
    for (int j = 0; j < m->n_joints; ++j) {
      const pom_mech_joint *jt = &m->joint[j];
      if (!used[j] || (jt->body[0] != b && jt->body[1] != b)) continue;
      int other = jt->body[0] == b ? jt->body[1] : jt->body[0];
      if (in[other]) continue;
      in[other] = 1;
      t->parent[other] = b;
      t->parent_joint[other] = j;
      queue[tail++] = other;
    }
  }
  for (int b = 0; b < m->n_bodies; ++b)
    if (!in[b])
      POM_FAIL(err, POM_ERR_ARG, "MJCF: body %s is not connected to the ground by joints",
               m->body[b].name);
  for (int j = 0; j < m->n_joints; ++j) {
    if (used[j]) continue;
    const pom_mech_joint *jt = &m->joint[j];
    if (cut_rank(jt) == 0)
      POM_FAIL(err, POM_ERR_ARG,
               "MJCF: joint %s (%s%s) would close a loop; MJCF's equality constraints "
               "here close loops at passive spherical, revolute and universal joints only",
               jt->name, jt->actuator >= 0 ? "actuated " : "", pom_joint_type_name(jt->type));
    t->closes[j] = 1;
    ++t->n_closures;
  }
  return POM_OK;
}

/* ---- checked output ------------------------------------------------------------- */
typedef struct {
  FILE *f;
  int failed;
} writer;

#if defined(__GNUC__)
__attribute__((format(printf, 2, 3)))
#endif
static void
out(writer *w, const char *fmt, ...) {
  if (w->failed) return;
  va_list ap;
  va_start(ap, fmt);
  if (vfprintf(w->f, fmt, ap) < 0) w->failed = 1;
  va_end(ap);
}

/* A name as an XML attribute value (quotes, <, >, & escaped). */
static void out_name(writer *w, const char *s) {
  for (; *s && !w->failed; ++s) {
    switch (*s) {
    case '&':
      out(w, "&amp;");
      break;
    case '<':
      out(w, "&lt;");
      break;
    case '>':
      out(w, "&gt;");
      break;
    case '"':
      out(w, "&quot;");
      break;
    default:
      if (fputc(*s, w->f) == EOF) w->failed = 1;
    }
  }
}

/* Text for an XML comment: no "--" inside. */
static void out_comment_text(writer *w, const char *s) {
  for (char prev = 0; *s && !w->failed; prev = *s++)
    if (fputc(*s == '-' && prev == '-' ? '_' : *s, w->f) == EOF) w->failed = 1;
}

static void out_v3(writer *w, const double v[3]) {
  out(w, "%.17g %.17g %.17g", v[0], v[1], v[2]);
}

static void indent(writer *w, int depth) {
  out(w, "%*s", 2 * depth, "");
}

/* ---- geoms ------------------------------------------------------------------- */
/* One capsule from a to b (fixed frame at home) in body b's frame. */
static void geom_capsule(writer *w, int depth, const double cm[3], const double a[3],
                         const double b[3], double radius) {
  double p[3], q[3];
  pom_v3_sub(p, a, cm);
  pom_v3_sub(q, b, cm);
  indent(w, depth);
  out(w, "<geom type=\"capsule\" size=\"%.17g\" fromto=\"", radius);
  out_v3(w, p);
  out(w, " ");
  out_v3(w, q);
  out(w, "\"/>\n");
}

static void geom_shape(writer *w, int depth, const double cm[3], const pom_kin_shape *s) {
  double c[3], d[3];
  switch (s->kind) {
  case POM_SHAPE_SEGMENT:
    pom_v3_sub(d, s->to, s->from);
    if (pom_v3_norm(d) > 0.0) {
      geom_capsule(w, depth, cm, s->from, s->to, s->radius);
    } else {
      pom_v3_sub(c, s->from, cm);
      indent(w, depth);
      out(w, "<geom type=\"sphere\" size=\"%.17g\" pos=\"", s->radius);
      out_v3(w, c);
      out(w, "\"/>\n");
    }
    return;
  case POM_SHAPE_BOX: {
    pom_v3_sub(c, s->center, cm);
    indent(w, depth);
    out(w, "<geom type=\"box\" size=\"%.17g %.17g %.17g\" pos=\"", 0.5 * s->size[0],
        0.5 * s->size[1], 0.5 * s->size[2]);
    out_v3(w, c);
    out(w, "\" xyaxes=\"");
    out_v3(w, s->axis);
    out(w, " ");
    out_v3(w, s->axis2);
    out(w, "\"/>\n");
    return;
  }
  case POM_SHAPE_ARC: {
    /* the shorter way from `from` to `to` about `center`, in ARC_PIECES capsules */
    double a[3], b[3], n[3];
    pom_v3_sub(a, s->from, s->center);
    pom_v3_sub(b, s->to, s->center);
    double r = pom_v3_norm(a);
    pom_v3_cross(n, a, b);
    double ang = atan2(pom_v3_norm(n), pom_v3_dot(a, b));
    if (pom_v3_normalize(n, n) <= 0.0 || !(r > 0.0)) {
      geom_capsule(w, depth, cm, s->from, s->to, s->radius);
      return;
    }
    double t[3], prev[3];
    pom_v3_cross(t, n, a); /* a rotated by 90 deg about n, length r */
    pom_v3_copy(prev, s->from);
    for (int k = 1; k <= ARC_PIECES; ++k) {
      double phi = ang * k / ARC_PIECES, p[3];
      pom_v3_scale(p, cos(phi), a);
      pom_v3_axpy(p, p, sin(phi), t);
      pom_v3_add(p, p, s->center);
      geom_capsule(w, depth, cm, prev, p, s->radius);
      pom_v3_copy(prev, p);
    }
    return;
  }
  case POM_SHAPE_DISC: {
    double p[3], q[3];
    pom_v3_axpy(p, s->center, -0.5 * s->thickness, s->axis);
    pom_v3_axpy(q, s->center, 0.5 * s->thickness, s->axis);
    pom_v3_sub(p, p, cm);
    pom_v3_sub(q, q, cm);
    indent(w, depth);
    out(w, "<geom type=\"cylinder\" size=\"%.17g\" fromto=\"", s->radius);
    out_v3(w, p);
    out(w, " ");
    out_v3(w, q);
    out(w, "\"/>\n");
    return;
  }
  }
}

/* ---- bodies and joints --------------------------------------------------------- */
typedef struct {
  const pom_kin_arch *arch;
  const pom_mechanism *m;
  const pom_mjcf_tree *t;
  const pom_kin_shape *shape;
  int n_shapes;
  double scale; /* length between the two connect points of a hinge closure (m) */
} model;

/* The joint j that attaches child c: hinge, slide, ball or two hinges, its
 * axes oriented so that qpos is the joint's own coordinate (body[1]
 * relative to body[0]) whichever side the tree's parent is. */
static void tree_joint(writer *w, int depth, const model *md, int c, int j) {
  const pom_mechanism *m = md->m;
  const pom_mech_joint *jt = &m->joint[j];
  double pos[3], ax[3];
  pom_v3_sub(pos, jt->point, m->body[c].cm);
  double sign = jt->body[1] == c ? 1.0 : -1.0;
  pom_v3_scale(ax, sign, jt->axis);
  const char *type = "ball";
  if (jt->type == POM_JOINT_REVOLUTE) type = "hinge";
  if (jt->type == POM_JOINT_PRISMATIC) type = "slide";
  if (jt->type == POM_JOINT_UNIVERSAL) {
    /* the axis fixed in the parent first: MuJoCo applies a body's joints in order */
    const double *first = jt->body[0] == c ? jt->axis2 : jt->axis;
    const double *second = jt->body[0] == c ? jt->axis : jt->axis2;
    for (int k = 0; k < 2; ++k) {
      indent(w, depth);
      out(w, "<joint name=\"");
      out_name(w, jt->name);
      out(w, "_%d\" type=\"hinge\" pos=\"", k + 1);
      out_v3(w, pos);
      out(w, "\" axis=\"");
      out_v3(w, k ? second : first);
      out(w, "\"/>\n");
    }
    return;
  }
  indent(w, depth);
  out(w, "<joint name=\"");
  out_name(w, jt->name);
  out(w, "\" type=\"%s\" pos=\"", type);
  out_v3(w, pos);
  out(w, "\"");
  if (jt->type != POM_JOINT_SPHERICAL) {
    out(w, " axis=\"");
    out_v3(w, ax);
    out(w, "\"");
  }
  if (jt->actuator >= 0) {
    double half = 0.5 * m->actuator[jt->actuator].stroke;
    out(w, " limited=\"true\" range=\"%.17g %.17g\"", -half, half);
  }
  out(w, "/>\n");
}

/* The cross of a universal joint j that closes a loop: a body on body[0]
 * turning about `axis`, joined to body[1] by the hinge `axis2` (the
 * connects of closures()). */
static void cross_body(writer *w, int depth, const model *md, int b0, int j) {
  const pom_mech_joint *jt = &md->m->joint[j];
  double pos[3];
  pom_v3_sub(pos, jt->point, md->m->body[b0].cm);
  indent(w, depth);
  out(w, "<body name=\"");
  out_name(w, jt->name);
  out(w, "_cross\" pos=\"");
  out_v3(w, pos);
  out(w, "\">\n");
  indent(w, depth + 1);
  out(w, "<joint name=\"");
  out_name(w, jt->name);
  out(w, "_1\" type=\"hinge\" pos=\"0 0 0\" axis=\"");
  out_v3(w, jt->axis);
  out(w, "\"/>\n");
  indent(w, depth);
  out(w, "</body>\n");
}

static void body(writer *w, int depth, const model *md, int b) {
  const pom_mechanism *m = md->m;
  const pom_mech_body *bd = &m->body[b];
  int p = md->t->parent[b];
  double pos[3];
  pom_v3_sub(pos, bd->cm, m->body[p].cm);
  indent(w, depth);
  out(w, "<body name=\"");
  out_name(w, bd->name);
  out(w, "\" pos=\"");
  out_v3(w, pos);
  out(w, "\">\n");
  if (bd->mass > 0.0) {
    const double *I = bd->inertia;
    indent(w, depth + 1);
    out(w,
        "<inertial pos=\"0 0 0\" mass=\"%.17g\" fullinertia=\"%.17g %.17g %.17g %.17g %.17g "
        "%.17g\"/>\n",
        bd->mass, I[0], I[4], I[8], I[1], I[2], I[5]);
  }
  tree_joint(w, depth + 1, md, b, md->t->parent_joint[b]);
  for (int s = 0; s < md->n_shapes; ++s)
    if (md->shape[s].body == b) geom_shape(w, depth + 1, bd->cm, &md->shape[s]);
  for (int c = 1; c < m->n_bodies; ++c)
    if (md->t->parent[c] == b) body(w, depth + 1, md, c);
  for (int j = 0; j < m->n_joints; ++j)
    if (md->t->closes[j] && m->joint[j].type == POM_JOINT_UNIVERSAL && m->joint[j].body[0] == b)
      cross_body(w, depth + 1, md, b, j);
  indent(w, depth);
  out(w, "</body>\n");
}

/* One connect: the point x (fixed frame, home) of body1 and of body2 kept
 * together; the anchor is in body1's frame, whose origin is at o1. */
static void connect(writer *w, const char *b1, const char *b1_suffix, const double o1[3],
                    const char *b2, const double x[3]) {
  double a[3];
  pom_v3_sub(a, x, o1);
  out(w, "    <connect body1=\"");
  out_name(w, b1);
  out(w, "%s\" body2=\"", b1_suffix);
  out_name(w, b2);
  out(w, "\" anchor=\"");
  out_v3(w, a);
  out(w, "\"/>\n");
}

static void closures(writer *w, const model *md) {
  const pom_mechanism *m = md->m;
  for (int j = 0; j < m->n_joints; ++j) {
    if (!md->t->closes[j]) continue;
    const pom_mech_joint *jt = &m->joint[j];
    /* the ground is MJCF's worldbody, named "world" */
    const char *n0 = jt->body[0] == 0 ? "world" : m->body[jt->body[0]].name;
    const char *n1 = jt->body[1] == 0 ? "world" : m->body[jt->body[1]].name;
    const double *o0 = m->body[jt->body[0]].cm;
    double far[3];
    out(w, "    <!-- joint ");
    out_comment_text(w, jt->name);
    out(w, " (%s) closes a loop -->\n", pom_joint_type_name(jt->type));
    switch (jt->type) {
    case POM_JOINT_SPHERICAL:
      connect(w, n0, "", o0, n1, jt->point);
      break;
    case POM_JOINT_REVOLUTE:
      /* two points of the hinge line: 5 independent conditions of 6 */
      pom_v3_axpy(far, jt->point, md->scale, jt->axis);
      connect(w, n0, "", o0, n1, jt->point);
      connect(w, n0, "", o0, n1, far);
      break;
    case POM_JOINT_UNIVERSAL:
      /* the cross (on body[0], turning about axis) hinged to body[1] about axis2 */
      pom_v3_axpy(far, jt->point, md->scale, jt->axis2);
      connect(w, jt->name, "_cross", jt->point, n1, jt->point);
      connect(w, jt->name, "_cross", jt->point, n1, far);
      break;
    case POM_JOINT_PRISMATIC:
      break; /* refused by pom_mjcf_tree_build */
    }
  }
}

static pom_status unique_names(const pom_mechanism *m, pom_error *err) {
  for (int a = 0; a < m->n_bodies; ++a)
    for (int b = a + 1; b < m->n_bodies; ++b)
      if (strcmp(m->body[a].name, m->body[b].name) == 0)
        POM_FAIL(err, POM_ERR_ARG, "MJCF: two bodies are named '%s'", m->body[a].name);
  for (int a = 0; a < m->n_joints; ++a)
    for (int b = a + 1; b < m->n_joints; ++b)
      if (strcmp(m->joint[a].name, m->joint[b].name) == 0)
        POM_FAIL(err, POM_ERR_ARG, "MJCF: two joints are named '%s'", m->joint[a].name);
  return POM_OK;
}

pom_status pom_mjcf_write(FILE *f, const char *name, const pom_kin_arch *arch,
                          const pom_mechanism *m, const pom_mjcf_coil *coil, pom_error *err) {
  pom_mjcf_tree tree;
  POM_TRY(pom_mjcf_tree_build(m, &tree, err));
  POM_TRY(unique_names(m, err));
  pom_kin_shape shape[POM_KIN_MAX_SHAPES];
  int n_shapes = 0;
  POM_TRY(pom_kin_body_shapes(arch, m, shape, POM_KIN_MAX_SHAPES, &n_shapes, err));
  const model md = {.arch = arch,
                    .m = m,
                    .t = &tree,
                    .shape = shape,
                    .n_shapes = n_shapes,
                    .scale = pom_kin_draw_scale(arch, m)};
  writer w = {.f = f, .failed = 0};
  const char *arch_name = pom_kin_arch_name(arch);
  out(&w, "<!-- pomlab export: ");
  out_comment_text(&w, name);
  out(&w, " (architecture ");
  out_comment_text(&w, arch_name);
  out(&w,
      "), docs/export.md.\n"
      "     SI units (m, kg, kg m^2, rad, N, N m). Every body frame is parallel to the\n"
      "     fixed frame at home and sits at the body's centre of mass, so qpos = 0 is\n"
      "     pomlab's home pose. Joint qpos is the joint's own coordinate: a hinge's\n"
      "     angle and a slide's displacement of its second body relative to its first;\n"
      "     a universal joint is two hinges, the first on the axis fixed in the parent.\n"
      "     The %d joint(s) the tree leaves out close the loops as connect constraints.\n"
      "     Motors: ctrl is the force (N) or torque (N m); the coil gives ctrl = K i,\n"
      "     K in each motor's user data. -->\n",
      tree.n_closures);
  out(&w, "<mujoco model=\"");
  out_name(&w, name);
  out(&w, "\">\n");
  /* massless bodies (an idle link with no mass given) get MuJoCo's smallest
   * mass and inertia instead of a refusal; balanceinertia mends the thin
   * rods whose principal moments meet the triangle inequality with equality */
  out(&w, "  <compiler angle=\"radian\" inertiafromgeom=\"false\" boundmass=\"1e-9\" "
          "boundinertia=\"1e-15\" balanceinertia=\"true\"/>\n");
  out(&w, "  <option gravity=\"");
  out_v3(&w, m->gravity);
  out(&w, "\"/>\n  <size nuser_actuator=\"3\"/>\n");
  out(&w, "  <default>\n    <geom contype=\"0\" conaffinity=\"0\" rgba=\"0.6 0.6 0.7 1\"/>\n"
          "    <joint limited=\"false\"/>\n  </default>\n");
  out(&w, "  <worldbody>\n");
  for (int s = 0; s < n_shapes; ++s)
    if (shape[s].body == 0) geom_shape(&w, 2, m->body[0].cm, &shape[s]);
  for (int b = 1; b < m->n_bodies; ++b)
    if (tree.parent[b] == 0) body(&w, 2, &md, b);
  for (int j = 0; j < m->n_joints; ++j) /* a universal joint on the ground closing a loop */
    if (tree.closes[j] && m->joint[j].type == POM_JOINT_UNIVERSAL && m->joint[j].body[0] == 0)
      cross_body(&w, 2, &md, 0, j);
  out(&w, "  </worldbody>\n");
  if (tree.n_closures) {
    out(&w, "  <equality>\n");
    closures(&w, &md);
    out(&w, "  </equality>\n");
  }
  if (m->n_actuators) {
    const pom_act_desc *d = pom_act_kind_desc(m->actuator[0].kind);
    double top = coil && coil->resistance > 0.0
                     ? coil->constant * coil->voltage_limit / coil->resistance
                     : 0.0;
    out(&w,
        "  <!-- coil: %s %s = %.17g %s, R = %.17g ohm, V_max = %.17g V; user = K R V_max.\n"
        "       ctrlrange: the stall effort at V_max, K V_max / R (%s). -->\n",
        d ? d->device : "voice coil", d ? d->constant_symbol : "K", coil ? coil->constant : 0.0,
        d ? d->constant_unit : "", coil ? coil->resistance : 0.0, coil ? coil->voltage_limit : 0.0,
        d ? d->effort : "");
    out(&w, "  <actuator>\n");
    for (int a = 0; a < m->n_actuators; ++a) {
      const pom_mech_joint *jt = &m->joint[m->actuator[a].joint];
      out(&w, "    <motor name=\"");
      out_name(&w, jt->name);
      out(&w, "_motor\" joint=\"");
      out_name(&w, jt->name);
      out(&w, "\" gear=\"1\"");
      if (top > 0.0) out(&w, " ctrllimited=\"true\" ctrlrange=\"%.17g %.17g\"", -top, top);
      out(&w, " user=\"%.17g %.17g %.17g\"/>\n", coil ? coil->constant : 0.0,
          coil ? coil->resistance : 0.0, coil ? coil->voltage_limit : 0.0);
    }
    out(&w, "  </actuator>\n");
  }
  out(&w, "</mujoco>\n");
  if (w.failed || ferror(f))
    POM_FAIL(err, POM_ERR_IO, "writing the MJCF model failed: %s", strerror(errno));
  return POM_OK;
}
