"""A stand-in for the `ros2` command line (ros2cli has no PyPI wheels), so that the README's
`ros2 ...` lines run as written. Built on rclpy, as ros2cli is, for the verbs the README uses:

  ros2 service call NAME TYPE [VALUES]              one request, prints the response
  ros2 action send_goal [--feedback] NAME TYPE [VALUES]   one goal, waits for its result
  ros2 topic echo [--once] [--qos-durability D] NAME   prints one message and exits (as --once)

VALUES is YAML, as for ros2cli. Output follows ros2cli's wording ("response:", "Goal finished
with status: SUCCEEDED"). Exit 0 when the call went through, 1 on a timeout or a bad line.
"""

import importlib
import sys
import time

import rclpy
import rclpy.qos
import yaml
from rclpy.action import ActionClient

TIMEOUT = 20.0
STATUS = {1: "ACCEPTED", 2: "EXECUTING", 3: "CANCELING", 4: "SUCCEEDED", 5: "CANCELED", 6: "ABORTED"}


def msg_type(name):
    """`motion_msgs/srv/Power` -> the class."""
    pkg, kind, cls = name.split("/")
    return getattr(importlib.import_module(f"{pkg}.{kind}"), cls)


def set_fields(msg, values):
    """Fills `msg` from a YAML mapping, as ros2cli's set_message_fields does."""
    for key, value in (values or {}).items():
        current = getattr(msg, key)  # AttributeError for an unknown field, as in ros2cli
        if isinstance(value, dict):
            set_fields(current, value)
            continue
        if isinstance(current, float) and isinstance(value, int) and not isinstance(value, bool):
            value = float(value)
        setattr(msg, key, value)
    return msg


def spin_until(node, future, what):
    rclpy.spin_until_future_complete(node, future, timeout_sec=TIMEOUT)
    if not future.done():
        raise TimeoutError(f"{what}: no answer within {TIMEOUT} s")
    return future.result()


def service_call(node, name, type_name, values):
    srv = msg_type(type_name)
    client = node.create_client(srv, name)
    if not client.wait_for_service(timeout_sec=TIMEOUT):
        raise TimeoutError(f"service {name} not available")
    request = set_fields(srv.Request(), values)
    print(f"requester: making request: {request!r}\n")
    response = spin_until(node, client.call_async(request), name)
    print(f"response:\n{response!r}\n")


def send_goal(node, name, type_name, values, feedback):
    action = msg_type(type_name)
    client = ActionClient(node, action, name)
    if not client.wait_for_server(timeout_sec=TIMEOUT):
        raise TimeoutError(f"action {name} not available")
    goal = set_fields(action.Goal(), values)
    print(f"Waiting for an action server to become available...\nSending goal:\n     {goal!r}\n")
    on_feedback = (lambda f: print(f"Feedback:\n    {f.feedback!r}\n")) if feedback else None
    handle = spin_until(node, client.send_goal_async(goal, feedback_callback=on_feedback), name)
    if not handle.accepted:
        print("Goal was rejected.")
        return
    print(f"Goal accepted with ID: {bytes(handle.goal_id.uuid).hex()}\n")
    result = spin_until(node, handle.get_result_async(), name)
    print(f"Result:\n    {result.result!r}\n")
    print(f"Goal finished with status: {STATUS.get(result.status, result.status)}")


def topic_echo(node, name, durability="volatile"):
    deadline = time.monotonic() + TIMEOUT
    type_name = None
    while type_name is None:
        types = dict(node.get_topic_names_and_types())
        if name in types:
            type_name = types[name][0]
        elif time.monotonic() > deadline:
            raise TimeoutError(f"topic {name} not found")
        else:
            rclpy.spin_once(node, timeout_sec=0.1)
    got = []
    qos = rclpy.qos.QoSProfile(
        depth=10, durability=rclpy.qos.DurabilityPolicy.get_from_short_key(durability))
    node.create_subscription(msg_type(type_name), name, got.append, qos)
    while not got:
        if time.monotonic() > deadline:
            raise TimeoutError(f"no message on {name}")
        rclpy.spin_once(node, timeout_sec=0.1)
    print(f"{got[0]!r}\n---")


def main(argv):
    if len(argv) < 3:
        print(__doc__, file=sys.stderr)
        return 1
    rclpy.init()
    node = rclpy.create_node("ros2cli_stand_in")
    try:
        verb = argv[:2]
        args = argv[2:]
        if verb == ["service", "call"]:
            service_call(node, args[0], args[1], yaml.safe_load(args[2]) if len(args) > 2 else {})
        elif verb == ["action", "send_goal"]:
            feedback = "--feedback" in args
            args = [a for a in args if a != "--feedback"]
            send_goal(node, args[0], args[1], yaml.safe_load(args[2]) if len(args) > 2 else {}, feedback)
        elif verb == ["topic", "echo"]:
            durability = "volatile"
            if "--qos-durability" in args:
                i = args.index("--qos-durability")
                durability = args[i + 1]
                del args[i:i + 2]
            args = [a for a in args if a != "--once"]
            topic_echo(node, args[0], durability)
        else:
            print(f"ros2 {' '.join(verb)}: not supported by this stand-in", file=sys.stderr)
            return 1
        return 0
    except (TimeoutError, AttributeError, ValueError) as e:
        print(f"ros2: {e}", file=sys.stderr)
        return 1
    finally:
        node.destroy_node()
        rclpy.shutdown()


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
