#!/usr/bin/env python3
"""The Agile Eye's singular set in tilt-and-torsion angles, as an SVG
(docs/kinematics-modes.md section 6, docs/agile-eye-singularities.svg).

usage: agile_eye_singularities.py [--csv POINTS.csv] [-o OUT.svg]

Draws the six curves of the closed form (R = Rz(phi) Ry(theta) Rz(sigma -
phi), base axes u_k at azimuth p_k = 90, 210, 330 deg as configs/3rrr.cfg):

  v_k = +u_k: sigma = -60 deg, cot(theta/2) = sqrt2 cos(phi - p_k)
  v_k = -u_k: sigma = 2 phi - 2 p_k - 60 deg, tan(theta/2) = -sqrt2 cos(phi - p_k)

in two projections, (phi, theta) and (phi, sigma), with the 4 points where
they cross. With --csv (written by `build/tests/test_agile_sing --csv F`),
the points pomlab's kinematics found (grid sweep + Newton) and the curves it
traced by continuation are drawn over them: they are computed from pomlab's
Jacobian, the lines from the closed form. Standard library only.
"""
import math
import sys

P = [90.0, 210.0, 330.0]  # azimuths of u_1, u_2, u_3 (deg)
COLORS = ["#1f77b4", "#d62728", "#2ca02c"]
W, H = 460, 300  # one panel
ML, MR, MT, MB = 56, 16, 34, 44


def wrap(a):
    """angle (deg) in (-180, 180]"""
    a = math.fmod(a + 180.0, 360.0)
    if a <= 0.0:
        a += 360.0
    return a - 180.0


def curve(k, eps, n=721):
    """closed-form points (phi, theta, sigma) in deg of the curve v_k = eps u_k"""
    pts = []
    for i in range(1, n):
        x = -90.0 + 180.0 * i / n  # phi - p_k (eps > 0) or phi - p_k - 180 (eps < 0)
        if eps > 0:
            phi = P[k] + x
            th = 2.0 * math.degrees(math.atan2(1.0, math.sqrt(2.0) * math.cos(math.radians(x))))
            sg = -60.0
        else:
            phi = P[k] + 180.0 + x
            c = math.cos(math.radians(phi - P[k]))
            th = 2.0 * math.degrees(math.atan(-math.sqrt(2.0) * c))
            sg = wrap(2.0 * phi - 2.0 * P[k] - 60.0)
        pts.append((wrap(phi), th, sg))
    return pts


def split(pts, j):
    """polylines of coordinate j, broken where phi or the coordinate wraps"""
    out, cur = [], []
    for p in pts:
        if cur and (abs(p[0] - cur[-1][0]) > 90.0 or abs(p[j] - cur[-1][j]) > 90.0):
            out.append(cur)
            cur = []
        cur.append(p)
    if cur:
        out.append(cur)
    return out


class Panel:
    def __init__(self, x0, ylabel, ymin, ymax, yticks, title):
        self.x0, self.ymin, self.ymax = x0, ymin, ymax
        self.ylabel, self.yticks, self.title = ylabel, yticks, title

    def X(self, phi):
        return self.x0 + ML + (phi + 180.0) / 360.0 * (W - ML - MR)

    def Y(self, v):
        return MT + (self.ymax - v) / (self.ymax - self.ymin) * (H - MT - MB)

    def frame(self, svg):
        x1, x2, y1, y2 = self.X(-180), self.X(180), self.Y(self.ymax), self.Y(self.ymin)
        svg.append(f'<rect x="{x1:.1f}" y="{y1:.1f}" width="{x2 - x1:.1f}" height="{y2 - y1:.1f}" '
                   'fill="none" stroke="#444"/>')
        for t in range(-180, 181, 60):
            x = self.X(t)
            svg.append(f'<line x1="{x:.1f}" y1="{y2:.1f}" x2="{x:.1f}" y2="{y2 + 4:.1f}" stroke="#444"/>')
            svg.append(f'<text x="{x:.1f}" y="{y2 + 16:.1f}" text-anchor="middle">{t}</text>')
        for t in self.yticks:
            y = self.Y(t)
            svg.append(f'<line x1="{x1 - 4:.1f}" y1="{y:.1f}" x2="{x1:.1f}" y2="{y:.1f}" stroke="#444"/>')
            svg.append(f'<text x="{x1 - 7:.1f}" y="{y + 4:.1f}" text-anchor="end">{t}</text>')
        svg.append(f'<text x="{(x1 + x2) / 2:.1f}" y="{y2 + 34:.1f}" text-anchor="middle">'
                   'azimuth φ (deg)</text>')
        svg.append(f'<text transform="translate({self.x0 + 14:.1f},{(y1 + y2) / 2:.1f}) rotate(-90)" '
                   f'text-anchor="middle">{self.ylabel}</text>')
        svg.append(f'<text x="{(x1 + x2) / 2:.1f}" y="{MT - 12:.1f}" text-anchor="middle" '
                   f'font-weight="bold">{self.title}</text>')


