#!/usr/bin/env python3
"""Home-pose check of every architecture in docs/catalog.md.

For each catalog entry this script builds the home joint points and axes
from the entry's design parameters (the formulas of docs/catalog.md), then
computes the home Jacobian q_dot = J omega by screw theory, independently of
any closed form:

  limb i: sum_k x_k $_k = $_platform = (omega, 0)      (twists about O)

solved by the pseudo-inverse of the limb's 6 x n twist matrix. It reports,
per architecture:

  * the residual of that solve (0 = the limb lets the platform turn about O),
  * whether the actuated rate is unique (Type-1 check: the null space of the
    limb's twist matrix has no actuated component),
  * for limbs with 5 joint freedoms and no central joint: the constraint
    wrench (must be a pure force through O) and the determinant of the three
    unit constraint forces (0 = constraint singularity),
  * J, its singular values, its condition number, and where a closed form
    exists (3-RRR, P-S-S, U-P-S, R-S-S, U-P-U) the largest difference between
    J and the closed form.

Pure Python (no numpy). Run: python3 scripts/catalog_home.py [--points | --check]
(--check: exit status 1 if a figure of docs/catalog.md no longer holds).
"""

import math
import sys

DEG = math.pi / 180.0


# ---- small linear algebra ------------------------------------------------------


def add(a, b):
    return [x + y for x, y in zip(a, b)]


def sub(a, b):
    return [x - y for x, y in zip(a, b)]


def scl(s, a):
    return [s * x for x in a]


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def norm(a):
    return math.sqrt(dot(a, a))


def unit(a):
    n = norm(a)
    if n == 0.0:
        raise ValueError("zero vector")
    return scl(1.0 / n, a)


def transpose(m):
    return [list(r) for r in zip(*m)]


def matmul(a, b):
    bt = transpose(b)
    return [[dot(r, c) for c in bt] for r in a]


def jacobi_eig(a):
    """Eigenvalues and eigenvectors (columns) of a symmetric matrix."""
    n = len(a)
    a = [row[:] for row in a]
    v = [[1.0 if i == j else 0.0 for j in range(n)] for i in range(n)]
    for _ in range(100):
        off = sum(a[i][j] ** 2 for i in range(n) for j in range(n) if i != j)
        if off < 1e-30 * max(1e-300, sum(a[i][i] ** 2 for i in range(n))):
            break
        for p in range(n):
            for q in range(p + 1, n):
                if abs(a[p][q]) < 1e-300:
                    continue
                th = (a[q][q] - a[p][p]) / (2.0 * a[p][q])
                t = (1.0 if th >= 0 else -1.0) / (abs(th) + math.sqrt(th * th + 1.0))
                c = 1.0 / math.sqrt(t * t + 1.0)
                s = t * c
                for k in range(n):
                    akp, akq = a[k][p], a[k][q]
                    a[k][p] = c * akp - s * akq
                    a[k][q] = s * akp + c * akq
                for k in range(n):
                    apk, aqk = a[p][k], a[q][k]
                    a[p][k] = c * apk - s * aqk
                    a[q][k] = s * apk + c * aqk
                for k in range(n):
                    vkp, vkq = v[k][p], v[k][q]
                    v[k][p] = c * vkp - s * vkq
                    v[k][q] = s * vkp + c * vkq
    return [a[i][i] for i in range(n)], v


def singular_values(m):
    lam, _ = jacobi_eig(matmul(transpose(m), m))
    return sorted((math.sqrt(max(0.0, x)) for x in lam), reverse=True)


def det3(m):
    return dot(m[0], cross(m[1], m[2]))


# ---- frames and directions (docs/catalog.md section 1) ------------------------------

EZ = [0.0, 0.0, 1.0]


def e_r(eta):
    return [math.cos(eta), math.sin(eta), 0.0]


def e_t(eta):
    return [-math.sin(eta), math.cos(eta), 0.0]


def ldir(lam, alp, eta):
    """Unit direction with lean lam from +z, azimuth alp from e_r toward e_t."""
    h = add(scl(math.cos(alp), e_r(eta)), scl(math.sin(alp), e_t(eta)))
    return add(scl(math.sin(lam), h), scl(math.cos(lam), EZ))


