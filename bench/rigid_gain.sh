#!/bin/bash
# rigid_gain.sh BUILD [REPS] - the rigid path against the parasitic path at
# high loop gain (issue 30 item 3, docs/dynamics.md section 7, "Order and
# stability"): the maneuver (3, -3, 3) mm or deg of each shipped config at
# K_P x 1, 10, 1e2, 1e3, 1e4 (`--kp`), both joint models; steps, status and
# user CPU per maneuver (REPS runs, default 3, minus the start-up: the same
# command with a target outside the stroke, refused after the model is
# built). MAX_STEPS overrides solver.max_steps (the shipped 200000 stops
# main's rigid path at 1e3 x K_P); RIGID_GAIN_ARCHS the architectures.
# Exit 2 on bad usage.
set -euo pipefail
if [ $# -lt 1 ] || [ ! -x "$1/cli/pomlab" ]; then
  echo "usage: $0 BUILD [REPS, default 3]" >&2
  exit 2
fi
B=$1
REPS=${2:-3}
src=$(sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$B/CMakeCache.txt")
read -r -a archs <<<"${RIGID_GAIN_ARCHS:-3pss 3sps 3rrr}"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
exe=$B/cli/pomlab
# user CPU (s) of REPS runs of the command
cpu_of() {
  /usr/bin/time -f %U -o "$work/t" bash -c \
    'for ((i = 0; i < $0; ++i)); do "$@" >/dev/null 2>&1 || true; done' "$REPS" "$@"
  cat "$work/t"
}
echo "build $B ($(git -C "$src" rev-parse --short HEAD 2>/dev/null || echo '?')), $REPS runs per figure, $(uptime | sed 's/.*load/load/')"
printf "| %-4s | %-6s | %-18s | %-26s | %10s | %9s |\n" arch "K_P x" "parasitic steps, ms" "rigid steps, ms (status)" "steps r/p" "CPU r/p"
printf "|%s|\n" "------|--------|--------------------|----------------------------|------------|-----------"
for arch in "${archs[@]}"; do
  cfg=$work/$arch.cfg
  sed "s/^  max_steps = 200000;/  max_steps = ${MAX_STEPS:-200000};/" "$src/configs/$arch.cfg" >"$cfg"
  kp0=$(sed -n 's/^  kp = \([0-9.eE+-]*\);.*/\1/p' "$cfg")
  base=$(cpu_of "$exe" simulate "$cfg" --target 99,99,99 --json)
  for f in 1 10 100 1000 10000; do
    kp=$(awk -v a="$kp0" -v f="$f" 'BEGIN{printf "%g", a * f}')
    declare -A steps=() ms=() status=()
    for j in parasitic rigid; do
      out=$("$exe" simulate "$cfg" --target 3,-3,3 --joints "$j" --kp "$kp" --json 2>/dev/null || true)
      steps[$j]=$(echo "$out" | sed -n 's/.*"steps": \([0-9]*\).*/\1/p')
      status[$j]=$(echo "$out" | sed -n 's/.*"status": "\([A-Z_]*\)".*/\1/p')
      t=$(cpu_of "$exe" simulate "$cfg" --target 3,-3,3 --joints "$j" --kp "$kp" --json)
      ms[$j]=$(awk -v t="$t" -v b="$base" -v r="$REPS" 'BEGIN{printf "%.1f", 1e3 * (t - b) / r}')
    done
    awk -v a="$arch" -v f="$f" -v ps="${steps[parasitic]}" -v pm="${ms[parasitic]}" \
      -v rs="${steps[rigid]}" -v rm="${ms[rigid]}" -v st="${status[rigid]}" -v pst="${status[parasitic]}" \
      'BEGIN{printf "| %-4s | %-6s | %8d, %7.1f%s | %8d, %7.1f (%s) | %10.2f | %9.2f |\n",
             a, f, ps, pm, (pst == "POM_OK" ? "" : " !"), rs, rm, (st == "POM_OK" ? "ok" : st),
             rs / ps, (pm > 0 ? rm / pm : 0)}'
    unset steps ms status
  done
done
