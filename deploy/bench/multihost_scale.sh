#!/usr/bin/env bash
# Multi-host scale benchmark: the 1,000-agent run of lockstep_scale.sh, but over several emulated
# hosts, each with the SHIPPED profiles of its vendor set up as the files say for 200+ robots over
# hosts (a star with the arena host as its hub; docs/deploy.md §2): the arena in one network
# namespace, the agents split round-robin over --hosts others, all joined by veth links to a
# Linux bridge in one more namespace (the set-up of tests/integration/multihost_test.cpp). Every
# host has its own port space, so the limit of one domain's port block (about 120 participants
# per domain per host) applies per host; the swarm is also spread over --domains DDS domains
# (dds.domains), which the arena joins all of.
#
#   Cyclone DDS: deploy/dds/cyclonedds-multihost.xml with the file's "star over hosts without
#                multicast" environment: the arena RETREAT_DDS_MULTICAST=false and
#                RETREAT_DDS_PARTICIPANT_INDEX=0; each agent RETREAT_DDS_MULTICAST=false,
#                RETREAT_DDS_PEERS=<arena host>, RETREAT_DDS_MAX_PARTICIPANT_INDEX=2.
#   Fast DDS:    deploy/dds/fastdds-discovery-server-hub.xml (arena) and -client.xml (agents)
#                with 127.0.0.1 replaced by the arena host's address (the server's locator) and
#                by each host's own address (white list, own locators), as fastdds-multihost.xml
#                says.
# (The files' simple-discovery settings, multicast or unicast peers, are for about 100 processes:
# tried with 1,000 agents over 4 hosts, Fast DDS's unicast announcements to every peer's 16
# participant ports kept the 2-core machine saturated and half the agents unmatched after 240 s.)
#
# The world is lockstep_scale.sh's: kinetic, a square of N / 1.5 m^2, all N robots inside,
# agent.K_p = agent.lambda_in = 0 (nobody retreats), run.duration simulated seconds.
# Reports per vendor: seconds from the first agent's start until the last was started (each
# through `ip netns exec`, 5 ms apart) and until the arena had matched every agent (its "N agents
# matched" line, looked for every 50 ms; "<T" when the run ended before a look saw it), the
# run's wall time (summary.json wall_seconds), ticks, lost agents, the trajectory hash, and
# whether it equals the same scenario's in-process hash.
#
# Usage (root: it creates network namespaces; nothing is configured in the host's namespace, so
# no DDS packet can reach eth0):
#   deploy/bench/multihost_scale.sh [--agents N] [--hosts H] [--vendors "cyclonedds fastdds"]
#       [--domains K] [--duration S] [--domain ID] [--plans] [--out DIR] [--launcher PATH]
#   --agents N     agent processes (default 1000)
#   --hosts H      agent hosts, 2..200 (default 4); the arena has one more
#   --domains K    DDS domains of the swarm, from --domain on (default 20)
#   --duration S   simulated seconds (default 1200: 40,000 ticks)
#   --plans        event-driven lockstep (run.plans=true; default per tick, run.plans=false)
#   --domain ID    first DDS domain id (default 10: domains 10..10+K-1 keep every well-known port
#                  below Linux's ephemeral range 32768.., where a socket another domain bound
#                  at random could take it; docs/deploy.md §2 "Domain ids")
#
# Output: one line per vendor on stdout (also DIR/results.txt); logs and run directories in DIR.
# Every process this script starts it stops by PID, and it deletes the namespaces it created,
# also when interrupted.
set -euo pipefail

agents=1000
hosts=4
vendors="cyclonedds fastdds"
domains=20
duration=1200
domain=10
plans=false
bench_option() {
  if [ "$1" = --agents ]; then agents=$2; taken=2; fi
  if [ "$1" = --hosts ]; then hosts=$2; taken=2; fi
  if [ "$1" = --domains ]; then domains=$2; taken=2; fi
  if [ "$1" = --plans ]; then plans=true; taken=1; fi
}
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
bench_parse "$@"
[[ $agents =~ ^[1-9][0-9]*$ ]] || { echo "$bench_name: --agents '$agents': must be a whole number >= 1" >&2; exit 2; }
if ! [[ $hosts =~ ^[1-9][0-9]*$ ]] || [ "$hosts" -lt 2 ] || [ "$hosts" -gt 200 ]; then
  echo "$bench_name: --hosts '$hosts': must be a whole number in 2..200" >&2; exit 2
