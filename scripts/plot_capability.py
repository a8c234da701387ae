#!/usr/bin/python3
"""plot_capability.py - the capability map of `pomlab capability CFG --plots
DIR` (DIR/capability_map.csv) as three slices through home, (theta, phi) at
psi = 0, (psi, phi) at theta = 0 and (psi, theta) at phi = 0, coloured by the
inscribed angular acceleration (top row, deg/s^2), the inscribed steady
rate (middle row, deg/s) and, when the map has them, the worst-direction
-3 dB bandwidth (bottom row, Hz) on its own sub-grid (docs/capability.md
sections 4 and 7).

usage: /usr/bin/python3 scripts/plot_capability.py MAP.csv OUT.png [TITLE]
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

FIGURES = (("acc_inscribed_deg_s2", "inscribed acceleration (deg/s$^2$)"),
           ("rate_inscribed_deg_s", "inscribed steady rate (deg/s)"),
           ("bw_worst_hz", "worst-direction bandwidth (Hz)"))


def load(path):
    """Per figure present in the map: its grid axis (deg: the poses where
    it is finite, a sub-grid for the bandwidth) and its cube over (psi,
    theta, phi), NaN where the pose was not evaluated."""
    rows = list(csv.DictReader(open(path, newline="")))
    if not rows:
        raise ValueError("%s: no rows" % path)
    out = []
    for key, label in FIGURES:
        if key not in rows[0]:
            continue
        have = [r for r in rows if r["ok"] == "1" and np.isfinite(float(r[key]))]
        if not have:
            continue
        axis = np.unique([float(r[a]) for r in have for a in ("psi_deg", "theta_deg", "phi_deg")])
        index = {round(v, 9): k for k, v in enumerate(axis)}
        cube = np.full((axis.size,) * 3, np.nan)
        for r in have:
            i, j, l = (index[round(float(r[a]), 9)] for a in ("psi_deg", "theta_deg", "phi_deg"))
            cube[i, j, l] = float(r[key])
        out.append((key, label, axis, cube))
    return out


def main(argv):
    if len(argv) not in (3, 4):
        sys.stderr.write(__doc__)
        return 2
    figs = load(argv[1])
    fig, ax = plt.subplots(len(figs), 3, figsize=(13, 3.75 * len(figs)), squeeze=False)
    for row, (key, label, axis, C) in enumerate(figs):
        mid = axis.size // 2
        slices = (("theta (deg)", "phi (deg)", lambda C: C[mid, :, :], "psi = 0"),
                  ("psi (deg)", "phi (deg)", lambda C: C[:, mid, :], "theta = 0"),
                  ("psi (deg)", "theta (deg)", lambda C: C[:, :, mid], "phi = 0"))
        ext = (axis[0], axis[-1], axis[0], axis[-1])
        lo, hi = np.nanmin(C), np.nanmax(C)
        for col, (xl, yl, cut, title) in enumerate(slices):
            a = ax[row][col]
            im = a.imshow(cut(C).T, origin="lower", extent=ext, vmin=lo, vmax=hi, cmap="viridis",
                          aspect="equal")
            a.set_xlabel(xl)
            a.set_ylabel(yl)
            a.set_title("%s, %s" % (label.split(" (")[0], title), fontsize=9)
        fig.colorbar(im, ax=list(ax[row]), label=label, shrink=0.9)
    if len(argv) == 4:
        fig.suptitle(argv[3])
    fig.savefig(argv[2], dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
