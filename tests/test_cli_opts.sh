#!/usr/bin/env bash
# test_cli_opts.sh - every command's options come from one table
# (cli/cli_opts.h, docs/extending.md section 11): --help is generated from it
# and lists every option, a value that is also a config key is refused by the
# key's own check (the error names the option and the key), --name=value
# works for every option with a value, and an unknown option is a usage
# error (exit 2, the usage on stderr) for every command.
# Usage: test_cli_opts.sh PATH/TO/pomlab SOURCE_DIR
set -u
POMLAB=$1
SRC=$2
. "$(dirname "$0")/cli_lib.sh"
C="$SRC/configs"

# --- generated --help: every documented option of every command ---------------------------
declare -A options=(
  [model]="--json --list-architectures --list-controllers"
  [ik]="--euler-zyx --json"
  [fk]="--q --json"
  [workspace]="--map --json --quiet"
  [simulate]="--target --json --out --bode --controller --form --joints --orientation --linsol --kp --ki --kd --rtol"
  [tune]="--out --json --quiet"
  [synth]="--out --no-direct --json --quiet"
  [montecarlo]="--n --seed --threads --out --tabular --json --quiet"
  [study]="--threads --resume --out --stop-after --tabular --json --no-plots --no-summary --quiet"
  [sensitivity]="--candidate --threads --out --resume --stop-after --json --no-plots --quiet"
  [tradeoff]="--accuracy --maneuvers --repeats --csv --quiet"
  [view]="-o --pose --trace --frame --frames --workspace --compare --png --mp4 --size --fps"
  [export]="--mjcf"
  [gradient]="--params --maneuvers --seed --sens-margin --sens-error-test --quantile --bandwidth-ms --check --check-rtol --json"
)
for cmd in "${!options[@]}"; do
  expect_rc 0 "$POMLAB" "$cmd" --help
  expect_in "$TMP/out" "usage: pomlab $cmd"
  expect_in "$TMP/out" "  --help"
  for o in ${options[$cmd]}; do
    check "$cmd --help lists $o" grep -qE -- "^  $o( |\$)" "$TMP/out"
  done
  # an unknown option: exit 2, named, the usage on stderr
  expect_rc 2 "$POMLAB" "$cmd" "$C/3pss.cfg" --no-such-option
  expect_err "pomlab $cmd: unknown option '--no-such-option'"
  expect_err "usage: pomlab $cmd"
done
# an option that sets a config key says so in --help
"$POMLAB" simulate --help >"$TMP/help"
expect_in "$TMP/help" "sets controller.kp"
expect_in "$TMP/help" "sets solver.linear_solver"

# --- values that are config keys: the key's own check --------------------------------------
expect_rc 2 "$POMLAB" simulate "$C/3pss.cfg" --target 1,1,1 --kp -5
expect_err "--kp"
expect_err "controller.kp"
expect_rc 2 "$POMLAB" simulate "$C/3pss.cfg" --target 1,1,1 --linsol lu
expect_err "solver.linear_solver"
expect_rc 2 "$POMLAB" montecarlo "$C/3pss.cfg" --n 1.5 --quiet
expect_err "montecarlo.maneuvers"
# tradeoff's counts: the range of tradeoff.maneuvers (1..16) and tradeoff.repeats
expect_rc 2 "$POMLAB" tradeoff "$C/3pss.cfg" --maneuvers 17 --quiet
expect_err "--maneuvers"
expect_err "tradeoff.maneuvers"
expect_rc 2 "$POMLAB" tradeoff "$C/3pss.cfg" --repeats 0 --quiet
expect_err "tradeoff.repeats"
# whole numbers of a command's own range name the option and the range
expect_rc 2 "$POMLAB" view "$C/3pss.cfg" --frames 1 -o "$TMP/x.html"
expect_err "--frames expects a whole number in [2, 400], got '1'"
expect_rc 2 "$POMLAB" study "$SRC/tests/doe_study_small.cfg" --stop-after 0
expect_err "--stop-after expects a whole number >= 1"
expect_rc 2 "$POMLAB" study "$SRC/tests/doe_study_small.cfg" --threads 0
expect_err "--threads '0': expected an integer in [1, 1024]"
# a value missing at the end
expect_rc 2 "$POMLAB" simulate "$C/3pss.cfg" --target
expect_err "incomplete option '--target'"

