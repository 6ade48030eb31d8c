"""pickplace_node driven by an independent DDS implementation (cyclonedds), as rclpy would.

Starts `motion_launch` on a launch config in a subprocess (RMW_IMPLEMENTATION=rmw_cyclonedds_cpp,
so the node serves the Cyclone request/reply mapping), then: reads ~/state, sets the enable
levels, gets rejections with their error ids, feeds a workpiece on a running belt and sees it on
~/workpieces and ~/events, runs a ~/pick_and_place goal to its result, cancels one, and reads
~/markers. Run inside scripts/netns-run; see tests/tests/python_peer.rs.

Usage: python3 test_pickplace_node.py  (env MOTION_LAUNCH_BIN, ROS_DOMAIN_ID)
"""

import os
import sys
import time
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ros2_peer  # noqa: E402

CONFIG = """
nodes:
  - kind: pickplace_node
    cycle_period: 0.001
    state_rate: 50
    initial_tcp: [0, 0, 200, 180, 0, 0, 0]
    belts:
      "1":
        initial_velocity: 100.0
        params: {conveyor_belt_origin: [400, 500, 100, 0, 0, 180], lower_sync_limit: 200, upper_sync_limit: 800, z_dist_belt: 50}
    params:
      path_vel: 500
      path_acc: 5000
      path_dec: 5000
      path_jerk: 1000000
      max_vel: [0, 0, 0, 0, 0, 0, 0]
      max_acc_dec: [0, 0, 0, 0, 0, 0, 0]
      max_jerk: [0, 0, 0, 0, 0, 0, 0]
"""

UNKNOWN_OBJECT = 0x7F01
NOT_FINITE = 0x7F02
ENUM_OUT_OF_RANGE = 0x7F03
INVALID_PARAMETER = 90001
STATE_DISABLED, STATE_READY = 0, 1
KIND_STATE_CHANGED, KIND_WORKPIECE = 0, 2
WORKPIECE_RECEIVED, WORKPIECE_VISIBLE = 0, 1


