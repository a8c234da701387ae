/* test_optimize.c - experimental designs, quadratic response surfaces,
 * desirability and the NLopt driver. */
#include "check.h"
#include "pom_design.h"
#include "pom_desirability.h"
#include "pom_nlopt.h"
#include "pom_rng.h"
#include "pom_rsm.h"

#include <nlopt.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- designs ------------------------------------------------------------ */
static pom_design *make(pom_design_kind kind, int k, int centre, int reps) {
  pom_design_options o;
  pom_design_defaults(&o);
  o.kind = kind;
  o.center_points = centre;
  o.replicates = reps;
  pom_design *d = NULL;
  pom_error err;
  pom_error_clear(&err);
  (void)pom_design_create(&d, k, &o, &err); /* NULL on failure, checked by callers */
  return d;
}

/* Unscaled prediction variance x^T (X^T X)^-1 x of the quadratic model of a
 * design at coded point u, through a fit to an arbitrary response. */
static double pred_var(const pom_rsm_fit *fit, const double u[]) {
  double row[POM_RSM_MAX_TERMS];
  pom_rsm_row_terms(fit->k, u, row);
  double s = 0.0;
  for (int a = 0; a < fit->p; ++a)
    for (int b = 0; b < fit->p; ++b)
      s += row[a] * fit->cov_unscaled[a * fit->p + b] * row[b];
  return s;
}

/* Largest relative spread of the prediction variance over random points on
 * the sphere |u| = radius. */
static double variance_spread_on_sphere(const pom_design *d, double radius) {
  double *y = malloc(sizeof(double) * (size_t)d->n);
  pom_rng rng;
  pom_rng_seed(&rng, 77, 1);
  for (int r = 0; r < d->n; ++r)
    y[r] = pom_rng_normal(&rng);
  pom_rsm_fit fit;
  pom_error err;
  check_true(pom_rsm_fit_quadratic(&fit, d->k, d->n, d->coded, y, NULL, &err) == POM_OK);
  double vmin = 1e300, vmax = 0.0;
  for (int t = 0; t < 50; ++t) {
    double u[POM_RSM_MAX_K], n2 = 0.0;
    for (int j = 0; j < d->k; ++j) {
      u[j] = pom_rng_normal(&rng);
      n2 += u[j] * u[j];
    }
    for (int j = 0; j < d->k; ++j)
      u[j] *= radius / sqrt(n2);
    double v = pred_var(&fit, u);
    vmin = fmin(vmin, v);
    vmax = fmax(vmax, v);
  }
  free(y);
  return (vmax - vmin) / vmax;
}

