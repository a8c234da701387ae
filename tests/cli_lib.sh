# cli_lib.sh - the checks of pomlab's shell tests, sourced after POMLAB and
# SRC are set: a temporary folder $TMP (removed on exit), the counters
# $checks and $fails, and expect_rc, expect_in, expect_err, check,
# json_check. A test ends with `finish NAME` (or echoes its own summary and
# returns [ "$fails" = 0 ]).
PY=/usr/bin/python3
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
fails=0
checks=0

fail() {
  echo "FAIL: $*"
  fails=$((fails + 1))
}

# expect_rc WANT CMD... : runs CMD (at most 120 s: a hang fails the check
# instead of the whole suite's time), stdout -> $TMP/out, stderr -> $TMP/err
expect_rc() {
  local want=$1
  shift
  checks=$((checks + 1))
  timeout 120 "$@" >"$TMP/out" 2>"$TMP/err"
  local rc=$?
  if [ "$rc" != "$want" ]; then
    fail "exit $rc (want $want): $*"
    sed 's/^/  stderr: /' "$TMP/err" | head -5
  fi
}

# expect_in FILE TEXT : FILE contains TEXT (fixed string)
expect_in() {
  checks=$((checks + 1))
  grep -qF -- "$2" "$1" || {
    fail "'$2' not in $(basename "$1"):"
    head -5 "$1" | sed 's/^/  /'
  }
}

# json_check PYTHON-EXPR : evaluates EXPR with d = the JSON in $TMP/out (a
# repeated key in any object fails the check: parsers would keep only one)
json_check() {
  checks=$((checks + 1))
  "$PY" -c "
import json, sys, math
def pairs(kv):
    keys = [k for k, _ in kv]
    if len(set(keys)) != len(keys): sys.exit('duplicate JSON key in ' + repr(keys))
    return dict(kv)
d = json.load(open('$TMP/out'), object_pairs_hook=pairs)
sys.exit(0 if ($1) else 1)" || fail "JSON check failed: $1"
}

# expect_err TEXT : the last command's stderr contains TEXT
expect_err() {
  expect_in "$TMP/err" "$1"
}

# check DESCRIPTION TEST... : a shell test that must hold
check() {
  local what=$1
  shift
  checks=$((checks + 1))
  "$@" || fail "$what"
}

# finish NAME : the summary line and the exit status
finish() {
  echo "$1: $checks checks, $fails failed"
  [ "$fails" -eq 0 ]
}
