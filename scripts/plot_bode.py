#!/usr/bin/python3
"""plot_bode.py - Bode plots of the small-signal frequency response written
by `pomlab simulate CFG --target Q --bode F.json` (docs/capability.md,
"Small-signal frequency response"): the closed loop T per fixed axis and in
the worst direction (left), each actuator's loop gain L broken at its
voltage input (right), magnitude (dB) over phase (deg), with the -3 dB
bandwidths, gain crossovers and the parasitic modes marked.

usage: /usr/bin/python3 scripts/plot_bode.py BODE.json OUT.png [TITLE]
"""
import json
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def arr(values):
    """A JSON list with nulls as NaN."""
    return np.array([np.nan if v is None else float(v) for v in values])


def fmt(v, unit):
    return "inf" if v is None else "%.3g %s" % (v, unit)


def main(argv):
    if len(argv) not in (3, 4):
        sys.stderr.write(__doc__)
        return 2
    with open(argv[1]) as f:
        d = json.load(f)
    fr = arr(d["f_hz"])
    fig, axes = plt.subplots(2, 2, figsize=(13, 7.5), sharex=True, layout="constrained")
    (tm, lm), (tp, lp) = axes
    for k, name in enumerate("xyz"):
        c = d["axis"][k]
        bw = d["bandwidth_hz"][k]
        tm.semilogx(fr, arr(c["mag_db"]), label="about %s (bandwidth %s)" % (name, fmt(bw, "Hz")))
        tp.semilogx(fr, arr(c["phase_deg"]), label="about %s" % name)
    w = d["worst"]
    tm.semilogx(fr, arr(w["mag_db"]), "k--",
                label="worst direction, relative (bandwidth %s)" % fmt(d["bandwidth_worst_hz"], "Hz"))
    tp.semilogx(fr, arr(w["phase_deg"]), "k--", label="worst direction")
    tm.axhline(-3.0, color="0.6", lw=0.8)
    for k, c in enumerate(d["loop"]):
        lm.semilogx(fr, arr(c["mag_db"]),
                    label="actuator %d: crossover %s, PM %s, GM %s"
                    % (k + 1, fmt(d["crossover_hz"][k], "Hz"), fmt(d["phase_margin_deg"][k], "deg"),
                       fmt(d["gain_margin_db"][k], "dB")))
        lp.semilogx(fr, arr(c["phase_deg"]), label="actuator %d" % (k + 1))
    lm.axhline(0.0, color="0.6", lw=0.8)
    lp.axhline(-180.0, color="0.6", lw=0.8)
    for f in d.get("mode_hz", []):
        if f is not None and fr[0] <= f <= fr[-1]:
            for ax in (tm, lm):
                ax.axvline(f, color="tab:red", lw=0.5, alpha=0.5)
    tm.set_title("closed loop T: setpoint rotation -> platform rotation")
    lm.set_title("loop gain L of each actuator (red: parasitic modes)")
    tm.set_ylabel("magnitude (dB)")
    tp.set_ylabel("phase (deg)")
    for ax in (tp, lp):
        ax.set_xlabel("frequency (Hz)")
    for ax in axes.flat:
        ax.grid(True, which="both", lw=0.3)
        ax.legend(fontsize=7)
    lo = np.nanmin(arr(d["axis"][0]["mag_db"]))
    tm.set_ylim(max(lo, -80.0) - 5.0, 10.0)
    title = argv[3] if len(argv) == 4 else "small-signal frequency response at q = %s" % d["pose_q"]
    fig.suptitle(title)
    fig.savefig(argv[2], dpi=110)
    return 0 if math.isfinite(fr[0]) else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
