#!/usr/bin/env bash
# Installs the dashboard's front-end libraries (bridge/web/package-lock.json: uPlot) from the npm
# registry into DIR/node_modules (default build/web-deps). CMake never downloads anything: it
# only reads this folder. A no-op when the lock file has not changed since the last install.
# Usage: deploy/install-web-deps.sh [DIR]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
dir=${1:-${RETREAT_BUILD_DIR:-$root/build}/web-deps}
mkdir -p "$dir"
if [ -f "$dir/node_modules/.retreat-lock" ] &&
   cmp -s "$dir/node_modules/.retreat-lock" "$root/bridge/web/package-lock.json"; then
  exit 0
fi
if ! command -v npm >/dev/null 2>&1; then
  echo "install-web-deps: npm is missing; run deploy/install-deps.sh first" >&2
  exit 1
fi
cp "$root/bridge/web/package.json" "$root/bridge/web/package-lock.json" "$dir/"
(cd "$dir" && npm ci --ignore-scripts --no-audit --no-fund --loglevel=error)
cp "$root/bridge/web/package-lock.json" "$dir/node_modules/.retreat-lock"
echo "install-web-deps: installed the dashboard's npm packages into $dir"
