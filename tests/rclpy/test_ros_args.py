"""`--ros-args` as a ROS user passes them: the node renamed, a topic remapped, a parameter
overridden, all visible to rclpy."""

import pytest
from rcl_interfaces.srv import GetParameters

from conftest import call, spin_until, started, take
from motion_msgs.msg import AxisStateArray

CONFIG = """
nodes:
  - kind: axis_node
    axes: {x: {}}
"""


@pytest.fixture(scope="module")
def node(ros):
    launched = started(ros, CONFIG, "arm", "--ros-args", "-r", "__node:=arm", "-r",
                       "~/axis_states:=/arm_states", "-p", "state_rate:=25.0", "--")
    yield ros
    launched.stop()


def test_renamed_remapped_and_overridden(node):
    rnode, ex = node
    v = call(rnode, ex, GetParameters, "/arm/get_parameters", names=["state_rate"]).values
    assert v[0].double_value == 25.0
    m = take(rnode, ex, AxisStateArray, "/arm_states", timeout=20)
    assert [a.name for a in m.axes] == ["x"]
    spin_until(ex, lambda: {"/arm_states", "/arm/command_status"} <= set(dict(
        rnode.get_publisher_names_and_types_by_node("arm", "/"))), 10, "the topics in the graph")
    topics = dict(rnode.get_publisher_names_and_types_by_node("arm", "/"))
    assert "/arm/axis_states" not in topics and "/arm/command_status" in topics
