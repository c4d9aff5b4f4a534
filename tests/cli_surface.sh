#!/usr/bin/env bash
# The command-line surface every comlearn program and script shares (issue 16): --version prints
# "NAME VERSION" and exits 0; --help exits 0 with text on stdout and does nothing else; an unknown
# option exits 2 naming it; an option without its value says which. Scripts answer --help
# without side effects.
# usage: cli_surface.sh VERSION SOURCE_DIR PROGRAM...
set -uo pipefail
version=$1 src=$2
shift 2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fails=0
fail() { echo "FAIL: $*" >&2; fails=$((fails + 1)); }

# run CMD...: exit status into rc, stdout into $tmp/out, stderr into $tmp/err
run() { (cd "$tmp/cwd" && timeout 20 "$@" >"$tmp/out" 2>"$tmp/err"); rc=$?; }
mkdir -p "$tmp/cwd"

for prog in "$@"; do
  name=$(basename "$prog")
  run "$prog" --version
  [ "$rc" -eq 0 ] || fail "$name --version: exit $rc"
  [ "$(cat "$tmp/out")" = "$name $version" ] || fail "$name --version printed '$(cat "$tmp/out")'"
  run "$prog" --help
  [ "$rc" -eq 0 ] || fail "$name --help: exit $rc"
  [ -s "$tmp/out" ] || fail "$name --help: nothing on stdout"
  grep -qi usage "$tmp/out" || fail "$name --help: no usage line"
  run "$prog" --no-such-option
  [ "$rc" -eq 2 ] || fail "$name --no-such-option: exit $rc"
  grep -q "unknown option '--no-such-option'" "$tmp/err" ||
    fail "$name --no-such-option said: $(head -n 1 "$tmp/err")"
done

# The comlearn commands, each on its own.
comlearn=
for prog in "$@"; do [ "$(basename "$prog")" = comlearn ] && comlearn=$prog; done
if [ -n "$comlearn" ]; then
  for cmd in inspect estimate watch stack experiments record logcheck plan; do
    run "$comlearn" "$cmd" --version
    [ "$rc" -eq 0 ] && [ "$(cat "$tmp/out")" = "comlearn $version" ] ||
      fail "comlearn $cmd --version: exit $rc, '$(cat "$tmp/out")'"
    run "$comlearn" "$cmd" --no-such-option
    [ "$rc" -eq 2 ] && grep -q "^comlearn $cmd: error: unknown option '--no-such-option'" "$tmp/err" ||
      fail "comlearn $cmd --no-such-option: exit $rc, $(head -n 1 "$tmp/err")"
  done
  run "$comlearn" estimate x.urdf --seed
  grep -q "comlearn estimate: error: --seed needs a value" "$tmp/err" ||
    fail "comlearn estimate --seed (no value) said: $(head -n 1 "$tmp/err")"
  run "$comlearn" record -c
  grep -q "comlearn record: error: -c needs a value" "$tmp/err" ||
    fail "comlearn record -c (no value) said: $(head -n 1 "$tmp/err")"
  run "$comlearn" --version
  [ "$(cat "$tmp/out")" = "comlearn $version" ] || fail "comlearn --version: '$(cat "$tmp/out")'"
  # the backend named the same way everywhere: --direct (in-process) or --lcm-url, not both
  for cmd in estimate stack experiments; do
    run "$comlearn" "$cmd" x.urdf --direct --lcm-url 'udpm://239.255.76.67:7667?ttl=0'
    [ "$rc" -eq 2 ] && grep -q "^comlearn: error: --direct.*--lcm-url" "$tmp/err" ||
      fail "comlearn $cmd --direct --lcm-url: exit $rc, $(head -n 1 "$tmp/err")"
  done
fi
for prog in "$@"; do
  [ "$(basename "$prog")" = comlearn-sim ] || continue
  run "$prog" --seed
  grep -q "comlearn-sim: error: --seed needs a value" "$tmp/err" ||
    fail "comlearn-sim --seed (no value) said: $(head -n 1 "$tmp/err")"
  run "$prog" extra
  [ "$rc" -eq 2 ] && grep -q "comlearn-sim: error: unexpected argument 'extra'" "$tmp/err" ||
    fail "comlearn-sim extra: exit $rc, $(head -n 1 "$tmp/err")"
  run "$prog" --lcm # an abbreviation getopt_long takes
  grep -q "comlearn-sim: error: --lcm-url needs a value" "$tmp/err" ||
    fail "comlearn-sim --lcm (no value) said: $(head -n 1 "$tmp/err")"
done

