"""Demo companion: starts motion_launch on a launch config and, as an independent Cyclone DDS
peer, prints what it sees (state topics with the manuals' state names, /diagnostics) and
drives a little motion (axes every 3 s, movers every 5 s, a workpiece on belt 1 every 2 s), so
a newcomer sees the machine working; --no-driver leaves all motion to the user. Ctrl-C (or
--duration) stops both.

  python3 tests/peer/monitor.py --launch target/release/motion_launch --config launch-configs/demo.yaml
"""

import argparse
import os
import signal
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ros2_peer  # noqa: E402

# State names as the manuals spell them (the messages carry the numbers).
AXIS_STATES = ["Undefined", "Disabled", "Standstill", "ErrorStop", "Stopping", "Homing",
               "DiscreteMotion", "ContinuousMotion", "SynchronizedMotion"]  # MC_AxisStates
MOVER_STATES = ["Invalid", "Disabled", "Enabling", "Enabled", "Disabling", "Error",
                "ErrorPending", "Resetting"]  # MC_PlanarState
PICKPLACE_STATES = ["DISABLED", "READY", "ERROR", "STOP", "SERVICE", "JOGPOS", "JOGNEG",
                    "HOMING", "PREPARING_PATH", "MOVE_PP", "PATH_INTERRUPT"]  # eTMState


def name_of(names, n):
    return names[n] if 0 <= n < len(names) else str(n)


# (topic, type, how to print one sample)
TOPICS = [
    ("/axis_node/axis_states", "motion_msgs/msg/AxisStateArray",
     lambda m: "axes: " + ", ".join(f"{a.name} {name_of(AXIS_STATES, a.motion_state)} at {a.act_pos:.3f}"
                                    for a in m.axes)),
    ("/planar_node/state", "motion_msgs/msg/PlanarState",
     lambda m: "movers: " + ", ".join(f"{v.name} {name_of(MOVER_STATES, v.state)} at ({v.x:.1f}, {v.y:.1f})"
                                      + (f" on {v.track}" if v.track else "") for v in m.movers)),
    ("/pickplace_node/state", "motion_msgs/msg/PickPlaceState",
     lambda m: f"pick&place: {name_of(PICKPLACE_STATES, m.state)}, TCP at ({m.tcp_x:.1f}, {m.tcp_y:.1f}, "
               f"{m.tcp_z:.1f}), gripper {'closed' if m.gripper_closed else 'open'}, "
               f"{sum(len(b.workpieces) for b in m.belts)} workpieces on the belts"),
]