static void test_designs(void) {
  /* Full factorial 3^3 + 2 centre runs, replicated twice: 2 * 27 + 2. */
  pom_design_options o;
  pom_design_defaults(&o);
  o.kind = POM_DESIGN_FULL_FACTORIAL;
  o.levels = 3;
  o.center_points = 2;
  o.replicates = 2;
  pom_design *d = NULL;
  pom_error err;
  check_true(pom_design_create(&d, 3, &o, &err) == POM_OK);
  check_true(d->n == 56);
  /* every level combination exactly twice in the replicated part */
  int count[27] = {0};
  for (int r = 0; r < 54; ++r) {
    int idx = 0;
    for (int j = 0; j < 3; ++j)
      idx = idx * 3 + (int)lround(d->coded[r * 3 + j] + 1.0);
    count[idx]++;
  }
  int all2 = 1;
  for (int c = 0; c < 27; ++c)
    all2 &= count[c] == 2;
  check_true(all2);
  pom_design_destroy(d);

  /* CCD: 2^k + 2k + centre; face-centred alpha = 1; rotatable alpha = (2^k)^(1/4). */
  for (int k = 2; k <= 5; ++k) {
    pom_design *f = make(POM_DESIGN_CCD_FACE, k, 4, 1);
    pom_design *r = make(POM_DESIGN_CCD_ROTATABLE, k, 4, 1);
    check_true(f->n == (1 << k) + 2 * k + 4 && r->n == f->n);
    check_abs(f->alpha, 1.0, 0.0);
    check_rel(r->alpha, pow(pow(2.0, k), 0.25), 1e-15);
    /* axial runs at +-alpha on one factor */
    double amax = 0.0;
    for (int q = 0; q < r->n * k; ++q)
      amax = fmax(amax, fabs(r->coded[q]));
    check_rel(amax, r->alpha, 1e-15);
    /* Rotatability: constant prediction variance on spheres (1e-9 allows for
       the round-off of (X^T X)^-1); the face-centred design is not rotatable
       (its spread is several percent), which shows the check can fail. */
    check_abs(variance_spread_on_sphere(r, 0.7315), 0.0, 1e-9);
    check_abs(variance_spread_on_sphere(r, 1.2385), 0.0, 1e-9);
    check_true(variance_spread_on_sphere(f, 1.2385) > 0.01);
    pom_design_destroy(f);
    pom_design_destroy(r);
  }

  /* Box-Behnken: 4 C(k,2) + centre runs (k = 3: 12 + 3 = 15, k = 4: 24 + 3,
     k = 5: 40 + 3); each run but the centre has two factors at +-1. */
  const int bb_runs[3] = {15, 27, 43};
  for (int k = 3; k <= 5; ++k) {
    pom_design *b = make(POM_DESIGN_BOX_BEHNKEN, k, 3, 1);
    check_true(b->n == bb_runs[k - 3]);
    int ok = 1;
    for (int r = 0; r < b->n - 3; ++r) {
      int nz = 0;
      for (int j = 0; j < k; ++j) {
        double c = b->coded[r * k + j];
        if (c != 0.0) {
          ++nz;
          ok &= fabs(c) == 1.0;
        }
      }
      ok &= nz == 2;
    }
    check_true(ok);
    pom_design_destroy(b);
  }
  check_true(make(POM_DESIGN_BOX_BEHNKEN, 2, 3, 1) == NULL);
  check_true(make(POM_DESIGN_BOX_BEHNKEN, 6, 3, 1) == NULL);

  /* LHS: one run per stratum in every factor; maximin over 200 candidates is
     at least as spread as the first candidate alone (same stream). */
  pom_design_defaults(&o);
  o.kind = POM_DESIGN_LHS;
  o.center_points = 0;
  o.lhs_points = 23;
  pom_design *l200 = NULL, *l1 = NULL;
  check_true(pom_design_create(&l200, 4, &o, &err) == POM_OK);
  o.lhs_candidates = 1;
  check_true(pom_design_create(&l1, 4, &o, &err) == POM_OK);
  int strat_ok = 1;
  for (int j = 0; j < 4; ++j) {
    int hit[23] = {0};
    for (int r = 0; r < 23; ++r) {
      double c = l200->coded[r * 4 + j];
      strat_ok &= c >= -1.0 && c < 1.0;
      int s = (int)floor((c + 1.0) * 23.0 / 2.0);
      if (s >= 0 && s < 23) hit[s]++;
    }
    for (int s = 0; s < 23; ++s)
      strat_ok &= hit[s] == 1;
  }
  check_true(strat_ok);
  double d200 = 1e300, d1 = 1e300;
  for (int a = 0; a < 23; ++a)
    for (int b = a + 1; b < 23; ++b) {
      double s200 = 0.0, s1 = 0.0;
      for (int j = 0; j < 4; ++j) {
        s200 += pow(l200->coded[a * 4 + j] - l200->coded[b * 4 + j], 2);
        s1 += pow(l1->coded[a * 4 + j] - l1->coded[b * 4 + j], 2);
      }
      d200 = fmin(d200, s200);
      d1 = fmin(d1, s1);
    }
  check_true(d200 >= d1);
  pom_design_destroy(l200);
  pom_design_destroy(l1);
  /* Maximin: candidates come from one stream, so the design of c candidates
     is the best of the first c; its smallest distance never decreases with
     c and, once it has changed, strictly grew (keeping the last or the first
     candidate instead would fail this). */
  o.lhs_candidates = 1;
  double prev = -1.0;
  int grew = 0, monotone = 1;
  for (int c = 1; c <= 40; ++c) {
    pom_design *lc = NULL;
    o.lhs_candidates = c;
    check_true(pom_design_create(&lc, 4, &o, &err) == POM_OK);
    double dc = 1e300;
    for (int a = 0; a < 23; ++a)
      for (int b = a + 1; b < 23; ++b) {
        double s = 0.0;
        for (int j = 0; j < 4; ++j)
          s += pow(lc->coded[a * 4 + j] - lc->coded[b * 4 + j], 2);
        dc = fmin(dc, s);
      }
    monotone &= dc >= prev;
    if (c > 1 && dc > prev) ++grew;
    prev = dc;
    pom_design_destroy(lc);
  }
  check_true(monotone);
  check_true(grew >= 2); /* 40 random hypercubes: the best is found more than once */

  /* Decoding: the extreme coded value lands on the bounds. */
  pom_design *r = make(POM_DESIGN_CCD_ROTATABLE, 2, 1, 1);
  const double lo[2] = {0.25, -3.0}, hi[2] = {0.75, 5.0};
  double nat[2 * 13];
  pom_design_decode(r, lo, hi, nat);
  double mn0 = 1e9, mx1 = -1e9;
  for (int q = 0; q < r->n; ++q) {
    mn0 = fmin(mn0, nat[2 * q]);
    mx1 = fmax(mx1, nat[2 * q + 1]);
  }
  check_abs(mn0, 0.25, 1e-15);
  check_abs(mx1, 5.0, 1e-15);
  check_abs(pom_design_to_coded(pom_design_to_natural(0.3871, r->alpha, 0.25, 0.75), r->alpha, 0.25,
                                0.75),
            0.3871, 1e-15);
  pom_design_destroy(r);

  /* errors */
  pom_design_defaults(&o);
  o.replicates = 0;
  check_true(pom_design_create(&d, 3, &o, &err) == POM_ERR_ARG && d == NULL);
  o.replicates = 1;
  check_true(pom_design_create(&d, 0, &o, &err) == POM_ERR_ARG);
}

