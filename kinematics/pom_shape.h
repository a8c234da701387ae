/* pom_shape.h - what a body of a mechanism looks like: drawable shapes
 * (segments with a radius, boxes, arcs, discs) at the home pose in the fixed
 * frame, each attached to one body of the mechanism (pom_mechanism.h). A
 * viewer poses them with the body poses of pom_kin_body_twists: a point p of
 * body b at home is at ref + R (p - ref_home) (docs/view.md section 3).
 *
 * An architecture describes its shapes through the optional `shapes`
 * operation of its type (pom_arch.h); every moving body it leaves without a
 * shape gets one derived from the mechanism's joint points, so a new
 * architecture is drawn without a line of drawing code. */
#ifndef POM_SHAPE_H
#define POM_SHAPE_H

#include "pom_kinematics.h"
#include "pom_mechanism.h"
#include "pom_status.h"

typedef enum {
  POM_SHAPE_SEGMENT = 0, /* a rod (cylinder) from `from` to `to`, radius `radius` */
  POM_SHAPE_BOX = 1,     /* a box at `center`, edges size[0] along axis, size[1] along axis2,
                            size[2] along axis x axis2 */
  POM_SHAPE_ARC = 2,     /* a tube of radius `radius` along the circle about `center` through
                            `from` and `to` (equally far from it), the shorter way */
  POM_SHAPE_DISC = 3     /* a disc at `center`, normal `axis`, radius `radius`, thickness
                            `thickness` */
} pom_kin_shape_kind;
#define POM_SHAPE_KINDS 4

/* One drawable shape of one body, at home, fixed frame, SI. */
typedef struct {
  pom_kin_shape_kind kind;
  int body;         /* index of the body it moves with (pom_mechanism.body[]) */
  double from[3];   /* SEGMENT: start; ARC: start point on the arc (m) */
  double to[3];     /* SEGMENT: end; ARC: end point on the arc (m) */
  double center[3]; /* BOX, DISC: centre; ARC: centre of the circle (m) */
  double axis[3];   /* BOX: first edge direction; DISC: normal (unit) */
  double axis2[3];  /* BOX: second edge direction, normal to axis (unit) */
  double size[3];   /* BOX: edge lengths (m) */
  double radius;    /* SEGMENT, ARC: tube radius; DISC: radius (m) */
  double thickness; /* DISC: thickness along the normal (m) */
} pom_kin_shape;

#define POM_KIN_MAX_SHAPES 48

/* Name of a shape kind ("segment", "box", "arc", "disc"); "?" otherwise. */
const char *pom_kin_shape_kind_name(pom_kin_shape_kind kind);

/* Characteristic length of a mechanism for drawing (m): the type's scale
 * (pom_kin_arch.design.scale) when set, else the largest distance of a joint point
 * from O (never 0: 1 mm at least). Radii of derived shapes and markers are
 * fractions of it. */
double pom_kin_draw_scale(const pom_kin_arch *arch, const pom_mechanism *mech);

/* Every shape of the mechanism built from arch (pom_kin_mechanism_from) at
 * home: first those of the type's `shapes` operation (when it has one),
 * then, for every body other than the ground that got none, one derived from
 * its joint points (docs/view.md section 3): the platform a disc through its
 * joint points away from O (through the points at the drawing scale along
 * its hinge axes when every joint point is O); a body with two distinct
 * joint points the segment between the farthest two; a body whose joints
 * coincide in hinges of different axes the arc between two axes at the
 * drawing scale about that point; a body whose joints coincide and that
 * slides on a prismatic joint a rod along its axis ending at the joint; any
 * other body a segment from its joint to its centre of mass, or a small
 * cube. *n receives the count (<= cap). POM_ERR_ARG when cap is too small or
 * a shape of the type is malformed (non-finite, unknown body or kind). */
pom_status pom_kin_body_shapes(const pom_kin_arch *arch, const pom_mechanism *mech,
                               pom_kin_shape *shape, int cap, int *n, pom_error *err);

#endif
