#!/usr/bin/env bash
# Sets up pomlab on a fresh Debian machine and runs the main job: the paper's
# architecture selection (configs/paper.cfg: 3P-S-S/S against 3S-P-S/S, 1000
# Monte-Carlo maneuvers each), after a kinematics report of both shipped
# architectures. Results: results/paper.h5, results/paper/summary.md + PNGs.
# Usage: bash scripts/run-main.sh [extra `pomlab study` options, e.g. --threads 2]
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup.sh
pomlab=./build/cli/pomlab

for cfg in configs/3pss.cfg configs/3sps.cfg; do
  echo "== kinematics: $cfg =="
  "$pomlab" workspace "$cfg"
  echo
done

echo "== the paper's study: configs/paper.cfg =="
"$pomlab" study configs/paper.cfg "$@"