/* ---- response surfaces -------------------------------------------------- */
static const double beta3[10] = {2.385, -1.17, 0.643, 3.29,   -0.871,
                                 1.93,  -2.46, 0.517, -0.339, 1.081};

static double quad3(const double u[3]) {
  double row[10];
  pom_rsm_row_terms(3, u, row);
  double y = 0.0;
  for (int j = 0; j < 10; ++j)
    y += beta3[j] * row[j];
  return y;
}

static void test_rsm_exact(void) {
  pom_design *d = make(POM_DESIGN_CCD_FACE, 3, 3, 1);
  double y[64];
  for (int r = 0; r < d->n; ++r)
    y[r] = quad3(d->coded + 3 * r);
  pom_rsm_fit fit;
  pom_error err;
  check_true(pom_rsm_fit_quadratic(&fit, 3, d->n, d->coded, y, NULL, &err) == POM_OK);
  /* an exact quadratic is recovered to round-off (coefficients are O(1)) */
  for (int j = 0; j < 10; ++j)
    check_abs(fit.beta[j], beta3[j], 1e-12);
  check_abs(fit.r2, 1.0, 1e-12);
  check_abs(fit.sigma, 0.0, 1e-12);
  /* ANOVA adds up: model + residual = total; linear + square + interaction = model */
  const pom_rsm_anova_row *A = fit.anova;
  check_rel(A[POM_RSM_ROW_MODEL].ss + A[POM_RSM_ROW_RESIDUAL].ss, A[POM_RSM_ROW_TOTAL].ss, 1e-12);
  check_rel(A[POM_RSM_ROW_LINEAR].ss + A[POM_RSM_ROW_SQUARE].ss + A[POM_RSM_ROW_INTERACTION].ss,
            A[POM_RSM_ROW_MODEL].ss, 1e-12);
  check_true(A[POM_RSM_ROW_MODEL].df == 9 && A[POM_RSM_ROW_TOTAL].df == d->n - 1);
  /* centre points only: pure error has 2 df and lack of fit 14 - 10 = 4 */
  check_true(fit.has_lack_of_fit && fit.n_distinct == 15);
  double u[3] = {0.3, -0.7, 0.11};
  check_abs(pom_rsm_predict(&fit, u, NULL), quad3(u), 1e-12);
  char name[16];
  pom_rsm_term_name(3, 9, name, sizeof name);
  check_true(strcmp(name, "x2*x3") == 0);

  /* errors: too few runs, a 2-level design (squares not estimable), NaN */
  check_true(pom_rsm_fit_quadratic(&fit, 3, 10, d->coded, y, NULL, &err) == POM_ERR_ARG);
  pom_design_options o;
  pom_design_defaults(&o);
  o.kind = POM_DESIGN_FULL_FACTORIAL;
  o.levels = 2;
  o.replicates = 2;
  pom_design *f2 = NULL;
  check_true(pom_design_create(&f2, 3, &o, &err) == POM_OK);
  check_true(pom_rsm_fit_quadratic(&fit, 3, f2->n, f2->coded, y, NULL, &err) == POM_ERR_ARG);
  pom_design_destroy(f2);
  y[4] = NAN;
  check_true(pom_rsm_fit_quadratic(&fit, 3, d->n, d->coded, y, NULL, &err) == POM_ERR_NONFINITE);
  pom_design_destroy(d);
}

static const double beta2[6] = {1.385, 0.62, -0.47, -1.13, 0.84, 0.391};

static double quad2(const double u[2], double cubic) {
  double row[6];
  pom_rsm_row_terms(2, u, row);
  double y = cubic * u[0] * u[0] * u[0];
  for (int j = 0; j < 6; ++j)
    y += beta2[j] * row[j];
  return y;
}

