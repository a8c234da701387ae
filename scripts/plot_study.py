#!/usr/bin/python3
"""Figures of a pomlab study results file (docs/results.md, "Figures").

usage: /usr/bin/python3 scripts/plot_study.py RESULTS.h5 OUTDIR

Writes into OUTDIR:
  execution_time.png  distribution of the execution time per candidate (ms)
  energy.png          distribution of the expended energy per candidate (J)
  paired.png          every candidate against the first, maneuver by maneuver
                      (only with two candidates or more; a stale one is removed)

Needs Debian's python3-h5py and python3-matplotlib (run with /usr/bin/python3).
Only maneuvers that finished without failure are drawn; execution time also
needs every actuator to have settled (the same sets as the tables).
"""
import os
import sys
import textwrap

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.ticker import MaxNLocator  # noqa: E402


def load(path):
    """Candidate names and per-maneuver arrays (NaN where not usable)."""
    with h5py.File(path, "r") as f:
        n = int(f.attrs["n_candidates"])
        names, times, energies = [], [], []
        for c in range(n):
            g = f["candidates/%d" % c]
            names.append(g.attrs["name"].decode() if isinstance(g.attrs["name"], bytes)
                         else str(g.attrs["name"]))
            rows = g["maneuvers"][:]
            ok = (rows["done"] == 1) & (rows["status"] == 0)
            settled = ok & np.all(rows["settled"] == 1, axis=1)
            t = np.where(settled, rows["execution_time"], np.nan)
            e = np.where(ok, rows["energy_total"], np.nan)
            times.append(t)
            energies.append(e)
        study = f.attrs["study_name"]
        study = study.decode() if isinstance(study, bytes) else str(study)
    return study, names, times, energies


def distribution(ax_hist, ax_box, names, values, scale, unit, label):
    finite = [v[np.isfinite(v)] * scale for v in values]
    allv = np.concatenate([v for v in finite if v.size]) if any(v.size for v in finite) else []
    if len(allv) == 0:
        ax_hist.text(0.5, 0.5, "no usable maneuvers", ha="center", transform=ax_hist.transAxes)
        return
    bins = np.linspace(np.min(allv), np.max(allv), 41)
    if bins[0] == bins[-1]:
        bins = 10
    for name, v in zip(names, finite):
        ax_hist.hist(v, bins=bins, alpha=0.55,
                     label="%s (n=%d, mean %.3g %s)" % (name, v.size, np.mean(v) if v.size else
                                                       np.nan, unit))
    ax_hist.set_xlabel("%s (%s)" % (label, unit))
    ax_hist.set_ylabel("maneuvers")
    ax_hist.yaxis.set_major_locator(MaxNLocator(integer=True))  # counts
    ax_hist.legend(fontsize=8, loc="best")
    # long config names (montecarlo uses the config's `name`) would squeeze the axes
    labels = [textwrap.fill(name, 24) for name in names]
    ax_box.boxplot([v if v.size else [np.nan] for v in finite], vert=False, labels=labels,
                   whis=(5, 95), showmeans=True)
    ax_box.set_xlabel("%s (%s)\nbox: quartiles, whiskers: 5-95 %%, triangle: mean" % (label, unit))


def main(argv):
    if len(argv) != 3:
        sys.stderr.write(__doc__)
        return 2
    path, outdir = argv[1], argv[2]
    os.makedirs(outdir, exist_ok=True)
    study, names, times, energies = load(path)

    for fname, values, scale, unit, label in (
            ("execution_time.png", times, 1e3, "ms", "execution time"),
            ("energy.png", energies, 1.0, "J", "expended energy")):
        fig, (ax_hist, ax_box) = plt.subplots(2, 1, figsize=(8, 6.5),
                                              gridspec_kw={"height_ratios": [2.2, 1]})
        distribution(ax_hist, ax_box, names, values, scale, unit, label)
        fig.suptitle("study %s: %s per maneuver" % (study, label))
        fig.tight_layout()
        fig.savefig(os.path.join(outdir, fname), dpi=110)
        plt.close(fig)

    paired = os.path.join(outdir, "paired.png")
    if len(names) < 2:
        # one candidate: nothing to pair; never leave an empty or stale figure
        if os.path.exists(paired):
            os.remove(paired)
        return 0
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.6))
    for ax, values, scale, unit, label in ((axes[0], times, 1e3, "ms", "execution time"),
                                           (axes[1], energies, 1.0, "J", "expended energy")):
        lo, hi = np.inf, -np.inf
        for c in range(1, len(names)):
            both = np.isfinite(values[0]) & np.isfinite(values[c])
            x, y = values[0][both] * scale, values[c][both] * scale
            if x.size:
                ax.plot(x, y, ".", ms=3, alpha=0.6, label="%s (%d pairs)" % (names[c], x.size))
                lo, hi = min(lo, x.min(), y.min()), max(hi, x.max(), y.max())
        if np.isfinite(lo):
            ax.plot([lo, hi], [lo, hi], "k-", lw=0.8, label="equal")
        ax.set_xlabel("%s of %s (%s)" % (label, names[0], unit))
        ax.set_ylabel("%s of the other candidate (%s)" % (label, unit))
        ax.legend(fontsize=8)
    fig.suptitle("study %s: paired maneuvers (same targets)" % study)
    fig.tight_layout()
    fig.savefig(paired, dpi=110)
    plt.close(fig)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