NEXT_STEPS = """What to try next (README "From the ros2 CLI and rclpy" and the node sections):
  scripts/demo.sh --host-network --no-driver     nodes on this machine's loopback, no driver:
                                                 drive them yourself with ros2 / rclpy
  ros2 service call /axis_node/power motion_msgs/srv/Power "{axis: x, enable: true}"
  ros2 action send_goal --feedback /axis_node/move_absolute motion_msgs/action/MoveAbsolute \\
      "{axis: x, position: 100.0, velocity: 500.0}"
  rviz2 (Fixed Frame world): MarkerArray /planar_node/markers and /pickplace_node/markers
  the live view: the page and Foxglove / Lichtblick addresses printed above (README "See it")
  motion_launch CONFIG --record run.mcap, then motion_plot run.mcap --out plots/
Ctrl-C stops the machine."""


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--launch", required=True)
    ap.add_argument("--config", default="launch-configs/demo.yaml")
    ap.add_argument("--duration", type=float, default=None)
    ap.add_argument("--no-driver", action="store_true",
                    help="only print: leave the axes, movers and the cell to your own commands")
    ap.add_argument("--web-bridge", metavar="DIR:PORTS", default=None,
                    help="run the inside half of tests/peer/web_bridge.py (the live view)")
    args = ap.parse_args()
    # This peer speaks the Cyclone request/reply mapping; the nodes take theirs from
    # RMW_IMPLEMENTATION (demo.sh sets rmw_cyclonedds_cpp unless you chose another).
    rmw = os.environ.setdefault("RMW_IMPLEMENTATION", "rmw_cyclonedds_cpp")
    if rmw != "rmw_cyclonedds_cpp" and not args.no_driver:
        print(f"(driver off: the nodes serve {rmw}'s request/reply mapping, this peer speaks "
              "Cyclone's; it only prints)", flush=True)
        args.no_driver = True
    print(NEXT_STEPS if not args.no_driver else
          "Demo machine without driver: it does only what you command (README).", flush=True)

    bridge = None
    if args.web_bridge:
        d, ports = args.web_bridge.rsplit(":", 1)
        bridge = subprocess.Popen([sys.executable, os.path.join(os.path.dirname(__file__), "web_bridge.py"),
                                   "inside", "--dir", d, "--ports", ports])
    proc = subprocess.Popen([args.launch, args.config])
    stop = {"now": False}
    signal.signal(signal.SIGTERM, lambda *_: stop.update(now=True))
    try:
        peer = ros2_peer.Peer(int(os.environ.get("ROS_DOMAIN_ID", "0")))
        readers = []
        for topic, ty, fmt in TOPICS:
            if ty in peer.types:
                readers.append((topic, peer.subscribe(topic, ty), fmt))
        diag = peer.subscribe("/diagnostics", "diagnostic_msgs/msg/DiagnosticArray")
        drivers = [] if args.no_driver else [AxisDriver(peer), PlanarDriver(peer), PickPlaceDriver(peer)]
        t0 = time.monotonic()
        while not stop["now"] and proc.poll() is None:
            if args.duration is not None and time.monotonic() - t0 > args.duration:
                break
            time.sleep(1.0)
            for d in drivers:
                d.tick()
            print(f"--- t = {time.monotonic() - t0:5.1f} s (peer: cyclonedds)", flush=True)
            for topic, r, fmt in readers:
                samples = r.take(N=100)
                if samples:
                    print(f"{topic}: {fmt(samples[-1])}", flush=True)
            for d in diag.take(N=100)[-3:]:
                for st in d.status:
                    kv = {k.key: k.value for k in st.values}
                    print(f"/diagnostics {st.name}: cycles {kv.get('cycles')} jitter p99 "
                          f"{kv.get('jitter_p99_us')} us, max {kv.get('jitter_max_us')} us, "
                          f"overruns {kv.get('overruns')}", flush=True)
    except KeyboardInterrupt:
        pass
    finally:
        if bridge:
            bridge.terminate()
        proc.send_signal(signal.SIGINT)
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            proc.kill()
    return 0


class AxisDriver:
    """Powers the axes of /axis_node and moves each back and forth between 0 and 100."""

    def __init__(self, peer):
        self.peer = peer
        self.ready = False
        self.target = 100.0
        self.axes = []

    def tick(self):
        try:
            if not self.ready:
                states = self.peer.subscribe("/axis_node/axis_states", "motion_msgs/msg/AxisStateArray")
                self.axes = [a.name for a in self.peer.take_one(states, timeout=5).axes]
                self.power = self.peer.service("/axis_node/power", "motion_msgs/srv/Power")
                self.move = self.peer.service("/axis_node/move_absolute", "motion_msgs/srv/MoveAbsolute")
                self.power.wait_for_server(5)
                self.move.wait_for_server(5)
                for a in self.axes:
                    self.power.call(axis=a, enable=True, enable_positive=True, enable_negative=True, override=100.0)
                self.ready = True
                self.last = 0.0
            if time.monotonic() - self.last > 3.0:
                for a in self.axes:
                    r = self.move.call(axis=a, position=self.target, velocity=100.0)
                    if not r.accepted:
                        print(f"move_absolute {a}: rejected {r.error_id:#x} {r.message}", flush=True)
                self.target = 100.0 - self.target
                self.last = time.monotonic()
        except (TimeoutError, KeyError) as e:
            print(f"(axis driver waiting: {e})", flush=True)


