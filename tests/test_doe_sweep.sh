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
# a table that cannot be written is a runtime failure that leaves nothing behind
code=0; "$POMLAB" study $CFG --out "$WORK/x.h5" --no-plots --no-summary --quiet \
  --tabular "$WORK/none/x.csv" > /dev/null 2> "$WORK/x.err" || code=$?
[ "$code" -eq 1 ] || { echo "unwritable tabular: exit $code, want 1"; exit 1; }
grep -q "none/x.csv" "$WORK/x.err"
echo "sweep: ok"
