#!/bin/sh
# test_sensitivity_cli.sh POMLAB SRCDIR WORKDIR
# pomlab sensitivity on a small exact-model config: a parameter that cannot
# act on the output (the solver's largest step, 1-2 s, far above any step
# of a 0.1 s horizon) gets indices 0 and Morris mu* 0; the derivative time
# dominates the execution time (as configs/sensitivity.cfg finds); HDF5
# layout; the same outputs with 1 and 2 threads; a non-HDF5 file at the
# output path is replaced; config errors name the key.
set -eu
POMLAB=$1
SRC=$2
WORK=$3
rm -rf "$WORK"
mkdir -p "$WORK"
cat > "$WORK/s.cfg" <<CFG
name = "s";
montecarlo = { maneuvers = 1; seed = 20120708; range_mm = 3.0; };
study = { override = { joints = { model = "rigid"; }; scene = { coil_inductance = false; }; }; };
uncertain = (
  { key = "controller.kd_s"; dist = "uniform"; min = 0.8; max = 1.2; relative = true; },
  { key = "solver.max_step_ms"; dist = "uniform"; min = 1000.0; max = 2000.0; },
  { key = "actuator.resistance_ohm"; dist = "uniform"; min = 0.95; max = 1.05; relative = true; }
);
sensitivity = { method = "sobol"; samples = 32; bootstrap = 200; metric = "execution_time"; };
candidates = ( { name = "3P-S-S/S"; config = "$SRC/configs/3pss.cfg"; } );
CFG
sed 's/method = "sobol"; samples = 32; bootstrap = 200;/method = "morris"; trajectories = 6;/' \
  "$WORK/s.cfg" > "$WORK/m.cfg"
echo "not an HDF5 file" > "$WORK/s.h5"
"$POMLAB" sensitivity "$WORK/s.cfg" --out "$WORK/s.h5" --threads 2 --quiet --json > "$WORK/s.json"
"$POMLAB" sensitivity "$WORK/s.cfg" --out "$WORK/s1.h5" --threads 1 --quiet --no-plots > "$WORK/s1.txt"
"$POMLAB" sensitivity "$WORK/m.cfg" --out "$WORK/m.h5" --quiet --no-plots > "$WORK/m.txt"
grep -q "controller.kd_s" "$WORK/s1.txt"
[ -s "$WORK/s.png" ] || { echo "no figure"; exit 1; }
/usr/bin/python3 - "$WORK" <<'PY'
import h5py, json, sys
import numpy as np
w = sys.argv[1]
s = json.load(open(f"{w}/s.json"))
f, f1, m = (h5py.File(f"{w}/{n}.h5", "r") for n in ("s", "s1", "m"))
assert f.attrs["method"] in ("sobol", b"sobol")
assert f["design"].shape == (32 * 5, 3) and f["outputs"].shape == (1, 160)
assert np.array_equal(f["outputs"][()], f1["outputs"][()])  # threads 1 and 2
v = f["values"][()]
assert np.all((v[:, 1] >= 1000.0) & (v[:, 1] <= 2000.0))
S1, ST = f["sobol/S1"][0], f["sobol/ST"][0]
# the solver's largest step (>= 1 s, never reached in a 0.1 s horizon)
# cannot change the output: its indices vanish
assert abs(S1[1]) < 1e-9 and abs(ST[1]) < 1e-9, (S1, ST)
# tau_D dominates (configs/sensitivity.cfg finds S1 ~ 1 with 512 samples)
assert ST[0] > 0.8 and ST[0] > 10 * ST[2], ST
c = s["candidates"][0]["indices"]
assert abs(c[0]["ST"] - ST[0]) < 1e-6 and c[0]["ST_ci"][0] <= ST[0] <= c[0]["ST_ci"][1]
mu = m["morris/mu_star"][0]
assert m["design"].shape == (6 * 4, 3)
assert mu[1] == 0 and mu[0] > 10 * mu[2], mu
print("sensitivity cli: ok")
PY
# --candidate: the second candidate of a two-level kd_s sweep is the config's
# own tau_D (3 ms), so its outputs equal the single-candidate run's (same
# design, same relative draws); by name or by position alike
sed 's|^candidates = .*|candidates = { sweep = "grid"; base = ( { name = "3P-S-S/S"; config = "'"$SRC"'/configs/3pss.cfg"; } ); factors = ( { key = "controller.kd_s"; min = 0.002; max = 0.003; levels = 2; } ); };|' \
  "$WORK/s.cfg" > "$WORK/two.cfg"
"$POMLAB" sensitivity "$WORK/two.cfg" --candidate 2 --out "$WORK/two.h5" --quiet --no-plots > /dev/null
"$POMLAB" sensitivity "$WORK/two.cfg" --candidate "3P-S-S/S kd_s=0.003" --out "$WORK/twon.h5" \
  --quiet --no-plots --json > "$WORK/twon.json"
/usr/bin/python3 - "$WORK" <<'PY'
import h5py, json, sys
import numpy as np
w = sys.argv[1]
one, two, twon = (h5py.File(f"{w}/{n}.h5", "r") for n in ("s1", "two", "twon"))
assert two["outputs"].shape == (1, 160)
assert np.array_equal(one["outputs"][()], two["outputs"][()])
assert np.array_equal(two["outputs"][()], twon["outputs"][()])
c = json.load(open(f"{w}/twon.json"))["candidates"]
assert len(c) == 1 and c[0]["name"] == "3P-S-S/S kd_s=0.003", c
PY
code=0; "$POMLAB" sensitivity "$WORK/two.cfg" --candidate 3 --quiet > /dev/null 2> "$WORK/e0" || code=$?
[ "$code" -eq 2 ] && grep -q "candidate '3' is not in study" "$WORK/e0" && grep -q "kd_s=0.002" "$WORK/e0"
# config errors: no uncertain group, an unknown sensitivity key, a bad metric
grep -v "^uncertain\|^  {" "$WORK/s.cfg" | grep -v "^);" > "$WORK/nounc.cfg"
code=0; "$POMLAB" sensitivity "$WORK/nounc.cfg" --quiet > /dev/null 2> "$WORK/e1" || code=$?
[ "$code" -eq 2 ] && grep -q "uncertain" "$WORK/e1"
sed 's/metric = "execution_time";/metric = "speed";/' "$WORK/s.cfg" > "$WORK/bad.cfg"
code=0; "$POMLAB" sensitivity "$WORK/bad.cfg" --quiet > /dev/null 2> "$WORK/e2" || code=$?
[ "$code" -eq 2 ] && grep -q "sensitivity.metric" "$WORK/e2"
sed 's/samples = 32;/samples = 32; sample = 3;/' "$WORK/s.cfg" > "$WORK/typo.cfg"
code=0; "$POMLAB" sensitivity "$WORK/typo.cfg" --quiet > /dev/null 2> "$WORK/e3" || code=$?
[ "$code" -eq 2 ] && grep -q "sensitivity.sample" "$WORK/e3"
echo "test_sensitivity_cli: ok"