static void test_rsm_noisy(void) {
  const double sigma = 0.1;
  pom_design *d = make(POM_DESIGN_CCD_ROTATABLE, 2, 5, 3); /* 3 * 8 + 5 = 29 runs */
  double y[64];
  pom_rng rng;
  pom_rng_seed(&rng, 2385, 5);
  for (int r = 0; r < d->n; ++r)
    y[r] = quad2(d->coded + 2 * r, 0.0) + sigma * pom_rng_normal(&rng);
  pom_rsm_options o;
  pom_rsm_defaults(&o);
  o.confidence = 0.999;
  pom_rsm_fit fit;
  pom_error err;
  check_true(pom_rsm_fit_quadratic(&fit, 2, d->n, d->coded, y, &o, &err) == POM_OK);
  /* Every true coefficient inside its 99.9 % interval: a correct fit misses
     one of six with probability < 0.6 %; the seed is fixed. */
  for (int j = 0; j < 6; ++j)
    check_true(fabs(fit.beta[j] - beta2[j]) <= fit.ci_half[j]);
  /* s estimates sigma: with 23 df, s/sigma lies in [0.6, 1.4] with
     probability > 99.9 % (chi-square). */
  check_true(fit.sigma > 0.6 * sigma && fit.sigma < 1.4 * sigma);
  /* replicates give pure error; lack of fit is not significant */
  check_true(fit.has_lack_of_fit);
  check_true(fit.anova[POM_RSM_ROW_LACK_OF_FIT].p > 0.001);
  check_true(fit.anova[POM_RSM_ROW_MODEL].p < 1e-6);

  /* Held-out check: 40 LHS points, 95 % prediction intervals. The count
     inside is binomial(40, 0.95); below 0.8 has probability < 0.3 %. */
  pom_design_options lo;
  pom_design_defaults(&lo);
  lo.kind = POM_DESIGN_LHS;
  lo.center_points = 0;
  lo.lhs_points = 40;
  pom_design *h = NULL;
  check_true(pom_design_create(&h, 2, &lo, &err) == POM_OK);
  double yh[40];
  for (int r = 0; r < 40; ++r)
    yh[r] = quad2(h->coded + 2 * r, 0.0) + sigma * pom_rng_normal(&rng);
  pom_rsm_check chk;
  pom_rsm_validate(&fit, 40, h->coded, yh, 0.95, &chk);
  check_true(chk.within_pi >= 0.8);
  check_true(chk.rmse < 1.5 * sigma && chk.r2 > 0.9);

  /* A cubic term the quadratic cannot follow: lack of fit is significant. */
  pom_rng_seed(&rng, 2385, 5);
  for (int r = 0; r < d->n; ++r)
    y[r] = quad2(d->coded + 2 * r, 1.5) + sigma * pom_rng_normal(&rng);
  check_true(pom_rsm_fit_quadratic(&fit, 2, d->n, d->coded, y, &o, &err) == POM_OK);
  check_true(fit.anova[POM_RSM_ROW_LACK_OF_FIT].p < 1e-6);
  pom_design_destroy(h);
  pom_design_destroy(d);
}

/* PRESS from the hat matrix equals brute-force leave-one-out refits. */
static void test_press(void) {
  pom_design_options o;
  pom_design_defaults(&o);
  o.kind = POM_DESIGN_LHS;
  o.center_points = 0;
  o.lhs_points = 17;
  pom_design *d = NULL;
  pom_error err;
  check_true(pom_design_create(&d, 2, &o, &err) == POM_OK);
  double y[17];
  pom_rng rng;
  pom_rng_seed(&rng, 99, 0);
  for (int r = 0; r < 17; ++r)
    y[r] = sin(2.1 * d->coded[2 * r]) + exp(d->coded[2 * r + 1]) + 0.05 * pom_rng_normal(&rng);
  pom_rsm_fit full, loo;
  check_true(pom_rsm_fit_quadratic(&full, 2, 17, d->coded, y, NULL, &err) == POM_OK);
  double press = 0.0, u16[32], y16[16];
  for (int out = 0; out < 17; ++out) {
    int m = 0;
    for (int r = 0; r < 17; ++r)
      if (r != out) {
        u16[2 * m] = d->coded[2 * r];
        u16[2 * m + 1] = d->coded[2 * r + 1];
        y16[m++] = y[r];
      }
    check_true(pom_rsm_fit_quadratic(&loo, 2, 16, u16, y16, NULL, &err) == POM_OK);
    double e = y[out] - pom_rsm_predict(&loo, d->coded + 2 * out, NULL);
    press += e * e;
  }
  check_rel(full.press, press, 1e-9);
  check_true(full.r2_pred < full.r2 && full.r2_adj < full.r2);
  check_true(!full.has_lack_of_fit); /* no replicates in an LHS */
  pom_design_destroy(d);
}

/* Every statistic of one small fit against an independent computation:
 * numpy.linalg.lstsq for b, s^2 (X^T X)^-1 for the standard errors, the hat
 * matrix for PRESS, nested lstsq fits for the sequential ANOVA, grouping of
 * identical runs for pure error, scipy.stats t and F for quantiles and p
 * (Debian python3-numpy 1.24 / python3-scipy 1.10). The data are a 3 x 3
 * grid in k = 2 with three centre runs, a replicated corner and one interior
 * point: 13 runs, 10 distinct, so pure error has 3 df and lack of fit 4.
 * Tolerance 1e-9 relative: the problem is well conditioned (both solvers
 * agree to ~1e-13); GSL's and scipy's t quantiles agree to ~1e-10. */
