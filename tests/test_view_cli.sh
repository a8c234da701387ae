#!/usr/bin/env bash
# test_view_cli.sh - pomlab view without a browser (docs/view.md): the page
# is one self-contained file (no <script src>, no link, three.js and its
# licence inlined) whose scene holds what was asked (bodies and shapes of
# every mechanism, trace frames, workspace grid, mechanisms side by side),
# and every refusal says why with the right exit code: usage errors, a pose
# that cannot be assembled, a trace that is not one, three.js, Chromium or
# ffmpeg missing. Runs in the sanitizer build too (the browser tests do not).
# Usage: test_view_cli.sh PATH/TO/pomlab SOURCE_DIR
set -u
POMLAB=$1
SRC=$2
. "$(dirname "$0")/cli_lib.sh"
C="$SRC/configs"
if [ ! -r "${POM_THREE_JS:-/usr/share/javascript/three/three.min.js}" ]; then
  [ "${POM_REQUIRE_BROWSER:-0}" = 1 ] && { echo "FAIL: three.js missing (libjs-three)"; exit 1; }
  echo "skipped: three.js missing (Debian package libjs-three)"
  exit 77
fi

# scene PAGE PYTHON-EXPR : EXPR with s = the page's scene JSON and html = the page
scene() {
  checks=$((checks + 1))
  "$PY" -c "
import json, re, sys
html = open('$1').read()
s = json.loads(re.search(r'<script type=\"application/json\" id=\"pom-scene\">(.*?)</script>', html, re.S).group(1))
sys.exit(0 if ($2) else 1)" || fail "scene check failed on $(basename "$1"): $2"
}

# --- the static page ----------------------------------------------------------------------
expect_rc 0 "$POMLAB" view "$C/3pss.cfg" -o "$TMP/home.html"
scene "$TMP/home.html" "len(s['mechs']) == 1 and len(s['mechs'][0]['frames']) == 1"
scene "$TMP/home.html" "sorted(set(x['body'] for x in s['mechs'][0]['shapes'])) == list(range(1, 8))"
scene "$TMP/home.html" "'<script src' not in html and '<link' not in html and 'MIT licence' in html"
scene "$TMP/home.html" "'REVISION=\"111\"' in html or 'REVISION' in html"
# at home every body is where the mechanism says: identity poses
scene "$TMP/home.html" "all(abs(v - w) < 1e-9 for v, w in zip(s['mechs'][0]['frames'][0][:12], [1,0,0,0,1,0,0,0,1,0,0,0]))"
# at a pose the platform's rotation is the ZYX Euler one (psi = 10 deg about z alone)
expect_rc 0 "$POMLAB" view "$C/3sps.cfg" --pose 10,0,0 -o "$TMP/pose.html"
scene "$TMP/pose.html" "abs(s['mechs'][0]['frames'][0][12] - 0.984808) < 1e-5 and abs(s['mechs'][0]['frames'][0][15] - 0.173648) < 1e-5"
# the 3-RRR's arcs and rotors, its platform a disc
expect_rc 0 "$POMLAB" view "$C/3rrr.cfg" --workspace -o "$TMP/ws.html"
scene "$TMP/ws.html" "sum(x['kind'] == 'arc' for x in s['mechs'][0]['shapes']) == 6 and any(x['kind'] == 'disc' for x in s['mechs'][0]['shapes'])"
scene "$TMP/ws.html" "s['workspace']['n_tilt'] * s['workspace']['n_azimuth'] == len(s['workspace']['state']) and s['workspace']['rdw_half_width'] > 0 and len(s['workspace']['outline']) > 12"
# --capability: the directions coloured by a capability figure; at tilt 0 (home, every
# azimuth) the value is `pomlab capability`'s home figure in the same display unit
expect_rc 0 "$POMLAB" capability "$C/3pss.cfg" --grid 1 --json --quiet
cp "$TMP/out" "$TMP/cap.json"
expect_rc 0 "$POMLAB" view "$C/3pss.cfg" --capability acc_inscribed -o "$TMP/cap_acc.html"
scene "$TMP/cap_acc.html" "(lambda c, h: c['name'] == 'acc_inscribed' and c['unit'] == 'deg/s^2' and (c['n_tilt'], c['n_azimuth']) == (s['workspace']['n_tilt'], s['workspace']['n_azimuth']) and len(c['value']) == c['n_tilt'] * c['n_azimuth'] and c['n_failed'] == 0 and all(abs(v - h['acc_inscribed_rad_per_s2'] * 57.29577951308232) < 1e-5 * v for v in c['value'][:c['n_azimuth']]) and c['lo'] < c['hi'] == max(v for v in c['value'] if v is not None))(s['workspace']['capability'], json.load(open('$TMP/cap.json'))['home'])"
# unusable directions are not evaluated; usable ones are
scene "$TMP/cap_acc.html" "all((v is None) == (st != 0) for v, st in zip(s['workspace']['capability']['value'], s['workspace']['state']))"
expect_rc 0 "$POMLAB" view "$C/3pss.cfg" --capability bw_worst -o "$TMP/cap_bw.html"
scene "$TMP/cap_bw.html" "(lambda c, h: c['unit'] == 'Hz' and c['joints'] == 'parasitic' and (c['stride_tilt'], c['stride_azimuth']) == (2, 3) and c['n_evaluated'] > 20 and abs(c['value'][0] - h['bw_worst_hz']) < 1e-4 * h['bw_worst_hz'] and c['lo'] < h['bw_worst_hz'] * (1 + 1e-5) and c['hi'] > h['bw_worst_hz'] * (1 - 1e-5))(s['workspace']['capability'], json.load(open('$TMP/cap.json'))['home'])"
expect_rc 2 "$POMLAB" view "$C/3pss.cfg" --capability bogus -o "$TMP/bogus.html"
expect_err "unknown figure 'bogus'" "acc_inscribed" "bw_worst"

