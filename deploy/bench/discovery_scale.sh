#!/usr/bin/env bash
# Discovery scale benchmark: one arena-like hub and N agent-like processes on this host, each
# its own DDS participant (an agent: a reader on <prefix>/robot_<i>/proximity and a writer on
# <prefix>/robot_<i>/decision; the hub: the matching writer and reader for every robot).
#
# Measures
#   * discovery: time until the hub has matched every robot's writer and reader, counted from
#     the start of the first agent (and, for reference, from the start of the last one);
#   * delivery: time until every agent has answered one frame (a match alone proves nothing);
#   * memory per process: RSS (includes shared library pages) and PSS (shared pages divided
#     among the processes that map them; the honest share of one process);
#   * idle CPU: CPU time used by all processes together over an idle window after discovery,
#     as % of one core and of the whole machine.
# then stops everything it started, by PID (SIGTERM, then SIGKILL after a grace period). Every
# wait has a timeout and every process has its own --max-seconds, so it never hangs.
#
# Usage:
#   deploy/bench/discovery_scale.sh --vendor fastdds|cyclonedds --profile star|loopback|default
#       [--agents N] [--domain ID] [--timeout S] [--idle S] [--out DIR] [--node PATH]
#       [--hub-profile FILE --agent-profile FILE] [--shards K]
#
#   --profile star      Fast DDS: fastdds-discovery-server-hub.xml / -client.xml;
#                       Cyclone: cyclonedds-star-hub.xml / cyclonedds-star-agent.xml
#   --profile loopback  fastdds-loopback.xml or cyclonedds-loopback.xml for everyone
#   --profile default   no profile: the adapter's built-in loopback settings
#   --agents N          number of agent processes (default 200)
#   --domain ID         DDS domain id (default 10: below 101 keeps every well-known port under
#                       Linux's ephemeral range 32768.., where any socket bound to a free port may
#                       take one; docs/deploy.md "Domain ids")
#   --timeout S         seconds to wait for discovery (default 240)
#   --idle S            idle window for the CPU measurement (default 10)
#   --shards K          Cyclone star only (default 1): K hubs, each for N/K of the robots, at
#                       participant indices 0, 2, 4, ...; each agent's only peer is its own
#                       hub's discovery port (the agent profile with that peer is written to
#                       DIR). A hub announces all its endpoints to every agent it discovers,
#                       whatever their topics: sharding divides that work by K (see
#                       docs/benchmarks.md, "Discovery"). Times are those of the slowest hub,
#                       memory is summed over the hubs.
#   --node PATH         the retreat_dds_swarm_node program, for hubs and agents alike
#                       (default: $RETREAT_BUILD_DIR/tests/integration/retreat_dds_swarm_node for
#                       hubs and, as retreat-launch starts retreat-agent-<vendor>, the node with
#                       one vendor linked, retreat_dds_swarm_node_<vendor>, for agents when it is
#                       built; RETREAT_BUILD_DIR defaulting to ./build)
#   --out DIR           logs and summary (default: a new directory under /tmp)
#
# Output: key=value lines on stdout, also written to DIR/summary.txt. Exit code 0 when every
# agent was matched and answered, 1 when not, 2 on bad arguments.
#
# DDS stays on loopback: every profile used here pins DDS to 127.0.0.1 / lo.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
profiles="$root/deploy/dds"

vendor=""
profile=""
agents=200
domain=10
timeout_s=240
idle_s=10
out=""
node="${RETREAT_BUILD_DIR:-$root/build}/tests/integration/retreat_dds_swarm_node"
agent_node=""  # empty: $node, or the single-vendor node beside it (after the arguments)
hub_profile=""
agent_profile=""
shards=1

usage() { sed -n '2,/^set -euo/p' "$0" | sed -e '/^set -euo/d' -e 's/^# \{0,1\}//'; }
die() { echo "discovery_scale: $*" >&2; exit 2; }

