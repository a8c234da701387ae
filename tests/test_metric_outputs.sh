#!/bin/sh
# test_metric_outputs.sh POMLAB SCHEMA_DUMP WORKDIR
# Every metric declared in POM_DYN_METRICS_LIST appears in every output: the
# HDF5 maneuvers compound (and /statistics/<stat> for reduced ones), the JSON
# of `pomlab simulate` and of `pomlab study`/`montecarlo`, summary.md and the
# /metrics attributes of `pomlab simulate --out F.h5` (equal to its JSON).
set -eu
POMLAB=$1
DUMP=$2
WORK=$3
rm -rf "$WORK"
mkdir -p "$WORK"
"$DUMP" > "$WORK/schema.json"
"$POMLAB" simulate configs/3pss.cfg --target 1,-2,0.5 --json --out "$WORK/simulate.h5" \
  > "$WORK/simulate.json"
"$POMLAB" study tests/doe_study_small.cfg --out "$WORK/s.h5" --threads 2 --no-plots --quiet \
  --json > "$WORK/study.json"
"$POMLAB" montecarlo configs/3pss.cfg --n 3 --seed 5 --quiet --json > "$WORK/mc.json"
/usr/bin/python3 tests/test_metric_outputs.py "$WORK/schema.json" "$WORK/simulate.json" \
  "$WORK/study.json" "$WORK/mc.json" "$WORK/s.h5" "$WORK/s/summary.md" "$WORK/simulate.h5"
