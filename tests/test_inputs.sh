#!/usr/bin/env bash
# test_inputs.sh - every input checked alike (issue 12, items 5-9): integers
# that libconfig 1.5 would wrap, command-line values against the config's
# ranges, a folder given as a config, @include targets libconfig would die
# on, and exit code 2 for every config error of every command.
# Usage: test_inputs.sh PATH/TO/pomlab SOURCE_DIR
set -u
POMLAB=$1
SRC=$2
. "$(dirname "$0")/cli_lib.sh"

CFG="$SRC/configs/3pss.cfg"
# a copy of the shipped config plus one line
with_line() {
  cp "$CFG" "$TMP/m.cfg"
  printf '%s\n' "$1" >>"$TMP/m.cfg"
}

# --- item 5: integers above 2^31 without L are refused, not wrapped ------------
with_line 'montecarlo = { seed = 5000000000; };'
expect_rc 2 "$POMLAB" montecarlo "$TMP/m.cfg" --n 1 --quiet
expect_err "m.cfg:$(wc -l <"$TMP/m.cfg"): key 'montecarlo.seed' = 5000000000"
expect_err "read as 705032704; write 5000000000L"
with_line 'montecarlo = { seed = 9007199254740992; };' # 2^53 reads as 0
expect_rc 2 "$POMLAB" montecarlo "$TMP/m.cfg" --n 1 --quiet
expect_err "9007199254740992L"
with_line 'montecarlo = { seed = -2147483649; };'
expect_rc 2 "$POMLAB" montecarlo "$TMP/m.cfg" --n 1 --quiet
expect_err "key 'montecarlo.seed' = -2147483649"
with_line 'montecarlo = { seed = 99999999999999999999L; };'
expect_rc 2 "$POMLAB" montecarlo "$TMP/m.cfg" --n 1 --quiet
expect_err "does not fit a 64-bit integer"
# with L it is the value written (and strings and comments are not numbers)
with_line 'montecarlo = { seed = 5000000000L; }; # 7000000000 in a comment'
expect_rc 0 "$POMLAB" montecarlo "$TMP/m.cfg" --n 1 --quiet --json
grep -q '"seed": 5000000000,' "$TMP/out" || fail "seed 5000000000L not kept"
# in an included file: the message names that file as written
printf 'montecarlo = { seed = 3000000000; };\n' >"$TMP/mc.cfg"
with_line "@include \"$TMP/mc.cfg\""
expect_rc 2 "$POMLAB" montecarlo "$TMP/m.cfg" --n 1 --quiet
expect_err "pomlab: config: $TMP/mc.cfg:1: key 'montecarlo.seed' = 3000000000"

# --- item 6: command-line values go through the config's ranges ----------------
expect_rc 2 "$POMLAB" montecarlo "$CFG" --n 1 --quiet --seed 99999999999999999999
expect_err "command line --seed: key 'montecarlo.seed' = 99999999999999999999"
expect_rc 2 "$POMLAB" montecarlo "$CFG" --n 1 --quiet --seed 9007199254740992
expect_err "expected an integer in [0, 9007199254740991]"
expect_rc 2 "$POMLAB" montecarlo "$CFG" --n 100000001 --quiet
expect_err "command line --n: key 'montecarlo.maneuvers'"
expect_rc 2 "$POMLAB" montecarlo "$CFG" --n 1 --quiet --threads 100000
expect_err "--threads '100000': expected an integer in [1, 1024]"
expect_rc 2 "$POMLAB" study "$SRC/tests/doe_study_small.cfg" --threads 100000 --quiet
expect_err "--threads '100000': expected an integer in [1, 1024]"
expect_rc 2 "$POMLAB" sensitivity "$SRC/configs/sensitivity.cfg" --threads 100000 --quiet
expect_err "pomlab sensitivity: --threads '100000': expected an integer in [1, 1024]"
# a seed above 2^31 from the command line is the seed given
expect_rc 0 "$POMLAB" montecarlo "$CFG" --n 1 --quiet --json --seed 5000000000
grep -q '"seed": 5000000000,' "$TMP/out" || fail "--seed 5000000000 not kept"
for opt in "--kp 1e13" "--kp 1e300" "--ki 1e10" "--kd -1" "--rtol 1"; do
  set -- $opt
  expect_rc 2 "$POMLAB" simulate "$CFG" --target 1,1,1 "$1" "$2"
  expect_err "command line $1: key '"
  expect_err "out of range"
done
expect_rc 2 "$POMLAB" simulate "$CFG" --target 1,1,1 --kd abc
expect_err "command line --kd: key 'controller.kd_s' = 'abc': expected a number"

# --- item 7: a folder as config -------------------------------------------------
for cmd in model "simulate --target 1,1,1" montecarlo study tune synth; do
  expect_rc 2 "$POMLAB" $cmd "$TMP"
  expect_err "$TMP: is a directory, not a config file"
done

# --- item 8: @include targets checked before libconfig sees them ----------------
mkdir -p "$TMP/sub"
for target in "/" "" "sub" "$TMP/sub"; do
  with_line "@include \"$target\""
  expect_rc 2 "$POMLAB" model "$TMP/m.cfg"
  expect_err "pomlab: config: $TMP/m.cfg:$(wc -l <"$TMP/m.cfg"): @include \"$target\""
  checks=$((checks + 1))
  grep -q "flex scanner" "$TMP/err" && fail "libconfig's own exit for @include \"$target\""
done
with_line '@include "missing.cfg"'
expect_rc 2 "$POMLAB" model "$TMP/m.cfg"
expect_err "@include \"missing.cfg\": $TMP/missing.cfg: cannot open config file"
# a syntax error in an absolute include names the file as written
printf 'zz = ;\n' >"$TMP/bad.cfg"
with_line "@include \"$TMP/bad.cfg\""
expect_rc 2 "$POMLAB" model "$TMP/m.cfg"
expect_err "pomlab: config: $TMP/bad.cfg:1: syntax error"
# an include of itself stops at the nesting limit
printf '@include "loop.cfg"\n' >"$TMP/loop.cfg"
expect_rc 2 "$POMLAB" model "$TMP/loop.cfg"
expect_err "nested deeper than 10"

# --- item 9: every command exits 2 on a config it cannot read -------------------
printf 'a = ;\n' >"$TMP/unparsable.cfg"
printf '@include "nothere.cfg"\n' >"$TMP/misinc.cfg"
for f in "$TMP/none.cfg" "$TMP/unparsable.cfg" "$TMP/misinc.cfg"; do
  expect_rc 2 "$POMLAB" simulate "$f" --target 1,1,1
  expect_err "pomlab: "
  expect_rc 2 "$POMLAB" montecarlo "$f"
  expect_rc 2 "$POMLAB" model "$f"
done

finish test_inputs
