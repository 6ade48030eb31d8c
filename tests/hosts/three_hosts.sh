#!/usr/bin/env bash
# Three "machines" on one private subnet (issue 13 §4): network namespaces joined by veth
# pairs on a bridge, each with only its own address (10.77.0.1-3/24) besides loopback.
# Run inside scripts/netns-run (the hub namespace, which holds the bridge); every packet stays
# among the namespaces this script made (network rule).
# Usage: three_hosts.sh CMD_A -- CMD_B -- CMD_C   (each host runs its command; the exit code
# is host C's, A and B are stopped after C ends). ROS_AUTOMATIC_DISCOVERY_RANGE=SUBNET is set
# for all three.
set -euo pipefail
[ "${MOTION_IN_NETNS:-}" = 1 ] || { echo "run inside scripts/netns-run" >&2; exit 2; }
# The bridge lives in a hub namespace of its own, gone when this script ends.
if [ -z "${THREE_HOSTS_HUB:-}" ]; then exec unshare --net env THREE_HOSTS_HUB=1 "$0" "$@"; fi
cmds=(); cur=()
for a in "$@"; do
  if [ "$a" = -- ]; then cmds+=("$(printf '%q ' "${cur[@]}")"); cur=(); else cur+=("$a"); fi
done
cmds+=("$(printf '%q ' "${cur[@]}")")
[ ${#cmds[@]} = 3 ] || { echo "usage: $0 CMD_A -- CMD_B -- CMD_C" >&2; exit 2; }

ip link add br0 type bridge
ip link set br0 up
export ROS_AUTOMATIC_DISCOVERY_RANGE=SUBNET
pids=()
for i in 0 1 2; do
  addr="10.77.0.$((i + 1))"
  # The host waits for its interface, configures it, then runs its command.
  unshare --net -- bash -c '
    for _ in $(seq 200); do ip link show eth0 >/dev/null 2>&1 && break; sleep 0.05; done
    ip link set lo up
    ip addr add '"$addr"'/24 dev eth0
    ip link set eth0 multicast on
    ip link set eth0 up
    ip route add 224.0.0.0/4 dev eth0
    export MOTION_HOST_ADDR='"$addr"'
    eval "exec $0"' "${cmds[$i]}" &
  pids+=($!)
  # The child has its own namespace only once unshare(2) ran.
  for _ in $(seq 200); do
    [ "$(readlink "/proc/${pids[$i]}/ns/net")" != "$(readlink /proc/self/ns/net)" ] && break
    sleep 0.01
  done
  ip link add "veth$i" type veth peer name eth0 netns "${pids[$i]}"
  ip link set "veth$i" master br0
  ip link set "veth$i" up
done
set +e
wait "${pids[2]}"
rc=$?
kill -TERM "${pids[0]}" "${pids[1]}" 2>/dev/null
wait "${pids[0]}" "${pids[1]}" 2>/dev/null
exit $rc
