/* pom_json.c - the small JSON writers every report uses (pom_json.h). */
#include "pom_json.h"

#include <math.h>

void pom_json_string(FILE *out, const char *s) {
  fputc('"', out);
  for (const unsigned char *p = (const unsigned char *)s; *p; ++p) {
    if (*p == '"' || *p == '\\') {
      fprintf(out, "\\%c", *p);
    } else if (*p < 0x20) {
      fprintf(out, "\\u%04x", *p);
    } else {
      fputc(*p, out);
    }
  }
  fputc('"', out);
}

void pom_json_number(FILE *out, double v) {
  if (isfinite(v)) {
    fprintf(out, "%.17g", v);
  } else {
    fputs("null", out);
  }
}

void pom_json_vec(FILE *out, const double *v, int n, double scale) {
  fputc('[', out);
  for (int k = 0; k < n; ++k) {
    if (k) fputs(", ", out);
    pom_json_number(out, v[k] * scale);
  }
  fputc(']', out);
}

void pom_json_mat3(FILE *out, const double M[9], double scale) {
  fputc('[', out);
  for (int r = 0; r < 3; ++r) {
    if (r) fputs(", ", out);
    pom_json_vec(out, M + 3 * r, 3, scale);
  }
  fputc(']', out);
}
