/* test_expr.c - pom_expr: values against the same formulas written in C
 * (high-entropy inputs; equal to the last bit or within a few ulps where
 * the evaluation order differs), precedence and associativity, the
 * vector functions and their conventions, and every kind of bad input:
 * the column and token each error names. */
#include "check.h"
#include "pom_expr.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static const pom_expr_var vars[] = {
    {.name = "x", .kind = POM_EXPR_SCALAR, .slot = 0},
    {.name = "y", .kind = POM_EXPR_SCALAR, .slot = 1},
    {.name = "v", .kind = POM_EXPR_VECTOR, .slot = 2},
    {.name = "w", .kind = POM_EXPR_VECTOR, .slot = 5},
    {.name = "eta_1", .kind = POM_EXPR_SCALAR, .slot = 8},
};
static const double slots[9] = {0.7137, -1.2391, 0.31, -0.547, 0.8123, -2.05, 0.119, 1.337, 2.385};
#define NV ((int)(sizeof vars / sizeof vars[0]))

/* Compiles and evaluates text; returns its kind (0 on a compile error). */
static int eval(const char *text, double out[3]) {
  pom_expr e;
  pom_expr_error er;
  if (pom_expr_compile(&e, text, vars, NV, &er) != POM_OK) {
    printf("unexpected compile error in \"%s\": %s\n", text, er.message);
    return 0;
  }
  if (pom_expr_eval(&e, slots, out) != POM_OK) {
    printf("unexpected evaluation error in \"%s\"\n", text);
    return 0;
  }
  return (int)e.kind;
}

static void scalar(const char *text, double want, double tol_rel) {
  double out[3] = {NAN, NAN, NAN};
  int k = eval(text, out);
  check_true(k == 1);
  if (tol_rel == 0.0) {
    if (!check_true(out[0] == want)) printf("  %s = %.17g, want %.17g\n", text, out[0], want);
  } else {
    check_rel(out[0], want, tol_rel);
  }
}

static void vector(const char *text, const double want[3], double tol_abs) {
  double out[3] = {NAN, NAN, NAN};
  int k = eval(text, out);
  check_true(k == 3);
  for (int c = 0; c < 3; ++c)
    if (!check_abs(out[c], want[c], tol_abs)) printf("  in %s, component %d\n", text, c);
}

/* Expects a compile error at column col naming token tok (NULL: do not
 * check the token) with msg in the message. */
static void bad(const char *text, int col, const char *tok, const char *msg) {
  pom_expr e;
  pom_expr_error er;
  pom_status st = pom_expr_compile(&e, text, vars, NV, &er);
  check_true(st == POM_ERR_CONFIG);
  if (!check_true(er.column == col)) printf("  \"%s\": column %d, want %d\n", text, er.column, col);
  if (tok && !check_true(strcmp(er.token, tok) == 0))
    printf("  \"%s\": token '%s', want '%s'\n", text, er.token, tok);
  if (!check_true(strstr(er.message, msg) != NULL))
    printf("  \"%s\": message \"%s\" lacks \"%s\"\n", text, er.message, msg);
  check_true(e.n_ops == 0); /* nothing half-compiled is left */
}

