#!/usr/bin/env bash
# The wrappers of LCM's Java GUIs, scripts/lcm-spy.sh and scripts/lcm-logplayer-gui.sh (issue 16).
# 1. Without a real Java (fake java, fake jar folder, fake ip, a copy of the scripts with a
#    fake setup.sh): each missing prerequisite exits 1 naming 'bash scripts/setup.sh --gui';
#    --install runs setup.sh --gui once and goes on; a bad LOG exits 2; no route and no DISPLAY
#    are named.
# 2. With this machine's java (needs AWT), lcm.jar, jchart2d.jar and the build's types jar:
#    --check prints the java command with the right main class, class path and URL, and that
#    command (its arguments replaced by --help) loads the main class on this JDK; Debian's
#    /usr/bin/lcm-logplayer-gui does not (-Xincgc). Without them: exit 77 (CTest: skipped).
# usage: gui_wrappers.sh SOURCE_DIR [TYPES_JAR]   (TYPES_JAR empty: the build made none)
set -uo pipefail
unset JAVA COMLEARN_JAVA_LIBS COMLEARN_LCMTYPES_JAR
[ $# -ge 1 ] && [ $# -le 2 ] || { echo "usage: gui_wrappers.sh SOURCE_DIR [TYPES_JAR]" >&2; exit 2; }
src=$(cd "$1" && pwd)
types_jar=${2:-}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fails=0
fail() { echo "FAIL: $*" >&2; fails=$((fails + 1)); }
spy=$src/scripts/lcm-spy.sh
player=$src/scripts/lcm-logplayer-gui.sh
fix='bash scripts/setup.sh --gui'

# run CMD...: exit status into rc, stdout into $tmp/out, stderr into $tmp/err
run() { timeout 60 "$@" >"$tmp/out" 2>"$tmp/err"; rc=$?; }
# expect_fail WHAT RC PATTERN CMD...: CMD exits RC and its stderr matches PATTERN (grep -E)
expect_fail() {
  local what=$1 want=$2 pattern=$3
  shift 3
  run "$@"
  [ "$rc" -eq "$want" ] || { fail "$what: exit $rc, not $want ($(head -n 1 "$tmp/err"))"; return; }
  grep -Eq -- "$pattern" "$tmp/err" || fail "$what: stderr lacks /$pattern/: $(cat "$tmp/err")"
}
# ready_cmd: the command --check printed (on stdout, shell-quoted), into the array cmd
ready_cmd() {
  local line
  line=$(sed -n "s/^$1: ready: //p" "$tmp/out")
  cmd=()
  [ -n "$line" ] && eval "cmd=($line)"
}
# arg_after WORD: the element of cmd after WORD (empty if none)
arg_after() {
  local i
  for ((i = 0; i + 1 < ${#cmd[@]}; i++)); do
    [ "${cmd[i]}" = "$1" ] && { printf '%s' "${cmd[i + 1]}"; return; }
  done
}

# An LCM log of one event: sync word, event number, time, channel and data lengths, both.
log=$tmp/one.lcmlog
printf '\xed\xa1\xda\x01\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\1\0\0\0\4\0\0\0\2TEST\1\2' >"$log"
printf 'not a log\n' >"$tmp/text.log"

# --- 1. fakes ----------------------------------------------------------------------------------
# A java that reports a java.home with or without AWT's X11 library.
mkdir -p "$tmp/bin" "$tmp/jre/lib" "$tmp/libs" "$tmp/nolibs" "$tmp/noroute"
cat >"$tmp/bin/java" <<EOF
#!/bin/sh
echo "    java.home = $tmp/jre" >&2
EOF
chmod +x "$tmp/bin/java"
fake=$tmp/bin/java
: >"$tmp/libs/lcm.jar"
: >"$tmp/libs/jchart2d.jar"
: >"$tmp/types.jar"
printf '#!/bin/sh\nexit 1\n' >"$tmp/noroute/ip"
chmod +x "$tmp/noroute/ip"

for s in "$spy" "$player"; do
  n=$(basename "$s")
  expect_fail "$n, no java" 1 "no java \('$tmp/none/java' not found\)" \
    env JAVA="$tmp/none/java" bash "$s" --check
  grep -qF "$fix" "$tmp/err" || fail "$n, no java: does not name '$fix'"
  grep -qF -- "--install" "$tmp/err" || fail "$n, no java: does not name --install"
  expect_fail "$n, headless java" 1 "$tmp/jre is a headless Java runtime .*starts a GUI" \
    env JAVA="$fake" bash "$s" --check
  grep -qF "$fix" "$tmp/err" || fail "$n, headless java: does not name '$fix'"
done
: >"$tmp/jre/lib/libawt_xawt.so"
for s in "$spy" "$player"; do
  n=$(basename "$s")
  expect_fail "$n, no lcm.jar" 1 "$tmp/nolibs/lcm.jar missing \(Debian package liblcm-java\)" \
    env JAVA="$fake" COMLEARN_JAVA_LIBS="$tmp/nolibs" bash "$s" --check --jar "$tmp/types.jar"
  grep -qF "$fix" "$tmp/err" || fail "$n, no lcm.jar: does not name '$fix'"
  expect_fail "$n, no route" 1 'no route to the multicast group 239\.255\.76\.67.*' \
    env JAVA="$fake" COMLEARN_JAVA_LIBS="$tmp/libs" PATH="$tmp/noroute:$PATH" \
    bash "$s" --check --jar "$tmp/types.jar"
  grep -qF 'ip route add 224.0.0.0/4 dev lo' "$tmp/err" || fail "$n, no route: no fix named"
  expect_fail "$n, no DISPLAY" 1 'DISPLAY is not set' \
    env -u DISPLAY JAVA="$fake" COMLEARN_JAVA_LIBS="$tmp/libs" bash "$s" --jar "$tmp/types.jar" \
    --lcm-url tcpq://127.0.0.1:7700
  expect_fail "$n, empty --lcm-url" 2 '--lcm-url is empty' bash "$s" --lcm-url ''
done
: >"$tmp/nolibs/lcm.jar"
expect_fail "lcm-spy.sh, no jchart2d.jar" 1 \
  "$tmp/nolibs/jchart2d.jar missing \(the message viewer needs it\) \(Debian package libjchart2d-java\)" \
  env JAVA="$fake" COMLEARN_JAVA_LIBS="$tmp/nolibs" bash "$spy" --check --jar "$tmp/types.jar"
expect_fail "lcm-spy.sh, no types jar" 1 "the jar of comlearn's types is not built: $tmp/none.jar" \
  env JAVA="$fake" COMLEARN_JAVA_LIBS="$tmp/libs" bash "$spy" --check --jar "$tmp/none.jar"
grep -qF "$fix" "$tmp/err" || fail "lcm-spy.sh, no types jar: does not name '$fix'"
# The log player needs no jchart2d and runs without the types' jar (LogPlayer decodes nothing).
run env JAVA="$fake" COMLEARN_JAVA_LIBS="$tmp/nolibs" bash "$player" --check --jar "$tmp/none.jar" \
  --lcm-url 'tcpq://127.0.0.1:7700' "$log"
ready_cmd lcm-logplayer-gui.sh
[ "$rc" -eq 0 ] && [ "$(arg_after -cp)" = "$tmp/nolibs/lcm.jar" ] &&
  [ "$(arg_after lcm.logging.LogPlayer)" = --lcm-url ] && [ "${cmd[-1]}" = "$log" ] &&
  grep -q "warning: the jar of comlearn's types is not built: $tmp/none.jar" "$tmp/err" ||
  fail "lcm-logplayer-gui.sh without jchart2d and the types' jar: exit $rc, ${cmd[*]:-}, $(cat "$tmp/err")"

# LOG and the command line: exit 2, the problem named.
expect_fail "lcm-logplayer-gui.sh, missing LOG" 2 "LOG '$tmp/none.lcmlog' is not a readable file" \
  bash "$player" --check "$tmp/none.lcmlog"
expect_fail "lcm-logplayer-gui.sh, text LOG" 2 "LOG '$tmp/text.log' is not an LCM log" \
  bash "$player" --check "$tmp/text.log"
expect_fail "lcm-logplayer-gui.sh, two LOGs" 2 "one LOG at most" bash "$player" --check "$log" "$log"
expect_fail "lcm-logplayer-gui.sh, --jar without value" 2 "--jar needs a value" bash "$player" --jar
expect_fail "lcm-spy.sh, an argument" 2 "unexpected argument 'x'" bash "$spy" x

# --install: a copy of the scripts whose setup.sh records its arguments and "installs" the jar;
# the wrapper runs it once, then itself again without --install, and gets ready.
tree=$tmp/tree
mkdir -p "$tree/scripts/lib" "$tree/lcmtypes" "$tree/build/default/lcmtypes"
cp "$spy" "$player" "$tree/scripts/"
cp "$src/scripts/lib/java.sh" "$tree/scripts/lib/"
cat >"$tree/scripts/setup.sh" <<EOF
#!/bin/sh
echo "\$*" >>"$tmp/setup.calls"
: >"$tree/build/default/lcmtypes/comlearn_lcmtypes.jar"
EOF
run env JAVA="$fake" COMLEARN_JAVA_LIBS="$tmp/libs" bash "$tree/scripts/lcm-spy.sh" --install \
  --check --lcm-url tcpq://127.0.0.1:7700
ready_cmd lcm-spy.sh
[ "$rc" -eq 0 ] && [ "$(cat "$tmp/setup.calls" 2>/dev/null)" = --gui ] &&
  [ "$(arg_after -cp)" = "$tree/build/default/lcmtypes/comlearn_lcmtypes.jar:$tmp/libs/lcm.jar:$tmp/libs/jchart2d.jar" ] &&
  grep -qF "running: $fix" "$tmp/err" ||
  fail "lcm-spy.sh --install: exit $rc, setup.sh called with '$(cat "$tmp/setup.calls" 2>/dev/null)', ${cmd[*]:-}, $(cat "$tmp/err")"
# Nothing missing: --install does not run setup.sh.
rm -f "$tmp/setup.calls"
run env JAVA="$fake" COMLEARN_JAVA_LIBS="$tmp/libs" bash "$tree/scripts/lcm-logplayer-gui.sh" \
  --install --check --lcm-url tcpq://127.0.0.1:7700 "$log"
[ "$rc" -eq 0 ] && [ ! -e "$tmp/setup.calls" ] ||
  fail "lcm-logplayer-gui.sh --install with nothing missing: exit $rc, setup.sh ran: $(cat "$tmp/setup.calls" 2>/dev/null)"
# A setup that fails (not root): named, exit 1, no loop.
printf '#!/bin/sh\necho "setup: need root" >&2\nexit 1\n' >"$tree/scripts/setup.sh"
rm -f "$tree/build/default/lcmtypes/comlearn_lcmtypes.jar"
expect_fail "lcm-spy.sh --install, setup fails" 1 "'$fix' failed" \
  env JAVA="$fake" COMLEARN_JAVA_LIBS="$tmp/libs" bash "$tree/scripts/lcm-spy.sh" --install --check

# --- 2. this machine's Java ----------------------------------------------------------------------
skip=
java=$(command -v java || true)
libs=/usr/share/java
if [ -z "$java" ]; then
  skip="no java"
else
  home=$("$java" -XshowSettings:properties -version 2>&1 | sed -n 's/^ *java\.home = //p')
  [ -e "$home/lib/libawt_xawt.so" ] || skip="java ($home) is headless"
fi
[ -n "$skip" ] || [ -f "$libs/lcm.jar" ] || skip="no $libs/lcm.jar"
[ -n "$skip" ] || [ -f "$libs/jchart2d.jar" ] || skip="no $libs/jchart2d.jar"
[ -n "$skip" ] || [ -n "$types_jar" ] || skip="the build made no types jar (no JDK at configure)"
[ -n "$skip" ] || [ -f "$types_jar" ] || skip="$types_jar not built"
if [ -n "$skip" ]; then
  [ "$fails" -eq 0 ] || { echo "$fails failures" >&2; exit 1; }
  echo "gui wrappers: the checks without Java passed; SKIP the ones with Java: $skip ($fix installs it)"
  exit 77
fi

port=$((20000 + $$ % 30000))
url="udpm://239.255.76.67:$port?ttl=0"
ip route get 239.255.76.67 >/dev/null 2>&1 || url="tcpq://127.0.0.1:$port"
run bash "$spy" --check --jar "$types_jar" --lcm-url "$url"
ready_cmd lcm-spy.sh
[ "$rc" -eq 0 ] || fail "lcm-spy.sh --check: exit $rc: $(cat "$tmp/err")"
[ "${cmd[0]:-}" = "$java" ] || fail "lcm-spy.sh: java is '${cmd[0]:-}', not $java"
[ "$(arg_after -cp)" = "$types_jar:$libs/lcm.jar:$libs/jchart2d.jar" ] ||
  fail "lcm-spy.sh: class path '$(arg_after -cp)'"
[ "$(arg_after lcm.spy.Spy)" = "--lcm-url=$url" ] || fail "lcm-spy.sh: main class and URL: ${cmd[*]}"
[ "${cmd[-1]}" = "--lcm-url=$url" ] || fail "lcm-spy.sh: the URL is not last: ${cmd[*]}"
# The same java, options and class path start Spy on this JDK (--help: usage, no window).
spy_cmd=("${cmd[@]}")
unset 'spy_cmd[${#spy_cmd[@]}-1]'
run env -u DISPLAY "${spy_cmd[@]}" --help
grep -q '^usage: lcm-spy' "$tmp/err" || fail "lcm-spy.sh's java command did not start Spy: $(cat "$tmp/err")"

run bash "$player" --check --jar "$types_jar" --lcm-url "$url" --paused "$log"
ready_cmd lcm-logplayer-gui.sh
[ "$rc" -eq 0 ] || fail "lcm-logplayer-gui.sh --check: exit $rc: $(cat "$tmp/err")"
[ "${cmd[0]:-}" = "$java" ] || fail "lcm-logplayer-gui.sh: java is '${cmd[0]:-}', not $java"
[ "$(arg_after -cp)" = "$types_jar:$libs/lcm.jar" ] ||
  fail "lcm-logplayer-gui.sh: class path '$(arg_after -cp)'"
# --lcm-url and the URL as two words (LogPlayer splits --lcm-url=URL at '='), then the log.
n=${#cmd[@]}
[ "$n" -ge 5 ] && [ "${cmd[n - 5]}" = lcm.logging.LogPlayer ] && [ "${cmd[n - 4]}" = --lcm-url ] &&
  [ "${cmd[n - 3]}" = "$url" ] && [ "${cmd[n - 2]}" = --paused ] && [ "${cmd[n - 1]}" = "$log" ] ||
  fail "lcm-logplayer-gui.sh: main class, URL, --paused and log: ${cmd[*]}"
if printf '%s\n' "${cmd[@]}" | grep -q -- '-Xincgc'; then fail "lcm-logplayer-gui.sh passes -Xincgc"; fi
run env -u DISPLAY "${cmd[@]:0:n-4}" --help
grep -q '^usage: lcm-logplayer-gui' "$tmp/err" ||
  fail "lcm-logplayer-gui.sh's java command did not start LogPlayer: $(cat "$tmp/err")"
# Why the wrapper exists: Debian's script does not start on this JDK.
if [ -x /usr/bin/lcm-logplayer-gui ]; then
  run env -u DISPLAY /usr/bin/lcm-logplayer-gui --help
  [ "$rc" -ne 0 ] && grep -q 'Unrecognized option: -Xincgc' "$tmp/err" ||
    fail "/usr/bin/lcm-logplayer-gui --help: exit $rc, $(head -n 2 "$tmp/err") (fixed? then the docs are stale)"
fi

[ "$fails" -eq 0 ] || { echo "$fails failures" >&2; exit 1; }
echo "gui wrappers: lcm-spy.sh and lcm-logplayer-gui.sh checked, with this machine's java ($java)"
