#!/bin/bash
# accuracy.sh OLD_BUILD NEW_BUILD [N] [SETTING...] - the accuracy side of
# bench/throughput.sh: for each architecture x setting (bench/settings.sh),
# N maneuvers of the montecarlo seed (default 200) with the old build, the new
# build, and the new build at a tight tolerance of the same model (rtol 1e-9,
# atol_scale 1e-6), then bench/compare_h5.py OLD NEW TIGHT: per metric the
# largest relative difference new vs old and each build's largest and rms
# error against the tight run. Settings default to every one of settings.sh;
# THROUGHPUT_ARCHS overrides the architectures. Files are kept in
# ACCURACY_DIR (default a temporary directory, removed). Exit 2 on bad usage.
set -euo pipefail
if [ $# -lt 2 ] || [ ! -x "$1/cli/pomlab" ] || [ ! -x "$2/cli/pomlab" ]; then
  echo "usage: $0 OLD_BUILD NEW_BUILD [N maneuvers, default 200] [SETTING...]" >&2
  exit 2
fi
old=$1 new=$2
N=${3:-200}
shift $(($# < 3 ? $# : 3))
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=bench/settings.sh
. "$here/settings.sh"
[ $# -gt 0 ] && settings=("$@")
read -r -a archs <<<"${THROUGHPUT_ARCHS:-3pss 3sps 3rrr}"
if [ -n "${ACCURACY_DIR:-}" ]; then
  work=$ACCURACY_DIR
  mkdir -p "$work"
else
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
fi
src_of() { sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$1/CMakeCache.txt"; }
run() { # BUILD ARCH SETTING [BASE] OUT
  local build=$1 arch=$2 setting=$3 base=$4 out=$5
  setting_config "$(src_of "$build")" "$arch" "$setting" "$base" >"$out.cfg"
  "$build/cli/pomlab" montecarlo "$out.cfg" --n "$N" --threads 2 --quiet --out "$out.h5" >/dev/null
}
status=0
for arch in "${archs[@]}"; do
  for s in "${settings[@]}"; do
    echo "== $arch $s ($N maneuvers; tight: rtol 1e-9, atol_scale 1e-6)"
    run "$old" "$arch" "$s" "" "$work/${arch}_${s}_old"
    run "$new" "$arch" "$s" "" "$work/${arch}_${s}_new"
    run "$new" "$arch" tight "$s" "$work/${arch}_${s}_tight"
    /usr/bin/python3 "$here/compare_h5.py" "$work/${arch}_${s}_old.h5" "$work/${arch}_${s}_new.h5" \
      "$work/${arch}_${s}_tight.h5" || status=1
  done
done
exit $status
