"""planar_node as an rclpy user meets it: a mover enabled and moved by an action goal, a track
ride (enable the track, join it, move along it), poses and markers in metres."""

import pytest
from action_msgs.msg import GoalStatus
from geometry_msgs.msg import PoseArray
from visualization_msgs.msg import MarkerArray

from conftest import call, run_goal, started, take
from motion_msgs.action import MoverJoinTrack, MoverMoveOnTrack, MoverMoveToPosition
from motion_msgs.msg import PlanarState, PlanarTrackState
from motion_msgs.srv import MoverEnable, TrackEnable

CONFIG = """
nodes:
  - kind: planar_node
    cycle_period: 0.001
    state_rate: 50
    coordinate_systems: [0x01010060]
    parts:
      - name: table
        oid: 0x01010020
        tiles: [[0, 0], [240, 0], [480, 0], [720, 0], [0, 240], [240, 240], [480, 240], [720, 240]]
        positions: {1: {cs: 0x01010060, x: 0, y: 0}}
    environment: {name: environment, oid: 0x01010001, processing_unit_oid: 0x01010002}
    movers:
      - {name: m1, initial_pose: {x: 120, y: 120}}
      - {name: m2, initial_pose: {x: 720, y: 360}}
    tracks:
      - name: line
        geometry: [{line: {start: [120, 120], end: [840, 120]}}]
"""

STATE_ENABLED = 3


@pytest.fixture(scope="module")
def node(ros):
    launched = started(ros, CONFIG, "planar_node")
    yield ros
    launched.stop()


def mover(state, name):
    return [m for m in state.movers if m.name == name][0]


def test_mover_enable_and_move_to_position(node):
    rnode, ex = node
    for m in ("m1", "m2"):
        r = call(rnode, ex, MoverEnable, "/planar_node/mover_enable", mover=m)
        assert r.accepted, r.message
    take(rnode, ex, PlanarState, "/planar_node/state", timeout=20,
         cond=lambda s: all(m.state == STATE_ENABLED for m in s.movers))
    res = run_goal(rnode, ex, MoverMoveToPosition, "/planar_node/mover_move_to_position",
                   MoverMoveToPosition.Goal(mover="m2", x=600.0, y=360.0, c=10.0,
                                            use_orientation=True))
    assert res.status == GoalStatus.STATUS_SUCCEEDED, res.result
    # xplanar.md §7: ±0.1 mm, ±0.01°.
    assert abs(res.result.x - 600.0) < 0.1 and abs(res.result.y - 360.0) < 0.1
    assert abs(res.result.c - 10.0) < 0.01


def test_track_ride(node):
    rnode, ex = node
    r = call(rnode, ex, TrackEnable, "/planar_node/track_enable", track="line")
    assert r.accepted, r.message
    take(rnode, ex, PlanarState, "/planar_node/state", timeout=20,
         cond=lambda s: s.tracks and s.tracks[0].operation_mode == PlanarTrackState.MODE_STANDING)
    res = run_goal(rnode, ex, MoverJoinTrack, "/planar_node/mover_join_track",
                   MoverJoinTrack.Goal(mover="m1", track="line", use_orientation=True))
    assert res.status == GoalStatus.STATUS_SUCCEEDED, res.result
    assert res.result.track == "line"
    res = run_goal(rnode, ex, MoverMoveOnTrack, "/planar_node/mover_move_on_track",
                   MoverMoveOnTrack.Goal(mover="m1", target_position=400.0, velocity=500.0))
    assert res.status == GoalStatus.STATUS_SUCCEEDED, res.result
    assert abs(res.result.track_position - 400.0) < 0.1
    assert abs(res.result.x - 520.0) < 0.1 and abs(res.result.y - 120.0) < 0.1


def test_poses_and_markers_in_metres(node):
    rnode, ex = node
    p = take(rnode, ex, PoseArray, "/planar_node/mover_poses", timeout=20)
    assert p.header.frame_id == "planar_env"
    now = rnode.get_clock().now().nanoseconds
    assert abs(now - (p.header.stamp.sec * 10**9 + p.header.stamp.nanosec)) < 50e6
    assert abs(p.poses[0].position.x - 0.52) < 1e-4 and abs(p.poses[0].position.y - 0.12) < 1e-4
    m = take(rnode, ex, MarkerArray, "/planar_node/markers", timeout=20)
    movers = [k for k in m.markers if k.ns == "movers"]
    assert movers and abs(movers[0].scale.x - 0.155) < 1e-9
