#!/bin/bash
# test_optimize_cli.sh POMLAB SOURCE_DIR - `pomlab synth` and `pomlab tune` on
# small problems: the written geometry fragment, read back by `pomlab
# workspace`, really covers the target workspace within the 12 mm stroke; the
# --json output stays valid with a quoted config name.
set -u
POMLAB=$1
SRC=$2
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
fail=0
PY=/usr/bin/python3
expect_rc() {
  local want=$1; shift
  "$@" > "$TMP/out" 2> "$TMP/err"
  local rc=$?
  if [ $rc -ne "$want" ]; then
    echo "FAIL (rc $rc, want $want): $*"; cat "$TMP/err"; fail=1
  fi
}

# The 3PSS reference with a quoted name, and a small synthesis: two variables,
# a face-centred CCD (9 runs), coarse region, a target between two workspace
# grid steps (9.3 deg, step 1 deg: only a 10 deg cube covers it).
sed 's/^name = .*/name = "a \\"quoted\\" name \\\\ here";/' "$SRC/configs/3pss.cfg" > "$TMP/base.cfg"
cat "$TMP/base.cfg" - > "$TMP/syn.cfg" <<'EOF'
synthesis = {
  variables = ( { name = "limb_lean_deg"; min = 30.0; max = 45.0; },
                { name = "limb_azimuth_deg"; min = 50.0; max = 75.0; } );
  design = { kind = "ccd_face"; center_points = 1; };
  holdout_points = 3;
  region_half_width_deg = 6.0; region_resolution_deg = 4.0;
  goals = ( { response = "gci"; goal = "maximize"; low = 0.5; high = 1.0; } );
  optimizer = { global = "direct_l"; global_max_evals = 200; local = "bobyqa"; };
  target_half_width_deg = 9.3; scale_min_mm = 2.0; scale_max_mm = 100.0;
};
EOF
expect_rc 0 "$POMLAB" synth "$TMP/syn.cfg" --no-direct --json --out "$TMP/s_"
cp "$TMP/out" "$TMP/synth.json"
if ! $PY -c "
import json
r = json.load(open('$TMP/synth.json'))['synth'][0]
assert r['name'] == 'a \"quoted\" name \\\\ here', r['name']
assert r['architecture'] == '3PSS'
assert r['responses']['rdw_deg']['scaled'] >= 9.3 - 1e-9, r['responses']['rdw_deg']
open('$TMP/geo', 'w').write(r['geometry_file'])
"; then echo "FAIL: synth --json"; cat "$TMP/synth.json"; fail=1; fi

# The fragment in place of the base geometry: pomlab workspace finds the
# target cube (10 deg on the 1 deg grid) with the stroke, cones and clearance.
if [ -s "$TMP/geo" ]; then
  $PY - "$TMP/base.cfg" "$(cat "$TMP/geo")" "$TMP/ws.cfg" <<'EOF'
import sys
text = open(sys.argv[1]).read()
i = text.index('geometry = {')
j = text.index('};', i) + 2
open(sys.argv[3], 'w').write(text[:i] + '@include "%s"\n' % sys.argv[2] + text[j:])
EOF
  expect_rc 0 "$POMLAB" workspace "$TMP/ws.cfg" --json
  if ! $PY -c "
import json
r = json.load(open('$TMP/out'))
hw = r['half_width_deg']
assert hw >= 9.3 and r['check_limits'] and not r['capped'], r
"; then echo "FAIL: workspace of the synthesized fragment"; cat "$TMP/out"; fail=1; fi
fi

