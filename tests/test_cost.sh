#!/usr/bin/env bash
# test_cost.sh - long or large work said before it starts, and what cannot
# fit in memory refused with the keys that size it (issue 22, items 15 and
# 16): study, montecarlo and sensitivity announce their runs, memory, file
# size and time (from a short calibration); simulate announces large traces;
# a run whose tables cannot fit in memory is a config error (exit 2) before
# any work; a killed run's PATH.tmp.<pid> does not stay for good.
# Usage: test_cost.sh PATH/TO/pomlab SOURCE_DIR
set -u
POMLAB=$1
SRC=$2
. "$(dirname "$0")/cli_lib.sh"

cd "$TMP" || exit 1
cp "$SRC/configs/3pss.cfg" 3pss.cfg
RIGID='study = { override = { joints = { model = "rigid"; }; scene = { coil_inductance = false; }; }; };'

# --- item 16: too large for memory: the size, the runs, the keys; exit 2 at once --
cat >huge.cfg <<CFG
name = "huge";
montecarlo = { maneuvers = 100000000; seed = 3; range_mm = 3.0; };
$RIGID
candidates = { sweep = "grid"; base = ( { name = "A"; config = "3pss.cfg"; } );
  factors = ( { key = "geometry.platform_radius_mm"; min = 10.0; max = 18.0; levels = 32; },
              { key = "controller.kp"; min = 1.0e4; max = 1.3e4; levels = 32; } ); };
CFG
expect_rc 2 "$POMLAB" study huge.cfg --out huge.h5 --quiet --no-plots
expect_err "pomlab study: config: huge.cfg: 1024 candidate(s) x 100000000 maneuvers = 1.024e+11 runs need about"
expect_err "of memory"
expect_err "more than this machine's"
expect_err "lower montecarlo.maneuvers or the number of candidates"
check "refused before any work: no results file" [ ! -e huge.h5 ] && [ ! -e huge.h5.partial ]
check "no 'out of memory'" bash -c "! grep -q 'out of memory' '$TMP/err'"
# sensitivity: samples = 2^20 with 1000 maneuvers per sample
sed -e 's/samples = 512;/samples = 1048576;/' -e 's/maneuvers = 1; /maneuvers = 1000;/' \
  "$SRC/configs/sensitivity.cfg" >sbig.cfg
expect_rc 2 "$POMLAB" sensitivity sbig.cfg --out sbig.h5 --quiet --no-plots
expect_err "pomlab sensitivity: config: sbig.cfg: 8388608 design rows (sensitivity.samples N x (inputs + 2)) x 1000 maneuver(s) (sensitivity.maneuvers) x 1 candidate(s) = 8.389e+09 runs need about"
expect_err "lower sensitivity.samples, sensitivity.maneuvers or the candidates"
check "sensitivity refused before any work" [ ! -e sbig.h5 ]

# --- item 15: a long study is announced before it starts, with a measured time ---
cat >long.cfg <<CFG
name = "long";
montecarlo = { maneuvers = 100000; seed = 3; range_mm = 3.0; };
candidates = ( { name = "A"; config = "3pss.cfg"; } );
CFG
expect_rc 0 "$POMLAB" study long.cfg --out long.h5 --stop-after 2 --no-plots --no-summary
expect_err "pomlab study: long: 1 candidate(s) x 100000 maneuvers = 1e+05 runs; memory about"
expect_err "results file about"
expect_err "ms per run, measured on a few runs"
check "announced before the first progress line" \
  bash -c "tr '\r' '\n' <'$TMP/err' | grep -m1 -v '^$' | grep -q '^pomlab study: long:'"
expect_rc 0 "$POMLAB" study long.cfg --out long2.h5 --stop-after 2 --no-plots --no-summary --quiet
check "--quiet: no announcement" bash -c "! grep -q 'runs; memory' '$TMP/err'"
# a small study is not announced (and not calibrated)
printf 'name = "small";\nmontecarlo = { maneuvers = 3; seed = 3; };\n%s\n%s\n' "$RIGID" \
  'candidates = ( { name = "A"; config = "3pss.cfg"; } );' >small.cfg