int main(void) {
  const double x = slots[0], y = slots[1], *v = slots + 2, *w = slots + 5, eta = slots[8];
  const double pi = 3.14159265358979323846;

  /* ---- scalars: same operations in the same order as C: exact ---- */
  scalar("x + y * 2.5", x + y * 2.5, 0.0);
  scalar("(x + y) * 2.5", (x + y) * 2.5, 0.0);
  scalar("x - y - 1", (x - y) - 1.0, 0.0);
  scalar("x / y / 3", (x / y) / 3.0, 0.0);
  scalar("-x^2", -pow(x, 2.0), 0.0);             /* ^ binds tighter than unary minus */
  scalar("2^3^2", pow(2.0, pow(3.0, 2.0)), 0.0); /* right associative: 512 */
  scalar("2^-1", 0.5, 0.0);
  scalar("- - x", x, 0.0);
  scalar("+x", x, 0.0);
  scalar("1.5e-3 * x", 1.5e-3 * x, 0.0);
  scalar(".25 + 3.", 3.25, 0.0);
  scalar("pi", pi, 0.0);
  scalar("sin(x) + cos(y) * tan(x)", sin(x) + cos(y) * tan(x), 0.0);
  scalar("asin(x) - acos(x) + atan(y)", asin(x) - acos(x) + atan(y), 0.0);
  scalar("atan2(y, x)", atan2(y, x), 0.0);
  scalar("sqrt(abs(y)) + exp(x) - log(x)", sqrt(fabs(y)) + exp(x) - log(x), 0.0);
  scalar("deg(120)", 120.0 * (pi / 180.0), 0.0);
  scalar("rad(x)", x * (180.0 / pi), 0.0);
  scalar("eta_1 + 2*pi/3", eta + 2.0 * pi / 3.0, 0.0);
  scalar("v.x + v.y*w.z", v[0] + v[1] * w[2], 0.0);
  scalar("dot(v, w)", v[0] * w[0] + v[1] * w[1] + v[2] * w[2], 0.0);
  scalar("norm(v)", sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]), 0.0);
  scalar("[1, 2, 3].z", 3.0, 0.0);

  /* ---- vectors ---- */
  {
    double want[3];
    for (int c = 0; c < 3; ++c)
      want[c] = v[c] + 2.0 * w[c] - v[c] / 4.0;
    vector("v + 2*w - v/4", want, 1e-15);
    for (int c = 0; c < 3; ++c)
      want[c] = -(v[c] * x);
    vector("-(v*x)", want, 0.0);
    double cr[3] = {v[1] * w[2] - v[2] * w[1], v[2] * w[0] - v[0] * w[2],
                    v[0] * w[1] - v[1] * w[0]};
    vector("cross(v, w)", cr, 1e-15);
    /* cross is orthogonal to both, and e_x x e_y = e_z */
    scalar("dot(cross(v, w), v) + 1", 1.0, 1e-15);
    vector("cross([1,0,0], [0,1,0])", (double[3]){0, 0, 1}, 0.0);
    double n = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    vector("unit(w)", (double[3]){w[0] / n, w[1] / n, w[2] / n}, 1e-16);
    scalar("norm(unit(w))", 1.0, 2e-16);
    vector("[x, y, x*y]", (double[3]){x, y, x * y}, 0.0);
    /* sph(eta, gamma) = Rz(eta) Rx(gamma) e_z = [sin eta sin g, -cos eta sin g, cos g] */
    vector("sph(x, y)", (double[3]){sin(x) * sin(y), -cos(x) * sin(y), cos(y)}, 0.0);
    vector("sph(0, pi/2)", (double[3]){0.0, -1.0, cos(pi / 2.0)}, 1e-16);
    vector("sph(pi/2, pi/2)", (double[3]){1.0, 0.0, 0.0}, 1e-16);
    vector("polar(x, y, 0.25)", (double[3]){x * cos(y), x * sin(y), 0.25}, 0.0);
    /* rotz is right-handed: e_x -> e_y at +90 deg */
    vector("rotz(deg(90), [1, 0, 0])", (double[3]){0.0, 1.0, 0.0}, 1e-16);
    vector("rotz(y, v)",
           (double[3]){cos(y) * v[0] - sin(y) * v[1], sin(y) * v[0] + cos(y) * v[1], v[2]}, 0.0);
    /* a deep but legal expression: 30 nested parentheses */
    char deep[256] = "";
    for (int k = 0; k < 30; ++k)
      strcat(deep, "(");
    strcat(deep, "x");
    for (int k = 0; k < 30; ++k)
      strcat(deep, ")");
    scalar(deep, x, 0.0);
  }

  /* ---- the stack need is what compile says, and eval does not exceed it ---- */
  {
    pom_expr e;
    check_true(pom_expr_compile(&e, "cross(v, w) + [x, y, 1]*2", vars, NV, NULL) == POM_OK);
    check_true(e.max_stack == 7); /* v w (6) -> v, then 3 + 1 */
  }

  /* ---- bad input: column and token ---- */
  bad("x + * 2", 5, "*", "expected a value");
  bad("sin(x", 6, "", "expected ')' to close sin(");
  bad("foo + 1", 1, "foo", "unknown name");
  bad("x + etaa", 5, "etaa", "unknown name");
  bad("[1, 2]", 6, "]", "a vector has 3 components");
  bad("[1, 2, 3, 4]", 9, ",", "not more");
  bad("v * w", 3, "*", "vector * vector");
  bad("x / v", 3, "/", "division by a vector");
  bad("x + v", 3, "+", "a scalar plus a vector");
  bad("v - 1", 3, "-", "a vector minus a scalar");
  bad("2x", 1, "2x", "a number followed by a letter");
  bad("1e999", 1, "1e999", "number out of range");
  bad("dot(v, 1)", 8, "1", "argument 2 of dot must be a vector");
  bad("sph(v, 1)", 5, "v", "argument 1 of sph must be a scalar");
  bad("atan2(x)", 8, ")", "atan2 takes 2 arguments");
  bad("sin(x, y)", 6, ",", "sin takes 1 argument");
  bad("(x + 1", 7, "", "expected ')'");
  bad("x + 1)", 6, ")", "unmatched ')'");
  bad("x y", 3, "y", "expected an operator or the end");
  bad("x $ 1", 3, "$", "unexpected character");
  bad("", 1, "", "expected a value");
  bad("x.x", 3, "x", "a component (.x, .y, .z) of a scalar");
  bad("v.q", 3, "q", "expected x, y or z");
  bad("v^2", 2, "^", "a vector cannot be raised");
  bad("x^v", 3, "v", "an exponent must be a scalar");
  bad("x(1)", 2, "(", "x is a variable, not a function");
  bad("sin + 1", 5, "+", "expected '(' after the function sin");
  bad("[v, 1, 2]", 2, "v", "component 1 of a vector must be a scalar");
  {
    char deep[256] = "";
    for (int k = 0; k < 60; ++k)
      strcat(deep, "(");
    strcat(deep, "x");
    for (int k = 0; k < 60; ++k)
      strcat(deep, ")");
    pom_expr e;
    pom_expr_error er;
    check_true(pom_expr_compile(&e, deep, vars, NV, &er) == POM_ERR_CONFIG);
    check_true(strstr(er.message, "nested more than") != NULL);
    /* too many operations */
    char longx[1024] = "x";
    for (int k = 0; k < 200; ++k)
      strcat(longx, "+x");
    check_true(pom_expr_compile(&e, longx, vars, NV, &er) == POM_ERR_CONFIG);
    check_true(strstr(er.message, "expression too long") != NULL);
    /* a NULL error record is allowed */
    check_true(pom_expr_compile(&e, "x +", vars, NV, NULL) == POM_ERR_CONFIG);
  }

  /* ---- evaluation: a non-finite result is a status ---- */
  {
    pom_expr e;
    double out[3];
    check_true(pom_expr_compile(&e, "sqrt(y)", vars, NV, NULL) == POM_OK);
    check_true(pom_expr_eval(&e, slots, out) == POM_ERR_NONFINITE);
    check_true(pom_expr_compile(&e, "v / (x - x)", vars, NV, NULL) == POM_OK);
    check_true(pom_expr_eval(&e, slots, out) == POM_ERR_NONFINITE);
    check_true(pom_expr_compile(&e, "unit([0, 0, 0])", vars, NV, NULL) == POM_OK);
    check_true(pom_expr_eval(&e, slots, out) == POM_ERR_NONFINITE);
  }

  /* ---- names ---- */
  check_true(pom_expr_reserved("pi") && pom_expr_reserved("sph") && pom_expr_reserved("rotz"));
  check_true(!pom_expr_reserved("eta") && !pom_expr_reserved(NULL));
  check_true(pom_expr_identifier("limb_1") && pom_expr_identifier("_a"));
  check_true(!pom_expr_identifier("1a") && !pom_expr_identifier("a-b") && !pom_expr_identifier(""));
  return check_summary("test_expr");
}
