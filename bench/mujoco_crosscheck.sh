#!/usr/bin/env bash
# Cross-check lib/balance against MuJoCo (docs/physics.md, "Cross-check with MuJoCo").
# usage: bash bench/mujoco_crosscheck.sh BUILD_DIR WORK_DIR [mujoco_crosscheck.py options...]
# Writes the objects (comlearn-shapegen box, pebble, lumpy, ring, mug, feet3, seeds 1-2, and
# comlearn-rockgen random rocks 1-2; even and uneven each), the placements with lib/balance's
# verdicts (placements_dump), a Python venv with mujoco 4.0.0 and trimesh 5.2.0 from PyPI
# (WORK_DIR/venv, created once), and the MuJoCo replay: WORK_DIR/report.md (tables) and
# WORK_DIR/mujoco.jsonl. Bench only: nothing of the build or the tests needs Python or MuJoCo.
set -euo pipefail
if [[ $# -lt 2 || $1 == -h || $1 == --help ]]; then
  sed -n '2,8p' "$0" | sed 's/^# \{0,1\}//'
  exit $([[ $# -ge 1 && ($1 == -h || $1 == --help) ]] && echo 0 || echo 2)
fi
if [[ $1 == -* ]]; then
  echo "mujoco_crosscheck.sh: unknown option '$1' (try --help)" >&2
  exit 2
fi
build=$1 work=$2
shift 2
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$work"
for family in box pebble lumpy ring mug feet3; do
  "$build/tools/comlearn-shapegen" --family "$family" --seed 1 --count 2 --out-dir "$work/objs" >/dev/null
done
"$build/tools/comlearn-rockgen" --random 1 --count 2 --out-dir "$work/objs" >/dev/null
"$build/bench/placements_dump" "$work"/objs/*.urdf >"$work/placements.jsonl"
if [[ ! -x $work/venv/bin/python ]]; then
  python3 -m venv "$work/venv"
  "$work/venv/bin/pip" install --quiet mujoco==4.0.0 trimesh==5.2.0 # the versions measured
fi
"$work/venv/bin/python" "$here/mujoco_crosscheck.py" "$work/placements.jsonl" --lines \
  --out "$work/mujoco.jsonl" "$@" | tee "$work/report.md"