static void test_rsm_reference(void) {
  const double u[26] = {-1, -1, 1, -1, -1, 1, 1, 1, -1, 0, 1, 0,   0,
                        -1, 0,  1, 0,  0,  0, 0, 0, 0,  1, 1, 0.5, -0.5};
  const double y[13] = {3.1, 5.2, 4.4, 9.9, 2.7, 6.1, 3.3, 5.0, 4.1, 3.8, 4.4, 10.6, 4.0};
  const double b[6] = {3.771525179856115,  1.9223669064748181, 1.4101510791366905,
                       1.0361726618705043, 0.7861726618705029, 1.0260575539568344};
  const double se[6] = {0.2916028277752278, 0.2291793620836069,  0.2301523206594777,
                        0.3709197473340902, 0.37091974733409017, 0.27760097565582353};
  const double pv[6] = {3.839611319951803e-06, 6.727845676353257e-05, 0.0004781918234460748,
                        0.026772375477583366,  0.07177211294424803,   0.007693840741892261};
  const double ci[6] = {0.6895311182204833, 0.5419230774139672, 0.5442237588576997,
                        0.8770858297248025, 0.8770858297248024, 0.6564219991398801};
  pom_rsm_fit f;
  pom_error err;
  check_true(pom_rsm_fit_quadratic(&f, 2, 13, u, y, NULL, &err) == POM_OK);
  for (int j = 0; j < 6; ++j) {
    check_rel(f.beta[j], b[j], 1e-9);
    check_rel(f.se[j], se[j], 1e-9);
    check_rel(f.p_value[j], pv[j], 1e-9);
    check_rel(f.ci_half[j], ci[j], 1e-9);
  }
  check_rel(f.r2, 0.9648589287737738, 1e-9);
  check_rel(f.r2_adj, 0.9397581636121836, 1e-9);
  check_rel(f.r2_pred, 0.8507484635504077, 1e-9);
  check_rel(f.press, 10.773435136428338, 1e-9);
  check_rel(f.sigma, 0.601971836963683, 1e-9);
  /* ANOVA rows: SS, df, F, p (model, linear, square, interaction, lack of fit) */
  const struct {
    int row;
    double ss, df, f, p;
  } an[5] = {
      {POM_RSM_ROW_MODEL, 69.64648627559491, 5, 38.43942296429372, 6.056293772576098e-05},
      {POM_RSM_ROW_LINEAR, 56.50829695342594, 2, 77.97042046706238, 1.64338115785305e-05},
      {POM_RSM_ROW_SQUARE, 8.187635179393883, 2, 11.297338479239883, 0.006435696081139416},
      {POM_RSM_ROW_INTERACTION, 4.950554142775084, 1, 13.661596928864052, 0.007693840741892295},
      {POM_RSM_ROW_LACK_OF_FIT, 2.111590647482016, 4, 3.726336436732971, 0.15421803477951396}};
  for (int i = 0; i < 5; ++i) {
    const pom_rsm_anova_row *a = &f.anova[an[i].row];
    check_rel(a->ss, an[i].ss, 1e-9);
    check_true(a->df == an[i].df);
    check_rel(a->ms, an[i].ss / an[i].df, 1e-9);
    check_rel(a->f, an[i].f, 1e-9);
    check_rel(a->p, an[i].p, 1e-9);
  }
  check_true(f.has_lack_of_fit && f.n_distinct == 10);
  check_true(pom_rsm_lack_of_fit_note(&f) == NULL); /* the test applies: p above */
  check_rel(f.anova[POM_RSM_ROW_PURE_ERROR].ss, 0.425, 1e-9);
  check_true(f.anova[POM_RSM_ROW_PURE_ERROR].df == 3 && f.anova[POM_RSM_ROW_RESIDUAL].df == 7);
  check_rel(f.anova[POM_RSM_ROW_TOTAL].ss, 72.18307692307692, 1e-9);
  /* held-out: prediction and its standard error at (0.3, 0.7) */
  const double uh[4] = {0.3, 0.7, -0.8, 0.2}, yh[2] = {5.5, 3.0};
  double sem = 0.0;
  check_rel(pom_rsm_predict(&f, uh, &sem), 6.029293237410071, 1e-9);
  check_rel(sem, 0.29258986863516045, 1e-9);
  pom_rsm_check chk;
  pom_rsm_validate(&f, 2, uh, yh, 0.95, &chk);
  check_rel(chk.rmse, 0.3756831283806168, 1e-9);

  /* A group of terms that explains nothing: the nested SSE differ by
     round-off of either sign. The synthesis met this on a 3SPS workspace
     response (13 or 14 deg, no interaction): the clamped SS must give a
     mean square >= 0 and F >= 0, p in [0, 1], never a negative MS or NaN p. */
  pom_design *d = make(POM_DESIGN_CCD_FACE, 3, 1, 1);
  double yd[15];
  for (int r = 0; r < d->n; ++r)
    yd[r] = (d->coded[3 * r] > 0.5 ? 14.0 : 13.0) * (3.14159265358979323846 / 180.0);
  check_true(pom_rsm_fit_quadratic(&f, 3, d->n, d->coded, yd, NULL, &err) == POM_OK);
  for (int r = POM_RSM_ROW_MODEL; r <= POM_RSM_ROW_RESIDUAL; ++r) {
    const pom_rsm_anova_row *a = &f.anova[r];
    check_true(a->ss >= 0.0 && a->ms >= 0.0 && a->ms == a->ss / a->df);
    check_true(isnan(a->f) || (a->f >= 0.0 && a->p >= 0.0 && a->p <= 1.0));
  }
  /* one centre run: no replicates, so no lack-of-fit test, and the reader is told why */
  check_true(!f.has_lack_of_fit && isnan(f.anova[POM_RSM_ROW_LACK_OF_FIT].p));
  const char *note = pom_rsm_lack_of_fit_note(&f);
  check_true(note && strcmp(note, "no replicates") == 0);
  pom_design_destroy(d);
  /* three centre runs of a deterministic response: 2 pure-error df, but the
     replicates agree exactly, so the F test does not apply either */
  d = make(POM_DESIGN_CCD_FACE, 3, 3, 1);
  double yc[17];
  for (int r = 0; r < d->n; ++r)
    yc[r] = 2.385 + d->coded[3 * r] * d->coded[3 * r + 1] * d->coded[3 * r + 2];
  check_true(pom_rsm_fit_quadratic(&f, 3, d->n, d->coded, yc, NULL, &err) == POM_OK);
  check_true(f.has_lack_of_fit && f.anova[POM_RSM_ROW_PURE_ERROR].df == 2);
  note = pom_rsm_lack_of_fit_note(&f);
  check_true(note && strcmp(note, "zero pure error") == 0);
  pom_design_destroy(d);
}

