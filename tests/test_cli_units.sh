#!/usr/bin/env bash
# test_cli_units.sh - physics is not silent and text has one unit per
# quantity (docs/conventions.md): a stroke excursion is flagged, a refused
# target is printed with its digits, and the numbers printed as text equal
# the SI numbers of --json once converted by the documented factors.
# Usage: test_cli_units.sh PATH/TO/pomlab SOURCE_DIR
set -u
POMLAB=$1
SRC=$2
. "$(dirname "$0")/cli_lib.sh"
cfg="$SRC/configs/3pss.cfg"

# --- stroke excursions are flagged -----------------------------------------------------
# kp = 0: no drive; gravity pulls every piston down past the -6 mm stroke end
# (the model has no end stops): measured -6.99 mm at the horizon
expect_rc 0 "$POMLAB" simulate "$cfg" --target 1,2,3 --kp 0 --json
json_check "d['stroke_exceeded'] == [True, True, True] and d['half_stroke'] == 0.006"
json_check "all(q < -0.006 for q in d['final_q_m']) and all(m > 0.006 for m in d['max_abs_q'])"
expect_in "$TMP/err" "warning: an actuator left its stroke +-6 mm"
expect_rc 0 "$POMLAB" simulate "$cfg" --target 1,2,3 --kp 0
expect_in "$TMP/out" "STROKE EXCEEDED: actuator 2 reached |q| = 6.99"
# a normal maneuver stays inside and says nothing about it (the parasitic
# model's validity warning aside: at the shipped k_p = 1e6 N/m the rule flags
# it, docs/dynamics.md section 13b); on rigid joints it says nothing at all
expect_rc 0 "$POMLAB" simulate "$cfg" --target 1,2,3 --json
json_check "d['stroke_exceeded'] == [False, False, False]"
checks=$((checks + 1))
grep -v "warning: the parasitic model is not at its rigid limit" "$TMP/err" > "$TMP/err2" || true
[ ! -s "$TMP/err2" ] || fail "a maneuver inside the stroke printed on stderr: $(head -2 "$TMP/err2")"
cp "$TMP/out" "$TMP/sim.json"
expect_rc 0 "$POMLAB" simulate "$cfg" --target 1,2,3 --joints rigid --json
checks=$((checks + 1))
[ ! -s "$TMP/err" ] || fail "a rigid maneuver inside the stroke printed on stderr: $(head -2 "$TMP/err")"

# --- a refused target shows the digits that put it outside -----------------------------
expect_rc 2 "$POMLAB" simulate "$cfg" --target 6.000001,0,0
expect_in "$TMP/err" "q1 = 6.000001 mm is outside the stroke +-6 mm"
# a rotary actuator's in degrees, naming its real limits key
expect_rc 2 "$POMLAB" simulate "$SRC/configs/3rrr.cfg" --target 0,30.5,0
expect_in "$TMP/err" "q2 = 30.5 deg is outside the stroke +-30 deg (limits.range_deg = 60)"
# the dynamics' own refusal, reached by tune's default rotary maneuvers
# (3 mm through the 15 mm/rad lever: 0.2 rad = 11.46 deg) beyond a +-10 deg
# range: in degrees too
sed 's/^  range_deg = 60.0;/  range_deg = 20.0;/' "$SRC/configs/3rrr.cfg" >"$TMP/3rrr_narrow.cfg"
echo 'tuning = { overshoot_max_percent = 5.0; };' >>"$TMP/3rrr_narrow.cfg"
expect_rc 1 "$POMLAB" tune "$TMP/3rrr_narrow.cfg" --out "$TMP/tune_" --quiet
expect_in "$TMP/err" "target of actuator 1 = 11.4591559 deg is outside its stroke +-10 deg"

# --- text numbers are the JSON numbers in ms, mm, J, deg --------------------------------
expect_rc 0 "$POMLAB" simulate "$cfg" --target 1,2,3
cp "$TMP/out" "$TMP/sim.txt"
expect_rc 0 "$PY" - "$TMP/sim.txt" "$TMP/sim.json" <<'PYEOF'
import json, re, sys
text = open(sys.argv[1]).read()
d = json.load(open(sys.argv[2]))
def num(pattern):
    m = re.search(pattern, text)
    if not m:
        sys.exit('not found: ' + pattern)
    return float(m.group(1))
