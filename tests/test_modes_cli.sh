#!/usr/bin/env bash
# test_modes_cli.sh - `pomlab ik --all` and `pomlab fk --all`
# (docs/kinematics-modes.md): the Agile Eye's 8 working modes (the other
# root of each leg 180 deg away, the home mode equal to plain `ik`) and 4
# assembly modes (each reproducing q on its own working mode), a single-root
# architecture, the options' checks, and Orbita's arm-angle limit in the
# report (docs/architecture-files.md 2.6).
POMLAB=$1
SRC=$2
. "$SRC/tests/cli_lib.sh"

EYE="$SRC/configs/3rrr.cfg"
expect_rc 0 "$POMLAB" ik "$EYE" --euler-zyx 10,20,-15 --json
cp "$TMP/out" "$TMP/plain.json"
expect_rc 0 "$POMLAB" ik "$EYE" --euler-zyx 10,20,-15 --all
expect_in "$TMP/out" "working modes: 8 (two IK roots on limbs 1, 2, 3"
expect_rc 0 "$POMLAB" ik "$EYE" --euler-zyx 10,20,-15 --all --json
json_check 'd["kind"] == "working_modes" and d["count"] == 8 and d["working_modes"] == 8'
json_check 'all(m["reachable"] and not m["parallel_singular"] and m["serial_singular_limbs"] == [] for m in d["modes"])'
# the other root of every leg is 180 deg from the home one (u . w0 = 0)
json_check 'all(abs(abs(math.remainder(m["q"][i] - d["modes"][0]["q"][i], 2 * math.pi)) - (0 if m["branch"][i] == 1 else math.pi)) < 1e-12 for m in d["modes"] for i in range(3))'
checks=$((checks + 1))
$PY - "$TMP/plain.json" "$TMP/out" <<'PYEOF' || fail "ik --all: mode 1 is not plain ik's pose"
import json, sys
a, b = (json.load(open(f)) for f in sys.argv[1:3])
m = b["modes"][0]
ok = m["branch"] == [1, 1, 1] and all(abs(x - y) <= 1e-15 for x, y in zip(a["q"], m["q"]))
ok &= abs(a["kappa"] - m["kappa"]) <= 1e-12 * a["kappa"]
sys.exit(0 if ok else 1)
PYEOF

# the serial bit in ik's report (docs/kinematics-tables.md 3.2): the tilt
# about the horizontal axis at azimuth 30 deg, 1e-6 rad short of the curve
# Gamma_1^- (v_1 = -u_1, docs/kinematics-modes.md 6.2): leg 1's transmission
# |u_1 x v_1| ~ 1e-6, named in text, JSON and every working mode; 1e-2 rad
# short, none (the range limit of limb 2 is exceeded: exit 1)
NEAR=36.5867435687024,29.3338808234636,103.262610719353
FAR=36.2664018405679,29.3980062462588,102.609371923316
expect_rc 1 "$POMLAB" ik "$EYE" --euler-zyx $NEAR
expect_in "$TMP/out" "singularity: serial (limb 1), parallel"
expect_rc 1 "$POMLAB" ik "$EYE" --euler-zyx $NEAR --json
json_check 'd["singularities"] == ["serial", "parallel"] and d["serial_limbs"] == [1] and 5e-7 < d["transmission"][0] < 2e-6 and min(d["transmission"][1:]) > 0.5'
expect_rc 1 "$POMLAB" ik "$EYE" --euler-zyx $NEAR --all --json
json_check 'd["count"] == 8 and all(m["serial_singular_limbs"] == [1] and m["serial_limbs"] == [1] for m in d["modes"])'
expect_rc 1 "$POMLAB" ik "$EYE" --euler-zyx $FAR --json
json_check 'd["singularities"] == [] and d["serial_limbs"] == [] and 5e-3 < d["transmission"][0] < 2e-2'

# 4 assembly modes at a generic input; the stroke (+-30 deg) is exceeded by
# the inputs' own q2, q3: exit 1, the report still printed
expect_rc 1 "$POMLAB" fk "$EYE" --q 20,-35,50 --all --json
json_check 'd["kind"] == "assembly_modes" and d["count"] == 4 and d["working_modes"] == 8'
json_check 'all(abs(m["q"][i] - d["q_target"][i]) < 1e-11 and m["residual"] <= 1e-12 for m in d["modes"] for i in range(3))'
json_check 'len(set(tuple(m["branch"]) for m in d["modes"])) == 4'
json_check 'all(abs(abs(m["det_unit_rows"]) - abs(d["modes"][0]["det_unit_rows"])) < 1e-9 for m in d["modes"])'
expect_rc 0 "$POMLAB" fk "$EYE" --q 5,-3,8 --all
expect_in "$TMP/out" "assembly modes: 4 (damped Newton from 128 starts on each of the 8 working modes"
expect_rc 0 "$POMLAB" fk "$EYE" --q 5,-3,8 --all --seeds 16
expect_in "$TMP/out" "from 16 starts"

# the solution plain fk reaches from home is one of the modes
expect_rc 0 "$POMLAB" fk "$SRC/configs/3pss.cfg" --q 1,2,-1 --json
cp "$TMP/out" "$TMP/plain.json"
expect_rc 0 "$POMLAB" fk "$SRC/configs/3pss.cfg" --q 1,2,-1 --all --json
checks=$((checks + 1))
$PY - "$TMP/plain.json" "$TMP/out" <<'PYEOF' || fail "fk --all lacks plain fk's solution"
import json, sys
a, b = (json.load(open(f)) for f in sys.argv[1:3])
R = a["rotation"]
hit = [m for m in b["modes"]
       if max(abs(x - y) for r, t in zip(R, m["rotation"]) for x, y in zip(r, t)) < 1e-9]
sys.exit(0 if len(hit) == 1 and hit[0]["mode"] == 1 else 1)
PYEOF
# a single-root architecture: one working mode
expect_rc 0 "$POMLAB" fk "$SRC/configs/3sps.cfg" --q 1,2,-1 --all
expect_in "$TMP/out" "one IK root per limb: branch 1"
expect_rc 0 "$POMLAB" ik "$SRC/configs/3sps.cfg" --euler-zyx 3,2,1 --all --json
json_check 'd["count"] == 1 and d["modes"][0]["branch"] == [0, 0, 0]'

# options
expect_rc 2 "$POMLAB" fk "$EYE" --q 5,-3,8 --seeds 16
expect_err "--seeds 16: only with --all"
expect_rc 2 "$POMLAB" fk "$EYE" --q 5,-3,8 --all --seeds 0
expect_err "--seeds"

# Orbita: the arm-angle limit in the report (120 + q2 - q3 = 33.04 deg < 40)
ORB="$SRC/configs/catalog/orbita3d.cfg"
expect_rc 1 "$POMLAB" ik "$ORB" --euler-zyx 0,45,0 --json
json_check '"arm angle min limbs 2-3" in d["violations"] and "arm angle max limbs 2-3" not in d["violations"]'
json_check 'all(abs(math.radians(d["arm_angle_deg"][i]) - (math.radians(120) + d["q"][i] - d["q"][(i + 1) % 3]) % (2 * math.pi)) < 1e-9 for i in range(3))'
expect_rc 0 "$POMLAB" ik "$ORB" --euler-zyx 10,5,0
expect_in "$TMP/out" "arm angle max  <=      175 deg"
finish test_modes_cli
