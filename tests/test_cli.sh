#!/usr/bin/env bash
# test_cli.sh - runs the kinematics commands of pomlab on the shipped configs
# and on broken ones: exit codes, JSON contents, and error messages that name
# the offending key.
# Usage: test_cli.sh PATH/TO/pomlab SOURCE_DIR
set -u
POMLAB=$1
SRC=$2
. "$(dirname "$0")/cli_lib.sh"

for arch in 3pss 3sps; do
  cfg="$SRC/configs/$arch.cfg"
  # --- shipped configs work -----------------------------------------------
  expect_rc 0 "$POMLAB" model "$cfg"
  expect_in "$TMP/out" "platform"
  expect_rc 0 "$POMLAB" model "$cfg" --json
  json_check "len(d['mechanism']['bodies']) == 8 and len(d['mechanism']['joints']) == 10 and len(d['mechanism']['actuators']) == 3"
  json_check "abs(d['mechanism']['bodies'][1]['mass_kg'] - (0.0293 if '$arch' == '3pss' else 0.0299)) < 1e-12"
  expect_rc 0 "$POMLAB" ik "$cfg" --euler-zyx 0,0,0 --json
  # isotropic home: kappa = 1, singular values 15 mm, q = 0
  json_check "abs(d['kappa'] - 1) < 1e-9 and all(abs(s - 0.015) < 1e-12 for s in d['singular_values']) and max(map(abs, d['q'])) < 1e-15 and d['actuator_unit'] == 'm'"
  expect_rc 0 "$POMLAB" ik "$cfg" --euler-zyx 7.5,-4.25,3.125
  expect_in "$TMP/out" "limit check: ok"
  # IK -> FK through the command line (JSON carries 17 digits)
  expect_rc 0 "$POMLAB" ik "$cfg" --euler-zyx 7.5,-4.25,3.125 --json
  q=$("$PY" -c "import json; d=json.load(open('$TMP/out')); print(','.join('%.17g' % v for v in d['q_display']))")
  expect_rc 0 "$POMLAB" fk "$cfg" --q "$q" --json
  json_check "max(abs(a - b) for a, b in zip(d['euler_zyx_deg'], [7.5, -4.25, 3.125])) < 1e-8 and d['residual'] <= 1e-12"
  json_check "max(abs(a - b) for a, b in zip(d['q'], d['q_target'])) <= 1e-12"
  expect_rc 0 "$POMLAB" fk "$cfg" --q 1.5,-2,0.7
  expect_in "$TMP/out" "quaternion"
  expect_rc 0 "$POMLAB" workspace "$cfg" --json --map "$TMP/map.csv"
  json_check "d['half_width_deg'] == 13 and d['min_dexterity'] >= 0.3 and 0.3 < d['gci'] < 1"
  checks=$((checks + 1))
  [ "$(head -1 "$TMP/map.csv")" = "psi_deg,theta_deg,phi_deg,reachable,within_limits,dexterity,q1_mm,q2_mm,q3_mm,violations" ] &&
    [ "$(wc -l <"$TMP/map.csv")" = $((21 * 21 * 21 + 1)) ] || fail "dexterity map header or size"

  # --- poses reported as unreachable / out of limits -------------------------
  expect_rc 1 "$POMLAB" ik "$cfg" --euler-zyx 0,35,0
  expect_in "$TMP/out" "FAILED - stroke limb"
  expect_rc 1 "$POMLAB" fk "$cfg" --q 500,-500,500
  expect_in "$TMP/err" "continuation stalled"

  # --- broken configs: exit 2 and the key named -------------------------------
  sed 's/stroke_mm = 12.0;/stroke_mm = "12";/' "$cfg" >"$TMP/mistyped.cfg"
  expect_rc 2 "$POMLAB" ik "$TMP/mistyped.cfg" --euler-zyx 0,0,0
  expect_in "$TMP/err" "key 'limits.stroke_mm'"
  expect_in "$TMP/err" "expected a real number"
  sed 's/stroke_mm = 12.0;/stroke_mm = -12.0;/' "$cfg" >"$TMP/range.cfg"
  expect_rc 2 "$POMLAB" workspace "$TMP/range.cfg"
  expect_in "$TMP/err" "key 'limits.stroke_mm' = -12"
  expect_in "$TMP/err" "out of range"
  sed 's/cone_base_max_deg = /cone_base_max_dg = /' "$cfg" >"$TMP/unknown.cfg"
  expect_rc 2 "$POMLAB" fk "$TMP/unknown.cfg" --q 0,0,0
  expect_in "$TMP/err" "limits.cone_base_max_dg"
  expect_in "$TMP/err" "unknown key"
  printf 'bogus_group = { a = 1; };\n' | cat "$cfg" - >"$TMP/top.cfg"
  expect_rc 2 "$POMLAB" model "$TMP/top.cfg"
  expect_in "$TMP/err" "bogus_group"
  sed 's/mass_kg = 2.9[39]e-2;/mass_kg = 0.0;/' "$cfg" >"$TMP/mass.cfg"
  expect_rc 2 "$POMLAB" model "$TMP/mass.cfg"
  expect_in "$TMP/err" "key 'inertia.platform.mass_kg' = 0"
  sed 's/moments_kgm2 = \[1.0e-6, 1.0e-6, 2.0e-6\]/moments_kgm2 = [1.0e-6, 1.0e-6, 5.0e-6]/; s/moments_kgm2 = \[1.02e-6, 1.0e-6, 2.0e-6\]/moments_kgm2 = [1.02e-6, 1.0e-6, 5.0e-6]/' "$cfg" >"$TMP/moments.cfg"
  expect_rc 2 "$POMLAB" model "$TMP/moments.cfg"
  expect_in "$TMP/err" "inertia.platform.moments_kgm2"
  sed 's/mode = "parameters";/mode = "parameters" ]/' "$cfg" >"$TMP/syntax.cfg"
  expect_rc 2 "$POMLAB" ik "$TMP/syntax.cfg" --euler-zyx 0,0,0
  expect_in "$TMP/err" "syntax.cfg:"
  sed 's/architecture = "3[PS][SP]S";/architecture = "3QQQ";/' "$cfg" >"$TMP/arch.cfg"
  expect_rc 2 "$POMLAB" ik "$TMP/arch.cfg" --euler-zyx 0,0,0
  expect_in "$TMP/err" "key 'architecture' = \"3QQQ\""
  sed 's/resolution_deg = 1.0;/resolution_deg = 0.0;/' "$cfg" >"$TMP/ws.cfg"
  expect_rc 2 "$POMLAB" workspace "$TMP/ws.cfg"
  expect_in "$TMP/err" "workspace.resolution_deg"