# side by side
expect_rc 0 "$POMLAB" view "$C/3pss.cfg" --compare "$C/3sps.cfg" "$C/3rrr.cfg" --pose 3,4,-5 -o "$TMP/cmp.html"
scene "$TMP/cmp.html" "[m['arch'] for m in s['mechs']] == ['3PSS', '3SPS', '3RRR']"

# --- a maneuver ------------------------------------------------------------------------------
expect_rc 0 "$POMLAB" simulate "$C/3pss.cfg" --target 1,2,3 --out "$TMP/m.h5"
expect_rc 0 "$POMLAB" view "$C/3pss.cfg" --trace "$TMP/m.h5" --frames 50 --frame -1 -o "$TMP/m.html"
scene "$TMP/m.html" "len(s['trace']['t']) == 50 and len(s['mechs'][0]['frames']) == 50 and s['frame'] == 49 and s['failed_frames'] == 0"
# the pointing error starts where the platform is (home) and ends near the target's
scene "$TMP/m.html" "s['trace']['err'][0] > 1e-3 and s['trace']['err'][-1] < 1e-2 * s['trace']['err'][0]"
scene "$TMP/m.html" "abs(s['trace']['target'][2] - 0.003) < 1e-12"

# a trace of another mechanism is drawn with the config's kinematics, with a warning
expect_rc 0 "$POMLAB" view "$C/3sps.cfg" --trace "$TMP/m.h5" --frames 10 -o "$TMP/other.html"
expect_err "warning: the trace"

