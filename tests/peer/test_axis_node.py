"""axis_node driven by an independent DDS implementation (cyclonedds), as rclpy would.

Starts `motion_launch` on a launch config in a subprocess (RMW_IMPLEMENTATION=rmw_cyclonedds_cpp,
so the node serves the Cyclone request/reply mapping), then: discovers the node, reads
~/axis_states and /diagnostics, calls services (accepted and rejected with error ids), runs an
action to its result and cancels one. Run inside scripts/netns-run; see tests/tests/python_peer.rs.

Usage: python3 test_axis_node.py  (env MOTION_LAUNCH_BIN, MOTION_LAUNCH_CONFIG, ROS_DOMAIN_ID)
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
    cycle_period: 0.001
    state_rate: 50
    axes:
      x:
        max_velocity: 1000.0
        acceleration: 10000.0
        deceleration: 10000.0
        jerk: 100000.0
"""

UNKNOWN_OBJECT = 0x7F01
ENUM_OUT_OF_RANGE = 0x7F03


class AxisNodeOverCyclone(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.proc, cls.domain = ros2_peer.launch(CONFIG, "axis")
        cls.peer = ros2_peer.Peer(cls.domain)

    @classmethod
    def tearDownClass(cls):
        ros2_peer.stop(cls.proc)

    def test_1_state_topic_and_diagnostics(self):
        states = self.peer.subscribe("/axis_node/axis_states", "motion_msgs/msg/AxisStateArray")
        s = self.peer.take_one(states, timeout=20)
        self.assertEqual([a.name for a in s.axes], ["x"])
        diag = self.peer.subscribe("/diagnostics", "diagnostic_msgs/msg/DiagnosticArray")
        d = self.peer.take_one(diag, timeout=20)
        st = d.status[0]
        self.assertEqual(st.name, "axis_node: cycle")
        keys = {kv.key: kv.value for kv in st.values}
        self.assertEqual(keys["period_us"], "1000.0")
        self.assertGreater(int(keys["cycles"]), 0)
        for k in ("jitter_p99_us", "exec_max_us", "overruns"):
            self.assertIn(k, keys)

    def test_2_services_and_action(self):
        power = self.peer.service("/axis_node/power", "motion_msgs/srv/Power")
        power.wait_for_server()
        r = power.call(axis="x", enable=True, enable_positive=True, enable_negative=True, override=100.0)
        self.assertTrue(r.accepted, r.message)

        move = self.peer.service("/axis_node/move_absolute", "motion_msgs/srv/MoveAbsolute")
        move.wait_for_server()
        r = move.call(axis="nope", position=1.0, velocity=10.0)
        self.assertFalse(r.accepted)
        self.assertEqual(r.error_id, UNKNOWN_OBJECT)
        self.assertIn("nope", r.message)
        r = move.call(axis="x", position=1.0, velocity=10.0, buffer_mode=7)
        self.assertFalse(r.accepted)
        self.assertEqual(r.error_id, ENUM_OUT_OF_RANGE)
        r = move.call(axis="x", position=float("inf"), velocity=10.0)
        self.assertFalse(r.accepted)
        self.assertNotEqual(r.error_id, 0)

        act = self.peer.action("/axis_node/move_absolute", "motion_msgs/action/MoveAbsolute")
        act.wait_for_server()
        gid, accepted = act.send(axis="x", position=20.0, velocity=200.0)
        self.assertTrue(accepted)
        status, result = act.result(gid, timeout=30)
        self.assertEqual(status, ros2_peer.STATUS_SUCCEEDED, result)
        self.assertTrue(result.done)
        self.assertAlmostEqual(result.position, 20.0, places=6)

    def test_3_cancel(self):
        act = self.peer.action("/axis_node/move_velocity", "motion_msgs/action/MoveVelocity")
        act.wait_for_server()
        # A slow ramp: the goal would succeed at InVelocity; it is canceled while ramping.
        gid, accepted = act.send(axis="x", velocity=50.0, acceleration=1.0, direction=1)
        self.assertTrue(accepted)
        fb = act.feedback_for(gid, timeout=10)
        self.assertTrue(fb.busy)
        time.sleep(0.3)
        c = act.cancel_goal(gid)
        self.assertEqual(len(c.goals_canceling), 1)
        status, result = act.result(gid, timeout=30)
        self.assertEqual(status, ros2_peer.STATUS_CANCELED, result)
        self.assertTrue(result.command_aborted)


if __name__ == "__main__":
    unittest.main(verbosity=2)
