#!/usr/bin/python3
"""Work-precision plot of `pomlab tradeoff --csv` tables (docs/tradeoff.md).

usage: /usr/bin/python3 scripts/plot_tradeoff.py OUT.png NAME=FILE.csv [NAME=FILE.csv ...]

One column per table (e.g. one per architecture): wall time per maneuver
against the worst relative error (top: the largest of the settling-time,
energy and trajectory errors; bottom: the settling-time error alone), one
marker per setting family, the recommended setting circled.
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
    fig, axes = plt.subplots(2, len(tables), figsize=(6.5 * len(tables), 10), squeeze=False)
    for col, (name, path) in enumerate(tables):
        rows = read(path)
        for row, key in enumerate(("err_max", "err_settle")):
            panel(axes[row][col], rows, key, name)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    return 0


def panel(ax, rows, key, name):
    if True:
        seen = set()
        for r in rows:
            fam = r["family"]
            if fam == "reference":
                continue
            t = float(r["time_s"]) * 1e3
            e = float(r[key])
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
            pts = [(max(float(r[key]), FLOOR), float(r["time_s"]) * 1e3) for r in rows
                   if r["family"] == fam and math.isfinite(float(r[key]))]
            if pts:
                colour = MARKERS[fam][0]
                ax.loglog([p[0] for p in pts], [p[1] for p in pts], color=colour, alpha=0.4)
        ax.set_xlabel("worst relative error vs reference: " +
                      ("max of settling, energy, trajectory" if key == "err_max"
                       else "execution (settling) time"))
        ax.set_ylabel("wall time per maneuver (ms, median of repeats)")
        ax.set_title(name)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, loc="best")


if __name__ == "__main__":
    sys.exit(main(sys.argv))
