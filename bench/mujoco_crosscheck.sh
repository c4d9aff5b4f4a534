#!/usr/bin/env bash
# Cross-check lib/balance against MuJoCo (docs/physics.md, "Cross-check with MuJoCo").
# usage: bash bench/mujoco_crosscheck.sh BUILD_DIR WORK_DIR [--pivots] [python options...]
# Writes the objects (comlearn-shapegen box, pebble, lumpy, ring, mug, feet3, seeds 1-2, and
# comlearn-rockgen random rocks 1-2; even and uneven each), the placements with lib/balance's
# verdicts (placements_dump), a Python venv with mujoco 4.0.0 and trimesh 5.2.0 from PyPI
# (WORK_DIR/venv, created once), and the MuJoCo replay: WORK_DIR/report.md (tables) and
# WORK_DIR/mujoco.jsonl. --pivots: pivot trials instead (seeds 1-3, bowls too; bench_pivot --edges
# 3 --dump, bench/mujoco_pivots.py --bisect): WORK_DIR/pivots-report.md, mujoco-pivots.jsonl.
# Bench only: nothing of the build or the tests needs Python or MuJoCo.
set -euo pipefail
if [[ $# -lt 2 || $1 == -h || $1 == --help ]]; then
  sed -n '2,10p' "$0" | sed 's/^# \{0,1\}//'
  exit $([[ $# -ge 1 && ($1 == -h || $1 == --help) ]] && echo 0 || echo 2)
fi
if [[ $1 == -* ]]; then
  echo "mujoco_crosscheck.sh: unknown option '$1' (try --help)" >&2
  exit 2
fi
build=$1 work=$2
shift 2
pivots=0
if [[ ${1:-} == --pivots ]]; then
  pivots=1
  shift
fi
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$work"
families=(box pebble lumpy ring mug feet3) count=2
[[ $pivots == 1 ]] && families+=(rim) && count=3 # a box has few edges: 3 for >= 200 placements
for family in "${families[@]}"; do
  "$build/tools/comlearn-shapegen" --family "$family" --seed 1 --count $count \
    --out-dir "$work/objs" >/dev/null
done
"$build/tools/comlearn-rockgen" --random 1 --count $count --out-dir "$work/objs" >/dev/null
if [[ ! -x $work/venv/bin/python ]]; then
  python3 -m venv "$work/venv"
  "$work/venv/bin/pip" install --quiet mujoco==4.0.0 trimesh==5.2.0 # the versions measured
fi
if [[ $pivots == 1 ]]; then
  "$build/bench/bench_pivot" --edges 3 --dump "$work/pivots.jsonl" "$work"/objs/*.urdf >/dev/null
  "$work/venv/bin/python" "$here/mujoco_pivots.py" "$work/pivots.jsonl" --bisect \
    --out "$work/mujoco-pivots.jsonl" "$@" | tee "$work/pivots-report.md"
  exit 0
fi
"$build/bench/placements_dump" "$work"/objs/*.urdf >"$work/placements.jsonl"
"$work/venv/bin/python" "$here/mujoco_crosscheck.py" "$work/placements.jsonl" --lines \
  --out "$work/mujoco.jsonl" "$@" | tee "$work/report.md"
