# cli_lib.sh - the checks of pomlab's shell tests, sourced after POMLAB and
# SRC are set: a temporary folder $TMP (removed on exit), the counters
# $checks and $fails, and expect_rc, expect_in, json_check. A test ends with
#   echo "NAME: $checks checks, $fails failed"; [ "$fails" = 0 ]
PY=/usr/bin/python3
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
fails=0
checks=0

fail() {
  echo "FAIL: $*"
  fails=$((fails + 1))
}

# expect_rc WANT CMD... : runs CMD, stdout -> $TMP/out, stderr -> $TMP/err
expect_rc() {
  local want=$1
  shift
  checks=$((checks + 1))
  "$@" >"$TMP/out" 2>"$TMP/err"
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

