#!/usr/bin/env python3
"""Rank stability of a co-design ranking across runs (docs/optimize.md
section 11.10): the same codesign file run at other seeds or budgets.

usage: codesign_ranks.py [--metric hv|fresh|para] [--drop PREFIX]... LABEL=REPORT.txt ...

Each REPORT.txt is the standard output of one `pomlab codesign CFG` run (the
report: a section "== NAME (config)" per candidate with its front and
"hypervolume H ms mJ"); where the results file it names ("Results: X.h5")
exists and h5dump is installed, the hypervolumes are read from its
attributes (the report rounds them to 4 digits). Prints, per candidate, the rank (by hypervolume,
larger first) and the p95 at the time optimum on the fresh maneuvers, rigid /
parasitic, in every run; then Kendall's tau-b and Spearman's rho between the
rankings of every pair of runs; then the ranks that are established and the
ties, by the metric chosen (default hv; fresh = fresh rigid p95 at the time
optimum, smaller first; para = the same, parasitic). --drop leaves out the
candidates whose name starts with PREFIX (one that differs between the runs
for a reason of its own):

- (hv only when every run has the same hypervolume reference point, i.e.
  the same fresh set: a hypervolume on another reference does not compare)
- a candidate's spread is the interval [min, max] of its metric over the
  runs;
- two candidates are told apart when their intervals do not overlap (every
  run puts them in the same order, with room: the worst run of the better
  one still beats the best run of the other);
- a tie group is a maximal chain of candidates, ordered by their median,
  whose neighbours' intervals overlap; a group of one is an established
  position.

With 3-5 runs the interval is a crude spread (no confidence level): an
overlap says "not told apart by these runs", never "equal". An infeasible
candidate (no hypervolume) ranks last with the metric undefined. Standard
library only (and h5dump, optional).
"""
import os
import re
import shutil
import statistics
import subprocess
import sys


