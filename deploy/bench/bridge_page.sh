#!/usr/bin/env bash
# The dashboard with N robots (issue 18), in headless Chromium: a scripted swarm
# (retreat_scripted_swarm: telemetry and poses 10 times a second, every robot's status once a
# second, over DDS), retreat-bridge, and the page, per N. Both programs and the benchmark
# (tests/benchmarks/bridge/bridge_page_bench.cpp) come from a build with
# -DRETREAT_BUILD_BENCHMARKS=ON; Chromium from deploy/install-deps.sh. Everything runs in a new
# network namespace that has only its own loopback (unshare -rn).
#
# Usage:
#   deploy/bench/bridge_page.sh [--vendor fastdds|cyclonedds] [--seconds S] [--robots 'N ...'] [--out DIR]
#   --robots LIST   swarm sizes (default: 100 1000 2000 5000)
#   --seconds S     how long each swarm publishes (default 30; the page is measured for 10 s)
#
# Output: one JSON line per N (DIR/results.jsonl; bridge_page_bench.cpp says what each field is)
# and a Markdown table on stdout (also DIR/results.md). The aims: with 1,000 robots, 20 frames a
# second or more and the population plotted within 2 s; no sample lost by the bridge.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${RETREAT_BUILD_DIR:-$root/build}
bench=$build/tests/benchmarks/bridge/bridge_page_bench
vendor=cyclonedds
seconds=30
robots="100 1000 2000 5000"
out=""
usage() { sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; }
while [ $# -gt 0 ]; do
  case "$1" in
    --vendor) vendor=$2; shift 2 ;;
    --seconds) seconds=$2; shift 2 ;;
    --robots) robots=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "bridge_page.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
[ -x "$bench" ] || { echo "bridge_page.sh: no benchmark at '$bench': build with -DRETREAT_BUILD_BENCHMARKS=ON (RETREAT_BUILD_DIR=...)" >&2; exit 2; }
[[ $vendor =~ ^(fastdds|cyclonedds)$ ]] || { echo "bridge_page.sh: --vendor '$vendor': fastdds or cyclonedds" >&2; exit 2; }
[[ $seconds =~ ^[0-9]+$ ]] && [ "$seconds" -ge 20 ] || { echo "bridge_page.sh: --seconds '$seconds': a whole number, at least 20" >&2; exit 2; }
for n in $robots; do
  [[ $n =~ ^[0-9]+$ ]] && [ "$n" -ge 1 ] && [ "$n" -le 100000 ] ||
    { echo "bridge_page.sh: --robots '$n': whole numbers from 1 to 100000" >&2; exit 2; }
done
command -v unshare >/dev/null || { echo "bridge_page.sh: needs unshare (util-linux)" >&2; exit 2; }

if [ -z "${RETREAT_BRIDGE_PAGE_NETNS:-}" ]; then
  out=${out:-$(mktemp -d /tmp/bridge-page.XXXXXX)}
  exec unshare -rn env RETREAT_BRIDGE_PAGE_NETNS=1 "$0" --vendor "$vendor" --seconds "$seconds" --robots "$robots" --out "$out"
fi
ip link set lo up 2>/dev/null || true
mkdir -p "$out"
echo "bridge_page.sh: $(nproc) cores, $(uname -r), $vendor, $(date -u +%FT%TZ)" | tee "$out/results.md"
# shellcheck disable=SC2086
"$bench" "$vendor" 0 "$seconds" $robots | tee "$out/results.jsonl" >/dev/null
python3 - "$out/results.jsonl" <<'PY' | tee -a "$out/results.md"
import json, sys
rows = [json.loads(line) for line in open(sys.argv[1])]
print("| robots | first population plot (ms) | frames/s (page) | draws/s | one draw p50 / p99 / max (ms) | draws/s it could make | statuses written / received by the bridge | poses written / received |")
print("|---:|---:|---:|---:|---|---:|---|---|")
for r in rows:
    if "error" in r:
        print(f'| {r["robots"]} | error: {r["error"][:80]} |')
        continue
    d, w, g = r["draw_ms"], r["written"] or {}, r["received"] or {}
    print(f'| {r["robots"]:,} | {r["first_plot_ms"]:.0f} | {r["frames_per_s"]} | {r["draws_per_s"]} | '
          f'{d["p50"]} / {d["p99"]} / {d["max"]} | {r["draw_capacity_per_s"]:.0f} | '
          f'{w.get("statuses")} / {g.get("agent_status", 0):.0f} | {w.get("poses")} / {g.get("poses", 0):.0f} |')
PY
echo "bridge_page.sh: results in $out"
