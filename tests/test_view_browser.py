#!/usr/bin/env python3
"""test_view_browser.py - pomlab view in a real browser (docs/view.md section 5).

usage: test_view_browser.py POMLAB SOURCE_DIR WORKDIR CONFIG [TARGET]
       test_view_browser.py --radial TEST_ARCH_REGISTRY WORKDIR

For one shipped architecture (CONFIG under SOURCE_DIR/configs): the page at
home, at a pose, and a simulated maneuver (TARGET, display units) at its
first and last frame are opened in headless Chromium with software WebGL.
Each must report in #status that it finished (data-ready=1), ran WebGL, drew
every moving body of `pomlab model --json` and had no script error; each
screenshot must be non-blank (pixel variance), the pose must differ from
home and the last frame from the first (in the 3-D view, outside the text).
With --radial: the test-only architecture of tests/test_arch_registry.c,
drawn from the shapes derived from its joint points.

Exit 77 (skipped) when Chromium is missing, unless POM_REQUIRE_BROWSER=1
(scripts/run-tests.sh sets it: CI installs Chromium). PNGs are decoded with
zlib here (no PIL needed).
"""
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import zlib

CHROMIUM_FLAGS = [
    "--headless", "--no-sandbox", "--disable-gpu",
    # software WebGL: SwiftShader through ANGLE (--use-gl=swiftshader alone
    # gives no WebGL in Chromium 120+)
    "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
    "--hide-scrollbars", "--mute-audio", "--no-first-run",
    "--virtual-time-budget=3000",
]
W, H = 640, 400
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)
    return ok


def chromium():
    exe = os.environ.get("POM_CHROMIUM") or shutil.which("chromium") or shutil.which(
        "chromium-browser")
    if not exe:
        if os.environ.get("POM_REQUIRE_BROWSER") == "1":
            print("FAIL chromium not found (Debian package chromium)")
            sys.exit(1)
        print("skipped: chromium not found")
        sys.exit(77)
    return exe


def start_render(exe, html, fragment, png):
    """Starts Chromium on file://html#fragment: a screenshot into png, the DOM on stdout."""
    url = "file://" + os.path.abspath(html) + ("#" + fragment if fragment else "")
    if os.path.exists(png):
        os.remove(png)
    return subprocess.Popen([exe] + CHROMIUM_FLAGS + ["--window-size=%d,%d" % (W, H),
                                                      "--screenshot=" + os.path.abspath(png),
                                                      "--dump-dom", url],
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)


def render(exe, html, fragment, png):
    return status(start_render(exe, html, fragment, png))


def status(proc):
    """The #status attributes of the page Chromium rendered."""
    out, _ = proc.communicate(timeout=120)
    dom = out.decode("utf-8", "replace")
    m = re.search(r'<div id="status"([^>]*)>', dom)
    attrs = dict(re.findall(r'data-([a-z-]+)="([^"]*)"', m.group(1))) if m else {}
    errs = re.search(r'<pre id="errors"[^>]*>([^<]*)', dom)
    if errs and errs.group(1).strip():
        print("     page errors: " + errs.group(1).strip())
    return attrs


def read_png(path):
    """(width, height, rows of RGB tuples flattened) of an 8-bit RGB/RGBA PNG."""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path + ": not a PNG"
    pos, idat, w = 8, b"", 0
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, ctype = struct.unpack(">IIBB", body[:10])
            assert depth == 8 and ctype in (2, 6), path + ": not 8-bit RGB(A)"
            bpp = 3 if ctype == 2 else 4
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw = zlib.decompress(idat)
    stride = w * bpp
    prev = bytearray(stride)
    gray = []
    for y in range(h):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        if f == 1:
            for i in range(bpp, stride):
                line[i] = (line[i] + line[i - bpp]) & 255
        elif f == 2:
            for i in range(stride):
                line[i] = (line[i] + prev[i]) & 255
        elif f == 3:
            for i in range(stride):
                left = line[i - bpp] if i >= bpp else 0
                line[i] = (line[i] + ((left + prev[i]) >> 1)) & 255
        elif f == 4:
            for i in range(stride):
                a = line[i - bpp] if i >= bpp else 0
                b = prev[i]
                c = prev[i - bpp] if i >= bpp else 0
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pr = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[i] = (line[i] + pr) & 255
        gray.append(bytes((line[i] * 3 + line[i + 1] * 6 + line[i + 2]) // 10
                          for i in range(0, stride, bpp)))
        prev = line
    return w, h, gray