class PlanarDriver:
    """Enables the demo movers and the track ring of /planar_node (built from the launch
    config), joins m1 and m3 to the ring and sends them half a lap on opposite sides every
    5 s; shuttles the free movers m2 and m4 along the top row."""

    RING = ("bottom", "right", "top", "left")
    # (m1 target, m3 target): (track, arc length), alternating; both always drive forwards.
    LEGS = ((("bottom", 180.0), ("top", 410.0)), (("top", 410.0), ("bottom", 180.0)))

    def __init__(self, peer):
        self.peer = peer
        self.stage = 0
        self.leg = 0
        self.shuttle = 0
        self.last = 0.0

    def call(self, srv, **kw):
        r = srv.call(**kw)
        if not r.accepted:
            print(f"planar {kw}: rejected {r.error_id:#x} {r.message}", flush=True)

    def tick(self):
        try:
            if self.stage == 0:
                if "motion_msgs/srv/MoverEnable" not in [k.rsplit("_", 1)[0] for k in self.peer.types]:
                    return
                svc = lambda name, ty: self.peer.service(f"/planar_node/{name}", f"motion_msgs/srv/{ty}")
                self.enable = svc("mover_enable", "MoverEnable")
                self.move = svc("mover_move_to_position", "MoverMoveToPosition")
                self.track_enable = svc("track_enable", "TrackEnable")
                self.join = svc("mover_join_track", "MoverJoinTrack")
                self.move_on = svc("mover_move_on_track", "MoverMoveOnTrack")
                for s in (self.enable, self.move, self.track_enable, self.join, self.move_on):
                    s.wait_for_server(5)
                for t in self.RING:
                    self.call(self.track_enable, track=t)
                for m in ("m1", "m2", "m3", "m4"):
                    self.call(self.enable, mover=m)
                self.stage, self.last = 1, time.monotonic()
            elif self.stage == 1 and time.monotonic() - self.last > 1.0:
                for m, t in (("m1", "left"), ("m3", "bottom")):
                    self.call(self.join, mover=m, track=t)
                self.stage, self.last = 2, time.monotonic()
            elif self.stage == 2 and time.monotonic() - self.last > 5.0:
                for m, (t, s) in zip(("m1", "m3"), self.LEGS[self.leg]):
                    self.call(self.move_on, mover=m, track=t, target_position=s)
                self.leg = 1 - self.leg
                for m, xs in (("m2", (120.0, 360.0)), ("m4", (600.0, 840.0))):
                    self.call(self.move, mover=m, x=xs[self.shuttle], y=630.0, c=0.0)
                self.shuttle = 1 - self.shuttle
                self.last = time.monotonic()
        except (TimeoutError, KeyError) as e:
            print(f"(planar driver waiting: {e})", flush=True)


class PickPlaceDriver:
    """Switches the /pickplace_node cell on, starts its endless tracking mode and feeds a
    workpiece onto belt 1 every 2 s."""

    def __init__(self, peer):
        self.peer = peer
        self.ready = False
        self.last = 0.0

    def tick(self):
        try:
            if not self.ready:
                if "motion_msgs/srv/PickPlaceSetEnable_Request" not in self.peer.types:
                    return
                svc = lambda n, t: self.peer.service(f"/pickplace_node/{n}", f"motion_msgs/srv/{t}")
                enable, regulator = svc("set_enable", "PickPlaceSetEnable"), svc("set_regulator_on", "PickPlaceSetRegulatorOn")
                self.execute, self.detect = svc("execute", "PickPlaceExecute"), svc("detect_workpiece", "PickPlaceDetectWorkpiece")
                for s in (enable, regulator, self.execute, self.detect):
                    s.wait_for_server(5)
                enable.call(enable=True)
                regulator.call(regulator_on=True)
                time.sleep(0.5)
                r = self.execute.call(set_target=0)
                if not r.accepted:
                    print(f"pick&place execute: rejected {r.error_id} {r.message}", flush=True)
                self.ready = True
            if time.monotonic() - self.last > 2.0:
                self.detect.call(belt=1, position=[0.0, 0.0, 0.0, 0.0, 0.0, 0.0])
                self.last = time.monotonic()
        except (TimeoutError, KeyError) as e:
            print(f"(pick&place driver waiting: {e})", flush=True)


if __name__ == "__main__":
    sys.exit(main())
