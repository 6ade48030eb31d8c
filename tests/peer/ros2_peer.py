"""A ROS 2 peer on an independent DDS implementation (the PyPI `cyclonedds` package).

It speaks the ROS 2 wire conventions exactly as rclpy on rmw_cyclonedds_cpp does:
topics `rt/<name>`, services `rq/<name>Request` / `rr/<name>Reply` with type names
`<pkg>::srv::dds_::<Srv>_Request_`, Cyclone's request header (u64 client guid, i64 sequence)
in front of every request and reply, and actions as three services plus the feedback and
status topics under `<action>/_action/`. The message classes are generated from our
.msg/.srv/.action files (msgs/tools/gen_python_types.py), whose output is checked byte for
byte against the Rust types (msgs/tests/python_types.rs).

Loopback only: Cyclone is configured for `lo` without multicast, with 127.0.0.1 as its
only peer; run it inside scripts/netns-run as every DDS test.
"""

import os
import random
import subprocess
import sys
import time
import typing
import uuid
from dataclasses import dataclass, field

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "msgs", "tools"))

LOOPBACK_URI = (
    "<CycloneDDS><Domain><General><Interfaces><NetworkInterface name=\"lo\"/></Interfaces>"
    "<AllowMulticast>false</AllowMulticast></General><Discovery><ParticipantIndex>auto</ParticipantIndex>"
    "<Peers><Peer address=\"127.0.0.1\"/></Peers></Discovery></Domain></CycloneDDS>"
)
# Must be set before the Cyclone library creates its first participant.
os.environ["CYCLONEDDS_URI"] = LOOPBACK_URI

from cyclonedds.core import Policy, Qos  # noqa: E402
from cyclonedds.domain import DomainParticipant  # noqa: E402
from cyclonedds.idl import IdlStruct  # noqa: E402
from cyclonedds.idl import types as idl  # noqa: E402
from cyclonedds.pub import DataWriter  # noqa: E402
from cyclonedds.sub import DataReader  # noqa: E402
from cyclonedds.internal import InvalidSample  # noqa: E402
from cyclonedds.topic import Topic  # noqa: E402
from cyclonedds.util import duration  # noqa: E402

import gen_python_types  # noqa: E402

# GoalStatus values (action_msgs/msg/GoalStatus).
STATUS_SUCCEEDED = 4
STATUS_CANCELED = 5
STATUS_ABORTED = 6


def launch(config, tag, env=None):
    """Starts MOTION_LAUNCH_BIN on `config` (YAML text) as rclpy on rmw_cyclonedds_cpp would
    see it (Cyclone request/reply mapping), on ROS_DOMAIN_ID; returns (process, domain).
    Refuses to run outside the private network namespace (network rule)."""
    if os.environ.get("MOTION_IN_NETNS") != "1":
        raise RuntimeError("run inside scripts/netns-run (network rule)")
    domain = int(os.environ.get("ROS_DOMAIN_ID", "77"))
    cfg = os.path.join(os.environ.get("TMPDIR", "/tmp"), f"peer_{tag}_{os.getpid()}.yaml")
    with open(cfg, "w") as f:
        f.write(config)
    full_env = dict(os.environ, RMW_IMPLEMENTATION="rmw_cyclonedds_cpp", ROS_DOMAIN_ID=str(domain))
    full_env.update(env or {})
    return subprocess.Popen([os.environ["MOTION_LAUNCH_BIN"], cfg], env=full_env), domain


def stop(proc):
    """SIGTERM, then SIGKILL after 10 s."""
    proc.terminate()
    try:
        proc.wait(timeout=10)
    except subprocess.TimeoutExpired:
        proc.kill()


def reliable_qos(depth=10, transient_local=False):
    policies = [Policy.Reliability.Reliable(max_blocking_time=duration(milliseconds=100)),
                Policy.History.KeepLast(depth)]
    policies.append(Policy.Durability.TransientLocal if transient_local else Policy.Durability.Volatile)
    return Qos(*policies)


