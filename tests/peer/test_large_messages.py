"""Large messages between our node and an independent DDS (cyclonedds), issue 12 §1.

A state topic of about 1 MB (`/big/axis_states` of 4700 axes) and service replies of about
64 kB and 256 kB (`~/submit_batch` with 1300 and 5000 refused orders, each refusal with its
message) cross between motion_launch and the Python peer whole; the node keeps answering
afterwards. tests/tests/python_peer.rs runs this on a clean link and again inside a nested
namespace whose nftables drops 5 % of UDP packets (retransmission and fragment repair).

Usage: python3 test_large_messages.py  (env MOTION_LAUNCH_BIN, ROS_DOMAIN_ID; inside netns-run)
"""

import gc
import json
import os
import sys
import time
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ros2_peer  # noqa: E402

AXES = 4700
AXIS = "{max_velocity: 1000.0, acceleration: 10000.0, deceleration: 10000.0, jerk: 100000.0}"
# Two nodes, each with its own participant: `big` publishes the 1 MB state, `axis_node`
# serves the long replies.
CONFIG = ("nodes:\n  - kind: axis_node\n    name: big\n    cycle_period: 0.02\n    state_rate: 1\n    axes:\n"
          + "".join(f"      a{k}: {AXIS}\n" for k in range(AXES))
          + f"  - kind: axis_node\n    axes:\n      a0: {AXIS}\n")

ORDER = json.dumps({"MoveAbsolute": {
    "axis": "a0", "position": 1.0, "velocity": 10.0, "acceleration": 0.0, "deceleration": 0.0,
    "jerk": 0.0, "buffer_mode": "Aborting",
    "options": {"enable_blending_position": False, "blending_position": 0.0,
                "ignore_position_monitoring": False, "enable_stop_position_monitoring": False}}})


class LargeMessages(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.proc, cls.domain = ros2_peer.launch(CONFIG, "large", env={"RUST_LOG": "error"})

    @classmethod
    def tearDownClass(cls):
        ros2_peer.stop(cls.proc)

    def test_1_state_topic_of_1_mb(self):
        # A participant of its own, gone at the end: a subscriber that keeps 1 MB samples
        # unread would load the (lossy) link during the next test.
        peer = ros2_peer.Peer(self.domain)
        states = peer.subscribe("/big/axis_states", "motion_msgs/msg/AxisStateArray")
        s = peer.take_one(states, timeout=60.0)
        self.assertEqual(len(s.axes), AXES)
        self.assertEqual([a.name for a in s.axes[:3]], ["a0", "a1", "a2"])
        size = len(s.serialize())
        print(f"axis_states sample: {size} bytes", file=sys.stderr)
        self.assertGreater(size, 1_000_000)
        del states, peer
        gc.collect()

    def test_2_long_service_replies(self):
        peer = ros2_peer.Peer(self.domain)
        sb = peer.service("/axis_node/submit_batch", "motion_msgs/srv/SubmitBatch")
        sb.wait_for_server(timeout=60.0)
        for n, at_least in ((1300, 64_000), (5000, 256_000)):
            r = sb.call(timeout=60.0, orders=[ORDER] * n)
            self.assertTrue(r.accepted, r.message)
            self.assertEqual(len(r.order_accepted), n)
            self.assertFalse(any(r.order_accepted))
            self.assertTrue(all(e != 0 for e in r.error_ids))
            size = len(r.serialize())
            print(f"submit_batch reply of {n} orders: {size} bytes", file=sys.stderr)
            self.assertGreater(size, at_least)
        # Still serving.
        rs = peer.service("/axis_node/read_status", "motion_msgs/srv/ReadStatus")
        rs.wait_for_server()
        self.assertTrue(rs.call(axis="a0").accepted)


if __name__ == "__main__":
    unittest.main(verbosity=2)
