#!/usr/bin/env python3
"""The gain-tuning criterion of one study candidate over the tuner's box,
with the tuner's path through it, as an SVG (docs/catalog.md section 10.1,
docs/catalog-c07-tuning.svg).

usage: tune_basins.py MAP.csv [ZOOM.csv] --path PATH.csv [--path PATH2.csv]
                      [--title TEXT] -o OUT.svg   (TEXT: lines split at '|')

MAP.csv (and ZOOM.csv, a finer map of a part of the box, drawn as a second
panel) are written by `build/bench/tune_map STUDY CANDIDATE grid N F.csv`,
PATH.csv by `build/bench/tune_map STUDY CANDIDATE path F.csv [LOCAL_STARTS]`:
the global stage's points (g rows) as dots, each local run (l rows, a new run
where a row is farther from the previous one than the local stage's trust
region ever moves in one step: it starts at a global-stage point) as a line
to its end, the result (best row) as a star. The colour is the criterion
(ms, log scale, clipped); cells whose criterion carries a penalty (an
overshoot or saturation beyond its limit: criterion above the mean execution
time) are hatched. Standard library only.
"""
import csv
import math
import sys

W, H = 430, 330  # one panel
ML, MR, MT, MB = 62, 14, 34, 46
BAR = 70  # colour bar width
# viridis, 9 stops
STOPS = ["#440154", "#472d7b", "#3b528b", "#2c728e", "#21918c", "#28ae80", "#5ec962",
         "#addc30", "#fde725"]
RUN_COLORS = ["#d62728", "#ff7f0e", "#e377c2", "#8c564b"]


def colour(t):
    """viridis at t in [0, 1]"""
    t = min(1.0, max(0.0, t)) * (len(STOPS) - 1)
    k = min(int(t), len(STOPS) - 2)
    f = t - k
    a = [int(STOPS[k][i:i + 2], 16) for i in (1, 3, 5)]
    b = [int(STOPS[k + 1][i:i + 2], 16) for i in (1, 3, 5)]
    return "#%02x%02x%02x" % tuple(round(a[i] + f * (b[i] - a[i])) for i in range(3))


def load(path):
    rows = list(csv.DictReader(open(path, newline="")))
    if not rows:
        raise ValueError("%s: no rows" % path)
    return rows


def runs(rows):
    """the local rows split into runs: a run starts where the step from the
    previous row is larger than any step inside a run (the trust region
    shrinks; a new run jumps to another global-stage point)"""
    local = [r for r in rows if r["stage"] == "l"]
    starts = {(float(r["z0"]), float(r["z1"])) for r in rows if r["stage"] == "g"}
    out = []
    for r in local:
        z = (float(r["z0"]), float(r["z1"]))
        if not out or (z in starts and out[-1] and z != out[-1][-1]):
            out.append([])
        out[-1].append(z)
    return out


