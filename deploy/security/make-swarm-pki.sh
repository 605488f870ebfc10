#!/usr/bin/env bash
# Creates the DDS Security PKI of one swarm (docs/security.md): a certificate authority, one
# identity per robot agent, one per robot's own link (driver_<id>: a real robot's frames or
# tracked pose, and its decisions), one for the arena, one for the bridge and one for the recorder
# (retreat-record: it reads every topic and writes none), a governance document and
# one permissions document per identity, both signed by the CA (S/MIME). Both DDS vendors read
# the same files (dds.security: on, dds.security_dir: DIR).
#
# Usage:
#   deploy/security/make-swarm-pki.sh --out DIR --robots IDS [--prefix P] [--domains A-B] [--days N]
#   --out DIR       where the PKI goes (created if missing)
#   --robots IDS    robot ids that get an agent and a driver identity: N (one robot) or A-B
#   --prefix P      topic prefix of the swarm (dds.prefix, default retreat)
#   --domains A-B   DDS domain ids the documents allow (default 0-230: Cyclone DDS 0.10 reads no
#                   domain id above 230 in these documents)
#   --days N        validity of new certificates and permissions, in days (default 3650)
#
# Layout of DIR:
#   ca.pem, ca.key             the CA (identity CA and permissions CA); keep ca.key private
#   governance.xml, .p7s       the swarm's rules (the .p7s is what the participants load)
#   <identity>/cert.pem, key.pem, permissions.xml, permissions.p7s
#       for the identities robot_<id>, driver_<id>, arena, bridge and recorder
#
# Idempotent: an existing CA and existing identities are kept (an identity whose certificate
# the CA does not verify is made again); a document is signed again only when its text changed.
# ECDSA P-256 keys, SHA-256 signatures. Needs the `openssl` command (Debian package openssl).
set -euo pipefail

program=make-swarm-pki.sh
fail() { echo "$program: $*" >&2; exit 2; }
usage() { sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; }

out="" robots="" prefix="retreat" domains="0-230" days=3650
while [ $# -gt 0 ]; do
  case "$1" in
    --out|--robots|--prefix|--domains|--days)
      [ $# -ge 2 ] || fail "$1 needs a value (see --help)"
      case "$1" in
        --out) out=$2 ;; --robots) robots=$2 ;; --prefix) prefix=$2 ;;
        --domains) domains=$2 ;; --days) days=$2 ;;
      esac
      shift 2 ;;
    -h|--help) usage; exit 0 ;;
    *) fail "unknown argument '$1' (allowed: --out --robots --prefix --domains --days; see --help)" ;;
  esac
done