def sph_elbow(u, v, a1, a2, elbow):
    """Elbow axis w with u.w = cos a1, w.v = cos a2 (docs/kinematics-3rrr.md s.1)."""
    k = dot(u, v)
    s2 = 1.0 - k * k
    a = (math.cos(a1) - k * math.cos(a2)) / s2
    b = (math.cos(a2) - k * math.cos(a1)) / s2
    c2 = (1.0 - a * a - b * b - 2.0 * a * b * k) / s2
    if c2 < 0.0:
        raise ValueError("3-RRR triangle cannot close")
    return add(add(scl(a, u), scl(b, v)), scl(elbow * math.sqrt(c2), cross(u, v)))


# ---- joints as twists -----------------------------------------------------------------
# A joint is (type, point, axes, actuated); a revolute axis u through p gives the
# twist (u, p x u) about O; a prismatic joint along e gives (0, e).


def joint_twists(joint):
    kind, p, axes, act = joint
    out = []
    if kind == "P":
        out.append(([0.0, 0.0, 0.0], unit(axes[0])))
    else:
        for a in axes:
            a = unit(a)
            out.append((a, cross(p, a)))
    return [(w, v, act and i == 0) for i, (w, v) in enumerate(out)]


S_AXES = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]


def limb_solve(joints, omega):
    tw = [t for j in joints for t in joint_twists(j)]
    cols = [w + v for (w, v, _) in tw]  # 6-vectors (omega; v_O)
    act = [k for k, (_, _, a) in enumerate(tw) if a]
    assert len(act) == 1
    T = transpose(cols)  # 6 x n
    target = omega + [0.0, 0.0, 0.0]
    TtT = matmul(transpose(T), T)
    lam, V = jacobi_eig(TtT)
    lmax = max(lam)
    n = len(cols)
    rhs = [dot(c, target) for c in cols]
    x = [0.0] * n
    null = []
    for k in range(n):
        vk = [V[r][k] for r in range(n)]
        if lam[k] > 1e-12 * lmax:
            coef = dot(vk, rhs) / lam[k]
            x = add(x, scl(coef, vk))
        else:
            null.append(vk)
    res = sub([sum(T[r][k] * x[k] for k in range(n)) for r in range(6)], target)
    null_act = max([abs(vk[act[0]]) for vk in null] + [0.0])
    return x[act[0]], norm(res), null_act, cols


def constraint_wrenches(cols):
    """Wrenches (f, m_O) reciprocal to every twist column: f.v + m.omega = 0."""
    rows = [c[3:] + c[:3] for c in cols]  # unknown (f, m): row (v, omega)
    M = matmul(transpose(rows), rows)
    lam, V = jacobi_eig(M)
    lmax = max(lam)
    return [[V[r][k] for r in range(6)] for k in range(6) if lam[k] < 1e-12 * lmax]


def analyse(arch):
    J = []
    worst_res = 0.0
    worst_null = 0.0
    cons = []
    for joints in arch["limbs"]:
        row = []
        for k in range(3):
            om = [1.0 if i == k else 0.0 for i in range(3)]
            qd, res, nact, cols = limb_solve(joints, om)
            row.append(qd)
            worst_res = max(worst_res, res)
            worst_null = max(worst_null, nact)
        J.append(row)
        if not arch.get("central_S", False):
            cons.append(constraint_wrenches(cols))
    sv = singular_values(J)
    out = {"J": J, "sv": sv, "cond": sv[0] / sv[-1], "res": worst_res, "null_act": worst_null}
    if cons:
        # every limb wrench (f, m_O) reciprocal to all its joint twists; with no central
        # joint these must be pure forces through O (m = 0) spanning 3 directions
        forces = []
        mom = 0.0
        for c in cons:
            for wr in c:
                f, m = wr[:3], wr[3:]
                mom = max(mom, norm(m) / max(norm(f), 1e-300))
                forces.append(unit(f))
        out["constraint_moment_over_force"] = mom
        out["constraint_count"] = [len(c) for c in cons]
        out["constraint_smin"] = singular_values(forces)[2] if len(forces) >= 3 else 0.0
    if "closed" in arch:
        Jc = arch["closed"]
        out["closed_diff"] = max(abs(J[i][k] - Jc[i][k]) for i in range(3) for k in range(3))
    return out


# ---- the catalog -------------------------------------------------------------------

ETA1 = 90.0 * DEG


def etas(eta1=ETA1):
    return [eta1 + i * 120.0 * DEG for i in range(3)]


