#!/usr/bin/python3
"""Figures of a pomlab study results file (docs/results.md, "What you see").

usage: /usr/bin/python3 scripts/plot_study.py RESULTS.h5 OUTDIR

Writes into OUTDIR:
  execution_time.png  execution time per candidate (ms): histograms and box
                      plots up to 6 candidates, beyond one line per candidate
                      (median, quartiles, 5-95 %, mean) sorted by mean
  energy.png          the same for the expended energy (J)
  paired.png          2 to 4 candidates: each against the first, maneuver by maneuver
  main_effects.png    sweeps: mean and interval of each response per factor level
  heatmap.png         sweeps of 2+ factors: mean responses over the first two
  pareto.png          3+ candidates: mean execution time against mean energy,
                      the Pareto front marked
Figures that a study does not call for are removed from OUTDIR, so the folder
never shows a stale one.

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

FEW = 6          # up to this many candidates: overlapping histograms are readable
ALL_PAIRS = 4    # paired scatter up to this many (as the comparisons, POM_DOE_ALL_PAIRS_MAX)
FIGURES = ("execution_time.png", "energy.png", "paired.png", "main_effects.png", "heatmap.png",
           "pareto.png")
RESPONSES = (("execution_time", 1e3, "ms", "execution time"),
             ("energy", 1.0, "J", "expended energy"))


def text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


def load(path):
    """Everything the figures need; per-maneuver rows only for few candidates."""
    d = {}
    with h5py.File(path, "r") as f:
        n = int(f.attrs["n_candidates"])
        d["study"] = text(f.attrs["study_name"])
        d["names"] = [text(f["candidates/%d" % c].attrs["name"]) for c in range(n)]
        d["stats"] = {key: f["statistics/" + key][:] for key, _, _, _ in RESPONSES}
        if "factors" in f:
            d["factors"] = f["factors"][:]
            d["factor_labels"] = text(f["factors"].attrs["labels"]).split(",")
        if "effects" in f:
            d["effects"] = f["effects/main"][:]
            d["common"] = f["effects/common_means"][:]
        if n <= FEW:
            d["rows"] = {"execution_time": [], "energy": []}
            for c in range(n):
                rows = f["candidates/%d/maneuvers" % c][:]
                ok = (rows["done"] == 1) & (rows["status"] == 0)
                settled = ok & np.all(rows["settled"] == 1, axis=1)
                d["rows"]["execution_time"].append(
                    np.where(settled, rows["execution_time"], np.nan))
                d["rows"]["energy"].append(np.where(ok, rows["energy_total"], np.nan))
    return d


def short_names(d):
    """Sweep candidates by their factor values only (the base name is common)."""
    if "factors" not in d:
        return d["names"]
    return [" ".join("%s=%.4g" % (lab, v) for lab, v in zip(d["factor_labels"], row))
            for row in d["factors"]]


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


def few_candidates(d, key, scale, unit, label, out):
    fig, (ax_hist, ax_box) = plt.subplots(2, 1, figsize=(8, 6.5),
                                          gridspec_kw={"height_ratios": [2.2, 1]})
    distribution(ax_hist, ax_box, d["names"], d["rows"][key], scale, unit, label)
    fig.suptitle("study %s: %s per maneuver" % (d["study"], label))
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def many_candidates(d, key, scale, unit, label, out):
    """One line per candidate from its statistics, sorted by mean: legible at
    64 candidates where histograms would overlap."""
    s = d["stats"][key]  # n,max,mean,min,sigma,median,p05,p25,p75,p95
    names = short_names(d)
    order = np.argsort(np.where(np.isfinite(s[:, 2]), s[:, 2], np.inf))[::-1]
    n = len(order)
    fig, ax = plt.subplots(figsize=(8, 1.2 + 0.16 * n))
    y = np.arange(n)
    ax.hlines(y, s[order, 6] * scale, s[order, 9] * scale, color="0.6", lw=1, label="5-95 %")
    ax.hlines(y, s[order, 7] * scale, s[order, 8] * scale, color="C0", lw=4, label="quartiles")
    ax.plot(s[order, 5] * scale, y, "|", color="k", ms=7, label="median")
    ax.plot(s[order, 2] * scale, y, "o", color="C3", ms=3, label="mean")
    ax.set_yticks(y)
    ax.set_yticklabels([names[c] for c in order], fontsize=6.5 if n > 32 else 8)
    ax.set_ylim(-0.7, n - 0.3)
    ax.set_xlabel("%s (%s)" % (label, unit))
    ax.grid(axis="x", alpha=0.3)
    ax.legend(fontsize=7, loc="lower right", ncol=4)
    ax.set_title("study %s: %s per maneuver, %d candidates (best at the bottom)"
                 % (d["study"], label, n), fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def paired(d, out):
    names, values = d["names"], d["rows"]
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.6))
    for ax, (key, scale, unit, label) in zip(axes, RESPONSES):
        v = values[key]
        lo, hi = np.inf, -np.inf
        for c in range(1, len(names)):
            both = np.isfinite(v[0]) & np.isfinite(v[c])
            x, y = v[0][both] * scale, v[c][both] * scale
            if x.size:
                ax.plot(x, y, ".", ms=3, alpha=0.6, label="%s (%d pairs)" % (names[c], x.size))
                lo, hi = min(lo, x.min(), y.min()), max(hi, x.max(), y.max())
        if np.isfinite(lo):
            ax.plot([lo, hi], [lo, hi], "k-", lw=0.8, label="equal")
        ax.set_xlabel("%s of %s (%s)" % (label, names[0], unit))
        ax.set_ylabel("%s of the other candidate (%s)" % (label, unit))
        ax.legend(fontsize=8)
    fig.suptitle("study %s: paired maneuvers (same targets)" % d["study"])
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def main_effects(d, out):
    e = d["effects"]  # factor,level,lo,hi,n_candidates,metric,n,mean,ci_low,ci_high
    labels = d["factor_labels"]
    nf = len(labels)
    fig, axes = plt.subplots(nf, 2, figsize=(9, 2.8 * nf + 0.6), squeeze=False)
    for f in range(nf):
        vals = d["factors"][:, f]
        logx = np.all(vals > 0) and vals.max() / vals.min() > 8
        for m, (key, scale, unit, label) in enumerate(RESPONSES):
            ax = axes[f][m]
            r = e[(e[:, 0] == f) & (e[:, 5] == m)]
            x = 0.5 * (r[:, 2] + r[:, 3])
            mean = r[:, 7] * scale
            err = np.vstack([mean - r[:, 8] * scale, r[:, 9] * scale - mean])
            ax.errorbar(x, mean, yerr=np.nan_to_num(err), fmt="o-", ms=4, capsize=3)
            if logx:
                ax.set_xscale("log")
            ax.set_xlabel(labels[f])
            ax.set_ylabel("%s (%s)" % (label, unit))
            ax.grid(alpha=0.3)
    fig.suptitle("study %s: main effects (mean over each level's candidates, %s)"
                 % (d["study"], "bars: interval over the maneuvers"), fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def levels(vals):
    """Distinct values (at most 12) or 8 equal-width bins, as the C tables."""
    u = np.unique(vals)
    if u.size <= 12:
        return np.searchsorted(u, vals), ["%.4g" % v for v in u]
    edges = np.linspace(u[0], u[-1], 9)
    idx = np.clip(((vals - u[0]) / (edges[1] - edges[0])).astype(int), 0, 7)
    return idx, ["%.3g-%.3g" % (edges[i], edges[i + 1]) for i in range(8)]


def heatmap(d, out):
    i0, lab0 = levels(d["factors"][:, 0])
    i1, lab1 = levels(d["factors"][:, 1])
    fig, axes = plt.subplots(1, 2, figsize=(11, 1.6 + 0.45 * len(lab0)))
    for m, (ax, (key, scale, unit, label)) in enumerate(zip(axes, RESPONSES)):
        grid = np.full((len(lab0), len(lab1)), np.nan)
        for a in range(len(lab0)):
            for b in range(len(lab1)):
                sel = (i0 == a) & (i1 == b) & np.isfinite(d["common"][:, m])
                if sel.any():
                    grid[a, b] = d["common"][sel, m].mean() * scale
        im = ax.imshow(grid, origin="lower", aspect="auto", cmap="viridis")
        ax.set_xticks(range(len(lab1)))
        ax.set_xticklabels(lab1, rotation=45, ha="right", fontsize=7)
        ax.set_yticks(range(len(lab0)))
        ax.set_yticklabels(lab0, fontsize=7)
        ax.set_xlabel(d["factor_labels"][1])
        ax.set_ylabel(d["factor_labels"][0])
        if grid.size <= 100:
            mid = np.nanmean(grid)
            for a in range(len(lab0)):
                for b in range(len(lab1)):
                    if np.isfinite(grid[a, b]):
                        ax.text(b, a, "%.4g" % grid[a, b], ha="center", va="center", fontsize=6,
                                color="w" if grid[a, b] < mid else "k")
        fig.colorbar(im, ax=ax, label="mean %s (%s)" % (label, unit))
    fig.suptitle("study %s: mean over the maneuvers every candidate completed" % d["study"],
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def pareto(d, out):
    cm = d["common"]  # execution_time_s, energy_J, pareto
    names = short_names(d)
    fig, ax = plt.subplots(figsize=(11, 5.5))
    ok = np.isfinite(cm[:, 0]) & np.isfinite(cm[:, 1])
    front = ok & (cm[:, 2] == 1)
    ax.plot(cm[ok & ~front, 0] * 1e3, cm[ok & ~front, 1], "o", color="0.65", ms=4,
            label="dominated")
    order = np.argsort(cm[front, 0])
    fx, fy = cm[front, 0][order] * 1e3, cm[front, 1][order]
    ax.plot(fx, fy, "o-", color="C3", ms=5, label="Pareto front (%d)" % front.sum())
    # front points numbered along the front, their names listed beside the
    # axes (names at the points would overlap where the front is dense)
    idx = np.nonzero(front)[0][order]
    for j, (x, y) in enumerate(zip(fx, fy)):
        ax.annotate(str(j + 1), (x, y), xytext=(3, 4), textcoords="offset points", fontsize=7)
    listing = "\n".join("%d: %s" % (j + 1, textwrap.shorten(names[c], 48))
                        for j, c in enumerate(idx[:40]))
    if len(idx) > 40:
        listing += "\n... (%d more: see the Pareto table)" % (len(idx) - 40)
    ax.text(1.02, 1.0, "Pareto front\n" + listing, transform=ax.transAxes, va="top", fontsize=6.5,
            family="monospace")
    ax.set_xlabel("mean execution time (ms)")
    ax.set_ylabel("mean expended energy (J)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title("study %s: %d candidates, means over the common maneuvers"
                 % (d["study"], len(names)), fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def main(argv):
    if len(argv) != 3:
        sys.stderr.write(__doc__)
        return 2
    path, outdir = argv[1], argv[2]
    os.makedirs(outdir, exist_ok=True)
    d = load(path)
    n = len(d["names"])
    made = []
    for key, scale, unit, label in RESPONSES:
        name = "%s.png" % key
        (few_candidates if n <= FEW else many_candidates)(d, key, scale, unit, label,
                                                          os.path.join(outdir, name))
        made.append(name)
    if 2 <= n <= ALL_PAIRS:  # one candidate has no pairs: no (empty) figure
        paired(d, os.path.join(outdir, "paired.png"))
        made.append("paired.png")
    if "factors" in d and "effects" in d and d["effects"].size:
        main_effects(d, os.path.join(outdir, "main_effects.png"))
        made.append("main_effects.png")
        if d["factors"].shape[1] >= 2:
            heatmap(d, os.path.join(outdir, "heatmap.png"))
            made.append("heatmap.png")
    if n >= 3 and "common" in d:
        pareto(d, os.path.join(outdir, "pareto.png"))
        made.append("pareto.png")
    for name in FIGURES:
        if name not in made and os.path.exists(os.path.join(outdir, name)):
            os.remove(os.path.join(outdir, name))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
