#!/usr/bin/env bash
# test_messages.sh - failures that name the key, the value and the rule
# (issue 22, items 17, 18 and 19): solver settings inside their documented
# range that used to fail later in CVODE's words, a sensitivity analysis
# without usable runs, and messages that named the wrong key.
# Usage: test_messages.sh PATH/TO/pomlab SOURCE_DIR
set -u
POMLAB=$1
SRC=$2
. "$(dirname "$0")/cli_lib.sh"

CFG="$SRC/configs/3pss.cfg"
# a copy of the shipped config with one solver key set to a value
with_solver() {
  sed "s/^\( *$1 *= *\)[^;]*;/\1$2;/" "$CFG" >"$TMP/m.cfg"
  grep -q "$1 = $2;" "$TMP/m.cfg" || fail "could not set $1 = $2"
}

# --- item 17: tiny tolerances and step bounds are refused by name ---------------
with_solver atol_scale 1e-320
expect_rc 2 "$POMLAB" simulate "$TMP/m.cfg" --target 1,1,1
expect_err "key 'solver.atol_scale' = 9.99988867182683e-321: expected 0 (natural sizes) or a value in [1e-15, 1]"
with_solver atol_scale 1e-300
expect_rc 2 "$POMLAB" simulate "$TMP/m.cfg" --target 1,1,1
expect_err "key 'solver.atol_scale'"
with_solver max_step_ms 1e-320
expect_rc 2 "$POMLAB" simulate "$TMP/m.cfg" --target 1,1,1
expect_err "key 'solver.max_step_ms' = 9.99988867182683e-321: expected 0 (unlimited) or a value in [1e-06, 1e+06] ms"
with_solver max_step_ms 1e-9
expect_rc 2 "$POMLAB" montecarlo "$TMP/m.cfg" --n 1 --quiet
expect_err "key 'solver.max_step_ms'"
# the bounds themselves are accepted; what fails there names solver.max_steps
with_solver atol_scale 1e-15
expect_rc 1 "$POMLAB" simulate "$TMP/m.cfg" --target 1,1,1 --joints rigid
expect_err "solver.max_steps"
with_solver max_step_ms 1e-6
expect_rc 1 "$POMLAB" simulate "$TMP/m.cfg" --target 1,1,1 --joints rigid
expect_err "solver.max_steps"
with_solver atol_scale 1e-9
expect_rc 0 "$POMLAB" simulate "$TMP/m.cfg" --target 1,1,1 --joints rigid

# --- item 18: a sensitivity analysis without usable runs -------------------------
# a stroke drawn in 0.5-1 mm puts every 3 mm target outside it: every run fails
cp "$CFG" "$TMP/3pss.cfg"
cat >"$TMP/nouse.cfg" <<CFG
name = "nouse";
montecarlo = { maneuvers = 2; seed = 5; range_mm = 3.0; };
study = { threads = 1; override = { joints = { model = "rigid"; };
  scene = { coil_inductance = false; }; }; };
uncertain = ( { key = "limits.stroke_mm"; dist = "uniform"; min = 0.5; max = 1.0; },
  { key = "controller.kp"; dist = "uniform"; min = 0.8; max = 1.2; relative = true; } );
sensitivity = { method = "sobol"; samples = 8; bootstrap = 20; maneuvers = 1; };
candidates = ( { name = "A"; config = "3pss.cfg"; } );
CFG
expect_rc 1 "$POMLAB" sensitivity "$TMP/nouse.cfg" --out "$TMP/n.h5" --quiet
expect_err "pomlab sensitivity: candidate 'A': no indices: sobol: 0 of 8 base samples usable"
expect_err "no candidate has indices, so nothing was written to $TMP/n.h5"
check "no results file of NaN" [ ! -e "$TMP/n.h5" ]
check "no figure" [ ! -e "$TMP/n.png" ]
check "nothing on stdout" [ ! -s "$TMP/out" ]
sed -i 's/method = "sobol"; samples = 8; bootstrap = 20;/method = "morris"; trajectories = 4;/' "$TMP/nouse.cfg"
expect_rc 1 "$POMLAB" sensitivity "$TMP/nouse.cfg" --out "$TMP/n.h5" --quiet --json
expect_err "pomlab sensitivity: candidate 'A': no indices:"
check "morris: no results file" [ ! -e "$TMP/n.h5" ]

# --- item 19: each message names the key that breaks the rule ------------------
# an uncertain parameter's spread, bounds and centre, not its `dist`
unc() {
  printf 'name = "u";\nmontecarlo = { maneuvers = 2; seed = 5; };\nuncertain = %s;\n%s\n' "$1" \
    'candidates = ( { name = "A"; config = "3pss.cfg"; } );' >"$TMP/u.cfg"
  expect_rc 2 "$POMLAB" study "$TMP/u.cfg" --out "$TMP/u.h5" --quiet --no-plots
  expect_err "$2"
  check "no message against .dist: $2" bash -c "! grep -q \"dist'\" '$TMP/err'"
}
R='key = "actuator.resistance_ohm"'
unc "( { $R; dist = \"normal\"; mean = 10.0; sd = -0.5; } )" \
  "key 'uncertain.[0].sd' = -0.5: normal: needs a finite mean and sd > 0"
