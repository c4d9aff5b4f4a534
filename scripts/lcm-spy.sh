#!/usr/bin/env bash
# Start lcm-spy with comlearn's message types, so it decodes YUMI_COMMAND, YUMI_STATUS,
# OBJECT_STATE, SIM_CONTROL, COM_TRIAL and COM_ESTIMATE field by field (double-click a channel to
# open its message viewer).
#
# Calls java itself: Debian's /usr/bin/lcm-spy passes -Xincgc, which JDK 17 refuses.
# The class path is the types' jar (built by the default preset), lcm.jar and jchart2d.jar (the
# message viewer needs it).
set -euo pipefail

here=$(cd "$(dirname "$0")/.." && pwd)
default_url='udpm://239.255.76.67:7667?ttl=0'
default_jar="$here/build/default/lcmtypes/comlearn_lcmtypes.jar"
url=$default_url
jar=${COMLEARN_LCMTYPES_JAR:-$default_jar}
check_only=0

usage() {
  cat <<EOF
usage: scripts/lcm-spy.sh [--lcm-url URL] [--jar PATH] [--check]

Start lcm-spy with comlearn's LCM types on the class path.

  --lcm-url URL   LCM URL to listen on (default: $default_url)
  --jar PATH      jar of comlearn's types (default: \$COMLEARN_LCMTYPES_JAR if set, else
                  $default_jar,
                  which 'scripts/setup.sh' or 'cmake --build --preset default' builds)
  --check         check the prerequisites, print the java command, do not start lcm-spy
  -h, --help      this help

Environment: COMLEARN_LCMTYPES_JAR (jar), JAVA (java executable; default: java on PATH).
EOF
}

die() {
  echo "lcm-spy.sh: $*" >&2
  exit 1
}

while [ $# -gt 0 ]; do
  case "$1" in
    --lcm-url) [ $# -ge 2 ] || { usage >&2; exit 2; }; url=$2; shift 2 ;;
    --lcm-url=*) url=${1#--lcm-url=}; shift ;;
    --jar) [ $# -ge 2 ] || { usage >&2; exit 2; }; jar=$2; shift 2 ;;
    --jar=*) jar=${1#--jar=}; shift ;;
    --check) check_only=1; shift ;;
    -h|--help) usage; exit 0 ;;
    *) echo "lcm-spy.sh: unknown argument: $1" >&2; usage >&2; exit 2 ;;
  esac
done
[ -n "$url" ] || die "--lcm-url is empty"

# Java with a GUI toolkit (a headless JRE has no libawt_xawt).
java=${JAVA:-java}
command -v "$java" >/dev/null 2>&1 ||
  die "no java: install a JRE (apt-get install default-jre), or set JAVA"
java_home=$("$java" -XshowSettings:properties -version 2>&1 | sed -n 's/^ *java\.home = //p')
if [ -n "$java_home" ] && [ ! -e "$java_home/lib/libawt_xawt.so" ]; then
  die "$java_home is a headless Java runtime (no lib/libawt_xawt.so) and lcm-spy is a GUI:" \
      "apt-get install default-jre (or openjdk-17-jre), or set JAVA to a java with AWT"
fi

# The jars.
if [ ! -f "$jar" ]; then
  die "the jar of comlearn's types is not built: $jar
  build it with: scripts/setup.sh   (or: cmake --preset default && cmake --build --preset default)
  or point --jar / COMLEARN_LCMTYPES_JAR at a build's lcmtypes/comlearn_lcmtypes.jar"
fi
for lcm_file in "$here"/lcmtypes/*.lcm; do
  if [ "$lcm_file" -nt "$jar" ]; then
    echo "lcm-spy.sh: warning: $jar is older than ${lcm_file#"$here"/}; rebuild it" \
         "(cmake --build --preset default) or lcm-spy may not recognize that type" >&2
  fi
done
lcm_jar=/usr/share/java/lcm.jar
chart_jar=/usr/share/java/jchart2d.jar
[ -f "$lcm_jar" ] || die "$lcm_jar missing: apt-get install liblcm-java"
[ -f "$chart_jar" ] ||
  die "$chart_jar missing (the message viewer needs it): apt-get install libjchart2d-java"

# udpm needs a route for its multicast group; a host with only loopback has none.
case "$url" in
  udpm://*)
    group=${url#udpm://}
    group=${group%%\?*}
    group=${group%%:*}
    [ -n "$group" ] || group=239.255.76.67
    if command -v ip >/dev/null 2>&1 && ! ip route get "$group" >/dev/null 2>&1; then
      die "no route to the multicast group $group, so LCM cannot receive on $url.
  With only loopback, add one (as root):  ip route add 224.0.0.0/4 dev lo"
    fi
    ;;
esac

cmd=("$java" -Djava.net.preferIPv4Stack=true -Xms64m -Xmx256m -ea
     -cp "$jar:$lcm_jar:$chart_jar" lcm.spy.Spy "--lcm-url=$url")

if [ "$check_only" -eq 1 ]; then
  printf 'lcm-spy.sh: ready:'
  printf ' %q' "${cmd[@]}"
  printf '\n'
  exit 0
fi
[ -n "${DISPLAY:-}" ] ||
  die "DISPLAY is not set: lcm-spy is a GUI (use a desktop session, ssh -X, or xvfb-run)"
exec "${cmd[@]}"