# One name per kind of output (docs/design.md, "Command-line contracts"): --out DIR for a folder,
# --svg FILE for one picture; the older spellings still do the same.
for prog in "$@"; do
  case "$(basename "$prog")" in
    comlearn-shapegen)
      run "$prog" --family box --seed 3 --count 1 --out "$tmp/a" &&
        run "$prog" --family box --seed 3 --count 1 --out-dir "$tmp/b"
      [ "$rc" -eq 0 ] && diff -r "$tmp/a" "$tmp/b" >/dev/null && [ -n "$(ls "$tmp/a")" ] ||
        fail "comlearn-shapegen --out and --out-dir differ"
      rm -rf "$tmp/a" "$tmp/b" ;;
    comlearn-rocks-svg)
      run "$prog" --svg "$tmp/a.svg" && run "$prog" --out "$tmp/b.svg"
      [ "$rc" -eq 0 ] && grep -q '<svg' "$tmp/a.svg" && cmp -s "$tmp/a.svg" "$tmp/b.svg" ||
        fail "comlearn-rocks-svg --svg and --out differ"
      rm -f "$tmp/a.svg" "$tmp/b.svg" ;;
  esac
done

# Scripts: --help prints a usage and does nothing else (no out/, no build, no install).
for s in "$src"/scripts/*.sh "$src"/bench/*.sh; do
  name=${s#"$src"/}
  before=$(ls -A "$src")
  OUT="$tmp/cwd/job" run bash "$s" --help
  [ "$rc" -eq 0 ] || fail "$name --help: exit $rc ($(head -n 1 "$tmp/err"))"
  grep -qi usage "$tmp/out" || fail "$name --help: no usage on stdout"
  [ -z "$(ls -A "$tmp/cwd")" ] || fail "$name --help wrote into the current folder: $(ls -A "$tmp/cwd")"
  [ "$(ls -A "$src")" = "$before" ] || fail "$name --help changed the source tree's top level"
  run bash "$s" --no-such-option
  [ "$rc" -eq 2 ] || fail "$name --no-such-option: exit $rc"
done

# The GUI wrappers of LCM's Java tools (tests/gui_wrappers.sh checks what they start): refused
# options and missing values named; their --help names what installs their packages.
for name in lcm-spy.sh lcm-logplayer-gui.sh; do
  s=$src/scripts/$name
  [ -f "$s" ] || { fail "scripts/$name missing"; continue; }
  run bash "$s" --no-such-option
  [ "$rc" -eq 2 ] && grep -q "^$name: unknown option '--no-such-option'" "$tmp/err" ||
    fail "$name --no-such-option: exit $rc, $(head -n 1 "$tmp/err")"
  run bash "$s" --lcm-url
  [ "$rc" -eq 2 ] && grep -q "^$name: --lcm-url needs a value" "$tmp/err" ||
    fail "$name --lcm-url (no value): exit $rc, $(head -n 1 "$tmp/err")"
  run bash "$s" --help
  grep -q 'bash scripts/setup.sh --gui' "$tmp/out" || fail "$name --help does not name setup.sh --gui"
  grep -q -- '--install' "$tmp/out" && grep -q -- '--check' "$tmp/out" ||
    fail "$name --help lacks --install or --check"
done
run bash "$src/scripts/lcm-logplayer-gui.sh" --check a.lcmlog b.lcmlog
[ "$rc" -eq 2 ] && grep -q "one LOG at most" "$tmp/err" ||
  fail "lcm-logplayer-gui.sh with two logs: exit $rc, $(head -n 1 "$tmp/err")"
# setup.sh --packages: the list and nothing else; Java only with --gui (issue 16).
before=$(ls -A "$src")
run bash "$src/scripts/setup.sh" --packages
[ "$rc" -eq 0 ] && grep -qx cmake "$tmp/out" && grep -qx python3 "$tmp/out" ||
  fail "setup.sh --packages: exit $rc, $(tr '\n' ' ' <"$tmp/out")"
! grep -E 'jdk|jre|-java$' "$tmp/out" || fail "setup.sh --packages lists Java packages"
run bash "$src/scripts/setup.sh" --packages --gui
for p in default-jre default-jdk-headless liblcm-java libjchart2d-java cmake; do
  grep -qx "$p" "$tmp/out" || fail "setup.sh --packages --gui lacks $p"
done
run bash "$src/scripts/setup.sh" --gui --packages fuzz
grep -qx default-jre "$tmp/out" && grep -qx clang "$tmp/out" || fail "setup.sh --gui --packages fuzz"
run bash "$src/scripts/setup.sh" --packages nosuchpreset
[ "$rc" -eq 2 ] && grep -q "unknown preset 'nosuchpreset'" "$tmp/err" ||
  fail "setup.sh --packages nosuchpreset: exit $rc, $(head -n 1 "$tmp/err")"
[ -z "$(ls -A "$tmp/cwd")" ] && [ "$(ls -A "$src")" = "$before" ] ||
  fail "setup.sh --packages wrote files"

[ "$fails" -eq 0 ] || { echo "$fails failures" >&2; exit 1; }
echo "cli surface: $# programs and their commands, $(ls "$src"/scripts/*.sh "$src"/bench/*.sh | wc -l) scripts"
