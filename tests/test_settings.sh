#!/usr/bin/env bash
# test_settings.sh - settings that would be read as something else are
# refused or compared (issue 22, items 8-14): misspelt override groups,
# repeated or conflicting sweep factors, factor and uncertain keys the model
# never reads, relative draws on a zero nominal, what --resume compares and
# checks, and integer keys given a fraction.
# Usage: test_settings.sh PATH/TO/pomlab SOURCE_DIR
set -u
POMLAB=$1
SRC=$2
. "$(dirname "$0")/cli_lib.sh"

# study NAME [STUDY-OVERRIDE-EXTRA] [CANDIDATES] [MORE]: a small fast study
# (rigid joints, quasi-static coil) of the shipped 3P-S-S/S
study() {
  local cands=${3:-"candidates = ( { name = \"A\"; config = \"$SRC/configs/3pss.cfg\"; } );"}
  cat >"$TMP/$1.cfg" <<CFG
name = "$1";
montecarlo = { maneuvers = ${M:-6}; seed = 4242; range_mm = 3.0; };
study = { override = { joints = { model = "rigid"; }; scene = { coil_inductance = false; };
  ${2:-} }; };
$cands
${4:-}
CFG
}
run() { # run NAME [ARGS...]
  local n=$1
  shift
  expect_rc "${WANT:-0}" "$POMLAB" study "$TMP/$n.cfg" --out "$TMP/$n.h5" --no-plots \
    --no-summary --quiet "$@"
}
sweep() { # sweep FACTORS : candidates group of a grid sweep
  printf 'candidates = { sweep = "grid"; base = ( { name = "A"; config = "%s"; } );\n' \
    "$SRC/configs/3pss.cfg"
  printf '  factors = ( %s ); };\n' "$1"
}

# --- item 8: a misspelt group inside an override is refused (file, key, 2) ---
study o1 'jionts = { model = "rigid"; };'
WANT=2 run o1
expect_err "o1.cfg:4: key 'study.override.jionts'"
expect_err "unknown group"
study o2 "" "candidates = ( { name = \"A\"; config = \"$SRC/configs/3pss.cfg\";
  override = { controler = { kp = 5.0e3; }; }; } );"
WANT=2 run o2
expect_err "o2.cfg:6: key 'candidates.[0].override.controler'"
# a group the model never reads is refused the same way (it changes nothing)
study o3 'workspace = { dexterity_min = 0.5; };'
WANT=2 run o3
expect_err "key 'study.override.workspace'"
# known groups are still fine
study o4 'controller = { kp = 1.1e4; };'
run o4

# --- item 10: the same key as two sweep factors ------------------------------
study f1 "" "$(sweep '{ key = "controller.kp"; min = 1.0e4; max = 1.2e4; levels = 2; },
  { key = "controller.kp"; min = 0.9e4; max = 1.1e4; levels = 2; }')"
WANT=2 run f1
expect_err "key 'candidates.factors.[1].key' = \"controller.kp\""
expect_err "already factor candidates.factors.[0]"

# --- item 11: a factor and an absolute uncertain parameter on one key --------
UNC_ABS='uncertain = ( { key = "controller.kp"; dist = "uniform"; min = 1.0e4; max = 1.2e4; } );'
UNC_REL='uncertain = ( { key = "controller.kp"; dist = "uniform"; min = 0.9; max = 1.1;
  relative = true; } );'
study f2 "" "$(sweep '{ key = "controller.kp"; min = 1.0e4; max = 1.2e4; levels = 2; }')" \
  "$UNC_ABS"
WANT=2 run f2
expect_err "key 'candidates.factors.[0].key' = \"controller.kp\""
expect_err "also uncertain.[0] with absolute draws"
# relative about each candidate's own value is meaningful
study f3 "" "$(sweep '{ key = "controller.kp"; min = 1.0e4; max = 1.2e4; levels = 2; }')" \
  "$UNC_REL"
run f3

# --- items 12, 13: keys in an unknown group, without a dot, never read -------
for key in nosuch.key workspace.dexterity_min montecarlo.range_mm; do
  study k1 "" "$(sweep "{ key = \"$key\"; min = 0.4; max = 0.6; levels = 2; }")"
  WANT=2 run k1
  expect_err "key 'candidates.factors.[0].key' = \"$key\""
  expect_err "never reads group '${key%%.*}'"
  study k2 "" "" "uncertain = ( { key = \"$key\"; dist = \"uniform\"; min = 0.4; max = 0.6; } );"
  WANT=2 run k2
  expect_err "key 'uncertain.[0].key' = \"$key\""
  expect_err "never reads group '${key%%.*}'"
done
# a candidate's own montecarlo group is not the study's
cp "$SRC/configs/3pss.cfg" "$TMP/mc.cfg"
printf 'montecarlo = { range_mm = 2.0; };\n' >>"$TMP/mc.cfg"
study k3 "" "$(printf 'candidates = { sweep = "grid"; base = ( { name = "A"; config = "%s"; } );
  factors = ( { key = "montecarlo.range_mm"; min = 1.0; max = 2.0; levels = 2; } ); };' \
  "$TMP/mc.cfg")"
