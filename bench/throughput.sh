#!/bin/bash
# throughput.sh OLD_BUILD NEW_BUILD [N] - maneuvers per CPU-second of two
# builds in one session (bench/README.md, "Throughput"): each architecture x
# path x setting as `pomlab montecarlo CFG --n N --threads 1` (user CPU of the
# whole process, start-up included), then the paper study's wall time at 1 and
# 2 threads (skipped when THROUGHPUT_NO_STUDY is set). Each build runs its own source tree's configs (from its
# CMakeCache.txt); the two builds alternate, twice, and the table keeps the
# best of the two rounds (the machine may be shared). Exit 2 on bad usage.
set -euo pipefail
if [ $# -lt 2 ] || [ ! -x "$1/cli/pomlab" ] || [ ! -x "$2/cli/pomlab" ]; then
  echo "usage: $0 OLD_BUILD NEW_BUILD [N maneuvers, default 100]" >&2
  echo "  (each BUILD a CMake build directory holding cli/pomlab)" >&2
  exit 2
fi
N=${3:-100}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
src_of() { sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$1/CMakeCache.txt"; }

# setting name -> sed expression applied to the architecture's config
settings=("parasitic" "rigid" "parasitic-quasi-static")
edit_of() {
  case "$1" in
  parasitic) echo 's/^joints = {/joints = {\n  model = "parasitic";/' ;;
  rigid) echo 's/^joints = {/joints = {\n  model = "rigid";/' ;;
  parasitic-quasi-static) echo 's/^  coil_inductance = true;/  coil_inductance = false;/' ;;
  esac
}

# cpu_of BUILD ARCH SETTING -> user+system CPU seconds of N maneuvers
cpu_of() {
  local build=$1 arch=$2 setting=$3 src cfg
  src=$(src_of "$build")
  cfg="$work/${arch}_${setting}.cfg"
  sed -e "$(edit_of "$setting")" "$src/configs/$arch.cfg" >"$cfg"
  /usr/bin/time -f "%U %S" -o "$work/t" "$build/cli/pomlab" montecarlo "$cfg" --n "$N" \
    --threads 1 --quiet >/dev/null
  awk '{print $1 + $2}' "$work/t"
}

# wall_of BUILD THREADS -> wall seconds of the paper study
wall_of() {
  local build=$1 threads=$2 src
  src=$(src_of "$build")
  (cd "$src" && /usr/bin/time -f "%e %U" -o "$work/t" "$build/cli/pomlab" study configs/paper.cfg \
    --threads "$threads" --quiet --no-plots --no-summary --out "$work/paper.h5" >/dev/null)
  awk '{print $1 " (CPU " $2 " s)"}' "$work/t"
}

declare -A best
better() { # keeps the smaller of two CPU figures
  local k=$1 v=$2
  if [ -z "${best[$k]:-}" ] || awk -v a="$v" -v b="${best[$k]}" 'BEGIN{exit !(a < b)}'; then
    best[$k]=$v
  fi
}
echo "machine: $(nproc) cores, $(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -1); load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "old: $1 ($(git -C "$(src_of "$1")" rev-parse --short HEAD 2>/dev/null || echo '?'))"
echo "new: $2 ($(git -C "$(src_of "$2")" rev-parse --short HEAD 2>/dev/null || echo '?'))"
for round in 1 2; do
  for arch in 3pss 3sps; do
    for s in "${settings[@]}"; do
      for which in old new; do
        b=$1
        [ "$which" = new ] && b=$2
        better "$which/$arch/$s" "$(cpu_of "$b" "$arch" "$s")"
      done
    done
  done
done
echo
echo "maneuvers per CPU-second ($N maneuvers of the montecarlo seed, 1 thread, best of 2 rounds)"
printf "| %-6s | %-24s | %8s | %8s | %6s |\n" arch setting old new new/old
printf "|%s|\n" "--------|--------------------------|----------|----------|--------"
for arch in 3pss 3sps; do
  for s in "${settings[@]}"; do
    o=${best[old/$arch/$s]} n=${best[new/$arch/$s]}
    awk -v a="$arch" -v s="$s" -v o="$o" -v n="$n" -v N="$N" \
      'BEGIN{printf "| %-6s | %-24s | %8.1f | %8.1f | %6.2f |\n", a, s, N/o, N/n, o/n}'
  done
done
echo
[ -n "${THROUGHPUT_NO_STUDY:-}" ] && exit 0
echo "paper study (configs/paper.cfg, 2 x 1000 maneuvers), wall seconds"
for t in 1 2; do
  echo "threads $t: old $(wall_of "$1" "$t"), new $(wall_of "$2" "$t")"
done
