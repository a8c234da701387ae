#!/bin/sh
# test_doe_study.sh POMLAB WORKDIR [MPIRUN]
# A real (small) study through the command line: threads 1 and 2 give the same
# rows, an interrupted study resumes to the same rows, a failure is recorded,
# and h5py reads the file (tests/test_doe_h5.py checks layout and statistics).
# With MPIRUN given, a 2-rank run must give the same rows as well.
set -eu
POMLAB=$1
WORK=$2
MPIRUN=${3:-}
CFG=tests/doe_study_small.cfg
rm -rf "$WORK"
mkdir -p "$WORK"
"$POMLAB" study $CFG --threads 1 --out "$WORK/t1.h5" --no-plots --no-summary --quiet > "$WORK/t1.txt"
"$POMLAB" study $CFG --threads 2 --out "$WORK/t2.h5" --no-plots --quiet --json > "$WORK/t2.json"
# interrupted after 3 units, then resumed
"$POMLAB" study $CFG --threads 2 --out "$WORK/r.h5" --stop-after 3 --no-plots --no-summary --quiet \
  > "$WORK/r1.txt" 2> "$WORK/r1.err"
grep -q "continue with --resume" "$WORK/r1.err"
"$POMLAB" study $CFG --threads 2 --out "$WORK/r.h5" --resume --no-plots --no-summary --quiet \
  > "$WORK/r2.txt"
# a file of another results format version is not resumed
cp "$WORK/r.h5" "$WORK/ver.h5"
/usr/bin/python3 -c "import h5py, sys; h5py.File(sys.argv[1], 'a').attrs['format_version'] = 99" \
  "$WORK/ver.h5"
if "$POMLAB" study $CFG --out "$WORK/ver.h5" --resume --no-plots --no-summary --quiet \
  > /dev/null 2> "$WORK/ver.err"; then
  echo "resumed a file of another format version"; exit 1
fi
grep -q "format version 99" "$WORK/ver.err"
# nor one of another program (a plain HDF5 file without the format attribute)
/usr/bin/python3 -c "import h5py, sys; h5py.File(sys.argv[1], 'w').create_dataset('x', data=[1.0])" \
  "$WORK/foreign.h5"
code=0; "$POMLAB" study $CFG --out "$WORK/foreign.h5" --resume --no-plots --no-summary --quiet \
  > /dev/null 2> "$WORK/foreign.err" || code=$?
[ "$code" -eq 2 ] || { echo "foreign results file: exit $code, want 2"; exit 1; }
grep -q "is not a pomlab study results file" "$WORK/foreign.err"
# a config error stops before any work (exit 2, no file)
# (written in WORK, not in the source tree, so concurrent test runs do not race)
printf 'candidates = ( { name = "x"; config = "%s/configs/3pss.cfg"; colour = 2; } );\n' \
  "$(pwd)" > "$WORK/bad.cfg"
if "$POMLAB" study "$WORK/bad.cfg" --out "$WORK/bad.h5" --quiet 2> "$WORK/bad.err"; then
  echo "bad config accepted"; exit 1
else
  code=$?
fi
[ "$code" -eq 2 ] || { echo "bad config: exit $code, want 2"; exit 1; }
grep -q "candidates.\[0\].colour" "$WORK/bad.err"
[ ! -e "$WORK/bad.h5" ]
# a study file or a candidate config that cannot be opened is a config error too
code=0; "$POMLAB" study "$WORK/none.cfg" --quiet 2> /dev/null || code=$?
[ "$code" -eq 2 ] || { echo "missing study file: exit $code, want 2"; exit 1; }
printf 'candidates = ( { name = "x"; config = "%s/none.cfg"; } );\n' "$WORK" > "$WORK/nocand.cfg"
code=0; "$POMLAB" study "$WORK/nocand.cfg" --out "$WORK/nocand.h5" --quiet 2> /dev/null || code=$?
[ "$code" -eq 2 ] || { echo "missing candidate config: exit $code, want 2"; exit 1; }
[ ! -e "$WORK/nocand.h5" ]
# nor does it touch an existing results file
cp "$WORK/t1.h5" "$WORK/keep.h5"
if "$POMLAB" study "$WORK/bad.cfg" --out "$WORK/keep.h5" --quiet 2> /dev/null; then exit 1; fi
cmp -s "$WORK/t1.h5" "$WORK/keep.h5" || { echo "config error changed the results file"; exit 1; }
# a loop that runs past the stroke is a recorded failure in a study too
# (and a results file name without extension gets its summary in <name>_summary/)
"$POMLAB" study tests/doe_study_runaway.cfg --out "$WORK/run" --no-plots --quiet > /dev/null
[ -s "$WORK/run_summary/summary.md" ] || { echo "no summary for an output without extension"; exit 1; }
grep -q "^| .* | \(parasitic\|rigid\) joints.*, \(inductive\|quasi-static\) coil |$" \
  "$WORK/run_summary/summary.md" || { echo "summary lacks the candidate's model"; exit 1; }
