#!/usr/bin/env bash
# One deterministic fuzz run for CTest (tests/fuzz/CMakeLists.txt): a fixed seed, a fixed number
# of inputs, and a work corpus emptied first, so the same commit always runs the same inputs and
# gets the same verdict. The committed seed corpora are read, never written.
# Usage: run_fuzzer.sh WORK_DIR FUZZER RUNS [libFuzzer options...] -- SEED_DIR...
set -euo pipefail
work=$1 fuzzer=$2 runs=$3
shift 3
options=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do options+=("$1"); shift; done
[ "${1:-}" = "--" ] && shift
rm -rf "$work"
mkdir -p "$work"
# setarch -R: no address randomisation, since code whose branches follow addresses (containers
# ordered by pointer, as in yaml-cpp) would otherwise cover differently from run to run and
# steer the mutations apart. -seed: the mutation sequence; -runs: how many inputs (not seconds: a loaded machine runs the
# same inputs, only slower); -reload=0: the corpus is not re-read every second (a clock
# would decide which inputs join); -timeout 60 s for one input is a hang even when loaded.
exec setarch "$(uname -m)" -R "$fuzzer" -seed=1 -runs="$runs" -reload=0 -timeout=60 -rss_limit_mb=2048 -print_final_stats=1 \
  -artifact_prefix="$work/" "${options[@]}" "$work" "$@"
