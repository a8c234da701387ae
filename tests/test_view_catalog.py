#!/usr/bin/env python3
"""test_view_catalog.py - pomlab view draws every architecture of catalog/
(docs/view.md section 5, docs/catalog.md).

usage: test_view_catalog.py POMLAB SOURCE_DIR WORKDIR [--browser]

Every file of SOURCE_DIR/catalog/*.arch is found here, so a new file is
checked without editing this test. Its run config is configs/catalog/<stem>.cfg,
else configs/<stem>.cfg (the three shipped files), copied with
architecture = the file's name (as tests/test_catalog.c does). Per file, the
page of `pomlab view` at home must hold, against `pomlab model --json`:
  - every body of the mechanism, and at least one shape on every moving body
    (each body is drawable; the shapes come from the joints when the file
    has no drawing of its own, kinematics/kin_shape.c);
  - every joint with its type, its two bodies and its point;
  - finite coordinates everywhere, no degenerate shape (a segment or arc of
    zero length, a radius <= 0, an arc whose ends are not equally far from
    its centre);
  - the identity pose of every body at home.
Then `pomlab view --compare` of the whole catalog in one page: every
mechanism, each with its architecture's label.

With --browser (ctest label browser): each page and the compare page are
opened in headless Chromium (tests/test_view_browser.py's flags): finished,
WebGL, every moving body drawn, no script error, screenshot not blank. Exit
77 when Chromium is missing, unless POM_REQUIRE_BROWSER=1.
"""
import glob
import json
import math
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import test_view_browser as tvb  # noqa: E402  (chromium, render, page_ok, drawn)

failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)
    return ok


def run(args):
    r = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    if r.returncode != 0:
        sys.stdout.write(r.stderr.decode())
    return r


def scene_of(html):
    text = open(html, encoding="utf-8").read()
    m = re.search(r'<script type="application/json" id="pom-scene">(.*?)</script>', text, re.S)
    return json.loads(m.group(1)) if m else None


def finite(x):
    if isinstance(x, (int, float)):
        return math.isfinite(x)
    if isinstance(x, list):
        return all(finite(v) for v in x)
    if isinstance(x, dict):
        return all(finite(v) for v in x.values())
    return True


def dist(a, b):
    return math.sqrt(sum((p - q) ** 2 for p, q in zip(a, b)))


def shape_ok(s, scale):
    """'' when the shape can be drawn, else why not. The page prints 6
    significant digits (pom_view_page.c), model --json 9 or more: points
    agree to ~1e-6 of their size, hence the bounds of 1e-5 below."""
    tiny = 1e-9 * scale
    k = s["kind"]
    if k in ("segment", "arc") and not s["radius"] > 0:
        return "radius %g" % s["radius"]
    if k == "segment" and dist(s["from"], s["to"]) <= tiny:
        return "zero length"
    if k == "arc":
        r0, r1 = dist(s["from"], s["center"]), dist(s["to"], s["center"])
        if r0 <= tiny or dist(s["from"], s["to"]) <= tiny:
            return "zero arc"
        if abs(r0 - r1) > 1e-5 * r0:  # the page prints 6 digits: 1e-6 of r0 at most
            return "ends %g and %g from the centre" % (r0, r1)
    if k == "disc" and not (s["radius"] > 0 and s["thickness"] > 0):
        return "disc radius %g thickness %g" % (s["radius"], s["thickness"])
    if k == "box" and not all(v > 0 for v in s["size"]):
        return "box size %s" % s["size"]
    return ""


def entries(src, work):
    """(stem, architecture name, config path) of every catalog file."""
    out = []
    for path in sorted(glob.glob(os.path.join(src, "catalog", "*.arch"))):
        stem = os.path.basename(path)[:-5]
        m = re.search(r'^name = "([^"]+)";', open(path, encoding="utf-8").read(), re.M)
        if not check(m is not None, stem + ": the file has a name"):
            continue
        cfg = os.path.join(src, "configs", "catalog", stem + ".cfg")
        if not os.path.exists(cfg):
            cfg = os.path.join(src, "configs", stem + ".cfg")
        if not check(os.path.exists(cfg), stem + ": a run config"):
            continue
        text, n = re.subn(r'^architecture = "[^"]*";', 'architecture = "%s";' % m.group(1),
                          open(cfg, encoding="utf-8").read(), count=1, flags=re.M)
        if not check(n == 1, stem + ": the config names its architecture"):
            continue
        own = os.path.join(work, stem + ".cfg")
        with open(own, "w", encoding="utf-8") as f:
            f.write(text)
        out.append((stem, m.group(1), own))
    return out


