#!/usr/bin/env bash
# The demo command (README): builds and starts the nodes of a launch config
# (default launch-configs/demo.yaml) and a Cyclone DDS peer that prints what it sees of them.
# Prints the live view's address (the page and the Foxglove feed, launch key `live`).
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
# The live view (the config's `live` key): the launcher prints its addresses. In the private
# namespace they are the namespace's loopback; tests/peer/web_bridge.py brings those ports to
# this machine's 127.0.0.1 (TCP only, through Unix sockets), so a browser here opens them.
bridge=""
ports=$(python3 -c 'import sys, yaml
l = (yaml.safe_load(open(sys.argv[1])) or {}).get("live")
if l is True: l = {}
if isinstance(l, dict) and l.get("enabled", True):
    print("%s,%s" % (l.get("page_port", 8080), l.get("port", 8765)))' "$config")
if [ -n "$wrap" ] && [ -n "$ports" ]; then
  dir=$(mktemp -d)
  python3 tests/peer/web_bridge.py outside --dir "$dir" --ports "$ports" &
  outside=$!
  trap 'kill $outside 2>/dev/null; rm -rf "$dir"' EXIT
  bridge="--web-bridge $dir:$ports"
  echo "Live view: http://127.0.0.1:${ports%%,*}/  (Foxglove / Lichtblick: ws://127.0.0.1:${ports##*,})"
fi
$wrap python3 tests/peer/monitor.py --launch target/release/motion_launch --config "$config" ${duration:+--duration "$duration"} $driver $bridge
