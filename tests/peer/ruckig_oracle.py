"""Time-optimal durations from the PyPI `ruckig` package (the independent oracle).

Reads JSON lines {"p0":..,"p1":..,"v":..,"a":..,"d":..,"j":..} (a move from rest to rest) on
stdin and prints one duration [s] per line. Separate deceleration: ruckig's max_acceleration /
min_acceleration are set by the direction of travel (accelerating uses `a`, braking `d`).
"""
import json
import sys

from ruckig import InputParameter, Result, Ruckig, Trajectory


def duration(m):
    otg = Ruckig(1)
    inp = InputParameter(1)
    inp.current_position = [m["p0"]]
    inp.current_velocity = [0.0]
    inp.current_acceleration = [0.0]
    inp.target_position = [m["p1"]]
    inp.target_velocity = [0.0]
    inp.target_acceleration = [0.0]
    inp.max_velocity = [m["v"]]
    if m["p1"] >= m["p0"]:
        inp.max_acceleration = [m["a"]]
        inp.min_acceleration = [-m["d"]]
    else:
        inp.max_acceleration = [m["d"]]
        inp.min_acceleration = [-m["a"]]
    inp.max_jerk = [m["j"]]
    traj = Trajectory(1)
    res = otg.calculate(inp, traj)
    if res not in (Result.Working, Result.Finished):
        return float("nan")
    return traj.duration


for line in sys.stdin:
    if line.strip():
        print(repr(duration(json.loads(line))))
