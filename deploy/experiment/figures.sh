#!/usr/bin/env bash
# Renders figures of a retreat-experiment report to PNG with the Debian headless Chromium, for
# the docs (docs/figures/). Each figure is shown alone (report.html#only=<id>) and screenshotted.
#
#   deploy/experiment/figures.sh RUN_DIR PREFIX [ID ...]
#
# writes docs/figures/PREFIX-<id>.png for every figure ID of RUN_DIR/report.html (all of them
# when none is named). FIGURES_DIR=... writes elsewhere; CHROMIUM=... picks the browser.
set -euo pipefail

if [[ $# -lt 2 ]]; then
  echo "usage: $0 RUN_DIR PREFIX [ID ...]" >&2
  exit 2
fi
run_dir=$(realpath "$1")
prefix=$2
shift 2
report="$run_dir/report.html"
[[ -f "$report" ]] || { echo "$0: $report: no such file (a retreat-experiment run directory)" >&2; exit 2; }
chromium=${CHROMIUM:-/usr/bin/chromium}
[[ -x "$chromium" ]] || { echo "$0: $chromium: no such program (apt-get install chromium)" >&2; exit 2; }
out=${FIGURES_DIR:-$(dirname "$(realpath "$0")")/../../docs/figures}
mkdir -p "$out"
out=$(realpath "$out")

ids=("$@")
if [[ ${#ids[@]} -eq 0 ]]; then
  # The page's data is compact JSON: every figure has "id":"<id>".
  mapfile -t ids < <(grep -o '"id":"[A-Za-z0-9_-]*"' "$report" | sed 's/"id":"\(.*\)"/\1/')
fi

profile=$(mktemp -d)
trap 'rm -rf "$profile"' EXIT
for id in "${ids[@]}"; do
  png="$out/$prefix-$id.png"
  "$chromium" --headless --no-sandbox --disable-gpu --disable-dev-shm-usage --hide-scrollbars \
    --no-first-run --disable-background-networking --disable-component-update --disable-sync \
    --user-data-dir="$profile" --window-size=860,540 --screenshot="$png" \
    "file://$report#only=$id" >/dev/null 2>&1
  [[ -s "$png" ]] || { echo "$0: $id: no screenshot written" >&2; exit 1; }
  echo "$png"
done
