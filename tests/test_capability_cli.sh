#!/bin/bash
# test_capability_cli.sh POMLAB SOURCE_DIR - `pomlab capability`: the three
# shipped configs (JSON in SI, the HDF5 file, the map), an existing --out
# refused and kept, bad inputs refused with exit status 2 and a message that
# names the key or option and the value.
set -u
POMLAB=$1
SRC=$2
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
fail=0
PY=/usr/bin/python3
expect_rc() {
  local want=$1; shift
  "$@" > "$TMP/out" 2> "$TMP/err"
  local rc=$?
  if [ $rc -ne "$want" ]; then
    echo "FAIL (rc $rc, want $want): $*"; cat "$TMP/err"; fail=1
  fi
}
expect_msg() { # the last command's stderr holds every word given
  for w in "$@"; do
    if ! grep -qF -- "$w" "$TMP/err"; then
      echo "FAIL: message lacks '$w':"; cat "$TMP/err"; fail=1
    fi
  done
}

for cfg in 3pss 3sps 3rrr; do
  expect_rc 0 "$POMLAB" capability "$SRC/configs/$cfg.cfg" --grid 3 --json --quiet
  if ! $PY -c "
import json, math
r = json.load(open('$TMP/out'))
h = r['home']
assert h['ok'] and h['acc_inscribed_rad_per_s2'] > 1e3, h
assert h['acc_inscribed_rad_per_s2'] <= min(h['acc_axis_rad_per_s2']) * (1 + 1e-12)
assert h['rate_inscribed_rad_per_s'] <= min(h['rate_axis_rad_per_s']) * (1 + 1e-9)
assert r['worst_acc']['acc_inscribed_rad_per_s2'] <= h['acc_inscribed_rad_per_s2']
assert len(r['slews']) == 4
for s in r['slews']:
    assert all(st == 'POM_OK' for st in s['status']), s
    assert abs(s['amplitude_rad'][-1] - s['edge_rad']) < 1e-12
    t = s['slew_time_s']
    assert all(0 < a < 0.1 for a in t), t
# bandwidth and margins (docs/capability.md section 7): parasitic joints by default
assert r['bandwidth_joints'] == 'parasitic' and r['bandwidth_poses'] == 27
assert r['bandwidth_failed'] == 0
fin = lambda v: v is not None and math.isfinite(v)
for p in (h, r['worst_bw'], r['worst_pm']):
    assert p['freq_ok'], p
    assert all(fin(b) and 1 < b < 1e4 for b in p['bw_axis_hz']), p
    assert fin(p['bw_worst_hz']) and fin(p['pm_deg_min']) and fin(p['peak_db_worst'])
    assert p['bw_worst_hz'] <= min(p['bw_axis_hz']) * (1 + 1e-6), p
    assert 0 < p['pm_deg_min'] < 180 and (p['gm_db_min'] is None or p['gm_db_min'] > 0)
    assert fin(p['mode_hz']) and p['mode_hz'] > 3 * max(p['bw_axis_hz']), p
assert r['bw_worst_hz'] == r['worst_bw']['bw_worst_hz'] <= h['bw_worst_hz']
assert r['pm_worst_deg'] == r['worst_pm']['pm_deg_min'] <= h['pm_deg_min']
assert r['worst_acc']['freq_ok'] and r['worst_rate']['freq_ok']
"; then echo "FAIL: $cfg JSON"; cat "$TMP/out"; fail=1; fi
done

# text in device units
expect_rc 0 "$POMLAB" capability "$SRC/configs/3pss.cfg" --grid 1 --quiet
for w in "deg/s^2" "deg/s" "time ms" "workspace edge" "bandwidth and margins" " Hz" " dB" \
         "phase margin" "deg" "lowest parasitic mode"; do
  grep -qF "$w" "$TMP/out" || { echo "FAIL: text lacks '$w'"; fail=1; }
done

# --out: HDF5 in SI, then a second run refuses to overwrite it
expect_rc 0 "$POMLAB" capability "$SRC/configs/3pss.cfg" --grid 3 --quiet --out "$TMP/cap.h5"
[ -f "$TMP/cap.h5" ] && [ ! -e "$TMP/cap.h5.partial" ] || { echo "FAIL: no cap.h5"; fail=1; }
if $PY -c "import h5py" 2> /dev/null; then
  $PY -c "
