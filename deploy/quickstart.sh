#!/usr/bin/env bash
# The main job: installs what is missing, builds, and runs the paper's Robotarium experiment
# (deploy/scenarios/robotarium-2019.yaml) with 12 retreat-agent processes, a retreat-arena and,
# when built, the retreat-bridge, over Fast DDS on loopback. The run directory is printed at the end.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${RETREAT_BUILD_DIR:-$root/build}
"$root/deploy/build.sh"
out=${1:-$root/runs/robotarium-2019-$(date +%Y%m%d-%H%M%S)}
exec "$build/deploy/launch/retreat-launch" "$root/deploy/scenarios/robotarium-2019.yaml" --out "$out"
