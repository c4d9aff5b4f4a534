# Sourced by scripts/lcm-spy.sh and scripts/lcm-logplayer-gui.sh, not run on its own: what both
# wrappers of LCM's Java GUIs check before they start one, each failure naming its fix. They call
# java themselves because Debian's /usr/bin/lcm-spy and /usr/bin/lcm-logplayer-gui pass -Xincgc,
# which JDK 17 refuses ("Unrecognized option: -Xincgc").
#
# The caller sets gui_tool (its name in messages) and gui_here (the source tree) before sourcing
# and rerun=("$0"); it reads its options with gui_common_option (the shared ones: URL, jar,
# --check, --install) and ends them with gui_common_checked (gui_rerun: its own command line
# without --install, run again after installing).

# The packages are not part of the default setup (issue 16): this installs them and builds the jar.
gui_setup_cmd='bash scripts/setup.sh --gui'
gui_default_jar=$gui_here/build/default/lcmtypes/comlearn_lcmtypes.jar
# Where Debian's liblcm-java and libjchart2d-java put lcm.jar and jchart2d.jar.
gui_java_libs=${COMLEARN_JAVA_LIBS:-/usr/share/java}
gui_install=0
gui_rerun=()

# What both take: an LCM URL, the types' jar, --check and --install. The caller's url, jar,
# check_only and rerun (its command line so far) start from these defaults.
gui_default_url='udpm://239.255.76.67:7667?ttl=0'
url=$gui_default_url
jar=${COMLEARN_LCMTYPES_JAR:-$gui_default_jar}
check_only=0

# gui_common_option ARGS...: when ARGS starts with one of the options both wrappers take
# (--lcm-url URL, --jar PATH, each also as --opt=VALUE; --check; --install), apply it to url, jar,
# check_only or gui_install, add it to rerun (not --install) and set gui_shift to the number of
# words it used; else gui_shift=0.
gui_common_option() {
  gui_shift=0
  case "$1" in
    --lcm-url | --jar)
      [ $# -ge 2 ] || gui_usage_error "$1 needs a value"
      if [ "$1" = --jar ]; then jar=$2; else url=$2; fi
      rerun+=("$1" "$2") gui_shift=2 ;;
    --lcm-url=*) url=${1#--lcm-url=} gui_shift=1; rerun+=("$1") ;;
    --jar=*) jar=${1#--jar=} gui_shift=1; rerun+=("$1") ;;
    --check) check_only=1 gui_shift=1; rerun+=("$1") ;;
    --install) gui_install=1 gui_shift=1 ;;
  esac
}

# gui_common_checked: after the options, the URL and the jar must not be empty; gui_rerun is the
# command line seen.
gui_common_checked() {
  [ -n "$url" ] || gui_usage_error "--lcm-url is empty"
  [ -n "$jar" ] || gui_usage_error "--jar is empty"
  gui_rerun=("${rerun[@]}")
}

gui_die() {
  echo "$gui_tool: $*" >&2
  exit 1
}

# gui_usage_error WHAT...: bad command line, exit 2.
gui_usage_error() {
  echo "$gui_tool: $* (try --help)" >&2
  exit 2
}

# gui_missing WHAT...: a GUI package or the jar is missing. With --install, run the setup and
# then this script again (without --install, so at most once); else fail naming the command.
gui_missing() {
  if [ "$gui_install" -eq 1 ]; then
    echo "$gui_tool: $*; running: $gui_setup_cmd" >&2
    (cd "$gui_here" && bash scripts/setup.sh --gui) >&2 ||
      gui_die "'$gui_setup_cmd' failed (it installs packages as root)"
    exec bash "${gui_rerun[@]}"
  fi
  gui_die "$*
  the GUI tools' packages (a JRE with AWT, a JDK, liblcm-java, libjchart2d-java) are not part
  of the default setup; install them and build the jar (as root, in $gui_here):
    $gui_setup_cmd
  or run this script again with --install"
}

# gui_find_java: gui_java, a java that can open a window ($JAVA, default: java on PATH).
gui_find_java() {
  local home
  gui_java=$(command -v "${JAVA:-java}") || gui_missing "no java ('${JAVA:-java}' not found)"
  home=$("$gui_java" -XshowSettings:properties -version 2>&1 | sed -n 's/^ *java\.home = //p')
  [ -n "$home" ] || gui_die "'$gui_java' did not say its java.home: is it a Java runtime?"
  # A headless JRE (default-jre-headless, the JDK's own dependency) has no libawt_xawt.
  [ -e "$home/lib/libawt_xawt.so" ] ||
    gui_missing "$home is a headless Java runtime (no lib/libawt_xawt.so), and $gui_tool starts a GUI"
}

# gui_need_jar PATH PACKAGE [WHY]: fail naming the Debian PACKAGE when PATH is missing.
gui_need_jar() {
  [ -f "$1" ] || gui_missing "$1 missing${3:+ ($3)} (Debian package $2)"
}

# gui_types_jar_fresh JAR: warn when an .lcm file is newer than the jar built from it.
gui_types_jar_fresh() {
  local lcm_file
  for lcm_file in "$gui_here"/lcmtypes/*.lcm; do
    if [ "$lcm_file" -nt "$1" ]; then
      echo "$gui_tool: warning: $1 is older than ${lcm_file#"$gui_here"/}; rebuild it" \
           "(cmake --build --preset default) or that type is not recognized" >&2
    fi
  done
}

# gui_types_jar_missing JAR: the message for a jar that is not built.
gui_types_jar_missing() {
  if [ "$1" = "$gui_default_jar" ]; then
    echo "the jar of comlearn's types is not built: $1"
  else
    echo "the jar of comlearn's types is not built: $1 (or point --jar /" \
         "COMLEARN_LCMTYPES_JAR at a build's lcmtypes/comlearn_lcmtypes.jar)"
  fi
}

# gui_check_route URL: udpm needs a route for its multicast group; a host with only loopback
# has none.
gui_check_route() {
  local group
  case "$1" in
    udpm://*)
      group=${1#udpm://}
      group=${group%%\?*}
      group=${group%%:*}
      [ -n "$group" ] || group=239.255.76.67
      if command -v ip >/dev/null 2>&1 && ! ip route get "$group" >/dev/null 2>&1; then
        gui_die "no route to the multicast group $group, so LCM cannot use $1.
  With only loopback, add one (as root):  ip route add 224.0.0.0/4 dev lo"
      fi
      ;;
  esac
}

# gui_start CHECK_ONLY CMD...: print "TOOL: ready: CMD" for --check (1), else start CMD.
gui_start() {
  local check_only=$1
  shift
  if [ "$check_only" -eq 1 ]; then
    printf '%s: ready:' "$gui_tool"
    printf ' %q' "$@"
    printf '\n'
    exit 0
  fi
  [ -n "${DISPLAY:-}" ] ||
    gui_die "DISPLAY is not set: $gui_tool starts a GUI (use a desktop session, ssh -X, or xvfb-run)"
  exec "$@"
}
