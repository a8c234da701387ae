#!/bin/bash
# test_tradeoff_cli.sh POMLAB SOURCE_DIR - `pomlab tradeoff`: a small sweep
# through a config with a `tradeoff` group, the CSV it writes, the plot, and
# the usage errors (docs/tradeoff.md).
set -u
POMLAB=$1
SRC=$2
TMP=$(mktemp -d /tmp/pom_tradeoff_cli.XXXXXX)
trap 'rm -rf "$TMP"' EXIT
fail=0
check() { if ! eval "$1"; then echo "FAIL: $1"; fail=1; fi; }

sed '/^maneuver = {/,/^};/d' "$SRC/configs/3pss.cfg" > "$TMP/t.cfg"
cat >> "$TMP/t.cfg" <<'CFG'
maneuver = { horizon_ms = 30.0; };
tradeoff = { maneuvers = 1; repeats = 1; rtol = [1e-4]; stiffness_N_per_m = [1e7];
             linear_solvers = false; scenes = false; reference_rtol = 1e-9;
             fidelity_maneuvers = 3; };
CFG
"$POMLAB" tradeoff "$TMP/t.cfg" --csv "$TMP/t.csv" --quiet > "$TMP/out.txt" 2> "$TMP/err.txt"
check '[ $? -eq 0 ]'
check 'grep -q "recommended for 1 % accuracy" "$TMP/out.txt"'
# the rule says how it chose: a selection set and a validation set of another seed
check 'grep -q "selection set (maneuvers 0..2 of seed 20120708" "$TMP/out.txt"'
check 'grep -q "validation set drawn from a different seed (maneuvers 0..2 of seed 20120709" "$TMP/out.txt"'
check 'grep -q "validated on 3 other maneuvers (seed 20120709)" "$TMP/out.txt"'
check '[ ! -s "$TMP/err.txt" ]'
check 'head -1 "$TMP/t.csv" | grep -q "^label,family,n_states,time_s"'
check 'head -1 "$TMP/t.csv" | grep -q ",int_settle,int_energy,int_traj,int_max,"'
check 'grep -q "integ\. = the worst of the three" "$TMP/out.txt"'
check '[ $(wc -l < "$TMP/t.csv") -eq 13 ]'           # header + 12 rows
check '[ $(grep -c ",1$" "$TMP/t.csv") -le 1 ]'      # at most one recommended row
# --accuracy tighter than anything: no recommendation, still exit 0
"$POMLAB" tradeoff "$TMP/t.cfg" --accuracy 1e-9 --quiet > "$TMP/out2.txt" 2>&1
check '[ $? -eq 0 ]'
check 'grep -q "no setting of the ladder meets" "$TMP/out2.txt"'
# the validation set must come from another seed
sed 's/fidelity_maneuvers = 3; };/fidelity_maneuvers = 3; validation_seed = 20120708; };/' "$TMP/t.cfg" > "$TMP/same.cfg"
"$POMLAB" tradeoff "$TMP/same.cfg" --quiet > /dev/null 2> "$TMP/e3.txt"
check '[ $? -eq 2 ] && grep -q "different seed" "$TMP/e3.txt"'
# the plot
if /usr/bin/python3 -c "import matplotlib" 2>/dev/null; then
  /usr/bin/python3 "$SRC/scripts/plot_tradeoff.py" "$TMP/t.png" A="$TMP/t.csv"
  check '[ -s "$TMP/t.png" ]'
fi
# usage and config errors: exit 2 with a message naming the problem
"$POMLAB" tradeoff "$TMP/t.cfg" --accuracy abc > /dev/null 2> "$TMP/e1.txt"
check '[ $? -eq 2 ] && grep -q "accuracy" "$TMP/e1.txt"'
"$POMLAB" tradeoff > /dev/null 2>&1
check '[ $? -eq 2 ]'
sed -i 's/tradeoff = { maneuvers = 1;/tradeoff = { bogus = 1; maneuvers = 1;/' "$TMP/t.cfg"
"$POMLAB" tradeoff "$TMP/t.cfg" --quiet > /dev/null 2> "$TMP/e2.txt"
check '[ $? -eq 2 ] && grep -q "tradeoff.bogus" "$TMP/e2.txt"'
exit $fail