import h5py
f = h5py.File('$TMP/cap.h5', 'r')
assert f['poses/figures'].shape == (27, 26)
fig = f['poses/figures'][:]
assert (fig[:, 16] == 1).all() and (fig[:, 17] > 1).all()  # freq_ok, bw_worst (Hz)
assert f.attrs['bw_worst_hz'] == fig[:, 17].min()
assert 'config' in f and 'x' in f['slews']
" || { echo "FAIL: cap.h5 content"; fail=1; }
fi
size=$(stat -c %s "$TMP/cap.h5")
expect_rc 2 "$POMLAB" capability "$SRC/configs/3pss.cfg" --quiet --out "$TMP/cap.h5"
expect_msg "cap.h5" "never overwritten"
[ "$(stat -c %s "$TMP/cap.h5")" = "$size" ] || { echo "FAIL: cap.h5 changed"; fail=1; }
expect_rc 2 "$POMLAB" capability "$SRC/configs/3pss.cfg" --quiet --out "$TMP/cap.csv"
expect_msg "--out" ".h5"

# the map
if $PY -c "import matplotlib" 2> /dev/null; then
  expect_rc 0 "$POMLAB" capability "$SRC/configs/3pss.cfg" --grid 5 --quiet --plots "$TMP/plots"
  for f in capability_map.csv capability_map.png bode_home.json bode_home.png bode_worst.json \
           bode_worst.png; do
    [ -s "$TMP/plots/$f" ] || { echo "FAIL: no $f"; cat "$TMP/err"; fail=1; }
  done
  head -1 "$TMP/plots/capability_map.csv" | grep -qF "bw_worst_hz" ||
    { echo "FAIL: map lacks bw_worst_hz"; fail=1; }
fi

# the small-signal figures follow joints.model: rigid joints have no parasitic mode;
# bandwidth_grid_points = 0 turns them off (no section, NaN/null figures)
sed 's/^joints = {/joints = { model = "rigid";/' "$SRC/configs/3pss.cfg" > "$TMP/rigid.cfg"
expect_rc 0 "$POMLAB" capability "$TMP/rigid.cfg" --grid 1 --json --quiet
$PY -c "
import json
r = json.load(open('$TMP/out'))
assert r['bandwidth_joints'] == 'rigid' and r['home']['freq_ok'] and r['home']['mode_hz'] is None
assert r['bandwidth_poses'] == 1
" || { echo "FAIL: rigid-joint bandwidth"; cat "$TMP/out"; fail=1; }
{ cat "$SRC/configs/3pss.cfg"; echo "capability = { bandwidth_grid_points = 0; };"; } > "$TMP/nobw.cfg"
expect_rc 0 "$POMLAB" capability "$TMP/nobw.cfg" --grid 1 --quiet
if grep -qF "bandwidth and margins" "$TMP/out"; then echo "FAIL: bandwidth section printed"; fail=1; fi

# bad inputs: exit 2, the key or option and the value named
expect_rc 2 "$POMLAB" capability "$SRC/configs/3pss.cfg" --grid 4
expect_msg "capability.grid_points" "4" "odd"
expect_rc 2 "$POMLAB" capability "$SRC/configs/3pss.cfg" --grid 99
expect_msg "--grid" "99"
expect_rc 2 "$POMLAB" capability "$SRC/configs/3pss.cfg" --current-limit -1
expect_msg "--current-limit" "-1"
expect_rc 2 "$POMLAB" capability "$SRC/configs/3pss.cfg" --bogus
expect_msg "unknown option" "--bogus"
expect_rc 2 "$POMLAB" capability
expect_msg "missing CONFIG"
for bad in "slew_amplitudes_deg = [10.0, 3.0];|slew_amplitudes_deg|ascending" \
           "slew_directions = 7;|slew_directions|7" \
           "rate_directions = 3;|rate_directions|3" \
           "grid_point = 3;|grid_point|" \
           "bandwidth_grid_points = 2;|bandwidth_grid_points|odd"; do
  IFS='|' read -r line key word <<< "$bad"
  { cat "$SRC/configs/3pss.cfg"; echo "capability = { $line };"; } > "$TMP/bad.cfg"
  expect_rc 2 "$POMLAB" capability "$TMP/bad.cfg" --quiet
  expect_msg "$key" $word
done

exit $fail
