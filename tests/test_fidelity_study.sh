#!/bin/bash
# test_fidelity_study.sh POMLAB SOURCE_DIR WORKDIR - study.fidelity = "auto"
# (docs/results.md section 12): a small orientation-space study of the three
# shipped architectures; each candidate's setting, its selection errors and
# its validated bound are in the results file (/candidates/<c> attributes,
# the resolved config) and in summary.md beside the means; the bound is
# within the accuracy; the keys are refused by name when wrong. Short: 40 ms
# horizon, 8 + 8 fidelity maneuvers, 12 study maneuvers.
set -u
POMLAB=$1
SRC=$2
W=$3
rm -rf "$W"
mkdir -p "$W"
fail=0
check() { if ! eval "$1"; then echo "FAIL: $1"; fail=1; fi; }
study() {
  cat > "$W/$1.cfg" <<CFG
name = "$1";
montecarlo = { maneuvers = 12; seed = 11; space = "orientation"; tilt_max_deg = 8.0;
               torsion_max_deg = 8.0; };
study = { output = "$W/$1.h5"; threads = 2; $2
          override = { maneuver = { horizon_ms = 40.0; }; }; };
candidates = (
  { name = "3P-S-S/S"; config = "$SRC/configs/3pss.cfg"; },
  { name = "3S-P-S/S"; config = "$SRC/configs/3sps.cfg"; },
  { name = "3-RRR"; config = "$SRC/configs/3rrr.cfg"; }
);
CFG
}

study fid 'fidelity = "auto"; fidelity_accuracy_percent = 1.0; fidelity_maneuvers = 8;'
"$POMLAB" study "$W/fid.cfg" --no-plots > "$W/out.txt" 2> "$W/err.txt"
check '[ $? -eq 0 ]'
check '[ $(grep -c "^fidelity \[[1-3]/3\]" "$W/err.txt") -eq 3 ]'
check 'grep -q "Fidelity earned per candidate" "$W/fid/summary.md"'
check 'grep -q "on 8 maneuvers of seed 12 (selection) and within 1 % on the study.s first 8 maneuvers (held out, seed 11)" "$W/fid/summary.md"'
check '[ $(grep -c "^| 3.* | rigid, .* coil, rtol 1e-[0-9] | " "$W/fid/summary.md") -eq 3 ]'
check '! grep -q "accuracy not met" "$W/fid/summary.md"'
# the results file: the choice, its bound within 1 %, the setting in the
# candidate's resolved config and in the evaluator's own attributes
for c in 0 1 2; do
  h5dump -A -g "/candidates/$c" "$W/fid.h5" > "$W/a$c.txt" 2>&1
  check 'grep -q "ATTRIBUTE \"fidelity_setting\"" "$W/a$c.txt"'
  for a in fidelity_error_time fidelity_error_energy; do
    v=$(grep -A4 "ATTRIBUTE \"$a\"" "$W/a$c.txt" | grep "(0)" | sed 's/.*(0): //')
    check "awk -v v=$v 'BEGIN { exit !(v >= 0 && v <= 0.01) }'"
  done
  check 'grep -A4 "ATTRIBUTE \"fidelity_validation_seed\"" "$W/a$c.txt" | grep -q "(0): 11$"'
  check 'grep -A10 "ATTRIBUTE \"joints_model\"" "$W/a$c.txt" | grep -q "\"rigid\""'
  check 'grep -A4 "ATTRIBUTE \"solver_atol_scale\"" "$W/a$c.txt" | grep -q "(0): 0$"'
  h5dump -d "/candidates/$c/config" "$W/fid.h5" > "$W/c$c.txt" 2>&1
  check 'grep -q "atol_scale = 0" "$W/c$c.txt"'
done
# the 3-RRR's coil lag (L/R = 0.1 ms) makes the inductive coil its choice
check 'grep -q "^| 3-RRR | rigid, inductive coil" "$W/fid/summary.md"'

# --json carries the same per candidate
"$POMLAB" study "$W/fid.cfg" --json --no-plots --no-summary --quiet > "$W/fid.json" 2> /dev/null
check '[ $? -eq 0 ]'
check '/usr/bin/python3 -c "
import json, sys
d = json.load(open(\"$W/fid.json\"))
f = [c[\"fidelity\"] for c in d[\"candidates\"]]
sys.exit(not (len(f) == 3 and all(x[\"met\"] and max(x[\"error_time\"], x[\"error_energy\"]) <= 0.01 for x in f)))"'

# wrong keys: exit 2, the key named
bad() {
  study bad "$1"
  "$POMLAB" study "$W/bad.cfg" --no-plots --quiet > /dev/null 2> "$W/bad.txt"
  check "[ \$? -eq 2 ] && grep -q \"$2\" \"$W/bad.txt\""
}
bad 'fidelity = "best";' "study.fidelity"
bad 'fidelity = "auto"; fidelity_accuracy_percent = 0.0;' "study.fidelity_accuracy_percent"
bad 'fidelity = "auto"; fidelity_margin = 0.5;' "study.fidelity_margin"
bad 'fidelity = "auto"; fidelity_maneuvers = 0;' "study.fidelity_maneuvers"
bad 'fidelity = "auto"; fidelity_seed = 11;' "study.fidelity_seed"
bad 'fidelity_maneuvers = 8;' "only with study.fidelity"
exit $fail
