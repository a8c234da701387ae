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
rm -f "$SRC/tests/.cap_req_$$.cfg" "$SRC/tests/.cap_bad_$$.cfg"

[ $fail -eq 0 ] && echo "test_study_capability: ok"
exit $fail
