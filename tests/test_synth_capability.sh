#!/bin/bash
# test_synth_capability.sh POMLAB SOURCE_DIR - the capability floor of
# `pomlab synth` (synthesis.capability_require, docs/optimize.md 6b): the
# scaled optimum's figures equal `pomlab capability --grid 3` on the written
# geometry with the same model (the same code on the same mechanism); a
# floor the written (surrogate) optimum fails but the direct one meets makes
# the direct one written; a floor no optimum meets: exit 1, the value and
# the bound named; the syntax is study.capability_require's (a bad one
# refused naming file, key, value).
set -u
POMLAB=$1
SRC=$2
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
fail=0
PY=/usr/bin/python3

# the 3P-S-S/S reference (its @include made absolute) and a small synthesis
sed "s#@include \"\\([^/\"]*\\)\"#@include \"$SRC/configs/\\1\"#" "$SRC/configs/3pss.cfg" \
  > "$TMP/base.cfg"
syn() { # FILE FLOOR [EXTRA]
  cat "$TMP/base.cfg" - > "$1" <<EOF
synthesis = {
  variables = ( { name = "limb_lean_deg"; min = 30.0; max = 45.0; },
                { name = "limb_azimuth_deg"; min = 50.0; max = 75.0; } );
  design = { kind = "ccd_face"; center_points = 1; };
  region_half_width_deg = 6.0; region_resolution_deg = 4.0;
  goals = ( { response = "gci"; goal = "maximize"; low = 0.5; high = 1.0; } );
  optimizer = { global = "direct_l"; global_max_evals = 200; local = "bobyqa"; };
  direct = { global = "direct_l"; global_max_evals = 60; local = "bobyqa"; local_max_evals = 40; };
  target_half_width_deg = 9.3; scale_min_mm = 2.0; scale_max_mm = 100.0;
  capability_require = [$2];
  ${3:-}
};
EOF
}
run() { # NAME -> $TMP/NAME.json, rc in $TMP/NAME.rc
  "$POMLAB" synth "$TMP/$1.cfg" --json --quiet --out "$TMP/$1_" > "$TMP/$1.json" 2> "$TMP/$1.err"
  echo $? > "$TMP/$1.rc"
}

# a loose floor on the surrogate's and on the direct optimum (write = "direct")
syn "$TMP/s.cfg" '"acc_inscribed_worst >= 1e3", "bw_worst_hz >= 10"'
syn "$TMP/d.cfg" '"acc_inscribed_worst >= 1e3"' 'write = "direct";'
run s
run d
for n in s d; do
  [ "$(cat "$TMP/$n.rc")" = 0 ] || { echo "FAIL: synth $n rc $(cat "$TMP/$n.rc")"; cat "$TMP/$n.err"; fail=1; }
done

# the figures equal pomlab capability on the written geometry (same model, grid 3)
geo=$($PY -c "import json; print(json.load(open('$TMP/s.json'))['synth'][0]['geometry_file'])")
$PY - "$TMP/base.cfg" "$geo" "$TMP/cap.cfg" <<'EOF'
import sys
text = open(sys.argv[1]).read()
i = text.index('geometry = {')
j = text.index('};', i) + 2
open(sys.argv[3], 'w').write(text[:i] + '@include "%s"\n' % sys.argv[2] + text[j:])
EOF
"$POMLAB" capability "$TMP/cap.cfg" --grid 3 --json --quiet > "$TMP/cap.json" 2> "$TMP/err" \
  || { echo "FAIL: capability of the written geometry"; cat "$TMP/err"; fail=1; }

if ! $PY - "$TMP" <<'EOF'; then echo "FAIL: floor met"; fail=1; fi
import json, sys
tmp = sys.argv[1]
s = json.load(open(tmp + "/s.json"))["synth"][0]
cap = json.load(open(tmp + "/cap.json"))
c = s["capability"]
assert c["met"] is True and c["switched"] is False and len(c["checks"]) == 1, c
ck = c["checks"][0]
assert ck["optimum"] == "surrogate" and s["written"] == "surrogate", ck
# the geometry file is written with %.17g-free digits: the radius to 1e-9 relative
assert abs(ck["platform_radius_mm"] - s["platform_radius_mm"]) <= 1e-9 * s["platform_radius_mm"]
got = {q["figure"]: q["value"] for q in ck["requirements"]}
want = {"acc_inscribed_worst": cap["worst_acc"]["acc_inscribed_rad_per_s2"],
        "bw_worst_hz": cap["bw_worst_hz"]}
# the same code on the same mechanism; the geometry file rounds the design
# parameters to its printed digits, hence 1e-6 and not rounding
for k, v in want.items():
    assert abs(got[k] - v) <= 1e-6 * abs(v), (k, got[k], v)
assert all(q["met"] for q in ck["requirements"]), ck
assert ck["requirements"][0]["requirement"] == "acc_inscribed_worst >= 1000", ck
# text: each requirement with its value and the bound
EOF

