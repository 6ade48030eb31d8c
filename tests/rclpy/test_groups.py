"""Axis groups as an rclpy user meets them: a PLCopen Part 4 group enabled and moved linearly
by an action goal, and a collision-avoidance group (TF5410) whose follower keeps its gap
behind the leader and then reaches its target."""

import pytest
from action_msgs.msg import GoalStatus

from conftest import call, result_of, run_goal, send_goal, started, take
from motion_msgs.action import MoveAbsoluteCa, MoveLinearAbsolute
from motion_msgs.msg import CaGroupState, McLreal
from motion_msgs.srv import (AxesGroupCommand, AxesGroupReadActual, CaAddAxis, CaGroupCommand,
                             Power)

DYN = "max_velocity: 2000.0, acceleration: 10000.0, deceleration: 10000.0, jerk: 100000.0"
CONFIG = f"""
nodes:
  - kind: axis_node
    axes:
      x: {{{DYN}}}
      y: {{{DYN}}}
      a: {{initial_position: 1000.0, auto_power: true, {DYN}}}
      b: {{initial_position: 500.0, auto_power: true, {DYN}}}
    groups:
      - {{name: g, axes: [x, y]}}
    ca_groups:
      ring: {{rail_length: 3000.0, default_gap: 100.0}}
"""


@pytest.fixture(scope="module")
def node(ros):
    launched = started(ros, CONFIG, "axis_node")
    rnode, ex = ros
    for axis in ("x", "y"):  # a and b: auto_power
        r = call(rnode, ex, Power, "/axis_node/power", axis=axis, enable=True,
                 enable_positive=True, enable_negative=True, override=100.0)
        assert r.accepted, r.message
    yield rnode, ex
    launched.stop()


def test_part4_group_linear_move(node):
    rnode, ex = node
    r = call(rnode, ex, AxesGroupCommand, "/axis_node/groups/g/group_enable")
    assert r.accepted, r.message
    res = run_goal(rnode, ex, MoveLinearAbsolute, "/axis_node/groups/g/move_linear_absolute",
                   MoveLinearAbsolute.Goal(position=[30.0, 40.0], velocity=500.0,
                                           coord_system=1))
    assert res.status == GoalStatus.STATUS_SUCCEEDED, res.result.message
    p = call(rnode, ex, AxesGroupReadActual, "/axis_node/groups/g/read_actual_position",
             coord_system=1)
    assert p.accepted and abs(p.values[0] - 30.0) < 1e-9 and abs(p.values[1] - 40.0) < 1e-9


def test_ca_follower_keeps_its_gap(node):
    rnode, ex = node
    ns = "/axis_node/ca/ring"
    for i, axis in enumerate(("a", "b")):
        r = call(rnode, ex, CaAddAxis, f"{ns}/add_axis", axis=axis, ident_in_group=i + 1)
        assert r.accepted, r.message
    r = call(rnode, ex, CaGroupCommand, f"{ns}/group_enable")
    assert r.accepted, r.message
    take(rnode, ex, CaGroupState, f"{ns}/state", timeout=20,
         cond=lambda s: s.state == CaGroupState.STATE_GROUP_STANDBY and len(s.axes) == 2)
    # b (at 500) to 2000 past a (at 1000, standing): it waits at 900, the default gap behind.
    v = lambda x: McLreal(kind=McLreal.VALUE, value=x)  # noqa: E731
    ac, handle = send_goal(rnode, ex, MoveAbsoluteCa, f"{ns}/move_absolute",
                           MoveAbsoluteCa.Goal(axis="b", position=v(2000.0), velocity=v(500.0)))
    def waiting(s):
        b = [x for x in s.axes if x.name == "b"][0]
        return b.active_command_id != 0 and abs(b.velocity) < 1e-9 and b.position > 800.0

    s = take(rnode, ex, CaGroupState, f"{ns}/state", timeout=20, cond=waiting)
    b = [x for x in s.axes if x.name == "b"][0]
    assert abs(b.position - 900.0) < 1e-6, b
    assert b.gap_actual >= b.gap_target - 1e-6 and abs(b.gap_target - 100.0) < 1e-9, b
    # The leader moves on; the follower then reaches its target.
    res = run_goal(rnode, ex, MoveAbsoluteCa, f"{ns}/move_absolute",
                   MoveAbsoluteCa.Goal(axis="a", position=v(2900.0), velocity=v(1000.0)))
    assert res.status == GoalStatus.STATUS_SUCCEEDED, res.result.message
    r = result_of(ex, handle)
    assert r.status == GoalStatus.STATUS_SUCCEEDED, r.result.message
    assert abs(r.result.final_position - 2000.0) < 1e-6
    ac.destroy()