while [ $# -gt 0 ]; do
  case "$1" in
    --vendor) vendor=${2:?}; shift 2 ;;
    --profile) profile=${2:?}; shift 2 ;;
    --agents) agents=${2:?}; shift 2 ;;
    --domain) domain=${2:?}; shift 2 ;;
    --timeout) timeout_s=${2:?}; shift 2 ;;
    --idle) idle_s=${2:?}; shift 2 ;;
    --out) out=${2:?}; shift 2 ;;
    --node) node=${2:?}; agent_node=$node; shift 2 ;;
    --hub-profile) hub_profile=${2:?}; shift 2 ;;
    --agent-profile) agent_profile=${2:?}; shift 2 ;;
    --shards) shards=${2:?}; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    *) die "unknown argument '$1' (see --help)" ;;
  esac
done

case "$vendor" in fastdds|cyclonedds) ;; *) die "--vendor '$vendor': must be fastdds or cyclonedds" ;; esac
int_in() {  # int_in NAME VALUE MIN MAX: dies unless VALUE is an integer in MIN..MAX
  if ! [[ "$2" =~ ^[0-9]+$ ]] || [ "$2" -lt "$3" ] || [ "$2" -gt "$4" ]; then
    die "$1 '$2': must be an integer in $3..$4"
  fi
}
int_in --agents "$agents" 1 1000
int_in --domain "$domain" 0 232
int_in --timeout "$timeout_s" 1 3600
int_in --idle "$idle_s" 1 3600
int_in --shards "$shards" 1 64
if [ "$shards" -gt 1 ]; then
  [ "$vendor/$profile" = cyclonedds/star ] || die "--shards $shards: only with --vendor cyclonedds --profile star"
  [ $((agents % shards)) -eq 0 ] || die "--shards $shards: must divide --agents $agents"
fi
[ -x "$node" ] || die "--node '$node': not an executable (build the target retreat_dds_swarm_node)"
if [ -z "$agent_node" ]; then
  agent_node=$node
  [ -x "${node}_$vendor" ] && agent_node=${node}_$vendor
fi

if [ -z "$hub_profile$agent_profile" ]; then
  case "$vendor/$profile" in
    fastdds/star) hub_profile=$profiles/fastdds-discovery-server-hub.xml
                  agent_profile=$profiles/fastdds-discovery-server-client.xml ;;
    cyclonedds/star) hub_profile=$profiles/cyclonedds-star-hub.xml
                     agent_profile=$profiles/cyclonedds-star-agent.xml ;;
    */loopback) hub_profile=$profiles/$vendor-loopback.xml; agent_profile=$hub_profile ;;
    */default) ;;
    *) die "--profile '$profile': must be star, loopback or default (or give --hub-profile and --agent-profile)" ;;
  esac
else
  if [ ! -f "$hub_profile" ] || [ ! -f "$agent_profile" ]; then
    die "--hub-profile and --agent-profile must both be files"
  fi
  profile=custom
fi

[ -n "$out" ] || out=$(mktemp -d "/tmp/retreat-discovery-scale.XXXXXX")
mkdir -p "$out"
rm -f "$out"/hub*.result "$out"/summary.txt
if [ "$shards" -gt 1 ]; then
  # The shipped agent profile with one peer: its hub's discovery port (Cyclone expands the
  # variable; the port is 7410 + 250 * domain + 2 * participant index).
  sed 's|<Peer address="127.0.0.1"/>|<Peer address="127.0.0.1:${RETREAT_HUB_PORT}"/>|' "$agent_profile" \
    > "$out/agent-sharded.xml"
  grep -q RETREAT_HUB_PORT "$out/agent-sharded.xml" || die "$agent_profile: no <Peer address=\"127.0.0.1\"/> to point at a shard"
  agent_profile=$out/agent-sharded.xml
fi

# Every process exits by itself after this long, even if this script is killed with SIGKILL.
life_s=$((timeout_s + idle_s + 180))