WANT=2 run k3
expect_err "never reads group 'montecarlo'"
for key in kp controller. .kp; do
  study k4 "" "$(sweep "{ key = \"$key\"; min = 1.0e4; max = 1.2e4; levels = 2; }")"
  WANT=2 run k4
  expect_err "key 'candidates.factors.[0].key' = \"$key\": expected a dotted key"
  study k5 "" "" "uncertain = ( { key = \"$key\"; dist = \"uniform\"; min = 0.9; max = 1.1; } );"
  WANT=2 run k5
  expect_err "key 'uncertain.[0].key' = \"$key\""
done
# relative draws about a zero nominal value have no spread
study k6 "" "" 'uncertain = ( { key = "geometry.actuator_tilt_deg"; dist = "uniform"; min = 0.9;
  max = 1.1; relative = true; } );'
WANT=2 run k6
expect_err "key 'uncertain.[0].key' = \"geometry.actuator_tilt_deg\""
expect_err "nominal value, which is 0"
# a key of another controller type is in a group the model reads, yet the
# candidates' controller never reads it (issue 31 item 6): a computed-torque
# gain on PID candidates is refused as a factor and as an uncertain key,
# naming the type; on computed-torque candidates the same factor is a sweep
for key in controller.omega_n_rad_per_s controller.trajectory_duration_s controller.feedforward; do
  study c1 "" "$(sweep "{ key = \"$key\"; min = 1.0; max = 2.0; levels = 2; }")"
  WANT=2 run c1
  expect_err "c1.cfg:6: key 'candidates.factors.[0].key' = \"$key\""
  expect_err "the PID controller (controller.type = \"pid\") of candidate 'A "
  expect_err "never reads it, so the key would change nothing (its keys: kp, ki_per_s, kd_s, form)"
  study c2 "" "" "uncertain = ( { key = \"$key\"; dist = \"uniform\"; min = 1.0; max = 2.0; } );"
  WANT=2 run c2
  expect_err "c2.cfg:6: key 'uncertain.[0].key' = \"$key\""
  expect_err "the PID controller (controller.type = \"pid\") of candidate 'A' never reads it"
done
M=2 study c3 'controller = { type = "computed_torque"; };' \
  "$(sweep '{ key = "controller.omega_n_rad_per_s"; min = 200.0; max = 400.0; levels = 2; }')"
run c3
M=2 study c4 'controller = { type = "computed_torque"; };' "" \
  'uncertain = ( { key = "controller.zeta"; dist = "uniform"; min = 0.8; max = 1.0; } );'
run c4
# the PID's own gains and its type stay fine
M=2 study c5 "" "$(sweep '{ key = "controller.kd_s"; min = 2.0e-3; max = 3.0e-3; levels = 2; }')"
run c5

# --- item 9: --resume compares every setting that changes a row --------------
M=40 study r1 "" "" 'uncertain = ( { key = "actuator.resistance_ohm"; dist = "uniform"; min = 0.9;
  max = 1.1; relative = true; } );'
run r1 --stop-after 2 --threads 1
sed -i 's/relative = true;/relative = false;/' "$TMP/r1.cfg"
cp "$TMP/r1.h5.partial" "$TMP/r1.before"
WANT=2 run r1 --resume
expect_err "changed: key 'uncertain.[0].relative' (true in the file, false now)"
check "a refused resume (relative) leaves the file as it was" cmp -s "$TMP/r1.h5.partial" "$TMP/r1.before"

# --- item 14: --resume checks the rows it carries, and touches nothing when it
# refuses; a renamed candidate is a change ------------------------------------
# tamper FILE FIELD VALUE: sets FIELD of the first done row of candidate 0
tamper() {
  "$PY" - "$@" <<'PY'
import sys, h5py
path, field, value = sys.argv[1], sys.argv[2], float(sys.argv[3])
with h5py.File(path, "r+") as f:
    ds = f["candidates/0/maneuvers"]
    rows = ds[()]
    k = [i for i in range(len(rows)) if rows["done"][i] == 1][0]
    rows[field][k] = value
    ds[k] = rows[k]
    print(k)
PY
}
M=40 study r2
run r2 --stop-after 3 --threads 1
cp "$TMP/r2.h5.partial" "$TMP/r2.good"
for tv in "energy_total 1e6 field 'energy_total' = 1000000 is not the sum of 'energy'" \
  "execution_time -5 field 'execution_time' = -5 is negative" \
  "energy_coil -0.25 field 'energy_coil[0]' = -0.25 is negative" \
  "steps -3 field 'steps' = -3 is negative" \
  "peak_voltage nan field 'peak_voltage[0]' = nan is NaN" \
  "done 2 done = 2"; do
  set -- $tv
  cp "$TMP/r2.good" "$TMP/r2.h5.partial"
  k=$(tamper "$TMP/r2.h5.partial" "$1" "$2")
  cp "$TMP/r2.h5.partial" "$TMP/r2.before"
  WANT=1 run r2 --resume
  shift 2
  expect_err "candidate 0 maneuver $k: $*"
  check "a refused resume ($*) leaves the file as it was" cmp -s "$TMP/r2.h5.partial" "$TMP/r2.before"