def region(img, x0, y0, x1, y1):
    w, h, g = img
    return [row[x0:min(x1, w)] for row in g[y0:min(y1, h)]]


def variance(rows):
    vals = [v for row in rows for v in row]
    mean = sum(vals) / len(vals)
    return sum((v - mean) ** 2 for v in vals) / len(vals)


def differing(a, b):
    """Fraction of pixels whose gray level differs by more than 8."""
    n = d = 0
    for ra, rb in zip(a, b):
        for x, y in zip(ra, rb):
            n += 1
            d += abs(x - y) > 8
    return d / max(n, 1)


def page_ok(attrs, what, bodies, min_frames=1):
    check(attrs.get("ready") == "1", what + ": the page finished its first render")
    check(attrs.get("webgl") == "1", what + ": WebGL ran")
    check(attrs.get("errors") == "0", what + ": no script error (data-errors=%s)"
          % attrs.get("errors"))
    check(attrs.get("bodies") == str(bodies), what + ": %s bodies drawn, expected %d"
          % (attrs.get("bodies"), bodies))
    check(int(attrs.get("frames", "0")) >= min_frames, what + ": %s frames"
          % attrs.get("frames"))


def drawn(png, what, side=0):
    img = read_png(png)
    # the 3-D view below the toolbar (and left of the trace panel)
    view = region(img, 0, 60, img[0] - side, img[1])
    v = variance(view)
    check(v > 20.0, what + ": screenshot not blank (gray variance %.1f)" % v)
    return view


def pomlab(args, **kw):
    r = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, **kw)
    if r.returncode != 0:
        print(r.stderr.decode())
    return r


