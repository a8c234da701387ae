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

finish test_messages
