#!/usr/bin/env bash
# test_dataloss.sh - a full disk and failed writes lose nothing (issue 22,
# items 1 and 3 to 6). One part per ctest entry (tests/cli.cmake):
#   full_disk   items 1 and 6: a study on a disk that fills up at every size
#               from 8 KB to the complete file (a small tmpfs when this user
#               may mount one, and always a file size limit, ulimit -f) exits
#               1, never 139 (HDF5's exit handler on a file that failed to
#               close); --resume with room completes rows equal to a clean run
#   report      item 4: a report that cannot be written never replaces the
#               finished file
#   tabular     item 5: the two tables are both the new pair or both the old
#               one, never one of each (needs a tmpfs)
#   sensitivity item 3: pomlab sensitivity takes its output before the first
#               run (lock, rows file), resumes (--stop-after, a full disk),
#               and prints its indices when only the file cannot be written
# Exit 77 (ctest SKIP_RETURN_CODE) when a part needs a tmpfs and mounting is
# not permitted here.
# Usage: test_dataloss.sh PATH/TO/pomlab SOURCE_DIR PART
set -u
POMLAB=$1
SRC=$2
PART=$3
. "$(dirname "$0")/cli_lib.sh"

STUDY="$SRC/tests/doe_study_small.cfg"
RUN_STUDY=("$POMLAB" study "$STUDY" --no-plots --no-summary --quiet)
MNT="$TMP/mnt"
mkdir -p "$MNT"
trap 'mountpoint -q "$MNT" && umount "$MNT"; rm -rf "$TMP"' EXIT

# mount_small KB : a tmpfs of KB kilobytes at $MNT (returns 1 when not permitted)
mount_small() {
  mountpoint -q "$MNT" && umount "$MNT"
  mount -t tmpfs -o "size=$1k" tmpfs "$MNT" 2>/dev/null
}

# rows_equal REF FILE... : every candidate's rows of each FILE equal REF's
# (wall times aside, the one field that differs between runs)
rows_equal() {
  checks=$((checks + 1))
  "$PY" - "$@" <<'PY' || fail "resumed rows differ from a clean run"
import sys, h5py
ref = h5py.File(sys.argv[1], "r")
for path in sys.argv[2:]:
    f = h5py.File(path, "r")
    assert sorted(f["candidates"]) == sorted(ref["candidates"]), path
    for c in ref["candidates"]:
        x, y = f["candidates"][c]["maneuvers"][:], ref["candidates"][c]["maneuvers"][:]
        x["wall_time"] = y["wall_time"] = 0.0
        assert x.tobytes() == y.tobytes(), (path, c)
    assert "statistics" in f and "ranking" in f, path
PY
}

# no_sanitizer_report : the last command's stderr has no sanitizer report
# (their exit status, 1, is also the one a failed write gives)
no_sanitizer_report() {
  check "$label: a sanitizer report" test -z "$(grep -l Sanitizer "$TMP/err")"
}

# after_failure RC DIR KIND : a run that ran out of space (KIND: the system's
# reason) exited 1 naming it, left no finished file and no temporary one
after_failure() {
  local rc=$1 dir=$2 why=$3
  checks=$((checks + 1))
  if [ "$rc" != 1 ]; then
    fail "$label: exit $rc, want 1 (or 0 when it fits)"
    sed 's/^/  stderr: /' "$TMP/err" | head -3
    return
  fi
  expect_in "$TMP/err" "$why"
  no_sanitizer_report
  check "$label: a failed run left a finished file" test ! -e "$dir/s.h5"
  check "$label: a failed run left a temporary file" \
    test -z "$(find "$dir" -name 's.h5.tmp.*' -print -quit)"
}

# resume_with_room DIR : --resume completes the study
resume_with_room() {
  local dir=$1
  expect_rc 0 "${RUN_STUDY[@]}" --out "$dir/s.h5" --resume
  check "$label: no finished file after --resume" test -e "$dir/s.h5"
  check "$label: a .partial left after a complete --resume" test ! -e "$dir/s.h5.partial"
}

