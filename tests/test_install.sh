#!/usr/bin/env bash
# test_install.sh - `cmake --install` into a temporary prefix gives a working
# program: bin/pomlab, its plotting scripts in share/pomlab/scripts (found
# relative to the installed program, not in the source tree), the configs
# and the docs; a Monte-Carlo run from there makes its figures.
# Usage: test_install.sh PATH/TO/pomlab SOURCE_DIR BUILD_DIR CMAKE
set -u
POMLAB=$1
SRC=$2
BUILD=$3
CMAKE=$4
. "$(dirname "$0")/cli_lib.sh"
P="$TMP/prefix"

expect_rc 0 "$CMAKE" --install "$BUILD" --prefix "$P"
for f in bin/pomlab bin/pomlab-full share/pomlab/scripts/plot_study.py share/pomlab/scripts/plot_traces.py \
  share/pomlab/scripts/plot_tradeoff.py share/pomlab/configs/3pss.cfg \
  share/pomlab/configs/paper.cfg share/doc/pomlab/README.md share/doc/pomlab/conventions.md; do
  checks=$((checks + 1))
  [ -f "$P/$f" ] || fail "not installed: $f"
done
# the installed program finds the installed scripts; the build tree's finds
# the source tree's
expect_rc 0 "$P/bin/pomlab" --version
expect_in "$TMP/out" "scripts: $P/bin/../share/pomlab/scripts"
expect_rc 0 "$POMLAB" --version
expect_in "$TMP/out" "scripts: $SRC/scripts"
# a command that needs the scripts, run from elsewhere with the installed
# config: figures next to the results file
mkdir -p "$TMP/run"
(cd "$TMP/run" && "$P/bin/pomlab" montecarlo "$P/share/pomlab/configs/3pss.cfg" --n 12 \
  --out mc.h5 --quiet >"$TMP/out" 2>"$TMP/err")
checks=$((checks + 1))
[ $? = 0 ] || fail "installed montecarlo failed: $(head -3 "$TMP/err")"
for f in mc.h5 mc/summary.md mc/execution_time.png mc/energy.png; do
  checks=$((checks + 1))
  [ -s "$TMP/run/$f" ] || fail "installed montecarlo did not write $f: $(head -3 "$TMP/err")"
done

# the dexterity map's figure from the installed script
expect_rc 0 "$P/bin/pomlab" workspace "$P/share/pomlab/configs/3pss.cfg" --map "$TMP/map.csv"
expect_rc 0 "$PY" "$P/share/pomlab/scripts/plot_workspace.py" "$TMP/map.csv" "$TMP/map.png"
checks=$((checks + 1))
[ -s "$TMP/map.png" ] || fail "plot_workspace.py wrote no figure"

# one candidate: no paired figure (it would be empty), and the summary does
# not show one
checks=$((checks + 1))
[ ! -e "$TMP/run/mc/paired.png" ] || fail "one candidate, yet paired.png was written"
checks=$((checks + 1))
grep -q "paired.png" "$TMP/run/mc/summary.md" && fail "summary.md shows a paired figure"

echo "test_install: $checks checks, $fails failed"
[ "$fails" = 0 ]
