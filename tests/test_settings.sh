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

# an integer key refuses a fraction (3-RRR elbow = 0.5 was read as +1)
sed 's/^\( *elbow = \).*/\10.5;/' "$SRC/configs/3rrr.cfg" >"$TMP/elbow.cfg"
expect_rc 2 "$POMLAB" model "$TMP/elbow.cfg"
expect_err "elbow.cfg:$(grep -n '^ *elbow = ' "$TMP/elbow.cfg" | cut -d: -f1): key 'geometry.elbow' = 0.5"
expect_err "not a fraction"
sed 's/^\( *elbow = \).*/\1-1.0;/' "$SRC/configs/3rrr.cfg" >"$TMP/elbow.cfg"
expect_rc 0 "$POMLAB" model "$TMP/elbow.cfg"

finish test_settings
