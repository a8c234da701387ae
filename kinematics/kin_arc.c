/* kin_arc.c - mass properties of the 3-RRR's arc links, shared by
 * arch_3rrr.c and the limb tables (kin_limb.c): docs/kinematics-3rrr.md
 * section 6. */
#include "kin_internal.h"
#include "pom_math.h"

#include <math.h>

void pom_kin_pair_frame(double F[9], const double a[3], const double b[3]) {
  double e2[3], e3[3];
  pom_v3_axpy(e2, b, -pom_v3_dot(a, b), a);
  pom_v3_normalize(e2, e2);
  pom_v3_cross(e3, a, e2);
  for (int r = 0; r < 3; ++r) {
    F[3 * r + 0] = a[r];
    F[3 * r + 1] = e2[r];
    F[3 * r + 2] = e3[r];
  }
}

void pom_kin_arc_inertia(double *mass, double cm[3], double IO[9], const double a[3],
                         const double b[3], double r, double lam) {
  double F[9];
  pom_kin_pair_frame(F, a, b);
  double e1[3] = {F[0], F[3], F[6]}, e2[3] = {F[1], F[4], F[7]};
  double al = pom_kin_angle_between(a, b), m = lam * r * al;
  double c11 = 0.5 * al + 0.25 * sin(2.0 * al), c22 = 0.5 * al - 0.25 * sin(2.0 * al);
  double c12 = 0.5 * sin(al) * sin(al), k = lam * r * r * r;
  *mass = m;
  for (int i = 0; i < 3; ++i) {
    cm[i] = r / al * (sin(al) * e1[i] + (1.0 - cos(al)) * e2[i]);
    for (int j = 0; j < 3; ++j) {
      double S =
          k * (c11 * e1[i] * e1[j] + c22 * e2[i] * e2[j] + c12 * (e1[i] * e2[j] + e2[i] * e1[j]));
      IO[3 * i + j] = (i == j ? m * r * r : 0.0) - S;
    }
  }
}

void pom_kin_add_point_mass(double *mass, double s[3], double IO[9], double m, const double p[3]) {
  double pp = pom_v3_dot(p, p);
  *mass += m;
  for (int i = 0; i < 3; ++i) {
    s[i] += m * p[i];
    for (int j = 0; j < 3; ++j)
      IO[3 * i + j] += m * ((i == j ? pp : 0.0) - p[i] * p[j]);
  }
}

int pom_kin_body_from_O(pom_mechanism *mech, const char *name, int limb_no, double mass,
                        const double s[3], const double IO[9]) {
  double I3[9], cm[3];
  pom_m3_identity(I3);
  pom_v3_scale(cm, 1.0 / mass, s);
  int k = pom_kin_build_body(mech, name, limb_no, NULL, I3, cm);
  pom_mech_body *b = &mech->body[k];
  pom_v3_copy(b->cm, cm); /* pom_kin_build_body keeps cm only with mass properties */
  double cc = pom_v3_dot(cm, cm);
  b->mass = mass;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      b->inertia[3 * i + j] = IO[3 * i + j] - mass * ((i == j ? cc : 0.0) - cm[i] * cm[j]);
  for (int i = 0; i < 3; ++i) /* exactly symmetric */
    for (int j = 0; j < i; ++j)
      b->inertia[3 * i + j] = b->inertia[3 * j + i];
  return k;
}
