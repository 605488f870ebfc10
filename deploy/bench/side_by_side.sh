#!/usr/bin/env bash
# Side-by-side CPU time of two retreat-launch builds on the same in-process seeds: both run at the
# same time, each pinned to its own core (taskset), and the cores are swapped every round, so the
# machine's own speed (which moves by ±10 % from run to run on a shared host) is the same for both
# and cancels in their ratio. Used for the changes of docs/benchmarks.md, "Sweeps on every core".
# Needs two cores. The two builds must give the same trajectories: each round compares them.
#
# Usage:
#   deploy/bench/side_by_side.sh OLD NEW [--scenario FILE] [--seeds A:B] [--rounds N]
#   OLD, NEW        two retreat-launch binaries (copy them out of their build trees first)
#   --scenario FILE default deploy/scenarios/steady-influx.yaml
#   --seeds A:B     default 1:5
#   --rounds N      default 8
#
# Output: a line per round (each binary's user CPU seconds and NEW/OLD), then the ratios sorted
# and their median. Exit 1 if a round's trajectory hashes differ.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
usage() { echo "usage: $0 OLD NEW [--scenario FILE] [--seeds A:B] [--rounds N]" >&2; exit 2; }
[ $# -ge 2 ] || usage
old=$1 new=$2
shift 2
scenario=$root/deploy/scenarios/steady-influx.yaml seeds=1:5 rounds=8
while [ $# -gt 0 ]; do
  case "$1" in
    --scenario) scenario=${2:?}; shift 2 ;;
    --seeds) seeds=${2:?}; shift 2 ;;
    --rounds) rounds=${2:?}; shift 2 ;;
    *) echo "side_by_side.sh: unknown argument '$1' (allowed: --scenario, --seeds, --rounds)" >&2; exit 2 ;;
  esac
done
for binary in "$old" "$new"; do
  [ -x "$binary" ] || { echo "side_by_side.sh: '$binary' is not an executable" >&2; exit 2; }
done
case "$rounds" in '' | *[!0-9]* | 0) echo "side_by_side.sh: --rounds '$rounds': must be a whole number >= 1" >&2; exit 2 ;; esac
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# run BINARY CORE TAG: the seeds in process, one at a time, on CORE; user seconds in TAG.time,
# trajectory hashes in TAG.hashes.
run() {
  /usr/bin/time -f "%U" -o "$work/$3.time" taskset -c "$2" "$1" "$scenario" --in-process --seeds "$seeds" \
    --jobs 1 --no-bridge --out "$work/$3" >"$work/$3.log" 2>&1
  grep -o 'trajectory [0-9a-f]*' "$work/$3.log" >"$work/$3.hashes"
  rm -rf "${work:?}/$3"
}

ratios=()
for round in $(seq 1 "$rounds"); do
  if (( round % 2 )); then core_old=0 core_new=1; else core_old=1 core_new=0; fi
  run "$old" "$core_old" old & pid_old=$!
  run "$new" "$core_new" new & pid_new=$!
  wait "$pid_old"; wait "$pid_new"
  if ! cmp -s "$work/old.hashes" "$work/new.hashes"; then
    echo "side_by_side.sh: round $round: the two builds gave different trajectories" >&2
    exit 1
  fi
  t_old=$(cat "$work/old.time") t_new=$(cat "$work/new.time")
  ratio=$(awk -v a="$t_old" -v b="$t_new" 'BEGIN { printf "%.4f", b / a }')
  ratios+=("$ratio")
  echo "round $round: old ${t_old} s (core $core_old), new ${t_new} s (core $core_new), new/old $ratio"
done
printf '%s\n' "${ratios[@]}" | sort -n | awk '{ r[NR] = $1 } END {
  line = ""; for (i = 1; i <= NR; ++i) line = line " " r[i]
  median = NR % 2 ? r[(NR + 1) / 2] : (r[NR / 2] + r[NR / 2 + 1]) / 2
  printf "new/old, sorted:%s; median %.4f\n", line, median }'