fi
[ "$(id -u)" -eq 0 ] || { echo "$bench_name: needs root to create network namespaces (uid $(id -u))" >&2; exit 2; }
command -v ip >/dev/null || { echo "$bench_name: needs iproute2 (ip)" >&2; exit 2; }
bench_prepare retreat-multihost-scale

arena_bin="$build/arena/program/retreat-arena"
scenario="$root/deploy/scenarios/robotarium-2019.yaml"
side=$(python3 -c "import math; print(round(math.sqrt($agents / 1.5), 3))")
world=(--set arena.encounter_model=kinetic --set arena.shape=rectangle
       --set arena.width="$side" --set arena.height="$side"
       --set arena.robots_inside="$agents" --set arena.robots_waiting=0 --set arena.queue=finite
       --set agent.K_p=0 --set agent.lambda_in=0 --set run.duration="$duration"
       --set run.startup_timeout=240 --set run.agent_timeout=10 --set run.plans="$plans"
       --set dds.domains="$domains")

prefix="retreat-mhs-$$-"
namespaces=()
pids=()
cleanup() {
  for pid in "${pids[@]}"; do kill -TERM "$pid" 2>/dev/null || true; done
  sleep 1
  for pid in "${pids[@]}"; do kill -KILL "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do wait "$pid" 2>/dev/null || true; done
  pids=()
  # Anything still in a namespace (a process started just as a signal came, before its PID was
  # noted), by the PIDs the namespace lists, then the namespaces.
  for ns in "${namespaces[@]}"; do
    for pid in $(ip netns pids "$ns" 2>/dev/null); do kill -KILL "$pid" 2>/dev/null || true; done
    ip netns delete "$ns" 2>/dev/null || true
  done
  namespaces=()
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# Seconds since $1 (a ${EPOCHREALTIME/./} in µs), one decimal.
elapsed_since() { local ds=$(( (${EPOCHREALTIME/./} - $1) / 100000 )); echo "$(( ds / 10 )).$(( ds % 10 ))"; }

# The network: namespace "sw" holds the bridge; host 0 is the arena (10.213.0.1), hosts 1..H the
# agents (10.213.0.2 ...). Interface names are per namespace: every host's end is mh0.
address() { local i=$(( $1 + 1 )); echo "10.213.$(( i / 256 )).$(( i % 256 ))"; }
ip netns add "${prefix}sw"; namespaces+=("${prefix}sw")
ip -n "${prefix}sw" link add br0 type bridge forward_delay 0 stp_state 0 mcast_snooping 0
ip -n "${prefix}sw" link set br0 up
for h in $(seq 0 "$hosts"); do
  ns="${prefix}$h"
  ip netns add "$ns"; namespaces+=("$ns")
  ip -n "${prefix}sw" link add "port$h" type veth peer name mh0 netns "$ns"
  ip -n "${prefix}sw" link set "port$h" master br0 up
  ip -n "$ns" link set lo up
  ip -n "$ns" addr add "$(address "$h")/16" dev mh0
  ip -n "$ns" link set mh0 up
  ip -n "$ns" route add 224.0.0.0/4 dev mh0
done

# The DDS profile of host h (0: the arena, the hub), and its environment (Cyclone DDS).
profile_of() {  # vendor host
  if [ "$1" = cyclonedds ]; then
    echo "dds.profile=$root/deploy/dds/cyclonedds-multihost.xml"
  elif [ "$2" -eq 0 ]; then
    sed -e "s/127\.0\.0\.1/$(address 0)/g" "$root/deploy/dds/fastdds-discovery-server-hub.xml" > "$out/fastdds-hub.xml"
    echo "dds.profile=$out/fastdds-hub.xml"
  else
    sed -e "/<discoveryServersList>/,/<\/discoveryServersList>/ s/127\.0\.0\.1/$(address 0)/" \
        -e "s/127\.0\.0\.1/$(address "$2")/g" "$root/deploy/dds/fastdds-discovery-server-client.xml" \
        > "$out/fastdds-client-host$2.xml"
    echo "dds.profile=$out/fastdds-client-host$2.xml"
  fi
}
env_of() {  # vendor host
  if [ "$1" = cyclonedds ]; then
    if [ "$2" -eq 0 ]; then
      echo env RETREAT_DDS_INTERFACE=mh0 RETREAT_DDS_MULTICAST=false RETREAT_DDS_PARTICIPANT_INDEX=0
    else
      echo env RETREAT_DDS_INTERFACE=mh0 RETREAT_DDS_MULTICAST=false "RETREAT_DDS_PEERS=$(address 0)" \
        RETREAT_DDS_MAX_PARTICIPANT_INDEX=2
    fi
  fi
}

# The in-process reference: the same scenario and seed without DDS.
"$launcher" "$scenario" --in-process --no-bridge --out "$out/in-process" "${world[@]}" > "$out/in-process.log" 2>&1
reference=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['trajectory_sha256'])" "$out/in-process/summary.json")

