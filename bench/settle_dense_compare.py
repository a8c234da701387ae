#!/usr/bin/python3
"""Settling times of one study from three runs compared maneuver by maneuver
(bench/README.md, "Issue 20 item 4: settling on the dense output").

    settle_dense_compare.py REF.h5 OLD.h5 NEW.h5

REF: the old build with maneuver.output_dt_ms = 0.001 (a 1 us grid: the old
linear-interpolation method's converged value); OLD: the old build at the
shipped 0.1 ms grid; NEW: this build (the crossing located on CVODE's
interpolant, independent of the grid). For every candidate and metric it
prints the max and rms of |OLD - REF| and |NEW - REF| (s, or the metric's
unit) over the maneuvers where all three are finite, the max relative
difference, and how many maneuvers differ in finiteness (settled/unsettled).
Rows are matched by position; the targets are checked to be identical.
"""
import sys

import h5py
import numpy as np

METRICS = ["settling_time", "settling_time_final", "execution_time",
           "pointing_settling_time", "max_abs_q", "tracking_rms_error"]


def rows(path):
    with h5py.File(path, "r") as f:
        g = f["candidates"]
        return {k: g[k]["maneuvers"][:] for k in sorted(g, key=int)}


def stats(d, ref):
    if d.size == 0:
        return "      -            -            -"
    rel = np.abs(d) / np.where(np.abs(ref) > 0, np.abs(ref), np.nan)
    return "%12.3e %12.3e %12.3e" % (np.max(np.abs(d)), np.sqrt(np.mean(d * d)),
                                      np.nanmax(rel) if np.any(np.isfinite(rel)) else np.nan)


def main(argv):
    if len(argv) != 4:
        sys.exit(__doc__)
    ref, old, new = (rows(p) for p in argv[1:])
    worst = 0.0
    for c in ref:
        r, o, n = ref[c], old[c], new[c]
        if not (np.array_equal(r["target"], o["target"]) and np.array_equal(r["target"], n["target"])):
            sys.exit("candidate %s: the targets differ: not the same maneuvers" % c)
        print("candidate %s (%d maneuvers)" % (c, len(r)))
        print("  %-24s %-38s %-38s %s" % ("metric", "old 0.1 ms grid - 1 us: max rms rel",
                                          "new dense - 1 us: max rms rel", "finiteness differs"))
        for k in METRICS:
            a, b, x = r[k].ravel(), o[k].ravel(), n[k].ravel()
            ok = np.isfinite(a) & np.isfinite(b) & np.isfinite(x)
            nf = int(np.sum(np.isfinite(a) != np.isfinite(x)))
            nfo = int(np.sum(np.isfinite(a) != np.isfinite(b)))
            print("  %-24s %s  %s  old %d new %d" % (k, stats(b[ok] - a[ok], a[ok]),
                                                     stats(x[ok] - a[ok], a[ok]), nfo, nf))
            if k.endswith("time") and ok.any():
                worst = max(worst, float(np.max(np.abs(x[ok] - a[ok]))))
    print("largest |new - 1 us| over every time metric: %.3e s" % worst)


if __name__ == "__main__":
    main(sys.argv)
