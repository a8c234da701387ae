#!/usr/bin/env bash
# test_catalog_sim.sh - one `pomlab simulate CONFIG --json` per file of
# catalog/ (its run config as test_catalog.c finds it: configs/catalog/<stem>.cfg,
# else configs/<stem>.cfg with architecture = the file's name) on the rigid
# and on the parasitic joint model (and `pomlab model --json` parses): the run succeeds and its energy audit
# closes, energy_balance_error < 1e-3 (the bound of test_dynamics_cli.sh for
# the shipped designs). Targets: 5, -3, 2 deg for rotary actuators (a
# quarter of the +-30 deg range or less), 2, -1, 1 mm for linear ones (a
# third of the +-6 mm stroke or less).
POMLAB=$1
SRC=$2
. "$SRC/tests/cli_lib.sh"

n=0
for arch in "$SRC"/catalog/*.arch; do
  stem=$(basename "$arch" .arch)
  name=$(sed -n 's/^name = "\(.*\)";$/\1/p' "$arch")
  cfg="$SRC/configs/catalog/$stem.cfg"
  [ -f "$cfg" ] || cfg="$SRC/configs/$stem.cfg"
  checks=$((checks + 1))
  if [ ! -f "$cfg" ] || [ -z "$name" ]; then
    fail "$arch: no name or no run config"
    continue
  fi
  sed "s/^architecture = \".*\";/architecture = \"$name\";/" "$cfg" >"$TMP/$stem.cfg"
  if grep -q '^actuator = "rotary";' "$arch"; then target=5,-3,2; else target=2,-1,1; fi
  # the model as JSON parses (a file's type has design values but no points)
  expect_rc 0 "$POMLAB" model "$TMP/$stem.cfg" --json
  json_check 'd["architecture"] == "'"$name"'" and "design" in d["geometry"]'
  for joints in rigid parasitic; do
    expect_rc 0 "$POMLAB" simulate "$TMP/$stem.cfg" --target "$target" --joints "$joints" --json
    e=$("$PY" -c "import json; print(json.load(open('$TMP/out'))['energy_balance_error'])" 2>/dev/null)
    echo "$stem ($name) $joints: energy_balance_error $e"
    json_check 'd["energy_balance_error"] is not None and 0.0 <= d["energy_balance_error"] < 1e-3'
  done
  n=$((n + 1))
done
check "at least 10 catalog files" [ "$n" -ge 10 ]
finish test_catalog_sim
