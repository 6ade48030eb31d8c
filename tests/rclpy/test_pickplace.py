"""pickplace_node as an rclpy user meets it: enable, a pick-and-place goal to its result, and
one canceled while the TCP moves (xPathStop), with events and markers."""

import pytest
from action_msgs.msg import GoalStatus
from visualization_msgs.msg import MarkerArray

from conftest import call, result_of, run_goal, send_goal, spin_until, started, take
from motion_msgs.action import PickPlaceExecute
from motion_msgs.msg import PickPlaceState
from motion_msgs.srv import PickPlaceSetEnable, PickPlaceSetRegulatorOn

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
"""

STATE_READY = 1


@pytest.fixture(scope="module")
def node(ros):
    launched = started(ros, CONFIG, "pickplace_node")
    rnode, ex = ros
    r = call(rnode, ex, PickPlaceSetEnable, "/pickplace_node/set_enable", enable=True)
    assert r.accepted, r.message
    r = call(rnode, ex, PickPlaceSetRegulatorOn, "/pickplace_node/set_regulator_on",
             regulator_on=True)
    assert r.accepted, r.message
    take(rnode, ex, PickPlaceState, "/pickplace_node/state", timeout=20,
         cond=lambda s: s.state == STATE_READY and s.axes_enabled)
    yield rnode, ex
    launched.stop()


def test_pick_and_place_goal_reaches_its_target(node):
    rnode, ex = node
    target = [100.0, 50.0, 150.0, 180.0, 0.0, 30.0, 0.0]
    res = run_goal(rnode, ex, PickPlaceExecute, "/pickplace_node/pick_and_place",
                   PickPlaceExecute.Goal(set_target=0, use_target_pose=True,
                                         target_pose=target, params=""))
    assert res.status == GoalStatus.STATUS_SUCCEEDED, res.result
    assert res.result.done
    for a, b in zip(res.result.tcp, target):
        assert abs(a - b) < 1e-6
    m = take(rnode, ex, MarkerArray, "/pickplace_node/markers", timeout=10)
    tcp = [k for k in m.markers if k.ns == "tcp"][0]
    assert tcp.header.frame_id == "pickplace_mcs"
    assert abs(tcp.pose.position.x - 0.100) < 1e-6 and abs(tcp.pose.position.z - 0.150) < 1e-6


def test_cancel_stops_the_path(node):
    rnode, ex = node
    feedback = []
    ac, handle = send_goal(rnode, ex, PickPlaceExecute, "/pickplace_node/pick_and_place",
                           PickPlaceExecute.Goal(
                               set_target=0, use_target_pose=True,
                               target_pose=[2100.0, 50.0, 150.0, 180.0, 0.0, 30.0, 0.0],
                               params="{path_vel: 100}"),
                           feedback=lambda f: feedback.append(f.feedback))
    spin_until(ex, lambda: feedback and feedback[-1].tcp[0] > 120.0, 10, "the TCP moving")
    cancel = handle.cancel_goal_async()
    ex.spin_until_future_complete(cancel, timeout_sec=10.0)
    assert len(cancel.result().goals_canceling) == 1
    res = result_of(ex, handle)
    ac.destroy()
    assert res.status == GoalStatus.STATUS_CANCELED
    assert res.result.command_aborted
    assert res.result.tcp[0] < 2100.0
