/* pom_expr.h - scalar and 3-vector expressions of named variables, compiled
 * once to a small stack bytecode and evaluated many times without
 * allocation (the joint points and axes of an architecture file,
 * docs/architecture-files.md section 3).
 *
 * Syntax: numbers (1, 2.5, 1e-3), `pi`, names, + - * / ^ (right
 * associative, binds tighter than unary minus: -2^2 = -4), parentheses,
 * vectors [a, b, c], a vector's component v.x, v.y, v.z, and the functions
 *   scalar -> scalar: sin cos tan asin acos atan sqrt abs exp log
 *                     deg(x) = x degrees in rad (x pi/180),
 *                     rad(x) = x rad in degrees (x 180/pi)
 *   atan2(y, x)
 *   dot(a, b), norm(a) -> scalar;  cross(a, b), unit(a) -> vector
 *   sph(eta, gamma) = [sin eta sin gamma, -cos eta sin gamma, cos gamma]
 *                     (= Rz(eta) Rx(gamma) e_z: the unit vector at angle
 *                     gamma from +z, its horizontal part at azimuth
 *                     eta - 90 deg from +x)
 *   polar(r, eta, z) = [r cos eta, r sin eta, z]
 *   rotz(angle, v)   = Rz(angle) v (right-handed about +z)
 * Types are checked when compiling: scalar * vector and vector / scalar
 * are allowed, vector * vector is not (dot or cross say which product).
 * Every error names the column (1-based) and the offending token. */
#ifndef POM_EXPR_H
#define POM_EXPR_H

#include "pom_status.h"

#include <stddef.h>

#define POM_EXPR_MAX_OPS    192 /* bytecode instructions of one expression */
#define POM_EXPR_MAX_CONSTS 64  /* numeric literals of one expression */
#define POM_EXPR_MAX_STACK  96  /* doubles on the evaluation stack (a vector takes 3) */
#define POM_EXPR_MAX_TEXT   1024

/* What a value is: a scalar or a 3-vector (the number of doubles). */
typedef enum { POM_EXPR_SCALAR = 1, POM_EXPR_VECTOR = 3 } pom_expr_kind;

/* One variable an expression may name: its name, its kind and where its
 * value sits in the slots array given to pom_expr_eval (slot .. slot + kind
 * - 1). */
typedef struct {
  const char *name;
  pom_expr_kind kind;
  int slot;
} pom_expr_var;

/* A compiled expression (plain data, copyable; no pointers into the text or
 * the variable table). */
typedef struct {
  pom_expr_kind kind; /* kind of the result */
  int n_ops;
  int n_consts;
  int max_stack;                        /* doubles the evaluation needs */
  unsigned short op[POM_EXPR_MAX_OPS];  /* [n_ops] opcode << 8 | small operand */
  unsigned short arg[POM_EXPR_MAX_OPS]; /* [n_ops] slot or constant index */
  double cst[POM_EXPR_MAX_CONSTS];      /* [n_consts] */
} pom_expr;

/* Where compiling failed. */
typedef struct {
  int column;        /* 1-based column of the offending token */
  char token[48];    /* the token as written ("" at the end of the text) */
  char message[256]; /* what is wrong, naming the column and the token */
} pom_expr_error;

/* Compiles text over the n_vars variables vars (names looked up in this
 * table only; `pi` and the function names are reserved). POM_ERR_CONFIG
 * with *perr filled (perr may be NULL) on a syntax or type error, a name
 * not in vars, or an expression too large for the fixed tables. */
pom_status pom_expr_compile(pom_expr *e, const char *text, const pom_expr_var *vars, int n_vars,
                            pom_expr_error *perr);

/* Evaluates e with the variable values in slots (as laid out by the
 * pom_expr_var table it was compiled with) into out (e->kind doubles).
 * Returns POM_OK, or POM_ERR_NONFINITE when the result is not finite (a
 * square root of a negative number, acos beyond 1, a division by zero...).
 * Never allocates. */
pom_status pom_expr_eval(const pom_expr *e, const double *slots, double out[3]);

/* 1 when name is reserved (pi or a function name): not usable as a
 * variable. */
int pom_expr_reserved(const char *name);

/* 1 when name is an identifier the compiler reads as one name: a letter or
 * '_' then letters, digits or '_'. */
int pom_expr_identifier(const char *name);

#endif
