#!/bin/sh
# Recorded runs replayed, re-decided and compared, over real DDS processes (docs/recording.md):
#   - a Cyclone DDS run with plans and a Fast DDS run per tick (retreat-launch --record, 150 s)
#     replay to the same answers over each vendor: the Fast DDS recording over Cyclone DDS too;
#   - re-deciding a run with plans tick by tick with its own rule gives its decisions at every
#     tick (the plans expanded as the agent expands them), and with another rule differs;
#   - an agent started by hand with another seed is found out: its answers differ, exit 5;
#   - retreat-diff finds the two runs (plans over Cyclone DDS, per tick over Fast DDS) and an
#     in-process run identical, finds a planted divergence (agent.K_p = 0) at the tick and robot
#     retreats.csv gives (and in the recordings no later), and refuses a truncated recording in
#     one line.
#
#   replay_run.sh LAUNCH REPLAY DIFF AGENT SCENARIO DOMAIN WORKDIR
set -u
launch=$1 replay=$2 diff=$3 agent=$4 scenario=$5 domain=$6 work=$7
rm -rf "$work"
mkdir -p "$work"
status=0
fail() {
  echo "replay_run: $*"
  status=1
}
# expect CODE PATTERN LOG -- COMMAND...: runs COMMAND with its output in LOG; the exit code must
# be CODE and the output must contain PATTERN (an extended regular expression).
expect() {
  code=$1 pattern=$2 log=$3
  shift 4
  "$@" >"$log" 2>&1
  got=$?
  if [ "$got" -ne "$code" ]; then
    fail "$*: exit code $got, expected $code:"; cat "$log"; return
  fi
  grep -Eq -- "$pattern" "$log" || { fail "$*: no line matches '$pattern':"; cat "$log"; }
}

