#!/usr/bin/env bash
# Idempotent setup: install the Debian packages comlearn needs (only the missing ones), then
# configure and build one CMake preset. Safe to run again; a second run only rebuilds what changed.
# usage: scripts/setup.sh [--gui] [--packages] [PRESET]   (PRESET: default | asan | fuzz)
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)

usage() {
  cat <<'EOF'
usage: scripts/setup.sh [--gui] [--packages] [PRESET]
Installs the Debian 12 packages comlearn needs (only the missing ones; as root), raises the
UDP receive buffer limit and adds a multicast route when there is none (as root), then
configures and builds the CMake preset. Safe to run again.
  PRESET      default | asan | fuzz (default: default); see CMakePresets.json
  --gui       also install what the GUI tools scripts/lcm-spy.sh and
              scripts/lcm-logplayer-gui.sh need: a JRE with AWT (default-jre), the JDK that
              builds the jar of comlearn's types (default-jdk-headless), liblcm-java and
              libjchart2d-java; the build then makes the jar and the Java decode test.
              Without it no Java is installed: the build, the tests and scripts/main.sh need none
  --packages  print the packages this would install if missing, one a line; nothing else
  -h, --help  this text (and nothing else)
EOF
}

gui=0 print=0 preset=
while [ $# -gt 0 ]; do
  case "$1" in
    -h | --help) usage; exit 0 ;;
    --gui) gui=1 ;;
    --packages) print=1 ;;
    -*) echo "setup: unknown option '$1' (try --help)" >&2; exit 2 ;;
    *)
      [ -z "$preset" ] || { echo "setup: one PRESET at most (try --help)" >&2; exit 2; }
      preset=$1 ;;
  esac
  shift
done
preset=${preset:-default}
case "$preset" in
  default | asan | fuzz) ;;
  *) echo "setup: unknown preset '$preset': default, asan or fuzz (try --help)" >&2; exit 2 ;;
esac

# Build tools and libraries, all from Debian 12; python3 runs the tests of the Python package
# comlearn and its example client. No Java: without a JDK, lcmtypes/ skips the jar and
# tests/messages.cmake the Java decode test, each with a STATUS line.
pkgs=(gcc g++ make cmake pkg-config git python3
      libode-dev liblcm-dev liblcm-bin libccd-dev libassimp-dev
      liburdfdom-dev liburdfdom-tools check libglib2.0-dev iproute2 binutils clang-format)
# The fuzz preset (scripts/fuzz.sh) builds with clang and its libFuzzer.
if [ "$preset" = fuzz ]; then
  pkgs+=(clang libclang-rt-14-dev)
fi
# --gui: lcm-spy and lcm-logplayer-gui are Java GUIs (a JRE with AWT and lcm.jar; lcm-spy's
# message viewer needs jchart2d), and a JDK builds the jar of comlearn's types that they load.
if [ "$gui" -eq 1 ]; then
  pkgs+=(default-jre default-jdk-headless liblcm-java libjchart2d-java)
fi
if [ "$print" -eq 1 ]; then
  printf '%s\n' "${pkgs[@]}"
  exit 0
fi

missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}" >&2
  if [ "$(id -u)" -ne 0 ]; then
    echo "setup: need root to install packages: ${missing[*]}" >&2
    exit 1
  fi
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
fi

# LCM's default transport (udpm) needs a multicast route; a host with only loopback has none.
# Idempotent: only when `ip route get` finds no route, and only as root.
mcast=239.255.76.67
if ip route get "$mcast" >/dev/null 2>&1; then
  echo "setup: multicast route to $mcast present" >&2
elif [ "$(id -u)" -eq 0 ]; then
  ip route add 224.0.0.0/4 dev lo
  echo "setup: added multicast route: ip route add 224.0.0.0/4 dev lo" >&2
else
  echo "setup: no multicast route to $mcast; as root run: ip route add 224.0.0.0/4 dev lo" >&2
fi

# comlearn's programs ask LCM for a 4 MiB receive buffer (apps/common cli_net.h); Linux caps it
# at net.core.rmem_max (208 KiB by default), and with that a trial's statuses overflow it. Raised,
# never lowered, and only as root; the programs warn when they get less.
want_rmem=4194304
rmem=$(cat /proc/sys/net/core/rmem_max 2>/dev/null || echo 0)
if [ "$rmem" -ge "$want_rmem" ]; then
  echo "setup: net.core.rmem_max is $rmem" >&2
elif [ "$(id -u)" -eq 0 ] && echo $want_rmem 2>/dev/null >/proc/sys/net/core/rmem_max; then
  echo "setup: raised net.core.rmem_max from $rmem to $want_rmem" >&2
else
  echo "setup: net.core.rmem_max is $rmem; as root run:" \
    "echo $want_rmem > /proc/sys/net/core/rmem_max" >&2
fi

cd "$here"
cmake --preset "$preset" >&2
cmake --build --preset "$preset" -j "$(nproc)" >&2
# --gui: the configure above found the JDK just installed (CMake searches again for what it did
# not find before), so the build made the jar that the GUI scripts load.
if [ "$gui" -eq 1 ]; then
  jar=$here/build/$preset/lcmtypes/comlearn_lcmtypes.jar
  [ -f "$jar" ] || { echo "setup: --gui: the build made no $jar (see the STATUS lines above)" >&2; exit 1; }
  echo "setup: GUI tools ready: bash scripts/lcm-spy.sh, bash scripts/lcm-logplayer-gui.sh LOG" >&2
fi
