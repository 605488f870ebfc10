#!/usr/bin/env bash
# Installs every Debian package retreat needs to build, test and run.
# Idempotent: when everything is present it only checks and exits (no apt-get call).
# Usage: deploy/install-deps.sh            (as root on Debian 12)
set -euo pipefail

packages=(
  # toolchain
  build-essential cmake ninja-build pkg-config git
  # DDS: Fast DDS 2.9 + Fast CDR + generator, Cyclone DDS 0.10 C API + idlc
  libfastrtps-dev libfastcdr-dev fastddsgen cyclonedds-dev cyclonedds-tools
  # DDS Security: Cyclone's plugins (libdds_security_*.so) and openssl for the swarm PKI script
  libddsc0debian openssl
  # pure libraries and program plumbing
  libeigen3-dev libyaml-cpp-dev nlohmann-json3-dev libcli11-dev libssl-dev
  # the bridge's HTTP server (Boost.Beast and Boost.Asio, headers only); cpp-httplib is the
  # HTTP client of its tests
  libboost1.74-dev libcpp-httplib-dev
  # the launcher reads DDS profile files (XML) for its capacity check
  libtinyxml2-dev
  # recordings (MCAP): zstd-compressed chunks, zlib's CRC-32
  libzstd-dev zlib1g-dev
  # tests and benchmarks; the fuzzers (tests/fuzz) need Clang and its libFuzzer runtime
  libgtest-dev libgmock-dev googletest libbenchmark-dev clang libclang-rt-14-dev
  # the portability check of the test command: the pure core built with Clang and libc++
  libc++-14-dev libc++abi-14-dev
  # test helpers: network namespaces for multi-host tests, python for scripts
  iproute2 procps python3
  # packet loss between emulated hosts (tests/integration/multihost_test.cpp)
  nftables
  # the bridge's page: npm installs its front-end library (uPlot) at build time (npm ships
  # inside nodejs where nodejs is NodeSource's, which conflicts with Debian's npm package)
  nodejs $(command -v npm >/dev/null 2>&1 || echo npm)
  # the bridge's browser test: headless Chromium
  chromium
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

if [ "$(id -u)" -ne 0 ]; then
  echo "install-deps: missing packages (${missing[*]}); run this script as root" >&2
  exit 1
fi

echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}"
