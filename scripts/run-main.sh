#!/usr/bin/env bash
# Sets up pomlab on a fresh Debian machine and runs the main job: the paper's
# architecture selection, 3P-S-S/S against 3S-P-S/S on 1000 common Monte-Carlo
# maneuvers each, after a kinematics report of the three shipped architectures;
# three studies (CPU time measured with /usr/bin/time -v on a shared 2-core
# machine, the same figures as README.md):
#   1. configs/paper-exact.cfg: the fast exact model (rigid joints, quasi-static
#      coil), 3.7 s of CPU time;
#   2. configs/paper.cfg: the paper's own model (parasitic joints k_p = 1e6,
#      inductive coil), 28 s of CPU time;
#   3. configs/architectures.cfg: the two against the 3-RRR spherical wrist
#      (rotary voice coils) in orientation space, gains tuned by one
#      criterion, each at the fidelity it earns, 7.2 s of CPU time.
# Results: results/<study>.h5 and results/<study>/summary.md with PNG figures
# (reference outputs in results/reference/<study>/).
# Usage: bash scripts/run-main.sh [extra `pomlab study` options, e.g. --threads 2]
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup.sh
pomlab=./build/cli/pomlab

for cfg in configs/3pss.cfg configs/3sps.cfg configs/3rrr.cfg; do
  echo "== kinematics: $cfg =="
  "$pomlab" workspace "$cfg"
  echo
done

echo "== the paper's study on the fast exact model: configs/paper-exact.cfg =="
"$pomlab" study configs/paper-exact.cfg "$@"
echo
echo "== the paper's study on the paper's model (parasitic joints): configs/paper.cfg =="
"$pomlab" study configs/paper.cfg "$@"
echo
echo "== three architectures in orientation space: configs/architectures.cfg =="
"$pomlab" study configs/architectures.cfg "$@"
