"""The README's examples, run as written against the demo machine: the rclpy example (the
python block under "From the ros2 CLI and rclpy") must power the axis and end its goal
SUCCEEDED at 100; every `ros2` CLI line must go through (issue 15.14)."""

import os
import re
import subprocess
import sys
import time

from conftest import launch

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")


def readme_example():
    with open(os.path.join(ROOT, "README.md")) as f:
        text = f.read()
    section = text[text.index("### From the ros2 CLI and rclpy"):]
    return re.search(r"```python\n(.*?)```", section, re.S).group(1)


def test_the_readme_rclpy_example_runs_as_written():
    with open(os.path.join(ROOT, "launch-configs", "demo.yaml")) as f:
        demo = launch(f.read())
    try:
        out = subprocess.run([sys.executable, "-c", readme_example()], capture_output=True,
                             text=True, timeout=120)
    finally:
        demo.stop()
    assert out.returncode == 0, out.stderr
    assert "power accepted: True" in out.stdout, out.stdout
    assert "status: 4 position: 100.0" in out.stdout, out.stdout
    assert "at " in out.stdout  # feedback while the axis moved


DOCS = [os.path.join("docs", p) for p in ("axis_node.md", "pickplace_node.md", "planar_node.md")]


def cli_lines():
    """Every `ros2 ...` line of the user guide's and the README's shell blocks (a `for` loop
    counts as one line), in order (guide pages first: the README's last block stops `x`),
    with the page and heading of its section."""
    lines = []
    for page in DOCS + ["README.md"]:
        with open(os.path.join(ROOT, page)) as f:
            text = f.read()
        for block in re.finditer(r"```\n(.*?)```", text, re.S):
            heading = re.findall(r"^#+ (.*)$", text[: block.start()], re.M)[-1]
            for line in block.group(1).splitlines():
                if line.startswith("ros2 ") or (line.startswith("for ") and " ros2 " in line):
                    lines.append((f"{page}: {heading}", line))
    return lines


def test_the_readme_ros2_cli_lines_run_as_written(tmp_path):
    """Every `ros2` line of the README (axis, planar and pick-and-place blocks) against the
    demo machine, typed one after the other as a user would (0.5 s apart), through a `ros2`
    that is tests/rclpy/ros2_cli.py (ros2cli has no wheels): each must go through, no
    service may refuse (accepted=False), every goal must end SUCCEEDED."""
    lines = cli_lines()
    for node in ("/axis_node/", "/planar_node/", "/pickplace_node/"):
        assert any(node in l for _, l in lines), f"no ros2 example line for {node}"
    shim = tmp_path / "ros2"
    shim.write_text(f"#!/bin/sh\nexec {sys.executable} "
                    f"{os.path.join(os.path.dirname(os.path.abspath(__file__)), 'ros2_cli.py')} \"$@\"\n")
    shim.chmod(0o755)
    env = dict(os.environ, PATH=f"{tmp_path}:{os.environ['PATH']}")
    with open(os.path.join(ROOT, "launch-configs", "demo.yaml")) as f:
        demo = launch(f.read())
    failures = []
    try:
        for heading, line in lines:
            out = subprocess.run(["bash", "-c", line], capture_output=True, text=True,
                                 timeout=120, env=env)
            text = out.stdout + out.stderr
            calls = line.count("ros2 ")
            if out.returncode != 0:
                failures.append(f"[{heading}] {line}\n  exit {out.returncode}: {text[-600:]}")
            elif "accepted=False" in text:
                failures.append(f"[{heading}] {line}\n  refused: {text[-600:]}")
            elif " send_goal " in line and text.count("Goal finished with status: SUCCEEDED") != calls:
                failures.append(f"[{heading}] {line}\n  goal did not succeed: {text[-600:]}")
            elif " topic echo " in line and "---" not in text:
                failures.append(f"[{heading}] {line}\n  no message: {text[-600:]}")
            time.sleep(0.5)
    finally:
        demo.stop()
    assert not failures, "\n".join(failures)


def test_the_guide_names_every_service_action_and_topic(ros):
    """docs/<node>.md names every service, action and topic each node of the demo offers (the
    last name component in a code span), so the guide's FB maps are complete (issue 15.13)."""
    import rclpy  # noqa: F401
    node, ex = ros
    with open(os.path.join(ROOT, "launch-configs", "demo.yaml")) as f:
        demo = launch(f.read())
    missing = []
    try:
        for name in ("axis_node", "planar_node", "pickplace_node"):
            with open(os.path.join(ROOT, "docs", f"{name}.md")) as f:
                page = f.read()
            spans = " ".join(re.findall(r"`([^`]+)`", page))
            # Discovery fills the graph over time: wait until it has not grown for 3 s.
            end = time.monotonic() + 60
            services, topics, stable_since, seen = [], [], time.monotonic(), -1
            while time.monotonic() < end:
                ex.spin_once(timeout_sec=0.2)
                try:
                    services = node.get_service_names_and_types_by_node(name, "/")
                    topics = node.get_publisher_names_and_types_by_node(name, "/")
                except Exception:  # not yet discovered
                    services, topics = [], []
                count = len(services) + len(topics)
                if count != seen:
                    seen, stable_since = count, time.monotonic()
                elif count > 0 and time.monotonic() - stable_since > 3.0:
                    break
            assert services, f"{name} not discovered"
            names = set()
            for full, _ in services:
                if "/_action/" in full:
                    full = full.split("/_action/")[0]
                names.add(full)
            for full, _ in topics:
                if "/_action/" not in full:
                    names.add(full)
            for full in sorted(names):
                last = full.rsplit("/", 1)[-1]
                if last in ("describe_parameters", "get_parameter_types", "get_parameters",
                            "list_parameters", "set_parameters", "set_parameters_atomically",
                            "get_type_description", "rosout", "parameter_events", "clock",
                            "tf_static", "diagnostics", "joint_states"):
                    continue  # ROS-wide names, on the README's page
                if not re.search(r"(^|[/\s~])" + re.escape(last) + r"($|[\s,])", spans):
                    missing.append(f"{name}: {full}")
    finally:
        demo.stop()
    assert not missing, "not in the guide:\n" + "\n".join(missing)