def main(argv):
    out, csv = "docs/agile-eye-singularities.svg", None
    i = 1
    while i < len(argv):
        if argv[i] == "-o" and i + 1 < len(argv):
            out = argv[i + 1]
            i += 2
        elif argv[i] == "--csv" and i + 1 < len(argv):
            csv = argv[i + 1]
            i += 2
        else:
            sys.stderr.write(__doc__)
            return 2
    found, traced = [], {}
    if csv:
        try:
            with open(csv) as f:
                head = f.readline().strip().split(",")
                if head[:6] != ["kind", "k", "eps", "phi_deg", "theta_deg", "sigma_deg"]:
                    sys.stderr.write(f"{csv}: unexpected header {head}\n")
                    return 1
                for n, line in enumerate(f, start=2):
                    r = line.strip().split(",")
                    try:
                        kind, k, e = r[0], int(r[1]), int(r[2])
                        p = (float(r[3]), float(r[4]), float(r[5]))
                    except (IndexError, ValueError):
                        sys.stderr.write(f"{csv}:{n}: bad row {line!r}\n")
                        return 1
                    if kind == "point":
                        found.append((k, e, p))
                    else:
                        traced.setdefault((k, e), []).append(p)
        except OSError as err:
            sys.stderr.write(f"{csv}: {err}\n")
            return 1
    panels = [Panel(0, "tilt θ (deg)", 0, 180, [0, 30, 60, 90, 120, 150, 180],
                    "tilt θ against azimuth φ"),
              Panel(W, "torsion σ (deg)", -180, 180, [-180, -120, -60, 0, 60, 120, 180],
                    "torsion σ against azimuth φ")]
    svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{2 * W}" height="{H + 40}" '
           f'viewBox="0 0 {2 * W} {H + 40}" font-family="sans-serif" font-size="11">',
           f'<rect width="{2 * W}" height="{H + 40}" fill="white"/>']
    for j, pan in enumerate(panels, start=1):
        pan.frame(svg)
        for k in range(3):
            for eps in (1, -1):
                for poly in split(curve(k, eps), j):
                    d = " ".join(f"{pan.X(p[0]):.1f},{pan.Y(p[j]):.1f}" for p in poly)
                    dash = "" if eps > 0 else ' stroke-dasharray="6,3"'
                    svg.append(f'<polyline points="{d}" fill="none" stroke="{COLORS[k]}" '
                               f'stroke-width="1.6"{dash}/>')
        for (k, e), pts in traced.items():
            for poly in split(pts, j):
                d = " ".join(f"{pan.X(p[0]):.1f},{pan.Y(p[j]):.1f}" for p in poly)
                svg.append(f'<polyline points="{d}" fill="none" stroke="black" '
                           'stroke-width="0.5" stroke-opacity="0.6"/>')
        for k, e, p in found:
            svg.append(f'<circle cx="{pan.X(p[0]):.1f}" cy="{pan.Y(p[j]):.1f}" r="2.2" '
                       f'fill="none" stroke="black" stroke-width="0.7"/>')
        # crossing points: Rz(120 deg) (theta = 0, sigma = 120, any phi) and
        # phi = p_k + 180, theta = 2 atan sqrt2, sigma = -60
        tx = 2.0 * math.degrees(math.atan(math.sqrt(2.0)))
        for k in range(3):
            p = (wrap(P[k] + 180.0), tx, -60.0)
            svg.append(f'<rect x="{pan.X(p[0]) - 4:.1f}" y="{pan.Y(p[j]) - 4:.1f}" width="8" '
                       'height="8" fill="none" stroke="black" stroke-width="1.2"/>')
        if j == 2:
            y = pan.Y(120.0)
            svg.append(f'<line x1="{pan.X(-180):.1f}" y1="{y:.1f}" x2="{pan.X(180):.1f}" '
                       f'y2="{y:.1f}" stroke="black" stroke-width="0.6" stroke-dasharray="1,3"/>')
    # legend
    y = H + 14
    x = ML
    for k in range(3):
        for eps, name in ((1, "+"), (-1, "−")):
            dash = "" if eps > 0 else ' stroke-dasharray="6,3"'
            svg.append(f'<line x1="{x}" y1="{y}" x2="{x + 26}" y2="{y}" stroke="{COLORS[k]}" '
                       f'stroke-width="1.6"{dash}/>')
            svg.append(f'<text x="{x + 30}" y="{y + 4}">v{k + 1} = {name}u{k + 1}</text>')
            x += 104
    svg.append(f'<rect x="{x + 4}" y="{y - 4}" width="8" height="8" fill="none" stroke="black" '
               'stroke-width="1.2"/>')
    svg.append(f'<text x="{x + 16}" y="{y + 4}">3 curves cross (4th: θ = 0, σ = 120)</text>')
    y += 18
    note = ("lines: closed form; circles and thin black lines: pomlab (grid + Newton, "
            "continuation), tests/test_agile_sing" if csv else "lines: closed form")
    svg.append(f'<text x="{ML}" y="{y}">{note}</text>')
    svg.append("</svg>")
    try:
        with open(out, "w") as f:
            f.write("\n".join(svg) + "\n")
    except OSError as err:
        sys.stderr.write(f"{out}: {err}\n")
        return 1
    print(f"wrote {out} ({len(found)} points, {len(traced)} traced curves)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
