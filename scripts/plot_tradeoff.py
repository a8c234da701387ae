#!/usr/bin/python3
"""Work-precision plot of `pomlab tradeoff --csv` tables (docs/tradeoff.md).

usage: /usr/bin/python3 scripts/plot_tradeoff.py OUT.png NAME=FILE.csv [NAME=FILE.csv ...]

One panel per table (e.g. one per architecture): wall time per maneuver
against the worst relative error (the largest of the settling-time, energy
and trajectory errors), one marker per setting family, the reference error
floor and the recommended setting circled.
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

MARKERS = {
    "config": ("k", "*"),
    "rtol": ("tab:blue", "o"),
    "stiffness": ("tab:orange", "s"),
    "linsol": ("tab:gray", "D"),
    "scene": ("tab:green", "^"),
    "combined": ("tab:red", "v"),
    "rigid": ("tab:purple", "P"),
}
FLOOR = 1e-7  # errors below this are drawn at the floor (log axis)


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def main(argv):
    if len(argv) < 3 or "=" not in "".join(argv[2:]):
        sys.stderr.write(__doc__)
        return 2
    out = argv[1]
    tables = [a.split("=", 1) for a in argv[2:]]
    fig, axes = plt.subplots(1, len(tables), figsize=(6.5 * len(tables), 5.2), squeeze=False)
    for ax, (name, path) in zip(axes[0], tables):
        rows = read(path)
        seen = set()
        for r in rows:
            fam = r["family"]
            if fam == "reference":
                continue
            t = float(r["time_s"]) * 1e3
            e = float(r["err_max"])
            if not math.isfinite(t) or not math.isfinite(e):
                continue  # failed settings are listed in the table, not plotted
            colour, marker = MARKERS.get(fam, ("k", "x"))
            ax.loglog(max(e, FLOOR), t, marker=marker, color=colour, linestyle="none",
                      markersize=7, label=fam if fam not in seen else None)
            seen.add(fam)
            if r["recommended"] == "1":
                ax.loglog(max(e, FLOOR), t, marker="o", markersize=16, markerfacecolor="none",
                          markeredgecolor="k", linestyle="none", label="recommended")
            short = r["label"].replace("quasi-static+lumped", "qs+lumped")
            ax.annotate(short, (max(e, FLOOR), t), fontsize=6, xytext=(3, 2),
                        textcoords="offset points")
        # the rtol and stiffness sweeps as lines
        for fam in ("rtol", "stiffness"):
            pts = [(max(float(r["err_max"]), FLOOR), float(r["time_s"]) * 1e3) for r in rows
                   if r["family"] == fam and math.isfinite(float(r["err_max"]))]
            if pts:
                colour = MARKERS[fam][0]
                ax.loglog([p[0] for p in pts], [p[1] for p in pts], color=colour, alpha=0.4)
        ax.set_xlabel("worst relative error vs reference (settling, energy, trajectory)")
        ax.set_ylabel("wall time per maneuver (ms, median of repeats)")
        ax.set_title(name)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, loc="upper right")
    fig.tight_layout()
    fig.savefig(out, dpi=130)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
