/* pom_synth_cap.c - a capability floor on the synthesis' scaled optimum
 * (synthesis.capability_require, docs/optimize.md 6b): the figures of
 * capability/pom_cap_figures.h on the full mechanism of the scaled geometry
 * with the config's inertia, actuator and controller, checked on the final
 * optima (the written one, then the other when it fails), never inside the
 * optimizers: one capability run costs seconds, the optimizers make
 * thousands of evaluations. The choice of the optima to check and the
 * switch are pom_syn_finish's (pom_synth.c); this file only evaluates. */
#include "pom_synth.h"

#include "pom_math.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

pom_status pom_syn_cap_load(pom_syn_cap *c, const pom_kin_arch *base, const pom_cfg *cfg,
                            pom_error *err) {
  static const char *const key = "synthesis.capability_require";
  static const char *const gkey = "synthesis.capability_grid_points";
  memset(c, 0, sizeof *c);
  POM_TRY(pom_cap_requirements_load(cfg, key, c->req, POM_SYN_MAX_CAP_REQUIRE, &c->n, err));
  if (c->n == 0) {
    if (pom_cfg_has(cfg, gkey))
      return pom_cfg_error(cfg, gkey, NULL, err, "only with synthesis.capability_require");
    return POM_OK;
  }
  long g = 3;
  POM_TRY(pom_cfg_int_opt(cfg, gkey, 1, POM_CAP_MAX_GRID, g, &g, err));
  if (g % 2 == 0) return pom_cfg_error(cfg, gkey, NULL, err, "must be odd (home on the grid)");
  c->grid = (int)g;
  for (int j = 0; j < c->n; ++j)
    c->want[c->req[j].figure] = 1;
  /* the model the figures need besides the geometry: the config's own */
  POM_TRY(pom_kin_inertia_load(&c->inertia, base, cfg, err));
  pom_dyn_params_defaults(&c->params);
  POM_TRY(pom_dyn_params_load(&c->params, cfg, err));
  POM_TRY(pom_cap_load(&c->opts, cfg, err));
  pom_cap_opts_for_figures(&c->opts, c->want, c->grid);
  return POM_OK;
}

static void judge(const pom_syn_cap *c, pom_syn_cap_check *ck) {
  ck->all_met = 1;
  for (int j = 0; j < c->n; ++j) {
    ck->met[j] = pom_cap_requirement_met(&c->req[j], ck->value[c->req[j].figure]);
    ck->all_met &= ck->met[j];
  }
}

void pom_syn_cap_check_start(pom_syn_cap_check *ck, int direct, const double *x, double d) {
  memset(ck, 0, sizeof *ck);
  ck->direct = direct;
  memcpy(ck->x, x, sizeof ck->x);
  ck->d = d;
  ck->scale = NAN;
  for (int i = 0; i < POM_CAP_N_FIGURES; ++i)
    ck->value[i] = NAN;
}

void pom_syn_cap_check_unevaluated(const pom_syn_cap *c, pom_syn_cap_check *ck, const char *why) {
  snprintf(ck->note, sizeof ck->note, "%s", why);
  judge(c, ck);
}

pom_status pom_syn_cap_check_arch(const pom_syn_cap *c, const pom_kin_ws_opts *ws,
                                  const pom_kin_arch *arch, pom_syn_cap_check *ck, pom_error *err) {
  pom_mechanism *mech = calloc(1, sizeof *mech);
  if (!mech) POM_FAIL(err, POM_ERR_NOMEM, "synthesis.capability_require: out of memory");
  pom_cap_result res;
  memset(&res, 0, sizeof res);
  pom_error e;
  pom_error_clear(&e);
  pom_status st = pom_kin_mechanism_from(mech, arch, &c->inertia, &e);
  if (st == POM_OK) st = pom_cap_run(arch, ws, mech, &c->params, &c->opts, &res, &e);
  if (st == POM_OK)
    for (int i = 0; i < POM_CAP_N_FIGURES; ++i)
      ck->value[i] = c->want[i] ? pom_cap_figure_value(&res, i) : NAN;
  else
    snprintf(ck->note, sizeof ck->note, "capability run failed: %s", e.message);
  judge(c, ck);
  pom_cap_result_free(&res);
  free(mech);
  return st == POM_ERR_NOMEM ? pom_error_set(err, st, __FILE__, __LINE__, "%s", e.message) : POM_OK;
}

void pom_syn_cap_failure_text(const pom_syn_cap *c, const pom_syn_cap_check *checks, int n,
                              char *buf, size_t cap) {
  size_t used = 0;
  buf[0] = '\0';
  for (int k = 0; k < n; ++k) {
    const pom_syn_cap_check *ck = &checks[k];
    int w = snprintf(buf + used, cap - used, "%s%s optimum:", k ? "; " : "",
                     ck->direct ? "direct-search" : "surrogate");
    if (w > 0 && (size_t)w < cap - used) used += (size_t)w;
    for (int j = 0, first = 1; j < c->n; ++j) {
      if (ck->met[j]) continue;
      const pom_cap_requirement *q = &c->req[j];
      double v = ck->value[q->figure];
      char val[48];
      if (isnan(v))
        snprintf(val, sizeof val, "n/a");
      else
        snprintf(val, sizeof val, "%.6g %s", v, pom_cap_figure_unit(q->figure));
      w = snprintf(buf + used, cap - used, "%s %s = %s, required %s %.6g %s", first ? "" : ",",
                   pom_cap_figure_name(q->figure), val, q->at_most ? "<=" : ">=", q->bound,
                   pom_cap_figure_unit(q->figure));
      if (w > 0 && (size_t)w < cap - used) used += (size_t)w;
      first = 0;
    }
    if (ck->note[0]) {
      w = snprintf(buf + used, cap - used, " (%s)", ck->note);
      if (w > 0 && (size_t)w < cap - used) used += (size_t)w;
    }
  }
}
