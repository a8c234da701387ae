/* pom_expr.c - expressions of scalars and 3-vectors: a recursive-descent
 * compiler to a stack bytecode, and its evaluator (pom_expr.h). */
#include "pom_expr.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define EXPR_PI        3.14159265358979323846
#define EXPR_MAX_DEPTH 100 /* recursion: 2 per parenthesis, bracket or call, 1 per sign */

/* ---- opcodes ------------------------------------------------------------------ */
enum {
  OP_CONST = 1, /* arg: constant index -> s */
  OP_VAR_S,     /* arg: slot -> s */
  OP_VAR_V,     /* arg: slot -> v */
  OP_ADD_SS,
  OP_ADD_VV,
  OP_SUB_SS,
  OP_SUB_VV,
  OP_MUL_SS,
  OP_MUL_SV,
  OP_MUL_VS,
  OP_DIV_SS,
  OP_DIV_VS,
  OP_POW,
  OP_NEG_S,
  OP_NEG_V,
  OP_FN1,   /* arg: scalar function id */
  OP_ATAN2, /* s s -> s */
  OP_DOT,   /* v v -> s */
  OP_CROSS, /* v v -> v */
  OP_NORM,  /* v -> s */
  OP_UNIT,  /* v -> v */
  OP_SPH,   /* s s -> v */
  OP_POLAR, /* s s s -> v */
  OP_ROTZ,  /* s v -> v */
  OP_COMP   /* arg: 0, 1, 2; v -> s */
};

/* scalar functions of one scalar, in the order of their ids */
enum { F_SIN, F_COS, F_TAN, F_ASIN, F_ACOS, F_ATAN, F_SQRT, F_ABS, F_EXP, F_LOG, F_DEG, F_RAD };

typedef struct {
  const char *name;
  int op;                /* OP_FN1 or the opcode */
  int fn;                /* function id for OP_FN1 */
  int n_args;            /* 1..3 */
  pom_expr_kind args[3]; /* kinds of the arguments */
  pom_expr_kind result;
} func_desc;

#define S POM_EXPR_SCALAR
#define V POM_EXPR_VECTOR
static const func_desc funcs[] = {
    {.name = "sin", .op = OP_FN1, .fn = F_SIN, .n_args = 1, .args = {S}, .result = S},
    {.name = "cos", .op = OP_FN1, .fn = F_COS, .n_args = 1, .args = {S}, .result = S},
    {.name = "tan", .op = OP_FN1, .fn = F_TAN, .n_args = 1, .args = {S}, .result = S},
    {.name = "asin", .op = OP_FN1, .fn = F_ASIN, .n_args = 1, .args = {S}, .result = S},
    {.name = "acos", .op = OP_FN1, .fn = F_ACOS, .n_args = 1, .args = {S}, .result = S},
    {.name = "atan", .op = OP_FN1, .fn = F_ATAN, .n_args = 1, .args = {S}, .result = S},
    {.name = "sqrt", .op = OP_FN1, .fn = F_SQRT, .n_args = 1, .args = {S}, .result = S},
    {.name = "abs", .op = OP_FN1, .fn = F_ABS, .n_args = 1, .args = {S}, .result = S},
    {.name = "exp", .op = OP_FN1, .fn = F_EXP, .n_args = 1, .args = {S}, .result = S},
    {.name = "log", .op = OP_FN1, .fn = F_LOG, .n_args = 1, .args = {S}, .result = S},
    {.name = "deg", .op = OP_FN1, .fn = F_DEG, .n_args = 1, .args = {S}, .result = S},
    {.name = "rad", .op = OP_FN1, .fn = F_RAD, .n_args = 1, .args = {S}, .result = S},
    {.name = "atan2", .op = OP_ATAN2, .fn = 0, .n_args = 2, .args = {S, S}, .result = S},
    {.name = "dot", .op = OP_DOT, .fn = 0, .n_args = 2, .args = {V, V}, .result = S},
    {.name = "cross", .op = OP_CROSS, .fn = 0, .n_args = 2, .args = {V, V}, .result = V},
    {.name = "norm", .op = OP_NORM, .fn = 0, .n_args = 1, .args = {V}, .result = S},
    {.name = "unit", .op = OP_UNIT, .fn = 0, .n_args = 1, .args = {V}, .result = V},
    {.name = "sph", .op = OP_SPH, .fn = 0, .n_args = 2, .args = {S, S}, .result = V},
    {.name = "polar", .op = OP_POLAR, .fn = 0, .n_args = 3, .args = {S, S, S}, .result = V},
    {.name = "rotz", .op = OP_ROTZ, .fn = 0, .n_args = 2, .args = {S, V}, .result = V},
};
#undef S
#undef V
#define N_FUNCS ((int)(sizeof funcs / sizeof funcs[0]))

