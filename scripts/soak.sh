#!/usr/bin/env bash
# An hour under load (issue 33 §3; not in the test command): the demo's three nodes at 1 kHz
# under a mixed cyclonedds client load, one client killed and restarted every minute; prints
# the node process's RSS, open files and threads and the request/goal counts every minute and
# a verdict at the end (tests/peer/soak.py). Inside a private network namespace.
# Usage: scripts/soak.sh [MINUTES]   (default 60; MOTION_LAUNCH_BIN, default the release build)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
if [ -z "${MOTION_LAUNCH_BIN:-}" ]; then
  cargo build --release --quiet -p motion_launch
  export MOTION_LAUNCH_BIN=$PWD/target/release/motion_launch
fi
export ROS_DOMAIN_ID=${ROS_DOMAIN_ID:-211}
exec scripts/netns-run python3 tests/peer/soak.py --minutes "${1:-60}"
