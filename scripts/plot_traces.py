#!/usr/bin/python3
"""plot_traces.py - a figure like Fig. 7 of Rahman, Rideout & Krouglicof (2012):
actuator positions (mm) and cumulative source energy (J) of the three
actuators against time (ms), one maneuver per architecture, side by side.

Input: trace files written by `pomlab simulate CFG --target ... --out F`
(HDF5 .h5 or CSV .csv, SI units; docs/dynamics.md section 10).

usage: /usr/bin/python3 scripts/plot_traces.py OUT.png LABEL=TRACE [LABEL=TRACE ...]
  e.g. /usr/bin/python3 scripts/plot_traces.py fig7.png 3P-S-S/S=a.h5 3S-P-S/S=b.h5
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def load(path):
    """Returns (t [s], q [n][3] m, energy [n][3] J, target or None)."""
    if path.endswith(".h5"):
        import h5py

        with h5py.File(path, "r") as f:
            g = f["trace"]
            t = g["t"][:]
            q = g["q"][:]
            e = g["energy"][:]
            target = f["metrics"].attrs["target_m"] if "metrics" in f else None
        return t, q, e, target
    t, q, e = [], [], []
    with open(path, newline="") as fh:
        for row in csv.DictReader(fh):
            t.append(float(row["t_s"]))
            q.append([float(row["q%d_m" % k]) for k in (1, 2, 3)])
            e.append([float(row["E%d_J" % k]) for k in (1, 2, 3)])
    return t, q, e, None


def main(argv):
    if len(argv) >= 2 and argv[1] in ("-h", "--help"):
        sys.stdout.write(__doc__)
        return 0
    if len(argv) < 3 or any("=" not in a for a in argv[2:]):
        sys.stderr.write(__doc__)
        return 2
    out = argv[1]
    runs = [a.split("=", 1) for a in argv[2:]]
    for label, path in runs:
        if not os.path.isfile(path):
            sys.stderr.write("plot_traces.py: %s=%s: no such trace file\n" % (label, path))
            return 2
    fig, axes = plt.subplots(2, len(runs), figsize=(5.2 * len(runs), 7.0), squeeze=False)
    colors = ["tab:blue", "tab:orange", "tab:green"]
    for col, (label, path) in enumerate(runs):
        t, q, e, target = load(path)
        t_ms = [1e3 * x for x in t]
        ax_q, ax_e = axes[0][col], axes[1][col]
        for k in range(3):
            ax_q.plot(t_ms, [1e3 * row[k] for row in q], color=colors[k], label="actuator %d" % (k + 1))
            ax_e.plot(t_ms, [row[k] for row in e], color=colors[k], label="actuator %d" % (k + 1))
            if target is not None:
                ax_q.axhline(1e3 * target[k], color=colors[k], lw=0.6, ls=":")
        ax_q.set_title("Actuator responses: %s" % label)
        ax_q.set_xlabel("Time (ms)")
        ax_q.set_ylabel("Position (mm)")
        ax_e.set_title("Energy consumption: %s" % label)
        ax_e.set_xlabel("Time (ms)")
        ax_e.set_ylabel("Energy (J)")
        for ax in (ax_q, ax_e):
            ax.grid(True, lw=0.3)
            ax.legend(loc="best", fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
