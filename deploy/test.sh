#!/usr/bin/env bash
# The test command: installs what is missing, builds, and runs every test (unit, contract,
# integration, scenario, package) with CTest. Exit code 0 only if every test passed.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${RETREAT_BUILD_DIR:-$root/build}
"$root/deploy/build.sh"
# Two jobs on two cores; each multi-process test uses its own DDS domain id, so tests may overlap.
ctest --test-dir "$build" -j2 --output-on-failure --timeout 600 --no-tests=error
