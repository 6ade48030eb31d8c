"""Simulated time as an rclpy user meets it: a lockstep node is the clock (`~/step` runs
cycles, `/clock` follows, stamps are simulated time), and a `use_sim_time` node follows the
user's own `/clock`; the parameters read back as configured."""

import pytest
from rcl_interfaces.srv import GetParameters
from rosgraph_msgs.msg import Clock

from conftest import call, spin_until, started
from motion_msgs.msg import AxisStateArray
from motion_msgs.srv import StepCycles

AXIS = """
    axes:
      x: {max_velocity: 1000.0, acceleration: 10000.0, deceleration: 10000.0, jerk: 100000.0}
"""
STEPPED = f"""
nodes:
  - kind: axis_node
    name: stepped
    lockstep: true
    cycle_period: 0.002
{AXIS}
"""
# Its own process, after the lockstep node has gone: that node publishes /clock too, and two
# clocks on one domain are a user error.
FOLLOWER = f"""
nodes:
  - kind: axis_node
    name: follower
    use_sim_time: true
    cycle_period: 0.001
{AXIS}
"""


@pytest.fixture
def stepped(ros):
    launched = started(ros, STEPPED, "stepped")
    yield ros
    launched.stop()


@pytest.fixture
def follower(ros):
    launched = started(ros, FOLLOWER, "follower")
    yield ros
    launched.stop()


def ns(t):
    return t.sec * 10**9 + t.nanosec


def test_lockstep_step_and_clock(stepped):
    rnode, ex = stepped
    v = call(rnode, ex, GetParameters, "/stepped/get_parameters",
             names=["lockstep", "use_sim_time"]).values
    assert (v[0].bool_value, v[1].bool_value) == (True, False)
    clocks, stamps = [], []
    subs = [rnode.create_subscription(Clock, "/clock", lambda c: clocks.append(ns(c.clock)), 10),
            rnode.create_subscription(AxisStateArray, "/stepped/axis_states",
                                      lambda s: stamps.append(ns(s.header.stamp)), 10)]
    spin_until(ex, lambda: rnode.count_publishers("/clock") > 0, 10, "the /clock publisher")
    before = call(rnode, ex, StepCycles, "/stepped/step", cycles=0)
    r = call(rnode, ex, StepCycles, "/stepped/step", cycles=500)
    assert r.accepted and r.cycle_index == before.cycle_index + 500
    assert abs(r.sim_time - r.cycle_index * 0.002) < 1e-9
    # /clock and the state stamps carry the simulated time of that cycle, and nothing runs
    # without a step.
    want = round(r.sim_time * 1e9)
    spin_until(ex, lambda: want in clocks and want in stamps, 10, "/clock and stamps at the step")
    assert max(clocks) == want and max(stamps) == want
    for s in subs:
        rnode.destroy_subscription(s)


def test_use_sim_time_follows_the_users_clock(follower):
    rnode, ex = follower
    v = call(rnode, ex, GetParameters, "/follower/get_parameters",
             names=["lockstep", "use_sim_time"]).values
    assert (v[0].bool_value, v[1].bool_value) == (False, True)
    pub = rnode.create_publisher(Clock, "/clock", 10)
    t0 = 5_000 * 10**9
    stamps = []
    sub = rnode.create_subscription(AxisStateArray, "/follower/axis_states",
                                    lambda s: stamps.append(ns(s.header.stamp)), 10)
    sent = []

    def publish_until(times, cond, what):
        ticks = 0

        def tick():
            nonlocal ticks
            ticks += 1
            if ticks % 4 == 1:
                t = next(times)
                msg = Clock()
                msg.clock.sec, msg.clock.nanosec = divmod(t, 10**9)
                pub.publish(msg)
                sent.append(t)
            return cond()
        spin_until(ex, tick, 20, what)

    # A clock advancing by 1 ms per tick until the node's state shows it: every stamp is a
    # time the clock has shown (the first one is the origin, the rest are cycles after it).
    publish_until(iter(range(t0, t0 + 10**9, 1_000_000)), lambda: stamps,
                  "the follower stamped with /clock")
    assert all(t0 <= s <= max(sent) and (s - t0) % 1_000_000 == 0 for s in stamps), stamps
    # A jump of 300 ms runs the 300 cycles at once; the state is stamped with that time.
    t1 = max(sent) + 300_000_000
    publish_until(iter([t1] * 1000), lambda: t1 in stamps, "the follower 300 cycles on")
    assert max(stamps) == t1
    rnode.destroy_subscription(sub)
    rnode.destroy_publisher(pub)
