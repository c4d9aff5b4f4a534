#!/bin/sh
# bench/cortex_m4.sh: build lib/qlearn for Cortex-M4 (arm-none-eabi-gcc, -mcpu=cortex-m4 -mthumb
# -Os, hard float) and print text / data / bss per object and for the archive, plus a link check
# against newlib's libm (erfc, exp, sqrt, log2...). Installs Debian's gcc-arm-none-eabi and
# libnewlib-arm-none-eabi if missing (needs root). Usage: bench/cortex_m4.sh [outdir]
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
case "${1:-}" in
  -h | --help)
    echo "usage: bench/cortex_m4.sh [OUTDIR]   (default OUTDIR: \$TMPDIR/comlearn_cortex_m4)"
    echo "lib/qlearn built for Cortex-M4: text / data / bss per object and archive, and a link check."
    exit 0 ;;
  -*) echo "cortex_m4.sh: unknown option '$1' (try --help)" >&2; exit 2 ;;
esac
[ $# -le 1 ] || { echo "cortex_m4.sh: one OUTDIR at most (try --help)" >&2; exit 2; }
out=${1:-${TMPDIR:-/tmp}/comlearn_cortex_m4}
if ! command -v arm-none-eabi-gcc >/dev/null 2>&1; then
  echo "installing gcc-arm-none-eabi libnewlib-arm-none-eabi" >&2
  apt-get install -y --no-install-recommends gcc-arm-none-eabi libnewlib-arm-none-eabi >&2
fi
mkdir -p "$out"
flags="-std=c11 -mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16 -Os -ffreestanding
  -ffunction-sections -fdata-sections -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Werror"
objs=""
for src in policy qtable mlp paper bisect pba solve; do
  # shellcheck disable=SC2086
  arm-none-eabi-gcc $flags -I"$here/lib/qlearn/include" -I"$here/lib/math/include" \
    -I"$here/lib/qlearn/src" \
    -c "$here/lib/qlearn/src/$src.c" -o "$out/$src.o"
  objs="$objs $out/$src.o"
done
rm -f "$out/libcomlearn_qlearn.a"
# shellcheck disable=SC2086
arm-none-eabi-ar rcs "$out/libcomlearn_qlearn.a" $objs
echo "arm-none-eabi-gcc $(arm-none-eabi-gcc -dumpversion): $flags" | tr -s ' \n' ' '
echo
# shellcheck disable=SC2086
arm-none-eabi-size -t $objs
# Link check: every policy and the solve, with newlib's libm and nosys stubs.
cat > "$out/main.c" <<'EOC'
#include "comlearn/qlearn.h"
#include "comlearn/qlearn_solve.h"
static qlearn_policy_t policy;
static qlearn_solve_t solve;
int main(void) {
  qlearn_policy_config_t cfg;
  double x = 0.0, c = 0.0, hw = 0.0;
  for (int k = 0; k < 4; ++k) {
    qlearn_policy_config_default((qlearn_policy_kind_t)k, &cfg);
    if (qlearn_policy_init(&policy, &cfg) != QLEARN_OK) return 1;
    while (qlearn_policy_next(&policy, &x) == QLEARN_OK)
      if (qlearn_policy_observe(&policy, x, x < 0.01 ? QLEARN_TIPS : QLEARN_STAYS)) break;
    (void)qlearn_policy_estimate(&policy, &c, &hw);
  }
  qlearn_solve_result_t r;
  (void)qlearn_solve_init(&solve);
  (void)qlearn_solve_add_plane(&solve, (const double[3]){1, 0, 0}, c, 1e-4);
  return qlearn_solve_compute(&solve, 1.96, 1e-3, &r) == QLEARN_OK ? 0 : 2;
}
EOC
# shellcheck disable=SC2086
arm-none-eabi-gcc $flags -I"$here/lib/qlearn/include" "$out/main.c" "$out/libcomlearn_qlearn.a" \
  -Wl,--gc-sections -specs=nosys.specs -lm -o "$out/qlearn_m4.elf"
echo "linked image (main + lib/qlearn + newlib libm/libc, -specs=nosys.specs, --gc-sections):"
arm-none-eabi-size "$out/qlearn_m4.elf"
if arm-none-eabi-nm "$out/libcomlearn_qlearn.a" | grep -Eq ' U (malloc|calloc|realloc|free)$'; then
  echo "FAIL: the archive references the allocator" >&2
  exit 1
fi
echo "no allocator symbol in the Cortex-M4 archive"
