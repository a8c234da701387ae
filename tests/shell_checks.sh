# shell_checks.sh - checks shared by the shell tests (sourced): a temporary
# folder $TMP removed at exit, counters, and the checks below. The sourcing
# script ends with `finish NAME`.
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
