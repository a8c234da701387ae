#!/bin/bash
# test_dynamics_cli.sh POMLAB SOURCE_DIR - `pomlab simulate` on the shipped
# configs (both PID forms, both orientation options, both linear solvers),
# its traces and the Fig. 7 script; usage errors give exit status 2.
set -u
POMLAB=$1
SRC=$2
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
fail=0
expect_rc() {
  local want=$1; shift
  "$@" > "$TMP/out" 2> "$TMP/err"
  local rc=$?
  if [ $rc -ne "$want" ]; then
    echo "FAIL (rc $rc, want $want): $*"; cat "$TMP/err"; fail=1
  fi
}
PY=/usr/bin/python3

for cfg in 3pss 3sps; do
  for opt in "--form ideal --orientation euler" "--form ideal --orientation quaternion --linsol dense" \
             "--form parallel --kp 2e4 --ki 20 --kd 100 --orientation euler" \
             "--joints rigid --orientation quaternion"; do
    expect_rc 0 "$POMLAB" simulate "$SRC/configs/$cfg.cfg" --target 3,-3,3 $opt --json
    # every actuator settles within the horizon and the energy audit closes
    if ! $PY -c "
import json, sys
r = json.load(open('$TMP/out'))
assert r['status'] == 'POM_OK', r['status']
assert all(r['settled']), r['settled']
assert r['execution_time_s'] < 0.05, r['execution_time_s']
assert r['energy_balance_error'] < 1e-3, r['energy_balance_error']
assert all(abs(q - t) < 1e-5 for q, t in zip(r['final_q_m'], r['target_m']))
assert '--joints rigid' not in '$opt' or r['max_deflection_m'] == 0.0, r['max_deflection_m']
"; then echo "FAIL: $cfg $opt metrics"; cat "$TMP/out"; fail=1; fi
  done
done

# --json stays valid JSON when the config name holds quotes and backslashes
sed 's/^name = .*/name = "a \\"quoted\\" name \\\\ here";/' "$SRC/configs/3pss.cfg" > "$TMP/q.cfg"
expect_rc 0 "$POMLAB" simulate "$TMP/q.cfg" --target 0.5,0,0 --json
if ! $PY -c "
import json
r = json.load(open('$TMP/out'))
assert r['name'] == 'a \"quoted\" name \\\\ here', r['name']
"; then echo "FAIL: --json with a quoted name"; cat "$TMP/out"; fail=1; fi

# traces: HDF5 and CSV, then the figure
expect_rc 0 "$POMLAB" simulate "$SRC/configs/3pss.cfg" --target 1,-2,0.5 --out "$TMP/a.h5"
expect_rc 0 "$POMLAB" simulate "$SRC/configs/3sps.cfg" --target 1,-2,0.5 --out "$TMP/b.csv"
if ! $PY -c "
import csv, h5py
with h5py.File('$TMP/a.h5') as f:
    t = f['trace/t'][:]; q = f['trace/q'][:]
    assert len(t) == 1001 and abs(t[-1] - 0.1) < 1e-12, len(t)
    assert abs(q[-1, 1] + 2e-3) < 1e-5, q[-1]
    assert 'actuator' in f['config'][()].decode()
rows = list(csv.DictReader(open('$TMP/b.csv')))
assert len(rows) == 1001 and abs(float(rows[-1]['q3_m']) - 0.5e-3) < 1e-5
"; then echo "FAIL: traces"; fail=1; fi
expect_rc 0 $PY "$SRC/scripts/plot_traces.py" "$TMP/fig.png" "3P-S-S/S=$TMP/a.h5" "3S-P-S/S=$TMP/b.csv"
[ -s "$TMP/fig.png" ] || { echo "FAIL: no figure"; fail=1; }

# usage and config errors
expect_rc 2 "$POMLAB" simulate "$SRC/configs/3pss.cfg"
expect_rc 2 "$POMLAB" simulate "$SRC/configs/3pss.cfg" --target 1,2
expect_rc 2 "$POMLAB" simulate "$SRC/configs/3pss.cfg" --target nan,1,1
expect_rc 2 "$POMLAB" simulate "$SRC/configs/3pss.cfg" --target 1,inf,1
expect_rc 2 "$POMLAB" simulate "$SRC/configs/3pss.cfg" --target 1,2,3 --out x.txt
expect_rc 2 "$POMLAB" simulate "$SRC/configs/3pss.cfg" --target 1,2,3 --form pid
expect_rc 2 "$POMLAB" simulate "$SRC/configs/3pss.cfg" --target 1,2,3 --bogus
expect_rc 2 "$POMLAB" simulate "$SRC/configs/3pss.cfg" --target 1,2,3 --rtol 5
expect_rc 2 "$POMLAB" simulate "$SRC/configs/3pss.cfg" --target 0,6.5,0 --out "$TMP/stroke.h5"
grep -q "q2 = 6.5 mm is outside the stroke" "$TMP/err" || { echo "FAIL: stroke message"; fail=1; }
[ ! -e "$TMP/stroke.h5" ] || { echo "FAIL: traces written for a refused target"; fail=1; }
sed 's/resistance_ohm = 10.0;/resistance_ohm = -10.0;/' "$SRC/configs/3pss.cfg" > "$TMP/bad.cfg"
expect_rc 2 "$POMLAB" simulate "$TMP/bad.cfg" --target 1,2,3
grep -q "actuator.resistance_ohm" "$TMP/err" || { echo "FAIL: message does not name the key"; fail=1; }
sed 's/  rtol = 1.0e-6; /  rtol = 1.0e-6; bogus_key = 1;/' "$SRC/configs/3pss.cfg" > "$TMP/unknown.cfg"
expect_rc 2 "$POMLAB" simulate "$TMP/unknown.cfg" --target 1,2,3
# the controller by name, through the config's own checks (issue 17)
expect_rc 2 "$POMLAB" simulate "$SRC/configs/3pss.cfg" --target 1,2,3 --controller no_such_law
grep -q "command line --controller: key 'controller.type' = no_such_law" "$TMP/err" ||
  { echo "FAIL: --controller message"; fail=1; }
