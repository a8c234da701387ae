/* dyn_parasitic_jac.c - sparsity structure of the parasitic model's Jacobian
 * and its column colouring (Curtis-Powell-Reid): a joint couples only its two
 * bodies (an actuator, linear or rotary, only the bodies of its joint), so
 * columns whose rows do not overlap are perturbed together
 * (docs/dynamics.md section 7). The finite differences themselves are
 * dyn_fdjac.c's. */
#include "dyn_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- structure ----------------------------------------------------------- */
enum { KIND_U, KIND_P, KIND_H, KIND_ORI, KIND_FLUX, KIND_INT, KIND_ACC };

/* Entity (body slot 0..nb-1, actuator nb + a, -1 for an accumulator) and
 * kind of state i. */
static int state_entity(const pom_dyn_model *m, int i, int *kind) {
  if (i < m->n_bodies * m->body_states) {
    int r = i % m->body_states;
    *kind = r < DYN_BODY_P     ? KIND_U
            : r < DYN_BODY_H   ? KIND_P
            : r < DYN_BODY_ORI ? KIND_H
                               : KIND_ORI;
    return i / m->body_states;
  }
  for (int a = 0; a < m->n_actuators; ++a) {
    if (i == m->act[a].flux_state) {
      *kind = KIND_FLUX;
      return m->n_bodies + a;
    }
    if (m->act[a].ctrl_state >= 0 && i >= m->act[a].ctrl_state &&
        i < m->act[a].ctrl_state + m->ctrl->n_states) {
      *kind = KIND_INT;
      return m->n_bodies + a;
    }
  }
  *kind = KIND_ACC;
  return -1;
}

/* Does the derivative of a state of kind ki on entity ei depend on a state of
 * kind kj on entity ej? (adjacent = same entity or coupled by a joint or an
 * actuator; rate_deps = the controller's POM_DYN_CTRL_DEP_* flags, -1 for a
 * coupled controller (law_all, every entity adjacent);
 * docs/dynamics.md section 7) */
static int depends(int ki, int ei, int kj, int ej, int adjacent, int rate_deps) {
  int same = ei == ej;
  int body_col = kj <= KIND_ORI;
  switch (ki) {
  case KIND_U: /* u_dot = p / m */
    return same && kj == KIND_P;
  case KIND_ORI: /* orientation rate from its own orientation and h' */
    return same && (kj == KIND_ORI || kj == KIND_H);
  case KIND_P:
  case KIND_H: /* efforts of joints and actuators on the EJS */
    return adjacent && (body_col || kj == KIND_FLUX || kj == KIND_INT);
  case KIND_FLUX: /* coil: u(e, z, q_dot), back-emf, its own flux */
    return adjacent && (body_col || kj == KIND_FLUX || kj == KIND_INT);
  case KIND_INT:       /* controller states: z_dot(q(u, orientation) [, q_dot(p, h')] [, z]) */
    if (rate_deps < 0) /* a coupled law: anything it is adjacent to */
      return adjacent && (body_col || kj == KIND_FLUX || kj == KIND_INT);
    if (adjacent && !same && (kj == KIND_U || kj == KIND_ORI)) return 1;
    if ((rate_deps & POM_DYN_CTRL_DEP_QDOT) && adjacent && !same && (kj == KIND_P || kj == KIND_H))
      return 1;
    return (rate_deps & POM_DYN_CTRL_DEP_STATE) && same && kj == KIND_INT;
  default: /* accumulators: rows left out (they never feed back) */
    return 0;
  }
}

