#!/usr/bin/python3
"""Bar plot of a pomlab sensitivity file: Sobol S1 and ST with their
bootstrap intervals, or Morris mu* and sigma, one panel per candidate.

usage: plot_sensitivity.py RESULTS.h5 OUT.png
"""
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


def main(path, png):
    with h5py.File(path, "r") as f:
        inputs = [text(k) for k in f["inputs"][()]]
        names = [text(k) for k in f["candidates"][()]]
        method = text(f.attrs["method"])
        metric = text(f.attrs["metric"])
        data = {k: f[method][k][()] for k in f[method]}
        conf = f.attrs.get("confidence", 0.95)
    n = len(names)
    fig, axes = plt.subplots(n, 1, figsize=(8, 1.2 + 0.55 * len(inputs) * n), squeeze=False)
    y = np.arange(len(inputs))
    for c, ax in enumerate(axes[:, 0]):
        if method == "sobol":
            for k, (key, label, dy) in enumerate((("S1", "first order S1", -0.2),
                                                  ("ST", "total ST", 0.2))):
                v = data[key][c]
                err = np.vstack([v - data[key + "_low"][c], data[key + "_high"][c] - v])
                ax.barh(y + dy, v, height=0.4, xerr=np.clip(err, 0, None), capsize=3,
                        label=label, color=("C0", "C1")[k])
            ax.set_xlabel(f"Sobol index of {metric} ({100 * conf:.0f} % bootstrap intervals)")
        else:
            ax.barh(y - 0.2, data["mu_star"][c], height=0.4, label="mu*", color="C0")
            ax.barh(y + 0.2, data["sigma"][c], height=0.4, label="sigma", color="C1")
            ax.set_xlabel(f"Morris elementary effects of {metric} (per unit of u)")
        ax.set_yticks(y)
        ax.set_yticklabels(inputs)
        ax.invert_yaxis()
        ax.axvline(0, color="k", lw=0.5)
        ax.set_title(names[c])
        ax.legend(loc="lower right")
    fig.tight_layout()
    fig.savefig(png, dpi=110)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
