#!/usr/bin/python3
"""plot_traces.py - a figure like Fig. 7 of Rahman, Rideout & Krouglicof (2012):
actuator positions (mm, or deg for rotary actuators) with their setpoints
(dotted), cumulative source energy (J) of the three actuators and the
platform orientation (ZYX Euler angles, deg) against time (ms), one maneuver
per architecture, side by side.

Input: trace files written by `pomlab simulate CFG --target ... --out F`
(HDF5 .h5 or CSV .csv, SI units; docs/dynamics.md section 10).

usage: /usr/bin/python3 scripts/plot_traces.py OUT.png LABEL=TRACE [LABEL=TRACE ...]
  e.g. /usr/bin/python3 scripts/plot_traces.py fig7.png 3P-S-S/S=a.h5 3S-P-S/S=b.h5
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def load(path):
    """Returns (t [s], q [n][3], energy [n][3] J, euler [n][3] rad, target [3] or
    None, unit) with q and target in the actuator's SI unit `unit` ("m" or
    "rad")."""
    if path.endswith(".h5"):
        import h5py

        with h5py.File(path, "r") as f:
            g = f["trace"]
            unit = g.attrs.get("actuator_unit", b"m")
            unit = unit.decode() if isinstance(unit, bytes) else str(unit)
            t, q, e, eul = g["t"][:], g["q"][:], g["energy"][:], g["euler_zyx"][:]
            target = None
            if "metrics" in f:
                m = f["metrics"].attrs
                target = m["target"] if "target" in m else m.get("target_m")
        return t, q, e, eul, target, unit
    t, q, e, eul, target = [], [], [], [], None
    with open(path, newline="") as fh:
        reader = csv.DictReader(fh)
        unit = "rad" if "q1_rad" in (reader.fieldnames or []) else "m"
        for row in reader:
            t.append(float(row["t_s"]))
            q.append([float(row["q%d_%s" % (k, unit)]) for k in (1, 2, 3)])
            e.append([float(row["E%d_J" % k]) for k in (1, 2, 3)])
            eul.append([float(row[a + "_rad"]) for a in ("psi", "theta", "phi")])
            if "q1_set_" + unit in row:
                target = [float(row["q%d_set_%s" % (k, unit)]) for k in (1, 2, 3)]
    return t, q, e, eul, target, unit


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
    fig, axes = plt.subplots(3, len(runs), figsize=(5.2 * len(runs), 10.0), squeeze=False)
    colors = ["tab:blue", "tab:orange", "tab:green"]
    for col, (label, path) in enumerate(runs):
        t, q, e, eul, target, unit = load(path)
        # text units of docs/conventions.md: ms, mm or deg, J
        f, shown = (1e3, "mm") if unit == "m" else (180.0 / math.pi, "deg")
        t_ms = [1e3 * x for x in t]
        ax_q, ax_e, ax_o = axes[0][col], axes[1][col], axes[2][col]
        for k in range(3):
            ax_q.plot(t_ms, [f * row[k] for row in q], color=colors[k], label="actuator %d" % (k + 1))
            ax_e.plot(t_ms, [row[k] for row in e], color=colors[k], label="actuator %d" % (k + 1))
            if target is not None:
                ax_q.axhline(f * target[k], color=colors[k], lw=0.6, ls=":")
        for k, name in enumerate(("psi (yaw)", "theta (pitch)", "phi (roll)")):
            ax_o.plot(t_ms, [math.degrees(row[k]) for row in eul], color=colors[k], label=name)
        ax_q.set_title("Actuator responses: %s" % label)
        ax_q.set_xlabel("Time (ms)")
        ax_q.set_ylabel("Position (%s)%s" % (shown, ", setpoints dotted" if target is not None
                                              else ""))
        ax_e.set_title("Energy consumption: %s" % label)
        ax_e.set_xlabel("Time (ms)")
        ax_e.set_ylabel("Energy (J)")
        ax_o.set_title("Platform orientation: %s" % label)
        ax_o.set_xlabel("Time (ms)")
        ax_o.set_ylabel("ZYX Euler angle (deg)")
        for ax in (ax_q, ax_e, ax_o):
            ax.grid(True, lw=0.3)
            ax.legend(loc="best", fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
