#!/usr/bin/python3
"""plot_workspace.py - the dexterity map of `pomlab workspace CFG --map F.csv`
as three slices through home: (theta, phi) at psi = 0, (psi, phi) at
theta = 0 and (psi, theta) at phi = 0, coloured by dexterity 1/kappa; poses
that are unreachable or outside the limits are grey (docs/kinematics.md
section 6).

usage: /usr/bin/python3 scripts/plot_workspace.py MAP.csv OUT.png [TITLE]
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def load(path):
    """Grid axis (deg) and the dexterity cube D[i, j, l] over (psi, theta,
    phi), NaN where the pose is not usable."""
    rows = list(csv.DictReader(open(path, newline="")))
    if not rows:
        raise ValueError("%s: no rows" % path)
    axis = np.unique([float(r["psi_deg"]) for r in rows])
    index = {round(v, 9): k for k, v in enumerate(axis)}
    D = np.full((axis.size,) * 3, np.nan)
    for r in rows:
        if r["within_limits"] != "1":
            continue
        i, j, l = (index[round(float(r[a]), 9)] for a in ("psi_deg", "theta_deg", "phi_deg"))
        D[i, j, l] = float(r["dexterity"])
    return axis, D


def main(argv):
    if len(argv) not in (3, 4):
        sys.stderr.write(__doc__)
        return 2
    axis, D = load(argv[1])
    home = int(np.argmin(np.abs(axis)))
    slices = ((D[home, :, :], "theta (deg)", "phi (deg)", "psi = 0"),
              (D[:, home, :], "psi (deg)", "phi (deg)", "theta = 0"),
              (D[:, :, home], "psi (deg)", "theta (deg)", "phi = 0"))
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.8), layout="constrained")
    cmap = plt.get_cmap("viridis").copy()
    cmap.set_bad("0.8")
    usable = D[np.isfinite(D)]
    lo = float(usable.min()) if usable.size else 0.0
    h = (axis[1] - axis[0]) / 2 if axis.size > 1 else 0.5
    extent = (axis[0] - h, axis[-1] + h, axis[0] - h, axis[-1] + h)
    for ax, (S, xlabel, ylabel, title) in zip(axes, slices):
        # rows of S run along the first angle: transpose so it is the x axis
        im = ax.imshow(np.ma.masked_invalid(S.T), origin="lower", extent=extent, cmap=cmap,
                       vmin=lo, vmax=1.0, aspect="equal")
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.set_title("slice %s" % title)
    fig.colorbar(im, ax=axes, shrink=0.85, label="dexterity 1/kappa (grey: unreachable or "
                 "outside the limits)")
    fig.suptitle(argv[3] if len(argv) == 4 else "dexterity map %s" % argv[1])
    fig.savefig(argv[2], dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
