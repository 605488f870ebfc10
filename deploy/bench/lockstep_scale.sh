#!/usr/bin/env bash
# Lockstep scale benchmark: retreat-launch runs an arena and N retreat-agent processes on this
# host, per vendor, and reports
#   * ticks/s: lockstep ticks per wall second (summary.json ticks_per_second: every tick is one
#     round of N proximity frames out and N decisions back);
#   * start-up: seconds from the launch until the arena published tick 0, i.e. until it had
#     matched every agent (summary.json launch.seconds_to_first_tick);
#   * CPU: cpu_s, the arena's and the agents' CPU time over the whole launch (start-up and
#     shutdown included; summary.json launch.cpu_seconds, from getrusage of the reaped children),
#     and cpu_ms_per_tick, that over the ticks run;
#   * memory per agent process: peak RSS (VmHWM) and PSS (shared pages divided among the
#     processes mapping them), the largest value seen every 2 s while the run went on, mean over
#     the agents;
#   * trajectory: the first 16 hex digits of summary.json trajectory_sha256, which must be the
#     same for every vendor (and plans or not) at one N and duration.
#
# The world: the kinetic one (no positions, so any N fits), a square of N / 1.5 m^2 (density
# near λ* of the paper's parameters), all N robots inside, agent.K_p = agent.lambda_in = 0 (ε ≡ 0:
# nobody retreats, so all N agents answer every tick), run.duration simulated seconds.
# DDS discovery: the adapters' built-in loopback settings up to 50 agents; from 100 on the star
# of deploy/dds (Fast DDS Discovery Server with the arena as the server; Cyclone star hub/agent),
# as docs/dds-profiles.md recommends: simple discovery does not converge at 200.
#
# Usage:
#   deploy/bench/lockstep_scale.sh [--agents "12 50 100 200"] [--vendors "fastdds cyclonedds"]
#       [--duration S] [--domain ID] [--out DIR] [--launcher PATH] [--plans] [--domains K]
#   --domains K       spread the swarm over K DDS domains from --domain on (dds.domains: robot r's
#                     agent on domain ID + r mod K, the arena on every one; docs/dds-profiles.md)
#   --plans           event-driven lockstep (run.plans: agents answer with plans, a robot gets a
#                     frame only when its input changes or its plan ends; docs/protocol.md §6)
#   --launcher PATH   retreat-launch (default: $RETREAT_BUILD_DIR/deploy/launch/retreat-launch,
#                     RETREAT_BUILD_DIR defaulting to ./build)
#   --domain ID       first DDS domain id of the runs (default 10; keep ID + K - 1 below 101, so
#                     that no well-known port lies in Linux's ephemeral range 32768.., where any
#                     socket bound to a free port may take one: docs/deploy.md "Domain ids")
#   --duration S      simulated seconds per run (default 60: 2,000 ticks)
#
# Output: one line per run on stdout (also DIR/results.txt); the run directories stay in DIR.
# Every process is started and stopped by retreat-launch (by PID); this script only reads
# /proc of the PIDs listed in processes.json. DDS stays on loopback (built-in settings and the
# single-host star profiles pin it to 127.0.0.1 / lo).
set -euo pipefail

agents_list="12 50 100 200"
vendors="fastdds cyclonedds"
duration=60
domain=10
plans=false
domains=1
bench_option() {
  if [ "$1" = --agents ]; then agents_list=$2; taken=2; fi
  if [ "$1" = --domains ]; then domains=$2; taken=2; fi
  if [ "$1" = --plans ]; then plans=true; taken=1; fi
}
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
bench_parse "$@"
bench_prepare retreat-lockstep-scale

