#!/usr/bin/env bash
# The test command of README.md: set up, build and run every CTest suite, first in the normal
# build, then in the sanitizer build (ASan + UBSan) that runs the same suites, then run each
# libFuzzer harness for a bounded time (scripts/fuzz.sh).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
case "${1:-}" in
  -h | --help)
    cat <<'EOF'
usage: scripts/test.sh
The test command of README.md: set up and build (scripts/setup.sh), run every CTest suite in
the default and the sanitizer (asan) builds, then each fuzz harness for FUZZ_SECONDS (default
60) seconds. Exit status 0 when everything passed.
  -h, --help  this text (and nothing else)
EOF
    exit 0 ;;
  '') ;;
  *) echo "test: unexpected argument '$1' (try --help)" >&2; exit 2 ;;
esac
cd "$here"
for preset in default asan; do
  bash scripts/setup.sh "$preset"
  echo "== ctest --preset $preset" >&2
  ctest --preset "$preset"
done
# then the libFuzzer harnesses, each for a bounded time (FUZZ_SECONDS, default 60)
bash scripts/fuzz.sh
