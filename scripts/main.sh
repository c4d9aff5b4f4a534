#!/usr/bin/env bash
# The main job of README.md. Sets up and builds, then runs the most complete thing comlearn does
# today: inspect every bundled rock as the estimator sees it (geometry only) beside the truth, then
# estimate each rock's center of mass over LCM: `--spawn-sim` starts comlearn-sim (the YuMi
# controller and world stand-in), every placement is planned for the YuMi and driven through
# YUMI_COMMAND / YUMI_STATUS / OBJECT_STATE; the truth is read only afterwards, for the error.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"
bash scripts/setup.sh default
comlearn=build/default/apps/comlearn/comlearn
echo "== comlearn inspect --truth assets/rocks/*.urdf" >&2
"$comlearn" inspect --truth assets/rocks/*.urdf
for urdf in assets/rocks/*.urdf; do
  echo >&2
  echo "== comlearn estimate $urdf --spawn-sim --truth" >&2
  "$comlearn" estimate "$urdf" --spawn-sim --truth
done
