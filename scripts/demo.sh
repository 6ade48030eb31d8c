#!/usr/bin/env bash
# The demo command (README): builds and starts the nodes of a launch config
# (default launch-configs/demo.yaml) and a Cyclone DDS peer that prints what it sees of them.
# Runs inside a private network namespace (loopback only) unless --host-network is given,
# for use with your own ROS 2 tools on this machine (participants stay loopback-only then).
# --no-driver: the peer only prints; the machine does only what you command (README).
#   scripts/demo.sh [CONFIG.yaml] [--duration SECONDS] [--host-network] [--no-driver]
set -euo pipefail
cd "$(dirname "$0")/.."
config=launch-configs/demo.yaml; duration=""; wrap=scripts/netns-run; driver=""
while [ $# -gt 0 ]; do
  case "$1" in
    --duration) duration="$2"; shift 2;;
    --host-network) wrap=""; shift;;
    --no-driver) driver="--no-driver"; shift;;
    -h|--help) sed -n 2,8p "$0"; exit 0;;
    *) config="$1"; shift;;
  esac
done
scripts/setup.sh
cargo build --release --quiet -p motion_launch
export ROS_DOMAIN_ID=${ROS_DOMAIN_ID:-0}
export RMW_IMPLEMENTATION=${RMW_IMPLEMENTATION:-rmw_cyclonedds_cpp}
exec $wrap python3 tests/peer/monitor.py --launch target/release/motion_launch --config "$config" ${duration:+--duration "$duration"} $driver