class Panel:
    def __init__(self, x0, y0, zx, zy, title):
        self.x0, self.y0 = x0, y0
        self.zx, self.zy = zx, zy  # (lo, hi) of log10 kp and log10 kd
        self.title = title

    def px(self, z):
        return self.x0 + ML + (z - self.zx[0]) / (self.zx[1] - self.zx[0]) * (W - ML - MR)

    def py(self, z):
        return self.y0 + H - MB - (z - self.zy[0]) / (self.zy[1] - self.zy[0]) * (H - MT - MB)

    def inside(self, z0, z1):
        return self.zx[0] <= z0 <= self.zx[1] and self.zy[0] <= z1 <= self.zy[1]

    def frame(self, svg):
        x1, x2 = self.x0 + ML, self.x0 + W - MR
        y1, y2 = self.y0 + MT, self.y0 + H - MB
        svg.append(f'<rect x="{x1:.1f}" y="{y1:.1f}" width="{x2 - x1:.1f}" '
                   f'height="{y2 - y1:.1f}" fill="none" stroke="#444"/>')
        for v in (10, 30, 100, 300, 1000, 3000, 10000, 30000, 100000):
            z = math.log10(v)
            if self.zx[0] - 1e-9 <= z <= self.zx[1] + 1e-9:
                x = self.px(z)
                svg.append(f'<line x1="{x:.1f}" y1="{y2:.1f}" x2="{x:.1f}" y2="{y2 + 4:.1f}" '
                           'stroke="#444"/>')
                svg.append(f'<text x="{x:.1f}" y="{y2 + 16:.1f}" text-anchor="middle">{v:g}</text>')
        for v in (0.5, 0.7, 1.0, 1.5, 2.0, 3.0, 5.0, 10.0, 20.0):
            z = math.log10(v * 1e-3)
            if self.zy[0] - 1e-9 <= z <= self.zy[1] + 1e-9:
                y = self.py(z)
                svg.append(f'<line x1="{x1 - 4:.1f}" y1="{y:.1f}" x2="{x1:.1f}" y2="{y:.1f}" '
                           'stroke="#444"/>')
                svg.append(f'<text x="{x1 - 7:.1f}" y="{y + 4:.1f}" text-anchor="end">{v:g}</text>')
        svg.append(f'<text x="{(x1 + x2) / 2:.1f}" y="{y2 + 34:.1f}" text-anchor="middle">'
                   'k_P (V/V, log)</text>')
        svg.append(f'<text transform="translate({self.x0 + 14:.1f},{(y1 + y2) / 2:.1f}) '
                   'rotate(-90)" text-anchor="middle">τ_D (ms, log)</text>')
        svg.append(f'<text x="{(x1 + x2) / 2:.1f}" y="{self.y0 + 20:.1f}" text-anchor="middle" '
                   f'font-weight="bold">{self.title}</text>')

    def cells(self, svg, rows, cmin, cmax):
        z0 = sorted({float(r["z0"]) for r in rows})
        z1 = sorted({float(r["z1"]) for r in rows})
        d0 = (z0[-1] - z0[0]) / (len(z0) - 1)
        d1 = (z1[-1] - z1[0]) / (len(z1) - 1)
        for r in rows:
            a, b = float(r["z0"]), float(r["z1"])
            c = float(r["criterion_ms"])
            t = (math.log(c) - math.log(cmin)) / (math.log(cmax) - math.log(cmin))
            xa, xb = self.px(max(self.zx[0], a - d0 / 2)), self.px(min(self.zx[1], a + d0 / 2))
            ya, yb = self.py(min(self.zy[1], b + d1 / 2)), self.py(max(self.zy[0], b - d1 / 2))
            fill = colour(t)
            hatch = c > float(r["mean_execution_ms"]) * (1 + 1e-9)
            svg.append(f'<rect x="{xa:.1f}" y="{ya:.1f}" width="{xb - xa + 0.3:.1f}" '
                       f'height="{yb - ya + 0.3:.1f}" fill="{fill}"/>')
            if hatch:
                svg.append(f'<rect x="{xa:.1f}" y="{ya:.1f}" width="{xb - xa + 0.3:.1f}" '
                           f'height="{yb - ya + 0.3:.1f}" fill="url(#hatch)"/>')

    def clip(self, svg, ident):
        x1, x2 = self.x0 + ML, self.x0 + W - MR
        y1, y2 = self.y0 + MT, self.y0 + H - MB
        svg.append(f'<clipPath id="{ident}"><rect x="{x1:.1f}" y="{y1:.1f}" '
                   f'width="{x2 - x1:.1f}" height="{y2 - y1:.1f}"/></clipPath>')
        svg.append(f'<g clip-path="url(#{ident})" shape-rendering="crispEdges">')

    def path(self, svg, rows):
        for r in rows:
            if r["stage"] == "g" and self.inside(float(r["z0"]), float(r["z1"])):
                svg.append(f'<circle cx="{self.px(float(r["z0"])):.1f}" '
                           f'cy="{self.py(float(r["z1"])):.1f}" r="2.6" fill="white" '
                           'stroke="black" stroke-width="0.8"/>')
        for k, run in enumerate(runs(rows)):
            pts = [(self.px(a), self.py(b)) for a, b in run]
            col = RUN_COLORS[k % len(RUN_COLORS)]
            svg.append('<polyline fill="none" stroke="%s" stroke-width="1.4" points="%s"/>'
                       % (col, " ".join("%.1f,%.1f" % p for p in pts)))
            if self.inside(*run[0]):  # the run's start
                svg.append(f'<circle cx="{pts[0][0]:.1f}" cy="{pts[0][1]:.1f}" r="4" '
                           f'fill="none" stroke="{col}" stroke-width="1.6"/>')
        for r in rows:
            if r["stage"] == "best" and self.inside(float(r["z0"]), float(r["z1"])):
                x, y = self.px(float(r["z0"])), self.py(float(r["z1"]))
                svg.append(f'<text x="{x:.1f}" y="{y + 5:.1f}" text-anchor="middle" '
                           'font-size="16" fill="white" stroke="black" stroke-width="0.6">★</text>')


