/* pom_json.h - small JSON writers shared by the reports of every library
 * and the program: a string with escapes, a number (null when not finite),
 * arrays of numbers. */
#ifndef POM_JSON_H
#define POM_JSON_H

#include <stdio.h>

void pom_json_string(FILE *out, const char *s);
void pom_json_number(FILE *out, double v); /* %.17g, null when not finite */
void pom_json_vec(FILE *out, const double *v, int n, double scale);
void pom_json_mat3(FILE *out, const double M[9], double scale);

#endif
