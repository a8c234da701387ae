#!/usr/bin/env python3
"""Architectures x controllers: does the ranking of architectures hold across
controllers, and how much of each figure is the controller's? (issue 18 item 4,
docs/control.md section 4)

usage: arch_controller_report.py RESULTS.h5 [OUT.md]

Reads a study whose candidates are named "<architecture> <controller>"
(configs/architectures-controllers.cfg, configs/paper-controllers.cfg): every
pair ran the same maneuvers (common random numbers). A maneuver that did not
settle within the horizon is counted at the horizon (right-censored, never
dropped: a censored value ranks after every settled one), and the tables say
how many were censored.

Two answers, with figures:
1. The ranking of the architectures under each controller (mean execution
   time and mean energy), the share of maneuvers on which the first beats
   each other one, and whether the order is the same under every controller.
2. The two-way decomposition of the candidates' mean figures (architecture x
   controller, no replication): the shares of the sum of squares due to the
   architecture, to the controller and to their interaction; and per
   architecture, the spread of its figure across controllers relative to its
   figure under the paper's PID.
Writes OUT.md (default: results/<study>/controllers.md beside the summary)
and prints it.
"""
import os
import sys

import h5py
import numpy as np


def load(path):
    f = h5py.File(path, "r")
    cands = []
    for key in sorted(f["candidates"].keys(), key=int):
        g = f["candidates"][key]
        name = g.attrs["name"]
        name = name.decode() if isinstance(name, bytes) else str(name)
        arch, _, ctrl = name.rpartition(" ")
        rows = g["maneuvers"][()]
        horizon = float(g.attrs.get("maneuver_horizon_s", 0.1))
        ok = rows["status"] == 0
        # the platform-level time where the results have it (orientation
        # studies), else the paper's per-actuator execution time
        field = "pointing_settling_time" if "pointing_settling_time" in rows.dtype.names \
            else "execution_time"
        t = rows[field].astype(float)
        censored = ok & ~np.isfinite(t)
        t = np.where(censored, horizon, t)
        cands.append(dict(name=name, arch=arch, ctrl=ctrl, time=t * 1e3, ok=ok, field=field,
                          censored=int(censored.sum()), failed=int((~ok).sum()),
                          energy=rows["energy_total"].astype(float)))
    study = f.attrs.get("study_name", os.path.splitext(os.path.basename(path))[0])
    study = study.decode() if isinstance(study, bytes) else str(study)
    return study, cands


def decomposition(table):
    """Shares of the total sum of squares of a two-way table without
    replication: rows (architectures), columns (controllers), interaction."""
    grand = table.mean()
    ss_rows = table.shape[1] * ((table.mean(axis=1) - grand) ** 2).sum()
    ss_cols = table.shape[0] * ((table.mean(axis=0) - grand) ** 2).sum()
    ss_tot = ((table - grand) ** 2).sum()
    ss_int = ss_tot - ss_rows - ss_cols
    return ss_rows / ss_tot, ss_cols / ss_tot, ss_int / ss_tot


def main():
    if len(sys.argv) < 2:
        print(__doc__)
        return 2
    study, cands = load(sys.argv[1])
    archs = list(dict.fromkeys(c["arch"] for c in cands))
    ctrls = list(dict.fromkeys(c["ctrl"] for c in cands))
    by = {(c["arch"], c["ctrl"]): c for c in cands}
    if len(archs) < 2 or len(ctrls) < 2 or len(by) != len(archs) * len(ctrls):
        print("arch_controller_report: candidates must be named '<architecture> <controller>', "
              "every pair present", file=sys.stderr)
        return 2
    # maneuvers every candidate ran without a numerical failure
    common = np.logical_and.reduce([c["ok"] for c in cands])
    out = [f"# Architectures x controllers: {study}", "",
           f"Time metric: `{cands[0]['field']}`.", "",
           f"{len(archs)} architectures x {len(ctrls)} controllers on {int(common.sum())} common "
           "maneuvers (every pair ran them without a failure); an unsettled maneuver counts at "
           "the horizon (censored).", ""]
    answers = {}
    tlabel = "pointing time" if cands[0]["field"] == "pointing_settling_time" else "execution time"
    for metric, unit, label in (("time", "ms", tlabel), ("energy", "J", "energy")):
        out += [f"## {label.capitalize()} ({unit})", "",
                "| architecture | " + " | ".join(ctrls) + " | spread across controllers |",
                "|---|" + "---:|" * (len(ctrls) + 1)]
        table = np.array([[by[(a, k)][metric][common].mean() for k in ctrls] for a in archs])
        for i, a in enumerate(archs):
            cells = []
            for j, k in enumerate(ctrls):
                c = by[(a, k)]
                cen = f" ({c['censored']} censored)" if metric == "time" and c["censored"] else ""
                cells.append(f"{table[i, j]:.4g}{cen}")
            spread = (table[i].max() - table[i].min()) / table[i, 0] * 100.0
            out.append(f"| {a} | " + " | ".join(cells) + f" | {spread:.0f} % of its {ctrls[0]} figure |")
        out.append("")
        orders = []
        for j, k in enumerate(ctrls):
            order = [archs[i] for i in np.argsort(table[:, j], kind="stable")]
            orders.append(order)
            best = by[(order[0], k)][metric][common]
            wins = []
            for other in order[1:]:
                o = by[(other, k)][metric][common]
                wins.append(f"{other} on {np.mean(best < o) * 100:.1f} %")
            out.append(f"- under {k}: {' < '.join(order)}; {order[0]} is better than "
                       + ", ".join(wins) + " of the maneuvers")
        holds = all(o == orders[0] for o in orders)
        sa, sc, si = decomposition(table)
        answers[label] = (holds, sa, sc, si)
        out += ["", f"Ranking of the architectures the same under every controller: "
                f"**{'yes' if holds else 'no'}**.",
                f"Sum of squares of the {len(archs)}x{len(ctrls)} means: architecture "
                f"{sa * 100:.0f} %, controller {sc * 100:.0f} %, interaction {si * 100:.0f} %.", ""]
    out += ["## The two questions", ""]
    for label, (holds, sa, sc, si) in answers.items():
        out.append(f"- {label}: the ranking of the architectures {'holds' if holds else 'does NOT hold'} "
                   f"across the {len(ctrls)} controllers; of the spread of the candidates' means, "
                   f"{sa * 100:.0f} % is the architecture's, {sc * 100:.0f} % the controller's and "
                   f"{si * 100:.0f} % their interaction.")
    text = "\n".join(out) + "\n"
    path = sys.argv[2] if len(sys.argv) > 2 else os.path.join(
        os.path.dirname(sys.argv[1]), os.path.splitext(os.path.basename(sys.argv[1]))[0],
        "controllers.md")
    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    with open(path + ".tmp", "w") as f:
        f.write(text)
    os.replace(path + ".tmp", path)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
