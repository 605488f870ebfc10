#!/usr/bin/env bash
# Open-ended fuzzing (docs/fuzzing.md): builds the libFuzzer tree (build-fuzz/, Clang with
# AddressSanitizer and UndefinedBehaviorSanitizer) and runs each fuzzer for SECONDS with a new
# random seed, keeping what it finds in build-fuzz/fuzz-corpus-open/<target>/ across runs.
# A crash leaves its input as build-fuzz/fuzz-corpus-open/<target>/crash-*: copy it into the
# target's seed corpus as tests/fuzz/corpus/<dir>/regression-<what>, so that the test command's
# deterministic stage runs it from then on.
# Usage: deploy/fuzz.sh [SECONDS per fuzzer, default 120] [TARGET-REGEX, default all]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-120}
only=${2:-.}
build=${RETREAT_BUILD_DIR:-$root/build}
fuzz=${RETREAT_FUZZ_BUILD_DIR:-$build-fuzz}
"$root/deploy/install-deps.sh"
"$root/deploy/install-web-deps.sh" "$build/web-deps"
cmake -S "$root" -B "$fuzz" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang \
  -DCMAKE_CXX_COMPILER=clang++ -DRETREAT_BUILD_FUZZERS=ON -DRETREAT_BUILD_TESTS=OFF \
  -DRETREAT_BUILD_BENCHMARKS=OFF -DRETREAT_WEB_DEPS_DIR="$build/web-deps" >/dev/null
cmake --build "$fuzz" -j"$(nproc)" --target retreat_fuzzers
status=0
# The CTest commands know each target's seed corpora and options: reuse them, swapping the
# deterministic run for an open-ended one.
while read -r name; do
  [[ $name =~ $only ]] || continue
  line=$(ctest --test-dir "$fuzz" -N -V -R "^${name}\$" | sed -n 's/^[0-9]*: Test command: //p')
  workdir=$(ctest --test-dir "$fuzz" -N -V -R "^${name}\$" | sed -n 's/^[0-9]*: Working Directory: //p')
  read -r -a cmd <<<"$line"
  # cmd: bash run_fuzzer.sh WORK FUZZER RUNS [options...] -- SEEDS...
  fuzzer=${cmd[3]}
  options=() seeds=() past=0
  for word in "${cmd[@]:5}"; do
    if [ "$word" = "--" ]; then past=1; elif [ $past = 1 ]; then seeds+=("$word"); else options+=("$word"); fi
  done
  corpus=$fuzz/fuzz-corpus-open/$name
  mkdir -p "$corpus"
  echo "== $name: ${seconds} s"
  (cd "${workdir:-$fuzz}" && "$fuzzer" -max_total_time="$seconds" -timeout=60 -rss_limit_mb=2048 \
    -print_final_stats=1 -artifact_prefix="$corpus/" "${options[@]}" "$corpus" "${seeds[@]}") || status=1
done < <(ctest --test-dir "$fuzz" -N -L fuzz | sed -n 's/^ *Test *#[0-9]*: //p')
exit $status