# Tuning: a tiny budget, one maneuver; valid JSON with the quoted name.
cat "$TMP/base.cfg" - > "$TMP/tune.cfg" <<'EOF'
tuning = {
  variables = ( { name = "kd_s"; min = 1.0e-3; max = 2.0e-2; log = true; } );
  maneuvers_mm = ( [1.0, -0.5, 0.5] );
  optimizer = { global = "direct_l"; global_max_evals = 3; local = "bobyqa"; local_max_evals = 3; };
};
EOF
expect_rc 0 "$POMLAB" tune "$TMP/tune.cfg" --json --out "$TMP/t_"
if ! $PY -c "
import json
r = json.load(open('$TMP/out'))['tune'][0]
assert r['name'] == 'a \"quoted\" name \\\\ here', r['name']
assert r['criterion_s'] <= r['initial_criterion_s'], r
"; then echo "FAIL: tune --json"; cat "$TMP/out"; fail=1; fi
# the fragment is named by the whole name, made file-name safe (never cut)
[ -s "$TMP/t_a_quoted_name_here.controller.cfg" ] ||
  { echo "FAIL: tune fragment not named by the whole name"; ls "$TMP"; fail=1; }
sed 's/^name = .*/name = "a configuration name well beyond twenty-four characters";/' \
  "$TMP/tune.cfg" > "$TMP/tune_long.cfg"
expect_rc 0 "$POMLAB" tune "$TMP/tune_long.cfg" --quiet --out "$TMP/l_"
[ -s "$TMP/l_a_configuration_name_well_beyond_twenty_four_characters.controller.cfg" ] ||
  { echo "FAIL: a long name is cut in the tune fragment's file name"; ls "$TMP"; fail=1; }

# A criterion that cannot tell gains apart is refused (issue 31 item 8), in
# the library, naming file, line and key; no gains file is written. Zero
# steps (in mm, or orientations of zero through the IK) are refused at load;
# a horizon no maneuver settles in gives the same criterion at every gain set
# the search tries and is refused after the search.
no_motion() { # no_motion NAME KEY-LINE [SED]
  sed "${3:-}" "$TMP/tune.cfg" | sed "s|^  maneuvers_mm = .*|  $2|" > "$TMP/$1.cfg"
  rm -f "$TMP"/n_*
  expect_rc 2 "$POMLAB" tune "$TMP/$1.cfg" --quiet --out "$TMP/n_"
  line=$(grep -n '^  maneuvers_' "$TMP/$1.cfg" | cut -d: -f1)
  key=$(sed -n "${line}p" "$TMP/$1.cfg" | sed 's/^ *\([a-z_]*\) =.*/\1/')
  grep -qF "$1.cfg:$line: key 'tuning.$key'" "$TMP/err" ||
    { echo "FAIL: $1: no file, line and key"; cat "$TMP/err"; fail=1; }
  grep -qF "cannot tell gains apart" "$TMP/err" || { echo "FAIL: $1: no reason"; cat "$TMP/err"; fail=1; }
  ! ls "$TMP"/n_* > /dev/null 2>&1 || { echo "FAIL: $1: a gains file was written"; fail=1; }
}
no_motion zero 'maneuvers_mm = ( [0.0, 0.0, 0.0] );'
no_motion zero2 'maneuvers_mm = ( [0.0, 0.0, 0.0], [0.0, -0.0, 0.0] );'
no_motion euler0 'maneuvers_euler_deg = ( [0.0, 0.0, 0.0] );'
no_motion unsettled 'maneuvers_mm = ( [1.0, -0.5, 0.5] );' 's/^\( *horizon_ms = \)[0-9.]*;/\10.2;/'
grep -qF "at every one of the" "$TMP/err" || { echo "FAIL: unsettled: not the search's check"; fail=1; }
# one zero step among moving ones is fine
sed 's|^  maneuvers_mm = .*|  maneuvers_mm = ( [0.0, 0.0, 0.0], [1.0, -0.5, 0.5] );|' "$TMP/tune.cfg" > "$TMP/mixed.cfg"
expect_rc 0 "$POMLAB" tune "$TMP/mixed.cfg" --quiet --out "$TMP/m_"

# Diagnostics in human text: the one-centre-run CCD has no replicates, so the
# lack-of-fit column says so (no "nan" anywhere); the 3SPS workspace surface
# of configs/synth_3sps.cfg predicts left-out runs worse than their mean
# (predicted R2 -0.031 in its first stage) and is flagged.
expect_rc 0 "$POMLAB" synth "$TMP/syn.cfg" --no-direct --quiet --out "$TMP/h_"
if ! grep -q 'n/a (no replicates)' "$TMP/out" || grep -qi 'nan' "$TMP/out"; then
  echo "FAIL: synth lack-of-fit column"; cat "$TMP/out"; fail=1
