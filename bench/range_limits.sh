#!/usr/bin/env bash
# range_limits.sh - what integrates with the shipped defaults at the ends of
# the ranges of solver.rtol and the joint stiffnesses (issue 30 item 5;
# docs/dynamics.md section 14, "Ranges"). One maneuver to TARGET per
# architecture (configs/3pss.cfg, 3sps.cfg, 3rrr.cfg, max_steps 200000) and
# setting; each setting edits one key of the shipped file.
# Usage: bench/range_limits.sh BUILD_DIR [SRC_DIR] [TARGET] [SETTING...]
#   SETTING: rtol=X (parasitic), rigid-rtol=X, nat-rtol=X and rigid-nat-rtol=X
#            (atol_scale 0: natural sizes), k=X (joints.stiffness_N_per_m),
#            ka=X (joints.angular_stiffness_Nm_per_rad)
set -eu
B=$(realpath "$1"); SRC=$(realpath "${2:-$(dirname "$0")/..}"); TARGET=${3:-3,-3,3}
shift $(( $# < 3 ? $# : 3 ))
SETTINGS=("$@")
[ ${#SETTINGS[@]} -gt 0 ] || SETTINGS=(rtol=1e-12 rtol=1e-13 rigid-rtol=1e-12 rigid-rtol=1e-13
  nat-rtol=1e-12 nat-rtol=1e-13 rigid-nat-rtol=1e-12 rigid-nat-rtol=1e-13 k=1e10 k=3e10 k=1e11 k=1e12 ka=1e10 ka=1e11 ka=1e12)
W=$(mktemp -d); trap 'rm -rf "$W"' EXIT
printf '| arch | setting | status | steps | wall (s) | energy (J) | reason |\n|---|---|---|---|---|---|---|\n'
for arch in 3pss 3sps 3rrr; do
  for s in "${SETTINGS[@]}"; do
    v=${s#*=}; extra=()
    case "$s" in
    rtol=*) sed "s/^  rtol = .*/  rtol = $v;/" "$SRC/configs/$arch.cfg" > "$W/c.cfg" ;;
    rigid-rtol=*) sed "s/^  rtol = .*/  rtol = $v;/" "$SRC/configs/$arch.cfg" > "$W/c.cfg"
      extra=(--joints rigid) ;;
    nat-rtol=*) sed -e "s/^  rtol = .*/  rtol = $v;/" -e "s/^  atol_scale = .*/  atol_scale = 0;/" \
      "$SRC/configs/$arch.cfg" > "$W/c.cfg" ;;
    rigid-nat-rtol=*) sed -e "s/^  rtol = .*/  rtol = $v;/" -e "s/^  atol_scale = .*/  atol_scale = 0;/" \
      "$SRC/configs/$arch.cfg" > "$W/c.cfg"
      extra=(--joints rigid) ;;
    k=*) sed "s/^  stiffness_N_per_m = [^;]*;/  stiffness_N_per_m = $v;/" "$SRC/configs/$arch.cfg" > "$W/c.cfg" ;;
    ka=*) sed "s/^  angular_stiffness_Nm_per_rad = [^;]*;/  angular_stiffness_Nm_per_rad = $v;/" \
      "$SRC/configs/$arch.cfg" > "$W/c.cfg" ;;
    esac
    out=$("$B/cli/pomlab-full" simulate "$W/c.cfg" --target "$TARGET" --json "${extra[@]}" 2>&1 || true)
    if echo "$out" | jq -e . >/dev/null 2>&1; then
      echo "$out" | jq -r --arg a "$arch" --arg s "$s" \
        '"| \($a) | \($s) | \(.status) | \(.steps) | \(.wall_time_s * 100 | round / 100) | \(.energy_total_J) | \(.reason) |"'
    else
      printf '| %s | %s | refused | - | - | - | %s |\n' "$arch" "$s" "$(echo "$out" | head -1)"
    fi
  done
done
