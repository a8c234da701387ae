#!/bin/bash
# test_study_capability.sh POMLAB SOURCE_DIR - study.capability (docs/capability.md
# "As study responses and constraints"): the per-candidate figures of a small
# study equal `pomlab capability CFG --grid 3 --json` for the same candidate,
# in the JSON report, the candidates table, the HDF5 file and summary.md; a
# requirement binds (the 3S-P-S/S's acceleration is below the floor, the
# 3P-S-S/S's above); the bandwidth figure's plumbing (a number or null, never
# missing); a bad figure name or requirement refused naming file, key, value.
set -u
POMLAB=$1
SRC=$2
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
fail=0
PY=/usr/bin/python3
STUDY=$SRC/tests/doe_study_capability.cfg

for a in 3pss 3sps; do
  "$POMLAB" capability "$SRC/configs/$a.cfg" --grid 3 --json --quiet > "$TMP/$a.json" \
    || { echo "FAIL: capability $a"; fail=1; }
done
"$POMLAB" study "$STUDY" --out "$TMP/s.h5" --tabular "$TMP/s.csv" --json --quiet > "$TMP/s.json" \
  2> "$TMP/err" || { echo "FAIL: study"; cat "$TMP/err"; fail=1; }
if ! $PY - "$TMP" <<'PYEOF'; then echo "FAIL: study figures"; fail=1; fi
import csv, json, math, subprocess, sys
tmp = sys.argv[1]
rep = json.load(open(tmp + "/s.json"))
rows = {r["candidate"]: r for r in csv.DictReader(open(tmp + "/s_candidates.csv"))}
summary = open(tmp + "/s/summary.md").read()
h5 = subprocess.run(["h5dump", "-A", tmp + "/s.h5"], capture_output=True, text=True).stdout
assert "Capability per candidate" in summary, summary
for c, a in zip(rep["candidates"], ("3pss", "3sps")):
    cap = json.load(open(f"{tmp}/{a}.json"))
    want = {"acc_inscribed_worst": cap["worst_acc"]["acc_inscribed_rad_per_s2"],
            "rate_inscribed_worst": cap["worst_rate"]["rate_inscribed_rad_per_s"]}
    got = c["capability"]
    assert set(got) == {"acc_inscribed_worst", "rate_inscribed_worst", "bw_worst_hz",
                        "pm_worst_deg"}, got
    for k, v in want.items():
        # the same code on the same model and grid: equal to rounding of %.17g
        assert abs(got[k] - v) <= 1e-12 * abs(v), (c["name"], k, got[k], v)
        assert abs(float(rows[c["name"]]["capability_" + k]) - v) <= 1e-12 * abs(v)
        assert f"| {v:.5g}" in summary or f"{v:.5g}" in summary, (k, v)
    # the bandwidth: a number or null (not computed) in JSON, NaN in the table
    for k in ("bw_worst_hz", "pm_worst_deg"):
        assert got[k] is None or got[k] > 0, got
        t = float(rows[c["name"]]["capability_" + k])
        assert (got[k] is None and math.isnan(t)) or t == got[k]
    assert "capability_met" not in c  # no requirement asked
assert h5.count('"capability:acc_inscribed_worst"') == 2, h5
assert h5.count('"capability:bw_worst_hz"') == 2
PYEOF

# a requirement that binds: 3P-S-S/S ~2.4e4 rad/s^2 at its worst pose, 3S-P-S/S ~3.8e3
sed 's/capability = \[.*\];/capability_require = ["acc_inscribed_worst >= 1e4"];/' "$STUDY" \
  > "$SRC/tests/.cap_req_$$.cfg"
"$POMLAB" study "$SRC/tests/.cap_req_$$.cfg" --out "$TMP/r.h5" --json --quiet > "$TMP/r.json" \
  2> "$TMP/err" || { echo "FAIL: study with a requirement"; cat "$TMP/err"; fail=1; }
