#!/usr/bin/env bash
# Start lcm-spy with comlearn's message types, so it decodes YUMI_COMMAND, YUMI_STATUS,
# OBJECT_STATE, SIM_CONTROL, COM_TRIAL and COM_ESTIMATE field by field (double-click a channel to
# open its message viewer).
#
# Calls java itself: Debian's /usr/bin/lcm-spy passes -Xincgc, which JDK 17 refuses.
# The class path is the types' jar (built by the default preset when a JDK is there), lcm.jar
# and jchart2d.jar (the message viewer needs it). None of it is in the default setup:
# 'bash scripts/setup.sh --gui' (or this script's --install) installs it. The checks are shared
# with scripts/lcm-logplayer-gui.sh (scripts/lib/java.sh).
set -euo pipefail

here=$(cd "$(dirname "$0")/.." && pwd)
gui_tool=lcm-spy.sh gui_here=$here
# shellcheck source=lib/java.sh
. "$here/scripts/lib/java.sh"
rerun=("$0")

usage() {
  cat <<EOF
usage: scripts/lcm-spy.sh [--lcm-url URL] [--jar PATH] [--check] [--install]

Start lcm-spy with comlearn's LCM types on the class path.

  --lcm-url URL   LCM URL to listen on (default: $gui_default_url)
  --jar PATH      jar of comlearn's types (default: \$COMLEARN_LCMTYPES_JAR if set, else
                  $gui_default_jar,
                  which 'bash scripts/setup.sh --gui' builds)
  --check         check the prerequisites, print the java command, do not start lcm-spy
  --install       when a prerequisite package or the jar is missing, run
                  'bash scripts/setup.sh --gui' (as root), then go on (default: say so, exit 1)
  -h, --help      this help

Java, lcm.jar, jchart2d.jar and the jar are not in the default setup; a missing one is named
with the command that installs it: bash scripts/setup.sh --gui
Environment: COMLEARN_LCMTYPES_JAR (jar), JAVA (java executable; default: java on PATH),
COMLEARN_JAVA_LIBS (folder of lcm.jar and jchart2d.jar; default: /usr/share/java).
EOF
}

while [ $# -gt 0 ]; do
  gui_common_option "$@"
  if [ "$gui_shift" -gt 0 ]; then shift "$gui_shift"; continue; fi
  case "$1" in
    -h|--help) usage; exit 0 ;;
    -*) gui_usage_error "unknown option '$1'" ;;
    *) gui_usage_error "unexpected argument '$1'" ;;
  esac
done
gui_common_checked

gui_find_java
gui_need_jar "$gui_java_libs/lcm.jar" liblcm-java
gui_need_jar "$gui_java_libs/jchart2d.jar" libjchart2d-java "the message viewer needs it"
[ -f "$jar" ] || gui_missing "$(gui_types_jar_missing "$jar")"
gui_types_jar_fresh "$jar"
gui_check_route "$url"

gui_start "$check_only" "$gui_java" -Djava.net.preferIPv4Stack=true -Xms64m -Xmx256m -ea \
  -cp "$jar:$gui_java_libs/lcm.jar:$gui_java_libs/jchart2d.jar" lcm.spy.Spy "--lcm-url=$url"
