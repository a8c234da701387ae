#!/usr/bin/python3
"""Reads pomlab study results files with h5py (tests/test_doe_study.sh).

usage: test_doe_h5.py REPORT.json REFERENCE.h5 [OTHER.h5 ...]

Checks the documented layout (docs/results.md), that every maneuver is
stored, that out-of-stroke targets are recorded as failures with a reason,
that the statistics, paired comparisons and ranking in the file equal an
independent recomputation (numpy; scipy for the t quantile and the Wilcoxon
test when available), that the JSON report agrees, and that every OTHER file
holds bit-identical maneuver rows (wall time excepted) to the reference.
"""
import json
import sys

import h5py
import numpy as np

failures = 0


def check(cond, what):
    global failures
    if not cond:
        failures += 1
        print("FAIL:", what)


def text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


def rel_close(a, b, tol):
    if np.isnan(a) and np.isnan(b):
        return True
    return abs(a - b) <= tol * max(abs(a), abs(b), 1e-300)


def rows_of(path):
    with h5py.File(path, "r") as f:
        n = int(f.attrs["n_candidates"])
        out = []
        for c in range(n):
            r = f["candidates/%d/maneuvers" % c][:].copy()
            r["wall_time"] = 0.0  # the one field that differs between identical runs
            out.append(r)
        return out



def censored_time(r):
    """The primary time of a joint-space study's rows: the execution time, or
    the horizon when an actuator did not settle (right-censored there)."""
    settled = np.all(r["settled"] == 1, axis=1) & np.isfinite(r["execution_time"])
    return np.where(settled, r["execution_time"], r["horizon"])

