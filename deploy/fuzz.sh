#!/usr/bin/env bash
# Open-ended fuzzing (docs/fuzzing.md): builds the libFuzzer tree (build-fuzz/, Clang with
# AddressSanitizer and UndefinedBehaviorSanitizer) and runs each fuzzer for SECONDS with a new
# random seed, keeping what it finds in build-fuzz/fuzz-corpus-open/<target>/ across runs.
# A crash leaves its input as build-fuzz/fuzz-corpus-open/<target>/crash-*: copy it into the
# target's seed corpus as tests/fuzz/corpus/<dir>/regression-<what>, so that the test command's
# deterministic stage runs it from then on.
# Usage: deploy/fuzz.sh [SECONDS per fuzzer, default 120] [TARGET-REGEX, default all]
# RETREAT_FUZZ_DRY_RUN=1: install and build nothing, run nothing; check that every selected
# target's fuzzer, working directory and seed corpora exist and print what would run (the fuzz
# stage's test of this script, tests/fuzz/CMakeLists.txt).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-120}
only=${2:-.}
build=${RETREAT_BUILD_DIR:-$root/build}
fuzz=${RETREAT_FUZZ_BUILD_DIR:-$build-fuzz}
dry_run=${RETREAT_FUZZ_DRY_RUN:-0}
if [ "$dry_run" != 1 ]; then
  "$root/deploy/install-deps.sh"
  "$root/deploy/install-web-deps.sh" "$build/web-deps"
  cmake -S "$root" -B "$fuzz" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang \
    -DCMAKE_CXX_COMPILER=clang++ -DRETREAT_BUILD_FUZZERS=ON -DRETREAT_BUILD_TESTS=OFF \
    -DRETREAT_BUILD_BENCHMARKS=OFF -DRETREAT_WEB_DEPS_DIR="$build/web-deps" >/dev/null
  cmake --build "$fuzz" -j"$(nproc)" --target retreat_fuzzers
fi
status=0
# The CTest commands know each target's seed corpora and options: reuse them, swapping the
# deterministic run for an open-ended one. They are read from CTest's JSON (one line per test:
# name, working directory, then the command's arguments, tab-separated), not from `ctest -V`,
# which prints the arguments quoted. Only the fuzzers' runs (run_fuzzer.sh), not the stage's
# other tests.
tests=$(ctest --test-dir "$fuzz" --show-only=json-v1 -L fuzz | python3 -c '
import json, sys
for test in json.load(sys.stdin)["tests"]:
    command = test.get("command", [])
    if len(command) < 2 or not command[1].endswith("/run_fuzzer.sh"):
        continue
    workdir = next((p["value"] for p in test.get("properties", []) if p["name"] == "WORKING_DIRECTORY"), "")
    print("\t".join([test["name"], workdir or "-"] + command))
')
[ -n "$tests" ] || { echo "deploy/fuzz.sh: no fuzz tests in $fuzz" >&2; exit 1; }
matched=0
while IFS=$'\t' read -r -a fields; do
  name=${fields[0]} workdir=${fields[1]}
  [ "$workdir" != - ] || workdir=$fuzz
  [[ $name =~ $only ]] || continue
  matched=1
  # fields[2..]: bash run_fuzzer.sh WORK FUZZER RUNS [options...] -- SEEDS...
  cmd=("${fields[@]:2}")
  fuzzer=${cmd[3]}
  options=() seeds=() past=0
  for word in "${cmd[@]:5}"; do
    if [ "$word" = "--" ]; then past=1; elif [ $past = 1 ]; then seeds+=("$word"); else options+=("$word"); fi
  done
  corpus=$fuzz/fuzz-corpus-open/$name
  run=("$fuzzer" -max_total_time="$seconds" -timeout=60 -rss_limit_mb=2048 -print_final_stats=1
       -artifact_prefix="$corpus/" "${options[@]}" "$corpus" "${seeds[@]}")
  echo "== $name: ${seconds} s"
  if [ "$dry_run" = 1 ]; then
    [ -x "$fuzzer" ] || { echo "deploy/fuzz.sh: $name: fuzzer '$fuzzer' is not an executable file" >&2; status=1; }
    [ -d "$workdir" ] || { echo "deploy/fuzz.sh: $name: working directory '$workdir' does not exist" >&2; status=1; }
    for seed in "${seeds[@]}"; do
      [ -d "$seed" ] || { echo "deploy/fuzz.sh: $name: seed corpus '$seed' is not a directory" >&2; status=1; }
    done
    echo "(cd $(printf '%q' "$workdir") && $(printf '%q ' "${run[@]}"))"
    continue
  fi
  mkdir -p "$corpus"
  (cd "$workdir" && "${run[@]}" < /dev/null) || status=1
done <<<"$tests"
[ $matched = 1 ] || { echo "deploy/fuzz.sh: no fuzz target matches '$only'" >&2; exit 2; }
exit $status
