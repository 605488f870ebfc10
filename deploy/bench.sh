#!/usr/bin/env bash
# Builds (with benchmarks) and runs the project's Google Benchmark programs; results go to stdout.
# The scale and load benchmarks under deploy/bench/ are not run here: each takes minutes to hours
# and needs options of its own (agents, vendor, domains; discovery_scale.sh has no default
# vendor), so they run one at a time with the commands docs/benchmarks.md gives for each figure.
# This script lists them at the end.
# Usage: deploy/bench.sh            (see docs/benchmarks.md for the recorded figures)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${RETREAT_BUILD_DIR:-$root/build}
"$root/deploy/build.sh" -DRETREAT_BUILD_BENCHMARKS=ON
echo "== physics step (Google Benchmark; items_per_second = robot-steps per second)"
"$build/tests/benchmarks/arena/physics_step_bench" --benchmark_min_time=0.5
echo "== MCAP writer (Google Benchmark; items_per_second = messages per second into a file)"
"$build/tests/benchmarks/recording/mcap_writer_bench"
echo "== starting a child process: fork() + execve() against ChildProcess (Google Benchmark; arg = MiB the parent writes)"
"$build/tests/benchmarks/launch/child_process_bench"
echo "== ping-pong round trip over the project's transport (the bound for lockstep ticks/s)"
"$build/tests/benchmarks/pingpong/pingpong_bench" --benchmark_repetitions=3
echo "== scale and load benchmarks, not run here (one at a time: each script's header, docs/benchmarks.md)"
for script in "$root"/deploy/bench/*.sh; do
  [ -x "$script" ] || continue
  printf '  deploy/bench/%s: %s\n' "$(basename "$script")" "$(sed -n '2{s/^# //;s/:.*//;p}' "$script")"
done