for vendor in $vendors; do
  agent_bin="$build/agent/program/retreat-agent-$vendor"
  [ -x "$agent_bin" ] || agent_bin="$build/agent/program/retreat-agent"
  run="$out/$vendor"
  rm -rf "$run"; mkdir -p "$run/logs"
  common=(--scenario "$scenario" --dds "$vendor" --domain "$domain" "${world[@]}")
  # Same order as retreat-launch: the arena first, then the agents 5 ms apart.
  # shellcheck disable=SC2046
  ip netns exec "${prefix}0" $(env_of "$vendor" 0) "$arena_bin" "${common[@]}" --set "$(profile_of "$vendor" 0)" \
    --out "$run" > "$run/logs/arena.log" 2>&1 &
  arena_pid=$!
  pids+=("$arena_pid")
  start=${EPOCHREALTIME/./}  # µs; elapsed times without starting a process (one took 0.75 s under load)
  for h in $(seq 1 "$hosts"); do profile[$h]=$(profile_of "$vendor" "$h"); agent_env[$h]=$(env_of "$vendor" "$h"); done
  for r in $(seq 0 $(( agents - 1 ))); do
    h=$(( r % hosts + 1 ))
    # shellcheck disable=SC2086
    ip netns exec "${prefix}$h" ${agent_env[$h]} "$agent_bin" --robot-id "$r" "${common[@]}" --set "${profile[$h]}" \
      > "$run/logs/agent_$r.log" 2>&1 &
    pids+=("$!")
    sleep 0.005
  done
  spawned_s=$(elapsed_since "$start")
  # When the arena logged that every agent matched, to the next 50 ms; a run that ended between
  # two looks gives "<" and the time it was seen ended (an upper bound).
  matched_s=-1
  while kill -0 "$arena_pid" 2>/dev/null; do
    if [ "$matched_s" = -1 ] && grep -q "agents matched" "$run/logs/arena.log"; then
      matched_s=$(elapsed_since "$start")
    fi
    sleep 0.05
  done
  if [ "$matched_s" = -1 ] && grep -q "agents matched" "$run/logs/arena.log"; then
    matched_s="<$(elapsed_since "$start")"
  fi
  code=0
  wait "$arena_pid" || code=$?
  cleanup_agents=("${pids[@]}")
  for pid in "${cleanup_agents[@]}"; do kill -TERM "$pid" 2>/dev/null || true; done
  for pid in "${cleanup_agents[@]}"; do wait "$pid" 2>/dev/null || true; done
  pids=()
  python3 - "$run/summary.json" "$vendor" "$agents" "$hosts" "$domains" "$plans" "$code" "$spawned_s" "$matched_s" "$reference" <<'EOF' | tee -a "$results"
import json, sys
path, vendor, n, hosts, domains, plans, code, spawned, matched, reference = sys.argv[1:11]
try:
    j = json.load(open(path))
except Exception:
    print(f"vendor={vendor} agents={n} hosts={hosts} exit={code} no summary.json")
    sys.exit(0)
h = j["trajectory_sha256"]
print(f"vendor={vendor} agents={n} hosts={hosts} domains={domains} plans={plans} exit={code} "
      f"spawned_s={spawned} matched_s={matched} run_s={j.get('wall_seconds', 0):.1f} ticks={j['ticks']} "
      f"started={j['agents']['started']} lost={j['agents']['lost']} "
      f"hash={h[:16]} same_as_in_process={'yes' if h == reference else 'NO'}")
EOF
done
echo "results: $results"
