#!/bin/bash
# instructions.sh OLD_BUILD NEW_BUILD [N] - instructions per maneuver
# (callgrind, noise-free) of two builds for each architecture x setting of
# bench/settings.sh: (Ir of `pomlab montecarlo CFG --n N --threads 1` - Ir of
# --n 1) / (N - 1), so start-up cancels; N defaults to 6 on the parasitic
# settings and 10 N on the exact-path ones. Runs two valgrinds at a time.
# THROUGHPUT_ARCHS overrides the architectures. Exit 2 on bad usage.
set -euo pipefail
if [ $# -lt 2 ] || [ ! -x "$1/cli/pomlab" ] || [ ! -x "$2/cli/pomlab" ]; then
  echo "usage: $0 OLD_BUILD NEW_BUILD [N, default 6]" >&2
  exit 2
fi
N=${3:-6}
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=bench/settings.sh
. "$here/settings.sh"
read -r -a archs <<<"${THROUGHPUT_ARCHS:-3pss 3sps 3rrr}"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
src_of() { sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$1/CMakeCache.txt"; }
jobs=()
for arch in "${archs[@]}"; do
  for s in "${settings[@]}"; do
    for which in old new; do
      b=$1
      [ "$which" = new ] && b=$2
      exe=$b/cli/pomlab-full # the launcher pomlab execs it (callgrind would follow the launcher only)
      [ -x "$exe" ] || exe=$b/cli/pomlab
      setting_config "$(src_of "$b")" "$arch" "$s" >"$work/${which}_${arch}_$s.cfg"
      for n in 1 "$(n_of "$s")"; do
        jobs+=("$exe $work/${which}_${arch}_$s.cfg $n $work/${which}_${arch}_${s}_$n")
      done
    done
  done
done
printf '%s\n' "${jobs[@]}" | xargs -P 2 -L 1 bash -c \
  'valgrind --tool=callgrind --callgrind-out-file=/dev/null "$0" montecarlo "$1" --n "$2" --threads 1 --quiet >/dev/null 2>"$3.log"; sed -n "s/.*Collected : //p" "$3.log" >"$3.ir"'
echo "instructions per maneuver (callgrind; (Ir(N) - Ir(1)) / (N - 1); N = $N parasitic, $((10 * N)) exact)"
printf "| %-6s | %-22s | %12s | %12s | %7s |\n" arch setting old new new/old
printf "|%s|\n" "--------|------------------------|--------------|--------------|---------"
for arch in "${archs[@]}"; do
  for s in "${settings[@]}"; do
    k=$(n_of "$s")
    o=$(awk -v a="$(cat "$work/old_${arch}_${s}_$k.ir")" -v b="$(cat "$work/old_${arch}_${s}_1.ir")" -v k="$k" 'BEGIN{print (a - b) / (k - 1)}')
    w=$(awk -v a="$(cat "$work/new_${arch}_${s}_$k.ir")" -v b="$(cat "$work/new_${arch}_${s}_1.ir")" -v k="$k" 'BEGIN{print (a - b) / (k - 1)}')
    awk -v a="$arch" -v s="$s" -v o="$o" -v w="$w" \
      'BEGIN{printf "| %-6s | %-22s | %10.2f M | %10.2f M | %7.3f |\n", a, s, o / 1e6, w / 1e6, w / o}'
  done
done
