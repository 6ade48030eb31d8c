"""planar_node driven by an independent DDS implementation (cyclonedds), as rclpy would.

Starts `motion_launch` on a launch config in a subprocess (RMW_IMPLEMENTATION=rmw_cyclonedds_cpp,
so the node serves the Cyclone request/reply mapping), then: discovers the node, reads ~/state,
~/mover_poses and ~/markers, calls services (accepted and rejected with error ids), runs a
MoveToPosition action to its result and cancels one (cancel = the mover's Halt).
Run inside scripts/netns-run; see tests/tests/python_peer.rs.

Usage: python3 test_planar_node.py  (env MOTION_LAUNCH_BIN, ROS_DOMAIN_ID)
"""

import os
import sys
import time
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ros2_peer  # noqa: E402

CONFIG = """
nodes:
  - kind: planar_node
    cycle_period: 0.001
    state_rate: 50
    coordinate_systems: [0x01010060]
    parts:
      - name: table
        oid: 0x01010020
        tiles: [[0, 0], [240, 0], [480, 0], [0, 240], [240, 240], [480, 240]]
        positions: {1: {cs: 0x01010060, x: 0, y: 0}}
    environment: {name: env, processing_unit_oid: 0x01010002}
    movers:
      - {name: m1, initial_pose: {x: 120, y: 120}}
      - {name: m2, initial_pose: {x: 600, y: 360}, width: 210}
    groups: [{name: g1}]
"""

UNKNOWN_OBJECT = 0x7F01
NOT_FINITE = 0x7F02
ENUM_OUT_OF_RANGE = 0x7F03
E_INVALID_STATE = 0x4A01
STATE_DISABLED = 1
STATE_ENABLED = 3
MARKER_CUBE = 1


class PlanarNodeOverCyclone(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.proc, cls.domain = ros2_peer.launch(CONFIG, "planar")
        cls.peer = ros2_peer.Peer(cls.domain)
        cls.states = cls.peer.subscribe("/planar_node/state", "motion_msgs/msg/PlanarState")

    @classmethod
    def tearDownClass(cls):
        ros2_peer.stop(cls.proc)

    def wait_state(self, pred, timeout=20.0):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            s = self.peer.take_one(self.states, timeout=max(0.1, deadline - time.monotonic()))
            if pred(s):
                return s
        raise TimeoutError("state condition not reached")

    def enable_m1(self):
        enable = self.peer.service("/planar_node/mover_enable", "motion_msgs/srv/MoverEnable")
        enable.wait_for_server()
        r = enable.call(mover="m1")
        self.assertTrue(r.accepted, r.message)
        self.wait_state(lambda s: s.movers[0].state == STATE_ENABLED)
        return enable

    def test_1_topics(self):
        s = self.peer.take_one(self.states, timeout=20)
        self.assertEqual([m.name for m in s.movers], ["m1", "m2"])
        self.assertEqual(s.environment.stator_count, 6)
        self.assertEqual((s.movers[1].x, s.movers[1].y), (600.0, 360.0))
        poses = self.peer.subscribe("/planar_node/mover_poses", "geometry_msgs/msg/PoseArray")
        p = self.peer.take_one(poses, timeout=20)
        self.assertEqual(p.header.frame_id, "planar_env")
        self.assertAlmostEqual(p.poses[1].position.x, 0.6, places=9)
        markers = self.peer.subscribe("/planar_node/markers", "visualization_msgs/msg/MarkerArray")
        m = self.peer.take_one(markers, timeout=20)
        stators = [k for k in m.markers if k.ns == "stators"][0]
        self.assertEqual(len(stators.points), 6)
        m2 = [k for k in m.markers if k.ns == "movers" and k.id == 1][0]
        self.assertEqual(m2.type, MARKER_CUBE)
        self.assertAlmostEqual(m2.scale.x, 0.21, places=9)

    def test_2_services_and_action(self):
        enable = self.enable_m1()
        r = enable.call(mover="nope")
        self.assertFalse(r.accepted)
        self.assertEqual(r.error_id, UNKNOWN_OBJECT)
        self.assertIn("nope", r.message)

        move = self.peer.service("/planar_node/mover_move_to_position", "motion_msgs/srv/MoverMoveToPosition")
        move.wait_for_server()
        r = move.call(mover="m2", x=500.0, y=360.0, use_orientation=True)
        self.assertFalse(r.accepted)
        self.assertEqual(r.error_id, E_INVALID_STATE, r.message)
        r = move.call(mover="m1", x=float("inf"), y=100.0, use_orientation=True)
        self.assertFalse(r.accepted)
        self.assertEqual(r.error_id, NOT_FINITE, r.message)
        move_c = self.peer.service("/planar_node/mover_move_c", "motion_msgs/srv/MoverMoveC")
        move_c.wait_for_server()
        r = move_c.call(mover="m1", target_position=5.0, direction=9)
        self.assertFalse(r.accepted)
        self.assertEqual(r.error_id, ENUM_OUT_OF_RANGE, r.message)

        act = self.peer.action("/planar_node/mover_move_to_position", "motion_msgs/action/MoverMoveToPosition")
        act.wait_for_server()
        gid, accepted = act.send(mover="m1", x=300.0, y=200.0, c=10.0, use_orientation=True)
        self.assertTrue(accepted)
        status, result = act.result(gid, timeout=30)
        self.assertEqual(status, ros2_peer.STATUS_SUCCEEDED, result)
        self.assertTrue(result.done)
        # Spec tolerance ±0.1 mm, ±0.01° (xplanar.md §7).
        self.assertLess(abs(result.x - 300.0), 0.1)
        self.assertLess(abs(result.y - 200.0), 0.1)
        self.assertLess(abs(result.c - 10.0), 0.01)

    def test_3_cancel(self):
        self.enable_m1()  # already Enabled after test_2: Enable is then done at once
        act = self.peer.action("/planar_node/mover_move_to_position", "motion_msgs/action/MoverMoveToPosition")
        act.wait_for_server()
        gid, accepted = act.send(mover="m1", x=120.0, y=420.0, velocity=50.0, use_orientation=False)
        self.assertTrue(accepted)
        fb = act.feedback_for(gid, timeout=10)
        self.assertTrue(fb.busy)
        time.sleep(0.5)
        c = act.cancel_goal(gid)
        self.assertEqual(len(c.goals_canceling), 1)
        status, result = act.result(gid, timeout=30)
        self.assertEqual(status, ros2_peer.STATUS_CANCELED, result)
        self.assertTrue(result.command_aborted)
        self.assertFalse(result.done)
        self.assertLess(result.y, 410.0)


if __name__ == "__main__":
    unittest.main(verbosity=2)
