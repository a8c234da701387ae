#!/bin/bash
# table_cost.sh BUILD [N] [BUILD2 ...] - instructions per maneuver (callgrind,
# noise-free) of each shipped architecture run hand-coded ("3PSS") and from
# its table (catalog/3pss.arch, "3PSS-table") on the exact (rigid) path:
# the configs differ in the `architecture` line only. Settings: the rigid
# ones of bench/settings.sh (rigid-1e-6, exact-qs-1e-3, exact-recommended).
# Per maneuver = (Ir of `pomlab montecarlo CFG --n K --threads 1` - Ir of
# --n 1) / (K - 1), K = N (rigid-1e-6) or 10 N (exact-*), N defaults to 2, so
# start-up cancels. Several builds: one column pair each (old and new in one
# session, the jobs interleaved). TABLE_COST_ARCHS overrides the
# architectures, TABLE_COST_SETTINGS the settings. Runs two valgrinds at a
# time. Exit 2 on bad usage (docs/kinematics-tables.md section 8).
set -euo pipefail
if [ $# -lt 1 ] || [ ! -x "$1/cli/pomlab" ]; then
  echo "usage: $0 BUILD [N, default 2] [BUILD2 ...]" >&2
  exit 2
fi
builds=("$1")
N=${2:-2}
shift $(($# < 2 ? $# : 2))
for b in "$@"; do
  [ -x "$b/cli/pomlab" ] || {
    echo "table_cost.sh: $b/cli/pomlab is not a build" >&2
    exit 2
  }
  builds+=("$b")
done
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=bench/settings.sh
. "$here/settings.sh"
read -r -a archs <<<"${TABLE_COST_ARCHS:-3pss 3sps 3rrr}"
read -r -a sets <<<"${TABLE_COST_SETTINGS:-rigid-1e-6 exact-qs-1e-3 exact-recommended}"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
src_of() { sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$1/CMakeCache.txt"; }
jobs=()
for arch in "${archs[@]}"; do
  A=$(echo "$arch" | tr '[:lower:]' '[:upper:]')
  for s in "${sets[@]}"; do
    for bi in "${!builds[@]}"; do
      b=${builds[$bi]}
      exe=$b/cli/pomlab-full # the launcher pomlab execs it (callgrind would follow the launcher only)
      [ -x "$exe" ] || exe=$b/cli/pomlab
      setting_config "$(src_of "$b")" "$arch" "$s" >"$work/hand_${bi}_${arch}_$s.cfg"
      sed "s/^architecture = \"$A\";/architecture = \"$A-table\";/" \
        "$work/hand_${bi}_${arch}_$s.cfg" >"$work/table_${bi}_${arch}_$s.cfg"
      grep -q "^architecture = \"$A-table\";" "$work/table_${bi}_${arch}_$s.cfg" || {
        echo "table_cost.sh: configs/$arch.cfg has no line architecture = \"$A\";" >&2
        exit 2
      }
      for which in hand table; do
        for n in 1 "$(n_of "$s")"; do
          jobs+=("$exe $work/${which}_${bi}_${arch}_$s.cfg $n $work/${which}_${bi}_${arch}_${s}_$n")
        done
      done
    done
  done
done
printf '%s\n' "${jobs[@]}" | xargs -P 2 -L 1 bash -c \
  'valgrind --tool=callgrind --callgrind-out-file=/dev/null "$0" montecarlo "$1" --n "$2" --threads 1 --quiet >/dev/null 2>"$3.log"; sed -n "s/.*Collected : //p" "$3.log" >"$3.ir"; [ -s "$3.ir" ] || { echo "table_cost.sh: no count in $3.log" >&2; cat "$3.log" >&2; }'
per() { # which build arch setting -> Ir per maneuver
  local k
  k=$(n_of "$4")
  awk -v a="$(cat "$work/$1_$2_$3_$4_$k.ir")" -v b="$(cat "$work/$1_$2_$3_$4_1.ir")" -v k="$k" \
    'BEGIN{printf "%.0f", (a - b) / (k - 1)}'
}
echo "instructions per maneuver (callgrind; (Ir(K) - Ir(1)) / (K - 1); K = $N rigid-1e-6, $((10 * N)) exact-*)"
for bi in "${!builds[@]}"; do echo "build $bi: ${builds[$bi]} ($(git -C "$(src_of "${builds[$bi]}")" rev-parse --short HEAD 2>/dev/null || echo '?'))"; done
printf "| arch | setting |"
for bi in "${!builds[@]}"; do printf " hand %d | table %d | table/hand %d |" "$bi" "$bi" "$bi"; done
printf "\n|---|---|"
for _ in "${builds[@]}"; do printf -- "---:|---:|---:|"; done
printf "\n"
for arch in "${archs[@]}"; do
  for s in "${sets[@]}"; do
    printf "| %s | %s |" "$arch" "$s"
    for bi in "${!builds[@]}"; do
      h=$(per hand "$bi" "$arch" "$s")
      t=$(per table "$bi" "$arch" "$s")
      awk -v h="$h" -v t="$t" 'BEGIN{printf " %.2f M | %.2f M | %.3f |", h / 1e6, t / 1e6, t / h}'
    done
    printf "\n"
  done
done