def rrr(a1, a2, b, g, t, elbow, rad):
    """3-RRR: u from -z at cone b, v from +z at cone g, twist t (kinematics-3rrr.md)."""
    limbs, closed, pts = [], [], []
    for eta in etas():
        u = sub(scl(math.sin(b), e_r(eta)), scl(math.cos(b), EZ))
        v = add(scl(math.sin(g), e_r(eta + t)), scl(math.cos(g), EZ))
        w = sph_elbow(u, v, a1, a2, elbow)
        limbs.append(
            [("R", scl(rad, u), [u], True), ("R", scl(rad, w), [w], False), ("R", scl(rad, v), [v], False)]
        )
        closed.append(scl(1.0 / dot(cross(u, w), v), cross(w, v)))
        pts.append({"u": u, "w": w, "v": v})
    # IK branch (kinematics-3rrr.md s.2): theta = phi + s acos(-C/rho), home root s = -sign(phi)
    u, w, v = pts[0]["u"], pts[0]["w"], pts[0]["v"]
    A = dot(w, v) - dot(u, w) * dot(u, v)
    Bq = dot(cross(u, w), v)
    phi = math.atan2(Bq, A)
    branch = "theta = phi + s acos(-C/rho): phi = %.4f deg, home branch s = %+d" % (phi / DEG, -1 if phi > 0 else 1)
    return {"limbs": limbs, "closed": closed, "pts": pts, "branch": branch}


def pss(r, h, L, lam, alp, gam, dlt):
    limbs, closed, pts = [], [], []
    for eta in etas():
        C = add(scl(r, e_r(eta)), scl(h * r, EZ))
        s = ldir(lam, alp, eta)
        B = sub(C, scl(L, s))
        d = ldir(gam, dlt, eta)
        limbs.append([("P", B, [d], True), ("S", B, S_AXES, False), ("S", C, S_AXES, False)])
        closed.append(scl(1.0 / dot(s, d), cross(C, s)))
        pts.append({"B": B, "C": C, "d": d, "s": s})
    ls = dot(pts[0]["s"], pts[0]["d"])
    branch = "q = d.u - s sqrt(disc): branch s = sign(l.u) = %+d, l.u = %.4f (0 = the roots meet)" % (
        1 if ls > 0 else -1, ls)
    return {"limbs": limbs, "closed": closed, "central_S": True, "pts": pts, "branch": branch}


def ups(r, h, L0, lam, alp):
    limbs, closed, pts = [], [], []
    for eta in etas():
        Bp = add(scl(r, e_r(eta)), scl(h * r, EZ))
        s = ldir(lam, alp, eta)
        A = sub(Bp, scl(L0, s))
        a1 = unit(cross(EZ, s))
        a2 = cross(s, a1)
        limbs.append([("U", A, [a1, a2], False), ("P", A, [s], True), ("S", Bp, S_AXES, False)])
        closed.append(cross(Bp, s))
        pts.append({"A": A, "B": Bp, "a1": a1, "s": s})
    branch = "q = |R B - A| - L0: unique"
    return {"limbs": limbs, "closed": closed, "central_S": True, "pts": pts, "branch": branch}


def rss(r, h, L, lam, alp, rho, crank):
    limbs, closed, pts = [], [], []
    for eta in etas():
        C = add(scl(r, e_r(eta)), scl(h * r, EZ))
        s = ldir(lam, alp, eta)
        B = sub(C, scl(L, s))
        if crank == "tangential":  # axis e_r, arm along e_t: tip moves along e_z
            k, arm = e_r(eta), scl(rho, e_t(eta))
        else:  # radial crank: axis e_t, arm along -e_r (pivot outside the tip)
            k, arm = e_t(eta), scl(-rho, e_r(eta))
        A = sub(B, arm)
        limbs.append([("R", A, [k], True), ("S", B, S_AXES, False), ("S", C, S_AXES, False)])
        closed.append(scl(1.0 / dot(s, cross(k, arm)), cross(C, s)))
        pts.append({"A": A, "B": B, "C": C, "k": k, "arm": arm})
    p0 = pts[0]
    e1, e2 = p0["arm"], cross(p0["k"], p0["arm"])
    AC = sub(p0["A"], p0["C"])
    P, Q = dot(AC, e1), dot(AC, e2)
    phi = math.atan2(Q, P)
    branch = ("P cos th + Q sin th = W, th = phi + s acos(W/hypot(P,Q)): phi = %.4f deg, home branch s = %+d"
              % (phi / DEG, -1 if phi > 0 else 1))
    return {"limbs": limbs, "closed": closed, "central_S": True, "pts": pts, "branch": branch}