# Cyclone DDS 11.0.1 (the PyPI wheel) builds a new topic's serializer by walking the domain's
# type-dependency tree without taking its lock (ddspy_topic_create ->
# ddsi_topic_descriptor_from_type -> ddsi_type_resolved_locked), while its "gc" thread frees the
# types of deleted readers, writers and topics from that tree. A topic made just after another
# was dropped crashed the peer now and then (SIGSEGV in that walk, seen under gdb; about once in
# 20 000 service clients made and dropped). Cyclone frees a type only when its last user goes,
# so every type a peer uses is also held by a topic of one participant per domain that lives as
# long as the process: the tree then never shrinks, and grows only on the thread that walks it.
_TYPE_KEEPERS = {}  # domain id -> (participant, {data type: Topic})


def topic(domain_id, dp, name, data_type):
    """Topic(dp, name, data_type), its type kept for the life of the process (see above)."""
    if domain_id not in _TYPE_KEEPERS:
        _TYPE_KEEPERS[domain_id] = (DomainParticipant(domain_id), {})
    keeper, kept = _TYPE_KEEPERS[domain_id]
    if data_type not in kept:
        kept[data_type] = Topic(keeper, name, data_type)
    return Topic(dp, name, data_type)


def valid(samples):
    """The samples that carry data. Cyclone also hands out an InvalidSample when an instance
    loses its last writer (the node's writer lost during a partition): a state change, no data."""
    return [s for s in samples if not isinstance(s, InvalidSample)]


def _with_cyclone_header(cls):
    """The same struct with rmw_cyclonedds's request header in front (same DDS type name)."""
    hints = typing.get_type_hints(cls, include_extras=True)
    ns = {"dataclass": dataclass, "field": field, "IdlStruct": IdlStruct, "idl": idl}
    lines = [
        "@dataclass",
        f"class {cls.__name__}_WithHeader(IdlStruct, typename={cls.__idl_typename__!r}):",
        "    cdds_client_guid: idl.uint64 = 0",
        "    cdds_sequence: idl.int64 = 0",
    ]
    proto = cls()
    for i, (name, ann) in enumerate(hints.items()):
        ns[f"A{i}"] = ann
        ns[f"D{i}"] = getattr(proto, name)
        lines.append(f"    {name}: A{i} = field(default_factory=lambda: __import__('copy').deepcopy(D{i}))")
    exec("\n".join(lines), ns)
    return ns[f"{cls.__name__}_WithHeader"]


def _dds_name(prefix, ros_name, suffix=""):
    assert ros_name.startswith("/"), ros_name
    return f"{prefix}{ros_name}{suffix}"


class Peer:
    """One DDS participant on `domain_id` with ROS 2 helpers."""

    def __init__(self, domain_id, msgs_dir=os.path.join(ROOT, "msgs")):
        self.types = gen_python_types.load_types(msgs_dir)
        self.domain_id = domain_id
        self.dp = DomainParticipant(domain_id)
        self._guid = random.getrandbits(63) or 1
        self._headered = {}

    def type(self, ros_name):
        return self.types[ros_name]

    def headered(self, ros_name):
        if ros_name not in self._headered:
            self._headered[ros_name] = _with_cyclone_header(self.types[ros_name])
        return self._headered[ros_name]

    # Topics -----------------------------------------------------------------------------
    def topic(self, dds_name, data_type):
        return topic(self.domain_id, self.dp, dds_name, data_type)

    def subscribe(self, topic, ros_type, transient_local=False):
        t = self.topic(_dds_name("rt", topic), self.types[ros_type])
        return DataReader(self.dp, t, qos=reliable_qos(transient_local=transient_local))

    def take_one(self, reader, timeout=10.0):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            samples = valid(reader.take(N=1))
            if samples:
                return samples[0]
            time.sleep(0.01)
        raise TimeoutError("no sample within %.1f s" % timeout)

    # Services ---------------------------------------------------------------------------
    def service(self, name, srv_type):
        return ServiceClient(self, name, srv_type)

    def action(self, name, action_type):
        return ActionClient(self, name, action_type)