/* ---- desirability ------------------------------------------------------- */
static void test_desirability(void) {
  /* Maximize on [80, 100]: halfway = 0.5; s = 2 gives 0.25, s = 0.5 sqrt(0.5). */
  pom_desir_spec mx = pom_desir_make(POM_DESIR_MAXIMIZE, 80.0, 0.0, 100.0);
  check_abs(pom_desir_individual(&mx, 90.0), 0.5, 1e-15);
  check_abs(pom_desir_individual(&mx, 79.0), 0.0, 0.0);
  check_abs(pom_desir_individual(&mx, 101.0), 1.0, 0.0);
  mx.shape_low = 2.0;
  check_abs(pom_desir_individual(&mx, 90.0), 0.25, 1e-15);
  mx.shape_low = 0.5;
  check_abs(pom_desir_individual(&mx, 90.0), sqrt(0.5), 1e-15);
  /* Minimize on [0.2, 0.7]: y = 0.325 -> 0.75. */
  pom_desir_spec mn = pom_desir_make(POM_DESIR_MINIMIZE, 0.2, 0.0, 0.7);
  check_abs(pom_desir_individual(&mn, 0.325), 0.75, 1e-15);
  check_abs(pom_desir_individual(&mn, 0.1), 1.0, 0.0);
  /* Target 67.5 in [60, 75] (Derringer-Suich hardness): 63.75 -> 0.5; 71.25 with t = 2 -> 0.25. */
  pom_desir_spec tg = pom_desir_make(POM_DESIR_TARGET, 60.0, 67.5, 75.0);
  tg.shape_high = 2.0;
  check_abs(pom_desir_individual(&tg, 63.75), 0.5, 1e-15);
  check_abs(pom_desir_individual(&tg, 71.25), 0.25, 1e-15);
  check_abs(pom_desir_individual(&tg, 67.5), 1.0, 1e-15);
  check_abs(pom_desir_individual(&tg, 76.0), 0.0, 0.0);
  check_abs(pom_desir_individual(&tg, NAN), 0.0, 0.0);
  /* Overall: geometric mean; importances weight it; one zero makes D = 0. */
  pom_desir_spec sp[2] = {pom_desir_make(POM_DESIR_MAXIMIZE, 80.0, 0.0, 100.0), tg};
  double yv[2] = {90.0, 71.25}, dv[2];
  check_abs(pom_desir_overall(2, sp, yv, dv), sqrt(0.125), 1e-15);
  check_abs(dv[1], 0.25, 1e-15);
  sp[0].importance = 2.0;
  check_abs(pom_desir_overall(2, sp, yv, NULL), cbrt(0.0625), 1e-15);
  yv[0] = 70.0;
  check_abs(pom_desir_overall(2, sp, yv, NULL), 0.0, 0.0);
  /* validation */
  pom_error err;
  check_true(pom_desir_validate(&tg, "hardness", &err) == POM_OK);
  tg.target = 80.0;
  check_true(pom_desir_validate(&tg, "hardness", &err) == POM_ERR_ARG);
  check_true(strstr(err.message, "hardness") != NULL);
}

/* ---- NLopt driver ------------------------------------------------------- */
/* Negated Rastrigin shifted to (0.3, -0.2): global maximum 0 there, a local
 * maximum near every other integer offset. */
static pom_status rastrigin(void *ctx, const double x[], double *f, pom_error *err) {
  (void)ctx;
  (void)err;
  double s = 0.0;
  const double c[2] = {0.3, -0.2};
  for (int i = 0; i < 2; ++i) {
    double z = x[i] - c[i];
    s += z * z - 10.0 * cos(2.0 * 3.14159265358979323846 * z) + 10.0;
  }
  *f = -s;
  return POM_OK;
}

typedef struct {
  int calls;
  int fail_at;
  int nan;
} failing_ctx;

