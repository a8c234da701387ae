#!/usr/bin/env bash
# test_cli_split.sh - the two programs (cli/CMakeLists.txt, bench/README.md
# start-up): pomlab loads no HDF5, SUNDIALS or NLopt, runs the kinematic
# commands itself, hands the others to pomlab-full beside it (same output as
# running pomlab-full), and says so when pomlab-full is missing.
# Usage: test_cli_split.sh PATH/TO/pomlab PATH/TO/pomlab-full SOURCE_DIR
set -u
POMLAB=$1
FULL=$2
SRC=$3
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
fails=0
fail() {
  echo "FAIL: $*"
  fails=$((fails + 1))
}

needed=$(readelf -d "$POMLAB" | grep NEEDED)
for lib in hdf5 sundials nlopt gsl; do
  if echo "$needed" | grep -qi "$lib"; then fail "pomlab links $lib: $needed"; fi
done
echo "$(readelf -d "$FULL" | grep NEEDED)" | grep -qi hdf5 || fail "pomlab-full does not link HDF5"

"$POMLAB" model "$SRC/configs/3pss.cfg" --json >"$TMP/model.json" || fail "model exit $?"
grep -q '"bodies"' "$TMP/model.json" || fail "model: no bodies in its JSON"

# a heavy command through pomlab: the same metrics as pomlab-full's own
args=(simulate "$SRC/configs/3pss.cfg" --target 1.5,-2,0.5 --joints rigid --json)
"$POMLAB" "${args[@]}" >"$TMP/a.json" || fail "simulate through pomlab: exit $?"
"$FULL" "${args[@]}" >"$TMP/b.json" || fail "simulate by pomlab-full: exit $?"
grep -v wall_time "$TMP/a.json" >"$TMP/a.txt"
grep -v wall_time "$TMP/b.json" >"$TMP/b.txt"
cmp -s "$TMP/a.txt" "$TMP/b.txt" || fail "simulate: pomlab and pomlab-full differ"

# pomlab without its sibling: a clear message and exit 1, for heavy commands only
cp "$POMLAB" "$TMP/pomlab"
"$TMP/pomlab" simulate "$SRC/configs/3pss.cfg" --target 1,1,1 >"$TMP/out" 2>"$TMP/err"
rc=$?
[ "$rc" = 1 ] || fail "missing pomlab-full: exit $rc (want 1)"
grep -q "cannot run .*pomlab-full" "$TMP/err" || fail "missing pomlab-full: message '$(cat "$TMP/err")'"
"$TMP/pomlab" fk "$SRC/configs/3pss.cfg" --q 1,-1,0.5 >/dev/null || fail "fk alone: exit $?"

if [ "$fails" -gt 0 ]; then
  echo "test_cli_split: $fails failed"
  exit 1
fi
echo "test_cli_split: ok"
