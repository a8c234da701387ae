"""test_model_json.py - `pomlab model CFG --json` is enough for an outside
tool to rebuild the mechanism (issue 27 item 4): for every shipped
architecture, every body has a mass, a centre of mass and an inertia tensor
about it that a rigid body can have (symmetric, principal moments >= 0 and
obeying the triangle inequality); every joint a known type, two distinct
bodies, a finite point, unit axes where its type has them (a universal
joint's two axes normal), and `actuated` agreeing with the actuator list;
the joints join the ground to the platform through three chains of limb
bodies, each limb body in exactly two joints; every actuator drives a joint
of its kind on a body the joint joins.

usage: test_model_json.py POMLAB SOURCE_DIR"""
import json
import math
import subprocess
import sys

POMLAB, SRC = sys.argv[1], sys.argv[2]
fails = []


def check(cond, what):
    if not cond:
        fails.append(what)


def unit(v):
    return abs(math.sqrt(sum(x * x for x in v)) - 1.0) <= 1e-12


def principal_moments(I):
    """Eigenvalues of a symmetric 3x3 matrix (closed form)."""
    p1 = I[0][1] ** 2 + I[0][2] ** 2 + I[1][2] ** 2
    q = (I[0][0] + I[1][1] + I[2][2]) / 3.0
    if p1 == 0.0:
        return sorted([I[0][0], I[1][1], I[2][2]])
    p2 = sum((I[k][k] - q) ** 2 for k in range(3)) + 2.0 * p1
    p = math.sqrt(p2 / 6.0)
    B = [[(I[r][c] - (q if r == c else 0.0)) / p for c in range(3)] for r in range(3)]
    detB = (B[0][0] * (B[1][1] * B[2][2] - B[1][2] * B[2][1])
            - B[0][1] * (B[1][0] * B[2][2] - B[1][2] * B[2][0])
            + B[0][2] * (B[1][0] * B[2][1] - B[1][1] * B[2][0]))
    r = max(-1.0, min(1.0, detB / 2.0))
    phi = math.acos(r) / 3.0
    e1 = q + 2.0 * p * math.cos(phi)
    e3 = q + 2.0 * p * math.cos(phi + 2.0 * math.pi / 3.0)
    return sorted([e1, 3.0 * q - e1 - e3, e3])


TYPES = {"spherical", "prismatic", "universal", "revolute"}
for cfg in ("3pss.cfg", "3sps.cfg", "3rrr.cfg"):
    out = subprocess.run([POMLAB, "model", f"{SRC}/configs/{cfg}", "--json"],
                         capture_output=True, text=True, check=True).stdout
    m = json.loads(out)["mechanism"]
    bodies, joints, acts = m["bodies"], m["joints"], m["actuators"]
    nb = len(bodies)
    check(bodies[0]["name"] == "ground" and bodies[0]["mass_kg"] == 0.0, f"{cfg}: body 0 ground")
    for b in bodies[1:]:
        I = b["inertia_kgm2"]
        scale = max(abs(I[k][k]) for k in range(3))
        check(b["mass_kg"] > 0.0, f"{cfg}: {b['name']} mass")
        check(all(math.isfinite(x) for x in b["cm_m"]), f"{cfg}: {b['name']} cm")
        check(all(abs(I[r][c] - I[c][r]) <= 1e-15 * scale for r in range(3) for c in range(3)),
              f"{cfg}: {b['name']} inertia symmetric")
        e = principal_moments(I)
        check(e[0] >= -1e-12 * scale and e[2] <= (e[0] + e[1]) * (1 + 1e-9) + 1e-12 * scale,
              f"{cfg}: {b['name']} principal moments {e}")
    degree = [0] * nb
    act_joints = set()
    for j in joints:
        b0, b1 = j["bodies"]
        check(j["type"] in TYPES, f"{cfg}: joint {j['name']} type")
        check(0 <= b0 < nb and 0 <= b1 < nb and b0 != b1, f"{cfg}: joint {j['name']} bodies")
        check(j["body_names"] == [bodies[b0]["name"], bodies[b1]["name"]], f"{cfg}: joint names")
        check(all(math.isfinite(x) for x in j["point_m"]), f"{cfg}: joint {j['name']} point")
        if j["type"] == "spherical":
            check(j["axis"] is None, f"{cfg}: {j['name']} S axis")
        else:
            check(unit(j["axis"]), f"{cfg}: {j['name']} axis unit")
        if j["type"] == "universal":
            a, c = j["axis"], j["axis2"]
            check(unit(c) and abs(sum(x * y for x, y in zip(a, c))) <= 1e-12,
                  f"{cfg}: {j['name']} U axes")
        check(j["actuated"] == (j["actuator"] is not None), f"{cfg}: {j['name']} actuated")
        if j["actuated"]:
            act_joints.add(j["index"])
        degree[b0] += 1
        degree[b1] += 1
    # three chains ground -> limb body -> limb body -> platform
    plat = m["platform"]
    for k in range(nb):
        if k not in (0, plat):
            check(degree[k] == 2, f"{cfg}: limb body {bodies[k]['name']} in {degree[k]} joints")
    limb_joints = [j for j in joints if set(j["bodies"]) != {0, plat}]
    check(len(limb_joints) == 9 and nb == 8, f"{cfg}: 3 limbs of 3 joints and 2 bodies")
    for start in (j for j in limb_joints if 0 in j["bodies"]):
        body, seen, steps = [b for b in start["bodies"] if b != 0][0], {start["index"]}, 1
        while body != plat and steps < 4:
            nxt = [j for j in limb_joints if body in j["bodies"] and j["index"] not in seen]
            check(len(nxt) == 1, f"{cfg}: chain from {start['name']}")
            if len(nxt) != 1:
                break
            seen.add(nxt[0]["index"])
            body = [b for b in nxt[0]["bodies"] if b != body][0]
            steps += 1
        check(body == plat and steps == 3, f"{cfg}: chain from {start['name']} reaches the platform")
    check(len(acts) == 3 and {a["joint"] for a in acts} == act_joints, f"{cfg}: actuators")
    for a in acts:
        j = joints[a["joint"]]
        check(j["type"] == a["kind"] and a["moving_body"] in j["bodies"], f"{cfg}: actuator {a}")

for f in fails:
    print("FAIL", f)
print(f"test_model_json: {len(fails)} failed")
sys.exit(1 if fails else 0)