part_full_disk() {
  expect_rc 0 "${RUN_STUDY[@]}" --out "$TMP/ref.h5"
  local done_files=()
  # a file size limit (works anywhere): a write past it fails with EFBIG
  local kb rc
  for kb in $(seq 4 4 200); do
    label="ulimit -f $kb"
    mkdir -p "$TMP/u$kb"
    (
      trap '' XFSZ
      ulimit -f "$kb"
      exec "${RUN_STUDY[@]}" --out "$TMP/u$kb/s.h5"
    ) >"$TMP/out" 2>"$TMP/err"
    rc=$?
    [ "$rc" = 0 ] && break
    after_failure "$rc" "$TMP/u$kb" "File too large"
    resume_with_room "$TMP/u$kb"
    done_files+=("$TMP/u$kb/s.h5")
  done
  check "no size limit let the study complete" test "$rc" = 0
  rows_equal "$TMP/ref.h5" "${done_files[@]}"
  # a full tmpfs (the issue's reproduction): every size from 8 KB until the
  # study fits, the rows file and its report copy included
  if ! mount_small 8; then
    echo "test_dataloss: cannot mount a tmpfs here: the full-disk sweep is skipped"
    finish test_dataloss_full_disk
    return
  fi
  done_files=()
  for kb in $(seq 8 4 400); do
    label="tmpfs $kb KB"
    mount_small "$kb"
    timeout 120 "${RUN_STUDY[@]}" --out "$MNT/s.h5" >"$TMP/out" 2>"$TMP/err"
    rc=$?
    [ "$rc" = 0 ] && break
    after_failure "$rc" "$MNT" "No space left on device"
    mount -o remount,size=10m "$MNT"
    resume_with_room "$MNT"
    mkdir -p "$TMP/t$kb"
    cp "$MNT/s.h5" "$TMP/t$kb/s.h5"
    done_files+=("$TMP/t$kb/s.h5")
  done
  check "no tmpfs size let the study complete" test "$rc" = 0
  rows_equal "$TMP/ref.h5" "${done_files[@]}"
  echo "test_dataloss: full disk at ${#done_files[@]} sizes from 8 KB to $((kb - 4)) KB"
  finish test_dataloss_full_disk
}

part_report() {
  # a finished file, and an unfinished run of the same study whose report
  # cannot be written (its /statistics object header damaged)
  expect_rc 0 "${RUN_STUDY[@]}" --out "$TMP/r.h5"
  cp "$TMP/r.h5" "$TMP/r.ref"
  cp "$TMP/r.h5" "$TMP/r.h5.partial"
  checks=$((checks + 1))
  "$PY" - "$TMP/r.h5.partial" <<'PY' || fail "could not damage the report"
import sys, h5py
with h5py.File(sys.argv[1], "r") as f:
    addr = h5py.h5o.get_info(f["statistics"].id).addr
with open(sys.argv[1], "r+b") as g:
    g.seek(addr)
    g.write(b"\xff" * 16)
PY
  expect_rc 1 "${RUN_STUDY[@]}" --out "$TMP/r.h5" --resume
  label="damaged report"
  no_sanitizer_report
  expect_in "$TMP/err" "the report was not written; every finished maneuver is kept in '$TMP/r.h5.partial'"
  check "a failed report replaced the finished file" cmp -s "$TMP/r.h5" "$TMP/r.ref"
  check "a failed report lost the unfinished file" test -e "$TMP/r.h5.partial"
  check "a failed report left a temporary file" \
    test -z "$(find "$TMP" -name 'r.h5.tmp.*' -print -quit)"
  # the same when the finished file itself is resumed: it is never written
  rm "$TMP/r.h5.partial"
  cp "$TMP/r.h5" "$TMP/r2.h5"
  expect_rc 0 "${RUN_STUDY[@]}" --out "$TMP/r2.h5" --resume
  check "resuming a finished file left a .partial" test ! -e "$TMP/r2.h5.partial"
  rows_equal "$TMP/r.ref" "$TMP/r2.h5"
  finish test_dataloss_report
}

