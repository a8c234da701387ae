#!/usr/bin/env bash
# test_safety.sh - data safety (issue 12, items 1-4 and 11): a second run on
# the same results file is refused while the first holds it and never
# truncates a finished file; write failures (a full disk: /dev/full) are
# reported with the path and errno and a non-zero exit; stored rows are
# checked on resume; two configs of one name are refused by synth and tune;
# a refused resume names the key that changed.
# Usage: test_safety.sh PATH/TO/pomlab SOURCE_DIR
set -u
POMLAB=$1
SRC=$2
PY=/usr/bin/python3
. "$(dirname "$0")/cli_lib.sh"

STUDY="$SRC/tests/doe_study_small.cfg"
CFG="$SRC/configs/3pss.cfg"
# the small study, quiet, no figures
RUN_STUDY=("$POMLAB" study "$STUDY" --no-plots --quiet)

# --- item 1: one run per results file; a finished file is replaced whole -----
expect_rc 0 "${RUN_STUDY[@]}" --out "$TMP/a.h5" --no-summary
cp "$TMP/a.h5" "$TMP/a.ref.h5"
# another run holds the file (flock, as pomlab takes it): refused, nothing touched
checks=$((checks + 1))
flock -n "$TMP/a.h5.lock" "$POMLAB" study "$STUDY" --out "$TMP/a.h5" --no-plots --quiet \
  --no-summary >"$TMP/out" 2>"$TMP/err"
rc=$?
[ "$rc" = 1 ] || fail "a second run while the lock is held: exit $rc, want 1"
expect_in "$TMP/err" "is being written by another pomlab run"
check "a refused run changed the finished file" cmp -s "$TMP/a.h5" "$TMP/a.ref.h5"
check "a refused run left a partial file" test ! -e "$TMP/a.h5.partial"
# two real runs at once: the second is refused, the first completes a readable file
"$POMLAB" montecarlo "$CFG" --n 150 --threads 1 --quiet --out "$TMP/mc.h5" \
  >"$TMP/mc1.out" 2>"$TMP/mc1.err" &
first=$!
for _ in $(seq 100); do
  [ -e "$TMP/mc.h5.lock" ] && break
  sleep 0.1
done
expect_rc 1 "$POMLAB" montecarlo "$CFG" --n 150 --threads 1 --quiet --out "$TMP/mc.h5"
expect_in "$TMP/err" "is being written by another pomlab run"
wait $first
rc=$?
check "the first of two concurrent runs failed (exit $rc)" test "$rc" = 0
checks=$((checks + 1))
"$PY" -c "
import h5py, sys
r = h5py.File(sys.argv[1], 'r')['candidates/0/maneuvers']['done']
sys.exit(0 if len(r) == 150 and r.all() else 1)" "$TMP/mc.h5" ||
  fail "the first of two concurrent runs left an unreadable or incomplete file"
check "lock file left behind" test ! -e "$TMP/mc.h5.lock"
# a new run on a finished file, interrupted: the finished file is untouched and
# the new run is in .partial, which --resume completes
expect_rc 0 "${RUN_STUDY[@]}" --out "$TMP/a.h5" --no-summary --stop-after 3
check "an interrupted re-run changed the finished file" cmp -s "$TMP/a.h5" "$TMP/a.ref.h5"
check "an interrupted run left no .partial" test -e "$TMP/a.h5.partial"
expect_in "$TMP/err" "every finished one is in $TMP/a.h5.partial"
expect_rc 0 "${RUN_STUDY[@]}" --out "$TMP/a.h5" --no-summary --resume
check "a completed resume left the .partial" test ! -e "$TMP/a.h5.partial"
checks=$((checks + 1))
"$PY" - "$TMP/a.h5" "$TMP/a.ref.h5" <<'PY' || fail "resumed rows differ from a straight run"
import sys, h5py, numpy as np
a, b = (h5py.File(p, "r") for p in sys.argv[1:3])
for c in a["candidates"]:
    x, y = a["candidates"][c]["maneuvers"][:], b["candidates"][c]["maneuvers"][:]
    x["wall_time"] = y["wall_time"] = 0.0  # the one field that differs between runs
    assert x.tobytes() == y.tobytes(), c
PY

