"""The README's rclpy example, run as written (the python block under "From the ros2 CLI and
rclpy") against the demo machine: it must power the axis and end its goal SUCCEEDED at 100."""

import os
import re
import subprocess
import sys

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