if ! $PY - "$TMP" <<'PYEOF'; then echo "FAIL: requirement"; fail=1; fi
import json, sys
rep = json.load(open(sys.argv[1] + "/r.json"))
met = {c["name"]: c["capability_met"] for c in rep["candidates"]}
assert met == {"3PSS": True, "3SPS": False}, met
assert set(rep["candidates"][0]["capability"]) == {"acc_inscribed_worst"}
summary = open(sys.argv[1] + "/r/summary.md").read()
assert "**not met**" in summary and "acc_inscribed_worst >= 10000" in summary, summary
# the candidate that fails is out of the ranking, named with its value and the bound
assert rep["ranking"] == {"execution_time": ["3PSS"], "energy": ["3PSS"]}, rep["ranking"]
ex = rep["excluded"]
assert [e["name"] for e in ex] == ["3SPS"], ex
f = ex[0]["failed"]
acc = rep["candidates"][1]["capability"]["acc_inscribed_worst"]
assert len(f) == 1 and f[0]["figure"] == "acc_inscribed_worst" and f[0]["op"] == ">=", f
assert f[0]["bound"] == 1e4 and f[0]["value"] == acc and acc < 1e4, f
assert "- 3SPS: acc_inscribed_worst = %.6g rad/s^2, required >= 10000" % acc in summary, summary
PYEOF
h5dump -d /ranking/execution_time -d /ranking/excluded "$TMP/r.h5" > "$TMP/rank.txt" 2>&1
grep -A4 'execution_time' "$TMP/rank.txt" | grep -q '(0): 0$' \
  || { echo "FAIL: /ranking/execution_time is not [0]"; cat "$TMP/rank.txt"; fail=1; }
grep -A4 'excluded' "$TMP/rank.txt" | grep -q '(0): 1$' \
  || { echo "FAIL: /ranking/excluded is not [1]"; cat "$TMP/rank.txt"; fail=1; }

# none meets it: nothing ranked, said on stderr and in the report, exit 0
sed 's/capability = \[.*\];/capability_require = ["acc_inscribed_worst >= 1e6"];/' "$STUDY" \
  > "$SRC/tests/.cap_req_$$.cfg"
"$POMLAB" study "$SRC/tests/.cap_req_$$.cfg" --out "$TMP/n.h5" --quiet > "$TMP/n.txt" \
  2> "$TMP/err" || { echo "FAIL: study that no candidate passes"; cat "$TMP/err"; fail=1; }
grep -q "no candidate meets study.capability_require" "$TMP/err" \
  || { echo "FAIL: no warning when nothing is ranked"; cat "$TMP/err"; fail=1; }
grep -q "No candidate meets study.capability_require: nothing is ranked" "$TMP/n.txt" \
  || { echo "FAIL: the report does not say nothing is ranked"; fail=1; }
if grep -q "^- execution time (primary): 1\." "$TMP/n.txt"; then
  echo "FAIL: a ranking printed although no candidate meets the requirement"; fail=1
fi

# a sweep: the figures are responses of the factors (main effects), and a
# requirement excludes the low-voltage half (its acceleration ~1.2e4 rad/s^2
# against ~2.4e4 at 24 V: the effort bound K V / R doubles)
SWEEP=$SRC/tests/doe_sweep_capability.cfg
"$POMLAB" study "$SWEEP" --out "$TMP/w.h5" --json --quiet > "$TMP/w.json" 2> "$TMP/err" \
  || { echo "FAIL: sweep study"; cat "$TMP/err"; fail=1; }
sed 's/capability = \[.*\];/&\n  capability_require = ["acc_inscribed_worst >= 1.6e4"];/' "$SWEEP" \
  > "$SRC/tests/.cap_sweep_$$.cfg"
"$POMLAB" study "$SRC/tests/.cap_sweep_$$.cfg" --out "$TMP/wr.h5" --json --quiet > "$TMP/wr.json" \
  2> "$TMP/err" || { echo "FAIL: sweep study with a requirement"; cat "$TMP/err"; fail=1; }
if ! $PY - "$TMP" <<'PYEOF'; then echo "FAIL: sweep effects"; fail=1; fi
import json, math, sys
import h5py
tmp = sys.argv[1]
rep = json.load(open(tmp + "/w.json"))
summary = open(tmp + "/w/summary.md").read()
assert "Main effects on the capability figures" in summary, summary
with h5py.File(tmp + "/w.h5", "r") as f:
    eff = f["effects/capability"][:]
    figs = f["effects"].attrs["capability_figures"]
    figs = [s.strip() for s in (figs.decode() if isinstance(figs, bytes) else figs).split(",")]
    factors = [k.split(".")[-1] for k in rep["factors"]]
