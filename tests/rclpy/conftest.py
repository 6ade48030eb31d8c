"""The rclpy suite (issue 13): our nodes used exactly as an rclpy user uses them, with real
ROS 2 Jazzy rclpy on rmw_fastrtps_cpp (Fast DDS, the Enhanced request/reply mapping).

Runs in the venv of scripts/ros-venv.sh (source .ros/env.sh), inside the private network
namespace (scripts/netns-run), on ROS_DOMAIN_ID; tests/tests/rclpy_suite.rs runs it.
Each test module starts `motion_launch` (MOTION_LAUNCH_BIN) on its own launch config.
"""

import os
import subprocess
import tempfile
import time

import pytest
import rclpy
from rclpy.executors import SingleThreadedExecutor


def pytest_configure(config):
    if os.environ.get("MOTION_IN_NETNS") != "1":
        raise pytest.UsageError("run inside scripts/netns-run (network rule)")


class Launched:
    """A running motion_launch and its log file."""

    def __init__(self, config_text, extra_args=()):
        fd, self.config = tempfile.mkstemp(suffix=".yaml", prefix="rclpy_suite_")
        with os.fdopen(fd, "w") as f:
            f.write(config_text)
        self.log_path = self.config + ".log"
        self.log = open(self.log_path, "w")
        self.proc = subprocess.Popen(
            [os.environ["MOTION_LAUNCH_BIN"], self.config, *extra_args],
            stdout=self.log, stderr=subprocess.STDOUT, env=dict(os.environ))

    def output(self):
        self.log.flush()
        with open(self.log_path) as f:
            return f.read()

    def stop(self):
        self.proc.terminate()
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        self.log.close()
        for p in (self.config, self.log_path):
            try:
                os.unlink(p)
            except OSError:
                pass


@pytest.fixture(scope="module")
def ros():
    """rclpy initialised for one module; yields (node, executor)."""
    rclpy.init()
    node = rclpy.create_node("rclpy_suite")
    ex = SingleThreadedExecutor()
    ex.add_node(node)
    yield node, ex
    ex.shutdown()
    node.destroy_node()
    rclpy.shutdown()


def launch(config_text, *extra_args):
    return Launched(config_text, extra_args)


def spin_until(ex, cond, timeout, what):
    """Spins until cond() is true; fails the test with `what` after `timeout` seconds."""
    end = time.monotonic() + timeout
    while not cond():
        if time.monotonic() > end:
            pytest.fail(f"timed out after {timeout} s: {what}")
        ex.spin_once(timeout_sec=0.05)


def call(node, ex, srv_type, name, timeout=10.0, **fields):
    """One service call as an rclpy user writes it; returns the response."""
    cli = node.create_client(srv_type, name)
    try:
        assert cli.wait_for_service(timeout_sec=20.0), f"service {name} not found"
        req = srv_type.Request(**fields)
        fut = cli.call_async(req)
        ex.spin_until_future_complete(fut, timeout_sec=timeout)
        assert fut.done(), f"{name}: no answer within {timeout} s"
        return fut.result()
    finally:
        node.destroy_client(cli)


def take(node, ex, msg_type, topic, timeout=10.0, qos=10, cond=lambda m: True):
    """The first message on `topic` for which cond holds."""
    got = []
    sub = node.create_subscription(msg_type, topic, lambda m: got.append(m) if cond(m) else None, qos)
    try:
        spin_until(ex, lambda: got, timeout, f"a message on {topic}")
        return got[0]
    finally:
        node.destroy_subscription(sub)


def started(ros, config_text, name, *extra_args):
    """Launches `config_text` and waits until node `name` is in the graph."""
    launched = launch(config_text, *extra_args)
    rnode, ex = ros
    spin_until(ex, lambda: name in rnode.get_node_names(), 20, f"{name} in the graph")
    return launched


def send_goal(rnode, ex, action_type, name, goal, feedback=None):
    """An action goal as an rclpy user sends it; returns (client, accepted goal handle)."""
    from rclpy.action import ActionClient
    ac = ActionClient(rnode, action_type, name)
    assert ac.wait_for_server(timeout_sec=20.0), f"action {name} not found"
    fut = ac.send_goal_async(goal, feedback_callback=feedback)
    ex.spin_until_future_complete(fut, timeout_sec=10.0)
    handle = fut.result()
    assert handle is not None and handle.accepted, f"{name}: goal not accepted"
    return ac, handle


def result_of(ex, handle, timeout=30.0):
    """The goal's end: a GetResult response (status, result)."""
    fut = handle.get_result_async()
    ex.spin_until_future_complete(fut, timeout_sec=timeout)
    assert fut.done(), f"no result within {timeout} s"
    return fut.result()


def run_goal(rnode, ex, action_type, name, goal, feedback=None, timeout=30.0):
    """send_goal, then its result; the client is destroyed."""
    ac, handle = send_goal(rnode, ex, action_type, name, goal, feedback)
    try:
        return result_of(ex, handle, timeout)
    finally:
        ac.destroy()
