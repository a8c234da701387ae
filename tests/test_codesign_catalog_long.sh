#!/bin/bash
# test_codesign_catalog_long.sh POMLAB SOURCE_DIR - label long: runs
# `pomlab codesign configs/codesign-catalog.cfg` (every catalog architecture
# at its best, docs/optimize.md 11.10; several minutes on 2 cores) and checks
# what the ranking stands on: every candidate of the file is in the ranking,
# either with a feasible front whose fresh figures (rigid and parasitic) are
# finite and whose time optimum beats or equals its config design on the
# optimizer's maneuvers, or marked infeasible with a reason; the results file
# holds one group per candidate; the figure's axes start at 0 or above.
# Skipped (77) unless POMLAB_LONG=1.
set -u
POMLAB=$1
SRC=$2
if [ "${POMLAB_LONG:-0}" != 1 ]; then
  echo "skipped: set POMLAB_LONG=1 (runs the catalog co-design, several minutes)"
  exit 77
fi
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
fail=0
bad() { echo "FAIL: $*"; fail=1; }
CAT="$SRC/configs/codesign-catalog.cfg"
"$POMLAB" codesign "$CAT" --out "$TMP/cat.h5" --threads 2 --quiet > "$TMP/r.txt" 2> "$TMP/r.err"
rc=$?
[ $rc -eq 0 ] || { echo "FAIL: exit $rc: $(cat "$TMP/r.err")"; exit 1; }
n=$(grep -c '{ name = "C[0-9][0-9] ' "$CAT")
ranked=$(awk '/^Ranking at each/ {on = 1; next} on && /^  [0-9-]+ +C[0-9][0-9] / {k++} END {print k + 0}' "$TMP/r.txt")
[ "$ranked" -eq "$n" ] || bad "ranking lists $ranked of $n candidates"
# an infeasible candidate carries its reason in its section
inf=$(grep -c "^  -    C[0-9][0-9] .*infeasible" "$TMP/r.txt")
reasons=$(grep -c "^  INFEASIBLE: no design met the requirement set; at the best point kept: ." "$TMP/r.txt")
[ "$inf" -eq "$reasons" ] || bad "$inf infeasible in the ranking, $reasons reasons given"
# feasible rows: finite p95 triple and hypervolume > 0
awk '/^Ranking at each/ {on = 1; next} on && /^  [0-9]+ +C[0-9][0-9] / {
       if (!match($0, / [0-9.e+]+ +[0-9.]+\/[0-9.]+\/[0-9.]+ /)) { print "bad row: " $0; bad = 1; next }
       split(substr($0, RSTART + 1, RLENGTH - 2), f, / +/); split(f[2], p, "/");
       if (!(f[1] + 0 > 0) || !(p[2] + 0 > 0) || !(p[3] + 0 > 0)) { print "bad row: " $0; bad = 1 } }
     END {exit bad}' "$TMP/r.txt" || bad "a ranked row lacks a hypervolume or a fresh figure"
# per candidate: the optimizer's time optimum no worse than the config design
# on the optimizer's own maneuvers (COBYLA starts there, keeps its best feasible)
awk '/^== / {name = $0} /config.s design: optimizer set/ {c = $5}
     /^  1 +min t/ {if ($4 + 0 > c + 1e-9 && c + 0 > 0) {print name ": " $4 " > " c; bad = 1}}
     END {exit bad}' "$TMP/r.txt" || bad "a time optimum is worse than its config design"
groups=$(h5ls "$TMP/cat.h5/candidates" | wc -l)
[ "$groups" -eq "$n" ] || bad "results file: $groups candidate groups, want $n"
# axes: no negative tick label
grep -o 'text-anchor="end">[^<]*<' "$TMP/cat.svg" | grep -q '>-' && bad "figure: a negative energy tick"
grep -o 'text-anchor="middle">[-0-9.]*<' "$TMP/cat.svg" | grep -q '>-' && bad "figure: a negative time tick"
exit $fail
