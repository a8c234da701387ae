#!/bin/bash
# throughput.sh OLD_BUILD NEW_BUILD [N] - maneuvers per CPU-second of two
# builds in one session (bench/README.md, "Throughput"): each architecture x
# path x setting as `pomlab montecarlo CFG --n N --threads 1` (user + system
# CPU of the whole process, start-up included; the exact-path settings run
# 10 N maneuvers, they are ~10x cheaper), then the wall time of the paper
# studies on 2 threads (skipped when THROUGHPUT_NO_STUDY is set). Each build
# runs its own source tree's configs (from its CMakeCache.txt); the two builds
# alternate, THROUGHPUT_ROUNDS times (default 2), and the table keeps the best
# round of each (the machine may be shared). THROUGHPUT_ARCHS overrides the
# architectures ("3pss 3sps 3rrr"). Exit 2 on bad usage.
set -euo pipefail
if [ $# -lt 2 ] || [ ! -x "$1/cli/pomlab" ] || [ ! -x "$2/cli/pomlab" ]; then
  echo "usage: $0 OLD_BUILD NEW_BUILD [N maneuvers, default 100]" >&2
  echo "  (each BUILD a CMake build directory holding cli/pomlab)" >&2
  exit 2
fi
N=${3:-100}
ROUNDS=${THROUGHPUT_ROUNDS:-2}
read -r -a archs <<<"${THROUGHPUT_ARCHS:-3pss 3sps 3rrr}"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
src_of() { sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$1/CMakeCache.txt"; }

# the settings and their config edits (shared with bench/accuracy.sh)
# shellcheck source=bench/settings.sh
. "$(dirname "$0")/settings.sh"

# cpu_of BUILD ARCH SETTING -> user+system CPU seconds of n_of(SETTING) maneuvers
cpu_of() {
  local build=$1 arch=$2 setting=$3 src cfg
  src=$(src_of "$build")
  cfg="$work/${arch}_${setting}.cfg"
  setting_config "$src" "$arch" "$setting" >"$cfg"
  /usr/bin/time -f "%U %S" -o "$work/t" "$build/cli/pomlab" montecarlo "$cfg" \
    --n "$(n_of "$setting")" --threads 1 --quiet >/dev/null
  awk '{print $1 + $2}' "$work/t"
}

# wall_of BUILD CONFIG THREADS -> wall seconds of a study
wall_of() {
  local build=$1 cfg=$2 threads=$3 src
  src=$(src_of "$build")
  (cd "$src" && /usr/bin/time -f "%e %U" -o "$work/t" "$build/cli/pomlab" study "$cfg" \
    --threads "$threads" --quiet --no-plots --no-summary --out "$work/study.h5" >/dev/null)
  rm -f "$work/study.h5"
  awk '{print $1, $2}' "$work/t"
}

declare -A best
better() { # keeps the smaller of two figures (the first field)
  local k=$1 v=$2
  if [ -z "${best[$k]:-}" ] || awk -v a="${v%% *}" -v b="${best[$k]%% *}" 'BEGIN{exit !(a < b)}'; then
    best[$k]=$v
  fi
}
echo "machine: $(nproc) cores, $(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -1); load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "old: $1 ($(git -C "$(src_of "$1")" rev-parse --short HEAD 2>/dev/null || echo '?'))"
echo "new: $2 ($(git -C "$(src_of "$2")" rev-parse --short HEAD 2>/dev/null || echo '?'))"
studies=("configs/paper.cfg" "configs/paper-exact.cfg")
for round in $(seq "$ROUNDS"); do
  for arch in "${archs[@]}"; do
    for s in "${settings[@]}"; do
      for which in old new; do
        b=$1
        [ "$which" = new ] && b=$2
        better "$which/$arch/$s" "$(cpu_of "$b" "$arch" "$s")"
      done
    done
  done
  if [ -z "${THROUGHPUT_NO_STUDY:-}" ]; then
    for cfg in "${studies[@]}"; do
      for which in old new; do
        b=$1
        [ "$which" = new ] && b=$2
        better "$which/$cfg" "$(wall_of "$b" "$cfg" 2)"
      done
    done
  fi
  echo "round $round done: load $(cut -d' ' -f1-3 /proc/loadavg)" >&2
done
echo "load at the end: $(cut -d' ' -f1-3 /proc/loadavg)"
echo
echo "CPU per maneuver (ms) and maneuvers per CPU-second (montecarlo seed, 1 thread, best of $ROUNDS rounds;"
echo "$N maneuvers per parasitic setting, $((10 * N)) per exact-path setting)"
printf "| %-6s | %-22s | %9s | %9s | %8s | %8s | %7s |\n" arch setting "old ms" "new ms" "old /s" "new /s" new/old
printf "|%s|\n" "--------|------------------------|-----------|-----------|----------|----------|---------"
for arch in "${archs[@]}"; do
  for s in "${settings[@]}"; do
    o=${best[old/$arch/$s]} n=${best[new/$arch/$s]} k=$(n_of "$s")
    awk -v a="$arch" -v s="$s" -v o="$o" -v n="$n" -v N="$k" \
      'BEGIN{printf "| %-6s | %-22s | %9.3f | %9.3f | %8.1f | %8.1f | %7.2f |\n", a, s, 1e3*o/N, 1e3*n/N, N/o, N/n, o/n}'
  done
done
echo
[ -n "${THROUGHPUT_NO_STUDY:-}" ] && exit 0
echo "studies on 2 threads, wall seconds (user CPU), best of $ROUNDS rounds"
for cfg in "${studies[@]}"; do
  echo "$cfg: old ${best[old/$cfg]% *} s (${best[old/$cfg]#* } s), new ${best[new/$cfg]% *} s (${best[new/$cfg]#* } s)"
done