# Memory per agent: while PID $1 (the launcher) lives, one Python process reads every agent's
# VmHWM (peak resident set) and Pss (shared pages divided among the processes mapping them) every
# 2 s, keeps each agent's largest, and at the end prints the means in MiB ("- -" if none). One
# process every 2 s, not two awk per agent twice a second: at 1,000 agents that sampler was
# seen taking 15 % of the machine it measures.
sample_memory() {
  python3 - "$1" "$2" <<'PY'
import json, os, sys, time
launcher, processes = int(sys.argv[1]), sys.argv[2]
peak = {}
pids, seen = [], None
def field(path, name):
    try:
        with open(path) as f:
            for line in f:
                if line.startswith(name):
                    return int(line.split()[1])
    except OSError:
        return None
    return None
while True:
    try:  # the launcher is our shell's child: once it exits it stays a zombie until reaped
        alive = open(f"/proc/{launcher}/stat").read().rsplit(")", 1)[1].split()[0] not in "ZX"
    except OSError:
        alive = False
    try:  # re-read only when the launcher rewrote it (225 KB at 1,000 agents)
        stamp = os.stat(processes).st_mtime_ns
        if stamp != seen:
            pids, seen = [a["pid"] for a in json.load(open(processes))["agents"]], stamp
    except (OSError, ValueError, KeyError):
        pass
    for pid in pids:
        rss = field(f"/proc/{pid}/status", "VmHWM:")
        if rss is None:
            continue
        pss = field(f"/proc/{pid}/smaps_rollup", "Pss:") or 0
        old = peak.get(pid, (0, 0))
        peak[pid] = (max(old[0], rss), max(old[1], pss))
    if not alive:
        break
    time.sleep(2)
if peak:
    k = len(peak)
    print(f"{sum(r for r, _ in peak.values()) / k / 1024:.1f} {sum(p for _, p in peak.values()) / k / 1024:.1f}")
else:
    print("- -")
PY
}

for vendor in $vendors; do
  for n in $agents_list; do
    run="$out/${vendor}_$n"
    rm -rf "$run"
    side=$(python3 -c "import math; print(round(math.sqrt($n / 1.5), 3))")
    profile_args=()
    if [ "$n" -ge 100 ]; then
      if [ "$vendor" = fastdds ]; then
        profile_args=(--set "dds.profile=$root/deploy/dds/fastdds-discovery-server-client.xml"
                      --arena-profile "$root/deploy/dds/fastdds-discovery-server-hub.xml")
      else
        profile_args=(--set "dds.profile=$root/deploy/dds/cyclonedds-star-agent.xml"
                      --arena-profile "$root/deploy/dds/cyclonedds-star-hub.xml")
      fi
    fi
    "$launcher" "$root/deploy/scenarios/robotarium-2019.yaml" --dds "$vendor" --domain "$domain" \
      --no-bridge --out "$run" \
      --set arena.encounter_model=kinetic --set arena.shape=rectangle \
      --set arena.width="$side" --set arena.height="$side" \
      --set arena.robots_inside="$n" --set arena.robots_waiting=0 --set arena.queue=finite \
      --set agent.K_p=0 --set agent.lambda_in=0 --set run.duration="$duration" \
      --set run.startup_timeout=240 --set run.agent_timeout=10 --set run.plans="$plans" \
      --set dds.domains="$domains" \
      "${profile_args[@]}" > "$out/${vendor}_$n.log" 2>&1 &
    launch_pid=$!
    mem=$(sample_memory "$launch_pid" "$run/processes.json")
    code=0
    wait "$launch_pid" || code=$?
    line=$(python3 - "$run/summary.json" "$vendor" "$n" "$code" $mem "$plans" "$domains" <<'EOF'
import json, sys
path, vendor, n, code, rss, pss, plans, domains = sys.argv[1:9]
try:
    j = json.load(open(path))
except Exception:
    print(f"vendor={vendor} agents={n} exit={code} no summary.json")
    sys.exit(0)
l = j.get("launch", {})
cpu = l.get("cpu_seconds")
cpu_s = cpu["user"] + cpu["system"] if cpu else None
cpu_text = f"cpu_s={cpu_s:.1f} cpu_ms_per_tick={1000 * cpu_s / max(1, j['ticks']):.3f}" if cpu else "cpu_s=- cpu_ms_per_tick=-"
tps = j['ticks_per_second']
# Per-tick runs of 500 and more agents make a few ticks a second: keep two decimals there.
tps_text = f"{tps:.0f}" if tps >= 100 else f"{tps:.2f}"
print(f"vendor={vendor} agents={n} domains={domains} plans={plans} exit={code} ticks={j['ticks']} ticks_per_second={tps_text} "
      f"answers={j.get('decisions_received')} planned={j.get('decisions_planned')} run_s={j.get('wall_seconds', 0):.2f} "
      f"startup_s={l.get('seconds_to_first_tick', -1):.2f} matched={j['agents'].get('matched')} "
      f"lost={j['agents']['lost']} agent_rss_mib={rss} agent_pss_mib={pss} wall_s={l.get('wall_seconds', 0):.1f} {cpu_text} "
      f"trajectory={j.get('trajectory_sha256', '-')[:16]}")
EOF
)
    echo "$line" | tee -a "$results"
  done
done
echo "results: $results"
