#!/usr/bin/env bash
# The main job of README.md. Sets up and builds, then runs the most complete thing comlearn does
# today: inspect every bundled rock as the estimator sees it (geometry only) beside the truth, and
# estimate each rock's center of mass with the in-process simulator (`--direct`; the LCM path and
# the YuMi loop arrive with comlearn-sim), reporting the error against the truth afterwards.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"
bash scripts/setup.sh default
comlearn=build/default/apps/comlearn/comlearn
echo "== comlearn inspect --truth assets/rocks/*.urdf" >&2
"$comlearn" inspect --truth assets/rocks/*.urdf
for urdf in assets/rocks/*.urdf; do
  echo >&2
  echo "== comlearn estimate $urdf --direct --truth" >&2
  "$comlearn" estimate "$urdf" --direct --truth
done