expect_rc 0 "$POMLAB" simulate "$SRC/configs/3pss.cfg" --target 1,2,3 --controller pid --joints rigid --json
$PY -c "
import json,sys; r=json.load(open('$TMP/out'))
c=r['controller']; assert c['type']=='pid' and c['form']=='ideal' and c['kp']>0, c
" || { echo "FAIL: simulate JSON controller"; fail=1; }
expect_rc 0 "$POMLAB" model --list-controllers --json
$PY -c "
import json; r=json.load(open('$TMP/out'))
pid=[c for c in r['controllers'] if c['name']=='pid'][0]
keys=[g['key'] for g in pid['gains']]; assert keys==['kp','ki_per_s','kd_s'], keys
assert pid['states_per_actuator'][0]['name']=='integral' and pid['options'][0]['choices']==['ideal','parallel']
" || { echo "FAIL: --list-controllers JSON"; fail=1; }
expect_rc 0 "$POMLAB" simulate --help
grep -q -i "millimetres" "$TMP/out" || { echo "FAIL: --help does not state the unit"; fail=1; }

# what was not resolved or not computed is null in the JSON (docs/results.md
# sections 1c and 1d): the 38 nm gravity sag of a zero target on the rigid
# path, and the short-link design driven into its singular pose (exit 1)
expect_rc 0 "$POMLAB" simulate "$SRC/configs/3pss.cfg" --target 0,0,0 --joints rigid --json
$PY -c "
import json; r=json.load(open('$TMP/out'))
assert r['status']=='POM_OK' and r['settling_time_final_s']==[None]*3, r['settling_time_final_s']
assert r['stepinfo_unresolved']==[1,1,1], r['stepinfo_unresolved']
" || { echo "FAIL: unresolved stepinfo band not null"; fail=1; }
sed -e 's/^  platform_radius_mm = .*/  platform_radius_mm = 12.0;/' -e 's/^  limb_length = .*/  limb_length = 2.0;/' \
    -e 's/^  limb_lean_deg = .*/  limb_lean_deg = 80.0;/' -e 's/^  limb_azimuth_deg = .*/  limb_azimuth_deg = 60.0;/' \
    "$SRC/configs/3pss.cfg" > "$TMP/short.cfg"
expect_rc 1 "$POMLAB" simulate "$TMP/short.cfg" --target 6,-6,6 --joints rigid --json
$PY -c "
import json; r=json.load(open('$TMP/out'))
assert r['status']=='POM_ERR_SINGULAR', r['status']
for k in ('energy_total_J','energy_balance_error'): assert r[k] is None, (k, r[k])
for k in ('final_q','max_abs_q','energy_J'): assert r[k]==[None]*3, (k, r[k])
assert r['peak_voltage_V']==[24,24,24] and r['peak_angular_rate_rad_per_s']>100
" || { echo "FAIL: a failed maneuver's not-computed metrics not null"; fail=1; }

# --bode: the small-signal frequency response about a pose (docs/capability.md):
# the JSON file and stdout agree, the figures are there, the plot script draws it
expect_rc 0 "$POMLAB" simulate "$SRC/configs/3rrr.cfg" --target 2,-1,3 --bode "$TMP/bode.json" --json
$PY -c "
import json; f=json.load(open('$TMP/bode.json')); o=json.load(open('$TMP/out'))
assert f == o
assert len(f['bandwidth_hz']) == 3 and all(30 < b < 80 for b in f['bandwidth_hz']), f['bandwidth_hz']
assert f['bandwidth_worst_hz'] <= min(f['bandwidth_hz']) * 1.000001
assert f['stable'] is True and len(f['loop']) == 3 and len(f['axis'][0]['mag_db']) == len(f['f_hz'])
assert all(p > 0 for p in f['phase_margin_deg']) and f['mode_hz']
" || { echo "FAIL: --bode JSON"; fail=1; }
if $PY -c "import matplotlib" 2>/dev/null; then
  $PY "$SRC/scripts/plot_bode.py" "$TMP/bode.json" "$TMP/bode.png" >/dev/null 2>&1 && [ -s "$TMP/bode.png" ] \
    || { echo "FAIL: plot_bode.py"; fail=1; }
fi
expect_rc 0 "$POMLAB" simulate "$SRC/configs/3pss.cfg" --target 0,0,0 --bode "$TMP/b.json"
grep -q "worst direction" "$TMP/out" || { echo "FAIL: --bode text"; fail=1; }
expect_rc 2 "$POMLAB" simulate "$SRC/configs/3pss.cfg" --target 0,0,0 --bode "$TMP/b.txt"

if [ $fail -eq 0 ]; then echo "test_dynamics_cli: passed"; fi
exit $fail
