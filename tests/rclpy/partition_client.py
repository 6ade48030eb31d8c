"""The rclpy (Fast DDS) side of tests/peer/test_partition.py: an rclpy user's clients of
`/axis_fast` (Enhanced mapping) that live through network partitions.

Made once, before any partition, and kept: a service client, a subscription to
~/axis_states, an action client. Commands, one a line on stdin, answered with one JSON line
on stdout:
- `prepare SECONDS`: sends a MoveAbsolute goal on x that ends about SECONDS after now (so
  within the coming partition) and a state sample of y (moving at constant velocity); answers
  {"goal_position": ...}.
- `check`: sent at the heal; measures the seconds until each old client is served again
  (old service client, old subscription, the result of the goal sent before the cut, a new
  goal through the old action client) and a new service client, and how far y is from where
  its constant velocity puts it; answers with those figures.
The executor spins between commands, so the clients live as an application's would.

Usage: python partition_client.py  (venv of scripts/ros-venv.sh; env ROS_DOMAIN_ID)
"""

import json
import select
import sys
import time

import rclpy
from action_msgs.msg import GoalStatus
from rclpy.action import ActionClient
from rclpy.executors import SingleThreadedExecutor

from motion_msgs.action import MoveAbsolute
from motion_msgs.msg import AxisStateArray
from motion_msgs.srv import MoveVelocity, Power, ReadStatus

NODE = "/axis_fast"
GOAL_VELOCITY = 100.0  # [u/s] of the goals on x
Y_VELOCITY = 10.0  # [u/s] of y's endless move
LIMIT = 60.0  # [s] given up after


def answer(obj):
    print(json.dumps(obj), flush=True)


class Clients:
    def __init__(self):
        rclpy.init()
        self.node = rclpy.create_node("partition_client")
        self.ex = SingleThreadedExecutor()
        self.ex.add_node(self.node)
        self.states = []
        self.sub = self.node.create_subscription(
            AxisStateArray, f"{NODE}/axis_states", self.states.append, 10)
        self.status = self.node.create_client(ReadStatus, f"{NODE}/read_status")
        self.action = ActionClient(self.node, MoveAbsolute, f"{NODE}/move_absolute")
        self.goal = None
        self.goal_position = 0.0
        self.y_ref = None  # (stamp [s], position) of y at constant velocity

    def spin_until(self, cond, timeout=LIMIT):
        end = time.monotonic() + timeout
        while not cond():
            if time.monotonic() > end:
                return False
            self.ex.spin_once(timeout_sec=0.02)
        return True

    def call(self, client, request, timeout=LIMIT):
        """The response, retried as a user would: a request written while the service is
        not matched is not delivered (volatile), so each try waits at most 2 s."""
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            if not client.service_is_ready():
                self.ex.spin_once(timeout_sec=0.05)
                continue
            fut = client.call_async(request)
            if self.spin_until(fut.done, 2.0):
                return fut.result()
            client.remove_pending_request(fut)
        raise TimeoutError(f"{client.srv_name}: no answer within {timeout} s")

    def y_sample(self):
        """(stamp [s], set position) of y in the newest state message."""
        self.states.clear()
        assert self.spin_until(lambda: self.states), "no state"
        s = self.states[-1]
        y = next(a for a in s.axes if a.name == "y")
        return s.header.stamp.sec + s.header.stamp.nanosec * 1e-9, y.set_pos

    def start(self):
        power = self.node.create_client(Power, f"{NODE}/power")
        for axis in ("x", "y"):
            r = self.call(power, Power.Request(axis=axis, enable=True, enable_positive=True,
                                               enable_negative=True, override=100.0))
            assert r.accepted, r.message
        mv = self.node.create_client(MoveVelocity, f"{NODE}/move_velocity")
        r = self.call(mv, MoveVelocity.Request(axis="y", velocity=Y_VELOCITY, direction=1))
        assert r.accepted, r.message
        assert self.action.wait_for_server(timeout_sec=20.0)
        time.sleep(0.5)  # past y's ramp
        self.y_ref = self.y_sample()

    def send_goal(self, position):
        fut = self.action.send_goal_async(MoveAbsolute.Goal(axis="x", position=position,
                                                            velocity=GOAL_VELOCITY))
        assert self.spin_until(fut.done, 10.0), "no goal response"
        handle = fut.result()
        assert handle.accepted
        return handle

    def prepare(self, seconds):
        self.goal_position += GOAL_VELOCITY * seconds
        self.goal = self.send_goal(self.goal_position)
        answer({"goal_position": self.goal_position})

    def check(self):
        heal = time.monotonic()
        since = lambda: round(time.monotonic() - heal, 3)  # noqa: E731
        out = {}
        # The old subscription: a message sent after the heal.
        self.states.clear()
        self.spin_until(lambda: self.states)
        out["old_subscription"] = since() if self.states else None
        self.call(self.status, ReadStatus.Request(axis="x"))
        out["old_service_client"] = since()
        fut = self.goal.get_result_async()
        self.spin_until(fut.done)
        res = fut.result()
        assert res.status == GoalStatus.STATUS_SUCCEEDED, res
        assert abs(res.result.position - self.goal_position) < 1e-6, res.result
        out["old_goal_result"] = since()
        fresh = self.node.create_client(ReadStatus, f"{NODE}/read_status")
        self.call(fresh, ReadStatus.Request(axis="x"))
        self.node.destroy_client(fresh)
        out["new_service_client"] = since()
        # A new goal through the old action client (back by 1 u).
        self.goal_position -= 1.0
        fut = self.send_goal(self.goal_position).get_result_async()
        self.spin_until(fut.done)
        assert fut.result().status == GoalStatus.STATUS_SUCCEEDED, fut.result()
        out["old_action_client_new_goal"] = since()
        stamp, pos = self.y_sample()
        out["y_error"] = pos - self.y_ref[1] - Y_VELOCITY * (stamp - self.y_ref[0])
        answer(out)


def main():
    c = Clients()
    c.start()
    answer({"ready": True})
    while True:
        ready, _, _ = select.select([sys.stdin], [], [], 0)
        if not ready:
            c.ex.spin_once(timeout_sec=0.02)
            continue
        line = sys.stdin.readline()
        if not line:
            break
        cmd, *args = line.split()
        if cmd == "prepare":
            c.prepare(float(args[0]))
        elif cmd == "check":
            c.check()
        elif cmd == "quit":
            break


if __name__ == "__main__":
    main()
