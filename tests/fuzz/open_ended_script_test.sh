#!/usr/bin/env bash
# deploy/fuzz.sh (open-ended fuzzing) takes each fuzzer's command from this tree's CTest. Its dry
# run (RETREAT_FUZZ_DRY_RUN=1: nothing installed, built or run) must find every fuzz target, each
# an executable with its working directory and seed corpora (the script checks those and exits
# non-zero when one is missing).
# Usage: open_ended_script_test.sh FUZZ_BUILD_DIR deploy/fuzz.sh TARGETS...
set -euo pipefail
fuzz=$1 script=$2
shift 2
out=$(RETREAT_FUZZ_DRY_RUN=1 RETREAT_FUZZ_BUILD_DIR="$fuzz" bash "$script" 1)
found=$(sed -n 's/^== \([^:]*\): 1 s$/\1/p' <<<"$out" | sort)
expected=$(printf '%s\n' "$@" | sort)
if [ "$found" != "$expected" ]; then
  echo "deploy/fuzz.sh found these targets:"; echo "$found"
  echo "expected:"; echo "$expected"
  exit 1
fi
echo "deploy/fuzz.sh finds all $# fuzz targets"
