#!/bin/bash
# test_tradeoff_units.sh POMLAB SOURCE_DIR - `pomlab tradeoff` checks the
# maneuvers' range against the actuator kind as montecarlo and study do
# (pom_doe_maneuvers_check_kinds) and prints targets in the kind's display
# unit: the 3-RRR's default +-3 mm range is refused, a range_deg range is
# printed in deg (issue 18).
set -u
POMLAB=$1
SRC=$2
TMP=$(mktemp -d /tmp/pom_tradeoff_units.XXXXXX)
trap 'rm -rf "$TMP"' EXIT
fail=0
check() { if ! eval "$1"; then echo "FAIL: $1"; fail=1; fi; }
SMALL='tradeoff = { maneuvers = 2; repeats = 1; rtol = [1e-4]; stiffness_N_per_m = [1e6];
             linear_solvers = false; scenes = false; rigid = false; reference_rtol = 1e-8;
             fidelity_maneuvers = 2; };
maneuver = { horizon_ms = 20.0; };'

# the shipped 3-RRR config has no montecarlo range: refused, naming the key
"$POMLAB" tradeoff "$SRC/configs/3rrr.cfg" --quiet > "$TMP/o1" 2> "$TMP/e1"
check '[ $? -eq 2 ]'
check 'grep -q "montecarlo.range_deg" "$TMP/e1"'
check '[ ! -s "$TMP/o1" ]'

# a range in mm for revolute actuators: refused, naming the key to use
sed '/^maneuver = {/,/^};/d' "$SRC/configs/3rrr.cfg" > "$TMP/r.cfg"
cp "$TMP/r.cfg" "$TMP/r_mm.cfg"
printf 'montecarlo = { range_mm = 3.0; };\n%s\n' "$SMALL" >> "$TMP/r_mm.cfg"
"$POMLAB" tradeoff "$TMP/r_mm.cfg" --quiet > /dev/null 2> "$TMP/e2"
check '[ $? -eq 2 ]'
check 'grep -q "montecarlo.range_mm" "$TMP/e2" && grep -q "range_deg" "$TMP/e2"'

# a range in degrees: targets printed in deg, within +-3 deg
printf 'montecarlo = { range_deg = 3.0; };\n%s\n' "$SMALL" >> "$TMP/r.cfg"
"$POMLAB" tradeoff "$TMP/r.cfg" --quiet > "$TMP/o3" 2> "$TMP/e3"
check '[ $? -eq 0 ]'
check '[ $(grep -c "^maneuver [0-9]*: targets .* deg$" "$TMP/o3") -eq 2 ]'
check '! grep -q "^maneuver .* mm$" "$TMP/o3"'
# every printed target within the +-3 deg asked (not +-0.003 of anything)
check 'grep "^maneuver [0-9]*: targets" "$TMP/o3" | sed "s/.*targets //; s/ deg//; s/,//g" |
       awk "{ for (i = 1; i <= 3; ++i) { a = \$i < 0 ? -\$i : \$i; if (a > 3 || a < 0.01) bad = 1 } }
            END { exit bad }"'

# a prismatic mechanism still prints mm
sed '/^maneuver = {/,/^};/d' "$SRC/configs/3pss.cfg" > "$TMP/p.cfg"
printf '%s\n' "$SMALL" >> "$TMP/p.cfg"
"$POMLAB" tradeoff "$TMP/p.cfg" --quiet > "$TMP/o4" 2> "$TMP/e4"
check '[ $? -eq 0 ]'
check '[ $(grep -c "^maneuver [0-9]*: targets .* mm$" "$TMP/o4") -eq 2 ]'
[ $fail -ne 0 ] && { cat "$TMP/e3" "$TMP/e4"; }
exit $fail
