#!/bin/sh
# Runs read_mcap.mjs and takes its verdict from what it prints, not from node's exit: node has
# been seen (twice in several hundred runs, the second with --v8-pool-size=0) to print its
# verdict and then never exit, its main thread joining a V8 worker that waits for a background
# collection (gdb: NodePlatform::Shutdown -> uv_thread_join). Once the success line is out the
# work is done, so node is stopped by its PID; a failure exits node with 1 before that line.
#   read_mcap.sh NODE READ_MCAP_MJS NODE_MODULES FILE MESSAGES MIN_CHUNKS
set -u
node=$1; shift
out=$(mktemp)
"$node" "$@" >"$out" 2>&1 &
pid=$!
while kill -0 "$pid" 2>/dev/null; do
  if grep -q '^read_mcap: ok, ' "$out"; then
    kill -9 "$pid" 2>/dev/null
    wait "$pid" 2>/dev/null
    cat "$out"; rm -f "$out"
    exit 0
  fi
  sleep 0.1
done
wait "$pid"; rc=$?
cat "$out"; rm -f "$out"
exit "$rc"