def main(argv):
    maps, paths, title, out = [], [], "", None
    k = 1
    while k < len(argv):
        if argv[k] == "--path" and k + 1 < len(argv):
            paths.append(load(argv[k + 1]))
            k += 2
        elif argv[k] == "--title" and k + 1 < len(argv):
            title = argv[k + 1]
            k += 2
        elif argv[k] == "-o" and k + 1 < len(argv):
            out = argv[k + 1]
            k += 2
        else:
            maps.append(load(argv[k]))
            k += 1
    if not maps or len(maps) > 2 or out is None:
        sys.stderr.write(__doc__)
        return 2
    crit = [float(r["criterion_ms"]) for r in maps[0]]
    # the colours span the criterion's best value to 2.5 times it: the valley
    # and its walls; everything above (mostly penalised gains) is yellow
    cmin, cmax = min(crit), min(max(crit), 2.5 * min(crit))
    svg = []
    panels = []
    for m, rows in enumerate(maps):
        zx = (min(float(r["z0"]) for r in rows), max(float(r["z0"]) for r in rows))
        zy = (min(float(r["z1"]) for r in rows), max(float(r["z1"]) for r in rows))
        # the cells' half widths beyond the outer centres
        n0 = len({r["z0"] for r in rows})
        n1 = len({r["z1"] for r in rows})
        h0, h1 = (zx[1] - zx[0]) / (n0 - 1) / 2, (zy[1] - zy[0]) / (n1 - 1) / 2
        zx, zy = (zx[0] - h0, zx[1] + h0), (zy[0] - h1, zy[1] + h1)
        p = Panel(m * W, 0, zx, zy, ("whole box" if m == 0 else "zoom: the overshoot edge"))
        p.clip(svg, "panel%d" % m)
        p.cells(svg, rows, cmin, cmax)
        svg.append('</g><g clip-path="url(#panel%d)">' % m)  # the paths drawn smooth
        for pr in paths:
            p.path(svg, pr)
        svg.append("</g>")
        p.frame(svg)
        panels.append(p)
        if m == 1:  # the zoom's outline on the whole box
            q = panels[0]
            svg.append(f'<rect x="{q.px(zx[0]):.1f}" y="{q.py(zy[1]):.1f}" '
                       f'width="{q.px(zx[1]) - q.px(zx[0]):.1f}" '
                       f'height="{q.py(zy[0]) - q.py(zy[1]):.1f}" fill="none" stroke="white" '
                       'stroke-dasharray="4,3"/>')
    # colour bar
    bx = len(maps) * W + 12
    y1, y2 = MT, H - MB
    for i in range(100):
        t = i / 99.0
        y = y2 - t * (y2 - y1)
        svg.append(f'<rect x="{bx}" y="{y - (y2 - y1) / 99:.2f}" width="16" '
                   f'height="{(y2 - y1) / 99 + 0.4:.2f}" fill="{colour(t)}"/>')
    for v in (5, 6, 7, 8, 9, 10, 12, 15, 20, 30, 50, 100, 200, 400):
        if cmin <= v <= cmax:
            t = (math.log(v) - math.log(cmin)) / (math.log(cmax) - math.log(cmin))
            y = y2 - t * (y2 - y1)
            svg.append(f'<text x="{bx + 20}" y="{y + 4:.1f}">{v:g}</text>')
    svg.append(f'<text x="{bx}" y="{y1 - 10}">J (ms)</text>')
    width = len(maps) * W + BAR
    head = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{H + 46}" '
            'font-family="sans-serif" font-size="11">',
            '<defs><pattern id="hatch" width="5" height="5" patternUnits="userSpaceOnUse" '
            'patternTransform="rotate(45)"><line x1="0" y1="0" x2="0" y2="5" stroke="white" '
            'stroke-opacity="0.45" stroke-width="1.2"/></pattern></defs>',
            f'<rect width="{width}" height="{H + 46}" fill="white"/>']
    foot = [f'<text x="8" y="{H + 14 + 14 * k}">{t}</text>' for k, t in enumerate(title.split("|"))]
    foot.append("</svg>")
    with open(out, "w") as f:
        f.write("\n".join(head + svg + foot) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