done
cp "$TMP/r2.good" "$TMP/r2.h5.partial"
run r2 --resume
"$PY" -c "import h5py, sys; f = h5py.File('$TMP/r2.h5', 'r'); sys.exit(0 if 'last_resumed_utc' in f.attrs else 1)" ||
  fail "an accepted resume does not record last_resumed_utc"
# a renamed candidate
M=40 study r3
run r3 --stop-after 2 --threads 1
sed -i 's/name = "A";/name = "B";/' "$TMP/r3.cfg"
cp "$TMP/r3.h5.partial" "$TMP/r3.before"
WANT=2 run r3 --resume
expect_err "candidate 0 was run as 'A' and is named 'B' now"
check "a refused resume (name) leaves the file as it was" cmp -s "$TMP/r3.h5.partial" "$TMP/r3.before"
# revolute studies resume too (their file has sigma, not sigma_m), and their
# rows pass the checks
M=40 study r4 "" "candidates = ( { name = \"R\"; config = \"$SRC/configs/3rrr.cfg\"; } );"
sed -i 's/range_mm = 3.0;/range_deg = 10.0;/' "$TMP/r4.cfg"
run r4 --stop-after 3 --threads 1
run r4 --resume
# an integer key refuses a fraction (3-RRR elbow = 0.5 was read as +1)
sed 's/^\( *elbow = \).*/\10.5;/' "$SRC/configs/3rrr.cfg" >"$TMP/elbow.cfg"
expect_rc 2 "$POMLAB" model "$TMP/elbow.cfg"
expect_err "elbow.cfg:$(grep -n '^ *elbow = ' "$TMP/elbow.cfg" | cut -d: -f1): key 'geometry.elbow' = 0.5"
expect_err "not a fraction"
sed 's/^\( *elbow = \).*/\1-1.0;/' "$SRC/configs/3rrr.cfg" >"$TMP/elbow.cfg"
expect_rc 0 "$POMLAB" model "$TMP/elbow.cfg"

# --- item 22: the 3-RRR's spherical joint at O is a documented choice ---------
# default: the wrist as built, no central joint (9 revolute joints)
expect_rc 0 "$POMLAB" model "$SRC/configs/3rrr.cfg" --json
json_check "[j['name'] for j in d['mechanism']['joints']] == ['U1', 'W1', 'V1', 'U2', 'W2', 'V2', 'U3', 'W3', 'V3']"
for cj in false true; do
  sed "s/^\( *central_joint = \).*/\1$cj;/" "$SRC/configs/3rrr.cfg" >"$TMP/rrr_$cj.cfg"
  for model in rigid parasitic; do
    expect_rc 0 "$POMLAB" simulate "$TMP/rrr_$cj.cfg" --target 5,-8,3 --joints $model --json
    cp "$TMP/out" "$TMP/sim_${cj}_$model.json"
  done
done
expect_rc 0 "$POMLAB" model "$TMP/rrr_true.cfg" --json
json_check "d['mechanism']['joints'][0]['name'] == 'O' and len(d['mechanism']['joints']) == 10"
# the rigid formulation is the same with or without it (redundant there); the
# parasitic one differs (its springs are the extra stiffness) and stays within
# 2 % of the rigid energy, 1e-3 of its execution time
check "3-RRR central joint: rigid unchanged, parasitic close to rigid" "$PY" - "$TMP" <<'PY'
import json, sys
t = sys.argv[1]
r = {(cj, m): json.load(open("%s/sim_%s_%s.json" % (t, cj, m)))
     for cj in ("false", "true") for m in ("rigid", "parasitic")}
assert r["false", "rigid"]["energy_J"] == r["true", "rigid"]["energy_J"]
assert r["false", "rigid"]["execution_time_s"] == r["true", "rigid"]["execution_time_s"]
assert r["false", "parasitic"]["energy_J"] != r["true", "parasitic"]["energy_J"]
for cj in ("false", "true"):
    e, e0 = r[cj, "parasitic"]["energy_total_J"], r[cj, "rigid"]["energy_total_J"]
    assert abs(e - e0) <= 0.02 * e0, (cj, e, e0)
    x, x0 = r[cj, "parasitic"]["execution_time_s"], r[cj, "rigid"]["execution_time_s"]
    assert abs(x - x0) <= 1e-3 * x0, (cj, x, x0)
PY
# the 3P-S-S/S's joint O is its own: the key is unknown there
sed 's/^\( *mode = "parameters";\)/\1 central_joint = false;/' "$SRC/configs/3pss.cfg" >"$TMP/pss_cj.cfg"
expect_rc 2 "$POMLAB" model "$TMP/pss_cj.cfg"
expect_err "geometry.central_joint"

finish test_settings
