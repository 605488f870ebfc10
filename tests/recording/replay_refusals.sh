#!/bin/sh
# retreat-replay, retreat-diff and retreat-bridge --replay refuse bad input at start-up: exit
# code 2 and one line on stderr naming the value. Nothing joins DDS (each refusal comes before
# the participant) and nothing serves HTTP.
#   replay_refusals.sh RETREAT_REPLAY RETREAT_DIFF RETREAT_BRIDGE RECORDING WORKDIR
# RECORDING: a short recorded run (tests/fuzz/corpus/recording), robots 0..6.
set -u
replay=$1 diff=$2 bridge=$3 recording=$4 work=$5
rm -rf "$work"; mkdir -p "$work"
status=0
refused() {  # PROGRAM NAME EXPECTED_TEXT ARGS...
  program=$1 name=$2 text=$3; shift 3
  "$program" "$@" >"$work/$name.out" 2>"$work/$name.err"; code=$?
  lines=$(wc -l <"$work/$name.err")
  if [ "$code" -ne 2 ] || [ "$lines" -ne 1 ] || ! grep -q -- "$text" "$work/$name.err"; then
    echo "replay_refusals: $name: exit $code, $lines lines:"; cat "$work/$name.err"; status=1
  fi
}
head -c 3000 "$recording" >"$work/truncated.mcap"
printf 'not a recording' >"$work/text.mcap"
mkdir -p "$work/not-a-run"
r=$replay
refused "$r" missing "nothing.mcap': cannot read it as a file" "$work/nothing.mcap"
refused "$r" directory "not-a-run': cannot read it as a file" "$work/not-a-run"
refused "$r" not-mcap "not an MCAP file" "$work/text.mcap"
refused "$r" truncated "truncated at byte" "$work/truncated.mcap"
refused "$r" robots-text "--robots 'one'" "$recording" --robots one
refused "$r" robots-twice "robot 1 is named twice" "$recording" --robots 1,2,1
refused "$r" robots-absent "robot 40 has no frames" "$recording" --robots 40 --dds inmemory
refused "$r" pace "--pace 'fast'" "$recording" --pace fast
refused "$r" controller "--controller 'nope': must be one of paper" "$recording" --controller nope
refused "$r" set-arena "--set 'arena.width=3'" "$recording" --set arena.width=3
refused "$r" set-range "agent.K_p = -1" "$recording" --set agent.K_p=-1 --dds inmemory
refused "$r" dds "--dds 'zenoh'" "$recording" --dds zenoh
refused "$r" domain "--domain '300': must be a whole number in 0..232" "$recording" --domain 300
refused "$r" domain-negative "--domain '-1': must be a whole number in 0..232" "$recording" --domain -1
refused "$r" timeout "--answer-timeout" "$recording" --answer-timeout 0
refused "$r" no-agents-inmemory "--no-agents with --dds inmemory" "$recording" --no-agents --dds inmemory
refused "$r" recorded-redecide "--pace recorded with --controller" "$recording" --pace recorded --controller paper
d=$diff
refused "$d" one-argument "b is required" "$recording"
refused "$d" kinds "one is a run directory, the other a recording" "$work/not-a-run" "$recording"
refused "$d" absent "no such file or directory" "$work/nothing" "$recording"
refused "$d" no-chain "no chain.bin" "$work/not-a-run" "$work/not-a-run"
mkdir -p "$work/chain-is-a-directory/chain.bin"  # read as a file, a directory threw a stream error
refused "$d" chain-directory "chain-is-a-directory': no chain.bin" "$work/chain-is-a-directory" "$work/not-a-run"
refused "$d" diff-truncated "truncated at byte" "$work/truncated.mcap" "$recording"
b=$bridge
refused "$b" bridge-truncated "--replay: '.*truncated.mcap': truncated at byte" --replay "$work/truncated.mcap" --http 127.0.0.1:0
refused "$b" bridge-not-mcap "not an MCAP file" --replay "$work/text.mcap" --http 127.0.0.1:0
refused "$b" bridge-scenario "--scenario with --replay" --replay "$recording" --scenario x.yaml
refused "$b" bridge-out "--out with --replay" --replay "$recording" --out "$work/run"
[ "$status" -eq 0 ] && rm -rf "$work"
exit $status
