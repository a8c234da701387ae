#!/usr/bin/python3
"""compare_h5.py OLD.h5 NEW.h5 [REF.h5] [--rows N] - per-metric comparison of
two study results files (bench/README.md, "Throughput"): for every candidate
and every per-maneuver metric, the largest relative difference NEW vs OLD over
the first N maneuver rows (all by default), and with REF (the same study at a
tight tolerance) the largest relative error of OLD and of NEW against it, and
the root-mean-square error of each against it over the maneuvers, scaled by
the metric's median magnitude in REF (a measure that single near-zero
values, such as a small actuator's energy, do not dominate).
Exit 0 when every metric of NEW is within 1e-4 relative of OLD, or (with REF)
no farther from REF than OLD; 1 otherwise; 2 on bad usage."""
import sys

import h5py
import numpy as np

METRICS = ["execution_time", "settling_time", "settling_time_final", "pointing_settling_time",
           "final_pointing_error", "tracking_rms_error", "energy", "energy_positive",
           "energy_total", "peak_voltage", "saturation_time", "final_q", "max_abs_q"]
TOL = 1e-4


def rows(path, n):
    out = {}
    with h5py.File(path, "r") as f:
        for c in f["candidates"]:
            d = f["candidates"][c]["maneuvers"][:]
            name = f["candidates"][c].attrs.get("name", c)
            name = name.decode() if isinstance(name, bytes) else str(name)
            out[name] = d[:n] if n else d
    return out


def rel(a, b):
    """largest |a - b| / |b| over finite pairs; NaN pattern mismatches count as inf"""
    a = np.asarray(a, float).ravel()
    b = np.asarray(b, float).ravel()
    if (np.isnan(a) != np.isnan(b)).any():
        return np.inf
    ok = ~np.isnan(b)
    if not ok.any():
        return 0.0
    den = np.maximum(np.abs(b[ok]), 1e-300)
    return float(np.max(np.abs(a[ok] - b[ok]) / den))


def rms_scaled(a, ref):
    """root-mean-square of |a - ref| / median |ref| over finite pairs"""
    a = np.asarray(a, float).ravel()
    ref = np.asarray(ref, float).ravel()
    ok = ~(np.isnan(a) | np.isnan(ref))
    if not ok.any():
        return 0.0
    scale = np.median(np.abs(ref[ok]))
    if not scale > 0:
        scale = 1.0
    return float(np.sqrt(np.mean(((a[ok] - ref[ok]) / scale) ** 2)))


def main(argv):
    n = 0
    if "--rows" in argv:
        i = argv.index("--rows")
        n = int(argv[i + 1])
        argv = argv[:i] + argv[i + 2:]
    if len(argv) not in (3, 4):
        print(__doc__, file=sys.stderr)
        return 2
    old, new = rows(argv[1], n), rows(argv[2], n)
    ref = rows(argv[3], n) if len(argv) == 4 else None
    ok = True
    for c in old:
        if c not in new:
            print(f"candidate {c}: missing in {argv[2]}")
            ok = False
            continue
        o, w = old[c], new[c]
        m = min(len(o), len(w))
        o, w = o[:m], w[:m]
        st = (o["status"] != 0).sum(), (w["status"] != 0).sum()
        steps = o["steps"].sum(), w["steps"].sum()
        print(f"candidate {c}: {m} maneuvers, failed old {st[0]} new {st[1]}, "
              f"steps old {steps[0]} new {steps[1]} ({steps[1] / max(steps[0], 1):.2f}x)")
        hdr = f"  {'metric':22s} {'new vs old':>11s}"
        if ref:
            hdr += f" {'old vs ref':>11s} {'new vs ref':>11s} {'rms old':>9s} {'rms new':>9s}"
        print(hdr)
        for k in METRICS:
            if k not in o.dtype.names:
                continue
            d = rel(w[k], o[k])
            line = f"  {k:22s} {d:11.2e}"
            good = d <= TOL
            if ref:
                r = ref[c][:m]
                eo, en = rel(o[k], r[k]), rel(w[k], r[k])
                line += f" {eo:11.2e} {en:11.2e}"
                line += f" {rms_scaled(o[k], r[k]):9.2e} {rms_scaled(w[k], r[k]):9.2e}"
                good = good or en <= eo
            ok = ok and good
            print(line + ("" if good else "   <- differs"))
    print("verdict:", "unchanged within 1e-4 or closer to the reference" if ok else "CHANGED")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
