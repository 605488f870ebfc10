#!/usr/bin/env bash
# DDS Security benchmark: lockstep ticks per wall second of the paper's experiment
# (robotarium-2019: 12 agent processes, one arena) in plain and in secure mode, per vendor,
# measured in the same invocation with plain and secure runs alternating (so that both see the
# same machine load). ticks/s is summary.json's ticks_per_second: every tick is one round of 12
# proximity frames out and 12 decisions back, each signed and encrypted in secure mode
# (docs/security.md). The PKI is made fresh in DIR/pki by deploy/security/make-swarm-pki.sh.
#
# Usage:
#   deploy/bench/security.sh [--vendors "fastdds cyclonedds"] [--duration S] [--repeat N]
#       [--domain ID] [--out DIR] [--launcher PATH]
#   --duration S      simulated seconds per run (default 300: 10,000 ticks)
#   --repeat N        plain/secure pairs per vendor (default 3)
#   --domain ID       DDS domain id of the runs (default 10: below 101 keeps every well-known port
#                     under Linux's ephemeral range 32768.., where any socket bound to a free port
#                     may take one; docs/deploy.md "Domain ids")
#   --launcher PATH   retreat-launch (default: $RETREAT_BUILD_DIR/deploy/launch/retreat-launch,
#                     RETREAT_BUILD_DIR defaulting to ./build)
#
# Output: one line per run and a median line per vendor and mode on stdout (also
# DIR/results.txt); the run directories stay in DIR. DDS stays on loopback (built-in settings).
set -euo pipefail

vendors="fastdds cyclonedds"
duration=300
repeat=3
domain=10
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
bench_parse "$@"
bench_prepare retreat-security-bench

"$root/deploy/security/make-swarm-pki.sh" --out "$out/pki" --robots 0-11 >/dev/null
scenario="$root/deploy/scenarios/robotarium-2019.yaml"
say "# $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'); robotarium-2019, $duration simulated s"

ticks_per_second() {
  python3 -c 'import json,sys; j=json.load(open(sys.argv[1])); print("%.0f %s" % (j["ticks_per_second"], j["trajectory_sha256"][:16]))' "$1"
}

for vendor in $vendors; do
  declare -A rates=([off]="" [on]="")
  for ((i = 1; i <= repeat; ++i)); do
    for security in off on; do
      run="$out/$vendor-$security-$i"
      "$launcher" "$scenario" --dds "$vendor" --domain "$domain" --no-bridge --out "$run" \
        --set run.duration="$duration" --set dds.security="$security" --set dds.security_dir="$out/pki" \
        > "$run.log" 2>&1 || { say "$vendor security=$security run $i: failed (see $run.log)"; continue; }
      read -r rate hash < <(ticks_per_second "$run/summary.json")
      rates[$security]+="$rate "
      say "$vendor security=$security run $i: $rate ticks/s (trajectory $hash)"
    done
  done
  for security in off on; do
    median=$(printf '%s\n' ${rates[$security]} | sort -n | awk '{a[NR]=$1} END {if (NR) print a[int((NR+1)/2)]; else print "-"}')
    say "$vendor security=$security: median $median ticks/s over $repeat runs"
  done
done