def ruu(a1, a2, b, g, t, elbow, rho_a, rho_b, rho_c):
    """3-RUU: R axis u through O; U at B = rho_b w (axes w, d); U at C = rho_c v (axes d, v);
    d = unit(w x v): the two intermediate axes parallel, the others through O."""
    limbs, pts, closed = [], [], []
    for eta in etas():
        u = sub(scl(math.sin(b), e_r(eta)), scl(math.cos(b), EZ))
        v = add(scl(math.sin(g), e_r(eta + t)), scl(math.cos(g), EZ))
        w = sph_elbow(u, v, a1, a2, elbow)
        d = unit(cross(w, v))
        B, C = scl(rho_b, w), scl(rho_c, v)
        limbs.append([("R", scl(rho_a, u), [u], True), ("U", B, [w, d], False), ("U", C, [d, v], False)])
        pts.append({"u": u, "w": w, "v": v, "d": d, "B": B, "C": C})
        closed.append(scl(1.0 / dot(cross(u, w), v), cross(w, v)))
    branch = "|B(theta) - R C| = const <=> w(theta).(R v0) = cos a2: the 3-RRR branch of the same u, w, v"
    return {"limbs": limbs, "pts": pts, "branch": branch, "closed": closed,
            "ruu": (a2, rho_a, rho_b, rho_c)}


def upu(r, h, L0, lam, alp):
    """3-UPU: base U at A with axes (unit A, n), P along s, platform U at C with axes (n, unit C);
    n = unit(A x C), the normal of the plane O A C."""
    limbs, closed, pts = [], [], []
    for eta in etas():
        C = add(scl(r, e_r(eta)), scl(h * r, EZ))
        s = ldir(lam, alp, eta)
        A = sub(C, scl(L0, s))
        n = unit(cross(A, C))
        limbs.append([("U", A, [unit(A), n], False), ("P", A, [s], True), ("U", C, [n, unit(C)], False)])
        closed.append(cross(C, s))
        pts.append({"A": A, "C": C, "n": n, "s": s})
    branch = "q = |R C - A| - L0: unique"
    return {"limbs": limbs, "closed": closed, "pts": pts, "branch": branch, "upu": True}


def rot(axis_angle):
    """Rotation matrix exp([r]x) (Rodrigues)."""
    th = norm(axis_angle)
    k = unit(axis_angle)
    K = [[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]]
    K2 = matmul(K, K)
    return [[(1.0 if i == j else 0.0) + math.sin(th) * K[i][j] + (1.0 - math.cos(th)) * K2[i][j]
             for j in range(3)] for i in range(3)]


def mv(m, x):
    return [dot(r, x) for r in m]


def rotate_about(u, th, x):
    return add(add(scl(math.cos(th), x), scl(math.sin(th), cross(u, x))), scl((1.0 - math.cos(th)) * dot(u, x), u))


def off_home(arch, rvec):
    """3-RUU / 3-UPU away from home: rebuild the joint axes at the rotated pose (limb IK of
    docs/catalog.md), check the limbs still let the platform turn about O and that every
    constraint wrench is still a pure force through O (full-cycle mobility, not only at home)."""
    Rm = rot(rvec)
    limbs, closed = [], []
    for p in arch["pts"]:
        if "ruu" in arch:
            a2, rho_a, rho_b, rho_c = arch["ruu"]
            u, w0, v = p["u"], p["w"], mv(Rm, p["v"])
            A = dot(w0, v) - dot(u, w0) * dot(u, v)
            Bq = dot(cross(u, w0), v)
            Cq = dot(u, w0) * dot(u, v) - math.cos(a2)
            phi = math.atan2(Bq, A)
            s = -1.0 if math.atan2(dot(cross(u, w0), p["v"]), dot(w0, p["v"]) - dot(u, w0) * dot(u, p["v"])) > 0 else 1.0
            th = phi + s * math.acos(-Cq / math.hypot(A, Bq))
            w = rotate_about(u, th, w0)
            d = unit(cross(w, v))
            B, C = scl(rho_b, w), scl(rho_c, v)
            limbs.append([("R", scl(rho_a, u), [u], True), ("U", B, [w, d], False), ("U", C, [d, v], False)])
            closed.append(scl(1.0 / dot(cross(u, w), v), cross(w, v)))  # the 3-RRR row
        else:
            A, C = p["A"], mv(Rm, p["C"])
            s = unit(sub(C, A))
            n = unit(cross(A, C))
            limbs.append([("U", A, [unit(A), n], False), ("P", A, [s], True), ("U", C, [n, unit(C)], False)])
            closed.append(cross(C, s))  # the 3-S-P-S row
    r = analyse({"limbs": limbs, "closed": closed})
    return r


