#!/bin/sh
# test_doe_sweep.sh POMLAB WORKDIR
# A real sweep through the command line: candidates named by their factor
# values, one column per factor in the tables, JSON and HDF5, and the
# tabular results read back by pandas (tests/test_doe_tabular.py).
set -eu
POMLAB=$1
WORK=$2
CFG=tests/doe_sweep_small.cfg
rm -rf "$WORK"
mkdir -p "$WORK"
"$POMLAB" study $CFG --out "$WORK/s.h5" --no-plots --quiet --tabular "$WORK/s.csv" > "$WORK/s.txt"
grep -q "^| 3PSS platform_radius_mm=12 | 12 | " "$WORK/s.txt" ||
  { echo "no candidate named by its factor value with a factor column"; exit 1; }
grep -q "^| candidate | platform_radius_mm | max |" "$WORK/s.txt" || { echo "no factor header"; exit 1; }
grep -q "^| 3PSS platform_radius_mm=14 | 14 | " "$WORK/s/summary.md" ||
  { echo "summary.md lacks the factor column"; exit 1; }
/usr/bin/python3 tests/test_doe_tabular.py "$WORK/s.h5" "$WORK/s.csv" "$WORK/s_candidates.csv"
/usr/bin/python3 tests/test_doe_effects.py "$WORK/s.h5"
grep -q "^### Main effects" "$WORK/s.txt" || { echo "no main effects table"; exit 1; }
grep -q "^| platform_radius_mm | 12 | 1 | " "$WORK/s.txt" || { echo "main effects: no level 12"; exit 1; }
grep -q "^### Pareto front" "$WORK/s.txt" || { echo "no Pareto front"; exit 1; }
grep -q "^### Friedman test (all 3 candidates" "$WORK/s.txt" || { echo "no Friedman test"; exit 1; }
# the figures of a sweep, referenced by summary.md
"$POMLAB" study $CFG --out "$WORK/p.h5" --quiet > /dev/null
for fig in execution_time energy paired main_effects pareto; do
  [ -s "$WORK/p/$fig.png" ] || { echo "no $fig.png"; exit 1; }
  grep -q "($fig.png)" "$WORK/p/summary.md" || { echo "summary.md lacks $fig.png"; exit 1; }
done
[ ! -e "$WORK/p/heatmap.png" ] || { echo "a heat map of one factor"; exit 1; }
"$POMLAB" study $CFG --out "$WORK/j.h5" --no-plots --no-summary --quiet --json > "$WORK/j.json"
/usr/bin/python3 - "$WORK/j.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
assert d["factors"] == ["geometry.platform_radius_mm"], d["factors"]
want = [10.0, 12.0, 14.0]
for c, v in zip(d["candidates"], want):
    assert c["factors"] == {"geometry.platform_radius_mm": v}, c["factors"]
    assert c["name"] == "3PSS platform_radius_mm=%g" % v, c["name"]
PY
# tabular results need a results file: a usage error before any work
code=0; "$POMLAB" montecarlo configs/3pss.cfg --n 2 --tabular "$WORK/m.csv" --quiet \
  > /dev/null 2> "$WORK/m.err" || code=$?
[ "$code" -eq 2 ] || { echo "--tabular without --out: exit $code, want 2"; exit 1; }
grep -q "need a results file" "$WORK/m.err"
[ ! -e "$WORK/m.csv" ]
# a table that cannot be written is a runtime failure that leaves nothing
# behind, found before the work (a missing folder is made, as for --out;
# here "none" is a file, so it cannot be: tests/test_output_paths.sh)
: > "$WORK/none"
code=0; "$POMLAB" study $CFG --out "$WORK/x.h5" --no-plots --no-summary --quiet \
  --tabular "$WORK/none/x.csv" > /dev/null 2> "$WORK/x.err" || code=$?
[ "$code" -eq 1 ] || { echo "unwritable tabular: exit $code, want 1"; exit 1; }
grep -q "none/x.csv" "$WORK/x.err"
[ ! -e "$WORK/x.h5" ] || { echo "unwritable tabular: the study ran"; exit 1; }
# identical candidates tie: no "faster on 50 %", a tie in the verdict, the
# comparison table and the ranking (item: ties are ties)
printf 'name = "same"; montecarlo = { maneuvers = 4; seed = 5; };\n%s\n%s\n' \
  'study = { override = { joints = { model = "rigid"; }; scene = { coil_inductance = false; }; }; };' \
  "candidates = ( { name = \"A\"; config = \"$(pwd)/configs/3pss.cfg\"; }, { name = \"B\"; config = \"$(pwd)/configs/3pss.cfg\"; } );" \
  > "$WORK/same.cfg"
"$POMLAB" study "$WORK/same.cfg" --out "$WORK/same.h5" --no-plots --no-summary --quiet > "$WORK/same.txt"
grep -q "^- execution time: A and B \*\*tie\*\*: the same execution time on every one of the 4 common" \
  "$WORK/same.txt" || { echo "identical candidates: no tie in the verdict"; exit 1; }
grep -q "^- expended energy: A and B \*\*tie\*\*" "$WORK/same.txt" || { echo "energy: no tie"; exit 1; }
if grep -q "faster than\|less energy than" "$WORK/same.txt"; then
  echo "identical candidates: a winner was named"; exit 1
fi
grep -q "^| execution time (ms) | A | B | 4 | 0.000 | .* | 0.0 % | 100.0 % | 0.0 % | 0 / 0 |$" "$WORK/same.txt" ||
  { echo "comparison table: ties not shown as ties"; exit 1; }
grep -q "^- execution time (primary): 1.= A, 1.= B (restricted mean: .*: A 0, B 0)$" "$WORK/same.txt" ||
  { echo "ranking: equal means do not share a place"; exit 1; }
# one candidate: no plural, no ranking of one, no comparison, no name column
"$POMLAB" montecarlo configs/3pss.cfg --n 3 --quiet > "$WORK/one.txt"
if grep -q "1 candidates\|Ranking\|Verdict\|nothing to compare\|| candidate |" "$WORK/one.txt"; then
  echo "single candidate: comparison sections or a name column"; exit 1
fi
grep -q "^| max | mean | min | sigma | median | p95 | n | unsettled | failed |$" "$WORK/one.txt"
# a mean and a majority that disagree (K_P 16000 has the lower mean execution
# time by 0.015 ms, yet K_P 12000 is faster on 95 % of the maneuvers, a
# significant signed-rank test): the verdict says "mixed", crowns nobody
cat > "$WORK/mixed.cfg" <<CFG
name = "mixed";
montecarlo = { maneuvers = 40; seed = 20120708; range_mm = 3.0; };
study = { override = { joints = { model = "rigid"; }; scene = { coil_inductance = false; }; }; };
candidates = { sweep = "grid"; base = ( { name = "3P-S-S/S"; config = "$PWD/configs/3pss.cfg"; } );
  factors = ( { key = "controller.kp"; min = 1.2e4; max = 1.6e4; levels = 2; } ); };
CFG
"$POMLAB" study "$WORK/mixed.cfg" --out "$WORK/mixed.h5" --no-plots --quiet > "$WORK/mixed.txt"
grep -q "^- execution time: mixed: \*\*3P-S-S/S kp=1.6e+04\*\* has the lower mean .* but 3P-S-S/S kp=1.2e+04 is faster on 95.0 % of 40" "$WORK/mixed.txt" ||
  { echo "mean and majority disagree: no mixed verdict"; exit 1; }
echo "sweep: ok"
