"""Host C of tests/hosts/three_hosts.sh: real rclpy (Fast DDS) on its own machine drives the
axis node of host A and the planar node of host B across the subnet: an axis move and a mover
move as action goals, each to SUCCEEDED at its target. Prints one line per step."""

import sys
import time

import rclpy
from action_msgs.msg import GoalStatus
from rclpy.action import ActionClient

from motion_msgs.action import MoveAbsolute, MoverMoveToPosition
from motion_msgs.srv import MoverEnable, Power


def main():
    rclpy.init()
    node = rclpy.create_node("remote_client")
    end = time.monotonic() + 60
    while not {"axis_node", "planar_node"} <= set(node.get_node_names()):
        if time.monotonic() > end:
            print("nodes not discovered:", node.get_node_names())
            return 1
        rclpy.spin_once(node, timeout_sec=0.1)
    print("discovered", sorted(node.get_node_names()), flush=True)

    def call(srv, name, **fields):
        cli = node.create_client(srv, name)
        assert cli.wait_for_service(timeout_sec=30.0), name
        fut = cli.call_async(srv.Request(**fields))
        rclpy.spin_until_future_complete(node, fut, timeout_sec=10.0)
        assert fut.done(), f"{name}: no answer"
        return fut.result()

    def goal(action, name, g):
        ac = ActionClient(node, action, name)
        assert ac.wait_for_server(timeout_sec=30.0), name
        fut = ac.send_goal_async(g)
        rclpy.spin_until_future_complete(node, fut, timeout_sec=10.0)
        handle = fut.result()
        assert handle is not None and handle.accepted, name
        res = handle.get_result_async()
        rclpy.spin_until_future_complete(node, res, timeout_sec=30.0)
        assert res.done(), f"{name}: no result"
        return res.result()

    r = call(Power, "/axis_node/power", axis="x", enable=True, enable_positive=True,
             enable_negative=True, override=100.0)
    assert r.accepted, r.message
    res = goal(MoveAbsolute, "/axis_node/move_absolute",
               MoveAbsolute.Goal(axis="x", position=42.0, velocity=200.0))
    assert res.status == GoalStatus.STATUS_SUCCEEDED and abs(res.result.position - 42.0) < 1e-6
    print("axis on host A at", res.result.position, flush=True)
    r = call(MoverEnable, "/planar_node/mover_enable", mover="m1")
    assert r.accepted, r.message
    time.sleep(0.5)  # the mover enables within a few cycles
    res = goal(MoverMoveToPosition, "/planar_node/mover_move_to_position",
               MoverMoveToPosition.Goal(mover="m1", x=200.0, y=120.0, use_orientation=False))
    assert res.status == GoalStatus.STATUS_SUCCEEDED, res.result.message
    assert abs(res.result.x - 200.0) < 0.1
    print("mover on host B at", res.result.x, res.result.y, flush=True)
    rclpy.shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
