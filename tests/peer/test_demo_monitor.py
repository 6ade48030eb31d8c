"""The demo companion (scripts/demo.sh -> monitor.py) on the demo machine (issue 15.14): it
prints the manuals' state names (DiscreteMotion, Enabled, MOVE_PP ...), never bare numbers,
says what to try next, and its driver moves the machine; with --no-driver it only prints and
the axes stay Disabled (the machine does only what the user commands).
Run inside scripts/netns-run; see tests/tests/python_peer.rs.
"""

import os
import re
import subprocess
import sys
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..")


def run_monitor(*extra, seconds=14):
    out = subprocess.run(
        [sys.executable, os.path.join(HERE, "monitor.py"), "--launch", os.environ["MOTION_LAUNCH_BIN"],
         "--config", os.path.join(ROOT, "launch-configs", "demo.yaml"), "--duration", str(seconds), *extra],
        capture_output=True, text=True, timeout=seconds + 60)
    return out.stdout


class DemoMonitor(unittest.TestCase):
    def test_driver_moves_the_machine_and_states_have_names(self):
        out = run_monitor()
        self.assertIn("What to try next", out)
        self.assertIn("--no-driver", out)
        axes = [l for l in out.splitlines() if l.startswith("/axis_node/axis_states: ")]
        self.assertTrue(axes, out)
        self.assertFalse(re.search(r"state \d", out), "bare state numbers:\n" + out)
        self.assertTrue(any("DiscreteMotion" in l or "Standstill" in l for l in axes), "\n".join(axes))
        movers = [l for l in out.splitlines() if l.startswith("/planar_node/state: ")]
        self.assertTrue(any("Enabled" in l for l in movers), "\n".join(movers))
        cell = [l for l in out.splitlines() if l.startswith("/pickplace_node/state: ")]
        self.assertTrue(any(n in l for l in cell for n in ("READY", "MOVE_PP", "PREPARING_PATH")),
                        "\n".join(cell))

    def test_no_driver_leaves_the_machine_alone(self):
        out = run_monitor("--no-driver", seconds=6)
        self.assertNotIn("What to try next", out)
        axes = [l for l in out.splitlines() if l.startswith("/axis_node/axis_states: ")]
        self.assertTrue(axes, out)
        # Nobody powered anything: every axis still Disabled at 0.
        self.assertTrue(all(l.count("Disabled at 0.000") == 3 for l in axes), "\n".join(axes))
        cell = [l for l in out.splitlines() if l.startswith("/pickplace_node/state: ")]
        self.assertTrue(cell and all("DISABLED" in l for l in cell), "\n".join(cell))


if __name__ == "__main__":
    unittest.main()
