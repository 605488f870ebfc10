#!/usr/bin/env bash
# Replay and diff benchmark: how fast recordings are replayed, re-decided and compared. Records
# the paper's experiment (robotarium-2019, 12 agents) once with plans over Cyclone DDS and once
# per tick over Fast DDS (retreat-launch --record), then times, --repeat times each:
#   retreat-replay FILE --dds V            checking every answer, agents as processes over V
#   retreat-replay FILE --dds inmemory     checking, agents in the process
#   retreat-replay FILE --dds inmemory --controller paper    re-deciding every tick
#   retreat-diff on the two run directories (hash chains), and on the two recordings
# and prints the median wall time with the answers per wall second (answers compared / time).
#
# Usage:
#   deploy/bench/replay.sh [--duration S] [--repeat N] [--domain ID] [--out DIR] [--launcher PATH]
#   --duration S      simulated seconds of the recorded runs (default 400: 13,334 ticks)
#   --repeat N        timings per case (default 3)
#   --domain ID       DDS domain id (default 84, the recording tests' block: do not run it beside
#                     the test suite)
#
# Output: one line per case on stdout (also DIR/results.txt); the runs stay in DIR.
set -euo pipefail

vendors=""
duration=400
repeat=3
domain=84
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
bench_parse "$@"
bench_prepare retreat-replay-bench
bin=$(dirname "$launcher")
replay="$bin/retreat-replay"
diff="$build/bridge/retreat-diff"
[ -x "$replay" ] && [ -x "$diff" ] || { echo "replay.sh: no retreat-replay or retreat-diff in $build" >&2; exit 2; }

scenario="$root/deploy/scenarios/robotarium-2019.yaml"
say "# $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'); robotarium-2019, $duration simulated s"
for run in cyclonedds:true fastdds:false; do
  vendor=${run%%:*} plans=${run#*:}
  "$launcher" "$scenario" --dds "$vendor" --domain "$domain" --no-bridge --out "$out/$vendor" \
    --set run.duration="$duration" --set run.plans="$plans" --record "$out/$vendor.mcap" >"$out/$vendor.log" 2>&1
done

# time_case NAME COMMAND...: the median wall time of --repeat runs, and the answers compared
# (retreat-replay's total line) per second.
time_case() {
  name=$1; shift
  times=()
  for _ in $(seq "$repeat"); do
    start=$(date +%s.%N)
    "$@" >"$out/case.out" 2>&1 || [ $? -eq 1 ] || { echo "replay.sh: $name failed:"; cat "$out/case.out"; exit 1; }
    times+=("$(echo "$(date +%s.%N) - $start" | bc)")
  done
  median=$(printf '%s\n' "${times[@]}" | sort -g | sed -n "$(( (repeat + 1) / 2 ))p")
  answers=$(sed -n 's/^[0-9]* robots: \([0-9]*\) answers as recorded, \([0-9]*\) differ.*/\1 \2/p' "$out/case.out" |
    awk '{ print $1 + $2 }')
  if [ -n "$answers" ]; then
    say "$name: median $(printf '%.2f' "$median") s, $answers answers, $(echo "$answers / $median" | bc) answers/s"
  else
    say "$name: median $(printf '%.3f' "$median") s: $(head -1 "$out/case.out")"
  fi
}
for rec in cyclonedds fastdds; do
  time_case "$rec recording, checked over cyclonedds" "$replay" "$out/$rec.mcap" --dds cyclonedds --domain "$domain"
  time_case "$rec recording, checked over fastdds" "$replay" "$out/$rec.mcap" --dds fastdds --domain "$domain"
  time_case "$rec recording, checked in process" "$replay" "$out/$rec.mcap" --dds inmemory
  time_case "$rec recording, re-decided in process" "$replay" "$out/$rec.mcap" --dds inmemory --controller paper
done
time_case "retreat-diff of the two run directories" "$diff" "$out/cyclonedds" "$out/fastdds"
time_case "retreat-diff of the two recordings" "$diff" "$out/cyclonedds.mcap" "$out/fastdds.mcap"
