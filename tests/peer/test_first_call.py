"""The first call of a fresh client is answered at once (issue 12 §4), with cyclonedds.

`ros2 service call` and many scripts make a fresh client for every call and send the request
as soon as the service is matched. Each trial here makes a fresh client (its own request
writer and reply reader), waits only until both directions are matched as rmw does, sends at
once, and measures the reply: every one within 100 ms. The same on fresh participants (a new
process each time, as the CLI). And ten thousand clients dropped at once leave the peer and the
node working (a race inside the Cyclone library; see ros2_peer.topic).

Usage: python3 test_first_call.py  (env MOTION_LAUNCH_BIN, ROS_DOMAIN_ID; inside netns-run)
"""

import os
import sys
import time
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ros2_peer  # noqa: E402

CONFIG = """
nodes:
  - kind: axis_node
    axes:
      x: {max_velocity: 1000.0, acceleration: 10000.0, deceleration: 10000.0, jerk: 100000.0}
"""

# 500 fresh clients take about 2 s.
TRIALS = int(os.environ.get("FIRST_CALL_TRIALS", "500"))
PARTICIPANT_TRIALS = int(os.environ.get("FIRST_CALL_PARTICIPANTS", "20"))
DROPPED = int(os.environ.get("FIRST_CALL_DROPPED", "10000"))
LIMIT = 0.100  # [s]


def matched(client, timeout=20.0):
    """Both directions matched, nothing more (what rmw's service_is_ready checks)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if client.writer.get_matched_subscriptions() and client.reader.get_matched_publications():
            return
        time.sleep(0.001)
    raise TimeoutError("no server")


def first_call(peer):
    c = ros2_peer.ServiceClient(peer, "/axis_node/read_status", "motion_msgs/srv/ReadStatus")
    matched(c)
    t0 = time.monotonic()
    r = c.call(timeout=10.0, axis="x")
    took = time.monotonic() - t0
    assert r.accepted, r
    return took


class FirstCall(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.proc, cls.domain = ros2_peer.launch(CONFIG, "first", env={"RUST_LOG": "error"})
        cls.peer = ros2_peer.Peer(cls.domain)
        # The node is up once a first (unmeasured) call is answered.
        c = ros2_peer.ServiceClient(cls.peer, "/axis_node/read_status", "motion_msgs/srv/ReadStatus")
        c.wait_for_server()
        c.call(timeout=20.0, axis="x")

    @classmethod
    def tearDownClass(cls):
        ros2_peer.stop(cls.proc)

    def report(self, what, times):
        times = sorted(times)
        slow = [t for t in times if t > LIMIT]
        print(f"{what}: {len(times)} trials, p50 {times[len(times) // 2] * 1e3:.1f} ms, "
              f"max {times[-1] * 1e3:.1f} ms, over {LIMIT * 1e3:.0f} ms: {len(slow)}", file=sys.stderr)
        self.assertEqual(slow, [], f"{what}: first calls over {LIMIT * 1e3:.0f} ms")

    def test_fresh_client(self):
        self.report("fresh client", [first_call(self.peer) for _ in range(TRIALS)])

    def test_clients_dropped_at_once(self):
        """Clients made and dropped without a call, as fast as the library goes: before the
        peer kept its types (ros2_peer.topic), Cyclone's unlocked walk of its type tree met
        the gc thread freeing the dropped ones and crashed about once in 20 000 clients (4 of 4
        runs of 40 000; with the keeper 5 of 5 ran through). This test crashed 2 of 6 times then."""
        services = [("/axis_node/read_status", "motion_msgs/srv/ReadStatus"),
                    ("/axis_node/power", "motion_msgs/srv/Power")]
        for i in range(DROPPED):
            name, srv = services[i % 2]
            ros2_peer.ServiceClient(self.peer, name, srv)
            if i % 3 == 0:
                time.sleep(0.0015)  # now and then the gc thread runs while no topic is made
        self.assertLess(first_call(self.peer), LIMIT, "the node still answers at once")

    def test_fresh_participant(self):
        times = []
        for _ in range(PARTICIPANT_TRIALS):
            times.append(first_call(ros2_peer.Peer(self.domain)))
        self.report("fresh participant", times)


if __name__ == "__main__":
    unittest.main(verbosity=2)