unc "( { $R; dist = \"lognormal\"; median = 10.0; sigma_ln = 0.0; } )" \
  "key 'uncertain.[0].sigma_ln' = 0: lognormal: needs a finite median and sigma_ln > 0"
unc "( { $R; dist = \"lognormal\"; median = -1.0; sigma_ln = 0.2; } )" \
  "key 'uncertain.[0].median' = -1: lognormal: median must be > 0"
unc "( { $R; dist = \"truncated_normal\"; mean = 10.0; sd = 1.0; min = 12.0; max = 9.0; } )" \
  "key 'uncertain.[0].max' = 9: truncated_normal: needs finite min < max (found 12, 9)"
unc "( { $R; dist = \"truncated_normal\"; mean = 10.0; sd = 0.01; min = 20.0; max = 21.0; } )" \
  "key 'uncertain.[0].min' = 20: truncated_normal: [min, max] = [20, 21] holds no probability"
unc "( { $R; dist = \"uniform\"; min = 1.0; max = 0.5; } )" \
  "key 'uncertain.[0].max' = 0.5: uniform: needs finite min < max"
unc "( { $R; dist = \"lognormal\"; median = 10.0; sigma_ln = 0.1; min = 5.0; max = 4.0; } )" \
  "key 'uncertain.[0].max' = 4: lognormal: needs 0 <= min < max"
# a group where a list belongs: said so, not "uncertain.[0].key missing"
unc "{ $R; dist = \"uniform\"; min = 9.0; max = 11.0; }" \
  "key 'uncertain' = {group}: expected a list in parentheses"
check "not the missing first key" bash -c "! grep -q 'uncertain.\[0\].key' '$TMP/err'"
# the 3-RRR whose links cannot join u and v: the rule that fails
rrr() {
  sed -e "s/proximal_angle_deg = 90.0/proximal_angle_deg = $1/" \
    -e "s/distal_angle_deg = 90.0/distal_angle_deg = $2/" "$SRC/configs/3rrr.cfg" >"$TMP/r.cfg"
  expect_rc 2 "$POMLAB" model "$TMP/r.cfg"
  expect_err "$3"
}
rrr 150 30 "the angle u-v = 90 deg (set by geometry.base_cone_deg, platform_cone_deg and platform_twist_deg) is shorter than |alpha1 - alpha2|: the leg would have to fold; it must lie in [|alpha1 - alpha2|, min(alpha1 + alpha2, 360 deg - alpha1 - alpha2)] = [120, 180] deg (alpha1 = geometry.proximal_angle_deg = 150, alpha2 = geometry.distal_angle_deg = 30)"
check "not the sum as the rule" bash -c "! grep -q 'alpha1 + alpha2 = 180' '$TMP/err'"
rrr 30 40 "is longer than alpha1 + alpha2: the links cannot reach; it must lie in [|alpha1 - alpha2|, min(alpha1 + alpha2, 360 deg - alpha1 - alpha2)] = [10, 70] deg"
rrr 170 170 "is longer than 360 deg - alpha1 - alpha2; it must lie in"

# --- issue 30 item 5: the ranges end where the shipped defaults integrate;
# what runs out of solver.max_steps names the joint mode its steps resolve
expect_rc 2 "$POMLAB" simulate "$CFG" --target 1,1,1 --rtol 1e-13
expect_err "key 'solver.rtol' = 1e-13: out of range: expected a value in [1e-12, 0.1]"
sed 's/^  stiffness_N_per_m = [^;]*;/  stiffness_N_per_m = 3e10;/' "$CFG" >"$TMP/k.cfg"
expect_rc 2 "$POMLAB" simulate "$TMP/k.cfg" --target 1,1,1
expect_err "key 'joints.stiffness_N_per_m' = 30000000000: out of range: expected a value in [1, 1e+10]"
sed -e 's/^  stiffness_N_per_m = [^;]*;/  stiffness_N_per_m = 1e10;/' \
  -e 's/^  damping_Ns_per_m = [^;]*;/  damping_Ns_per_m = 0;/' \
  -e 's/^  max_steps = [^;]*;/  max_steps = 3000;/' "$CFG" >"$TMP/k.cfg"
expect_rc 1 "$POMLAB" simulate "$TMP/k.cfg" --target 1,1,1
expect_err "(spherical) at joints.stiffness_N_per_m = 1e+10 has omega ~ 4.9e+06 rad/s (damping ratio 0)"

finish test_messages