static pom_status failing(void *ctx, const double x[], double *f, pom_error *err) {
  failing_ctx *c = ctx;
  if (++c->calls == c->fail_at) {
    if (c->nan) {
      *f = NAN;
      return POM_OK;
    }
    POM_FAIL(err, POM_ERR_UNREACHABLE, "limb 2 cannot be assembled at x = %g", x[0]);
  }
  *f = -(x[0] * x[0] + x[1] * x[1]);
  return POM_OK;
}

/* Rastrigin that records the best value and point it returned. */
typedef struct {
  double best_f, best_x[2];
  long calls;
} recording_ctx;

static pom_status recording(void *ctx, const double x[], double *f, pom_error *err) {
  recording_ctx *c = ctx;
  POM_TRY(rastrigin(NULL, x, f, err));
  if (c->calls++ == 0 || *f > c->best_f) {
    c->best_f = *f;
    c->best_x[0] = x[0];
    c->best_x[1] = x[1];
  }
  return POM_OK;
}

/* Two basins on [0, 1]^2 (docs/optimize.md, section 4): a broad peak of
 * height 1 at (0.5, 0.55), where DIRECT-L's first samples cluster, and a
 * narrow one of height 1.3 at (0.85, 0.15), between its samples. */
static pom_status two_basins(void *ctx, const double x[], double *f, pom_error *err) {
  (void)ctx;
  (void)err;
  double ra = (x[0] - 0.5) * (x[0] - 0.5) + (x[1] - 0.55) * (x[1] - 0.55);
  double rb = (x[0] - 0.85) * (x[0] - 0.85) + (x[1] - 0.15) * (x[1] - 0.15);
  *f = exp(-ra / (2.0 * 0.15 * 0.15)) + 1.3 * exp(-rb / (2.0 * 0.03 * 0.03));
  return POM_OK;
}

/* The multi-start local stage finds the better of two basins where the
 * single start (the global stage's best point) does not; one start is the
 * single-start run itself. */
static void test_local_starts(void) {
  const double lo[2] = {0.0, 0.0}, hi[2] = {1.0, 1.0};
  pom_opt_options o;
  pom_opt_defaults(&o);
  check_true(o.local_starts == 1 && o.local_start_separation == 0.1);
  o.global = POM_OPT_GLOBAL_DIRECT_L;
  o.global_max_evals = 40;
  o.local_max_evals = 40;
  o.local_xtol_rel = 1e-3;
  pom_opt_result one, two, many, apart;
  pom_error err;
  check_true(pom_opt_maximize(2, lo, hi, NULL, two_basins, NULL, &o, &one, &err) == POM_OK);
  /* the broad peak (the narrow one adds 1.3 exp(-0.2825 / 0.0018), nothing,
   * there); BOBYQA's x tolerance 1e-3 leaves f within 1e-4 of its top */
  check_abs(one.f, 1.0, 1e-4);
  check_abs(one.x[0], 0.5, 0.01);
  check_true(one.local_runs == 1);
  o.local_starts = 2;
  check_true(pom_opt_maximize(2, lo, hi, NULL, two_basins, NULL, &o, &two, &err) == POM_OK);
  /* the narrow peak: 1.3 plus the broad one's exp(-0.2825 / 0.045) = 0.0019;
   * x within 1e-3 of its top costs at most 1.3 / 0.03^2 / 2 * (1e-3)^2 = 7e-4 */
  check_abs(two.f, 1.3 + exp(-0.2825 / 0.045), 1e-3);
  check_abs(two.x[0], 0.85, 0.01);
  check_abs(two.x[1], 0.15, 0.01);
  check_true(two.local_runs == 2 && two.local_best_run == 1);
  /* the same global stage, and the first local run is the single start's */
  check_true(two.evals_global == one.evals_global && two.evals_local > one.evals_local);
  o.local_starts = 4;
  check_true(pom_opt_maximize(2, lo, hi, NULL, two_basins, NULL, &o, &many, &err) == POM_OK);
  check_true(many.f == two.f && many.local_runs == 4 && many.evals_local > two.evals_local);
  /* starts a whole box apart: only the global stage's best is one */
  o.local_start_separation = 1.0;
  check_true(pom_opt_maximize(2, lo, hi, NULL, two_basins, NULL, &o, &apart, &err) == POM_OK);
  check_true(apart.local_runs == 1 && apart.f == one.f && apart.evals_local == one.evals_local);
  /* refused options */
  o.local_start_separation = 0.0;
  check_true(pom_opt_maximize(2, lo, hi, NULL, two_basins, NULL, &o, &apart, &err) == POM_ERR_ARG);
  o.local_start_separation = 0.1;
  o.local_starts = POM_OPT_MAX_STARTS + 1;
  check_true(pom_opt_maximize(2, lo, hi, NULL, two_basins, NULL, &o, &apart, &err) == POM_ERR_ARG);
  o.local_starts = 0;
  check_true(pom_opt_maximize(2, lo, hi, NULL, two_basins, NULL, &o, &apart, &err) == POM_ERR_ARG);
  /* without a global stage there is one start, x0 */
  o.local_starts = 3;
  o.global = POM_OPT_GLOBAL_NONE;
  const double x0[2] = {0.45, 0.6};
  check_true(pom_opt_maximize(2, lo, hi, x0, two_basins, NULL, &o, &apart, &err) == POM_OK);
  check_true(apart.local_runs == 1 && apart.evals_global == 0);
  check_abs(apart.f, 1.0, 1e-4);
}