def main(argv):
    report, ref, others = argv[1], argv[2], argv[3:]
    with h5py.File(ref, "r") as f:
        # provenance
        check(text(f.attrs["format"]) == "pomlab study results", "format attribute")
        check(int(f.attrs["format_version"]) == 1, "format version")
        check(len(text(f.attrs["git_commit"])) > 0 and len(text(f.attrs["version"])) > 0,
              "version and commit")
        check("doe_small" in text(f["study_config"][()]), "study config text stored")
        mc = f["montecarlo"]
        m = int(mc.attrs["count"])
        check(m == int(f.attrs["n_maneuvers"]) == 8, "maneuver count")
        check(int(mc.attrs["seed"]) == 77, "seed")
        targets = mc["target"][:]
        check(targets.shape == (m, 3), "target table shape")
        nc = int(f.attrs["n_candidates"])
        names = [text(f["candidates/%d" % c].attrs["name"]) for c in range(nc)]
        check(names == ["3PSS", "3SPS"], "candidate names %s" % names)
        for c in range(nc):
            g = f["candidates/%d" % c]
            check("architecture" in text(g["config"][()]), "resolved config of %d" % c)
            check(g.attrs["solver_rtol"] == (1e-6 if c == 0 else 1e-5), "solver settings")
            # the documented provenance attributes (docs/results.md section 5)
            for key in ("architecture", "stroke_m", "controller_form", "controller_kp",
                        "controller_ki", "controller_kd", "orientation", "scene_gravity",
                        "solver_atol_scale", "solver_max_step_s", "solver_max_steps",
                        "solver_linear_solver", "maneuver_horizon_s", "maneuver_settle_band",
                        "model_states"):
                check(key in g.attrs, "candidate %d attribute %s" % (c, key))
            check(g.attrs["maneuver_horizon_s"] == 0.025, "study override in the settings")
            ds = g["maneuvers"]
            check("energy_total J" in text(ds.attrs["units"]), "row units of %d" % c)
            check("-6 joint, stroke" in text(ds.attrs["status_codes"]), "status legend of %d" % c)
        rows = [f["candidates/%d/maneuvers" % c][:] for c in range(nc)]
        stats_t = f["statistics/execution_time"][:]
        stats_f = f["statistics/execution_time_final"][:]
        stats_e = f["statistics/energy"][:]
        counts = f["statistics/counts"][:]
        paired = f["comparison/paired"][:]
        conf = float(f["comparison"].attrs["confidence"])
        check(text(f.attrs["time_metric"]) == "execution_time", "joint space: the per-actuator time")
        rank_t = list(f["ranking/execution_time"][:])
        rank_e = list(f["ranking/energy"][:])

    half_stroke = 6e-3
    n_fail = 0
    for c in range(nc):
        r = rows[c]
        check(np.all(r["done"] == 1), "every maneuver of candidate %d stored" % c)
        # common random numbers: every candidate's targets are the drawn ones
        check(np.array_equal(r["target"], targets), "targets of candidate %d" % c)
        out = np.any(np.abs(targets) > half_stroke, axis=1)
        check(np.all(r["status"][out] == -6), "out-of-stroke maneuvers fail with POM_ERR_LIMIT")
        for k in np.nonzero(out)[0]:
            check("stroke" in text(r["reason"][k]), "reason names the stroke: %r" % r["reason"][k])
        check(np.all(r["status"][~out] == 0), "in-stroke maneuvers of %d succeed" % c)
        n_fail += int(np.sum(out))
        ok = r["status"] == 0
        settled = ok & np.all(r["settled"] == 1, axis=1)
        t = r["execution_time"][settled]
        e = r["energy_total"][ok]
        check(counts[c, 0] == m and counts[c, 2] == np.sum(~ok), "counts of %d" % c)
        check(counts[c, 3] == np.sum(ok & ~settled), "unsettled count of %d" % c)
        check(counts[c, 4] == np.sum(ok & ~settled), "censored count of %d (joint space)" % c)
        tfin = np.max(r["settling_time_final"][ok], axis=1)
        tfin = tfin[np.isfinite(tfin)]
        for row, v in ((stats_t[c], t), (stats_e[c], e), (stats_f[c], tfin)):
            check(row[0] == v.size, "n")
            want = [v.max(), v.mean(), v.min(), v.std(ddof=1) if v.size > 1 else np.nan,
                    np.median(v)] + list(np.percentile(v, [5, 25, 75, 95]))
            for j, w in enumerate(want):
                check(rel_close(row[1 + j], w, 1e-12), "statistic %d: %r vs %r" % (j, row[1 + j], w))
    check(n_fail > 0, "the small study has out-of-stroke targets")

    # paired comparisons, recomputed
    try:
        from scipy import stats as sps
    except ImportError:
        sps = None
    for p in paired:
        a, b, metric = int(p[0]), int(p[1]), int(p[2])
        ra, rb = rows[a], rows[b]
        use = [(r["status"] == 0) for r in (ra, rb)]
        both = use[0] & use[1]
        if metric == 0:  # an unsettled time counts, censored at the horizon
            d = censored_time(ra)[both] - censored_time(rb)[both]
        else:
            d = ra["energy_total"][both] - rb["energy_total"][both]
        check(p[3] == d.size, "pairs")
        if metric == 0:
            for col, r in ((13, ra), (14, rb)):
                check(p[col] == np.sum(both & (censored_time(r) != r["execution_time"])),
                      "censored count in the pairs")
        check(rel_close(p[4], d.mean(), 1e-12), "mean difference")
        check(rel_close(p[10], np.sum(d < 0) / d.size, 1e-15), "wins")
        check(rel_close(p[11], np.sum(d == 0) / d.size, 1e-15), "ties")
        # two candidates: one comparison per metric, Holm changes nothing
        check(p[12] == p[8], "Holm p of a single comparison")
        if sps is not None and d.size >= 2:
            half = sps.t.ppf(0.5 + 0.5 * conf, d.size - 1) * d.std(ddof=1) / np.sqrt(d.size)
            check(rel_close(p[6] - p[4], half, 1e-9), "interval half-width")
            nz = d[d != 0]
            ties = len(np.unique(np.abs(nz))) < nz.size
            mode = "exact" if nz.size <= 50 and not ties else "approx"
            res = sps.wilcoxon(nz, zero_method="wilcox", correction=False, mode=mode)
            check(rel_close(p[8], res.pvalue, 1e-9), "Wilcoxon p %r vs scipy %r" % (p[8], res.pvalue))
    # ranking: mean over the maneuvers every candidate completed (an unsettled
    # time censored at the horizon: the restricted mean), ties broken by fewer
    # failed + censored, then by index
    bad = [int(counts[c, 2] + counts[c, 4]) for c in range(nc)]
    for key, want in (("execution_time", rank_t), ("energy", rank_e)):
        use = np.all([r["status"] == 0 for r in rows], axis=0)
        if key == "execution_time":
            means = [censored_time(rows[c])[use].mean() if use.any() else np.nan
                     for c in range(nc)]
        else:
            means = [rows[c]["energy_total"][use].mean() if use.any() else np.nan
                     for c in range(nc)]
        order = sorted(range(nc), key=lambda c: (np.isnan(means[c]), means[c], bad[c], c))
        check(want == order, "ranking by %s: %s, want %s" % (key, want, order))

    # the JSON report agrees with the file
    with open(report) as fj:
        rep = json.load(fj)
    for c in range(nc):
        check(rel_close(rep["candidates"][c]["execution_time_s"]["mean"], stats_t[c][2], 1e-9),
              "JSON mean execution time")
        check(rep["candidates"][c]["failed"] == counts[c, 2], "JSON failures")

    # identical rows, statistics, comparisons and ranking in every other file
    ref_rows = rows_of(ref)
    tables = ["statistics/execution_time", "statistics/energy", "statistics/energy_positive",
              "statistics/execution_time_final",
              "statistics/counts", "comparison/paired", "ranking/execution_time", "ranking/energy"]
    with h5py.File(ref, "r") as f:
        ref_tables = [f[t][:] for t in tables]
    for path in others:
        with h5py.File(path, "r") as f:
            if path.endswith("r.h5"):  # the resumed files say so
                check(len(text(f.attrs["last_resumed_git_commit"])) > 0, "resume recorded")
            for t, want in zip(tables, ref_tables):
                check(f[t][:].tobytes() == want.tobytes(), "%s in %s equals the reference" % (t, path))
        other = rows_of(path)
        for c in range(nc):
            for field in ref_rows[c].dtype.names:  # bit for bit, NaN included
                check(other[c][field].tobytes() == ref_rows[c][field].tobytes(),
                      "field %s of candidate %d in %s equals the reference" % (field, c, path))
    print("test_doe_h5: %d failures" % failures)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