part_tabular() {
  mount_small 64 || {
    echo "test_dataloss: cannot mount a tmpfs here: skipped"
    exit 77
  }
  umount "$MNT"
  # eight candidates, so that the candidates table is written in more than
  # one buffer; the results on the ordinary disk, the tables on a small
  # tmpfs that already holds an older pair, whose main table has a backup
  # (a hard link: replacing it frees no space)
  sed "s/levels = 3;/levels = 8;/; s/maneuvers = 6;/maneuvers = 2;/; s#\.\./configs#$SRC/configs#" \
    "$SRC/tests/doe_sweep_small.cfg" >"$TMP/sweep8.cfg"
  local run=("$POMLAB" study "$TMP/sweep8.cfg" --no-plots --no-summary --quiet --out "$TMP/t.h5")
  expect_rc 0 "${run[@]}" --tabular "$TMP/new.csv"
  local both
  both=$(($(cat "$TMP/new.csv" "$TMP/new_candidates.csv" | wc -c) / 1024))
  local kb rc mixed=0 sizes=0 a b
  # from room for the old pair alone to room for both pairs
  for kb in $(seq $(((both + 8) / 4 * 4)) 4 $((2 * both + 24))); do
    mount_small "$kb"
    { printf 'old\n' && cat "$TMP/new.csv"; } >"$MNT/t.csv" 2>/dev/null
    ln "$MNT/t.csv" "$MNT/t.csv.bak"
    { printf 'old\n' && cat "$TMP/new_candidates.csv"; } >"$MNT/t_candidates.csv" 2>/dev/null
    timeout 120 "${run[@]}" --resume --tabular "$MNT/t.csv" >"$TMP/out" 2>"$TMP/err"
    rc=$?
    sizes=$((sizes + 1))
    a=$(head -c 3 "$MNT/t.csv")
    b=$(head -c 3 "$MNT/t_candidates.csv")
    if [ "$a" != "$b" ]; then
      mixed=$((mixed + 1))
      fail "tmpfs $kb KB: one table is new, the other old (exit $rc)"
    fi
    if [ "$rc" = 0 ]; then
      check "tmpfs $kb KB: exit 0 but the main table is not the new one" \
        cmp -s "$MNT/t.csv" "$TMP/new.csv"
      check "tmpfs $kb KB: exit 0 but the candidates table is not the new one" \
        cmp -s "$MNT/t_candidates.csv" "$TMP/new_candidates.csv"
    else
      label="tmpfs $kb KB"
      check "$label: exit $rc, want 1" test "$rc" = 1
      expect_in "$TMP/err" "No space left on device"
      no_sanitizer_report
    fi
    check "tmpfs $kb KB: a temporary table left" \
      test -z "$(find "$MNT" -name '*.tmp.*' -print -quit)"
  done
  check "the tables never fitted" test "$rc" = 0
  echo "test_dataloss: tables at $sizes sizes, $mixed mixed pairs"
  finish test_dataloss_tabular
}

# same_table A B : the index tables (lines of "|") of two outputs are equal
# (the rest says the wall time and the file)
same_table() {
  grep -q '^|' "$1" && diff <(grep '^|' "$1") <(grep '^|' "$2") >/dev/null
}

# sens_equal REF FILE... : the same design outputs and indices as REF
sens_equal() {
  checks=$((checks + 1))
  "$PY" - "$@" <<'PY' || fail "a resumed sensitivity file differs from a clean run"
import sys, h5py, numpy as np
ref = h5py.File(sys.argv[1], "r")
for path in sys.argv[2:]:
    f = h5py.File(path, "r")
    for name in ("design", "values", "outputs", "sobol/S1", "sobol/ST"):
        assert np.array_equal(f[name][()], ref[name][()], equal_nan=True), (path, name)
PY
}