def catalog():
    AGILE = math.atan(math.sqrt(2.0))
    ISO_PSS_LAM, ISO_PSS_ALP = 38.55029818734936 * DEG, 62.54273588016925 * DEG
    TAN_LAM = math.atan(1.0 / math.sqrt(2.0))  # 35.2644 deg
    mm = 1e-3
    c = {}
    c["C01 3-PSS/S reference (configs/3pss.cfg)"] = pss(
        12.24744871391589 * mm, 0.0, 40.0 * mm, ISO_PSS_LAM, ISO_PSS_ALP, 0.0, 0.0
    )
    c["C02 3-UPS/S reference (configs/3sps.cfg)"] = ups(15.0 * mm, 0.0, 110.0 * mm, TAN_LAM, 90.0 * DEG)
    c["C03 3-RRR Agile Eye (configs/3rrr.cfg)"] = rrr(
        90 * DEG, 90 * DEG, AGILE, AGILE, 60 * DEG, 1, 30.0 * mm
    )
    c["C04 3-RRR general, non-orthogonal"] = rrr(
        60 * DEG, 75 * DEG, 55 * DEG, 40 * DEG, 60 * DEG, 1, 30.0 * mm
    )
    c["C05 3-RRR coaxial"] = rrr(45 * DEG, 90 * DEG, 0.0, 70 * DEG, 0.0, 1, 30.0 * mm)
    c["C06 Orbita 3D (coaxial 3-RRR)"] = rrr(54 * DEG, 90 * DEG, 0.0, 90 * DEG, 0.0, 1, 30.0 * mm)
    c["C07 3-RRR congruent"] = rrr(75 * DEG, 75 * DEG, 40 * DEG, 40 * DEG, 60 * DEG, 1, 30.0 * mm)
    c["C08 3-RSS/S tangential crank"] = rss(
        12.24744871391589 * mm, 0.0, 40.0 * mm, ISO_PSS_LAM, ISO_PSS_ALP, 15.0 * mm, "tangential"
    )
    c["C09 3-RSS/S radial crank"] = rss(
        12.24744871391589 * mm, 0.0, 40.0 * mm, TAN_LAM, 90.0 * DEG, 15.0 * mm, "radial"
    )
    c["C10 3-UPS/S stool (Valayil-Tanev type)"] = ups(15.0 * mm, 0.0, 60.0 * mm, 30.0 * DEG, 120.0 * DEG)
    c["C11 3-PSS/S inclined sliders (TUM type)"] = pss(
        12.24744871391589 * mm, 0.0, 40.0 * mm, ISO_PSS_LAM, ISO_PSS_ALP, 30.0 * DEG, 0.0
    )
    c["C12 3-PSS/S flat, tangential sliders"] = pss(
        15.0 / math.sqrt(3.0) * mm, 0.0, 40.0 * mm, TAN_LAM, 90.0 * DEG, 90.0 * DEG, 90.0 * DEG
    )
    c["C13 3-RUU wrist (no central joint)"] = ruu(
        90 * DEG, 90 * DEG, AGILE, AGILE, 60 * DEG, 1, 30.0 * mm, 25.0 * mm, 15.0 * mm
    )
    c["C14 3-UPU wrist (no central joint)"] = upu(15.0 * mm, 0.0, 110.0 * mm, TAN_LAM, 90.0 * DEG)
    return c


def fmt(v, s=1e3):
    return "(" + ", ".join("%.4f" % (s * x) for x in v) + ")"


# Expected home condition numbers. Analytic where docs/catalog.md derives one
# (isotropic designs: 1; Orbita: sqrt(2) tan(alpha); C10: s_z sqrt(1.5) / (s_t sqrt(3))),
# else the value documented in docs/catalog.md (a regression guard only).
EXPECTED_COND = {
    "C01": 1.0, "C02": 1.0, "C03": 1.0, "C04": 1.149599, "C05": 1.114275,
    "C06": math.sqrt(2.0) * math.tan(54.0 * DEG), "C07": 1.132866, "C08": 1.0, "C09": 1.0,
    "C10": math.cos(30 * DEG) * math.sqrt(1.5) / (math.sin(30 * DEG) * math.sin(120 * DEG) * math.sqrt(3.0)),
    "C11": 1.0, "C12": 1.0, "C13": 1.0, "C14": 1.0,
}