expect_rc 0 "$POMLAB" study small.cfg --out small.h5 --no-plots --no-summary
check "small study: no announcement" bash -c "! grep -q 'runs; memory' '$TMP/err'"
# montecarlo: the same announcement (it stops at SIGINT, keeping what it did)
expect_rc 124 timeout -s INT 5 "$POMLAB" montecarlo 3pss.cfg --n 100000 --threads 1
expect_err "pomlab montecarlo: 3pss: 1 candidate(s) x 100000 maneuvers = 1e+05 runs; memory about"
expect_err "on 1 thread(s)"
# sensitivity: 2^16 base samples, announced before the runs
sed -e 's/samples = 512;/samples = 65536;/' "$SRC/configs/sensitivity.cfg" >smed.cfg
expect_rc 124 timeout 5 "$POMLAB" sensitivity smed.cfg --out smed.h5 --no-plots --threads 1
expect_err "pomlab sensitivity: sensitivity: 524288 design rows x 1 maneuver(s) x 1 candidate(s) = 5.243e+05 runs; memory about"
expect_err "ms per run, measured on a few runs"

# --- item 15: large traces announced; too large for memory refused --------------
sed 's/^\( *output_dt_ms *= *\)[^;]*;/\10.00025;/' 3pss.cfg >tr.cfg
expect_rc 1 "$POMLAB" simulate tr.cfg --target 1,1,1 --joints rigid --out nosuch/tr.csv
expect_err "pomlab simulate: traces of 4e+05 samples (maneuver.horizon_ms = 100 / maneuver.output_dt_ms = 0.00025): memory about 86.4 MB, nosuch/tr.csv about 172 MB"
if grep -qa __asan_init "$(dirname "$POMLAB")/pomlab-full"; then
  echo "(sanitizer build: the ulimit -v check is skipped)"
else
  sed 's/^\( *output_dt_ms *= *\)[^;]*;/\11.0e-5;/' 3pss.cfg >tr7.cfg
  expect_rc 2 bash -c "ulimit -v 1500000; exec '$POMLAB' simulate tr7.cfg --target 1,1,1 --out tr7.csv"
  expect_err "pomlab simulate: config: tr7.cfg: traces of 1e+07 samples (maneuver.horizon_ms = 100 / maneuver.output_dt_ms = 1e-05) need about 2.16 GB of memory, more than this machine's"
  expect_err "raise maneuver.output_dt_ms or shorten the horizon"
  check "no trace written" [ ! -e tr7.csv ]
fi

# --- item 15: a killed run's temporary file does not stay for good ---------------
sh -c 'exit 0' &
dead=$!
wait $dead
sleep 1000 &
alive=$!
touch "trace.csv.tmp.$dead" "trace.csv.tmp.$alive" trace.csv.tmp.notapid
expect_rc 0 "$POMLAB" simulate 3pss.cfg --target 1,1,1 --joints rigid --out trace.csv
check "the trace is written" [ -s trace.csv ]
check "a dead process's temporary file is removed" [ ! -e "trace.csv.tmp.$dead" ]
check "a running process's temporary file is kept" [ -e "trace.csv.tmp.$alive" ]
check "other names are kept" [ -e trace.csv.tmp.notapid ]
kill "$alive"
# a real kill -9 while the table is written leaves a temporary file, removed by
# the next run to the same path
sed 's/^\( *output_dt_ms *= *\)[^;]*;/\10.0005;/' 3pss.cfg >k.cfg
"$POMLAB" simulate k.cfg --target 1,1,1 --joints rigid --out killed.csv >/dev/null 2>&1 &
victim=$!
for _ in $(seq 200); do
  ls killed.csv.tmp.* >/dev/null 2>&1 && break
  sleep 0.05
done
kill -9 "$victim" 2>/dev/null
wait "$victim" 2>/dev/null
if ls killed.csv.tmp.* >/dev/null 2>&1; then
  expect_rc 0 "$POMLAB" simulate 3pss.cfg --target 1,1,1 --joints rigid --out killed.csv
  check "the killed run's temporary file is gone" bash -c "! ls '$TMP'/killed.csv.tmp.* 2>/dev/null"
else
  echo "(the killed run finished or had not started its table: nothing to clean)"
fi

finish test_cost
