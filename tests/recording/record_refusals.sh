#!/bin/sh
# retreat-record refuses bad input at start-up: exit code 2, one line on stderr naming the value,
# and no file written. Nothing joins DDS (each refusal comes before the participant).
#   record_refusals.sh RETREAT_RECORD SCENARIO WORKDIR
set -u
record=$1 scenario=$2 work=$3
rm -rf "$work"; mkdir -p "$work"
status=0
refused() {  # NAME EXPECTED_TEXT ARGS...
  name=$1 text=$2; shift 2
  "$record" "$@" >"$work/$name.out" 2>"$work/$name.err"; code=$?
  lines=$(wc -l <"$work/$name.err")
  if [ "$code" -ne 2 ] || [ "$lines" -ne 1 ] || ! grep -q -- "$text" "$work/$name.err"; then
    echo "record_refusals: $name: exit $code, $lines lines:"; cat "$work/$name.err"; status=1
  fi
}
refused no-out "--out" --scenario "$scenario" --domain 84
refused no-directory "/nonexistent/run.mcap" --scenario "$scenario" --domain 84 --out /nonexistent/run.mcap
refused inmemory "dds.vendor = inmemory" --scenario "$scenario" --domain 84 --out "$work/x.mcap" --dds inmemory
refused security "dds.security" --scenario "$scenario" --domain 84 --out "$work/x.mcap" --set dds.security=on
# A swarm PKI without the recorder's identity (made before retreat-record had one).
mkdir -p "$work/pki" && : >"$work/pki/ca.pem" && : >"$work/pki/governance.p7s"
refused no-recorder-identity "no recorder/cert.pem" --scenario "$scenario" --domain 84 --out "$work/x.mcap" \
  --set dds.security=on --set dds.security_dir="$work/pki"
refused bad-domain "300" --scenario "$scenario" --domain 300 --out "$work/x.mcap"
if [ -e "$work/x.mcap" ]; then echo "record_refusals: a refused start wrote its file"; status=1; fi
[ "$status" -eq 0 ] && rm -rf "$work"
exit $status
