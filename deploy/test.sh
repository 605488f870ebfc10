#!/usr/bin/env bash
# The test command: installs what is missing, builds, and runs every test (unit, contract,
# integration, scenario, package) with CTest, then a deterministic run of every fuzzer
# (tests/fuzz: fixed seed, fixed number of inputs), then the golden trajectories from a Clang and
# libc++ build of the core (tests/portability). Exit code 0 only if every test passed.
# No test passes or fails by wall-clock speed: the whole command holds on a loaded machine.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${RETREAT_BUILD_DIR:-$root/build}
"$root/deploy/build.sh"
# Two jobs on two cores; each multi-process test uses its own DDS domain id, so tests may overlap.
status=0
ctest --test-dir "$build" -j2 --output-on-failure --no-tests=error || status=$?
# Fuzz stage (docs/fuzzing.md): a Clang tree instrumented for libFuzzer, ASan and UBSan; only the
# fuzz targets and what they need are built, then each fuzzer runs a fixed number of inputs with
# a fixed seed from its committed corpus (open-ended fuzzing: deploy/fuzz.sh).
fuzz=${RETREAT_FUZZ_BUILD_DIR:-$build-fuzz}
cmake -S "$root" -B "$fuzz" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang \
  -DCMAKE_CXX_COMPILER=clang++ -DRETREAT_BUILD_FUZZERS=ON -DRETREAT_BUILD_TESTS=OFF \
  -DRETREAT_BUILD_BENCHMARKS=OFF -DRETREAT_WEB_DEPS_DIR="$build/web-deps" >/dev/null
cmake --build "$fuzz" -j2 --target retreat_fuzzers
ctest --test-dir "$fuzz" -j2 -L fuzz --output-on-failure --no-tests=error || status=$?
# Portability stage (docs/conventions.md, "Determinism"): the in-memory core built with Clang and
# libc++ (no DDS, yaml-cpp or HTTP) runs the golden cases from their JSON scenarios and must give
# the GCC and libstdc++ build's recorded trajectory hashes. On a processor that has them, it is
# built for x86-64-v3 (AVX2, FMA), as a robot's processor with FMA would be: no a·b + c may fuse.
libcxx=${RETREAT_LIBCXX_BUILD_DIR:-$build-libcxx}
libcxx_flags=-stdlib=libc++
cpu_flags=" $( (grep -m1 '^flags' /proc/cpuinfo || true) 2>/dev/null | cut -d: -f2) "
if [ "$(uname -m)" = x86_64 ]; then
  v3=yes
  for flag in avx2 fma bmi2 movbe; do
    case "$cpu_flags" in *" $flag "*) ;; *) v3=no ;; esac
  done
  if [ "$v3" = yes ]; then libcxx_flags="$libcxx_flags -march=x86-64-v3"; fi
fi
echo "test.sh: portability stage: Clang, $libcxx_flags"
cmake -S "$root" -B "$libcxx" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang \
  -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_CXX_FLAGS="$libcxx_flags" -DCMAKE_EXE_LINKER_FLAGS=-stdlib=libc++ \
  -DRETREAT_PORTABILITY_ONLY=ON >/dev/null
cmake --build "$libcxx" -j2
ctest --test-dir "$libcxx" -j2 -L portability --output-on-failure --no-tests=error || status=$?
exit $status