# A whole-number range "A-B" or a single "N"; sets range_lo, range_hi.
parse_range() {  # name value max
  local name=$1 value=$2 max=$3
  if [[ $value =~ ^([0-9]{1,9})-([0-9]{1,9})$ ]]; then
    range_lo=$((10#${BASH_REMATCH[1]})) range_hi=$((10#${BASH_REMATCH[2]}))
  elif [[ $value =~ ^[0-9]{1,9}$ ]]; then
    range_lo=$((10#$value)) range_hi=$range_lo
  else
    fail "$name '$value': must be N or A-B (whole numbers, A <= B <= $max)"
  fi
  [ "$range_lo" -le "$range_hi" ] && [ "$range_hi" -le "$max" ] ||
    fail "$name '$value': must be N or A-B (whole numbers, A <= B <= $max)"
}

[ -n "$out" ] || fail "--out DIR is required (where the PKI goes)"
[ -n "$robots" ] || fail "--robots IDS is required (N or A-B: the robot ids that get an identity)"
parse_range --robots "$robots" 4294967295
robot_lo=$range_lo robot_hi=$range_hi
[ $((robot_hi - robot_lo)) -lt 100000 ] || fail "--robots '$robots': at most 100000 identities at a time"
parse_range --domains "$domains" 230
domain_lo=$range_lo domain_hi=$range_hi
[[ $prefix =~ ^[A-Za-z0-9_]+(/[A-Za-z0-9_]+)*$ ]] && [ ${#prefix} -le 64 ] ||
  fail "--prefix '$prefix': must be 1..64 characters of letters, digits and _, with single / between parts"
[[ $days =~ ^[0-9]{1,5}$ ]] && [ "$((10#$days))" -ge 1 ] || fail "--days '$days': must be a whole number of days in 1..99999"
command -v openssl >/dev/null || fail "the openssl command is missing (apt-get install openssl)"
mkdir -p "$out" 2>/dev/null && [ -w "$out" ] || fail "--out '$out': cannot create or write that directory"
cd "$out"
umask 077

organisation="retreat"
country="ZZ"
subject_of() { echo "/C=$country/O=$organisation/CN=$1"; }
# The same name as the DDS documents write it: RFC 2253 order (Fast DDS compares it that way).
rfc2253_of() { echo "CN=$1,O=$organisation,C=$country"; }

new_key() { openssl genpkey -algorithm EC -pkeyopt ec_paramgen_curve:P-256 -out "$1" 2>/dev/null; }

if [ ! -s ca.key ] || [ ! -s ca.pem ]; then
  new_key ca.key
  openssl req -x509 -new -key ca.key -sha256 -days "$days" -subj "$(subject_of "retreat swarm CA")" \
    -out ca.pem 2>/dev/null
  echo "$program: new CA in $out/ca.pem"
fi

# identity NAME: a key and a certificate signed by the CA (kept when the CA verifies it).
identity() {
  local name=$1
  mkdir -p "$name"
  if [ -s "$name/key.pem" ] && [ -s "$name/cert.pem" ] &&
     openssl verify -CAfile ca.pem "$name/cert.pem" >/dev/null 2>&1; then
    return
  fi
  new_key "$name/key.pem"
  openssl req -new -key "$name/key.pem" -subj "$(subject_of "$name")" -out "$name/cert.csr" 2>/dev/null
  openssl x509 -req -in "$name/cert.csr" -CA ca.pem -CAkey ca.key -set_serial "0x$(openssl rand -hex 8)" \
    -sha256 -days "$days" -out "$name/cert.pem" 2>/dev/null
  rm -f "$name/cert.csr"
}

# sign_if_changed XML TEXT: writes XML (and XML's .p7s) when TEXT differs from it.
sign_if_changed() {
  local xml=$1 text=$2 p7s=${1%.xml}.p7s
  if [ -s "$p7s" ] && [ -f "$xml" ] && [ "$(cat "$xml")" = "$text" ]; then return; fi
  printf '%s\n' "$text" > "$xml"
  openssl smime -sign -text -in "$xml" -signer ca.pem -inkey ca.key -out "$p7s"
}

domains_xml="<domains><id_range><min>$domain_lo</min><max>$domain_hi</max></id_range></domains>"

# One topic rule: discovery and liveliness protected, read and write access controlled, every
# submessage signed (authenticated) and the payload encrypted.
topic_rule() {
  cat <<EOF
        <topic_rule>
          <topic_expression>$1</topic_expression>
          <enable_discovery_protection>true</enable_discovery_protection>
          <enable_liveliness_protection>true</enable_liveliness_protection>
          <enable_read_access_control>true</enable_read_access_control>
          <enable_write_access_control>true</enable_write_access_control>
          <metadata_protection_kind>SIGN</metadata_protection_kind>
          <data_protection_kind>ENCRYPT</data_protection_kind>
        </topic_rule>
EOF
}

# No whole-message (RTPS) protection: every submessage is already signed (metadata) and every
# payload encrypted by the topic rules, and discovery and liveliness are encrypted. Fast DDS 2.9
# as packaged (statistics compiled in, assertions on) aborts when a protected RTPS message comes
# out of encoding within a statistics submessage of its buffer's size: the receiver-specific
# MACs grow the message after the room for statistics was reserved (later Fast DDS reserves
# room for the encoding, `calculate_extra_size_for_rtps_message`). Seen in about one secure run
# in ten (docs/security.md, "The files").
governance=$(cat <<EOF
<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_governance.xsd">
  <domain_access_rules>
    <domain_rule>
      $domains_xml
      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>
      <enable_join_access_control>true</enable_join_access_control>
      <discovery_protection_kind>ENCRYPT</discovery_protection_kind>
      <liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>
      <rtps_protection_kind>NONE</rtps_protection_kind>
      <topic_access_rules>
$(topic_rule "$prefix/robot_*/proximity")
$(topic_rule "$prefix/robot_*/decision")
$(topic_rule "$prefix/robot_*/plan")
$(topic_rule "$prefix/robot_*/tracked_pose")
$(topic_rule "$prefix/agent_status")
$(topic_rule "$prefix/arena_telemetry")
$(topic_rule "$prefix/poses")
      </topic_access_rules>
    </domain_rule>
  </domain_access_rules>
</dds>
EOF
)
sign_if_changed governance.xml "$governance"

# rule_xml publish|subscribe TOPICS...: the element, or nothing for no topics (Fast DDS refuses
# an empty <topics>).
rule_xml() {
  local kind=$1 t; shift
  [ $# -gt 0 ] || return 0
  printf '<%s><topics>' "$kind"
  for t in "$@"; do printf '<topic>%s</topic>' "$t"; done
  printf '</topics></%s>' "$kind"
}

# permissions NAME "PUBLISHED TOPICS" "SUBSCRIBED TOPICS": the identity's grant; everything
# else is denied. Valid as long as its certificate.
permissions() {
  local name=$1 publish=$2 subscribe=$3 start end
  start=$(openssl x509 -in "$name/cert.pem" -noout -startdate | cut -d= -f2)
  end=$(openssl x509 -in "$name/cert.pem" -noout -enddate | cut -d= -f2)
  # shellcheck disable=SC2086  # the topic lists split on spaces on purpose
  sign_if_changed "$name/permissions.xml" "$(cat <<EOF
<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_permissions.xsd">
  <permissions>
    <grant name="$name">
      <subject_name>$(rfc2253_of "$name")</subject_name>
      <validity>
        <not_before>$(date -u -d "$start" +%Y-%m-%dT%H:%M:%S)</not_before>
        <not_after>$(date -u -d "$end" +%Y-%m-%dT%H:%M:%S)</not_after>
      </validity>
      <allow_rule>
        $domains_xml
        $(rule_xml publish $publish)
        $(rule_xml subscribe $subscribe)
      </allow_rule>
      <default>DENY</default>
    </grant>
  </permissions>
</dds>
EOF
)"
}

for ((r = robot_lo; r <= robot_hi; ++r)); do
  identity "robot_$r"
  permissions "robot_$r" "$prefix/robot_$r/decision $prefix/robot_$r/plan $prefix/agent_status" \
    "$prefix/robot_$r/proximity"
  # The real robot r's own link (docs/robot-guide.md): its frames or tracked pose, its decisions.
  identity "driver_$r"
  permissions "driver_$r" "$prefix/robot_$r/proximity $prefix/robot_$r/tracked_pose" "$prefix/robot_$r/decision"
done
identity arena
permissions arena "$prefix/robot_*/proximity $prefix/arena_telemetry $prefix/poses" \
  "$prefix/robot_*/decision $prefix/robot_*/plan $prefix/robot_*/tracked_pose"
identity bridge
permissions bridge "" "$prefix/arena_telemetry $prefix/poses $prefix/agent_status"
identity recorder
permissions recorder "" "$prefix/robot_*/proximity $prefix/robot_*/decision $prefix/robot_*/plan \
$prefix/robot_*/tracked_pose $prefix/arena_telemetry $prefix/poses $prefix/agent_status"

echo "$program: $out: CA, robot_$robot_lo..robot_$robot_hi, driver_$robot_lo..driver_$robot_hi, arena, bridge, recorder (prefix $prefix, domains $domain_lo-$domain_hi)"
