#!/bin/bash
# test_gradient_check.sh POMLAB SOURCE_DIR - `pomlab gradient --check`
# (docs/optimize.md 12.6): the whole-run differences run at a tight
# solver.rtol (the config's, or 1e-10 where it is looser), so that at the
# shipped rtol 1e-6 they check the gradients instead of burying them in the
# runs' integration noise; --check-rtol sets it, checked as solver.rtol is.
POMLAB=$1
SRC=$2
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
fail=0
bad() { echo "FAIL: $*"; fail=1; }

# the shipped 3P-S-S/S at its rtol 1e-6, rigid joints (the gradients' path)
sed 's/^joints = {/joints = {\n  model = "rigid";/' "$SRC/configs/3pss.cfg" > "$TMP/3pss.cfg"
grep -q 'rtol = 1.0e-6;' "$TMP/3pss.cfg" || bad "premise: configs/3pss.cfg no longer says rtol = 1.0e-6"
KEYS=actuator.resistance_ohm,geometry.limb_length,controller.kp
run() { # OUT [ARGS...]
  local out=$1
  shift
  "$POMLAB" gradient "$TMP/3pss.cfg" --params $KEYS --maneuvers 2 --check "$@" > "$out" 2> "$out.err"
}
run "$TMP/d.json" --json || bad "default: exit $?: $(cat "$TMP/d.json.err")"
run "$TMP/l.json" --json --check-rtol 1e-6 || bad "--check-rtol 1e-6: exit $?: $(cat "$TMP/l.json.err")"
run "$TMP/d.txt" || bad "text: exit $?"
grep -q "solver.rtol 1e-10; the gradients at the config's" "$TMP/d.txt" \
  || bad "text: the header does not state the check's rtol: $(sed -n 3p "$TMP/d.txt")"

# worst energy elasticity error |g - c| |p| / E over both maneuvers and keys.
# Measured 3.8e-5 (2026-11-29): the sensitivities at rtol 1e-6 against the
# differences at 1e-10; the bound 2e-4 leaves 5x. At --check-rtol 1e-6 the
# differences carry the runs' noise over the step (measured 5.0e-2): the
# option must reach the runs, so the two checks must differ.
worst() {
  python3 - "$1" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
w = 0.0
for m in d["maneuvers"]:
    for k, g in m["gradient"].items():
        if not k.startswith("energy"):
            continue
        for j, (a, b) in enumerate(zip(g, m["check"][k])):
            if a is not None and b is not None:
                w = max(w, abs(a - b) * abs(d["values"][j]) / abs(m["metrics"][k]))
print("%.3e" % w)
PY
}
# the JSON says how both sides were computed (method, check_method)
methods() { # FILE -> "grad step rtol | grad step rtol"
  python3 - "$1" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
f = lambda m: "%s %g %g" % (m["gradients"], m["rel_step"], m["solver_rtol"])
print(f(d["method"]) + " | " + f(d["check_method"]))
PY
}
md=$(methods "$TMP/d.json")
ml=$(methods "$TMP/l.json")
[ "$md" = "sensitivities 3e-06 1e-06 | whole-run differences 0.001 1e-10" ] \
  || bad "default: method and check_method say '$md'"
[ "$ml" = "sensitivities 3e-06 1e-06 | whole-run differences 0.001 1e-06" ] \
  || bad "--check-rtol 1e-6: method and check_method say '$ml'"

wd=$(worst "$TMP/d.json")
wl=$(worst "$TMP/l.json")
echo "worst energy elasticity error: check at 1e-10 $wd, at 1e-6 $wl"
awk -v w="$wd" 'BEGIN {exit !(w + 0 <= 2e-4)}' || bad "default check: worst energy elasticity error $wd > 2e-4"
awk -v a="$wd" -v b="$wl" 'BEGIN {exit !(b + 0 > 10 * a)}' \
  || bad "--check-rtol 1e-6 changed nothing: $wl against $wd at the default"

# bad values: named, exit 2, as solver.rtol in a file
for v in abc 1e-20 0.5; do
  "$POMLAB" gradient "$TMP/3pss.cfg" --params controller.kp --maneuvers 1 --check --check-rtol "$v" \
    > /dev/null 2> "$TMP/e.err"
  rc=$?
  [ $rc -eq 2 ] && grep -q -- "--check-rtol.*solver.rtol.*$v" "$TMP/e.err" \
    || bad "--check-rtol $v: exit $rc, '$(cat "$TMP/e.err")'"
done
"$POMLAB" gradient "$TMP/3pss.cfg" --params controller.kp --maneuvers 1 --check-rtol 1e-8 \
  > /dev/null 2> "$TMP/e.err"
rc=$?
[ $rc -eq 2 ] && grep -q "only with --check" "$TMP/e.err" || bad "--check-rtol without --check: exit $rc"
exit $fail