class ServiceClient:
    """A ROS 2 service client with the Cyclone request/reply mapping."""

    def __init__(self, peer, name, srv_type, request_type=None, response_type=None):
        self.peer = peer
        self.name = name
        req_t = peer.headered(request_type or f"{srv_type}_Request")
        resp_t = peer.headered(response_type or f"{srv_type}_Response")
        self.req_fields = [k for k in typing.get_type_hints(req_t) if not k.startswith("cdds_")]
        self.req_t = req_t
        rq = peer.topic(_dds_name("rq", name, "Request"), req_t)
        rr = peer.topic(_dds_name("rr", name, "Reply"), resp_t)
        self.writer = DataWriter(peer.dp, rq, qos=reliable_qos())
        self.reader = DataReader(peer.dp, rr, qos=reliable_qos())
        self.seq = 0

    def wait_for_server(self, timeout=20.0):
        """Both directions matched (a request sent earlier could lose its reply)."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            w = self.writer.get_matched_subscriptions()
            r = self.reader.get_matched_publications()
            if w and r:
                return  # the server's reply waits for our reader (vendor/README.md)
            time.sleep(0.05)
        raise TimeoutError(f"service {self.name}: no server within {timeout} s")

    def call(self, timeout=10.0, **fields):
        unknown = set(fields) - set(self.req_fields)
        if unknown:
            raise KeyError(f"{self.name}: unknown request fields {sorted(unknown)}")
        self.seq += 1
        req = self.req_t(cdds_client_guid=self.peer._guid, cdds_sequence=self.seq, **fields)
        self.writer.write(req)
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            for s in valid(self.reader.take(N=16)):
                # ros2-client echoes the header bytes back unchanged (see notes/dds.md).
                if s.cdds_client_guid == self.peer._guid and s.cdds_sequence == self.seq:
                    return s
            time.sleep(0.002)
        raise TimeoutError(f"service {self.name}: no reply within {timeout} s")


class ActionClient:
    """A ROS 2 action client: send_goal / get_result / cancel_goal services, feedback topic."""

    def __init__(self, peer, name, action_type):
        self.peer = peer
        base = f"{name}/_action"
        self.send_goal = ServiceClient(peer, f"{base}/send_goal", None,
                                       f"{action_type}_SendGoal_Request", f"{action_type}_SendGoal_Response")
        self.get_result = ServiceClient(peer, f"{base}/get_result", None,
                                        f"{action_type}_GetResult_Request", f"{action_type}_GetResult_Response")
        self.cancel = ServiceClient(peer, f"{base}/cancel_goal", "action_msgs/srv/CancelGoal")
        self.feedback = peer.subscribe(f"{base}/feedback", f"{action_type}_FeedbackMessage")
        self.goal_t = peer.types[f"{action_type}_Goal"]
        self.uuid_t = peer.types["unique_identifier_msgs/msg/UUID"]

    def wait_for_server(self, timeout=20.0):
        for s in (self.send_goal, self.get_result, self.cancel):
            s.wait_for_server(timeout)

    def new_goal_id(self):
        return self.uuid_t(uuid=list(uuid.uuid4().bytes))

    def send(self, timeout=10.0, **goal_fields):
        goal_id = self.new_goal_id()
        resp = self.send_goal.call(timeout=timeout, goal_id=goal_id, goal=self.goal_t(**goal_fields))
        return goal_id, resp.accepted

    def result(self, goal_id, timeout=30.0):
        resp = self.get_result.call(timeout=timeout, goal_id=goal_id)
        return resp.status, resp.result

    def cancel_goal(self, goal_id, timeout=10.0):
        info_t = self.peer.types["action_msgs/msg/GoalInfo"]
        return self.cancel.call(timeout=timeout, goal_info=info_t(goal_id=goal_id))

    def feedback_for(self, goal_id, timeout=10.0):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            for s in valid(self.feedback.take(N=16)):
                if list(s.goal_id.uuid) == list(goal_id.uuid):
                    return s.feedback
            time.sleep(0.01)
        raise TimeoutError("no feedback for the goal")
