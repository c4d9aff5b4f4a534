#!/usr/bin/env bash
# Many robots across hosts: two network namespaces joined by a veth pair stand in for two hosts
# on a LAN. A comlearn-sim runs in each (channel prefixes R0_ and R1_) on one udpm URL with
# ttl=1, and each namespace runs an estimate against the *other* namespace's sim, so every
# message crosses the link. Each answer must equal the in-process (--direct) one: the same
# components and trials. The same pair with ttl=0 must not reach across (exit 1, no controller).
# Needs root (ip netns, ip link), iproute2 and util-linux's unshare; exits 77 when namespaces cannot
# be used here, e.g. in a chroot (CTest reports that as skipped). docs/messages.md, "Across hosts".
# usage: scripts/lan-check.sh [-h|--help] [BUILD_DIR]   (default BUILD_DIR: build/default)
set -euo pipefail
case "${1:-}" in
  -h | --help)
    sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//'
    exit 0
    ;;
  -*)
    echo "lan-check.sh: unknown option '$1' (try --help)" >&2
    exit 2
    ;;
esac
[ $# -le 1 ] || { echo "lan-check.sh: one BUILD_DIR at most (try --help)" >&2; exit 2; }
here=$(cd "$(dirname "$0")/.." && pwd)
bin=${1:-$here/build/default}
comlearn=$bin/apps/comlearn/comlearn
sim=$bin/daemon/comlearn-sim
rock=$here/assets/rocks/rock_1_uneven.urdf
for exe in "$comlearn" "$sim"; do
  [ -x "$exe" ] || { echo "lan-check: $exe is not built" >&2; exit 1; }
done
command -v ip >/dev/null || { echo "lan-check: no ip (iproute2); skipped" >&2; exit 77; }
# `ip netns exec` needs a network and a mount namespace and makes / a slave mount; a container or
# a chroot (where / is not a mount point) may allow neither. Probe first, so that nothing is left
# mounted where it cannot work.
if ! unshare --net --mount --propagation slave true 2>/dev/null; then
  echo "lan-check: network and mount namespaces are not available here (needs root, and / a" \
    "mount point); skipped" >&2
  exit 77
fi

ns_a=cl_lan_a_$$ ns_b=cl_lan_b_$$ va=cl_va_$$ vb=cl_vb_$$
pids=()
cleanup() {
  local p
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  for p in "${pids[@]}"; do wait "$p" 2>/dev/null || true; done
  ip netns del "$ns_a" 2>/dev/null || true
  ip netns del "$ns_b" 2>/dev/null || true
}
trap cleanup EXIT
skip() {
  echo "lan-check: $1 failed: namespaces or veth pairs cannot be made here; skipped" >&2
  exit 77
}
ip netns add "$ns_a" 2>/dev/null || skip "ip netns add"
ip netns add "$ns_b" 2>/dev/null || skip "ip netns add"
ip link add "$va" type veth peer name "$vb" 2>/dev/null || skip "ip link add (veth)"
ip link set "$va" netns "$ns_a" && ip link set "$vb" netns "$ns_b" || skip "ip link set netns"
ip -n "$ns_a" addr add 10.77.0.1/24 dev "$va" || skip "ip addr add"
ip -n "$ns_b" addr add 10.77.0.2/24 dev "$vb" || skip "ip addr add"
for n in "$ns_a:$va" "$ns_b:$vb"; do
  ip -n "${n%%:*}" link set lo up && ip -n "${n%%:*}" link set "${n#*:}" up || skip "ip link set up"
  # multicast over the "LAN"
  ip -n "${n%%:*}" route add 224.0.0.0/4 dev "${n#*:}" || skip "ip route add"
done
ip netns exec "$ns_a" true 2>/dev/null || skip "ip netns exec"

# the answer: the fields of the JSON that carry it
answer() { grep -o '"com_m": \[[^]]*\]\|"found": \[[^]]*\]\|"trials": [0-9]*' | tr '\n' ' '; }
want=$("$comlearn" estimate "$rock" --direct --json -q | answer)

run_pair() { # ttl: sims in both namespaces, each namespace estimating on the other's robot;
  # ok_a, ok_b: 1 when that namespace's estimate exited 0
  local url="udpm://239.255.76.67:$((7800 + $$ % 100 + $1))?ttl=$1"
  ok_a=1 ok_b=1
  ip netns exec "$ns_a" "$sim" --lcm-url "$url" --channel-prefix R0_ -q &
  pids+=($!)
  ip netns exec "$ns_b" "$sim" --lcm-url "$url" --channel-prefix R1_ -q &
  pids+=($!)
  sleep 0.5
  got_a=$(ip netns exec "$ns_a" "$comlearn" estimate "$rock" --lcm-url "$url" \
    --channel-prefix R1_ --json -q 2>/dev/null | answer) || ok_a=0
  got_b=$(ip netns exec "$ns_b" "$comlearn" estimate "$rock" --lcm-url "$url" \
    --channel-prefix R0_ --json -q 2>/dev/null | answer) || ok_b=0
  local p
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  for p in "${pids[@]}"; do wait "$p" 2>/dev/null || true; done
  pids=()
}

set -o pipefail
run_pair 1
if [ "$ok_a$ok_b" != 11 ]; then
  echo "lan-check: FAIL: with ttl=1 an estimate across the veth pair failed" >&2
  exit 1
fi
for got in "$got_a" "$got_b"; do
  if [ "$got" != "$want" ]; then
    echo "lan-check: FAIL: across the link: $got" >&2
    echo "lan-check:       in-process:       $want" >&2
    exit 1
  fi
done
echo "lan-check: ttl=1: both estimates across the veth pair equal --direct: $want" >&2
run_pair 0
if [ "$ok_a$ok_b" != 00 ]; then
  echo "lan-check: FAIL: with ttl=0 an estimate reached the other namespace's sim" >&2
  exit 1
fi
echo "lan-check: ttl=0: neither estimate reached the other namespace (no controller, exit 1)" >&2
echo "lan-check: ok" >&2
