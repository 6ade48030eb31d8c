"""Network partitions heal for every client (issue 33 §1), with both real peers at once.

One launch config, two axis nodes: `/axis_cyc` (Cyclone mapping) driven by a cyclonedds
participant made here, and `/axis_fast` (Enhanced mapping) driven by real rclpy on Fast DDS
(tests/rclpy/partition_client.py, in the venv of scripts/ros-venv.sh). Every client is made
before the first partition and kept. A partition drops all UDP on `lo` inside this test's
own namespace (nftables), for a bounded time:
- 5 s (shorter than every lease: nobody is lost);
- 2 x the longest lease, our participants' 20 s (RustDDS patch 12: announced every 3 s):
  every participant loses every other, Cyclone's (10 s lease) and Fast DDS's (20 s) too.
Before each cut a MoveAbsolute goal is sent that ends inside the cut, and axis y moves at
constant velocity throughout. After the heal, each side measures the seconds until its old
service client, old subscription and old action client (the result of the goal accepted
before the cut, then a new goal) and a new service client are served; all within HEAL_LIMIT.
The motions do not notice: the goal ends at its position and y is where its velocity puts it.

Usage: python3 test_partition.py  (env MOTION_LAUNCH_BIN, ROS_DOMAIN_ID; inside netns-run;
MOTION_REQUIRE_RCLPY=1 makes a missing rclpy venv a failure instead of a Cyclone-only run)
"""

import json
import os
import subprocess
import sys
import time
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ros2_peer  # noqa: E402

CONFIG = """
nodes:
  - kind: axis_node
    name: axis_cyc
    service_mapping: cyclone
    state_rate: 50
    axes: &axes
      x: {max_velocity: 1000.0, acceleration: 10000.0, deceleration: 10000.0, jerk: 100000.0}
      y: {max_velocity: 1000.0, acceleration: 10000.0, deceleration: 10000.0, jerk: 100000.0}
  - kind: axis_node
    name: axis_fast
    service_mapping: enhanced
    state_rate: 50
    axes: *axes
"""

NODE = "/axis_cyc"
LEASE = 20.0  # [s] our participants' lease (vendor/README.md, RustDDS patch 12)
CUTS = [5.0, 2 * LEASE]
# [s] from the heal until every old and new client is served: the announcement periods
# decide it. A peer that lost us finds us at our next announcement (3 s); one that we lost
# but that kept us, at its own (Cyclone: about 8 s with its 10 s lease; Fast DDS: 3 s).
HEAL_LIMIT = 10.0
GOAL_VELOCITY = 100.0  # [u/s]
Y_VELOCITY = 10.0  # [u/s]
# How far y may be from where its velocity puts it: stamps are the cycles' times, positions
# their set values; 20 ms of cycle timing.
Y_TOLERANCE = Y_VELOCITY * 0.020
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def nft(*args):
    subprocess.run(["nft", *args], check=True)


def partition(seconds):
    """All UDP on this namespace's `lo` dropped for `seconds`, then let through again."""
    nft("add", "table", "inet", "partition")
    nft("add", "chain", "inet", "partition", "input", "{ type filter hook input priority 0; }")
    nft("add", "rule", "inet", "partition", "input", "meta", "l4proto", "udp", "drop")
    try:
        time.sleep(seconds)
    finally:
        nft("delete", "table", "inet", "partition")


def rclpy_client():
    """tests/rclpy/partition_client.py in the ROS venv, or None when there is none."""
    if not os.path.exists(os.path.join(ROOT, ".ros/venv/.stamp-motion_msgs")):
        if os.environ.get("MOTION_REQUIRE_RCLPY") == "1":
            raise RuntimeError("the rclpy venv is missing: run scripts/ros-venv.sh")
        print("rclpy side skipped: no .ros/venv", file=sys.stderr)
        return None
    return subprocess.Popen(
        ["bash", "-c", ". .ros/env.sh && exec python tests/rclpy/partition_client.py"],
        cwd=ROOT, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True,
        env=dict(os.environ, RMW_IMPLEMENTATION="rmw_fastrtps_cpp"))


