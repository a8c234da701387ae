#!/usr/bin/env bash
# rtol_convergence.sh - does an asked-for --rtol deliver its accuracy?
# (issue 30 item 2; docs/dynamics.md section 7, "Tolerances").
# For each shipped architecture (configs/3pss.cfg, 3sps.cfg, 3rrr.cfg as
# shipped: rtol 1e-6, atol_scale 1e-3) one maneuver to TARGET is run with
# `pomlab-full simulate --rtol R` for R = 1e-3 ... 1e-10, and once as a
# reference with the config edited to rtol 1e-12, atol_scale 1e-9. Printed:
# steps, |E - E_ref| / E_ref of energy_total_J and |t - t_ref| of the
# pointing settling time (s).
# Usage: bench/rtol_convergence.sh BUILD_DIR [SRC_DIR] [TARGET] [--joints rigid]
set -eu
B=$(realpath "$1"); SRC=$(realpath "${2:-$(dirname "$0")/..}"); TARGET=${3:-3,-3,3}
shift $(( $# < 3 ? $# : 3 ))
EXTRA=("$@")
W=$(mktemp -d); trap 'rm -rf "$W"' EXIT
run() { "$B/cli/pomlab-full" simulate "$1" --target "$TARGET" --json "${EXTRA[@]}" "${@:2}" 2>/dev/null || true; }
field() { jq -r "$1"; }
printf '| arch | rtol | steps | energy rel. error | pointing time error (s) | status |\n|---|---|---|---|---|---|\n'
for arch in 3pss 3sps 3rrr; do
  sed -e 's/^  rtol = .*/  rtol = 1.0e-12;/' -e 's/^  atol_scale = .*/  atol_scale = 1.0e-9;/' \
    "$SRC/configs/$arch.cfg" > "$W/ref.cfg"
  ref=$(run "$W/ref.cfg")
  e_ref=$(echo "$ref" | field .energy_total_J); t_ref=$(echo "$ref" | field .pointing_settling_time_s)
  printf '| %s | ref 1e-12 | %s | %s J | %s s | %s |\n' "$arch" "$(echo "$ref" | field .steps)" \
    "$e_ref" "$t_ref" "$(echo "$ref" | field .status)"
  for r in 1e-3 1e-4 1e-5 1e-6 1e-7 1e-8 1e-9 1e-10; do
    out=$(run "$SRC/configs/$arch.cfg" --rtol "$r")
    read -r st e t status < <(echo "$out" | jq -r '"\(.steps) \(.energy_total_J) \(.pointing_settling_time_s) \(.status)"')
    awk -v a="$arch" -v r="$r" -v st="$st" -v e="$e" -v t="$t" -v s="$status" -v er="$e_ref" \
      -v tr="$t_ref" 'function abs(x) { return x < 0 ? -x : x }
      BEGIN { printf "| %s | %s | %s | %.1e | %.1e | %s |\n", a, r, st, abs((e - er) / er), abs(t - tr), s }'
  done
done