static const char *kind_word(pom_expr_kind k) {
  return k == POM_EXPR_VECTOR ? "a vector" : "a scalar";
}

/* ---- lexer -------------------------------------------------------------------- */
typedef enum { T_END, T_NUM, T_NAME, T_OP, T_BAD } tok_type;

typedef struct {
  const char *text;
  size_t pos;    /* next character to scan */
  tok_type type; /* current token */
  size_t start;  /* its first character */
  size_t len;    /* its length */
  double num;    /* T_NUM: its value */
  const pom_expr_var *vars;
  int n_vars;
  pom_expr *e;
  int depth; /* current stack depth (doubles) */
  int nest;  /* current recursion depth */
  pom_expr_error *perr;
  int failed;
} parser;

static int is_alpha(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
}
static int is_digit(char c) {
  return c >= '0' && c <= '9';
}

static pom_status fail(parser *p, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* Records the first error, at the current token. */
static pom_status fail(parser *p, const char *fmt, ...) {
  if (p->failed) return POM_ERR_CONFIG;
  p->failed = 1;
  if (!p->perr) return POM_ERR_CONFIG;
  char what[160];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(what, sizeof what, fmt, ap);
  va_end(ap);
  pom_expr_error *r = p->perr;
  r->column = (int)p->start + 1;
  size_t n = p->len < sizeof r->token - 1 ? p->len : sizeof r->token - 1;
  memcpy(r->token, p->text + p->start, n);
  r->token[n] = '\0';
  if (p->type == T_END)
    snprintf(r->message, sizeof r->message, "column %d: %s (at the end of the expression)",
             r->column, what);
  else
    snprintf(r->message, sizeof r->message, "column %d: %s (at '%s')", r->column, what, r->token);
  return POM_ERR_CONFIG;
}

/* Scans the next token. */
static pom_status next(parser *p) {
  const char *t = p->text;
  while (t[p->pos] == ' ' || t[p->pos] == '\t' || t[p->pos] == '\n' || t[p->pos] == '\r')
    ++p->pos;
  p->start = p->pos;
  char c = t[p->pos];
  if (c == '\0') {
    p->type = T_END;
    p->len = 0;
    return POM_OK;
  }
  if (is_digit(c) || (c == '.' && is_digit(t[p->pos + 1]))) {
    size_t k = p->pos;
    while (is_digit(t[k]))
      ++k;
    if (t[k] == '.') {
      ++k;
      while (is_digit(t[k]))
        ++k;
    }
    if (t[k] == 'e' || t[k] == 'E') {
      size_t m = k + 1;
      if (t[m] == '+' || t[m] == '-') ++m;
      if (is_digit(t[m])) {
        while (is_digit(t[m]))
          ++m;
        k = m;
      }
    }
    p->type = T_NUM;
    p->len = k - p->pos;
    p->pos = k;
    char buf[64];
    if (p->len >= sizeof buf) return fail(p, "number too long");
    memcpy(buf, t + p->start, p->len);
    buf[p->len] = '\0';
    p->num = strtod(buf, NULL);
    if (!isfinite(p->num)) return fail(p, "number out of range");
    if (is_alpha(t[p->pos])) {
      p->len += 1;
      return fail(p, "a number followed by a letter (write 2*x, not 2x)");
    }
    return POM_OK;
  }
  if (is_alpha(c)) {
    size_t k = p->pos;
    while (is_alpha(t[k]) || is_digit(t[k]))
      ++k;
    p->type = T_NAME;
    p->len = k - p->pos;
    p->pos = k;
    return POM_OK;
  }
  if (strchr("+-*/^()[],.", c)) {
    p->type = T_OP;
    p->len = 1;
    ++p->pos;
    return POM_OK;
  }
  p->type = T_BAD;
  p->len = 1;
  ++p->pos;
  return fail(p, "unexpected character");
}

static int at_op(const parser *p, char c) {
  return p->type == T_OP && p->text[p->start] == c;
}

static int name_is(const parser *p, const char *name) {
  return p->type == T_NAME && strlen(name) == p->len &&
         memcmp(p->text + p->start, name, p->len) == 0;
}

/* ---- emitter ------------------------------------------------------------------ */
/* Appends an instruction that pops `pop` doubles and pushes `push`. */
static pom_status emit(parser *p, int op, int arg, int pop, int push) {
  pom_expr *e = p->e;
  if (e->n_ops >= POM_EXPR_MAX_OPS)
    return fail(p, "expression too long (more than %d operations)", POM_EXPR_MAX_OPS);
  e->op[e->n_ops] = (unsigned short)op;
  e->arg[e->n_ops] = (unsigned short)arg;
  ++e->n_ops;
  p->depth += push - pop;
  if (p->depth > POM_EXPR_MAX_STACK)
    return fail(p, "expression too deep (more than %d values pending)", POM_EXPR_MAX_STACK);
  if (p->depth > e->max_stack) e->max_stack = p->depth;
  return POM_OK;
}

static pom_status parse_expr(parser *p, pom_expr_kind *kind);

static pom_status enter(parser *p) {
  if (++p->nest > EXPR_MAX_DEPTH) return fail(p, "nested more than %d levels deep", EXPR_MAX_DEPTH);
  return POM_OK;
}

/* A call name ( args ): the current token is the name. */
static pom_status parse_call(parser *p, const func_desc *f, pom_expr_kind *kind) {
  POM_TRY(next(p));
  if (!at_op(p, '(')) return fail(p, "expected '(' after the function %s", f->name);
  POM_TRY(next(p));
  for (int a = 0; a < f->n_args; ++a) {
    if (a) {
      if (!at_op(p, ',')) return fail(p, "%s takes %d arguments: expected ','", f->name, f->n_args);
      POM_TRY(next(p));
    }
    size_t arg_start = p->start, arg_len;
    pom_expr_kind k;
    POM_TRY(parse_expr(p, &k));
    if (k != f->args[a]) {
      /* point at the argument */
      arg_len = p->start > arg_start ? p->start - arg_start : 0;
      while (arg_len > 0 && p->text[arg_start + arg_len - 1] == ' ')
        --arg_len;
      p->start = arg_start;
      p->len = arg_len;
      p->type = T_NAME;
      return fail(p, "argument %d of %s must be %s, not %s", a + 1, f->name, kind_word(f->args[a]),
                  kind_word(k));
    }
  }
  if (at_op(p, ','))
    return fail(p, "%s takes %d argument%s", f->name, f->n_args, f->n_args > 1 ? "s" : "");
  if (!at_op(p, ')')) return fail(p, "expected ')' to close %s(", f->name);
  int pop = 0;
  for (int a = 0; a < f->n_args; ++a)
    pop += (int)f->args[a];
  POM_TRY(emit(p, f->op, f->fn, pop, (int)f->result));
  *kind = f->result;
  return next(p);
}

static pom_status parse_primary(parser *p, pom_expr_kind *kind) {
  POM_TRY(enter(p));
  if (p->type == T_NUM) {
    pom_expr *e = p->e;
    if (e->n_consts >= POM_EXPR_MAX_CONSTS)
      return fail(p, "more than %d numbers in one expression", POM_EXPR_MAX_CONSTS);
    e->cst[e->n_consts] = p->num;
    POM_TRY(emit(p, OP_CONST, e->n_consts++, 0, 1));
    *kind = POM_EXPR_SCALAR;
    POM_TRY(next(p));
  } else if (p->type == T_NAME) {
    if (name_is(p, "pi")) {
      pom_expr *e = p->e;
      if (e->n_consts >= POM_EXPR_MAX_CONSTS)
        return fail(p, "more than %d numbers in one expression", POM_EXPR_MAX_CONSTS);
      e->cst[e->n_consts] = EXPR_PI;
      POM_TRY(emit(p, OP_CONST, e->n_consts++, 0, 1));
      *kind = POM_EXPR_SCALAR;
      POM_TRY(next(p));
    } else {
      const func_desc *f = NULL;
      for (int k = 0; k < N_FUNCS && !f; ++k)
        if (name_is(p, funcs[k].name)) f = &funcs[k];
      if (f) {
        POM_TRY(parse_call(p, f, kind));
      } else {
        const pom_expr_var *v = NULL;
        for (int k = 0; k < p->n_vars && !v; ++k)
          if (name_is(p, p->vars[k].name)) v = &p->vars[k];
        if (!v) return fail(p, "unknown name");
        POM_TRY(
            emit(p, v->kind == POM_EXPR_VECTOR ? OP_VAR_V : OP_VAR_S, v->slot, 0, (int)v->kind));
        *kind = v->kind;
        POM_TRY(next(p));
        if (at_op(p, '(')) return fail(p, "%s is a variable, not a function", v->name);
      }
    }
  } else if (at_op(p, '(')) {
    POM_TRY(next(p));
    POM_TRY(parse_expr(p, kind));
    if (!at_op(p, ')')) return fail(p, "expected ')'");
    POM_TRY(next(p));
  } else if (at_op(p, '[')) {
    POM_TRY(next(p));
    for (int c = 0; c < 3; ++c) {
      if (c) {
        if (at_op(p, ']')) return fail(p, "a vector has 3 components, this one %d", c);
        if (!at_op(p, ',')) return fail(p, "expected ',' between the components of a vector");
        POM_TRY(next(p));
      }
      size_t at = p->start;
      pom_expr_kind k;
      POM_TRY(parse_expr(p, &k));
      if (k != POM_EXPR_SCALAR) {
        p->start = at;
        p->len = 1;
        return fail(p, "component %d of a vector must be a scalar", c + 1);
      }
    }
    if (at_op(p, ',')) return fail(p, "a vector has 3 components, not more");
    if (!at_op(p, ']')) return fail(p, "expected ']' to close the vector");
    *kind = POM_EXPR_VECTOR; /* three scalars on the stack are the vector */
    POM_TRY(next(p));
  } else if (p->type == T_END) {
    return fail(p, "expected a value");
  } else {
    return fail(p, "expected a value");
  }
  /* components */
  while (at_op(p, '.')) {
    POM_TRY(next(p));
    if (*kind != POM_EXPR_VECTOR) return fail(p, "a component (.x, .y, .z) of a scalar");
    int c = name_is(p, "x") ? 0 : name_is(p, "y") ? 1 : name_is(p, "z") ? 2 : -1;
    if (c < 0) return fail(p, "expected x, y or z after '.'");
    POM_TRY(emit(p, OP_COMP, c, 3, 1));
    *kind = POM_EXPR_SCALAR;
    POM_TRY(next(p));
  }
  --p->nest;
  return POM_OK;
}

/* power := primary ('^' unary)? */
static pom_status parse_unary(parser *p, pom_expr_kind *kind);

static pom_status parse_power(parser *p, pom_expr_kind *kind) {
  POM_TRY(parse_primary(p, kind));
  if (at_op(p, '^')) {
    if (*kind != POM_EXPR_SCALAR) return fail(p, "a vector cannot be raised to a power");
    POM_TRY(next(p));
    pom_expr_kind k;
    size_t at = p->start;
    POM_TRY(parse_unary(p, &k));
    if (k != POM_EXPR_SCALAR) {
      p->start = at;
      p->len = 1;
      return fail(p, "an exponent must be a scalar");
    }
    POM_TRY(emit(p, OP_POW, 0, 2, 1));
  }
  return POM_OK;
}

static pom_status parse_unary(parser *p, pom_expr_kind *kind) {
  POM_TRY(enter(p));
  if (at_op(p, '-') || at_op(p, '+')) {
    int neg = at_op(p, '-');
    POM_TRY(next(p));
    POM_TRY(parse_unary(p, kind));
    if (neg)
      POM_TRY(emit(p, *kind == POM_EXPR_VECTOR ? OP_NEG_V : OP_NEG_S, 0, (int)*kind, (int)*kind));
  } else {
    POM_TRY(parse_power(p, kind));
  }
  --p->nest;
  return POM_OK;
}

static pom_status parse_term(parser *p, pom_expr_kind *kind) {
  POM_TRY(parse_unary(p, kind));
  while (at_op(p, '*') || at_op(p, '/')) {
    int mul = at_op(p, '*');
    size_t op_start = p->start;
    POM_TRY(next(p));
    pom_expr_kind r;
    POM_TRY(parse_unary(p, &r));
    pom_expr_kind l = *kind;
    int op;
    if (mul) {
      if (l == POM_EXPR_VECTOR && r == POM_EXPR_VECTOR) {
        p->start = op_start;
        p->len = 1;
        p->type = T_OP;
        return fail(p, "vector * vector: write dot(a, b) or cross(a, b)");
      }
      op = l == POM_EXPR_SCALAR ? (r == POM_EXPR_SCALAR ? OP_MUL_SS : OP_MUL_SV) : OP_MUL_VS;
    } else {
      if (r == POM_EXPR_VECTOR) {
        p->start = op_start;
        p->len = 1;
        p->type = T_OP;
        return fail(p, "division by a vector");
      }
      op = l == POM_EXPR_SCALAR ? OP_DIV_SS : OP_DIV_VS;
    }
    *kind = (l == POM_EXPR_VECTOR || r == POM_EXPR_VECTOR) ? POM_EXPR_VECTOR : POM_EXPR_SCALAR;
    POM_TRY(emit(p, op, 0, (int)l + (int)r, (int)*kind));
  }
  return POM_OK;
}

static pom_status parse_expr(parser *p, pom_expr_kind *kind) {
  POM_TRY(parse_term(p, kind));
  while (at_op(p, '+') || at_op(p, '-')) {
    int add = at_op(p, '+');
    size_t op_start = p->start;
    POM_TRY(next(p));
    pom_expr_kind r;
    POM_TRY(parse_term(p, &r));
    if (r != *kind) {
      p->start = op_start;
      p->len = 1;
      p->type = T_OP;
      return fail(p, "%s %s %s", kind_word(*kind), add ? "plus" : "minus", kind_word(r));
    }
    int op =
        *kind == POM_EXPR_VECTOR ? (add ? OP_ADD_VV : OP_SUB_VV) : (add ? OP_ADD_SS : OP_SUB_SS);
    POM_TRY(emit(p, op, 0, 2 * (int)r, (int)r));
  }
  return POM_OK;
}

/* ---- public ------------------------------------------------------------------- */
int pom_expr_reserved(const char *name) {
  if (!name) return 0;
  if (strcmp(name, "pi") == 0) return 1;
  for (int k = 0; k < N_FUNCS; ++k)
    if (strcmp(name, funcs[k].name) == 0) return 1;
  return 0;
}

int pom_expr_identifier(const char *name) {
  if (!name || !is_alpha(name[0])) return 0;
  for (const char *c = name + 1; *c; ++c)
    if (!is_alpha(*c) && !is_digit(*c)) return 0;
  return 1;
}

pom_status pom_expr_compile(pom_expr *e, const char *text, const pom_expr_var *vars, int n_vars,
                            pom_expr_error *perr) {
  parser p;
  memset(e, 0, sizeof *e);
  memset(&p, 0, sizeof p);
  if (perr) memset(perr, 0, sizeof *perr);
  p.text = text ? text : "";
  p.vars = vars;
  p.n_vars = n_vars;
  p.e = e;
  p.perr = perr;
  if (strlen(p.text) > POM_EXPR_MAX_TEXT)
    return fail(&p, "longer than %d characters", POM_EXPR_MAX_TEXT);
  pom_expr_kind kind;
  pom_status st = next(&p);
  if (st == POM_OK) st = parse_expr(&p, &kind);
  if (st == POM_OK && p.type != T_END) {
    if (at_op(&p, ')') || at_op(&p, ']'))
      st = fail(&p, "unmatched '%c'", p.text[p.start]);
    else
      st = fail(&p, "expected an operator or the end");
  }
  if (st != POM_OK) {
    memset(e, 0, sizeof *e);
    return POM_ERR_CONFIG;
  }
  e->kind = kind;
  return POM_OK;
}

static double fn1(int id, double x) {
  switch (id) {
  case F_SIN:
    return sin(x);
  case F_COS:
    return cos(x);
  case F_TAN:
    return tan(x);
  case F_ASIN:
    return asin(x);
  case F_ACOS:
    return acos(x);
  case F_ATAN:
    return atan(x);
  case F_SQRT:
    return sqrt(x);
  case F_ABS:
    return fabs(x);
  case F_EXP:
    return exp(x);
  case F_LOG:
    return log(x);
  case F_DEG:
    return x * (EXPR_PI / 180.0);
  case F_RAD:
    return x * (180.0 / EXPR_PI);
  default:
    return NAN;
  }
}

pom_status pom_expr_eval(const pom_expr *e, const double *slots, double out[3]) {
  double st[POM_EXPR_MAX_STACK + 3];
  int sp = 0; /* next free */
  for (int k = 0; k < e->n_ops; ++k) {
    int a = e->arg[k];
    double *t = st + sp;
    switch (e->op[k]) {
    case OP_CONST:
      t[0] = e->cst[a];
      sp += 1;
      break;
    case OP_VAR_S:
      t[0] = slots[a];
      sp += 1;
      break;
    case OP_VAR_V:
      t[0] = slots[a];
      t[1] = slots[a + 1];
      t[2] = slots[a + 2];
      sp += 3;
      break;
    case OP_ADD_SS:
      t[-2] += t[-1];
      sp -= 1;
      break;
    case OP_SUB_SS:
      t[-2] -= t[-1];
      sp -= 1;
      break;
    case OP_MUL_SS:
      t[-2] *= t[-1];
      sp -= 1;
      break;
    case OP_DIV_SS:
      t[-2] /= t[-1];
      sp -= 1;
      break;
    case OP_POW:
      t[-2] = pow(t[-2], t[-1]);
      sp -= 1;
      break;
    case OP_ADD_VV:
      for (int c = 0; c < 3; ++c)
        t[-6 + c] += t[-3 + c];
      sp -= 3;
      break;
    case OP_SUB_VV:
      for (int c = 0; c < 3; ++c)
        t[-6 + c] -= t[-3 + c];
      sp -= 3;
      break;
    case OP_MUL_SV: { /* s v */
      double s = t[-4];
      for (int c = 0; c < 3; ++c)
        t[-4 + c] = s * t[-3 + c];
      sp -= 1;
    } break;
    case OP_MUL_VS:
      for (int c = 0; c < 3; ++c)
        t[-4 + c] *= t[-1];
      sp -= 1;
      break;
    case OP_DIV_VS:
      for (int c = 0; c < 3; ++c)
        t[-4 + c] /= t[-1];
      sp -= 1;
      break;
    case OP_NEG_S:
      t[-1] = -t[-1];
      break;
    case OP_NEG_V:
      for (int c = 1; c <= 3; ++c)
        t[-c] = -t[-c];
      break;
    case OP_FN1:
      t[-1] = fn1(a, t[-1]);
      break;
    case OP_ATAN2:
      t[-2] = atan2(t[-2], t[-1]);
      sp -= 1;
      break;
    case OP_DOT:
      t[-6] = t[-6] * t[-3] + t[-5] * t[-2] + t[-4] * t[-1];
      sp -= 5;
      break;
    case OP_CROSS: {
      double x = t[-5] * t[-1] - t[-4] * t[-2];
      double y = t[-4] * t[-3] - t[-6] * t[-1];
      double z = t[-6] * t[-2] - t[-5] * t[-3];
      t[-6] = x;
      t[-5] = y;
      t[-4] = z;
      sp -= 3;
    } break;
    case OP_NORM:
      t[-3] = sqrt(t[-3] * t[-3] + t[-2] * t[-2] + t[-1] * t[-1]);
      sp -= 2;
      break;
    case OP_UNIT: {
      double n = sqrt(t[-3] * t[-3] + t[-2] * t[-2] + t[-1] * t[-1]);
      for (int c = 1; c <= 3; ++c)
        t[-c] /= n;
    } break;
    case OP_SPH: { /* eta gamma */
      double eta = t[-2], g = t[-1];
      t[-2] = sin(eta) * sin(g);
      t[-1] = -cos(eta) * sin(g);
      t[0] = cos(g);
      sp += 1;
    } break;
    case OP_POLAR: { /* r eta z */
      double r = t[-3], eta = t[-2];
      t[-3] = r * cos(eta);
      t[-2] = r * sin(eta);
      break;
    }
    case OP_ROTZ: { /* angle v */
      double c = cos(t[-4]), s = sin(t[-4]), x = t[-3], y = t[-2], z = t[-1];
      t[-4] = c * x - s * y;
      t[-3] = s * x + c * y;
      t[-2] = z;
      sp -= 1;
    } break;
    case OP_COMP:
      t[-3] = t[-3 + a];
      sp -= 2;
      break;
    default:
      return POM_ERR_INTERNAL;
    }
  }
  int n = (int)e->kind;
  if (n != sp || (n != 1 && n != 3)) return POM_ERR_INTERNAL;
  for (int c = 0; c < n; ++c) {
    out[c] = st[c];
    if (!isfinite(out[c])) return POM_ERR_NONFINITE;
  }
  return POM_OK;
}
