#!/bin/bash
# bench_ir.sh OLD_BUILD NEW_BUILD - instructions (callgrind, noise-free) of
# the bench programs and of the kinematic commands' start-up, two builds
# side by side (bench/README.md, "Old vs new, 2026-11-29"). Each build runs
# its own source tree's configs (from its CMakeCache.txt), from that tree.
# Runs two valgrinds at a time. BENCH_IR_ARCHS overrides the architectures
# ("3pss 3sps 3rrr"). Exit 2 on bad usage, 1 when a run fails.
set -euo pipefail
if [ $# -lt 2 ] || [ ! -x "$1/cli/pomlab" ] || [ ! -x "$2/cli/pomlab" ]; then
  echo "usage: $0 OLD_BUILD NEW_BUILD" >&2
  exit 2
fi
old=$(cd "$1" && pwd)
new=$(cd "$2" && pwd)
read -r -a archs <<<"${BENCH_IR_ARCHS:-3pss 3sps 3rrr}"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
src_of() { sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$1/CMakeCache.txt"; }

# the runs: LABEL<TAB>COMMAND (B = the build directory; run from its sources)
runs=()
for a in "${archs[@]}"; do
  runs+=("bench_dynamics $a parasitic (1 maneuver)	B/bench/bench_dynamics configs/$a.cfg 3,-3,3 1 klu euler parasitic")
  runs+=("bench_dynamics $a rigid (1 maneuver)	B/bench/bench_dynamics configs/$a.cfg 3,-3,3 1 klu euler rigid")
  runs+=("bench_exact_maneuver $a 40 x 1e-4 qs	B/bench/bench_exact_maneuver configs/$a.cfg 40 1 1e-4 quasi-static")
  runs+=("pomlab model $a	B/cli/pomlab model configs/$a.cfg")
  runs+=("pomlab ik $a	B/cli/pomlab ik configs/$a.cfg --euler-zyx 5,-3,2")
done
jobs=()
for i in "${!runs[@]}"; do
  cmd=${runs[$i]#*$'\t'}
  for which in old new; do
    b=$old
    [ "$which" = new ] && b=$new
    jobs+=("$(src_of "$b")	${cmd//B\//$b/}	$work/${which}_$i")
  done
done
# shellcheck disable=SC2016 # the job's script, expanded by the inner bash
printf '%s\n' "${jobs[@]}" | xargs -P 2 -d '\n' -n 1 bash -c '
  IFS=$'"'"'\t'"'"' read -r dir cmd out <<<"$0"
  cd "$dir"
  # shellcheck disable=SC2086
  valgrind --tool=callgrind --callgrind-out-file=/dev/null --trace-children=no $cmd >"$out.stdout" 2>"$out.log" ||
    { echo "failed: $cmd (see $out.log)" >&2; exit 1; }
  sed -n "s/.*Collected : //p" "$out.log" >"$out.ir"'
printf "| %-44s | %14s | %14s | %7s |\n" run old new new/old
printf "|%s|\n" "----------------------------------------------|----------------|----------------|---------"
for i in "${!runs[@]}"; do
  o=$(cat "$work/old_$i.ir") w=$(cat "$work/new_$i.ir")
  awk -v l="${runs[$i]%%$'\t'*}" -v o="$o" -v w="$w" \
    'BEGIN{printf "| %-44s | %12.2f M | %12.2f M | %7.4f |\n", l, o / 1e6, w / 1e6, w / o}'
done
