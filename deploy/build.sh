#!/usr/bin/env bash
# Installs what is missing, then configures and builds retreat into build/ (or $RETREAT_BUILD_DIR).
# Extra arguments go to CMake, e.g. deploy/build.sh -DRETREAT_WITH_CYCLONEDDS=OFF
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${RETREAT_BUILD_DIR:-$root/build}
"$root/deploy/install-deps.sh"
"$root/deploy/install-web-deps.sh" "$build/web-deps"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "$@" >/dev/null
cmake --build "$build" -j"$(nproc)"