part_sensitivity() {
  # two inputs, 8 base samples: 32 runs of the exact model
  cat >"$TMP/s.cfg" <<CFG
name = "s";
montecarlo = { maneuvers = 1; seed = 20120708; range_mm = 3.0; };
study = { override = { joints = { model = "rigid"; }; scene = { coil_inductance = false; }; }; };
uncertain = (
  { key = "controller.kd_s"; dist = "uniform"; min = 0.8; max = 1.2; relative = true; },
  { key = "actuator.resistance_ohm"; dist = "uniform"; min = 0.95; max = 1.05; relative = true; }
);
sensitivity = { method = "sobol"; samples = 8; bootstrap = 50; metric = "execution_time"; };
candidates = ( { name = "3P-S-S/S"; config = "$SRC/configs/3pss.cfg"; } );
CFG
  local run=("$POMLAB" sensitivity "$TMP/s.cfg" --no-plots --quiet)
  expect_rc 0 "${run[@]}" --out "$TMP/ref.h5"
  cp "$TMP/out" "$TMP/ref.txt"
  # interrupted (--stop-after), then resumed: the same file as a clean run
  expect_rc 0 "${run[@]}" --out "$TMP/a.h5" --stop-after 10
  expect_in "$TMP/err" "every finished one is in '$TMP/a.h5.partial': continue with --resume"
  check "a stopped run left a results file" test ! -e "$TMP/a.h5"
  check "a stopped run kept no .partial" test -e "$TMP/a.h5.partial"
  expect_rc 0 "${run[@]}" --out "$TMP/a.h5" --resume
  check "a resumed run printed other indices" same_table "$TMP/out" "$TMP/ref.txt"
  check "a complete run left its .partial" test ! -e "$TMP/a.h5.partial"
  check "a complete run left its lock" test ! -e "$TMP/a.h5.lock"
  sens_equal "$TMP/ref.h5" "$TMP/a.h5"
  # another run holds the output: refused before any run, nothing touched
  checks=$((checks + 1))
  flock -n "$TMP/b.h5.lock" "${run[@]}" --out "$TMP/b.h5" >"$TMP/out" 2>"$TMP/err"
  [ $? = 1 ] || fail "a second run on a locked output: not exit 1"
  expect_in "$TMP/err" "is being written by another pomlab run"
  check "a refused run printed results" test ! -s "$TMP/out"
  # a file size limit (anywhere): every size exits 1 or 0, never 139
  local kb rc done_files=()
  for kb in $(seq 4 4 80); do
    mkdir -p "$TMP/u$kb"
    (
      trap '' XFSZ
      ulimit -f "$kb"
      exec "${run[@]}" --out "$TMP/u$kb/s.h5"
    ) >"$TMP/out" 2>"$TMP/err"
    rc=$?
    [ "$rc" = 0 ] && break
    label="ulimit -f $kb"
    check "$label: exit $rc, want 1" test "$rc" = 1
    expect_in "$TMP/err" "File too large"
    no_sanitizer_report
    expect_rc 0 "${run[@]}" --out "$TMP/u$kb/s.h5" --resume
    done_files+=("$TMP/u$kb/s.h5")
  done
  check "no size limit let the sensitivity run complete" test "$rc" = 0
  sens_equal "$TMP/ref.h5" "${done_files[@]}"
  if ! mount_small 8; then
    echo "test_dataloss: cannot mount a tmpfs here: the full-disk sweep is skipped"
    finish test_dataloss_sensitivity
    return
  fi
  # a read-only output folder: refused before the first run, stdout empty
  umount "$MNT"
  mount -t tmpfs -o size=64k,ro tmpfs "$MNT"
  expect_rc 1 "${run[@]}" --out "$MNT/s.h5"
  expect_in "$TMP/err" "cannot create the lock file '$MNT/s.h5.lock': Read-only file system"
  check "a refused output printed results" test ! -s "$TMP/out"
  # a full disk at every size until it fits: exit 1 or 0, never 139; when
  # the runs are done and only the file fails, the indices are printed all
  # the same; --resume with room writes the file of a clean run
  done_files=()
  local late=0
  for kb in $(seq 8 4 200); do
    label="tmpfs $kb KB"
    mount_small "$kb"
    timeout 120 "${run[@]}" --out "$MNT/s.h5" >"$TMP/out" 2>"$TMP/err"
    rc=$?
    [ "$rc" = 0 ] && break
    check "$label: exit $rc, want 1" test "$rc" = 1
    expect_in "$TMP/err" "No space left on device"
    no_sanitizer_report
    if grep -qF "every run is kept in '$MNT/s.h5.partial'" "$TMP/err"; then
      late=$((late + 1))
      check "$label: the file failed but the indices were not printed" \
        same_table "$TMP/out" "$TMP/ref.txt"
    else
      check "$label: output printed by a run that did not compute" test ! -s "$TMP/out"
    fi
    check "$label: a failed run left a results file" test ! -e "$MNT/s.h5"
    mount -o remount,size=10m "$MNT"
    expect_rc 0 "${run[@]}" --out "$MNT/s.h5" --resume
    check "$label: a resumed run printed other indices" same_table "$TMP/out" "$TMP/ref.txt"
    check "$label: a .partial left after a complete --resume" test ! -e "$MNT/s.h5.partial"
    mkdir -p "$TMP/t$kb"
    cp "$MNT/s.h5" "$TMP/t$kb/s.h5"
    done_files+=("$TMP/t$kb/s.h5")
  done
  check "no tmpfs size let the sensitivity run complete" test "$rc" = 0
  check "no size failed after the runs (the file alone)" test "$late" -gt 0
  sens_equal "$TMP/ref.h5" "${done_files[@]}"
  echo "test_dataloss: sensitivity on a full disk at ${#done_files[@]} sizes ($late after the runs)"
  finish test_dataloss_sensitivity
}

case "$PART" in
full_disk) part_full_disk ;;
report) part_report ;;
tabular) part_tabular ;;
sensitivity) part_sensitivity ;;
*)
  echo "test_dataloss.sh: unknown part '$PART'"
  exit 2
  ;;
esac
