#!/usr/bin/env bash
# test_cli_long.sh - long work is bounded and visible: the workspace pose
# budget (a search stopped at it, grids above it refused up front with the
# key and value), and the progress lines a log gets.
# Usage: test_cli_long.sh PATH/TO/pomlab SOURCE_DIR
set -u
POMLAB=$1
SRC=$2
. "$(dirname "$0")/cli_lib.sh"

# ws_cfg KEY=VALUE... : configs/3pss.cfg with workspace keys replaced -> $TMP/ws.cfg
ws_cfg() {
  cp "$SRC/configs/3pss.cfg" "$TMP/ws.cfg"
  local kv
  for kv in "$@"; do
    sed -i "s/^\( *\)${kv%%=*} = [^;]*;/\1${kv%%=*} = ${kv#*=};/" "$TMP/ws.cfg"
  done
}

# --- the documented finest step no longer runs for days -----------------------------
# 0.01 deg with a budget of 1e4 poses: the cube up to shell 10 (21^3 = 9261
# poses) fits, shell 11 (23^3) does not: half-width at least 0.1 deg.
ws_cfg resolution_deg=0.01
sed -i 's/^\( *\)check_limits = true;/&\n\1max_poses = 1e4;/' "$TMP/ws.cfg"
expect_rc 0 "$POMLAB" workspace "$TMP/ws.cfg" --json
json_check "d['budget_reached'] is True and d['capped'] is False and d['max_poses'] == 1e4"
json_check "abs(d['half_width_deg'] - 0.1) < 1e-9 and d['poses_evaluated'] == 9261"
json_check "d['first_failure'] is None"
expect_in "$TMP/err" "is a lower bound"
expect_rc 0 "$POMLAB" workspace "$TMP/ws.cfg"
expect_in "$TMP/out" "at least +-0.1 deg (search stopped at workspace.max_poses)"

# --- grids known in advance are refused above the budget, before any work ----------
# map: (2 * 2000 + 1)^3 = 6.4e10 poses at 0.01 deg over +-20 deg
ws_cfg map_resolution_deg=0.01
expect_rc 2 "$POMLAB" workspace "$TMP/ws.cfg" --map "$TMP/map.csv"
expect_in "$TMP/err" "ws.cfg"
expect_in "$TMP/err" "workspace.map_resolution_deg"
expect_in "$TMP/err" "6.4e+10 pose evaluations"
expect_in "$TMP/err" "workspace.max_poses = 1e+08"
checks=$((checks + 1))
[ ! -e "$TMP/map.csv" ] || fail "a refused map was written"
# without --map the map settings cost nothing
expect_rc 0 "$POMLAB" workspace "$TMP/ws.cfg"
# GCI over a given region: (2 * 10 / 0.01)^3 = 8e9 cells
ws_cfg resolution_deg=0.01 gci_half_width_deg=10.0
expect_rc 2 "$POMLAB" workspace "$TMP/ws.cfg"
expect_in "$TMP/err" "workspace.resolution_deg"
expect_in "$TMP/err" "workspace.gci_half_width_deg = 10 deg"
expect_in "$TMP/err" "8e+09 pose evaluations"
# the budget itself is range-checked
ws_cfg
sed -i 's/^\( *\)check_limits = true;/&\n\1max_poses = 10.0;/' "$TMP/ws.cfg"
expect_rc 2 "$POMLAB" workspace "$TMP/ws.cfg"
expect_in "$TMP/err" "workspace.max_poses"

# --- every maneuver has a wall-clock limit, 60 s unless the config says ---------------
expect_rc 0 "$POMLAB" model "$SRC/configs/3pss.cfg" --json
json_check "d['solver']['max_wall_s'] == 60"
expect_rc 0 "$POMLAB" model "$SRC/configs/3pss.cfg"
expect_in "$TMP/out" "max_wall_s 60"
# a limit hit is the maneuver's status with its reason (checked every 16
# steps: 1 us is over before the 16th), not a crash; a study counts it failed
sed 's/^\( *\)max_steps = \([0-9]*\);/&\n\1max_wall_s = 1e-6;/' "$SRC/configs/3pss.cfg" >"$TMP/wall.cfg"
expect_rc 1 "$POMLAB" simulate "$TMP/wall.cfg" --target 1,2,3 --json
json_check "d['status'] == 'POM_ERR_SOLVER' and 'wall-clock budget 1e-06 s' in d['reason']"
expect_rc 0 "$POMLAB" montecarlo "$TMP/wall.cfg" --n 3 --out "$TMP/wall.h5" --json
expect_rc 0 "$PY" -c "
import h5py, sys
with h5py.File('$TMP/wall.h5') as f:
    c = f['candidates'][list(f['candidates'])[0]]
    sys.exit(0 if c.attrs['solver_max_wall_s'] == 1e-6 else 1)"

echo "test_cli_long: $checks checks, $fails failed"
[ "$fails" = 0 ]