# --- --name=value, and the same output as --name value -------------------------------------
expect_rc 0 "$POMLAB" simulate "$C/3pss.cfg" --target=1,2,3 --kp=120 --json
grep -v wall_time "$TMP/out" >"$TMP/eq.json"
expect_rc 0 "$POMLAB" simulate "$C/3pss.cfg" --target 1,2,3 --kp 120 --json
check "--name=value reads as --name value" cmp -s "$TMP/eq.json" <(grep -v wall_time "$TMP/out")
expect_rc 0 "$POMLAB" ik "$C/3pss.cfg" --euler-zyx=5,-3,2

# --- the multi-config commands: at most 4 configs ------------------------------------------
expect_rc 2 "$POMLAB" tune "$C/3pss.cfg" "$C/3pss.cfg" "$C/3pss.cfg" "$C/3pss.cfg" "$C/3pss.cfg"
expect_err "at most 4 configs"
# --- gradient (issue 29): rigid joints only, keys present and numeric ------------------------
expect_rc 2 "$POMLAB" gradient "$C/3pss.cfg" --params actuator.resistance_ohm --maneuvers 1
expect_err 'joints.model = "rigid"'
sed 's/^\(  angular_damping_Nms_per_rad = .*\)$/\1\n  model = "rigid";/' "$C/3pss.cfg" >"$TMP/rigid.cfg"
expect_rc 2 "$POMLAB" gradient "$TMP/rigid.cfg" --params actuator.no_such_key --maneuvers 1
expect_err "design key 'actuator.no_such_key' is not a number in the config"
expect_rc 0 "$POMLAB" gradient "$TMP/rigid.cfg" --params actuator.resistance_ohm --maneuvers 1 --json
check "gradient --json is JSON with a defined energy gradient" python3 -c "
import json, sys, math
d = json.load(open('$TMP/out'))
g = d['maneuvers'][0]['gradient']['energy_total']
sys.exit(0 if len(g) == 1 and math.isfinite(g[0]) and d['keys'] == ['actuator.resistance_ohm'] else 1)"
# the sensitivities' accuracy (docs/optimize.md 12.4): the key's own check from the flag and the
# file alike, and a misspelt key of the gradient group refused
expect_rc 2 "$POMLAB" gradient "$TMP/rigid.cfg" --params actuator.resistance_ohm --maneuvers 1 \
  --sens-margin 0.5
expect_err "--sens-margin"
expect_err "gradient.sens_noise_margin"
printf 'gradient = { sens_noise_margin = 2e6; };\n' | cat "$TMP/rigid.cfg" - >"$TMP/margin.cfg"
expect_rc 2 "$POMLAB" gradient "$TMP/margin.cfg" --params actuator.resistance_ohm --maneuvers 1
expect_err "gradient.sens_noise_margin"
# the sensitivities' error test (docs/optimize.md 12.5): on or off, the same check from the flag
# and the file
expect_rc 2 "$POMLAB" gradient "$TMP/rigid.cfg" --params actuator.resistance_ohm --maneuvers 1 \
  --sens-error-test maybe
expect_err "--sens-error-test"
expect_err "gradient.sens_error_test"
printf 'gradient = { sens_error_test = "no"; };\n' | cat "$TMP/rigid.cfg" - >"$TMP/errtest.cfg"
expect_rc 2 "$POMLAB" gradient "$TMP/errtest.cfg" --params actuator.resistance_ohm --maneuvers 1
expect_err "gradient.sens_error_test"
# the smooth quantile's probability and bandwidth (docs/optimize.md 12.3): the same check from
# the flag and the file
expect_rc 2 "$POMLAB" gradient "$TMP/rigid.cfg" --params actuator.resistance_ohm --maneuvers 1 \
  --quantile 1.5
expect_err "--quantile"
expect_err "gradient.quantile"
printf 'gradient = { quantile_bandwidth_ms = 0.0; };\n' | cat "$TMP/rigid.cfg" - >"$TMP/bw.cfg"
expect_rc 2 "$POMLAB" gradient "$TMP/bw.cfg" --params actuator.resistance_ohm --maneuvers 1
expect_err "gradient.quantile_bandwidth_ms"
printf 'gradient = { sens_noise_margn = 300.0; };\n' | cat "$TMP/rigid.cfg" - >"$TMP/typo.cfg"
expect_rc 2 "$POMLAB" gradient "$TMP/typo.cfg" --params actuator.resistance_ohm --maneuvers 1
expect_err "gradient.sens_noise_margn"
finish test_cli_opts