# (text converted to SI, JSON, tolerance): %.6g values are within a half
# unit of the 6th digit (5e-6 relative), %.3f ms within 5e-7 s, %.3g
# within 5e-3 relative
checks = [
    (num(r'expended energy: (\S+) J'), d['energy_total_J'], 5e-6 * d['energy_total_J']),
    (num(r'\nenergy\s+J\s+(\S+)'), d['energy_J'][0], 5e-6 * d['energy_J'][0]),
    (num(r'\nsettling_time\s+ms\s+(\S+)') / 1e3, d['settling_time_s'][0],
     5e-6 * d['settling_time_s'][0]),
    (num(r'execution time: (\S+) ms') / 1e3, d['execution_time_s'], 5e-7),
    (num(r'\nfinal_q\s+mm\s+(\S+)') / 1e3, d['final_q_m'][0], 5e-6 * d['final_q_m'][0]),
    (num(r'largest parasitic deflection: (\S+) mm') / 1e3, d['max_deflection_m'],
     5e-3 * d['max_deflection_m']),
]
bad = [(a, b) for a, b, tol in checks if not abs(a - b) <= tol]
sys.exit('text and JSON disagree: %r' % bad if bad else 0)
PYEOF
# ik: the Jacobian as a lever arm in mm/rad (linear) or a ratio (rotary)
expect_rc 0 "$POMLAB" ik "$cfg" --euler-zyx 5,3,-2
cp "$TMP/out" "$TMP/ik.txt"
expect_rc 0 "$POMLAB" ik "$cfg" --euler-zyx 5,3,-2 --json
cp "$TMP/out" "$TMP/ik.json"
expect_rc 0 "$PY" - "$TMP/ik.txt" "$TMP/ik.json" <<'PYEOF'
import json, re, sys
text = open(sys.argv[1]).read()
d = json.load(open(sys.argv[2]))
sv = [float(x) for x in re.search(r'singular values \(mm/rad\): (.*)', text).group(1).split()]
# printed with 6 decimals in mm/rad, SI in m/rad
sys.exit(0 if all(abs(a / 1e3 - b) < 1e-9 for a, b in zip(sv, d['singular_values'])) else 1)
PYEOF
expect_rc 0 "$POMLAB" ik "$SRC/configs/3rrr.cfg" --euler-zyx 5,3,-2
cp "$TMP/out" "$TMP/ik.txt"
expect_rc 0 "$POMLAB" ik "$SRC/configs/3rrr.cfg" --euler-zyx 5,3,-2 --json
cp "$TMP/out" "$TMP/ik.json"
expect_rc 0 "$PY" - "$TMP/ik.txt" "$TMP/ik.json" <<'PYEOF'
import json, re, sys
text = open(sys.argv[1]).read()
d = json.load(open(sys.argv[2]))
sv = [float(x) for x in re.search(r'singular values \(rad/rad\): (.*)', text).group(1).split()]
sys.exit(0 if all(abs(a - b) < 1e-6 for a, b in zip(sv, d['singular_values'])) else 1)
PYEOF

# --- CSV traces carry their setpoints, so their figure draws them ----------------------
expect_rc 0 "$POMLAB" simulate "$cfg" --target 1.25,-2.5,0.75 --out "$TMP/tr.csv"
expect_rc 0 "$PY" -c "
import csv, sys
rows = list(csv.DictReader(open('$TMP/tr.csv')))
want = [0.00125, -0.0025, 0.00075]
sys.exit(0 if all(abs(float(r['q%d_set_m' % (k + 1)]) - want[k]) < 1e-15
                  for r in rows for k in range(3)) else 1)"
expect_rc 0 "$PY" "$SRC/scripts/plot_traces.py" "$TMP/tr.png" "3PSS=$TMP/tr.csv"
checks=$((checks + 1))
[ -s "$TMP/tr.png" ] || fail "plot_traces.py wrote no figure from a CSV trace"

echo "test_cli_units: $checks checks, $fails failed"
[ "$fails" = 0 ]
