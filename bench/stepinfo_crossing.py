#!/usr/bin/python3
"""stepinfo_crossing.py - what the stepinfo re-run (docs/results.md section
1c) costs and buys on the paper's Monte-Carlo draw (issue 30 items 1, 9).

Runs the first N maneuvers of configs/paper.cfg (both candidates, parasitic
path, shipped tolerances) with an OLD and a NEW pomlab, and the same with the
OLD pomlab at natural tolerances and rtol 1e-10 (the reference; the old one
because the new one would flag the reference's slow crossings against its
1 ns stated error). Prints, per candidate: the maneuvers the new one
re-integrated (its step count differs from the old one's), the steps and RHS
evaluations new / old, and each run's stepinfo times (settling_time_final)
against the reference: rms, max, and the count beyond the stated error
1 us + 1 ns (rtol 1e-6 and 1e-10: max(rtol x 1 s, 1 ns) each, the stated
error until the scale became 10 s; this script keeps the finer bound).

Usage: /usr/bin/python3 bench/stepinfo_crossing.py OLD_POMLAB NEW_POMLAB SOURCE_DIR [N]
(N = 100 by default; some 2 minutes on 2 cores. Needs h5py and numpy.)
"""

import os
import re
import subprocess
import sys
import tempfile

import h5py
import numpy as np


def study_cfg(src, tmp, name, n, reference):
    with open(os.path.join(src, "configs", "paper.cfg"), encoding="utf-8") as f:
        text = f.read()
    text = re.sub(r"maneuvers = 1000;", "maneuvers = %d;" % n, text)
    text = re.sub(r'output = "results/paper.h5";',
                  'output = "%s";' % os.path.join(tmp, name + ".h5"), text)
    text = re.sub(r'config = "([a-z0-9]+\.cfg)"',
                  lambda m: 'config = "%s"' % os.path.join(src, "configs", m.group(1)), text)
    if reference:
        text = text.replace(
            'rank_by = "execution_time";',
            'rank_by = "execution_time";\n  override = { solver = { rtol = 1.0e-10; '
            'atol_scale = 0.0; max_steps = 500000; }; };')
    path = os.path.join(tmp, name + ".cfg")
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)
    return path


def run(program, cfg):
    p = subprocess.run([program, "study", cfg, "--quiet", "--no-plots"], capture_output=True,
                       text=True)
    if p.returncode != 0:
        sys.exit("%s study %s failed: %s" % (program, cfg, p.stderr.strip()))


def maneuvers(path, c):
    with h5py.File(path, "r") as f:
        g = f["candidates"][c]
        name = g.attrs.get("name")
        return (name.decode() if isinstance(name, bytes) else str(name)), g["maneuvers"][:]


def main(argv):
    if len(argv) < 4:
        sys.exit(__doc__)
    old, new, src = argv[1], argv[2], os.path.abspath(argv[3])
    n = int(argv[4]) if len(argv) > 4 else 100
    stated = 1e-6 + 1e-9
    with tempfile.TemporaryDirectory(prefix="pomlab-stepinfo-") as tmp:
        runs = {}
        for name, prog, ref in (("old", old, False), ("new", new, False), ("ref", old, True)):
            cfg = study_cfg(src, tmp, name, n, ref)
            run(prog, cfg)
            runs[name] = os.path.join(tmp, name + ".h5")
        print("first %d maneuvers of configs/paper.cfg; stepinfo times against natural "
              "tolerances at rtol 1e-10 (us)" % n)
        print("| candidate | re-run | steps new/old | RHS new/old | old: rms, max, beyond 1 us "
              "| new: rms, max, beyond 1 us |")
        print("|---|---:|---:|---:|---|---|")
        for c in ("0", "1"):
            name, mo = maneuvers(runs["old"], c)
            _, mn = maneuvers(runs["new"], c)
            _, mr = maneuvers(runs["ref"], c)
            rerun = int((mn["steps"] != mo["steps"]).sum())
            cells = []
            for m in (mo, mn):
                e = np.abs(m["settling_time_final"] - mr["settling_time_final"])
                cells.append("%.3g, %.3g, %d" % (1e6 * np.sqrt(np.nanmean(e ** 2)),
                                                 1e6 * np.nanmax(e), int((e > stated).sum())))
            print("| %s | %d | %.2f | %.2f | %s | %s |" % (
                name, rerun, mn["steps"].sum() / mo["steps"].sum(),
                mn["rhs_evals"].sum() / mo["rhs_evals"].sum(), cells[0], cells[1]))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
