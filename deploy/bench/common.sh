# Sourced by the benchmark scripts of deploy/bench that run retreat-launch: where things are,
# the options they share, and the results file. A script sets its own defaults (vendors,
# duration, domain) before sourcing this file, defines bench_option to take its own options
# (it sets `taken` to how many words it used, 0 for none), then calls
#   bench_parse "$@"; bench_prepare TMP-NAME
# Usage text: the script's header comment, up to `set -euo pipefail`.

here=$(cd "$(dirname "${BASH_SOURCE[1]}")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${RETREAT_BUILD_DIR:-$root/build}
launcher="$build/deploy/launch/retreat-launch"
bench_name=$(basename "${BASH_SOURCE[1]}")
out=""

bench_usage() { sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; }

# The options every such script takes, then the script's own (bench_option).
bench_parse() {
  while [ $# -gt 0 ]; do
    case "$1" in
      --vendors) vendors=$2; shift 2 ;;
      --duration) duration=$2; shift 2 ;;
      --domain) domain=$2; shift 2 ;;
      --out) out=$2; shift 2 ;;
      --launcher) launcher=$2; shift 2 ;;
      --repeat)  # only a script that sets `repeat` takes it
        [ -n "${repeat+set}" ] || { echo "$bench_name: unknown argument '$1' (see --help)" >&2; exit 2; }
        repeat=$2; shift 2 ;;
      -h|--help) bench_usage; exit 0 ;;
      *)
        taken=0
        if declare -F bench_option >/dev/null; then bench_option "$@"; fi
        [ "$taken" -gt 0 ] || { echo "$bench_name: unknown argument '$1' (see --help)" >&2; exit 2; }
        shift "$taken" ;;
    esac
  done
}

# Checks the launcher and --repeat (when the script takes it: it sets `repeat` first), makes the
# output directory (a new one under /tmp unless --out) and an empty DIR/results.txt.
bench_prepare() {
  [ -x "$launcher" ] || { echo "$bench_name: no retreat-launch at '$launcher' (--launcher PATH)" >&2; exit 2; }
  if [ -n "${repeat+set}" ] && ! [[ $repeat =~ ^[1-9][0-9]*$ ]]; then
    echo "$bench_name: --repeat '$repeat': must be a whole number >= 1" >&2; exit 2
  fi
  out=${out:-$(mktemp -d "/tmp/$1.XXXXXX")}
  mkdir -p "$out"
  results="$out/results.txt"
  : > "$results"
}

# Prints a line and appends it to DIR/results.txt.
say() { echo "$*" | tee -a "$results"; }
