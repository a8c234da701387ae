#!/bin/sh
# test_uncertain_cli.sh POMLAB SRCDIR WORKDIR
# A study with an `uncertain` group through the command line: the draws are
# stored and do not move the maneuver targets; a stored row equals
# `pomlab simulate` of the candidate with that row's drawn values; threads 1
# and 2 agree; a distribution that reaches an invalid value is a config error
# naming the key; a resume with other draws is refused.
set -eu
POMLAB=$1
SRC=$2
WORK=$3
rm -rf "$WORK"
mkdir -p "$WORK"
study() { # study NAME UNCERTAIN-GROUP
  cat > "$WORK/$1.cfg" <<CFG
name = "$1";
montecarlo = { maneuvers = 10; seed = 4242; range_mm = 3.0; };
study = { override = { joints = { model = "rigid"; }; scene = { coil_inductance = false; }; }; };
$2
candidates = ( { name = "3P-S-S/S"; config = "$SRC/configs/3pss.cfg"; } );
CFG
}
GROUP='uncertain = (
  { key = "actuator.resistance_ohm"; dist = "normal"; mean = 10.0; sd = 1.0; },
  { key = "controller.kp"; dist = "lognormal"; median = 1.0; sigma_ln = 0.3; relative = true; },
  { key = "actuator.force_constant_N_per_A"; dist = "truncated_normal"; mean = 3.8; sd = 0.4;
    min = 3.2; max = 4.4; }
);'
study unc "$GROUP"
study nom ""
run() { "$POMLAB" study "$WORK/$1.cfg" --out "$WORK/$2.h5" --no-plots --no-summary --quiet; }
"$POMLAB" study "$WORK/unc.cfg" --out "$WORK/unc.h5" --threads 2 --no-plots --no-summary --quiet \
  --tabular "$WORK/unc.csv" > "$WORK/unc.txt"
"$POMLAB" study "$WORK/unc.cfg" --out "$WORK/unc1.h5" --threads 1 --no-plots --no-summary --quiet \
  > /dev/null
"$POMLAB" study "$WORK/nom.cfg" --out "$WORK/nom.h5" --threads 2 --no-plots --no-summary --quiet \
  > "$WORK/nom.txt"
grep -q "Robustness" "$WORK/unc.txt"
if grep -q "Robustness" "$WORK/nom.txt"; then
  echo "robustness table without uncertain parameters"; exit 1
fi
# row 4 again with pomlab simulate: the candidate's resolved config with the
# drawn values written in (kp relative: nominal 1.2e4 x draw)
/usr/bin/python3 - "$WORK" "$POMLAB" <<'PY'
import h5py, json, re, subprocess, sys
import numpy as np
work, pomlab = sys.argv[1], sys.argv[2]
u, n, u1 = (h5py.File(f"{work}/{f}.h5", "r") for f in ("unc", "nom", "unc1"))
d = u["uncertain/draws"][()]
assert d.shape == (10, 3), d.shape
assert u["uncertain"].attrs["keys"] in (b"actuator.resistance_ohm,controller.kp,"
                                        b"actuator.force_constant_N_per_A",
                                        "actuator.resistance_ohm,controller.kp,"
                                        "actuator.force_constant_N_per_A")
assert list(u["uncertain/relative"][()]) == [0, 1, 0]
assert np.allclose(u["uncertain/nominal"][0, 1], 1.2e4)
assert np.all((d[:, 2] >= 3.2) & (d[:, 2] <= 4.4))
assert len(set(d[:, 0])) == 10  # a draw per maneuver
# the maneuver targets are those of the study without uncertainty
assert np.array_equal(u["montecarlo/target"][()], n["montecarlo/target"][()])
ru, rn, r1 = (f["candidates/0/maneuvers"][()] for f in (u, n, u1))
assert np.array_equal(ru["target"], rn["target"])
# the draws change the results, and threads 1 and 2 agree bit for bit
assert not np.array_equal(ru["energy_total"], rn["energy_total"])
for field in ("energy_total", "execution_time", "steps"):
    assert np.array_equal(ru[field], r1[field], equal_nan=True), field