fi
sed -e "s|@include \"3sps.cfg\"|@include \"$SRC/configs/3sps.cfg\"|" \
    -e 's/refine_stages = 1;/refine_stages = 0;/' "$SRC/configs/synth_3sps.cfg" > "$TMP/syn3.cfg"
expect_rc 0 "$POMLAB" synth "$TMP/syn3.cfg" --no-direct --quiet --out "$TMP/w_"
if ! grep -q 'warning: stage 0 surface of rdw_deg has a negative predicted R2' "$TMP/out" ||
   grep -q 'warning: .* of gci ' "$TMP/out"; then
  echo "FAIL: negative predicted R2 warning"; cat "$TMP/out"; fail=1
fi

# The study pipeline: two candidates from one base config whose names share
# a file stem ("A/1", "A 1") keep separate files, all in the folder of --out;
# summary.md shows each one's geometry and gains, and its wall time counts
# the synthesis and tuning.
cat > "$TMP/pipe.cfg" <<EOF
name = "pipe";
montecarlo = { maneuvers = 2; seed = 2385; space = "joint"; distribution = "uniform"; range_mm = 1.0; };
study = {
  threads = 1;
  override = {
    synthesis = { run_in_study = true; direct = { enabled = false; }; };
    tuning = {
      run_in_study = true;
      variables = ( { name = "kd_s"; min = 1.0e-3; max = 2.0e-2; log = true; } );
      maneuvers_mm = ( [1.0, -0.5, 0.5] );
      optimizer = { global = "direct_l"; global_max_evals = 3; local = "bobyqa"; local_max_evals = 3; };
    };
  };
};
candidates = ( { name = "A/1"; config = "$TMP/syn.cfg"; },
               { name = "A 1"; config = "$TMP/syn.cfg";
                 override = { synthesis = { target_half_width_deg = 8.0; }; }; } );
EOF
(cd "$TMP" && "$POMLAB" study "$TMP/pipe.cfg" --out "$TMP/st/x.h5" --no-plots --quiet > "$TMP/out" 2> "$TMP/err") ||
  { echo "FAIL: pipeline study"; cat "$TMP/err"; fail=1; }
for f in A_1.geometry.cfg A_1.h5 A_1.controller.cfg A_1_2.geometry.cfg A_1_2.h5 A_1_2.controller.cfg; do
  [ -s "$TMP/st/x/$f" ] || { echo "FAIL: pipeline file $f not in the --out folder"; fail=1; }
done
[ -e "$TMP/results" ] && { echo "FAIL: pipeline wrote outside the --out folder"; fail=1; }
if ! $PY - "$TMP/st/x/summary.md" <<'PYEOF'
import re, sys
s = open(sys.argv[1]).read()
assert '### Pipeline: synthesized geometry and tuned gains' in s
rows = [l for l in s.splitlines() if l.startswith(('| A/1 |', '| A 1 |')) and 'platform_radius_mm' in l]
assert len(rows) == 2, rows
wall = float(re.search(r'this run: ([0-9.]+) s wall', s).group(1))
spent = 0.0
for l in rows:
    cells = [c.strip() for c in l.strip().strip('|').split('|')]
    assert '(tuned)' in cells[2], cells
    spent += sum(float(x) for x in cells[4].split(','))
# two targets, two radii: two syntheses, each in its own files
radii = [float(re.search(r'platform_radius_mm ([0-9.]+)', l).group(1)) for l in rows]
assert radii[0] != radii[1], radii
assert wall >= spent - 0.2, (wall, spent)  # times printed to 0.1 s
assert 'A_1_2.controller.cfg' in s
PYEOF
then echo "FAIL: pipeline summary"; cat "$TMP/st/x/summary.md"; fail=1; fi

# usage errors
expect_rc 2 "$POMLAB" synth
expect_rc 2 "$POMLAB" tune --bogus

[ $fail -eq 0 ] && echo "test_optimize_cli: ok"
exit $fail