sets="--set run.duration=150"
for run in cyclonedds:true fastdds:false; do
  vendor=${run%%:*} plans=${run#*:}
  "$launch" "$scenario" --dds "$vendor" --domain "$domain" --no-bridge --out "$work/$vendor" $sets \
    --set run.plans="$plans" --record "$work/$vendor.mcap" >"$work/$vendor-launch.log" 2>&1 ||
    { fail "retreat-launch $vendor failed:"; cat "$work/$vendor-launch.log"; }
done
[ "$status" -eq 0 ] || exit 1

# Replays: every answer as recorded, whichever vendor carries it.
for rec in cyclonedds fastdds; do
  for over in cyclonedds fastdds; do
    expect 0 '^12 robots: [1-9][0-9]* answers as recorded, 0 differ' "$work/replay-$rec-over-$over.log" -- \
      "$replay" "$work/$rec.mcap" --dds "$over" --domain "$domain"
  done
done
# One robot, at the recorded pace.
expect 0 '^1 robots: [1-9][0-9]* answers as recorded, 0 differ' "$work/replay-pace.log" -- \
  "$replay" "$work/cyclonedds.mcap" --robots 3 --pace recorded --domain "$domain"

# Re-deciding every tick: with the recorded rule, the recorded decisions at all 5,001 ticks of
# every robot that stays (fewer for one that leaves); with another rule, some differ.
expect 0 '^12 robots: [1-9][0-9]* answers as recorded, 0 differ' "$work/redecide-paper.log" -- \
  "$replay" "$work/cyclonedds.mcap" --dds inmemory --controller paper
grep -q '5001/5001 frames answered' "$work/redecide-paper.log" || fail "re-deciding with paper: no robot got every tick"
expect 0 '^12 robots: [0-9]+ answers as recorded, [1-9][0-9]* differ' "$work/redecide-other.log" -- \
  "$replay" "$work/cyclonedds.mcap" --dds inmemory --controller adaptive-proportional --report "$work/redecide.json"
grep -q '"first_difference"' "$work/redecide.json" || fail "the re-decision's report names no first difference"

# An agent that is not the recorded one: robot 3's, with another seed, started by hand.
sed -e 's/^seed: .*/seed: 99/' -e 's/^\( *recorders:\).*/\1 0/' "$work/cyclonedds/scenario.yaml" >"$work/other-seed.yaml"
grep -q '^seed: 99' "$work/other-seed.yaml" || fail "cannot write a scenario with seed 99"
"$agent" --scenario "$work/other-seed.yaml" --robot-id 3 --dds cyclonedds --domain "$domain" >"$work/agent3.log" 2>&1 &
agent_pid=$!
expect 5 '^1 robots: [0-9]+ answers as recorded, [1-9][0-9]* differ' "$work/replay-other-seed.log" -- \
  "$replay" "$work/cyclonedds.mcap" --robots 3 --no-agents --domain "$domain" --answer-timeout 120
kill -TERM "$agent_pid" 2>/dev/null
wait "$agent_pid" 2>/dev/null

# retreat-diff: the same run three ways; a planted divergence; a truncated recording.
"$launch" "$scenario" --in-process --no-bridge --out "$work/in-process" $sets >"$work/in-process.log" 2>&1 ||
  fail "the in-process run failed"
"$launch" "$scenario" --dds cyclonedds --domain "$domain" --no-bridge --out "$work/planted" $sets --set run.plans=true \
  --set agent.K_p=0 --record "$work/planted.mcap" >"$work/planted.log" 2>&1 || fail "the planted run failed"
expect 0 '^identical: 5000 ticks' "$work/diff-vendors.log" -- "$diff" "$work/cyclonedds" "$work/fastdds"
expect 0 '^identical: 5000 ticks' "$work/diff-in-process.log" -- "$diff" "$work/cyclonedds" "$work/in-process"
expect 0 '^identical: ' "$work/diff-recordings.log" -- "$diff" "$work/cyclonedds.mcap" "$work/cyclonedds.mcap"
expect 0 '^identical: ' "$work/diff-modes.log" -- "$diff" "$work/cyclonedds.mcap" "$work/fastdds.mcap"
# Where the planted run first differs, from retreats.csv alone: the earliest retreat one run has
# and the other has not (the runs agree until a robot decides differently).
first=$( (tail -n +2 "$work/in-process/retreats.csv" | sed 's/$/,A/'; tail -n +2 "$work/planted/retreats.csv" | sed 's/$/,B/') |
  sort -t, -k1,1n -k2,2n | awk -F, '{ key = $1 "," $2; n[key]++; line[key] = $0; order[NR] = key }
    END { for (i = 1; i <= NR; i++) if (n[order[i]] == 1) { print line[order[i]]; exit } }')
[ -n "$first" ] || fail "the planted run retreats exactly as the other: nothing to find"
tick=${first%%,*} rest=${first#*,} robot=${rest%%,*} side=${rest#*,}
if [ "$side" = A ]; then values="A retreat, B stay"; else values="A stay, B retreat"; fi
expect 1 "robot $robot decision $values" "$work/diff-planted.log" -- "$diff" "$work/in-process" "$work/planted"
grep -q "at tick $tick: robot $robot decision\|until tick $tick)" "$work/diff-planted.log" ||
  { fail "the planted divergence is at tick $tick (robot $robot), retreat-diff says:"; cat "$work/diff-planted.log"; }
# The same two runs' recordings differ no later than their trajectories do (a plan announces a
# retreat at the frame it answers, before the retreat's tick).
expect 1 '^differ at tick [0-9]+: robot [0-9]+ ' "$work/diff-planted-recordings.log" -- \
  "$diff" "$work/cyclonedds.mcap" "$work/planted.mcap"
seen=$(sed -n 's/^differ at tick \([0-9]*\):.*/\1/p' "$work/diff-planted-recordings.log")
[ -n "$seen" ] && [ "$seen" -le "$tick" ] ||
  fail "the recordings differ first at tick '$seen', after the trajectories (tick $tick)"
head -c 20000 "$work/fastdds.mcap" >"$work/truncated.mcap"
expect 2 "^retreat-diff: '.*truncated.mcap': truncated at byte" "$work/diff-truncated.log" -- \
  "$diff" "$work/truncated.mcap" "$work/fastdds.mcap"
expect 2 "^retreat-replay: '.*truncated.mcap': truncated at byte" "$work/replay-truncated.log" -- \
  "$replay" "$work/truncated.mcap"
[ "$(wc -l <"$work/replay-truncated.log")" -eq 1 ] || fail "retreat-replay said more than one line about a truncated file"

[ "$status" -eq 0 ] && rm -rf "$work"
exit $status
