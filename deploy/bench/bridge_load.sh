#!/usr/bin/env bash
# Bridge load benchmark (issue 18): how fast retreat-bridge answers /metrics and /api/state while
# other clients hold connections: event streams (viewers' dashboards) and half-open requests (a
# broken or hostile client). The bridge replays the committed recording
# (tests/fuzz/corpus/recording/cyclonedds-3-robots.mcap, no DDS) slowly, so that its state
# changes during the measurement; the client is deploy/bench/bridge_load.py (Python, standard
# library). Both run in a new network namespace that has only its own loopback (unshare -rn).
#
# Usage:
#   deploy/bench/bridge_load.sh [--bridge PATH] [--out DIR] [--cases 'CASE ...']
#   --bridge PATH   retreat-bridge (default $RETREAT_BUILD_DIR/bridge/retreat-bridge, build/...)
#   --cases LIST    space-separated `streams=S,half_open=H[,trickle=T][,from=ADDR]`
#                   (bridge_load.py says what each is; default: the issue's table: nothing; 16
#                   and 40 streams; 8 and 64 half-open; 60 half-open; 60 half-open with 40
#                   streams; then its aims: 200 streams; 500 half-open, and 250 half-open with
#                   250 trickling, each from the measuring client's own address and from another;
#                   all of it at once)
#
# Output: one JSON line per case (DIR/results.jsonl) and a Markdown table on stdout (also
# DIR/results.md): p50/p99/max in ms of 200 requests per endpoint (fewer when they take over 30 s
# in all; the count is in brackets), each on a new connection with a 10 s limit (failed: no 200
# within it), the streams open at the end and the 503s they got.
# The aims: /metrics and /api/state within 100 ms at p99 with 200 streams, and with 500
# half-open connections from one address.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
bridge=${RETREAT_BUILD_DIR:-$root/build}/bridge/retreat-bridge
out=""
cases="streams=0,half_open=0 streams=16,half_open=0 streams=40,half_open=0 streams=0,half_open=8 streams=0,half_open=64 streams=0,half_open=60 streams=40,half_open=60 streams=200,half_open=0 streams=0,half_open=500 streams=0,half_open=500,from=127.0.0.2 streams=0,half_open=250,trickle=250 streams=0,half_open=250,trickle=250,from=127.0.0.2 streams=200,half_open=250,trickle=250,from=127.0.0.2"
usage() { sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; }
while [ $# -gt 0 ]; do
  case "$1" in
    --bridge) bridge=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --cases) cases=$2; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "bridge_load.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
[ -x "$bridge" ] || { echo "bridge_load.sh: no retreat-bridge at '$bridge' (--bridge PATH)" >&2; exit 2; }
for c in $cases; do
  [[ $c =~ ^streams=[0-9]+,half_open=[0-9]+(,trickle=[0-9]+)?(,from=127\.[0-9]+\.[0-9]+\.[0-9]+)?$ ]] ||
    { echo "bridge_load.sh: case '$c': must be streams=S,half_open=H[,trickle=T][,from=127.X.Y.Z]" >&2; exit 2; }
done
command -v unshare >/dev/null || { echo "bridge_load.sh: needs unshare (util-linux)" >&2; exit 2; }

# Into a network namespace of our own: nothing here can reach or be reached from outside.
if [ -z "${RETREAT_BRIDGE_LOAD_NETNS:-}" ]; then
  out=${out:-$(mktemp -d /tmp/bridge-load.XXXXXX)}
  exec unshare -rn env RETREAT_BRIDGE_LOAD_NETNS=1 "$0" --bridge "$bridge" --out "$out" --cases "$cases"
fi
ip link set lo up 2>/dev/null || true
mkdir -p "$out"
recording="$root/tests/fuzz/corpus/recording/cyclonedds-3-robots.mcap"
"$bridge" --replay "$recording" --http 127.0.0.1:0 >"$out/bridge.log" 2>&1 &
pid=$!
trap 'kill -TERM "$pid" 2>/dev/null; wait "$pid" 2>/dev/null || true' EXIT
port=""
for _ in $(seq 100); do
  port=$(sed -n 's|^retreat-bridge: serving http://127.0.0.1:\([0-9]*\)/.*|\1|p' "$out/bridge.log")
  [ -n "$port" ] && break
  sleep 0.1
done
[ -n "$port" ] || { echo "bridge_load.sh: the bridge did not start:" >&2; cat "$out/bridge.log" >&2; exit 1; }
# 1.5 simulated s at 0.01x: 150 s of changing state, longer than the cases.
python3 -c "import urllib.request as u; u.urlopen(u.Request('http://127.0.0.1:$port/api/replay?play=1&speed=0.01', method='POST'))"

echo "bridge_load.sh: $(nproc) cores, $(uname -r), bridge pid $pid port $port, $(date -u +%FT%TZ)" | tee "$out/results.md"
# shellcheck disable=SC2086
python3 "$here/bridge_load.py" "$port" $cases | tee "$out/results.jsonl" >/dev/null
python3 - "$out/results.jsonl" <<'EOF' | tee -a "$out/results.md"
import json, sys
rows = [json.loads(line) for line in open(sys.argv[1])]
def cell(r):
    n = f' ({r["failed"]} of {r["requests"]} failed)' if r["failed"] else f' ({r["requests"]})'
    return ("–" if r["p50_ms"] is None else f'{r["p50_ms"]} / {r["p99_ms"]} / {r["max_ms"]}') + n
print("| streams | half-open | trickling | from | /metrics p50 / p99 / max (ms) | /api/state p50 / p99 / max (ms) | streams open | stream 503s |")
print("|---:|---:|---:|---|---|---|---:|---:|")
for r in rows:
    print(f'| {r["streams"]} | {r["half_open"]} | {r["trickle"]} | {r["from"]} | {cell(r["metrics"])} | {cell(r["state"])} | {r["streams_open"]} | {r["stream_503s"]} |')
EOF
echo "bridge_load.sh: results in $out"
