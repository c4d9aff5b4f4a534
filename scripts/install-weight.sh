#!/usr/bin/env bash
# What installing Debian packages costs on a fresh minimal Debian 12: apt-get's simulation
# (--no-install-recommends, as scripts/setup.sh installs) against a dpkg status that holds only
# a minimal system, then the sizes apt-cache gives for every package it would install.
# The minimal system is debootstrap's minbase: every package of priority required or
# essential, their dependencies, and usr-is-merged (as in the debian:bookworm image); apt-get
# resolves it from an empty status. Reads apt's package lists only (run apt-get update first);
# installs nothing, needs no root.
set -euo pipefail

usage() {
  cat <<'EOF'
usage: scripts/install-weight.sh [--list] PACKAGE...
What installing PACKAGE... with --no-install-recommends costs on a minimal Debian 12
(debootstrap's minbase: the packages of priority required or essential, their dependencies
and usr-is-merged). Prints one line:
  N packages, D MB to download, I MB installed (over M packages of the minimal system)
(MB = 10^6 bytes; sizes from apt-cache). Reads apt's lists (apt-get update first), installs
nothing. Example, the packages of scripts/setup.sh:
  bash scripts/install-weight.sh $(bash scripts/setup.sh --packages)
  --list      also print each package to install, with its download size in kB
  -h, --help  this text (and nothing else)
EOF
}

list=0
pkgs=()
while [ $# -gt 0 ]; do
  case "$1" in
    -h | --help) usage; exit 0 ;;
    --list) list=1; shift ;;
    --) shift; pkgs+=("$@"); break ;;
    -*) echo "install-weight: unknown option '$1' (try --help)" >&2; exit 2 ;;
    *) pkgs+=("$1"); shift ;;
  esac
done
[ ${#pkgs[@]} -gt 0 ] || { echo "install-weight: no PACKAGE given (try --help)" >&2; exit 2; }
for p in "${pkgs[@]}"; do
  apt-cache show --no-all-versions "$p" >/dev/null 2>&1 ||
    { echo "install-weight: no package '$p' in apt's lists (run apt-get update?)" >&2; exit 2; }
done

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# simulate STATUS OUT PKG...: what apt-get's simulation would install, one NAME=VERSION a line
simulate() {
  local status=$1 out=$2
  shift 2
  apt-get -s -o Dir::State::status="$status" -o Dir::State::extended_states="$tmp/ext" \
    install --no-install-recommends "$@" >"$tmp/apt.out" 2>"$tmp/apt.err" ||
    { echo "install-weight: apt-get -s failed: $(cat "$tmp/apt.err")" >&2; exit 1; }
  sed -n 's/^Inst \([^ ]*\) (\([^ ]*\) .*/\1=\2/p' "$tmp/apt.out" >"$out"
}

: >"$tmp/empty"
: >"$tmp/ext"
mapfile -t required < <(apt-cache dumpavail |
  awk -v RS= '/\nPriority: required\n/ || /\nEssential: yes\n/' | sed -n 's/^Package: //p' |
  sort -u)
simulate "$tmp/empty" "$tmp/base" "${required[@]}" usr-is-merged
mapfile -t base <"$tmp/base"
[ ${#base[@]} -gt 0 ] || { echo "install-weight: no minimal system resolved" >&2; exit 1; }
# The minimal system as a dpkg status: each package's record, marked installed.
apt-cache show "${base[@]}" | awk -v RS= -v ORS='\n\n' \
  '{ sub(/\n/, "\nStatus: install ok installed\n"); print }' >"$tmp/status"

simulate "$tmp/status" "$tmp/inst" "${pkgs[@]}"
mapfile -t inst <"$tmp/inst"
if [ ${#inst[@]} -eq 0 ]; then
  echo "0 packages, 0 MB to download, 0 MB installed (over ${#base[@]} packages of the minimal system)"
  exit 0
fi
apt-cache show "${inst[@]}" | awk -v RS= -v list=$list -v n=${#inst[@]} -v nb=${#base[@]} '
  { size = 0; isize = 0; name = ""
    if (match($0, /(^|\n)Package: [^\n]+/)) name = substr($0, RSTART, RLENGTH)
    sub(/.*Package: /, "", name)
    if (match($0, /\nSize: [0-9]+/)) size = substr($0, RSTART + 7, RLENGTH - 7) + 0
    if (match($0, /\nInstalled-Size: [0-9]+/)) isize = substr($0, RSTART + 17, RLENGTH - 17) + 0
    if (seen[name]++) next
    dl += size; ins += isize * 1024
    if (list) printf "%s %.0f kB\n", name, size / 1000 }
  END { printf "%d packages, %.0f MB to download, %.0f MB installed (over %d packages of the minimal system)\n",
          n, dl / 1e6, ins / 1e6, nb }'