done

# --- an unreachable pose: long, nearly horizontal links (3PSS) ------------------
cat >"$TMP/reach.cfg" <<'CFG'
architecture = "3PSS";
geometry = { mode = "parameters"; platform_radius_mm = 12.0; limb_length = 2.0;
             limb_lean_deg = 80.0; limb_azimuth_deg = 60.0; };
CFG
expect_rc 0 "$POMLAB" ik "$TMP/reach.cfg" --euler-zyx 0,10,0
expect_rc 1 "$POMLAB" ik "$TMP/reach.cfg" --euler-zyx 10,0,0
expect_in "$TMP/out" "reachable: NO - limb 1: the link cannot reach the slider axis"
expect_rc 1 "$POMLAB" ik "$TMP/reach.cfg" --euler-zyx 10,0,0 --json
json_check "d['reachable'] is False and d['unreachable_limb'] == 1 and d['q'] is None"

# --- usage errors and help -----------------------------------------------------
cfg="$SRC/configs/3pss.cfg"
for c in model ik fk workspace; do
  expect_rc 0 "$POMLAB" "$c" --help
  expect_in "$TMP/out" "usage: pomlab $c"
done
expect_in <("$POMLAB" ik --help) "DEGREES"
expect_in <("$POMLAB" fk --help) "MILLIMETRES"
expect_rc 2 "$POMLAB" ik "$cfg"
expect_in "$TMP/err" "missing --euler-zyx"
expect_rc 2 "$POMLAB" ik "$cfg" --euler-zyx 1,2
expect_in "$TMP/err" "expected three numbers"
expect_rc 2 "$POMLAB" ik "$cfg" --euler-zyx 0,90,0
expect_rc 2 "$POMLAB" fk "$cfg" --q a,b,c
# non-finite numbers are usage errors, not unreachable poses
expect_rc 2 "$POMLAB" ik "$cfg" --euler-zyx nan,0,0
expect_in "$TMP/err" "finite"
expect_rc 2 "$POMLAB" fk "$cfg" --q 1,inf,0
expect_in "$TMP/err" "finite"
expect_rc 2 "$POMLAB" fk "$cfg" --q 1,2,3 --frobnicate
expect_in "$TMP/err" "--frobnicate"
expect_rc 2 "$POMLAB" model "$TMP/does-not-exist.cfg"
expect_in "$TMP/err" "does-not-exist.cfg"

echo "test_cli: $checks checks, $fails failed"
[ "$fails" = 0 ]
