#!/usr/bin/env bash
# What a catch-all recording keeps of many robots on one URL (docs/replay.md, "Recorders").
# usage: bash bench/record_loss.sh BUILD_DIR [SIMS [RUNS]]
# Runs `comlearn experiments assets/rocks/*.urdf --seeds 0 --sims SIMS` (default 2) RUNS times
# (default 3) on a udpm URL of its own while lcm-logger and `comlearn record` both record every
# channel, then `comlearn logcheck` on each log. Prints a markdown table: per run, the trial
# records each log holds of those the runs' final COM_ESTIMATEs announce, and the datagrams lost
# to full receive buffers on the host meanwhile (RcvbufErrors: 0 means every loss was inside a
# recorder). Needs lcm-logger (Debian liblcm-bin) and a multicast route (scripts/setup.sh).
set -euo pipefail
if [[ $# -lt 1 || $1 == -h || $1 == --help ]]; then
  sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//'
  exit $([[ $# -ge 1 && ($1 == -h || $1 == --help) ]] && echo 0 || echo 2)
fi
if [[ $1 == -* ]]; then
  echo "record_loss.sh: unknown option '$1' (try --help)" >&2
  exit 2
fi
build=$1 sims=${2:-2} runs=${3:-3}
here=$(cd "$(dirname "$0")/.." && pwd)
comlearn=$build/apps/comlearn/comlearn
work=$(mktemp -d /tmp/record_loss.XXXXXX)
trap 'rm -rf "$work"' EXIT
url="udpm://239.255.76.67:$((9700 + $$ % 200))?ttl=0&recv_buf_size=4194304"
rcvbuf_errors() { awk '/^Udp:/ { n++; if (n == 2) print $6 }' /proc/net/snmp; }
verdict() { "$comlearn" logcheck -q "$1" | sed -E 's/^[A-Z]+: [0-9]+ runs, ([0-9]+ of [0-9]+) trial records.*/\1/I'; }

echo "| run | sims | lcm-logger: trial records kept | comlearn record: trial records kept | lost to full buffers (host) |"
echo "|---|---|---|---|---|"
for run in $(seq 1 "$runs"); do
  lcm-logger --lcm-url="$url" --quiet "$work/logger.lcmlog" &
  logger=$!
  "$comlearn" record "$work/record.lcmlog" --lcm-url "$url" -q &
  recorder=$!
  sleep 0.5
  lost0=$(rcvbuf_errors)
  "$comlearn" experiments "$here"/assets/rocks/*.urdf --seeds 0 --sims "$sims" --lcm-url "$url" \
    --json -q >/dev/null
  sleep 0.3
  lost1=$(rcvbuf_errors)
  kill -INT "$logger" "$recorder"
  wait "$logger" "$recorder" || true
  echo "| $run | $sims | $(verdict "$work/logger.lcmlog") | $(verdict "$work/record.lcmlog") | $((lost1 - lost0)) |"
  rm -f "$work/logger.lcmlog" "$work/record.lcmlog"
done