class CycloneClients:
    """The Cyclone side: made once, kept through every partition."""

    def __init__(self, peer):
        self.peer = peer
        self.states = peer.subscribe(f"{NODE}/axis_states", "motion_msgs/msg/AxisStateArray")
        self.status = peer.service(f"{NODE}/read_status", "motion_msgs/srv/ReadStatus")
        self.action = peer.action(f"{NODE}/move_absolute", "motion_msgs/action/MoveAbsolute")
        self.goal = None
        self.goal_position = 0.0
        power = peer.service(f"{NODE}/power", "motion_msgs/srv/Power")
        power.wait_for_server()
        for axis in ("x", "y"):
            r = power.call(axis=axis, enable=True, enable_positive=True, enable_negative=True,
                           override=100.0)
            assert r.accepted, r.message
        mv = peer.service(f"{NODE}/move_velocity", "motion_msgs/srv/MoveVelocity")
        mv.wait_for_server()
        assert mv.call(axis="y", velocity=Y_VELOCITY, direction=1).accepted
        self.status.wait_for_server()
        self.action.wait_for_server()
        time.sleep(0.5)  # past y's ramp
        self.y_ref = self.y_sample()

    def y_sample(self, timeout=10.0):
        """(stamp [s], set position) of y in a state message sent from now on."""
        self.states.take(N=1000)
        s = self.peer.take_one(self.states, timeout)
        y = next(a for a in s.axes if a.name == "y")
        return s.header.stamp.sec + s.header.stamp.nanosec * 1e-9, y.set_pos

    def call(self, client, deadline, **fields):
        """Retried as a user would: a request written while unmatched is not delivered."""
        while time.monotonic() < deadline:
            try:
                return client.call(timeout=1.0, **fields)
            except TimeoutError:
                pass
        raise TimeoutError(f"{client.name}: not served again")

    def prepare(self, seconds):
        self.goal_position += GOAL_VELOCITY * seconds
        self.goal, accepted = self.action.send(axis="x", position=self.goal_position,
                                               velocity=GOAL_VELOCITY)
        assert accepted

    def check(self, heal):
        since = lambda: round(time.monotonic() - heal, 3)  # noqa: E731
        deadline = heal + 60.0
        out = {}
        self.y_sample(timeout=60.0)
        out["old_subscription"] = since()
        self.call(self.status, deadline, axis="x")
        out["old_service_client"] = since()
        resp = self.call(self.action.get_result, deadline, goal_id=self.goal)
        assert resp.status == ros2_peer.STATUS_SUCCEEDED, resp
        assert abs(resp.result.position - self.goal_position) < 1e-6, resp.result
        out["old_goal_result"] = since()
        fresh = self.peer.service(f"{NODE}/read_status", "motion_msgs/srv/ReadStatus")
        self.call(fresh, deadline, axis="x")
        out["new_service_client"] = since()
        self.goal_position -= 1.0
        gid, accepted = self.action.send(axis="x", position=self.goal_position,
                                         velocity=GOAL_VELOCITY)
        assert accepted
        status, result = self.action.result(gid, timeout=30.0)
        assert status == ros2_peer.STATUS_SUCCEEDED, result
        out["old_action_client_new_goal"] = since()
        stamp, pos = self.y_sample()
        out["y_error"] = pos - self.y_ref[1] - Y_VELOCITY * (stamp - self.y_ref[0])
        return out


class Partition(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.proc, cls.domain = ros2_peer.launch(CONFIG, "partition", env={"RUST_LOG": "error"})
        cls.fast = rclpy_client()
        cls.peer = ros2_peer.Peer(cls.domain)

    @classmethod
    def tearDownClass(cls):
        if cls.fast:
            cls.fast.stdin.write("quit\n")
            cls.fast.stdin.close()
            try:
                cls.fast.wait(timeout=10)
            except subprocess.TimeoutExpired:
                cls.fast.kill()
        ros2_peer.stop(cls.proc)

    def ask(self, line):
        self.fast.stdin.write(line + "\n")
        self.fast.stdin.flush()
        reply = self.fast.stdout.readline()
        self.assertTrue(reply, f"the rclpy client ended on {line!r}")
        return json.loads(reply)

    def test_partitions_heal_for_old_and_new_clients(self):
        cyc = CycloneClients(self.peer)
        if self.fast:
            self.assertEqual(self.ask_ready(), {"ready": True})
        for cut in CUTS:
            with self.subTest(cut=cut):
                cyc.prepare(cut / 2)
                if self.fast:
                    self.ask(f"prepare {cut / 2}")
                partition(cut)
                heal = time.monotonic()
                if self.fast:
                    self.fast.stdin.write("check\n")
                    self.fast.stdin.flush()
                sides = {"cyclone": cyc.check(heal)}
                if self.fast:
                    reply = self.fast.stdout.readline()
                    self.assertTrue(reply, "the rclpy client ended")
                    sides["rclpy"] = json.loads(reply)
                for side, figures in sides.items():
                    print(f"cut {cut:.0f} s, {side}: {figures}", file=sys.stderr)
                    for what, took in figures.items():
                        if what == "y_error":
                            self.assertLess(abs(took), Y_TOLERANCE, f"{side}: y moved off")
                        else:
                            self.assertLess(took, HEAL_LIMIT, f"{side}: {what} after {cut} s")

    def ask_ready(self):
        reply = self.fast.stdout.readline()
        self.assertTrue(reply, "the rclpy client ended before it was ready")
        return json.loads(reply)


if __name__ == "__main__":
    unittest.main(verbosity=2)
