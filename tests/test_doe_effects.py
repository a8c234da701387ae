#!/usr/bin/python3
"""Many-candidate statistics of a sweep's results file, recomputed from its rows.

usage: test_doe_effects.py RESULTS.h5

- main effects (/effects/main): per level, the mean over the maneuvers of
  the per-maneuver mean over the level's candidates, and its Student-t
  interval (scipy's t quantile);
- the common-maneuver means and the Pareto front (/effects/common_means);
- Friedman's test (/comparison/friedman) against scipy.stats.friedmanchisquare;
- Holm's adjustment of the paired Wilcoxon p values (/comparison/paired).
"""
import sys

import h5py
import numpy as np
from scipy import stats


def close(a, b, tol):
    return (np.isnan(a) and np.isnan(b)) or abs(a - b) <= tol * max(abs(a), abs(b), 1e-300)


def main(path):
    with h5py.File(path, "r") as f:
        nc = int(f.attrs["n_candidates"])
        conf = float(f["comparison"].attrs["confidence"])
        factors = f["factors"][:]
        tm = f.attrs["time_metric"]
        pointing = (tm.decode() if isinstance(tm, bytes) else tm) == "pointing_settling_time"
        values, usable, censored = [], [], []
        for c in range(nc):
            r = f["candidates/%d/maneuvers" % c][:]
            ok = (r["done"] == 1) & (r["status"] == 0)
            # the primary time, an unsettled one censored at the horizon
            if pointing:
                t, settled = r["pointing_settling_time"], r["pointing_settled"] == 1
            else:
                t, settled = r["execution_time"], np.all(r["settled"] == 1, axis=1)
            settled = settled & np.isfinite(t)
            values.append((np.where(settled, t, r["horizon"]), r["energy_total"]))
            usable.append((ok, ok))
            censored.append(ok & ~settled)
        effects = f["effects/main"][:]
        common = f["effects/common_means"][:]
        friedman = f["comparison/friedman"][:]
        paired = f["comparison/paired"][:]
    for e in effects:
        fac, lo, hi, m = int(e[0]), e[2], e[3], int(e[5])
        members = [c for c in range(nc) if lo <= factors[c, fac] <= hi]
        assert int(e[4]) == len(members), ("candidates at level", e)
        v = np.array([values[c][m] for c in members])
        u = np.array([usable[c][m] for c in members])
        cnt = u.sum(axis=0)
        y = np.where(u, v, 0).sum(axis=0)[cnt > 0] / cnt[cnt > 0]
        assert int(e[6]) == y.size
        if m == 0:
            cens = np.array([censored[c] for c in members])
            assert int(e[10]) == int(cens[u].sum()), ("censored at level", e)
        assert close(e[7], y.mean(), 1e-12), ("level mean", e[7], y.mean())
        half = stats.t.ppf(0.5 + 0.5 * conf, y.size - 1) * y.std(ddof=1) / np.sqrt(y.size)
        assert close(e[9] - e[7], half, 1e-9), ("interval", e[9] - e[7], half)
    for m in range(2):
        all_ok = np.all([usable[c][m] for c in range(nc)], axis=0)
        x = np.array([values[c][m][all_ok] for c in range(nc)])
        for c in range(nc):
            assert close(common[c, m], x[c].mean(), 1e-12), ("common mean", c, m)
        if m == 0:
            n_cens = sum(int(censored[c][all_ok].sum()) for c in range(nc))
            assert int(friedman[0, 4]) == n_cens, ("Friedman censored", friedman[0, 4], n_cens)
            for c in range(nc):
                assert int(common[c, 3]) == int(censored[c][all_ok].sum()), ("censored", c)
        res = stats.friedmanchisquare(*x)
        assert int(friedman[m, 0]) == all_ok.sum() and int(friedman[m, 1]) == nc
        assert close(friedman[m, 2], res.statistic, 1e-12), (friedman[m, 2], res.statistic)
        assert close(friedman[m, 3], res.pvalue, 1e-9), (friedman[m, 3], res.pvalue)
        # Holm over this metric's comparisons
        rows = paired[paired[:, 2] == m]
        p = rows[:, 8]
        order = np.argsort(p, kind="stable")
        adj = np.maximum.accumulate(np.minimum(1, (len(p) - np.arange(len(p))) * p[order]))
        want = np.empty_like(adj)
        want[order] = adj
        assert np.allclose(rows[:, 12], want, rtol=1e-15, atol=0), (rows[:, 12], want)
    # Pareto: not dominated in (mean time, mean energy)
    for c in range(nc):
        t, e = common[c, 0], common[c, 1]
        dominated = any(common[d, 0] <= t and common[d, 1] <= e and
                        (common[d, 0] < t or common[d, 1] < e) for d in range(nc) if d != c)
        assert common[c, 2] == (0 if dominated else 1), ("Pareto", c)
    print("effects: %d main effects, Friedman, Holm and the Pareto front match" % len(effects))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