class PickPlaceNodeOverCyclone(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.proc, cls.domain = ros2_peer.launch(CONFIG, "pickplace")
        cls.peer = ros2_peer.Peer(cls.domain)
        cls.events = cls.peer.subscribe("/pickplace_node/events", "motion_msgs/msg/PickPlaceEvent")
        cls.event_buf = []

    @classmethod
    def tearDownClass(cls):
        ros2_peer.stop(cls.proc)

    def service(self, name, srv):
        s = self.peer.service(f"/pickplace_node/{name}", f"motion_msgs/srv/{srv}")
        s.wait_for_server()
        return s

    def latest_state(self, reader, timeout=10.0, pred=lambda s: True):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            for s in reader.take(N=100):
                if pred(s):
                    return s
            time.sleep(0.02)
        raise TimeoutError("no matching state sample")

    def event(self, pred, timeout=10.0):
        """The first event (oldest first) matching `pred`; later ones stay for the next call."""
        buf = type(self).event_buf
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            buf.extend(self.events.take(N=100))
            for i, e in enumerate(buf):
                if pred(e):
                    del buf[:i + 1]
                    return e
            time.sleep(0.01)
        raise TimeoutError("no matching event")

    def test_1_state_and_enable(self):
        states = self.peer.subscribe("/pickplace_node/state", "motion_msgs/msg/PickPlaceState")
        s = self.peer.take_one(states, timeout=20)
        self.assertEqual(s.state, STATE_DISABLED)
        self.assertEqual((s.tcp_x, s.tcp_y, s.tcp_z), (0.0, 0.0, 200.0))
        self.assertEqual([b.belt for b in s.belts], [1])
        self.assertEqual(s.belts[0].velocity, 100.0)
        time.sleep(0.5)  # the event reader has matched by now
        r = self.service("set_enable", "PickPlaceSetEnable").call(enable=True)
        self.assertTrue(r.accepted, r.message)
        r = self.service("set_regulator_on", "PickPlaceSetRegulatorOn").call(regulator_on=True)
        self.assertTrue(r.accepted, r.message)
        e = self.event(lambda e: e.kind == KIND_STATE_CHANGED and e.to_state == STATE_READY)
        self.assertEqual(e.from_state, STATE_DISABLED)
        s = self.latest_state(states, pred=lambda s: s.state == STATE_READY and s.axes_enabled)
        self.assertFalse(s.error)

    def test_2_rejections(self):
        belt_input = self.service("belt_input", "PickPlaceBeltInput")
        r = belt_input.call(belt=0, receive=True, valid_pos=False,
                            initial_object_position=[0.0] * 6, aux1_target_pos=0.0)
        self.assertFalse(r.accepted)
        self.assertEqual(r.error_id, UNKNOWN_OBJECT)
        r = belt_input.call(belt=1, receive=True, valid_pos=False,
                            initial_object_position=[0.0, float("nan"), 0.0, 0.0, 0.0, 0.0], aux1_target_pos=0.0)
        self.assertFalse(r.accepted)
        self.assertEqual(r.error_id, NOT_FINITE)
        r = self.service("set_params", "PickPlaceSetParams").call(params="{path_mode: 1, path_vel: -5}")
        self.assertFalse(r.accepted)
        self.assertEqual(r.error_id, INVALID_PARAMETER)
        self.assertIn("lrPathVel", r.message)
        r = self.service("sim/inject_fault", "PickPlaceSimInjectFault").call(axis=1, kind=9)
        self.assertFalse(r.accepted)
        self.assertEqual(r.error_id, ENUM_OUT_OF_RANGE)
        p = self.service("get_params", "PickPlaceGetParams").call(belt=0)
        self.assertTrue(p.accepted)
        self.assertIn("path_mode: 0", p.params)  # the rejected write changed nothing

    def test_3_workpiece_detection(self):
        wps = self.peer.subscribe("/pickplace_node/workpieces", "motion_msgs/msg/BeltWorkpieces")
        r = self.service("detect_workpiece", "PickPlaceDetectWorkpiece").call(
            belt=1, position=[50.0, 0.0, 10.0, 0.0, 0.0, 0.0], valid_delay_cycles=2)
        self.assertTrue(r.accepted, r.message)
        rx = self.event(lambda e: e.kind == KIND_WORKPIECE and e.workpiece_event == WORKPIECE_RECEIVED)
        vis = self.event(lambda e: e.kind == KIND_WORKPIECE and e.workpiece_event == WORKPIECE_VISIBLE)
        self.assertEqual((rx.belt, vis.workpiece_id), (1, rx.workpiece_id))
        self.assertEqual(vis.cycle - rx.cycle, 2)
        m = self.latest_state(wps, pred=lambda m: any(w.visible for w in m.workpieces))
        w = [w for w in m.workpieces if w.id == rx.workpiece_id][0]
        # Belt 1: belt (x, y, z) -> MCS (400 - x, 500 - y, 100 + z); the belt moves it on in +x.
        self.assertGreaterEqual(w.belt_position[0], 50.0)
        self.assertAlmostEqual(w.mcs_position[0], 400.0 - w.belt_position[0], places=6)
        self.assertAlmostEqual(w.mcs_position[1], 500.0, places=6)
        self.assertAlmostEqual(w.mcs_position[2], 110.0, places=6)

    def test_4_pick_and_place_action_and_markers(self):
        act = self.peer.action("/pickplace_node/pick_and_place", "motion_msgs/action/PickPlaceExecute")
        act.wait_for_server()
        target = [100.0, 50.0, 150.0, 180.0, 0.0, 30.0, 0.0]
        gid, accepted = act.send(set_target=0, use_target_pose=True, target_pose=target, params="")
        self.assertTrue(accepted)
        status, result = act.result(gid, timeout=30)
        self.assertEqual(status, ros2_peer.STATUS_SUCCEEDED, result)
        self.assertTrue(result.done)
        for a, b in zip(result.tcp, target):
            self.assertAlmostEqual(a, b, places=6)
        markers = self.peer.subscribe("/pickplace_node/markers", "visualization_msgs/msg/MarkerArray")
        m = self.peer.take_one(markers, timeout=10)
        by_ns = {}
        for mk in m.markers:
            by_ns.setdefault(mk.ns, []).append(mk)
        self.assertEqual(len(by_ns["belts"]), 16)
        self.assertEqual(by_ns["belts"][0].action, 0)  # belt 1 configured: ADD
        self.assertEqual(by_ns["belts"][0].header.frame_id, "pickplace_mcs")
        tcp = by_ns["tcp"][0]
        self.assertAlmostEqual(tcp.pose.position.x, 0.100, places=6)
        self.assertAlmostEqual(tcp.pose.position.z, 0.150, places=6)

    def test_5_cancel(self):
        act = self.peer.action("/pickplace_node/pick_and_place", "motion_msgs/action/PickPlaceExecute")
        act.wait_for_server()
        gid, accepted = act.send(set_target=0, use_target_pose=True,
                                 target_pose=[2100.0, 50.0, 150.0, 180.0, 0.0, 30.0, 0.0], params="{path_vel: 100}")
        self.assertTrue(accepted)
        fb = act.feedback_for(gid, timeout=10)
        self.assertGreater(fb.tcp[0], 99.0)
        time.sleep(0.3)
        c = act.cancel_goal(gid)
        self.assertEqual(len(c.goals_canceling), 1)
        status, result = act.result(gid, timeout=30)
        self.assertEqual(status, ros2_peer.STATUS_CANCELED, result)
        self.assertTrue(result.command_aborted)
        self.assertLess(result.tcp[0], 2100.0)


if __name__ == "__main__":
    unittest.main(verbosity=2)
