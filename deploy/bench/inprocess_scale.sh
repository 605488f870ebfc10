#!/usr/bin/env bash
# In-process scale benchmark: a whole swarm in one process (retreat-launch --in-process's
# run_in_memory: the arena's and every agent's own code over the in-memory transport, lockstep)
# against its bare world, measured in the same run by tests/benchmarks/launch/in_process_bench,
# for N = 1,000, 10,000 and 100,000 robots in the kinetic and the physical world
# (deploy/scenarios/kinetic-1000.yaml at its density of 1.6 robots/m^2; 1,000 ticks kinetic,
# 300 ticks physical). Prints, per world and N:
#   * bare world: robot-ticks per second of the world's step_tick() alone;
#   * in-process: robot-ticks per second of the whole run's loop (frames out, every agent's
#     step, decisions back, the world's step), and that as a multiple of real time;
#   * overhead: bare rate / in-process rate (1 = the agents and the messages cost nothing);
#   * set-up: seconds to build the swarm (N agents and their endpoints) before the first tick;
#   * each in-process run twice: per-tick lockstep, and event-driven lockstep (run.plans, where
#     an agent is sent a frame only when its robot's input changes or its plan ends; "planned"
#     is the share of robot-ticks its plan decided); and "deciding": plans again, with agent.L = 3 s
#     and agent.K_p = 0, so that from tick 100 every agent takes a decision step (a coin) every
#     tick and nobody leaves (within L = 90 s nobody decides at all).
#
# Usage:
#   deploy/bench/inprocess_scale.sh [--filter REGEX] [--out DIR]
#   --filter REGEX   Google Benchmark filter over bare_world/N/P and in_process/N/P/E (P: 0
#                    kinetic, 1 physical; E: 0 per tick, 1 plans, 2 plans deciding), e.g. '/(1000|10000)/'
#                    (default: everything)
#   --out DIR        where the JSON and results.txt go (default: a new directory under /tmp)
#
# Needs a build with -DRETREAT_BUILD_BENCHMARKS=ON (deploy/bench.sh makes one); the build
# directory is $RETREAT_BUILD_DIR, default ./build. Starts no process but the benchmark.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${RETREAT_BUILD_DIR:-$root/build}
bench="$build/tests/benchmarks/launch/in_process_bench"
filter="."
out=""
while [ $# -gt 0 ]; do
  case "$1" in
    --filter) filter=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "inprocess_scale.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
[ -x "$bench" ] || { echo "inprocess_scale.sh: no benchmark at '$bench' (build with -DRETREAT_BUILD_BENCHMARKS=ON, e.g. deploy/bench.sh)" >&2; exit 2; }
out=${out:-$(mktemp -d /tmp/retreat-inprocess-scale.XXXXXX)}
mkdir -p "$out"

"$bench" --benchmark_filter="$filter" --benchmark_out="$out/in_process_bench.json" \
  --benchmark_out_format=json >&2
python3 - "$out/in_process_bench.json" <<'PY' | tee "$out/results.txt"
import json, sys
runs = json.load(open(sys.argv[1]))["benchmarks"]
bare, inp = {}, {}
for b in runs:
    parts = b["name"].split("/")
    if parts[0] == "bare_world":
        bare[(int(parts[2]), int(parts[1]))] = b
    elif parts[0] == "in_process":
        inp[(int(parts[2]), int(parts[1]), int(parts[3]))] = b
print(f"{'world':<9} {'N':>7} {'lockstep':<11} {'bare robot-ticks/s':>19} {'in-process robot-ticks/s':>25} {'overhead':>9} {'x real time':>12} {'planned':>8} {'set-up s':>9}")
fmt = lambda v, f: (f.format(v) if v is not None else "-")
for (physical, n, plans), run in sorted(inp.items()):
    b = bare.get((physical, n), {}).get("items_per_second")
    rate = run.get("items_per_second")
    print(f"{'physical' if physical else 'kinetic':<9} {n:>7} {['per tick', 'plans', 'deciding'][plans]:<11} {fmt(b, '{:,.0f}'):>19} "
          f"{fmt(rate, '{:,.0f}'):>25} {fmt(b / rate if b and rate else None, '{:.1f}x'):>9} "
          f"{fmt(run.get('real_time_x'), '{:.2f}'):>12} {fmt(run.get('planned'), '{:.1%}'):>8} {fmt(run.get('setup_s'), '{:.1f}'):>9}")
PY
echo "inprocess_scale.sh: $out/results.txt" >&2
