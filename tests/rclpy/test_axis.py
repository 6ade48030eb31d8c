"""axis_node as an rclpy user meets it: the graph, parameters, services, an action goal with
feedback, result and cancel, a goal that fails screening, joint_states, /diagnostics, /rosout,
and header stamps on the system clock."""

import math
import time

import pytest
from action_msgs.msg import GoalStatus
from diagnostic_msgs.msg import DiagnosticArray
from rcl_interfaces.msg import Log, ParameterType
from rcl_interfaces.srv import DescribeParameters, GetParameters, ListParameters, SetParameters
from rcl_interfaces.msg import Parameter, ParameterValue
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState

from conftest import call, result_of, run_goal, send_goal, spin_until, started, take
from motion_msgs.action import MoveAbsolute as MoveAbsoluteAction
from motion_msgs.action import MoveVelocity as MoveVelocityAction
from motion_msgs.msg import AxisStateArray
from motion_msgs.srv import MoveAbsolute, Power, ReadActualPosition

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
      table:
        joint_type: revolute
        max_velocity: 720.0
        acceleration: 3600.0
        deceleration: 3600.0
        jerk: 36000.0
        modulo_value: 360.0
"""

UNKNOWN_OBJECT = 0x7F01
NOT_FINITE = 0x7F02


@pytest.fixture(scope="module")
def node(ros):
    launched = started(ros, CONFIG, "axis_node")
    rnode, ex = ros
    yield rnode, ex, launched
    launched.stop()


def stamp_ns(t):
    return t.sec * 1_000_000_000 + t.nanosec


def test_rosout_carries_the_start_up_line(node):
    rnode, ex, _ = node
    # rcl's rosout profile: a late reader still gets the lines of the last 10 s.
    qos = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
    m = take(rnode, ex, Log, "/rosout", timeout=20, qos=qos,
             cond=lambda m: m.name == "axis_node" and "node started" in m.msg)
    assert m.level == Log.INFO


def test_graph_names_and_types(node):
    rnode, ex, _ = node
    # Discovery of a node with some hundred endpoints takes a moment after its name appears.
    spin_until(ex, lambda: "/axis_node/list_parameters" in dict(
        rnode.get_service_names_and_types_by_node("axis_node", "/")), 10,
        "the parameter services in the graph")
    services = dict(rnode.get_service_names_and_types_by_node("axis_node", "/"))
    assert services["/axis_node/power"] == ["motion_msgs/srv/Power"]
    assert services["/axis_node/move_absolute"] == ["motion_msgs/srv/MoveAbsolute"]
    assert services.get("/axis_node/list_parameters") == ["rcl_interfaces/srv/ListParameters"], \
        sorted(services)
    # The publishers are discovered apart from the services (seen missing on a loaded machine).
    published = {"/axis_node/axis_states", "/joint_states", "/diagnostics", "/rosout"}
    spin_until(ex, lambda: published <= set(dict(
        rnode.get_publisher_names_and_types_by_node("axis_node", "/"))), 10,
        "the publishers in the graph")
    topics = dict(rnode.get_publisher_names_and_types_by_node("axis_node", "/"))
    assert topics["/axis_node/axis_states"] == ["motion_msgs/msg/AxisStateArray"]
    assert topics["/joint_states"] == ["sensor_msgs/msg/JointState"]
    assert topics["/diagnostics"] == ["diagnostic_msgs/msg/DiagnosticArray"]
    assert topics["/rosout"] == ["rcl_interfaces/msg/Log"]
    # Actions appear as their hidden services and topics, as `ros2 action list` reads them.
    from rclpy.action import get_action_names_and_types
    actions = dict(get_action_names_and_types(rnode))
    assert actions["/axis_node/move_absolute"] == ["motion_msgs/action/MoveAbsolute"]


def test_parameters_list_get_describe_and_refused_set(node):
    rnode, ex, _ = node
    names = call(rnode, ex, ListParameters, "/axis_node/list_parameters").result.names
    for n in ("cycle_period", "state_rate", "lockstep", "use_sim_time", "service_mapping"):
        assert n in names, names
    got = call(rnode, ex, GetParameters, "/axis_node/get_parameters",
               names=["cycle_period", "lockstep", "use_sim_time"]).values
    assert got[0].type == ParameterType.PARAMETER_DOUBLE and got[0].double_value == 0.001
    assert got[1].type == ParameterType.PARAMETER_BOOL and got[1].bool_value is False
    assert got[2].type == ParameterType.PARAMETER_BOOL and got[2].bool_value is False
    desc = call(rnode, ex, DescribeParameters, "/axis_node/describe_parameters",
                names=["cycle_period"]).descriptors[0]
    assert desc.read_only and "cycle" in desc.description
    r = call(rnode, ex, SetParameters, "/axis_node/set_parameters", parameters=[Parameter(
        name="cycle_period",
        value=ParameterValue(type=ParameterType.PARAMETER_DOUBLE, double_value=0.002))])
    assert not r.results[0].successful
    assert "read-only" in r.results[0].reason


def test_first_call_of_a_fresh_client_is_answered_within_100_ms(node):
    """A fresh client's first call (issue 12 §4): every one answered within 100 ms. (Until
    RustDDS patches 6, 8 and 9, 1 in 40 waited for Fast DDS's next heartbeat, 3 s; after
    them 380 of 380 were under 31 ms.)"""
    rnode, ex, _ = node
    took = []
    for _ in range(50):
        cli = rnode.create_client(Power, "/axis_node/power")
        assert cli.wait_for_service(timeout_sec=20.0)
        t0 = time.monotonic()
        fut = cli.call_async(Power.Request(axis="nope", enable=True))
        ex.spin_until_future_complete(fut, timeout_sec=5.0)
        took.append(time.monotonic() - t0)
        assert fut.done(), "a first call was never answered"
        assert fut.result().error_id == UNKNOWN_OBJECT
        rnode.destroy_client(cli)
    shown = " ".join(f"{t * 1000:.0f}" for t in took)
    assert max(took) < 0.1, "first calls [ms]: " + shown
    print("first calls [ms]:", shown)


def test_services_accept_and_refuse_with_error_ids(node):
    rnode, ex, launched = node
    r = call(rnode, ex, Power, "/axis_node/power", axis="x", enable=True,
             enable_positive=True, enable_negative=True, override=100.0)
    assert r.accepted, r.message
    r = call(rnode, ex, MoveAbsolute, "/axis_node/move_absolute", axis="nope",
             position=1.0, velocity=10.0)
    assert (r.accepted, r.error_id) == (False, UNKNOWN_OBJECT) and "nope" in r.message
    r = call(rnode, ex, MoveAbsolute, "/axis_node/move_absolute", axis="x",
             position=float("nan"), velocity=10.0)
    assert (r.accepted, r.error_id) == (False, NOT_FINITE)
    r = call(rnode, ex, MoveAbsolute, "/axis_node/move_absolute", axis="x",
             position=5.0, velocity=100.0)
    assert r.accepted and r.command_id > 0
    # The refusal is on /rosout at info, with the node's name.
    qos = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
    m = take(rnode, ex, Log, "/rosout", timeout=10, qos=qos,
             cond=lambda m: m.name == "axis_node" and "refused" in m.msg and "nope" in m.msg)
    assert m.level == Log.INFO


def test_action_goal_feedback_and_result(node):
    rnode, ex, _ = node
    call(rnode, ex, Power, "/axis_node/power", axis="x", enable=True,
         enable_positive=True, enable_negative=True, override=100.0)
    feedback = []
    res = run_goal(rnode, ex, MoveAbsoluteAction, "/axis_node/move_absolute",
                   MoveAbsoluteAction.Goal(axis="x", position=120.0, velocity=200.0),
                   feedback=lambda f: feedback.append(f.feedback))
    assert res.status == GoalStatus.STATUS_SUCCEEDED, res.result
    assert res.result.done and abs(res.result.position - 120.0) < 1e-6
    assert feedback and all(f.busy for f in feedback)
    assert 0.0 < feedback[len(feedback) // 2].position < 120.0


def test_a_goal_that_fails_screening_ends_aborted_with_its_error_id(node):
    rnode, ex, _ = node
    # Accepted (the goal service answers at once), then ABORTED with the id.
    res = run_goal(rnode, ex, MoveAbsoluteAction, "/axis_node/move_absolute",
                   MoveAbsoluteAction.Goal(axis="nope", position=1.0, velocity=1.0))
    assert res.status == GoalStatus.STATUS_ABORTED
    assert res.result.error and res.result.error_id == UNKNOWN_OBJECT


def test_cancel_halts_the_axis_and_the_goal_ends_canceled(node):
    rnode, ex, _ = node
    call(rnode, ex, Power, "/axis_node/power", axis="x", enable=True,
         enable_positive=True, enable_negative=True, override=100.0)
    ac, goal_handle = send_goal(rnode, ex, MoveVelocityAction, "/axis_node/move_velocity",
                                MoveVelocityAction.Goal(axis="x", velocity=50.0,
                                                        acceleration=1.0, direction=1))
    t_end = time.monotonic() + 0.3
    spin_until(ex, lambda: time.monotonic() > t_end, 2, "ramping")
    cancel_fut = goal_handle.cancel_goal_async()
    ex.spin_until_future_complete(cancel_fut, timeout_sec=10.0)
    assert len(cancel_fut.result().goals_canceling) == 1
    res = result_of(ex, goal_handle)
    assert res.status == GoalStatus.STATUS_CANCELED
    assert res.result.command_aborted
    ac.destroy()


def test_state_topics_are_stamped_with_the_system_clock(node):
    rnode, ex, _ = node
    for _ in range(5):
        m = take(rnode, ex, AxisStateArray, "/axis_node/axis_states")
        age = rnode.get_clock().now().nanoseconds - stamp_ns(m.header.stamp)
        assert -5e6 < age < 50e6, f"stamp {age / 1e6:.1f} ms from the client's clock"
        js = take(rnode, ex, JointState, "/joint_states")
        age = rnode.get_clock().now().nanoseconds - stamp_ns(js.header.stamp)
        assert -5e6 < age < 50e6, f"joint_states stamp {age / 1e6:.1f} ms from the clock"
    assert js.name == ["x", "table"]
    assert len(js.position) == len(js.velocity) == 2


def test_diagnostics(node):
    rnode, ex, _ = node
    d = take(rnode, ex, DiagnosticArray, "/diagnostics", timeout=20,
             cond=lambda d: d.status and d.status[0].name == "axis_node: cycle")
    keys = {kv.key: kv.value for kv in d.status[0].values}
    assert keys["period_us"] == "1000.0" and int(keys["cycles"]) > 0
    age = rnode.get_clock().now().nanoseconds - stamp_ns(d.header.stamp)
    assert -5e6 < age < 1.1e9


def test_joint_states_are_in_si_units(node):
    """REP-103: the prismatic x (mm) in m, the revolute table (deg) in rad."""
    rnode, ex, _ = node
    call(rnode, ex, Power, "/axis_node/power", axis="table", enable=True,
         enable_positive=True, enable_negative=True, override=100.0)
    r = call(rnode, ex, MoveAbsolute, "/axis_node/move_absolute", axis="table",
             position=90.0, velocity=360.0)
    assert r.accepted, r.message
    js = take(rnode, ex, JointState, "/joint_states", timeout=20,
              cond=lambda m: abs(m.position[1] - math.pi / 2) < 1e-9 and m.velocity[1] == 0.0)
    x = call(rnode, ex, ReadActualPosition, "/axis_node/read_actual_position", axis="x")
    assert abs(js.position[0] - x.position * 1e-3) < 1e-12, (js.position, x.position)
