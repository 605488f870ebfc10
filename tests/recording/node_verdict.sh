#!/bin/sh
# Runs a Node script and takes its verdict from what it prints, not from node's exit: node has
# been seen (twice in several hundred runs, the second with --v8-pool-size=0) to print its
# verdict and then never exit, its main thread joining a V8 worker that waits for a background
# collection (gdb: NodePlatform::Shutdown -> uv_thread_join). Every script run through here
# prints "NAME: ok, ..." as its last line on success (stdout or stderr); once that line is out the
# work is done, so node is stopped by its PID and this exits 0. A failure exits node non-zero
# before that line, and this exits with node's code. The script's stdout and stderr come out on
# this script's, in full, once node is done.
#   node_verdict.sh NAME NODE SCRIPT ARGS...
set -u
name=$1; shift
node=$1; shift
out=$(mktemp) err=$(mktemp)
"$node" "$@" >"$out" 2>"$err" &
pid=$!
finish() {
  cat "$out"; cat "$err" >&2
  rm -f "$out" "$err"
  exit "$1"
}
while kill -0 "$pid" 2>/dev/null; do
  if grep -q "^$name: ok, " "$out" "$err"; then
    kill -9 "$pid" 2>/dev/null
    wait "$pid" 2>/dev/null
    finish 0
  fi
  sleep 0.1
done
wait "$pid"; rc=$?
finish "$rc"