cands = rep["candidates"]
seen = set()
for row in eff:
    fac, lev, lo, hi, n_c, fig, n, mean, mn, mx = row
    key = rep["factors"][int(fac)]
    name = figs[int(fig)]
    vals = [c["capability"][name] for c in cands if c["factors"][key] == lo]
    assert n_c == len(vals) == 2 and n == 2, row
    # the level's mean and range over its candidates, to rounding
    want = sum(vals) / len(vals)
    assert abs(mean - want) <= 1e-12 * abs(want), (row, vals)
    assert mn == min(vals) and mx == max(vals), (row, vals)
    assert ("| %s | %.6g | %s |" % (factors[int(fac)], lo, name)) in summary, (row, factors)
    seen.add((int(fac), name))
assert seen == {(f, n) for f in (0, 1) for n in
                ("acc_inscribed_worst", "rate_inscribed_worst", "bw_worst_hz")}, seen
# physics: a larger voltage limit enlarges the effort box, so the reachable
# accelerations and rates grow (the level at 24 V above the one at 12 V)
acc = {r[2]: r[7] for r in eff if int(r[0]) == 1 and figs[int(r[5])] == "acc_inscribed_worst"}
assert acc[24.0] > 1.6e4 > acc[12.0], acc
# the requirement excludes the two 12 V candidates, the ranking keeps the 24 V ones
rr = json.load(open(tmp + "/wr.json"))
low = sorted(c["name"] for c in rr["candidates"] if c["factors"]["actuator.voltage_limit_V"] == 12)
high = sorted(c["name"] for c in rr["candidates"] if c["factors"]["actuator.voltage_limit_V"] == 24)
assert sorted(e["name"] for e in rr["excluded"]) == low, rr["excluded"]
assert sorted(rr["ranking"]["execution_time"]) == high, rr["ranking"]
assert sorted(rr["ranking"]["energy"]) == high
for e in rr["excluded"]:
    assert e["failed"][0]["value"] < 1.6e4 and e["failed"][0]["bound"] == 1.6e4, e
# the main effects keep every candidate: the same table with or without the requirement
with h5py.File(tmp + "/wr.h5", "r") as f:
    assert (f["effects/capability"][:] == eff).all()
    assert f["effects/main"].shape == (8, 11), f["effects/main"].shape
PYEOF

# refused: an unknown figure, a malformed requirement, the grid without figures
check_refused() { # FILE-TEXT-SED KEY VALUE
  sed "$1" "$STUDY" > "$SRC/tests/.cap_bad_$$.cfg"
  "$POMLAB" study "$SRC/tests/.cap_bad_$$.cfg" --out "$TMP/bad.h5" --quiet > /dev/null 2> "$TMP/err"
  local rc=$?
  [ $rc -eq 2 ] || { echo "FAIL: '$1' gave rc $rc, want 2"; fail=1; }
  for w in ".cap_bad_$$.cfg:" "$2" "$3"; do
    grep -qF -- "$w" "$TMP/err" || { echo "FAIL: message lacks '$w':"; cat "$TMP/err"; fail=1; }
  done
  [ ! -e "$TMP/bad.h5" ] || { echo "FAIL: a refused study wrote its results"; fail=1; }
}
check_refused 's/"pm_worst_deg"\]/"pm_worst_deg", "bandwith"]/' "study.capability.[4]" "bandwith"
check_refused 's/capability = \[.*\];/capability_require = ["bw_worst_hz > 100"];/' \
  "study.capability_require.[0]" "bw_worst_hz > 100"
check_refused 's/capability = \[.*\];/capability_require = ["bandwidth >= 100"];/' \
  "study.capability_require.[0]" "unknown capability figure 'bandwidth'"
check_refused 's/capability = \[.*\];//' "study.capability_grid_points" "only with"
check_refused 's/capability_grid_points = 3/capability_grid_points = 4/' \
  "study.capability_grid_points" "odd"
rm -f "$SRC/tests/.cap_req_$$.cfg" "$SRC/tests/.cap_bad_$$.cfg" "$SRC/tests/.cap_sweep_$$.cfg"

[ $fail -eq 0 ] && echo "test_study_capability: ok"
exit $fail
