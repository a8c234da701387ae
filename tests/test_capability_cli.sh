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
import json
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
"; then echo "FAIL: $cfg JSON"; cat "$TMP/out"; fail=1; fi
done

# text in device units
expect_rc 0 "$POMLAB" capability "$SRC/configs/3pss.cfg" --grid 1 --quiet
for w in "deg/s^2" "deg/s" "time ms" "workspace edge"; do
  grep -qF "$w" "$TMP/out" || { echo "FAIL: text lacks '$w'"; fail=1; }
done

# --out: HDF5 in SI, then a second run refuses to overwrite it
expect_rc 0 "$POMLAB" capability "$SRC/configs/3pss.cfg" --grid 3 --quiet --out "$TMP/cap.h5"
[ -f "$TMP/cap.h5" ] && [ ! -e "$TMP/cap.h5.partial" ] || { echo "FAIL: no cap.h5"; fail=1; }
if $PY -c "import h5py" 2> /dev/null; then
  $PY -c "
import h5py
f = h5py.File('$TMP/cap.h5', 'r')
assert f['poses/figures'].shape == (27, 13)
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
  [ -s "$TMP/plots/capability_map.csv" ] && [ -s "$TMP/plots/capability_map.png" ] ||
    { echo "FAIL: no map"; cat "$TMP/err"; fail=1; }
fi

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
           "grid_point = 3;|grid_point|"; do
  IFS='|' read -r line key word <<< "$bad"
  { cat "$SRC/configs/3pss.cfg"; echo "capability = { $line };"; } > "$TMP/bad.cfg"
  expect_rc 2 "$POMLAB" capability "$TMP/bad.cfg" --quiet
  expect_msg "$key" $word
done

exit $fail