def check_entry(pom, stem, arch, cfg, html):
    model = run([pom, "model", cfg, "--json"])
    if not check(model.returncode == 0, stem + ": pomlab model --json"):
        return None
    mech = json.loads(model.stdout)["mechanism"]
    if not check(run([pom, "view", cfg, "-o", html]).returncode == 0, stem + ": pomlab view"):
        return None
    S = scene_of(html)
    if not check(S is not None and len(S["mechs"]) == 1, stem + ": the page holds its scene"):
        return None
    M = S["mechs"][0]
    check(M["arch"] == arch, stem + ": the scene's architecture is %s (%s)" % (arch, M["arch"]))
    check(finite(M), stem + ": every number of the scene is finite")
    nb = len(mech["bodies"])
    check(M["bodies"] == [b["name"] for b in mech["bodies"]],
          stem + ": the %d bodies of pomlab model" % nb)
    scale = M["scale"]
    shaped = set()
    for s in M["shapes"]:
        why = shape_ok(s, scale)
        if not check(why == "", "%s: %s of body %d drawable%s" % (stem, s["kind"], s["body"],
                                                                  ": " + why if why else "")):
            continue
        shaped.add(s["body"])
    missing = [M["bodies"][b] for b in range(1, nb) if b not in shaped]
    check(not missing, stem + ": a shape on every moving body (%d of %d%s)"
          % (nb - 1 - len(missing), nb - 1, ", none on " + ", ".join(missing) if missing else ""))
    js = mech["joints"]
    check(len(M["joints"]) == len(js), stem + ": the %d joints of pomlab model (%d drawn)"
          % (len(js), len(M["joints"])))
    for a, b in zip(M["joints"], js):
        same = (a["name"] == b["name"] and a["type"] == b["type"] and
                a["bodies"] == b["bodies"] and
                dist(a["point"], b["point_m"]) <= 1e-5 * max(scale, math.hypot(*b["point_m"])))
        check(same, "%s: joint %s (%s) drawn at its point between its bodies"
              % (stem, b["name"], b["type"]))
    pose = M["frames"][0]
    ident = [1, 0, 0, 0, 1, 0, 0, 0, 1]
    worst = max(abs(pose[12 * k + i] - ident[i]) for k in range(nb) for i in range(9))
    check(worst <= 1e-12, stem + ": every body at its home pose (|R - I| %.1e)" % worst)
    return nb - 1


def main():
    args = [a for a in sys.argv[1:] if a != "--browser"]
    browser = "--browser" in sys.argv[1:]
    pom, src, work = args[:3]
    os.makedirs(work, exist_ok=True)
    exe = tvb.chromium() if browser else None
    cat = entries(src, work)
    check(len(cat) >= 12, "%d catalog files (at least 12)" % len(cat))
    moving = {}
    for stem, arch, cfg in cat:
        n = check_entry(pom, stem, arch, cfg, os.path.join(work, stem + ".html"))
        if n is not None:
            moving[stem] = n
    cmp_html = os.path.join(work, "compare.html")
    cfgs = [c for _, _, c in cat]
    ok = run([pom, "view", cfgs[0], "--compare"] + cfgs[1:] + ["-o", cmp_html]).returncode == 0
    if check(ok, "pomlab view --compare of the %d catalog files" % len(cfgs)):
        S = scene_of(cmp_html)
        check([m["arch"] for m in S["mechs"]] == [a for _, a, _ in cat],
              "the compare page holds every catalog architecture in order")
        check(all(m["arch_label"] for m in S["mechs"]), "each with its label")
    if browser and not failures:
        pages = [(stem, os.path.join(work, stem + ".html"), moving[stem]) for stem, _, _ in cat]
        pages.append(("compare", cmp_html, sum(moving.values())))
        for i in range(0, len(pages), 2):  # two browsers at a time
            pair = pages[i:i + 2]
            procs = [tvb.start_render(exe, html, "", os.path.join(work, name + ".png"))
                     for name, html, _ in pair]
            for (name, html, bodies), proc in zip(pair, procs):
                tvb.failures.clear()
                tvb.page_ok(tvb.status(proc), name + " in Chromium", bodies)
                tvb.drawn(os.path.join(work, name + ".png"), name)
                failures.extend(tvb.failures)
    print("%d failure(s)" % len(failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
