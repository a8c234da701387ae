#!/usr/bin/env bash
# test_export_cli.sh - pomlab export --mjcf without MuJoCo (docs/export.md):
# every shipped and catalog config gives a well-formed MJCF file whose
# bodies, joints, loop closures and motors are those of `pomlab model
# --json` (a hinge, slide or ball per R, P or S joint of the tree, two hinges
# per universal joint, one or two connects per closed loop, one motor per
# actuator with the coil's constant); refusals say why with the right exit
# code, and a failed write leaves nothing behind. test_mjcf (C) loads the
# files with MuJoCo itself when libmujoco-dev is installed.
# Usage: test_export_cli.sh PATH/TO/pomlab SOURCE_DIR
set -u
POMLAB=$1
SRC=$2
. "$(dirname "$0")/cli_lib.sh"
C="$SRC/configs"

for cfg in "$C/3pss.cfg" "$C/3sps.cfg" "$C/3rrr.cfg" "$C"/catalog/*.cfg; do
  stem=$(basename "$cfg" .cfg)
  expect_rc 0 "$POMLAB" export "$cfg" --mjcf "$TMP/$stem.xml"
  expect_in "$TMP/out" "written to $TMP/$stem.xml"
  "$POMLAB" model "$cfg" --json >"$TMP/$stem.json" 2>/dev/null
  checks=$((checks + 1))
  "$PY" - "$TMP/$stem.xml" "$TMP/$stem.json" "$cfg" <<'PYEOF' || fail "$stem: the MJCF model is not the mechanism"
import json, sys, xml.etree.ElementTree as ET
root = ET.parse(sys.argv[1]).getroot()   # well-formed, or this raises
mech = json.load(open(sys.argv[2]))["mechanism"]
cfg = open(sys.argv[3]).read()
bad = []
def want(ok, what):
    if not ok: bad.append(what)
bodies = [b.get("name") for b in root.iter("body")]
names = [b["name"] for b in mech["bodies"][1:]]
want(sorted(n for n in bodies if not n.endswith("_cross")) == sorted(names), "bodies %s" % bodies)
kinds = {"revolute": "hinge", "prismatic": "slide", "spherical": "ball"}
joints = {j.get("name"): j.get("type") for j in root.iter("joint")}
closures = 0
for j in mech["joints"]:
    n, t = j["name"], j["type"]
    if t == "universal" and (n + "_cross") in bodies:
        # closes a loop: its cross turns on body[0] by the hinge n_1, the
        # second hinge is two connects
        want(joints.get(n + "_1") == "hinge", n + "_1 a hinge")
        closures += 1
        want(not j["actuated"], n + " closes a loop")
    elif t == "universal" and (n + "_1") in joints:
        want(joints.get(n + "_1") == "hinge", n + "_1 a hinge")
        want(joints.get(n + "_2") == "hinge", n + "_2 a hinge")
    elif n in joints:
        want(joints[n] == kinds[t], "%s: %s as %s" % (n, t, joints[n]))
    else:
        closures += 1
        want(t != "prismatic" and not j["actuated"], n + " closes a loop")
# a tree over the bodies: one joint set per moving body, the rest close loops
want(closures == len(mech["joints"]) - len(names), "%d closures" % closures)
connects = list(root.iter("connect"))
want(len(connects) >= closures, "%d connects for %d closures" % (len(connects), closures))
motors = list(root.iter("motor"))
acts = [j["name"] for j in mech["joints"] if j["actuated"]]
want(sorted(m.get("joint") for m in motors) == sorted(acts), "motors on %s" % acts)
k = [float(m.get("user").split()[0]) for m in motors]
for key in ("force_constant_N_per_A", "torque_constant_Nm_per_A"):
    for line in cfg.splitlines():
        if line.strip().startswith(key):
            want(all(abs(x - float(line.split("=")[1].split(";")[0])) < 1e-12 for x in k),
                 "coil constant %s" % k)
mass = sum(float(i.get("mass")) for i in root.iter("inertial"))
want(abs(mass - sum(b["mass_kg"] for b in mech["bodies"])) <= 1e-12 * mass, "mass %g" % mass)
if bad:
    print("  " + "; ".join(bad))
sys.exit(1 if bad else 0)
PYEOF
done

# refusals: usage (2), a file that cannot be written (1, nothing left behind)
expect_rc 2 "$POMLAB" export "$C/3pss.cfg"
expect_err "missing --mjcf FILE.xml"
expect_rc 2 "$POMLAB" export "$C/3pss.cfg" --mjcf "$TMP/m.txt"
expect_err "--mjcf must end in .xml"
check "no file for a refused suffix" test ! -e "$TMP/m.txt"
expect_rc 2 "$POMLAB" export "$TMP/none.cfg" --mjcf "$TMP/none.xml"
check "no file for a missing config" test ! -e "$TMP/none.xml"
: >"$TMP/plain"
expect_rc 1 "$POMLAB" export "$C/3pss.cfg" --mjcf "$TMP/plain/m.xml"
expect_err "$TMP/plain/m.xml"
if [ -w /dev/full ]; then
  # /dev/full (a link to it with the suffix): every write fails, reported, exit 1
  ln -s /dev/full "$TMP/full.xml"
  expect_rc 1 "$POMLAB" export "$C/3pss.cfg" --mjcf "$TMP/full.xml"
  expect_err "full.xml"
fi
# an old file survives a failed export untouched
echo old >"$TMP/keep.xml"
expect_rc 2 "$POMLAB" export "$C/3pss.cfg" --mjcf "$TMP/keep.xml" --no-such-option
check "the old file is kept" grep -qx old "$TMP/keep.xml"
check "no temporary file left" sh -c "! ls '$TMP' | grep -q '\.tmp\.'"
finish test_export_cli
