"""The static TF tree as RViz and tf2 read it: every node publishes its frame on /tf_static
(transient local), under one configurable root, at its configured pose."""

import math

import pytest
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from tf2_msgs.msg import TFMessage

from conftest import launch, spin_until

CONFIG = """
nodes:
  - kind: axis_node
    axes: {x: {}}
  - kind: planar_node
    tf_pose: [1.5, 0.0, 0.0, 0.0, 0.0, 1.5707963267948966]
    coordinate_systems: [0x01010060]
    parts:
      - {name: table, oid: 0x01010020, tiles: [[0, 0]], positions: {1: {cs: 0x01010060, x: 0, y: 0}}}
    environment: {name: environment, oid: 0x01010001, processing_unit_oid: 0x01010002}
    movers: [{name: m1, initial_pose: {x: 120, y: 120}}]
  - kind: pickplace_node
    tf_parent: cell
    tf_pose: [0.0, 2.0, 0.5, 0.0, 0.0, 0.0]
    belts:
      "1": {params: {conveyor_belt_origin: [400, 500, 100, 0, 0, 180]}}
"""


@pytest.fixture(scope="module")
def frames(ros):
    launched = launch(CONFIG)
    rnode, ex = ros
    seen = {}

    def got(msg):
        for t in msg.transforms:
            seen[t.child_frame_id] = t

    # tf2's static listener QoS: reliable, transient local.
    qos = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
    sub = rnode.create_subscription(TFMessage, "/tf_static", got, qos)
    try:
        spin_until(ex, lambda: {"axes_base", "planar_env", "pickplace_mcs"} <= set(seen), 30,
                   "all three frames on /tf_static")
    finally:
        rnode.destroy_subscription(sub)
        launched.stop()
    return seen


def test_every_node_frame_hangs_under_its_configured_parent(frames):
    assert frames["axes_base"].header.frame_id == "world"
    assert frames["planar_env"].header.frame_id == "world"
    assert frames["pickplace_mcs"].header.frame_id == "cell"
    t = frames["axes_base"].transform
    assert (t.translation.x, t.translation.y, t.translation.z) == (0.0, 0.0, 0.0)
    assert (t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w) == (0.0, 0.0, 0.0, 1.0)


def test_frames_are_at_their_configured_poses(frames):
    t = frames["planar_env"].transform
    assert t.translation.x == 1.5
    # yaw 90 degrees: q = (0, 0, sin 45°, cos 45°)
    assert abs(t.rotation.z - math.sqrt(0.5)) < 1e-12 and abs(t.rotation.w - math.sqrt(0.5)) < 1e-12
    t = frames["pickplace_mcs"].transform
    assert (t.translation.x, t.translation.y, t.translation.z) == (0.0, 2.0, 0.5)
