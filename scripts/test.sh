#!/usr/bin/env bash
# The test command of README.md: set up, build and run every CTest suite, first in the normal
# build, then in the sanitizer build (ASan + UBSan) that runs the same suites, then run each
# libFuzzer harness for a bounded time (scripts/fuzz.sh).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"
for preset in default asan; do
  bash scripts/setup.sh "$preset"
  echo "== ctest --preset $preset" >&2
  ctest --preset "$preset"
done
# then the libFuzzer harnesses, each for a bounded time (FUZZ_SECONDS, default 60)
bash scripts/fuzz.sh
