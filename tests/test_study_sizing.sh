#!/bin/bash
# test_study_sizing.sh POMLAB SOURCE_DIR - the sizing rule of a study
# (docs/optimize.md 6c): a linear candidate runs the largest scale whose
# regular dexterous workspace covers the target (its workspace at that scale
# covers it, at 0.3 % more it does not, as `pomlab workspace` finds); a
# rotary candidate keeps its scale; a target a rotary candidate cannot reach
# stops the study with a message naming its workspace and the target; the
# key is checked like any other.
set -u
POMLAB=$1
SRC=$(cd "$2" && pwd)
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
fail=0
PY=/usr/bin/python3

study() { # study NAME TARGET_DEG: C01 (linear) and C05 (rotary), 2 maneuvers
  cat > "$TMP/$1.cfg" <<EOF
name = "$1";
montecarlo = { maneuvers = 2; seed = 5; space = "orientation"; tilt_max_deg = 4.0;
               torsion_max_deg = 4.0; };
study = {
  output = "$TMP/$1.h5";
  override = {
    joints = { model = "rigid"; };
    scene = { coil_inductance = false; };
    sizing = { run_in_study = true; target_half_width_deg = $2; };
  };
};
candidates = (
  { name = "C01"; config = "$SRC/configs/3pss.cfg"; override = { architecture = "3PSS-table"; }; },
  { name = "C05"; config = "$SRC/configs/catalog/3rrr_coaxial.cfg"; }
);
EOF
}

# the half-width (deg) `pomlab workspace` finds for CONFIG at platform radius R (mm)
rdw_at() {
  sed "s/^  platform_radius_mm = .*/  platform_radius_mm = $2;/" "$1" > "$TMP/at.cfg"
  "$POMLAB" workspace "$TMP/at.cfg" --json 2> /dev/null |
    $PY -c "import json, sys; print(json.load(sys.stdin)['half_width_deg'])"
}

study ok 8.0
if ! "$POMLAB" study "$TMP/ok.cfg" --no-plots --quiet > "$TMP/out" 2> "$TMP/err"; then
  echo "FAIL: the sized study did not run"; cat "$TMP/err"; exit 1
fi
read -r r_lin sized_lin scaled_lin r_rot sized_rot scaled_rot <<< "$($PY - "$TMP/ok.h5" <<'EOF'
import sys, h5py
f = h5py.File(sys.argv[1], "r")
out = []
for c in ("0", "1"):
    a = f["candidates"][c].attrs
    out += [repr(a["platform_radius_m"] * 1e3), str(a["pipeline_sized"]), str(a["sizing_scaled"])]
print(" ".join(out))
EOF
)"
[ "$sized_lin" = 1 ] && [ "$scaled_lin" = 1 ] || { echo "FAIL: C01 not scaled"; fail=1; }
[ "$sized_rot" = 1 ] && [ "$scaled_rot" = 0 ] || { echo "FAIL: C05 scaled"; fail=1; }
# the rotary candidate keeps its config's link radius (30 mm)
$PY -c "import sys; sys.exit(abs($r_rot - 30.0) > 1e-12)" || { echo "FAIL: C05 radius $r_rot"; fail=1; }
# largest covering scale: the workspace covers 8 deg at r, not at 1.003 r
# (bisection to scale_rel_tol = 1e-3)
w=$(rdw_at "$SRC/configs/3pss.cfg" "$r_lin")
w_more=$(rdw_at "$SRC/configs/3pss.cfg" "$($PY -c "print($r_lin * 1.003)")")
$PY -c "import sys; sys.exit(not ($w >= 8.0 and $w_more < 8.0))" ||
  { echo "FAIL: C01 at $r_lin mm covers $w deg, at 0.3 % more $w_more deg (target 8)"; fail=1; }
# the config's radius (12.25 mm) covers 13 deg: sizing to 8 deg must enlarge it
$PY -c "import sys; sys.exit(not $r_lin > 12.3)" || { echo "FAIL: C01 radius $r_lin"; fail=1; }
grep -q "C01, sizing (docs/optimize.md 6c): platform_radius_mm .* the largest whose stroke covers the target (linear" "$TMP/out" ||
  { echo "FAIL: no sizing line for C01"; fail=1; }
grep -q "C05, sizing (docs/optimize.md 6c): link_radius_mm 30 mm (config 30 mm), kept (rotary" "$TMP/out" ||
  { echo "FAIL: no sizing line for C05"; fail=1; }

# C05's range covers +-9 deg only: a target of 12 deg is refused, named
study short 12.0
"$POMLAB" study "$TMP/short.cfg" --no-plots --quiet > "$TMP/out" 2> "$TMP/err"
rc=$?
if [ $rc -eq 0 ] || ! grep -q "short of the target +-12 deg" "$TMP/err" ||
   ! grep -q "candidate 'C05'" "$TMP/err"; then
  echo "FAIL: an unreachable target (rc $rc):"; cat "$TMP/err"; fail=1
fi

# the key is checked: a target beyond the range
study bad 95.0
"$POMLAB" study "$TMP/bad.cfg" --no-plots --quiet > "$TMP/out" 2> "$TMP/err"
rc=$?
if [ $rc -ne 2 ] || ! grep -q "sizing.target_half_width_deg" "$TMP/err"; then
  echo "FAIL: target 95 deg (rc $rc):"; cat "$TMP/err"; fail=1
fi

[ $fail -eq 0 ] && echo "sizing: C01 $r_lin mm (covers $w deg, $w_more at +0.3 %), C05 kept"
exit $fail