# --- refusals --------------------------------------------------------------------------------
expect_rc 2 "$POMLAB" view "$C/3pss.cfg"
expect_err "missing -o FILE.html"
expect_rc 2 "$POMLAB" view "$C/3pss.cfg" -o "$TMP/x.htm"
expect_err "-o must end in .html"
expect_rc 2 "$POMLAB" view "$C/3pss.cfg" --pose 1,2 -o "$TMP/x.html"
expect_err "--pose expects three angles"
expect_rc 2 "$POMLAB" view "$C/3pss.cfg" --mp4 "$TMP/x.mp4"
expect_err "give it --trace"
expect_rc 2 "$POMLAB" view "$C/3pss.cfg" --trace "$TMP/m.h5" --pose 1,2,3 -o "$TMP/x.html"
expect_rc 2 "$POMLAB" view "$C/3pss.cfg" --trace "$TMP/m.h5" --frames 1 -o "$TMP/x.html"
expect_rc 2 "$POMLAB" view "$C/3pss.cfg" -o "$C/3pss.cfg.html" --png "$C/3pss.cfg"
# a pose the links cannot reach (links of 0.3 platform radii): nothing written
sed 's/^  limb_length = .*/  limb_length = 0.3;/' "$C/3pss.cfg" >"$TMP/short.cfg"
expect_rc 1 "$POMLAB" view "$TMP/short.cfg" --pose 0,60,0 -o "$TMP/far.html"
expect_err "cannot reach"
check "no page for an unreachable pose" test ! -e "$TMP/far.html"
# a trace that is not one
echo "not hdf5" >"$TMP/bad.h5"
expect_rc 1 "$POMLAB" view "$C/3pss.cfg" --trace "$TMP/bad.h5" -o "$TMP/x.html"
# three.js, Chromium, ffmpeg missing: what to install
POM_THREE_JS=$TMP/none.js expect_rc 1 "$POMLAB" view "$C/3pss.cfg" -o "$TMP/x.html"
expect_err "libjs-three"
check "no page without three.js" test ! -e "$TMP/x.html"
POM_CHROMIUM=$TMP/no-chromium expect_rc 1 "$POMLAB" view "$C/3pss.cfg" --png "$TMP/x.png"
expect_err "need Chromium"
mkdir -p "$TMP/bin"
ln -s "$(type -P true)" "$TMP/bin/chromium"
for tool in timeout sed head; do ln -s "$(type -P $tool)" "$TMP/bin/$tool"; done
PATH=$TMP/bin expect_rc 1 "$(cd "$(dirname "$POMLAB")" && pwd)/$(basename "$POMLAB")" view \
  "$C/3pss.cfg" --trace "$TMP/m.h5" --mp4 "$TMP/x.mp4"
expect_err "needs ffmpeg"
check "no film without ffmpeg" test ! -e "$TMP/x.mp4"
# --png into a folder that cannot be written (issue 31 item 9): refused before
# Chromium runs (a stand-in that would leave a mark), naming the folder. As
# root chmod does not stop writes, so there the folder is a path under a
# regular file, which nobody can write to.
printf '#!/bin/sh\ntouch "%s/chromium-ran"\n' "$TMP" >"$TMP/mark-chromium"
chmod +x "$TMP/mark-chromium"
mkdir -p "$TMP/ro"
chmod 555 "$TMP/ro"
if touch "$TMP/ro/probe" 2>/dev/null; then
  rm -f "$TMP/ro/probe"
  echo "note: chmod 555 does not stop this user (root): the unwritable folder is a path under a file"
  touch "$TMP/plain"
  POM_CHROMIUM=$TMP/mark-chromium expect_rc 1 "$POMLAB" view "$C/3pss.cfg" --png "$TMP/plain/x.png"
  expect_err "$TMP/plain"
else
  POM_CHROMIUM=$TMP/mark-chromium expect_rc 1 "$POMLAB" view "$C/3pss.cfg" --png "$TMP/ro/x.png"
  expect_err "--png: cannot write '$TMP/ro/x.png': the folder $TMP/ro is not writable"
fi
check "Chromium never ran for an unwritable target" test ! -e "$TMP/chromium-ran"
chmod 755 "$TMP/ro"
# Chromium failing: the log the message points to is still there to read
printf '#!/bin/sh\necho "the stand-in browser failed on purpose" >&2\nexit 3\n' >"$TMP/bad-chromium"
chmod +x "$TMP/bad-chromium"
POM_CHROMIUM=$TMP/bad-chromium expect_rc 1 "$POMLAB" view "$C/3pss.cfg" --png "$TMP/y.png"
expect_err "failed (exit 3); its messages: "
log=$(sed -n 's/.*its messages: \(.*chromium\.log\).*/\1/p' "$TMP/err" | head -1)
check "the Chromium log named in the message exists" test -s "$log"
check "the log holds Chromium's messages" grep -q "failed on purpose" "$log"
[ -n "$log" ] && rm -rf "$(dirname "$log")"
finish test_view_cli
