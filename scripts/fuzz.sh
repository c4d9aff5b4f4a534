#!/usr/bin/env bash
# Build the libFuzzer harnesses (tests/fuzz; the fuzz preset: clang with ASan and UBSan) and run
# each one for FUZZ_SECONDS seconds (default 60) on a scratch copy of its seed corpus. A crash, a
# leak, an out-of-memory or a hang (an input over 30 s) fails the run; the input that did it is
# kept in build/fuzz/artifacts/. Needs root the first time, to install clang. docs/security.md.
# usage: scripts/fuzz.sh [-h|--help]     (environment: FUZZ_SECONDS, default 60)
set -euo pipefail
case "${1:-}" in
  -h | --help)
    sed -n '2,6p' "$0" | sed 's/^# \{0,1\}//'
    exit 0
    ;;
  "") ;;
  *)
    echo "fuzz.sh: unexpected argument '$1' (try --help)" >&2
    exit 2
    ;;
esac
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"
seconds=${FUZZ_SECONDS:-60}
bash scripts/setup.sh fuzz
mkdir -p build/fuzz/artifacts
for h in msg mesh urdf; do
  work=build/fuzz/corpus/$h
  rm -rf "$work"
  mkdir -p "$work"
  echo "== fuzz_$h for ${seconds} s" >&2
  # new inputs go to the scratch corpus; the seeds (tests/fuzz/corpus/$h) are only read
  build/fuzz/tests/fuzz_$h -max_total_time="$seconds" -timeout=30 -rss_limit_mb=4096 \
    -print_final_stats=1 -artifact_prefix=build/fuzz/artifacts/ "$work" "tests/fuzz/corpus/$h" \
    2> "build/fuzz/fuzz_$h.log" || {
    tail -40 "build/fuzz/fuzz_$h.log" >&2
    echo "fuzz.sh: fuzz_$h failed; its input is in build/fuzz/artifacts/" >&2
    exit 1
  }
  grep -E "^stat::number_of_executed_units|^stat::peak_rss_mb" "build/fuzz/fuzz_$h.log" >&2 || true
done
echo "fuzz.sh: no crash, leak or hang in ${seconds} s per harness" >&2
