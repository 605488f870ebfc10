#!/usr/bin/env bash
# Recording benchmark: lockstep ticks per wall second of the paper's experiment (robotarium-2019:
# 12 agent processes, one arena) without and with retreat-record (retreat-launch --record), per
# vendor and lockstep kind (event-driven with plans, and per tick), measured in the same
# invocation with plain and recorded runs alternating (so that both see the same machine load).
# ticks/s is summary.json's ticks_per_second. For a recorded run it also prints what the
# recorder wrote and lost (its last log line; the MCAP file's size), and the messages recorded
# per wall second of the arena's loop.
#
# Usage:
#   deploy/bench/record_overhead.sh [--vendors "fastdds cyclonedds"] [--duration S] [--repeat N]
#       [--domain ID] [--out DIR] [--launcher PATH]
#   --duration S      simulated seconds per run (default 400: 13,334 ticks)
#   --repeat N        plain/recorded pairs per vendor and kind (default 3)
#   --domain ID       DDS domain id of the runs (default 84, the recording tests' block: do not
#                     run it beside the test suite)
#   --launcher PATH   retreat-launch (default: $RETREAT_BUILD_DIR/deploy/launch/retreat-launch,
#                     RETREAT_BUILD_DIR defaulting to ./build)
#
# Output: one line per run and a median line per vendor, kind and mode on stdout (also
# DIR/results.txt); the run directories and recordings stay in DIR. DDS stays on loopback.
set -euo pipefail

vendors="fastdds cyclonedds"
duration=400
repeat=3
domain=84
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
bench_parse "$@"
bench_prepare retreat-record-bench

scenario="$root/deploy/scenarios/robotarium-2019.yaml"
say "# $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'); robotarium-2019, $duration simulated s"

summary_of() {
  python3 -c 'import json,sys; j=json.load(open(sys.argv[1])); print("%.0f %.3f %s" % (j["ticks_per_second"], j["wall_seconds"], j["trajectory_sha256"][:16]))' "$1"
}

for vendor in $vendors; do
  for plans in true false; do
    kind=$([ "$plans" = true ] && echo "plans" || echo "per-tick")
    declare -A rates=([plain]="" [recorded]="")
    for ((i = 1; i <= repeat; ++i)); do
      for mode in plain recorded; do
        run="$out/$vendor-$kind-$mode-$i"
        record=()
        [ "$mode" = recorded ] && record=(--record "$run.mcap")
        "$launcher" "$scenario" --dds "$vendor" --domain "$domain" --no-bridge --out "$run" \
          --set run.duration="$duration" --set run.plans="$plans" "${record[@]}" \
          > "$run.log" 2>&1 || { say "$vendor $kind $mode run $i: failed (see $run.log)"; continue; }
        read -r rate wall hash < <(summary_of "$run/summary.json")
        rates[$mode]+="$rate "
        extra=""
        if [ "$mode" = recorded ]; then
          line=$(tail -1 "$run/logs/record.log")
          messages=$(echo "$line" | sed -n 's/^retreat-record: \([0-9]*\) messages.*/\1/p')
          lost=$(echo "$line" | sed -n 's/.*dropped \([0-9]*\).*/\1/p')
          size=$(stat -c %s "$run.mcap")
          per_s=$(python3 -c "print('%.0f' % (${messages:-0} / max($wall, 1e-9)))")
          extra="; recorded ${messages:-?} messages (${per_s}/s of the arena's loop), lost ${lost:-?}, $((size / 1024)) KiB"
        fi
        say "$vendor $kind $mode run $i: $rate ticks/s (trajectory $hash)$extra"
      done
    done
    for mode in plain recorded; do
      median=$(printf '%s\n' ${rates[$mode]} | sort -n | awk '{a[NR]=$1} END {if (NR) print a[int((NR+1)/2)]; else print "-"}')
      say "$vendor $kind $mode: median $median ticks/s over $repeat runs"
    done
  done
done
