#!/usr/bin/env bash
# readme_commands.sh SOURCE_DIR BUILD_DIR: runs the commands of README.md's "Using it" block (the
# first ```sh block after the "## Using it" heading), read from README.md at test time, so that
# the README a user reads is what is tested. Each line (continuation lines joined, the trailing
# "# comment" dropped, build/default/ replaced by BUILD_DIR) must match one rule below, which may
# make it small or private (the substitutions, each with its reason), runs it from SOURCE_DIR and
# checks that it exits 0 and prints or writes what the README says it does. A line that matches
# no rule fails the test: a new README line cannot go untested.
#
# Substitutions (and why):
#   /tmp/...                -> a private temp folder (no clash with the user's files or a
#                              parallel test)
#   daemons (comlearn-sim &, comlearn record &) and LCM clients
#                           -> a private udpm URL (ttl=0, a port from the pid), the daemons
#                              stopped at the end
#   comlearn-sim --realtime -> unpaced (a paced simulator makes the trials below take minutes)
#   --count 26 (shapegen)   -> --count 2
#   bench_coverage          -> --objects 2 --seeds 1 --jobs 1 (~1 min -> under 1 s)
#   experiments --seeds 5   -> --seeds 1
#   comlearn record         -> followed by one `comlearn estimate` over the private URL, so that
#                              the log holds a run for the next line's logcheck
#   lcm-spy.sh (a GUI)      -> --check (the prerequisites and the java command, no window);
#                              reported as skipped where a prerequisite is missing and named
#                              with `bash scripts/setup.sh --gui` (Java is not in the default
#                              setup)
set -uo pipefail
[ $# -eq 2 ] || { echo "usage: readme_commands.sh SOURCE_DIR BUILD_DIR" >&2; exit 2; }
src=$(cd "$1" && pwd)
bld=$(cd "$2" && pwd)
tmp=$(mktemp -d /tmp/readme_commands.XXXXXX)
port=$((20000 + $$ % 30000))
url="udpm://239.255.76.67:$port?ttl=0"
spawn_url="udpm://239.255.76.67:$((port + 1))?ttl=0"
comlearn=$bld/apps/comlearn/comlearn
sim_pid= rec_pid= failures=0 passed=0 skipped=0

cleanup() {
  for p in $rec_pid $sim_pid; do kill -INT "$p" 2>/dev/null && wait "$p" 2>/dev/null; done
  rm -rf "$tmp"
}
trap cleanup EXIT

fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
ok() { echo "ok:   $*"; passed=$((passed + 1)); }

# The block, continuation lines joined, comments dropped.
block=$(awk '/^## Using it/ {u = 1; next}
             u && /^```sh/ {b = 1; next}
             b && /^```/ {exit}
             b' "$src/README.md" |
        awk '{ if (sub(/\\$/, "")) { buf = buf $0; next } print buf $0; buf = "" }' |
        sed -E 's/[[:space:]]+#[[:space:]].*$//; s/[[:space:]]+$//')
[ -n "$block" ] || { echo "FAIL: no \`\`\`sh block after '## Using it' in README.md"; exit 1; }

cd "$src" || exit 1
out=$tmp/out
# run CMD...: runs it, stdout and stderr into $out; returns its exit status
run() { "$@" >"$out" 2>&1; }
# set_opt NAME VALUE: the argument after NAME in argv becomes VALUE
set_opt() {
  local k
  for ((k = 0; k < ${#argv[@]} - 1; ++k)); do [ "${argv[k]}" = "$1" ] && argv[k + 1]=$2; done
}
# drop_arg ARG: ARG taken out of argv
drop_arg() {
  local a kept=()
  for a in "${argv[@]}"; do [ "$a" = "$1" ] || kept+=("$a"); done
  argv=("${kept[@]}")
}
expect() { # expect REGEX WHAT: $out matches REGEX
  grep -Eq -- "$1" "$out" || { fail "$line: $2 (wanted /$1/), got: $(head -c 600 "$out")"; return 1; }
}

while IFS= read -r line; do
  [ -n "$line" ] || continue
  # /tmp/ first: the build folder may itself be under /tmp
  cmd=${line//\/tmp\//$tmp/}
  cmd=${cmd//build\/default\//$bld/}
  # the words as the shell gives them (globs and braces expanded: assets/rocks/*.urdf); a
  # trailing & (a daemon) is the rule's to handle
  eval "argv=(${cmd% &})"
  case "$line" in
    *comlearn\ inspect\ --json\ --truth*)
      run "${argv[@]}" || { fail "$line: exit $?"; continue; }
      [ "$(grep -o '"truth_com_m"' "$out" | wc -l)" -eq 6 ] || { fail "$line: not 6 truths"; continue; }
      ok "$line" ;;
    *comlearn\ inspect*)
      run "${argv[@]}" || { fail "$line: exit $?"; continue; }
      expect 'uniform CoM' "a uniform CoM column" || continue
      grep -q truth "$out" && { fail "$line: geometry only, yet it mentions the truth"; continue; }
      ok "$line" ;;
    *comlearn\ estimate*)
      [[ $line == *--direct* ]] || argv+=(--lcm-url "$spawn_url")
      run "${argv[@]}" || { fail "$line: exit $?"; continue; }
      if [[ $line == *--json* ]]; then
        expect '"found": \[true, true, true\]' "every component found" || continue
      else
        [ "$(grep -Ec '^  [xyz] .* yes ' "$out")" -eq 3 ] ||
          { fail "$line: not three components found: $(head -c 600 "$out")"; continue; }
      fi
      if [[ $line == *-noise-mm* ]]; then expect 'intervals: 95 %' "95 % intervals" || continue; fi
      if [[ $line == *--spawn-sim* ]]; then
        expect "started comlearn-sim \\(pid [0-9]+\\) on udpm" "a comlearn-sim of its own" || continue
      fi
      for ((k = 0; k < ${#argv[@]} - 1; ++k)); do
        if [ "${argv[k]}" = --svg ]; then
          head -c 300 "${argv[k + 1]}" 2>/dev/null | grep -q '<svg' ||
            { fail "$line: no SVG in ${argv[k + 1]}"; continue 2; }
        fi
      done
      ok "$line" ;;
    *comlearn-shapegen*)
      set_opt --count 2
      run "${argv[@]}" || { fail "$line: exit $?"; continue; }
      n=$(find "$tmp/shapes" -name '*.urdf' | wc -l)
      [ "$n" -ge 2 ] && ok "$line ($n URDFs with --count 2)" || fail "$line: $n URDFs in $tmp/shapes" ;;
    *bench_coverage*)
      run "${argv[@]}" --objects 2 --seeds 1 --jobs 1 || { fail "$line: exit $?"; continue; }
      expect '^\| box \| noiseless \| 2 \| 0 \| 6 of 6' "a coverage table" && ok "$line" ;;
    *comlearn\ experiments*)
      set_opt --seeds 1
      run "${argv[@]}" || { fail "$line: exit $?"; continue; }
      [ -s "$tmp/exp/table.md" ] && [ "$(ls "$tmp"/exp/fig2_*.svg | wc -l)" -eq 6 ] &&
        ok "$line (table.md and 6 Fig. 2 SVGs, --seeds 1)" || fail "$line: no table.md or Fig. 2 in $tmp/exp" ;;
    *comlearn\ stack*)
      run "${argv[@]}" || { fail "$line: exit $?"; continue; }
      head -c 300 "$tmp/stack.svg" 2>/dev/null | grep -q '<svg' || { fail "$line: no SVG"; continue; }
      expect '^(STANDS|FALLS)' "a verdict" && ok "$line" ;;
    *comlearn-sim*\&)
      drop_arg --realtime
      "${argv[@]}" --lcm-url "$url" -q >"$tmp/sim.log" 2>&1 &
      sim_pid=$!
      sleep 0.5
      kill -0 "$sim_pid" 2>/dev/null && ok "$line (unpaced, on $url)" ||
        { fail "$line: comlearn-sim exited: $(cat "$tmp/sim.log")"; sim_pid=; } ;;
    *comlearn\ record*\&)
      "${argv[@]}" --lcm-url "$url" >"$tmp/record.log" 2>&1 &
      rec_pid=$!
      sleep 0.5
      # a run to record: one LCM estimate against the daemon started above
      run "$comlearn" estimate assets/rocks/rock_1_even.urdf --lcm-url "$url" --json &&
        expect '"found": \[true, true, true\]' "an LCM estimate while recording" &&
        ok "$line (and one LCM estimate recorded)" || fail "$line: the estimate it records failed" ;;
    *comlearn\ logcheck*)
      [ -n "$rec_pid" ] && kill -INT "$rec_pid" && wait "$rec_pid"
      rc=$?
      rec_pid=
      [ "$rc" -eq 0 ] || { fail "comlearn record exited $rc on SIGINT: $(cat "$tmp/record.log")"; continue; }
      run "${argv[@]}" || { fail "$line: exit $?: $(head -c 600 "$out")"; continue; }
      expect '^complete: 1 runs, ([0-9]+) of \1 trial records, 0 missing' "every trial record there" &&
        ok "$line" ;;
    *lcm-spy.sh*)
      run "${argv[@]}" --check
      rc=$?
      if [ "$rc" -eq 1 ] && grep -q 'bash scripts/setup.sh --gui' "$out"; then
        # a GUI prerequisite missing (Java is not in the default setup), named with its install
        echo "SKIP: $line --check: $(grep -m1 -i 'missing\|not found\|headless\|no ' "$out")"
        skipped=$((skipped + 1))
        continue
      fi
      [ "$rc" -eq 0 ] || { fail "$line --check: exit $rc: $(head -c 600 "$out")"; continue; }
      expect 'lcm\.spy\.Spy' "the java command" && ok "$line --check" ;;
    *comlearn\ plan*)
      run "${argv[@]}" || { fail "$line: exit $?"; continue; }
      expect '^simulated \(lib/balance\): (stays|tips)$' "the simulated outcome" &&
        expect '^  release ' "the release waypoint" && ok "$line" ;;
    *one_trial.py*)
      [ -n "$sim_pid" ] || { fail "$line: no comlearn-sim running (its README line comes first)"; continue; }
      env "${argv[@]}" --lcm-url "$url" >"$out" 2>&1 || { fail "$line: exit $?: $(cat "$out")"; continue; }
      expect '^rock_1_uneven: (stays|tips|slides) \(settled at ' "the outcome" && ok "$line" ;;
    *)
      fail "no rule for README line: $line (add one to tests/readme_commands.sh)" ;;
  esac
done <<<"$block"

echo "readme_commands: $passed passed, $failures failed, $skipped skipped"
[ "$failures" -eq 0 ]
