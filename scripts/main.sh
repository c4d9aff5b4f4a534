#!/usr/bin/env bash
# The main job of README.md: the paper's experiments and the rock stack, end to end, over LCM.
#
#   1. set up and build (scripts/setup.sh);
#   2. start comlearn-sim (the YuMi controller and world stand-in) on a private LCM URL, and two
#      recorders under out/lcm/: lcm-logger for every robot's COM_* records, `comlearn record`
#      for every channel (lcm-logger drops messages under load, docs/replay.md);
#   3. `comlearn experiments --sims N`: every bundled rock x every policy, noiseless over LCM with
#      YuMi placement on N comlearn-sims of its own (robots R0_ .. on the same URL), then with the
#      noise profile over several seeds (in-process, same physics and seeding as comlearn-sim);
#      Table I and Fig. 2 under out/experiments/;
#   4. `comlearn stack`: the three uneven rocks stacked on their CoMs learned over LCM, then on
#      bounding-box centers and on the true CoMs, each simulated for 5 s; side views under out/;
#   5. stop the loggers and the simulator, check that both logs hold every trial record
#      (`comlearn logcheck`, out/lcm/logcheck_*.txt), write out/report.md (with one in-process
#      estimate of rock_1_uneven drawn: `comlearn estimate --svg`).
#
# Options (scripts/main.sh --help) or the environment: SEEDS (noisy runs per rock and policy,
# default 5), SIMS (simulators for the experiments, default 2: one per core here; 0 = the one of
# step 2), OUT (default out); the options win.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)

usage() {
  cat <<'EOF'
usage: scripts/main.sh [--out DIR] [--lcm-url URL] [--seeds N] [--sims N] [-h | --help]
The main job of README.md: set up and build (scripts/setup.sh), then the paper's experiments
and the rock stack over LCM against comlearn-sim, recorded; a report in DIR/report.md.
  --out DIR      where everything goes, emptied first; relative to the current folder
                 (default: $OUT, else out)
  --lcm-url URL  LCM URL of the job's comlearn-sim and recorders; no other comlearn-sim may
                 answer there (default: udpm://239.255.76.67:<7700 + pid % 1000>?ttl=0)
  --seeds N      noisy runs per rock and policy, 0..1000 (default: $SEEDS, else 5)
  --sims N       simulators for the experiments, 0..16; 0: the job's own (default: $SIMS,
                 else 2)
  -h, --help     this text (and nothing else)
Exit status: 0 done, 1 a step failed, 2 bad usage.
EOF
}

out=${OUT:-out}
seeds=${SEEDS:-5}
sims=${SIMS:-2}
url=
while [ $# -gt 0 ]; do
  case "$1" in
    -h | --help) usage; exit 0 ;;
    --out | --lcm-url | --seeds | --sims)
      [ $# -ge 2 ] || { echo "main: $1 needs a value (try --help)" >&2; exit 2; }
      case "$1" in
        --out) out=$2 ;;
        --lcm-url) url=$2 ;;
        --seeds) seeds=$2 ;;
        --sims) sims=$2 ;;
      esac
      shift 2 ;;
    *) echo "main: unexpected argument '$1' (try --help)" >&2; exit 2 ;;
  esac
done
whole() { # NAME VALUE MAX: a whole number 0..MAX
  case "$2" in
    '' | *[!0-9]*) echo "main: $1 '$2' is not a whole number" >&2; exit 2 ;;
  esac
  [ "$2" -le "$3" ] || { echo "main: $1 $2 is over $3" >&2; exit 2; }
}
whole --seeds "$seeds" 1000
whole --sims "$sims" 16
[ -n "$out" ] || { echo "main: --out is empty" >&2; exit 2; }
out=$(realpath -m -- "$out") # relative to where the job was started
case "$out" in
  / | "$(realpath -m -- "${HOME:-/}")" | "$(realpath -m -- "$here")")
    echo "main: refusing to empty '$out'" >&2; exit 2 ;;
esac
if [ -z "$url" ]; then
  url="udpm://239.255.76.67:$((7700 + $$ % 1000))?ttl=0"
fi
case "$url" in
  udpm://*) ;;
  *) echo "main: --lcm-url '$url' is not a udpm:// URL" >&2; exit 2 ;;
esac
# recv_buf_size for lcm-logger too: comlearn's programs add it when a URL has none (cli_net.h)
case "$url" in
  *recv_buf_size=*) ;;
  *\?*) url="$url&recv_buf_size=4194304" ;;
  *) url="$url?recv_buf_size=4194304" ;;
esac

cd "$here"
bash scripts/setup.sh default

bin=build/default
comlearn=$bin/apps/comlearn/comlearn
sim=$bin/daemon/comlearn-sim
stack_rocks=(assets/rocks/rock_1_uneven.urdf assets/rocks/rock_2_uneven.urdf
             assets/rocks/rock_3_uneven.urdf)

# The job's steps, counted, with the time since the start: 9 of them (the stack is three).
steps=9 stepno=0
step() {
  stepno=$((stepno + 1))
  printf '\n== [%d/%d, %d s] %s\n' "$stepno" "$steps" "$(($(date +%s) - started))" "$*" >&2
}

rm -rf "$out"
mkdir -p "$out/lcm" "$out/experiments"
started=$(date +%s)