# a floor between the two optima's accelerations: the surrogate's (written by
# default) fails it, the direct one meets it and is written instead
bound=$($PY -c "
import json
a = json.load(open('$TMP/s.json'))['synth'][0]['capability']['checks'][0]['requirements'][0]['value']
b = json.load(open('$TMP/d.json'))['synth'][0]['capability']['checks'][0]['requirements'][0]['value']
assert a != b, (a, b)
print(('acc_inscribed_worst >= %.17g' if b > a else 'acc_inscribed_worst <= %.17g') % ((a + b) / 2))
")
syn "$TMP/w.cfg" "\"$bound\""
run w
if ! $PY - "$TMP" <<'EOF'; then echo "FAIL: switched to the direct optimum"; cat "$TMP/w.json"; fail=1; fi
import json, sys
tmp = sys.argv[1]
w = json.load(open(tmp + "/w.json"))["synth"][0]
d = json.load(open(tmp + "/d.json"))["synth"][0]
assert open(tmp + "/w.rc").read().strip() == "0"
c = w["capability"]
assert c["met"] is True and c["switched"] is True and len(c["checks"]) == 2, c
assert [k["optimum"] for k in c["checks"]] == ["surrogate", "direct"], c
assert [k["met"] for k in c["checks"]] == [False, True], c
assert w["written"] == "direct", w["written"]
# the direct optimum scaled as in the run that wrote it directly
assert abs(w["platform_radius_mm"] - d["platform_radius_mm"]) <= 1e-9 * d["platform_radius_mm"]
EOF

# a floor nobody meets (the loop's bandwidth is ~53 Hz, set by tau_D): exit 1
syn "$TMP/n.cfg" '"bw_worst_hz >= 100"'
run n
"$POMLAB" synth "$TMP/n.cfg" --quiet --out "$TMP/nt_" > "$TMP/n.txt" 2> /dev/null
[ "$(cat "$TMP/n.rc")" = 1 ] || { echo "FAIL: unmet floor rc $(cat "$TMP/n.rc"), want 1"; fail=1; }
grep -q "no optimum meets synthesis.capability_require: surrogate optimum: bw_worst_hz = [0-9.]* Hz, required >= 100 Hz" "$TMP/n.err" \
  || { echo "FAIL: unmet floor message"; cat "$TMP/n.err"; fail=1; }
grep -q "bw_worst_hz = [0-9.]* Hz, required >= 100 Hz: FAILS" "$TMP/n.txt" \
  || { echo "FAIL: text report of the unmet floor"; cat "$TMP/n.txt"; fail=1; }
grep -q "NO optimum meets the floor" "$TMP/n.txt" || { echo "FAIL: text verdict"; fail=1; }
$PY -c "
import json
c = json.load(open('$TMP/n.json'))['synth'][0]['capability']
assert c['met'] is False and c['switched'] is False and len(c['checks']) == 2, c
for k in c['checks']:
    q = k['requirements'][0]
    assert q['figure'] == 'bw_worst_hz' and q['bound'] == 100 and 40 < q['value'] < 100, q
import glob, h5py
with h5py.File(glob.glob('$TMP/n_*.h5')[0], 'r') as f:
    g = f['capability']
    assert g.attrs['met'] == 0 and g['checks'].shape == (2, 5), g['checks'].shape
    for row, k in zip(g['checks'][:], c['checks']):
        assert row[3] == k['requirements'][0]['value'] or abs(row[3] / k['requirements'][0]['value'] - 1) < 1e-9
        assert row[4] == 0 and row[2] == 0
" || { echo "FAIL: unmet floor JSON and HDF5"; fail=1; }

# the syntax is study.capability_require's: refused naming file, key, value
syn "$TMP/bad.cfg" '"bw_worst_hz > 100"'
"$POMLAB" synth "$TMP/bad.cfg" --quiet --out "$TMP/b_" > /dev/null 2> "$TMP/err"
rc=$?
[ $rc -eq 2 ] || { echo "FAIL: bad requirement rc $rc, want 2"; fail=1; }
for w in "bad.cfg" "synthesis.capability_require.[0]" "bw_worst_hz > 100"; do
  grep -qF -- "$w" "$TMP/err" || { echo "FAIL: message lacks '$w'"; cat "$TMP/err"; fail=1; }
done
syn "$TMP/bad2.cfg" '"acc_inscribed_worst >= 1e3"' 'capability_grid_points = 4;'
"$POMLAB" synth "$TMP/bad2.cfg" --quiet --out "$TMP/b_" > /dev/null 2> "$TMP/err"
rc=$?
[ $rc -eq 2 ] && grep -q "synthesis.capability_grid_points" "$TMP/err" \
  || { echo "FAIL: even grid accepted (rc $rc)"; cat "$TMP/err"; fail=1; }

[ $fail -eq 0 ] && echo "test_synth_capability: ok"
exit $fail
