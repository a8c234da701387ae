#!/usr/bin/python3
"""Work-precision plot of `pomlab tradeoff --csv` tables (docs/tradeoff.md).

usage: /usr/bin/python3 scripts/plot_tradeoff.py OUT.png NAME=FILE.csv [NAME=FILE.csv ...]

One column per table (e.g. one per architecture): wall time per maneuver
against the worst relative error against the reference (top: the largest of
the settling-time, energy and trajectory errors; middle: the settling-time
error alone), one marker per setting family, the recommended setting
circled; bottom: the work-precision curves, wall time against the
integration error alone (each row against its own model at a tight
tolerance), one line per rtol family (parasitic and rigid).
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
    fig, axes = plt.subplots(3, len(tables), figsize=(6.5 * len(tables), 15), squeeze=False)
    for col, (name, path) in enumerate(tables):
        rows = read(path)
        for row, key in enumerate(("err_max", "err_settle")):
            panel(axes[row][col], rows, key, name)
        work_precision(axes[2][col], rows, name)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    return 0


# Offsets (points) tried in turn for a label, nearest first: a label takes the
# first that overlaps no label placed before it (the main cluster has a dozen
# settings within a few percent of each other); when none is free, the one
# that overlaps least.
OFFSETS = sorted(((dx, dy) for dx in (4, -4, 40, -40) for dy in range(-70, 71, 9)),
                 key=lambda o: abs(o[0]) + abs(o[1] - 2))


def overlap(a, b):
    """Area shared by two boxes (x0, y0, x1, y1)."""
    return max(0.0, min(a[2], b[2]) - max(a[0], b[0])) * max(0.0, min(a[3], b[3]) - max(a[1], b[1]))


def place_labels(ax, labels, fontsize=6):
    """Annotates (x, y, text) points without overlaps where an offset allows,
    with a leader line when the label moved away from its point."""
    ax.autoscale_view()
    fig = ax.figure
    fig.canvas.draw()  # final limits and transforms
    px_per_pt = fig.dpi / 72.0
    placed = []  # boxes (x0, y0, x1, y1) in display pixels
    for x, y, text in sorted(labels, key=lambda p: (p[1], p[0])):
        X, Y = ax.transData.transform((x, y))
        w = 0.62 * fontsize * len(text) * px_per_pt  # a rough text width
        h = 1.2 * fontsize * px_per_pt
        best = None
        for dx, dy in OFFSETS:
            x0 = X + dx * px_per_pt - (w if dx < 0 else 0)
            y0 = Y + dy * px_per_pt
            box = (x0, y0, x0 + w, y0 + h)
            cost = sum(overlap(box, b) for b in placed)
            if best is None or cost < best[0]:
                best = (cost, dx, dy, box)
            if cost == 0:
                break
        _, dx, dy, box = best
        placed.append(box)
        far = abs(dy) > 5 or abs(dx) > 5
        ax.annotate(text, (x, y), fontsize=fontsize, xytext=(dx, dy), textcoords="offset points",
                    ha="right" if dx < 0 else "left",
                    arrowprops=dict(arrowstyle="-", lw=0.4, color="0.5") if far else None)


def panel(ax, rows, key, name):
    labels = []
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
            labels.append((max(e, FLOOR), t,
                           r["label"].replace("quasi-static+lumped", "qs+lumped")))
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
        place_labels(ax, labels)


def work_precision(ax, rows, name):
    """Wall time against the integration error (int_max) of the two rtol
    families, each point labelled with its rtol."""
    families = (("parasitic rtol", "tab:blue", "o",
                 lambda r: r["family"] == "rtol"),
                ("rigid rtol", "tab:purple", "P",
                 lambda r: r["family"] == "rigid" and "quasi-static" not in r["label"]),
                ("rigid quasi-static rtol", "tab:red", "v",
                 lambda r: r["family"] == "rigid" and "quasi-static" in r["label"]))
    labels = []
    for title, colour, marker, member in families:
        pts = []
        for r in rows:
            if "int_max" not in r or not member(r):
                continue
            t, e = float(r["time_s"]) * 1e3, float(r["int_max"])
            if math.isfinite(t) and math.isfinite(e) and e > 0:  # no floor: the curve goes low
                pts.append((e, t, r["label"].split("rtol ")[-1]))
        if pts:
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], color=colour, marker=marker,
                      label=title)
            labels += pts
    ax.set_xlabel("integration error: worst of the three vs its own model at tight rtol")
    ax.set_ylabel("wall time per maneuver (ms, median of repeats)")
    ax.set_title(name + ": work-precision (labels: rtol)")
    ax.grid(True, which="both", alpha=0.3)
    if labels:
        ax.legend(fontsize=7, loc="best")
        place_labels(ax, labels)


if __name__ == "__main__":
    sys.exit(main(sys.argv))