# --- item 2: write failures are errors that name the path and the cause -------
mkdir -p "$TMP/full"
ln -s /dev/full "$TMP/full/summary.md"
expect_rc 1 "${RUN_STUDY[@]}" --out "$TMP/full.h5"
expect_in "$TMP/err" "writing '$TMP/full/summary.md' failed: No space left on device"
checks=$((checks + 1))
grep -q "^Summary:" "$TMP/out" && fail "a failed summary.md is announced as written"
ln -s /dev/full "$TMP/trace.csv"
expect_rc 1 "$POMLAB" simulate "$CFG" --target 1,1,1 --out "$TMP/trace.csv"
expect_in "$TMP/err" "writing '$TMP/trace.csv' failed: No space left on device"
expect_rc 1 "$POMLAB" workspace "$CFG" --map /dev/full
expect_in "$TMP/err" "writing '/dev/full' failed: No space left on device"
checks=$((checks + 1))
"$POMLAB" model "$CFG" --json >/dev/full 2>"$TMP/err"
rc=$?
[ "$rc" = 1 ] || fail "model --json on a full disk: exit $rc, want 1"
expect_in "$TMP/err" "writing standard output failed: No space left on device"
# figures that cannot be written: the script's own reason, no false hint
mkdir -p "$TMP/fig"
ln -s /dev/full "$TMP/fig/execution_time.png"
"$POMLAB" study "$STUDY" --out "$TMP/fig.h5" --quiet --no-summary >"$TMP/out" 2>"$TMP/err"
expect_in "$TMP/err" "No space left on device"
expect_in "$TMP/err" "figures not made"
checks=$((checks + 1))
grep -q "needs /usr/bin/python3 with h5py" "$TMP/err" && fail "figures warning blames python"

# --- item 3: stored rows are checked on resume --------------------------------
expect_rc 0 "${RUN_STUDY[@]}" --out "$TMP/d.h5" --no-summary --stop-after 6
cp "$TMP/d.h5.partial" "$TMP/d.keep"
# a damaged done flag, target and status (as a few corrupted bytes would leave)
"$PY" - "$TMP/d.h5.partial" <<'PY'
import sys, h5py
f = h5py.File(sys.argv[1], "a")
d = f["candidates/0/maneuvers"]
r = d[0]; r["done"] = -1; d[0] = r
r = d[1]; r["target"] = (0.0, 0.0, 0.0); d[1] = r
d = f["candidates/1/maneuvers"]
r = d[2]; r["status"] = 12345; d[2] = r
PY
expect_rc 1 "${RUN_STUDY[@]}" --out "$TMP/d.h5" --no-summary --resume
expect_in "$TMP/err" "3 stored row(s) are inconsistent"
expect_in "$TMP/err" "candidate 0 maneuver 0: done = -1"
expect_in "$TMP/err" "candidate 0 maneuver 1: target (0, 0, 0) is not maneuver 1's (seed 77)"
expect_in "$TMP/err" "candidate 1 maneuver 2: status = 12345 is no pomlab status"
check "a refused resume left no finished file" test ! -e "$TMP/d.h5"

# --- item 11: a refused resume names the key that changed ---------------------
cp "$TMP/d.keep" "$TMP/d.h5.partial"
# (copies in TMP, with the candidates' configs by absolute path)
sed "s|\"\.\./configs/|\"$SRC/configs/|; s/rtol = 1.0e-5/rtol = 2.0e-5/" "$STUDY" >"$TMP/rtol.cfg"
expect_rc 2 "$POMLAB" study "$TMP/rtol.cfg" --out "$TMP/d.h5" --no-plots --quiet --resume
expect_in "$TMP/err" "changed: key 'solver.rtol' (1e-05 in the file, 2e-05 now)"
sed "s|\"\.\./configs/|\"$SRC/configs/|; s/seed = 77/seed = 78/" "$STUDY" >"$TMP/seed.cfg"
expect_rc 2 "$POMLAB" study "$TMP/seed.cfg" --out "$TMP/d.h5" --no-plots --quiet --resume
expect_in "$TMP/err" "changed: key 'montecarlo.seed' (77 in the file, 78 now)"
check "a refused resume changed the unfinished file" cmp -s "$TMP/d.h5.partial" "$TMP/d.keep"

# --- item 4: two configs of one name are refused before any work --------------
expect_rc 2 "$POMLAB" tune "$CFG" "$CFG" --out "$TMP/t_"
expect_in "$TMP/err" "would both write $TMP/t_"
expect_rc 2 "$POMLAB" synth "$SRC/configs/synth_3pss.cfg" "$SRC/configs/synth_3pss.cfg" \
  --out "$TMP/s_"
expect_in "$TMP/err" "would both write $TMP/s_"
checks=$((checks + 1))
ls "$TMP"/t_* "$TMP"/s_* >/dev/null 2>&1 && fail "a refused synth or tune wrote a file"

finish test_safety
