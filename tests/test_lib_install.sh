#!/usr/bin/env bash
# test_lib_install.sh - libpomlab as installed (docs/api.md): `cmake
# --install` into a temporary prefix gives the shared library, the public
# headers (and none of the internal ones), pomlab.pc and the CMake package;
# the library imports no exit/abort and nothing that prints to the standard
# streams; examples/c, configured with find_package(pomlab) against that
# prefix, builds and agrees with the program (IK digit for digit, the
# maneuver's metrics as printed); a program built with pkg-config runs too;
# the Python module imports from the installed tree with PYTHONPATH alone
# and agrees with the program (docs/python.md).
# Usage: test_lib_install.sh PATH/TO/pomlab SOURCE_DIR BUILD_DIR CMAKE
set -u
POMLAB=$1
SRC=$2
BUILD=$3
CMAKE=$4
. "$(dirname "$0")/cli_lib.sh"
P="$TMP/prefix"

expect_rc 0 "$CMAKE" --install "$BUILD" --prefix "$P"
LIB=$(find "$P" -name libpomlab.so | head -1)
checks=$((checks + 1))
[ -n "$LIB" ] || fail "libpomlab.so not installed under $P/lib*"
LIBDIR=$(dirname "${LIB:-$P/lib/x}")
for f in include/pomlab/pom_api.h include/pomlab/pom_config.h include/pomlab/pom_kinematics.h \
  include/pomlab/pom_dynamics.h include/pomlab/pom_rows.h include/pomlab/pom_study.h \
  include/pomlab/pom_stats.h include/pomlab/pom_run.h include/pomlab/pom_explore.h \
  include/pomlab/pom_design.h include/pomlab/pom_pipeline.h; do
  checks=$((checks + 1))
  [ -f "$P/$f" ] || fail "not installed: $f"
done
for f in kin_internal.h dyn_internal.h dyn_ctrl_model.h study_internal.h stats_internal.h \
  run_internal.h pom_doe_mpi.h; do
  checks=$((checks + 1))
  [ ! -e "$P/include/pomlab/$f" ] || fail "internal header installed: $f"
done
for f in pkgconfig/pomlab.pc cmake/pomlab/pomlabConfig.cmake cmake/pomlab/pomlabTargets.cmake; do
  checks=$((checks + 1))
  [ -f "$LIBDIR/$f" ] || fail "not installed: $LIBDIR/$f"
done

# every public header compiles on its own with the installed flags
export PKG_CONFIG_PATH="$LIBDIR/pkgconfig"
CFLAGS=$(pkg-config --cflags pomlab)
for h in "$P"/include/pomlab/pom_*.h; do
  checks=$((checks + 1))
  echo "#include <$(basename "$h")>" >"$TMP/h.c"
  # shellcheck disable=SC2086
  cc -std=c11 -fsyntax-only $CFLAGS "$TMP/h.c" 2>"$TMP/err" ||
    fail "$(basename "$h") does not compile alone: $(head -2 "$TMP/err")"
done

# the library neither ends the process nor writes to the standard streams:
# no such import (it writes only files it was asked for, and the progress
# line to a FILE the caller passes)
checks=$((checks + 1))
bad=$(nm -D --undefined-only "$LIB" |
  grep -E ' (exit|_exit|_Exit|abort|quick_exit|printf|vprintf|puts|putchar|perror|stdout|stderr|__printf_chk|__vprintf_chk|system|popen)(@|$)')
[ -z "$bad" ] || fail "libpomlab imports: $bad"

# the example outside the tree, through find_package(pomlab)
expect_rc 0 "$CMAKE" -S "$SRC/examples/c" -B "$TMP/ex" -DCMAKE_PREFIX_PATH="$P" \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo
expect_rc 0 "$CMAKE" --build "$TMP/ex"
expect_rc 0 "$TMP/ex/pomlab_example" "$SRC/configs/3pss.cfg" 2 -1.5 1 1.5 -2 0.5
cp "$TMP/out" "$TMP/example.txt"
expect_in "$TMP/example.txt" "(3P-S-S/S)"
# IK: the same doubles as `pomlab ik --json` (both %.17g)
expect_rc 0 "$POMLAB" ik "$SRC/configs/3pss.cfg" --euler-zyx 2,-1.5,1 --json
checks=$((checks + 1))
want=$("$PY" -c "import json; d = json.load(open('$TMP/out')); print(' '.join('%.17g' % v for v in d['q']))")
grep -qxF "ik q $want" "$TMP/example.txt" || fail "example IK q differs from pomlab ik: want '$want'"
# the maneuver: the program's metrics, as printed (%.9g both)
expect_rc 0 "$POMLAB" simulate "$SRC/configs/3pss.cfg" --target 1.5,-2,0.5 --json
checks=$((checks + 1))
"$PY" -c "
import json, sys
d = json.load(open('$TMP/out'))
got = {l.split()[1]: l.split()[2] for l in open('$TMP/example.txt') if l.startswith('simulate ') and not l.startswith('simulate target')}
for k in ('execution_time_s', 'energy_total_J', 'steps'):
    want = '%.9g' % d[k] if k != 'steps' else str(d[k])
    if got[k] != want: sys.exit('%s: example %s, pomlab %s' % (k, got[k], want))
" || fail "example maneuver differs from pomlab simulate"

# a program built with pkg-config alone
cat >"$TMP/pc.c" <<'CEOF'
#include <pom_api.h>
#include <stdio.h>
int main(void) {
  const char *name = NULL;
  for (int k = 0; pom_api_arch_type_info(k, &name, NULL, NULL) == POM_OK; ++k) printf("%s\n", name);
  return 0;
}
CEOF
# shellcheck disable=SC2046
expect_rc 0 cc -std=c11 -o "$TMP/pc" "$TMP/pc.c" $(pkg-config --cflags --libs pomlab) -Wl,-rpath,"$LIBDIR"
expect_rc 0 "$TMP/pc"
expect_in "$TMP/out" "3RRR"

# the Python module from the installed tree: one path to set, the library
# found relative to the package (no POMLAB_LIBRARY), run from elsewhere
checks=$((checks + 1))
[ -f "$P/lib/python3/dist-packages/pomlab/__init__.py" ] || fail "pomlab (Python) not installed"
expect_rc 0 env -u POMLAB_LIBRARY PYTHONPATH="$P/lib/python3/dist-packages" sh -c "cd '$TMP' && $PY -c \"import pomlab; print(pomlab.simulate('$SRC/configs/3pss.cfg', target=(1e-3, 2e-3, 3e-3))['execution_time_s'])\""
cp "$TMP/out" "$TMP/py.txt"
expect_rc 0 env PYTHONPATH="$P/lib/python3/dist-packages" $PY -c "import pomlab; print(pomlab.__file__)"
expect_in "$TMP/out" "$P/lib/python3/dist-packages/pomlab/__init__.py"
expect_rc 0 "$POMLAB" simulate "$SRC/configs/3pss.cfg" --target 1,2,3 --json
checks=$((checks + 1))
"$PY" -c "
import json, sys
want = json.load(open('$TMP/out'))['execution_time_s']
got = float(open('$TMP/py.txt').read())
sys.exit(0 if float('%.9g' % got) == want else 'python %r, pomlab %r' % (got, want))
" || fail "the installed Python module and pomlab simulate differ"

echo "test_lib_install: $checks checks, $fails failed"
[ "$fails" = 0 ]
