#!/bin/bash
# grad_cost.sh BUILD [CFG] - instructions (callgrind) of one maneuver with
# forward sensitivities for p design keys against a plain maneuver on the
# exact path (issue 29 item 5: at most (1 + p) x). Per maneuver = (Ir of 3
# maneuvers - Ir of 1) / 2, so that loading, model building and start-up
# cancel; the same montecarlo targets in both commands. CFG defaults to the
# shipped 3P-S-S/S with joints.model = "rigid".
# Environment: PS="1 3" the parameter counts (default "1 3 6 9"); RTOL=1e-10
# replaces the config's solver.rtol and lifts its wall-clock budget (the
# sensitivities' noise margin only
# acts below rtol = margin x 7.4e-11, docs/optimize.md 12.4); MARGIN=100
# passes --sens-margin to `pomlab gradient`; ERRTEST=off passes
# --sens-error-test off (docs/optimize.md 12.5, "The error test").
set -eu
build=${1:?usage: grad_cost.sh BUILD [CFG]}
src=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cfg=${2:-}
if [ -z "$cfg" ]; then
  cfg=$tmp/rigid.cfg
  sed 's/^\(  angular_damping_Nms_per_rad = .*\)$/\1\n  model = "rigid";/' "$src/configs/3pss.cfg" > "$cfg"
fi
if [ -n "${RTOL:-}" ]; then
  # no wall-clock budget: under callgrind a maneuver at a tight rtol takes
  # over the 60 s default and would stop short, cutting its instructions
  sed "s/^\( *\)rtol = [^;]*;/\1rtol = $RTOL;\n\1max_wall_s = 0.0;/" "$cfg" > "$tmp/rtol.cfg"
  cfg=$tmp/rtol.cfg
fi
margin=()
[ -n "${MARGIN:-}" ] && margin=(--sens-margin "$MARGIN")
[ -n "${ERRTEST:-}" ] && margin+=(--sens-error-test "$ERRTEST")
ir() { # instructions of a command
  valgrind --tool=callgrind --callgrind-out-file="$tmp/cg.out" "$@" > /dev/null 2> "$tmp/err" ||
    { cat "$tmp/err" >&2; exit 1; }
  callgrind_annotate "$tmp/cg.out" 2> /dev/null | awk '/PROGRAM TOTALS/ {gsub(",", "", $1); print $1; exit}'
}
per() { # per-maneuver instructions of a command taking --maneuvers/--n N
  local flag=$1; shift
  local a b
  a=$(ir "$@" "$flag" 1)
  b=$(ir "$@" "$flag" 3)
  [ -n "$a" ] && [ -n "$b" ] || { echo "grad_cost.sh: a run failed" >&2; exit 1; }
  echo $(( (b - a) / 2 ))
}
plain=$(per --n "$build/cli/pomlab-full" montecarlo "$cfg" --threads 1 --quiet)
echo "plain maneuver: $plain instructions"
keys=(actuator.resistance_ohm controller.kd_s actuator.force_constant_N_per_A controller.kp
      inertia.link.mass_kg geometry.limb_length actuator.inductance_H inertia.platform.mass_kg
      geometry.limb_lean_deg)
for p in ${PS:-1 3 6 9}; do
  list=$(IFS=,; echo "${keys[*]:0:$p}")
  g=$(per --maneuvers "$build/cli/pomlab-full" gradient "$cfg" --params "$list" ${margin[@]+"${margin[@]}"})
  awk -v g="$g" -v pl="$plain" -v p="$p" 'BEGIN {
    printf "p = %d: %.0f instructions per maneuver = %.2f x plain (bound 1 + p = %d)\n", p, g, g / pl, 1 + p }'
done
