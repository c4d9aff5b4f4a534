#!/usr/bin/env bash
# Start LCM's log player GUI (lcm.logging.LogPlayer) on an LCM log: play, pause, seek, change
# the speed, and turn channels on and off while it republishes the log on an LCM URL (into
# comlearn watch or scripts/lcm-spy.sh).
#
# Calls java itself: Debian's /usr/bin/lcm-logplayer-gui passes -Xincgc, which JDK 17 refuses
# ("Unrecognized option: -Xincgc"), so it never starts. The class path is the types' jar when it
# is built, then lcm.jar. LCM 1.3.1's LogPlayer lists channels and does not decode messages, so it
# also runs without the jar (with a warning). The checks are shared with scripts/lcm-spy.sh
# (scripts/lib/java.sh).
set -euo pipefail

here=$(cd "$(dirname "$0")/.." && pwd)
gui_tool=lcm-logplayer-gui.sh gui_here=$here
# shellcheck source=lib/java.sh
. "$here/scripts/lib/java.sh"
paused=0 log=
rerun=("$0")

usage() {
  cat <<EOF
usage: scripts/lcm-logplayer-gui.sh [--lcm-url URL] [--jar PATH] [--paused] [--check]
                                    [--install] [LOG]

Start LCM's log player GUI on LOG (an LCM log: lcm-logger's or comlearn record's), which
republishes it on URL. Without LOG it opens a file dialog.

  --lcm-url URL   LCM URL to publish on (default: $gui_default_url)
  --jar PATH      jar of comlearn's types, put on the class path when built (default:
                  \$COMLEARN_LCMTYPES_JAR if set, else
                  $gui_default_jar,
                  which 'bash scripts/setup.sh --gui' builds)
  --paused        start with the log paused (default: playing)
  --check         check the prerequisites and LOG, print the java command, do not start it
  --install       when a prerequisite package is missing, run 'bash scripts/setup.sh --gui'
                  (as root), then go on (default: say so, exit 1)
  -h, --help      this help

Java and lcm.jar are not in the default setup; a missing one is named with the command that
installs it: bash scripts/setup.sh --gui
Environment: COMLEARN_LCMTYPES_JAR (jar), JAVA (java executable; default: java on PATH),
COMLEARN_JAVA_LIBS (folder of lcm.jar; default: /usr/share/java).
Exit status: 1 a prerequisite is missing, 2 a bad option or LOG.
EOF
}

while [ $# -gt 0 ]; do
  gui_common_option "$@"
  if [ "$gui_shift" -gt 0 ]; then shift "$gui_shift"; continue; fi
  case "$1" in
    --paused) paused=1; rerun+=("$1"); shift ;;
    -h | --help) usage; exit 0 ;;
    --) shift; [ $# -le 1 ] || gui_usage_error "one LOG at most"
      [ $# -eq 0 ] || { log=$1; rerun+=(-- "$1"); shift; } ;;
    -*) gui_usage_error "unknown option '$1'" ;;
    *) [ -z "$log" ] || gui_usage_error "one LOG at most (got '$log' and '$1')"
      log=$1; rerun+=(-- "$1"); shift ;;
  esac
done
# The log: a readable file that starts as an LCM event does (sync word 0xEDA1DA01).
if [ -n "$log" ]; then
  [ -f "$log" ] && [ -r "$log" ] || gui_usage_error "LOG '$log' is not a readable file"
  [ "$(od -An -tx1 -N4 "$log" | tr -d ' \n')" = eda1da01 ] ||
    gui_usage_error "LOG '$log' is not an LCM log (it does not start with LCM's sync word EDA1DA01)"
fi
gui_common_checked

gui_find_java
gui_need_jar "$gui_java_libs/lcm.jar" liblcm-java
cp=$gui_java_libs/lcm.jar
if [ -f "$jar" ]; then
  gui_types_jar_fresh "$jar"
  cp=$jar:$cp
else
  echo "$gui_tool: warning: $(gui_types_jar_missing "$jar"); the log player lists channels" \
       "without it ($gui_setup_cmd builds it)" >&2
fi
gui_check_route "$url"

# Two words, not --lcm-url=URL: LCM 1.3.1's LogPlayer splits that one at every '=' and keeps the
# second piece, so udpm://...?ttl=0 would lose its "=0".
args=(--lcm-url "$url")
[ "$paused" -eq 0 ] || args+=(--paused)
# LogPlayer reads its one non-option argument as the log; ./ keeps a name like -x.log from
# looking like an option.
if [ -n "$log" ]; then
  case "$log" in
    -*) args+=("./$log") ;;
    *) args+=("$log") ;;
  esac
fi
gui_start "$check_only" "$gui_java" -Djava.net.preferIPv4Stack=true -Xms32m -Xmx128m -ea \
  -cp "$cp" lcm.logging.LogPlayer "${args[@]}"
