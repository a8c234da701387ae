#!/usr/bin/env bash
# test_arch_file_cli.sh - architecture files through the command line
# (docs/architecture-files.md section 4): the catalog's types are listed
# with their parameters, a shipped config renamed to a catalog type gives
# the hand-coded type's q and Jacobian, a user's file is registered from
# $POMLAB_ARCHITECTURES, and a broken one stops pomlab naming its file.
POMLAB=$1
SRC=$2
. "$SRC/tests/cli_lib.sh"

expect_rc 0 "$POMLAB" model --list-architectures
expect_in "$TMP/out" "3PSS-table"
expect_in "$TMP/out" "geometry.limb_lean_deg"
expect_rc 0 "$POMLAB" model --list-architectures --json
# every file of catalog/ listed, after the hand-coded types, by name
cat_names=$(sed -n 's/^name = "\(.*\)";$/"\1"/p' "$SRC"/catalog/*.arch | sort | paste -sd, -)
json_check 'sorted(a["name"] for a in d["architectures"][3:]) == sorted(['"$cat_names"']) and len(['"$cat_names"']) >= 10'

for arch in 3pss 3sps 3rrr; do
  up=$(echo "$arch" | tr a-z A-Z)
  sed "s/^architecture = \"$up\";/architecture = \"$up-table\";/" "$SRC/configs/$arch.cfg" \
    >"$TMP/$arch-table.cfg"
  cp "$SRC/configs/$arch.cfg" "$TMP/$arch.cfg"
  expect_rc 0 "$POMLAB" ik "$TMP/$arch.cfg" --euler-zyx 7.3,-4.1,2.9 --json
  cp "$TMP/out" "$TMP/hand.json"
  expect_rc 0 "$POMLAB" ik "$TMP/$arch-table.cfg" --euler-zyx 7.3,-4.1,2.9 --json
  json_check "d['architecture'] == '$up-table'"
  checks=$((checks + 1))
  $PY - "$TMP/hand.json" "$TMP/out" <<'PYEOF' || fail "$arch: table IK differs from the hand-coded"
import json, sys
a, b = (json.load(open(f)) for f in sys.argv[1:3])
s = max(abs(x) for r in a["jacobian"] for x in r)
ok = all(abs(x - y) <= 1e-12 * s for x, y in zip(a["q"], b["q"]))
ok &= all(abs(x - y) <= 1e-12 * s for r, t in zip(a["jacobian"], b["jacobian"]) for x, y in zip(r, t))
sys.exit(0 if ok else 1)
PYEOF
  expect_rc 0 "$POMLAB" model "$TMP/$arch-table.cfg" --json
done

# a user's own file: the list form of the 3PSS
POMLAB_ARCHITECTURES="$SRC/tests/arch_per_limb.arch" expect_rc 0 "$POMLAB" model --list-architectures
expect_in "$TMP/out" "3PSS-per-limb"
# a broken file stops every command, naming the file, line and key
sed 's/B = "C - r\*L\*l"/B = "C - r*LL*l"/' "$SRC/catalog/3pss.arch" | sed 's/3PSS-table/3PSS-broken/' \
  >"$TMP/broken.arch"
POMLAB_ARCHITECTURES="$TMP/broken.arch" expect_rc 2 "$POMLAB" model --list-architectures
expect_in "$TMP/err" "broken.arch:47: key 'limbs.let.B' = \"C - r*LL*l\": column 7: unknown name (at 'LL')"
finish test_arch_file_cli