pids=()
cleanup() {
  local pid alive
  [ -z "${nap_pid:-}" ] || kill "$nap_pid" 2>/dev/null || true
  [ ${#pids[@]} -gt 0 ] || return 0
  for pid in "${pids[@]}"; do kill -TERM "$pid" 2>/dev/null || true; done
  for _ in $(seq 1 50); do  # up to 5 s for a clean exit
    alive=0
    for pid in "${pids[@]}"; do kill -0 "$pid" 2>/dev/null && alive=1 && break; done
    [ $alive -eq 0 ] && break
    nap 0.1
  done
  for pid in "${pids[@]}"; do kill -KILL "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do wait "$pid" 2>/dev/null || true; done
  pids=()
}
trap cleanup EXIT
trap 'exit 130' INT TERM

now() { date +%s.%N; }
# Sleeps in the background and waits for it: a trapped SIGINT/SIGTERM interrupts `wait` at once,
# whereas bash runs the trap only after a foreground `sleep` has finished.
nap_pid=""
nap() { sleep "$1" & nap_pid=$!; wait "$nap_pid"; nap_pid=""; }
profile_args() { [ -n "$1" ] && printf -- '--profile\n%s\n' "$1"; return 0; }

mapfile -t hub_args < <(profile_args "$hub_profile")
mapfile -t agent_args < <(profile_args "$agent_profile")

per_shard=$((agents / shards))
hub_pids=()
for ((k = 0; k < shards; k++)); do
  RETREAT_DDS_PARTICIPANT_INDEX=$((2 * k)) "$node" --role hub --dds "$vendor" "${hub_args[@]}" --domain "$domain" \
    --agents "$per_shard" --first-robot $((k * per_shard)) --match-timeout "$timeout_s" --answer-timeout 60 \
    --result "$out/hub$k.result" --linger --max-seconds "$life_s" > "$out/hub$k.log" 2>&1 &
  hub_pids+=("$!")
  pids+=("$!")
done

first_start=$(now)
agent_pids=()
for ((i = 0; i < agents; i++)); do
  RETREAT_HUB_PORT=$((7410 + 250 * domain + 4 * (i / per_shard))) "$agent_node" --role agent --dds "$vendor" "${agent_args[@]}" --domain "$domain" --robot "$i" \
    --max-seconds "$life_s" > "$out/agent_$i.log" 2>&1 &
  pids+=("$!")
  agent_pids+=("$!")
done
last_start=$(now)

# Wait for the hub's result (discovery timeout + answer timeout + margin).
deadline=$(( $(date +%s) + timeout_s + 90 ))
for ((k = 0; k < shards; k++)); do
  while [ ! -f "$out/hub$k.result" ]; do
    if ! kill -0 "${hub_pids[$k]}" 2>/dev/null; then
      echo "discovery_scale: hub $k exited early:" >&2
      tail -5 "$out/hub$k.log" >&2
      exit 1
    fi
    if [ "$(date +%s)" -gt "$deadline" ]; then
      echo "discovery_scale: no result from hub $k within $((timeout_s + 90)) s" >&2
      exit 1
    fi
    nap 0.2
  done
done
# Summed counts; the latest time (0, "never", if any hub never got there).
read -r matched answered matched_at answered_at < <(cat "$out"/hub*.result | awk '
  function field(name,   i, kv) { for (i = 1; i <= NF; i++) { split($i, kv, "="); if (kv[1] == name) return kv[2] } }
  { split(field("matched"), m, "/"); split(field("answered"), a, "/")
    mn += m[1]; md += m[2]; an += a[1]; ad += a[2]
    t = field("matched_at_unix") + 0; if (t == 0) mnever = 1; if (t > mt) mt = t
    t = field("answered_at_unix") + 0; if (t == 0) anever = 1; if (t > at) at = t }
  END { printf "%d/%d %d/%d %.3f %.3f\n", mn, md, an, ad, mnever ? 0 : mt, anever ? 0 : at }')

elapsed() {  # seconds from $2 to $1, or "n/a" when $1 is 0 (never happened)
  awk -v a="$1" -v b="$2" 'BEGIN { if (a + 0 == 0) print "n/a"; else printf "%.2f", a - b }'
}

failed=0
for pid in "${agent_pids[@]}"; do kill -0 "$pid" 2>/dev/null || failed=$((failed + 1)); done

# Idle: let the last acknowledgements settle, then measure CPU time over the idle window.
nap 2
clk=$(getconf CLK_TCK)
cpu_ticks() {  # utime + stime of every live process we started
  local total=0 pid stat rest
  for pid in "${pids[@]}"; do
    stat=$(cat "/proc/$pid/stat" 2>/dev/null) || continue
    rest=${stat##*) }  # fields after "(comm)": field 3 is the first
    read -r -a f <<< "$rest"
    total=$((total + f[11] + f[12]))  # fields 14 (utime) and 15 (stime)
  done
  echo "$total"
}
t0=$(cpu_ticks); s0=$(now)
nap "$idle_s"
t1=$(cpu_ticks); s1=$(now)
cores=$(nproc)
idle_cpu_one_core=$(awk -v d=$((t1 - t0)) -v c="$clk" -v s0="$s0" -v s1="$s1" \
  'BEGIN { printf "%.1f", 100 * d / c / (s1 - s0) }')
idle_cpu_machine=$(awk -v p="$idle_cpu_one_core" -v n="$cores" 'BEGIN { printf "%.1f", p / n }')

memory() {  # prints "rss_kib pss_kib" of one process
  local rss pss
  rss=$(awk '/^VmRSS:/ { print $2 }' "/proc/$1/status" 2>/dev/null || echo 0)
  pss=$(awk '/^Pss:/ { print $2 }' "/proc/$1/smaps_rollup" 2>/dev/null || echo 0)
  echo "${rss:-0} ${pss:-0}"
}
read -r hub_rss hub_pss < <(for pid in "${hub_pids[@]}"; do memory "$pid"; done | awk '{ r += $1; p += $2 } END { print r + 0, p + 0 }')
agent_mem=$(for pid in "${agent_pids[@]}"; do memory "$pid"; done)
mem_stats=$(awk '$1 > 0 { n++; rss += $1; pss += $2; if ($1 > max) max = $1 }
  END { if (n == 0) n = 1; printf "%.1f %.1f %.1f %.1f", rss / n / 1024, max / 1024, pss / n / 1024, pss / 1024 }' \
  <<< "$agent_mem")
read -r agent_rss_mean agent_rss_max agent_pss_mean agent_pss_total <<< "$mem_stats"

summary=$(cat <<EOF
vendor=$vendor
profile=$profile
hub_profile=${hub_profile:-built-in}
agent_profile=${agent_profile:-built-in}
hub_node=$node
agent_node=$agent_node
agents=$agents
shards=$shards
domain=$domain
agents_started_s=$(elapsed "$last_start" "$first_start")
matched=$matched
discovery_s_from_first_agent=$(elapsed "$matched_at" "$first_start")
discovery_s_from_last_agent=$(elapsed "$matched_at" "$last_start")
answered=$answered
all_answered_s_from_first_agent=$(elapsed "$answered_at" "$first_start")
agents_exited_early=$failed
hub_rss_mib=$(awk -v k="$hub_rss" 'BEGIN { printf "%.1f", k / 1024 }')
hub_pss_mib=$(awk -v k="$hub_pss" 'BEGIN { printf "%.1f", k / 1024 }')
agent_rss_mib_mean=$agent_rss_mean
agent_rss_mib_max=$agent_rss_max
agent_pss_mib_mean=$agent_pss_mean
agents_pss_mib_total=$agent_pss_total
idle_window_s=$idle_s
idle_cpu_percent_of_one_core=$idle_cpu_one_core
idle_cpu_percent_of_machine=$idle_cpu_machine (${cores} cores)
out=$out
EOF
)
echo "$summary" | tee "$out/summary.txt"

cleanup
[ "$matched" = "$agents/$agents" ] && [ "$answered" = "$agents/$agents" ] && [ "$failed" -eq 0 ]