def exact_hypervolumes(h5):
    """{name: hypervolume (ms mJ)} from the results file by h5dump (the
    report prints 4 digits), {} when h5dump or the file is missing"""
    if not h5 or not os.path.exists(h5) or not shutil.which("h5dump"):
        return {}
    try:
        text = subprocess.run(["h5dump", "-m", "%.12g", "-A", h5], check=True,
                              capture_output=True, text=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return {}
    out = {}
    hv = None
    want = None
    for line in text.splitlines():
        m = re.match(r'\s*GROUP "', line)
        if m:
            hv = None
            continue
        m = re.match(r'\s*ATTRIBUTE "(\w+)"', line)
        if m:
            want = m.group(1)
            continue
        m = re.match(r'\s*\(0\): (.*)$', line)
        if m and want == "hypervolume_sJ":
            hv = float(m.group(1)) * 1e6  # s J -> ms mJ
        elif m and want == "name" and hv is not None:
            out[m.group(1).strip().strip('"')] = hv
        if m:
            want = None
    return out


REFERENCES = {}  # report path -> its hypervolume reference point (text)


def parse_report(path):
    """{name: {"hv": float, "fresh": float, "para": float, "opt": float}}"""
    out = {}
    name = None
    h5 = None
    with open(path, encoding="utf-8") as f:
        for line in f:
            m = re.match(r"^Results: (.*\.h5); figure:", line)
            if m:
                h5 = m.group(1)
            m = re.search(r"against the reference ([0-9.]+ ms, [0-9.]+ mJ)", line)
            if m:
                REFERENCES[path] = m.group(1)
            m = re.match(r"^== (.*) \((.*)\)\s*$", line)
            if m:
                name = m.group(1)
                out[name] = {"hv": None, "fresh": None, "para": None, "opt": None}
                continue
            if name is None:
                continue
            m = re.match(r"^  1\s+min t\s+([0-9.]+) ms\s+[0-9.]+ mJ\s+([0-9.]+) ms\s+[0-9.]+ mJ"
                         r"\s+([0-9.]+) ms", line)
            if m:
                out[name]["opt"] = float(m.group(1))
                out[name]["fresh"] = float(m.group(2))
                out[name]["para"] = float(m.group(3))
                continue
            m = re.match(r"^  hypervolume ([0-9.e+-]+) ms mJ", line)
            if m:
                out[name]["hv"] = float(m.group(1))
                continue
            if line.startswith("Ranking at each"):
                name = None
    if not out:
        raise ValueError("%s: no candidate section ('== NAME (config)'): not a codesign report"
                         % path)
    exact = exact_hypervolumes(h5)
    for n, hv in exact.items():
        if n in out and out[n]["hv"] is not None:
            out[n]["hv"] = hv
    return out


def key_of(metric):
    """sort key: smaller is better; undefined last"""
    sign = -1.0 if metric == "hv" else 1.0

    def k(v):
        return (1, 0.0) if v is None else (0, sign * v)
    return k


def ranks(values, metric):
    """{name: rank 1..n} by the metric (ties share the average rank)"""
    k = key_of(metric)
    names = sorted(values, key=lambda n: k(values[n]))
    r = {}
    i = 0
    while i < len(names):
        j = i
        while j + 1 < len(names) and k(values[names[j + 1]]) == k(values[names[i]]):
            j += 1
        for t in range(i, j + 1):
            r[names[t]] = (i + j) / 2.0 + 1.0
        i = j + 1
    return r


def kendall_tau_b(a, b):
    n = len(a)
    conc = disc = ta = tb = 0
    for i in range(n):
        for j in range(i + 1, n):
            da = a[i] - a[j]
            db = b[i] - b[j]
            if da == 0 and db == 0:
                continue
            if da == 0:
                ta += 1
            elif db == 0:
                tb += 1
            elif da * db > 0:
                conc += 1
            else:
                disc += 1
    den = ((conc + disc + ta) * (conc + disc + tb)) ** 0.5
    return (conc - disc) / den if den > 0 else float("nan")


def spearman(a, b):
    ma, mb = statistics.mean(a), statistics.mean(b)
    num = sum((x - ma) * (y - mb) for x, y in zip(a, b))
    den = (sum((x - ma) ** 2 for x in a) * sum((y - mb) ** 2 for y in b)) ** 0.5
    return num / den if den > 0 else float("nan")


def fmt(v, spec):
    return "-" if v is None else format(v, spec)


def main(argv):
    metric = "hv"
    drop = []
    args = list(argv[1:])
    while len(args) >= 2 and args[0] in ("--metric", "--drop"):
        if args[0] == "--metric":
            metric = args[1]
        else:
            drop.append(args[1])
        args = args[2:]
    if metric not in ("hv", "fresh", "para") or len(args) < 2 or any("=" not in a for a in args):
        sys.stderr.write(__doc__)
        return 2
    runs = []
    for a in args:
        label, path = a.split("=", 1)
        try:
            runs.append((label, parse_report(path)))
        except (OSError, ValueError) as e:
            sys.stderr.write("codesign_ranks.py: %s\n" % e)
            return 1
    for _, rep in runs:
        for n in [n for n in rep if any(n.startswith(d) for d in drop)]:
            del rep[n]
    names = list(runs[0][1])
    for label, rep in runs[1:]:
        if set(rep) != set(names):
            sys.stderr.write("codesign_ranks.py: run '%s' has other candidates than '%s'\n"
                             % (label, runs[0][0]))
            return 1
    rk = {label: ranks({n: rep[n][metric] for n in names}, metric) for label, rep in runs}
    metric_name = {"hv": "hypervolume (larger first)",
                   "fresh": "fresh rigid p95 at the time optimum (smaller first)",
                   "para": "fresh parasitic p95 at the time optimum (smaller first)"}[metric]
    print("Ranks by %s; per run: rank  fresh rigid / parasitic p95 (ms)  [hypervolume 1e5 ms mJ]"
          % metric_name)
    head = "%-26s" % "candidate" + "".join("  %-27s" % lab for lab, _ in runs)
    print(head)
    med = {}
    for n in names:
        vals = [rep[n][metric] for _, rep in runs]
        med[n] = None if any(v is None for v in vals) else statistics.median(vals)
    order = sorted(names, key=lambda n: key_of(metric)(med[n]))
    for n in order:
        row = "%-26s" % n[:26]
        for lab, rep in runs:
            f = rep[n]
            hv = None if f["hv"] is None else f["hv"] / 1e5
            row += "  %4.1f %6s/%6s [%5s]  " % (rk[lab][n], fmt(f["fresh"], ".2f"),
                                                fmt(f["para"], ".2f"), fmt(hv, ".3f"))
        print(row)
    print()
    print("Rank agreement between runs (Kendall tau-b / Spearman rho over %d candidates)"
          % len(names))
    for i in range(len(runs)):
        for j in range(i + 1, len(runs)):
            a = [rk[runs[i][0]][n] for n in names]
            b = [rk[runs[j][0]][n] for n in names]
            print("  %-10s vs %-10s  tau %.3f  rho %.3f" % (runs[i][0], runs[j][0],
                                                            kendall_tau_b(a, b), spearman(a, b)))
    print()
    refs = sorted(set(REFERENCES.get(a.split("=", 1)[1], "?") for a in args))
    if metric == "hv" and len(refs) > 1:
        print("No spread: the runs' hypervolumes have different reference points (%s; another "
              "fresh set), so only their ranks compare" % "; ".join(refs))
        return 0
    print("Spread per candidate (min..max of the metric over the runs) and tie groups "
          "(neighbours' intervals overlap)")
    groups = []
    cur = []
    lo_hi = {}
    for n in order:
        vals = [rep[n][metric] for _, rep in runs]
        lo_hi[n] = None if any(v is None for v in vals) else (min(vals), max(vals))
    for n in order:
        if cur and lo_hi[n] is not None and lo_hi[cur[-1]] is not None:
            a, b = lo_hi[cur[-1]], lo_hi[n]
            if a[0] <= b[1] and b[0] <= a[1]:
                cur.append(n)
                continue
        if cur:
            groups.append(cur)
        cur = [n]
    if cur:
        groups.append(cur)
    pos = 1
    scale = 1e5 if metric == "hv" else 1.0
    unit = "1e5 ms mJ" if metric == "hv" else "ms"
    for g in groups:
        span = "%d" % pos if len(g) == 1 else "%d-%d" % (pos, pos + len(g) - 1)
        verdict = "established" if len(g) == 1 else "tie of %d" % len(g)
        print("  position %-6s %-12s %s" % (span, verdict, "; ".join(
            "%s %s..%s %s (ranks %s)" % (
                n, fmt(None if lo_hi[n] is None else lo_hi[n][0] / scale, ".4g"),
                fmt(None if lo_hi[n] is None else lo_hi[n][1] / scale, ".4g"), unit,
                ",".join("%g" % rk[lab][n] for lab, _ in runs)) for n in g)))
        pos += len(g)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
