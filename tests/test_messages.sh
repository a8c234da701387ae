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

finish test_messages
