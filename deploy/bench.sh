#!/usr/bin/env bash
# Builds (with benchmarks) and runs the project's benchmarks; results go to stdout.
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
for script in "$root"/deploy/bench/*.sh; do
  [ -x "$script" ] || continue
  echo "== $(basename "$script")"
  "$script"
done