def check():
    """Exit status 1 if a figure of docs/catalog.md no longer holds."""
    bad = []
    for name, arch in catalog().items():
        key = name.split()[0]
        r = analyse(arch)
        # 1e-6: the documented values carry 7 significant digits; analytic ones agree to ~1e-12
        if abs(r["cond"] - EXPECTED_COND[key]) > 1e-6:
            bad.append("%s: cond %.9f, expected %.9f" % (key, r["cond"], EXPECTED_COND[key]))
        # the limb solves are exact up to rounding: J entries are O(1) (rad/rad) or O(1e-2)
        # (m/rad), the pseudo-inverse keeps eigenvalues above 1e-12 of the largest
        if r["res"] > 1e-10:
            bad.append("%s: limb residual %.1e" % (key, r["res"]))
        if r["null_act"] > 1e-9:
            bad.append("%s: actuated rate not unique (%.1e)" % (key, r["null_act"]))
        if "closed_diff" in r and r["closed_diff"] > 1e-10:
            bad.append("%s: J differs from its closed form by %.1e" % (key, r["closed_diff"]))
        if "constraint_moment_over_force" in r:
            if r["constraint_moment_over_force"] > 1e-12:
                bad.append("%s: a constraint wrench is not a force through O" % key)
            if r["constraint_smin"] < 0.5:
                bad.append("%s: constraint forces nearly dependent (%.3f)" % (key, r["constraint_smin"]))
        if "ruu" in arch or "upu" in arch:
            ro = off_home(arch, [0.25, -0.15, 0.2])
            if ro["res"] > 1e-10 or ro["constraint_moment_over_force"] > 1e-12 or ro["closed_diff"] > 1e-10:
                bad.append("%s: off-home spherical-mobility check failed" % key)
    for b in bad:
        print("FAIL " + b)
    print("catalog_home: %d failure(s)" % len(bad))
    return 1 if bad else 0


def main():
    if "--check" in sys.argv:
        sys.exit(check())
    show_points = "--points" in sys.argv
    print("%-44s %9s %9s %9s %8s %9s %9s %9s %9s" % (
        "architecture", "sv_max", "sv_min", "cond", "resid", "null_act", "closed", "cons_m/f", "cons_smin"))
    for name, arch in catalog().items():
        r = analyse(arch)
        lin = any(j[0] == "P" for j in arch["limbs"][0] if j[3])
        unitsc = 1e3 if lin else 1.0  # m/rad shown as mm/rad
        print("%-44s %9.4f %9.4f %9.6f %8.1e %9.1e %9s %9s %9s" % (
            name, unitsc * r["sv"][0], unitsc * r["sv"][-1], r["cond"], r["res"], r["null_act"],
            "%.1e" % r["closed_diff"] if "closed_diff" in r else "-",
            "%.1e" % r["constraint_moment_over_force"] if "constraint_moment_over_force" in r else "-",
            "%.4f" % r["constraint_smin"] if "constraint_smin" in r else "-"))
        print("    home IK: " + arch["branch"] + ("; limb constraint wrenches %s" % r["constraint_count"]
                                                  if "constraint_count" in r else ""))
        if "ruu" in arch or "upu" in arch:
            ro = off_home(arch, [0.25, -0.15, 0.2])
            print("    off home (rotation vector (0.25, -0.15, 0.2) rad): resid %.1e, constraint m/f %.1e, "
                  "constraint smin %.4f, cond %.4f, |J - J_closed| %.1e" % (
                      ro["res"], ro["constraint_moment_over_force"], ro["constraint_smin"], ro["cond"],
                      ro["closed_diff"]))
        if show_points:
            for i, p in enumerate(arch["pts"]):
                print("    limb %d: " % (i + 1) + "; ".join(
                    "%s=%s" % (k, fmt(v, 1e3 if k in "ABC" else 1.0)) for k, v in p.items()))
            print("    J rows: " + "; ".join(fmt(row, unitsc) for row in r["J"]))


if __name__ == "__main__":
    main()