pom_status pom_dyn_structure_build(pom_dyn_model *m, pom_error *err) {
  pom_status st = POM_OK;
  int n = m->n_states;
  int ne = m->n_bodies + m->n_actuators;
  unsigned char *adj = NULL, *used = NULL;
  int *ent = NULL, *kind = NULL, *order = NULL, *rows = NULL;
  adj = calloc((size_t)(ne * ne), 1);
  m->dep = calloc((size_t)n * (size_t)n, 1);
  m->color = calloc((size_t)n, sizeof *m->color);
  used = calloc((size_t)n * (size_t)n, 1);
  ent = calloc((size_t)n, sizeof *ent);
  kind = calloc((size_t)n, sizeof *kind);
  order = calloc((size_t)n, sizeof *order);
  rows = calloc((size_t)n, sizeof *rows);
  if (!adj || !m->dep || !m->color || !used || !ent || !kind || !order || !rows)
    POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "allocating the Jacobian structure (%d states)", n);

  /* entity adjacency: a joint couples its two bodies; an actuator couples
   * with the bodies of its joint */
  for (int e = 0; e < ne; ++e)
    adj[e * ne + e] = 1;
  for (int j = 0; j < m->n_joints; ++j) {
    const dyn_joint *jt = &m->joint[j];
    int s0 = jt->slot[0], s1 = jt->slot[1];
    if (s0 >= 0 && s1 >= 0) adj[s0 * ne + s1] = adj[s1 * ne + s0] = 1;
    if (jt->actuator >= 0) {
      int ea = m->n_bodies + jt->actuator;
      for (int s = 0; s < 2; ++s)
        if (jt->slot[s] >= 0) adj[jt->slot[s] * ne + ea] = adj[ea * ne + jt->slot[s]] = 1;
    }
  }
  /* a coupled controller: every actuator's voltage reads every actuator's
   * sensors (and currents), so every entity is adjacent to every other */
  if (m->ctrl->law_all) memset(adj, 1, (size_t)(ne * ne));
  for (int i = 0; i < n; ++i)
    ent[i] = state_entity(m, i, &kind[i]);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      int a = ent[i] >= 0 && ent[j] >= 0 && adj[ent[i] * ne + ent[j]];
      unsigned char dij = (unsigned char)(a ? depends(kind[i], ent[i], kind[j], ent[j], 1,
                                                      m->ctrl->law_all ? -1 : m->ctrl->rate_deps)
                                            : 0);
      m->dep[(size_t)i * (size_t)n + (size_t)j] = dij;
    }
  }
  POM_TRY_GOTO(pom_dyn_pattern_build(m, err), done);

  /* greedy colouring of the columns: a colour's columns touch disjoint rows.
   * Columns are visited by decreasing row count (largest first), which puts
   * the most coupled bodies (the platform and its links) first: 48 colours
   * for the shipped mechanisms against 60 in state order. */
  m->n_colors = 0;
  for (int j = 0; j < n; ++j) {
    order[j] = j;
    rows[j] = 0;
    for (int i = 0; i < n; ++i)
      rows[j] += m->dep[(size_t)i * (size_t)n + (size_t)j];
  }
  for (int a = 1; a < n; ++a) /* insertion sort, stable, by decreasing rows */
    for (int b = a; b > 0 && rows[order[b]] > rows[order[b - 1]]; --b) {
      int t = order[b];
      order[b] = order[b - 1];
      order[b - 1] = t;
    }
  for (int jj = 0; jj < n; ++jj) {
    int j = order[jj];
    int c = 0;
    for (;; ++c) {
      if (c == m->n_colors) {
        ++m->n_colors;
        break;
      }
      int clash = 0;
      for (int i = 0; i < n && !clash; ++i)
        if (m->dep[(size_t)i * (size_t)n + (size_t)j] && used[(size_t)c * (size_t)n + (size_t)i])
          clash = 1;
      if (!clash) break;
    }
    m->color[j] = c;
    for (int i = 0; i < n; ++i)
      if (m->dep[(size_t)i * (size_t)n + (size_t)j]) used[(size_t)c * (size_t)n + (size_t)i] = 1;
  }
done:
  free(adj);
  free(used);
  free(ent);
  free(order);
  free(rows);
  free(kind);
  return st;
}
