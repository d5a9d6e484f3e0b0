#!/usr/bin/env bash
# Installs every Debian package specht needs to build, test and run, and nothing else.
# Non-interactive and idempotent: when everything is present it only checks and exits.
set -euo pipefail

PACKAGES=(
  # toolchain
  g++ cmake ninja-build pkg-config git
  ccache             # compiler cache: unchanged sources are not compiled again (CMakeLists.txt)
  clang libclang-rt-14-dev  # libFuzzer and its sanitizers (the fuzz preset, fuzz/)
  clang-format-14    # the format check (tests/docs/check_format.sh)
  # robotics libraries
  libmrpt-dev        # observations, rawlogs, ICP, occupancy grids, poses
  mrpt-common        # the built-in default rawlog and MRPT's demo datasets
  mrpt-apps          # rawlog-edit, icp-slam, graphslam-engine (comparisons in bench/)
  libceres-dev       # pose-graph optimisation
  liboctomap-dev     # 3D occupancy (OctoMap .bt) from stereo points
  libtorch-dev       # trajectory classifier (1D ResNet, CPU)
  libompl-dev        # Reeds-Shepp paths (hybrid A*), RRT baseline
  libopencv-dev      # images, PNG output, drawing
  libeigen3-dev
  libboost-dev       # Student's t distribution (Boost.Math) for the corrected t-test in cross-validation
  zlib1g-dev         # reading gzip CARMEN logs, AIS files
  libbz2-dev         # reading the Freiburg benchmark's .clf.bz2 logs
  libsqlite3-dev     # ROS 2 bags (rosbag2's sqlite3 storage, .db3)
  libfastcdr-dev     # eProsima Fast CDR: the CDR payloads of ROS 2 messages
  cyclonedds-dev cyclonedds-tools  # Eclipse Cyclone DDS and its idlc: the DDS transport (modules/net)
  libzstd-dev liblz4-dev  # MCAP chunk compression (zstd written; zstd and lz4 read)
  librosbag-storage-dev libsensor-msgs-dev libnav-msgs-dev libtf2-msgs-dev  # ROS 1 bags and their messages
  libshp-dev         # coastline shapefile (AIS distance to coast)
  libnanoflann-dev   # k-d tree (AIS nearest coast vertex / harbour)
  # configuration, CLI, output
  libyaml-cpp-dev    # parameter files
  libcli11-dev       # command line
  nlohmann-json3-dev # JSON reports
  libspdlog-dev libfmt-dev  # logging
  # tests and benchmarks
  libgtest-dev libgmock-dev libbenchmark-dev
  jq                 # reading JSON reports in bench scripts
  procps             # pkill: a test kills a node by its command line
)

# The independent readers the tests check specht's MCAP with (tests/npm: @mcap/core,
# @foxglove/rosmsg2-serialization), from the npm registry at the versions locked there.
npm_verifiers() {
  local dir
  dir="$(cd "$(dirname "$0")/.." && pwd)/tests/npm"
  if ! command -v npm > /dev/null; then
    echo "setup: npm not found: the MCAP conformance test will be skipped"
    return
  fi
  [[ -d "$dir/node_modules/@mcap/core" ]] || npm ci --prefix "$dir" --no-audit --no-fund --loglevel=error
}

missing=()
for p in "${PACKAGES[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done

if [[ ${#missing[@]} -eq 0 ]]; then
  echo "setup: all ${#PACKAGES[@]} packages present"
  npm_verifiers
  exit 0
fi

SUDO=""
if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
npm_verifiers
echo "setup: done"
