#!/usr/bin/env bash
# The main job of README.md. Sets up and builds, then runs the most complete thing comlearn does
# today: inspect every bundled rock as the estimator sees it (geometry only) beside the truth the
# simulator holds. It grows into the full run (simulator, LCM recording, estimates, stack) as the
# estimator lands.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"
bash scripts/setup.sh default
echo "== comlearn inspect --truth assets/rocks/*.urdf" >&2
build/default/apps/comlearn/comlearn inspect --truth assets/rocks/*.urdf