pids=()
stop_all() {
  # Loggers first (SIGINT: they flush what they queued), then the simulator.
  local p
  for p in "${pids[@]}"; do kill -INT "$p" 2>/dev/null || true; done
  for p in "${pids[@]}"; do wait "$p" 2>/dev/null || true; done
  pids=()
}
trap stop_all EXIT
trap 'exit 130' INT TERM

step "comlearn-sim on $url; lcm-logger and comlearn record -> $out/lcm/"
"$sim" --lcm-url "$url" -q &
sim_pid=$!
lcm-logger --lcm-url="$url" -c '([A-Za-z0-9_]*_)?COM_.*' --quiet "$out/lcm/results.lcmlog" &
log_results_pid=$!
"$comlearn" record "$out/lcm/all.lcmlog" --lcm-url "$url" -q &
log_all_pid=$!
pids=("$log_results_pid" "$log_all_pid" "$sim_pid")
sleep 1
kill -0 "$sim_pid" || { echo "main: comlearn-sim did not start" >&2; exit 1; }

step "comlearn inspect --truth assets/rocks/*.urdf"
"$comlearn" inspect --truth assets/rocks/*.urdf | tee "$out/inspect.txt"

sims_args=()
[ "$sims" -gt 0 ] && sims_args=(--sims "$sims")
step "comlearn experiments assets/rocks/*.urdf --lcm-url URL ${sims_args[*]} --seeds $seeds --out $out/experiments"
"$comlearn" experiments assets/rocks/*.urdf --lcm-url "$url" "${sims_args[@]}" --seeds "$seeds" \
  --out "$out/experiments" | tee "$out/experiments/table.txt"

for src in learned bbox true; do
  step "comlearn stack ${stack_rocks[*]} --com $src"
  extra=()
  [ "$src" = learned ] && extra=(--lcm-url "$url")
  "$comlearn" stack "${stack_rocks[@]}" --com "$src" "${extra[@]}" \
    --svg "$out/stack_$src.svg" | tee "$out/stack_$src.txt"
  "$comlearn" stack "${stack_rocks[@]}" --com "$src" "${extra[@]}" --json -q \
    > "$out/stack_$src.json"
done

step "stopping the loggers and comlearn-sim"
stop_all
trap - EXIT
ls -l "$out/lcm" >&2

step "comlearn logcheck: every trial record in both logs?"
logcheck=()
for f in all results; do
  "$comlearn" logcheck "$out/lcm/$f.lcmlog" > "$out/lcm/logcheck_$f.txt" ||
    echo "main: warning: $out/lcm/$f.lcmlog lacks trial records ($out/lcm/logcheck_$f.txt)" >&2
  logcheck+=("$f.lcmlog: $(tail -n 1 "$out/lcm/logcheck_$f.txt")")
done
printf '%s\n' "${logcheck[@]}" >&2

finished=$(date +%s)
commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)
{
  echo "# comlearn main job report"
  echo
  echo "Commit \`$commit\`, $(date -u '+%Y-%m-%d %H:%M UTC'), $((finished - started)) s."
  echo "Regenerate with \`bash scripts/main.sh\` (docs/results.md explains every column)."
  echo
  echo "## The paper's Table I, reproduced"
  echo
  echo "Noiseless runs over LCM against comlearn-sim with YuMi placement; noisy runs"
  echo "($seeds seeds per rock and policy) in-process with the same physics and seeding."
  echo
  sed "1{/^# /d}" "$out/experiments/table.md"
  echo
  echo "## Fig. 2: the estimate against trial number"
  echo
  for f in "$out"/experiments/fig2_*.svg; do
    echo "![$(basename "$f" .svg)](experiments/$(basename "$f"))"
    echo
  done
  if [ -f "$out/experiments/noisy.svg" ]; then
    echo "## Noisy runs: error and 95 % interval per component"
    echo
    echo "![noisy runs](experiments/noisy.svg)"
    echo
  fi
  echo "## The rock stack (three uneven rocks, 5 s)"
  echo
  for src in learned bbox true; do
    echo "### CoM source: $src"
    echo
    echo '```'
    cat "$out/stack_$src.txt"
    echo '```'
    echo
    echo "![stack, $src](stack_$src.svg)"
    echo
  done
  echo "## One estimate, drawn (rock_1_uneven, in-process trials)"
  echo
  "$comlearn" estimate assets/rocks/rock_1_uneven.urdf --direct --truth -q \
    --svg "$out/estimate_rock_1_uneven.svg" > "$out/estimate_rock_1_uneven.txt"
  echo '```'
  cat "$out/estimate_rock_1_uneven.txt"
  echo '```'
  echo
  echo "The views, the interval box, the truth, the faces and edge lines, the first trials' poses"
  echo "(docs/estimate.md, \"Picture\"):"
  echo
  echo "![estimate, rock_1_uneven](estimate_rock_1_uneven.svg)"
  echo
  echo "## Recording"
  echo
  echo "\`lcm/results.lcmlog\` (every robot's COM_TRIAL, COM_ESTIMATE) and \`lcm/all.lcmlog\`"
  echo "(every channel); \`comlearn logcheck\` on each (\`lcm/logcheck_*.txt\`):"
  echo
  printf -- '- %s\n' "${logcheck[@]}"
  echo
  echo "Replay: \`comlearn watch --lcm-url URL & lcm-logplayer --lcm-url=URL out/lcm/results.lcmlog\`"
  echo "(docs/replay.md)."
} > "$out/report.md"
step "report: $out/report.md ($((finished - started)) s)"