k = 4
text = u["candidates/0/config"][()]
text = text.decode() if isinstance(text, bytes) else text
def setkey(text, name, value):
    new, count = re.subn(r"\b%s\s*=\s*[-+0-9.eE]+;" % name, "%s = %r;" % (name, float(value)), text)
    assert count == 1, (name, count)
    return new
text = setkey(text, "resistance_ohm", d[k, 0])
text = setkey(text, "kp", 1.2e4 * d[k, 1])
text = setkey(text, "force_constant_N_per_A", d[k, 2])
open(f"{work}/row4.cfg", "w").write(text)
t = ",".join("%r" % (q * 1e3) for q in ru["target"][k])
out = subprocess.run([pomlab, "simulate", f"{work}/row4.cfg", "--target", t, "--json"],
                     check=True, capture_output=True, text=True).stdout
s = json.loads(out)
for key, field in (("energy_total_J", "energy_total"), ("execution_time_s", "execution_time")):
    want = ru[field][k]
    # simulate prints 9 significant digits
    assert abs(s[key] - want) <= 1e-8 * abs(want), (key, s[key], want)
# the tabular file has the values each row ran with
import pandas as pd
t = pd.read_csv(f"{work}/unc.csv")
assert np.allclose(t["drawn:actuator.resistance_ohm"], d[:, 0], rtol=1e-12)
assert np.allclose(t["drawn:controller.kp"], 1.2e4 * d[:, 1], rtol=1e-12)
assert np.allclose(t["energy_total_J"], ru["energy_total"], rtol=1e-12)
print("uncertain study: draws stored, targets unchanged, row 4 = simulate, tabular columns")
PY
# a distribution that reaches an invalid value: config error naming the key
study bad 'uncertain = ( { key = "actuator.resistance_ohm"; dist = "uniform"; min = -1.0; max = 5.0; } );'
code=0; run bad bad > /dev/null 2> "$WORK/bad.err" || code=$?
[ "$code" -eq 2 ] || { echo "invalid draw range: exit $code, want 2"; exit 1; }
grep -q "uncertain.\[0\]" "$WORK/bad.err"
grep -q "resistance_ohm" "$WORK/bad.err"
[ ! -e "$WORK/bad.h5" ] || { echo "a file was written for a config error"; exit 1; }
# integer keys cannot take drawn values
study int 'uncertain = ( { key = "solver.max_steps"; dist = "uniform"; min = 1000.0; max = 2000.0; } );'
code=0; run int int > /dev/null 2> "$WORK/int.err" || code=$?
[ "$code" -eq 2 ] && grep -q "integer key" "$WORK/int.err"
# a misspelt key is an unknown key of the candidate
study typo 'uncertain = ( { key = "actuator.resistanse_ohm"; dist = "uniform"; min = 9.0; max = 11.0; } );'
code=0; run typo typo > /dev/null 2> "$WORK/typo.err" || code=$?
[ "$code" -eq 2 ] && grep -q "resistanse_ohm" "$WORK/typo.err"
# resume with another distribution is refused, naming the parameter
"$POMLAB" study "$WORK/unc.cfg" --out "$WORK/res.h5" --stop-after 3 --no-plots --no-summary \
  --quiet > /dev/null 2>&1
sed -i 's/sd = 1.0/sd = 0.9/' "$WORK/unc.cfg"
code=0; "$POMLAB" study "$WORK/unc.cfg" --out "$WORK/res.h5" --resume --no-plots --no-summary \
  --quiet > /dev/null 2> "$WORK/res.err" || code=$?
[ "$code" -ne 0 ] && grep -q "changed: key 'uncertain.\[0\].sd' of 'actuator.resistance_ohm' (1 in the file, 0.9 now)" "$WORK/res.err"
# and a study without uncertainty does not resume a file with it
code=0; "$POMLAB" study "$WORK/nom.cfg" --out "$WORK/res.h5" --resume --no-plots --no-summary \
  --quiet > /dev/null 2> "$WORK/res2.err" || code=$?
[ "$code" -ne 0 ] && grep -q "uncertain" "$WORK/res2.err"
echo "test_uncertain_cli: ok"