static void test_nlopt(void) {
  const double lo[2] = {-5.12, -5.12}, hi[2] = {5.12, 5.12};
  pom_opt_options o;
  pom_opt_defaults(&o);
  pom_opt_result res, res2;
  pom_error err;
  /* CRS2 then BOBYQA: the global maximum, polished to 1e-6. */
  check_true(pom_opt_maximize(2, lo, hi, NULL, rastrigin, NULL, &o, &res, &err) == POM_OK);
  check_abs(res.x[0], 0.3, 1e-6);
  check_abs(res.x[1], -0.2, 1e-6);
  check_abs(res.f, 0.0, 1e-9);
  check_true(res.evals_global > 0 && res.evals_local > 0 && res.result_global > 0);
  /* the same seed gives the same run */
  check_true(pom_opt_maximize(2, lo, hi, NULL, rastrigin, NULL, &o, &res2, &err) == POM_OK);
  check_true(res.x[0] == res2.x[0] && res.x[1] == res2.x[1] &&
             res.evals_global == res2.evals_global);
  /* deterministic DIRECT-L */
  o.global = POM_OPT_GLOBAL_DIRECT_L;
  check_true(pom_opt_maximize(2, lo, hi, NULL, rastrigin, NULL, &o, &res, &err) == POM_OK);
  check_abs(res.x[0], 0.3, 1e-6);
  check_abs(res.x[1], -0.2, 1e-6);
  /* local only from a start in the global basin */
  o.global = POM_OPT_GLOBAL_NONE;
  const double x0[2] = {0.1, -0.1};
  check_true(pom_opt_maximize(2, lo, hi, x0, rastrigin, NULL, &o, &res, &err) == POM_OK);
  check_abs(res.x[0], 0.3, 1e-6);
  check_true(res.result_global == 0 && res.evals_global == 0);

  /* The result is the best point evaluated, not the last one: a short
     search (30 + 15 evaluations) ends far from converged. */
  pom_opt_defaults(&o);
  o.global_max_evals = 30;
  o.local = POM_OPT_LOCAL_NELDERMEAD;
  o.local_max_evals = 15;
  recording_ctx rc = {0.0, {0.0, 0.0}, 0};
  check_true(pom_opt_maximize(2, lo, hi, NULL, recording, &rc, &o, &res, &err) == POM_OK);
  check_true(rc.calls == res.evals_global + res.evals_local);
  check_true(res.f == rc.best_f && res.x[0] == rc.best_x[0] && res.x[1] == rc.best_x[1]);

  /* A failing objective stops NLopt and returns its own status. */
  pom_opt_defaults(&o);
  failing_ctx fc = {0, 10, 0};
  pom_error_clear(&err);
  check_true(pom_opt_maximize(2, lo, hi, NULL, failing, &fc, &o, &res, &err) ==
             POM_ERR_UNREACHABLE);
  check_true(fc.calls == 10 && res.evals_global == 10);
  check_true(res.result_global == NLOPT_FORCED_STOP);
  check_true(strstr(err.message, "limb 2") != NULL);
  /* ... also in the local stage */
  failing_ctx fl = {0, 0, 0};
  o.global_max_evals = 50;
  check_true(pom_opt_maximize(2, lo, hi, NULL, failing, &fl, &o, &res, &err) == POM_OK);
  fl.calls = 0;
  fl.fail_at = (int)res.evals_global + 10;
  check_true(pom_opt_maximize(2, lo, hi, NULL, failing, &fl, &o, &res, &err) ==
             POM_ERR_UNREACHABLE);
  check_true(res.result_local == NLOPT_FORCED_STOP && res.evals_local == 10);
  /* a NaN objective is a failure, not a value */
  failing_ctx fn = {0, 7, 1};
  check_true(pom_opt_maximize(2, lo, hi, NULL, failing, &fn, &o, &res, &err) == POM_ERR_NONFINITE);
  /* invalid arguments */
  const double bad_hi[2] = {-6.0, 5.12};
  check_true(pom_opt_maximize(2, lo, bad_hi, NULL, rastrigin, NULL, &o, &res, &err) == POM_ERR_ARG);
  check_true(pom_opt_maximize(0, lo, hi, NULL, rastrigin, NULL, &o, &res, &err) == POM_ERR_ARG);
}

int main(void) {
  test_designs();
  test_rsm_exact();
  test_rsm_noisy();
  test_press();
  test_rsm_reference();
  test_desirability();
  test_nlopt();
  test_local_starts();
  return check_summary("test_optimize");
}
