"""An hour under load (issue 33 §3): the demo's three nodes at 1 kHz and a mixed client load,
with the node process's resources reported every minute. Not part of the test command (an
hour); run it with scripts/soak.sh.

The load, all from cyclonedds participants (Cyclone mapping, as rmw_cyclonedds):
- service calls: ten a second to axis_node's ~/read_status, one to pickplace_node's
  ~/get_params;
- MoveAbsolute goals on axis x back and forth, each to its result; MoveVelocity goals on y
  canceled while they ramp (CANCELED asserted);
- subscribers joining and leaving (a reader of ~/axis_states or the planar ~/state made,
  one sample taken, deleted) every second;
- one client process (this script with --client) with its own participant calling and
  subscribing, killed with SIGKILL and started again every minute.
Every minute: the node process's RSS, open files, threads, and the counts so far: calls
answered / lost, goals with and without a result, cancels, subscriber rounds, client restarts.
At the end the verdict after warm-up (the first WARMUP minutes): RSS within +2 MB, open files
and threads constant, no lost request, every goal with a result; exit 1 otherwise.

Usage: scripts/soak.sh [MINUTES]   (python3 tests/peer/soak.py --minutes N inside netns-run)
"""

import argparse
import os
import signal
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ros2_peer  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
WARMUP = 5  # [min]


def resources(pid):
    with open(f"/proc/{pid}/status") as f:
        rss_kb = next(int(line.split()[1]) for line in f if line.startswith("VmRSS:"))
    fds = len(os.listdir(f"/proc/{pid}/fd"))
    threads = len(os.listdir(f"/proc/{pid}/task"))
    return rss_kb, fds, threads


def client_main(domain):
    """The client that is killed every minute: calls and a subscription until killed."""
    peer = ros2_peer.Peer(domain)
    status = peer.service("/axis_node/read_status", "motion_msgs/srv/ReadStatus")
    states = peer.subscribe("/axis_node/axis_states", "motion_msgs/msg/AxisStateArray")
    status.wait_for_server()
    while True:
        status.call(timeout=10.0, axis="x")
        states.take(N=100)
        time.sleep(0.05)


class Load:
    def __init__(self, peer):
        self.peer = peer
        self.counts = dict(calls=0, lost=0, goals=0, no_result=0, cancels=0, subscribers=0,
                           restarts=0)
        self.status = peer.service("/axis_node/read_status", "motion_msgs/srv/ReadStatus")
        self.pp = peer.service("/pickplace_node/get_params", "motion_msgs/srv/PickPlaceGetParams")
        power = peer.service("/axis_node/power", "motion_msgs/srv/Power")
        for s in (self.status, power):
            s.wait_for_server(60.0)
        for axis in ("x", "y"):
            assert power.call(axis=axis, enable=True, enable_positive=True, enable_negative=True,
                              override=100.0).accepted
        self.move = peer.action("/axis_node/move_absolute", "motion_msgs/action/MoveAbsolute")
        self.vel = peer.action("/axis_node/move_velocity", "motion_msgs/action/MoveVelocity")
        self.move.wait_for_server(60.0)
        self.vel.wait_for_server(60.0)
        self.target = 0.0

    def call(self, client, **fields):
        try:
            client.call(timeout=5.0, **fields)
            self.counts["calls"] += 1
        except TimeoutError:
            self.counts["lost"] += 1

    def goal(self):
        self.target = 100.0 if self.target == 0.0 else 0.0
        gid, accepted = self.move.send(axis="x", position=self.target, velocity=500.0)
        assert accepted
        status, _ = self.move.result(gid, timeout=30.0)
        self.counts["goals"] += 1
        if status != ros2_peer.STATUS_SUCCEEDED:
            self.counts["no_result"] += 1

    def cancel(self):
        gid, accepted = self.vel.send(axis="y", velocity=50.0, acceleration=10.0, direction=1)
        assert accepted
        time.sleep(0.2)
        self.vel.cancel_goal(gid)
        status, _ = self.vel.result(gid, timeout=30.0)
        self.counts["cancels"] += 1
        if status != ros2_peer.STATUS_CANCELED:
            self.counts["no_result"] += 1
        # Back near 0 for the next one (a velocity move leaves y where it stopped).
        gid, _ = self.move.send(axis="y", position=0.0, velocity=500.0)
        self.move.result(gid, timeout=30.0)

    def subscriber(self, n):
        topic, kind = [("/axis_node/axis_states", "motion_msgs/msg/AxisStateArray"),
                       ("/planar_node/state", "motion_msgs/msg/PlanarState")][n % 2]
        reader = self.peer.subscribe(topic, kind)
        self.peer.take_one(reader, timeout=10.0)
        del reader  # the DDS reader goes with it
        self.counts["subscribers"] += 1

    def second(self, n):
        """One second of load."""
        end = time.monotonic() + 1.0
        for _ in range(10):
            self.call(self.status, axis="x")
        self.call(self.pp)
        self.subscriber(n)
        if n % 5 == 0:
            self.goal()
        if n % 15 == 7:
            self.cancel()
        time.sleep(max(0.0, end - time.monotonic()))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--minutes", type=float, default=60.0)
    ap.add_argument("--client", action="store_true")
    args = ap.parse_args()
    domain = int(os.environ.get("ROS_DOMAIN_ID", "77"))
    if args.client:
        client_main(domain)
        return
    with open(os.path.join(ROOT, "launch-configs/demo.yaml")) as f:
        config = f.read()
    launcher, domain = ros2_peer.launch(config, "soak", env={"RUST_LOG": "error"})
    pid = launcher.pid  # motion_launch runs the three nodes in its one process
    peer = ros2_peer.Peer(domain)
    load = Load(peer)
    spawn = lambda: subprocess.Popen([sys.executable, __file__, "--client"])  # noqa: E731
    client = spawn()
    rows = []
    print("minute  rss_kB  fds  threads  calls  lost  goals  no_result  cancels  subscribers"
          "  restarts", flush=True)
    start = time.monotonic()
    n = 0
    minute = 0
    try:
        while time.monotonic() - start < args.minutes * 60:
            load.second(n)
            n += 1
            if time.monotonic() - start >= (minute + 1) * 60:
                minute += 1
                client.send_signal(signal.SIGKILL)
                client.wait()
                client = spawn()
                load.counts["restarts"] += 1
                rss, fds, threads = resources(pid)
                rows.append((minute, rss, fds, threads))
                c = load.counts
                print(f"{minute:6d} {rss:7d} {fds:4d} {threads:8d} {c['calls']:6d} {c['lost']:5d}"
                      f" {c['goals']:6d} {c['no_result']:10d} {c['cancels']:8d}"
                      f" {c['subscribers']:12d} {c['restarts']:9d}", flush=True)
    finally:
        client.kill()
        ros2_peer.stop(launcher)
    after = [r for r in rows if r[0] >= WARMUP]
    ok = True
    if after:
        base = after[0]
        grow = max(r[1] for r in after) - base[1]
        fds = {r[2] for r in after}
        threads = {r[3] for r in after}
        print(f"after warm-up (minute {WARMUP} on): RSS {base[1]} kB, growth {grow} kB; "
              f"open files {sorted(fds)}; threads {sorted(threads)}")
        ok = grow <= 2048 and len(fds) == 1 and len(threads) == 1
    c = load.counts
    ok = ok and c["lost"] == 0 and c["no_result"] == 0
    print(f"lost requests {c['lost']}, goals without their result {c['no_result']}: "
          f"{'PASS' if ok else 'FAIL'}")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