/usr/bin/python3 - "$WORK/run" <<'PY'
import sys, h5py, numpy as np
r = h5py.File(sys.argv[1], "r")["candidates/0/maneuvers"][:]
out = np.any(np.abs(r["final_q"]) > 6e-3, axis=1)
assert out.any() and (~out).any(), "runaway study: want maneuvers on both sides of the stroke"
assert np.all(r["status"][out] == -6), "runaway maneuvers not failed: %s" % r["status"]
assert all(b"ended outside its stroke" in x for x in r["reason"][out]), r["reason"]
assert np.all(r["status"][~out] == 0)
PY
SAME="$WORK/t1.h5 $WORK/t2.h5 $WORK/r.h5"
if [ -n "$MPIRUN" ]; then
  $MPIRUN --allow-run-as-root --oversubscribe -np 2 "$POMLAB" study $CFG --threads 1 \
    --out "$WORK/mpi.h5" --no-plots --no-summary --quiet > "$WORK/mpi.txt"
  # and 2 ranks interrupted, then resumed
  $MPIRUN --allow-run-as-root --oversubscribe -np 2 "$POMLAB" study $CFG --threads 1 \
    --out "$WORK/mpir.h5" --stop-after 3 --no-plots --no-summary --quiet > /dev/null 2>&1
  $MPIRUN --allow-run-as-root --oversubscribe -np 2 "$POMLAB" study $CFG --threads 1 \
    --out "$WORK/mpir.h5" --resume --no-plots --no-summary --quiet > /dev/null
  SAME="$SAME $WORK/mpi.h5 $WORK/mpir.h5"
fi
/usr/bin/python3 tests/test_doe_h5.py "$WORK/t2.json" $SAME
# the parasitic model's validity rule in the report (docs/dynamics.md section
# 13b): per candidate, the maneuvers flagged, "n/a" on rigid joints; the count
# is the rule applied to the rows (rigid_limit_ratio > 1e-2 or
# joint_dissipation_share > 2e-4, over the ok maneuvers). The 3P-S-S/S at
# k_p = 1e8 lies at the share's threshold: some of its maneuvers are flagged
# and some not (3 of 6), the shipped k_p = 1e6 all, the rigid joints none.
cat > "$WORK/validity.cfg" <<CFG
name = "validity_small";
montecarlo = { maneuvers = 6; seed = 5; range_mm = 4.0; };
candidates = (
  { name = "P6"; config = "$(pwd)/configs/3pss.cfg"; },
  { name = "P8"; config = "$(pwd)/configs/3pss.cfg";
    override = { joints = { stiffness_N_per_m = 1.0e8; }; }; },
  { name = "R"; config = "$(pwd)/configs/3pss.cfg"; override = { joints = { model = "rigid"; }; }; }
);
CFG
"$POMLAB" study "$WORK/validity.cfg" --out "$WORK/validity.h5" --no-plots --quiet \
  > "$WORK/validity.txt"
"$POMLAB" study "$WORK/validity.cfg" --out "$WORK/validity_j.h5" --no-plots --no-summary --quiet \
  --json > "$WORK/validity.json"
/usr/bin/python3 - "$WORK/validity.h5" "$WORK/validity.json" "$WORK/validity.txt" \
  "$WORK/validity/summary.md" <<'PY'
import sys, json, h5py, numpy as np
f = h5py.File(sys.argv[1], "r")
js = json.load(open(sys.argv[2]))["candidates"]
want = []
for c in range(3):
    r = f["candidates/%d/maneuvers" % c][:]
    ok = r["status"] == 0
    flag = (r["rigid_limit_ratio"] > 1e-2) | (r["joint_dissipation_share"] > 2e-4)
    measured = ok & ~(np.isnan(r["rigid_limit_ratio"]) & np.isnan(r["joint_dissipation_share"]))
    want.append((int(np.sum(flag & measured)), int(np.sum(measured))))
assert want[0] == (6, 6), want          # shipped k_p: every maneuver flagged
assert 0 < want[1][0] < 6 and want[1][1] == 6, want  # at the threshold: a mix
assert want[2] == (0, 0), want          # rigid joints: not measured
for c in range(2):
    assert js[c]["rigid_limit_flagged"] == want[c][0], (c, js[c], want)
    assert js[c]["rigid_limit_checked"] == want[c][1], (c, js[c], want)
assert js[2]["rigid_limit_flagged"] is None and js[2]["rigid_limit_checked"] == 0, js[2]
line = "P6 %d of %d, P8 %d of %d, R n/a maneuver(s) flagged" % (want[0] + want[1])
for path in sys.argv[3:]:
    text = open(path).read()
    assert line in text, (path, line)
    assert "Note: a flagged maneuver's parasitic result" in text, path
PY
