#!/bin/sh
# A recorded run, checked against its run directory by tools retreat did not write:
# retreat-launch --record over real DDS processes, then check_recording.mjs (@mcap/core,
# @foxglove/omgidl-serialization). Cases run one after another on one DDS domain id (the
# recording block of tests/support/include/retreat/testing/domains.hpp). When a Cyclone DDS and
# a Fast DDS per-tick case of 150 s both ran, their payloads are compared (compare_payloads.mjs).
#
# A case VENDOR:DURATION:PLANS runs retreat-launch --record (VENDOR: fastdds, cyclonedds or
# mixed); VENDOR:DURATION:PLANS:late runs retreat-launch --set run.recorders=1 and starts
# retreat-record (next to the launcher) by hand 2 s later: the arena and the agents must wait for
# it, or the first samples are missing. VENDOR:DURATION:PLANS:star records a star: the arena on
# the hub's profile, every other process on the agents' (deploy/dds/*star*, the Fast DDS
# discovery-server pair with its port moved from 11811 to 7313 so as not to meet a swarm of
# this host).
#
#   record_run.sh LAUNCH SCENARIO NODE CHECK NODE_MODULES DOMAIN WORKDIR  CASE...
set -u
launch=$1 scenario=$2 node=$3 check=$4 modules=$5 domain=$6 work=$7
shift 7
profiles="$(dirname "$scenario")/../dds"
verdict="$(dirname "$check")/node_verdict.sh"  # node's verdict from its last line, not its exit
rm -rf "$work"
mkdir -p "$work"
status=0
for case in "$@"; do
  IFS=: read -r vendor duration plans how <<EOF_CASE
$case
EOF_CASE
  dir="$work/$vendor-$duration-$plans${how:+-$how}"
  mkdir -p "$dir"
  sets="--set run.duration=$duration --set run.plans=$plans"
  if [ "$how" = star ]; then
    if [ "$vendor" = fastdds ]; then
      sed 's|<port>11811</port>|<port>7313</port>|' "$profiles/fastdds-discovery-server-hub.xml" >"$dir/hub.xml"
      sed 's|<port>11811</port>|<port>7313</port>|' "$profiles/fastdds-discovery-server-client.xml" >"$dir/agent.xml"
    else
      cp "$profiles/$vendor-star-hub.xml" "$dir/hub.xml"; cp "$profiles/$vendor-star-agent.xml" "$dir/agent.xml"
    fi
    sets="$sets --arena-profile $dir/hub.xml --set dds.profile=$dir/agent.xml"
  fi
  if [ "$how" != late ]; then
    "$launch" "$scenario" --dds "$vendor" --domain "$domain" --no-bridge --out "$dir/run" $sets \
      --record "$dir/run.mcap" >"$dir/launch.log" 2>&1
    code=$?
  else
    "$launch" "$scenario" --dds "$vendor" --domain "$domain" --no-bridge --out "$dir/run" $sets \
      --set run.recorders=1 >"$dir/launch.log" 2>&1 &
    launcher=$!
    sleep 2
    "$(dirname "$launch")/retreat-record" --scenario "$scenario" --dds "$vendor" --domain "$domain" $sets \
      --set run.recorders=1 --out "$dir/run.mcap" 2>"$dir/record.log" &
    recorder=$!
    wait "$launcher"; code=$?
    kill -TERM "$recorder"; wait "$recorder"
  fi
  if [ "$code" -ne 0 ]; then
    echo "record_run: $case: retreat-launch failed:"; cat "$dir/launch.log"; status=1; continue
  fi
  if ! "$verdict" check_recording "$node" "$check" "$modules" "$dir/run.mcap" "$dir/run"; then
    echo "record_run: $case: the recording does not match the run (files kept in $dir)"; status=1; continue
  fi
  rm -rf "$dir/run"  # the recording stays for the comparison below
done
# The per-tick runs over both vendors are the same run: their frames and answers must be the same
# bytes in both recordings, whichever vendor's recorder kept them.
a="$work/cyclonedds-150-false/run.mcap" b="$work/fastdds-150-false/run.mcap"
if [ "$status" -eq 0 ] && [ -f "$a" ] && [ -f "$b" ]; then
  "$verdict" compare_payloads "$node" "$(dirname "$check")/compare_payloads.mjs" "$modules" "$a" "$b" || status=1
fi
[ "$status" -eq 0 ] && rm -rf "$work"
exit $status