def main():
    if sys.argv[1] == "--radial":
        exe = chromium()
        test, work = sys.argv[2], sys.argv[3]
        os.makedirs(work, exist_ok=True)
        html = os.path.join(work, "radial.html")
        r = pomlab([test, "--view-html", html])
        check(r.returncode == 0, "test_arch_registry --view-html wrote the page")
        attrs = render(exe, html, "", os.path.join(work, "radial.png"))
        page_ok(attrs, "3PSS-radial (derived shapes)", 7)
        drawn(os.path.join(work, "radial.png"), "3PSS-radial")
        return finish()
    exe = chromium()
    pom, src, work, cfg = sys.argv[1:5]
    target = sys.argv[5] if len(sys.argv) > 5 else "1,2,3"
    os.makedirs(work, exist_ok=True)
    cfg_path = os.path.join(src, "configs", cfg)
    model = json.loads(pomlab([pom, "model", cfg_path, "--json"]).stdout)
    bodies = len(model["mechanism"]["bodies"]) - 1  # every body but the ground
    home, pose, man = (os.path.join(work, n + ".html") for n in ("home", "pose", "maneuver"))
    h5 = os.path.join(work, "maneuver.h5")
    check(pomlab([pom, "view", cfg_path, "-o", home]).returncode == 0, cfg + ": view at home")
    check(pomlab([pom, "view", cfg_path, "--pose", "8,-6,10", "-o", pose]).returncode == 0,
          cfg + ": view at a pose")
    check(pomlab([pom, "simulate", cfg_path, "--target", target, "--out", h5]).returncode == 0,
          cfg + ": simulate --out")
    check(pomlab([pom, "view", cfg_path, "--trace", h5, "-o", man]).returncode == 0,
          cfg + ": view --trace")
    if failures:
        return finish()
    shots, pages = {}, (("home", home, "", 0, 1), ("pose", pose, "", 0, 1),
                        ("frame 0", man, "frame=0", 400, 2),
                        ("last frame", man, "frame=last", 400, 2))
    # two browsers at a time: their start-up is mostly waiting
    for pair in (pages[:2], pages[2:]):
        procs = [start_render(exe, html, frag, os.path.join(work, name.replace(" ", "_") + ".png"))
                 for name, html, frag, _, _ in pair]
        for (name, html, frag, side, frames), proc in zip(pair, procs):
            png = os.path.join(work, name.replace(" ", "_") + ".png")
            page_ok(status(proc), "%s %s" % (cfg, name), bodies, frames)
            shots[name] = drawn(png, "%s %s" % (cfg, name), side)
    if cfg == "3pss.cfg":
        # the play button's loop runs without error and moves the frame
        attrs = render(exe, man, "play", os.path.join(work, "playing.png"))
        check(attrs.get("errors") == "0" and int(attrs.get("frame", "0")) > 0,
              cfg + ": #play animates (frame %s after the time budget)" % attrs.get("frame"))
        # the workspace coloured by a capability figure: drawn without a script error,
        # and the sphere's colours differ from the dexterity's
        cap, wsp = os.path.join(work, "cap.html"), os.path.join(work, "ws.html")
        ok = pomlab([pom, "view", cfg_path, "--capability", "acc_inscribed", "-o", cap]
                    ).returncode == 0
        ok = pomlab([pom, "view", cfg_path, "--workspace", "-o", wsp]).returncode == 0 and ok
        if check(ok, cfg + ": view --capability acc_inscribed and --workspace"):
            attrs = render(exe, cap, "", os.path.join(work, "cap.png"))
            page_ok(attrs, cfg + " --capability", bodies)
            check(attrs.get("capability") == "acc_inscribed",
                  cfg + ": the page colours by acc_inscribed (data-capability=%s)"
                  % attrs.get("capability"))
            render(exe, wsp, "", os.path.join(work, "ws.png"))
            d = differing(drawn(os.path.join(work, "cap.png"), cfg + " --capability"),
                          drawn(os.path.join(work, "ws.png"), cfg + " --workspace"))
            check(d > 0.002, cfg + ": --capability colours differ from the dexterity's "
                  "(%.2f%% of pixels)" % (100 * d))
        # pictures for papers: the page by headless Chromium, the film by ffmpeg
        pic = os.path.join(work, "picture.png")
        r = pomlab([pom, "view", cfg_path, "--pose", "8,-6,10", "--png", pic, "--size", "480x320"])
        if check(r.returncode == 0 and os.path.exists(pic), cfg + ": view --png"):
            drawn(pic, cfg + " --png")
        if shutil.which("ffmpeg"):
            film = os.path.join(work, "maneuver.mp4")
            r = pomlab([pom, "view", cfg_path, "--trace", h5, "--frames", "12", "--fps", "12",
                        "--size", "160x120", "--mp4", film])
            ok = r.returncode == 0 and os.path.exists(film)
            check(ok and open(film, "rb").read(12)[4:8] == b"ftyp", cfg + ": view --mp4")
        else:
            print("     (no ffmpeg: --mp4 not tried; test_view_cli checks its message)")
    d = differing(shots["home"], shots["pose"])
    check(d > 0.002, cfg + ": the pose differs from home (%.2f%% of pixels)" % (100 * d))
    d = differing(shots["frame 0"], shots["last frame"])
    check(d > 0.002, cfg + ": the last frame differs from the first (%.2f%% of pixels)"
          % (100 * d))
    return finish()


def finish():
    if failures:
        print("%d failure(s)" % len(failures))
        return 1
    print("all passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
