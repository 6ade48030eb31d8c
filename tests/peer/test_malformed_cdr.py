"""Malformed CDR on a request topic is dropped and the node keeps serving (issue 12 §6).

Writes requests whose bytes are not a `motion_msgs/srv/Power_Request` (truncated, a string
length far past the end, invalid UTF-8, a bool that is 7, nothing after the header, ...) on
`rq/axis_node/powerRequest` with the request's DDS type name, each from a fresh participant,
then checks that the node still answers a good request and its process is alive.

Usage: python3 test_malformed_cdr.py  (env MOTION_LAUNCH_BIN, ROS_DOMAIN_ID; inside netns-run)
"""

import os
import sys
import time
import unittest
from dataclasses import dataclass

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ros2_peer  # noqa: E402
from cyclonedds.domain import DomainParticipant  # noqa: E402
from cyclonedds.idl import IdlStruct  # noqa: E402
from cyclonedds.idl import types as idl  # noqa: E402
from cyclonedds.pub import DataWriter  # noqa: E402

TYPENAME = "motion_msgs::srv::dds_::Power_Request_"
CONFIG = """
nodes:
  - kind: axis_node
    axes:
      x: {max_velocity: 1000.0, acceleration: 10000.0, deceleration: 10000.0, jerk: 100000.0}
"""


@dataclass
class HeaderOnly(IdlStruct, typename=TYPENAME):
    guid: idl.uint64
    seq: idl.int64


@dataclass
class ThreeBytes(IdlStruct, typename=TYPENAME):
    a: idl.uint8
    b: idl.uint8
    c: idl.uint8


@dataclass
class Words(IdlStruct, typename=TYPENAME):
    guid: idl.uint64
    seq: idl.int64
    words: idl.array[idl.uint32, 2]


@dataclass
class Bytes(IdlStruct, typename=TYPENAME):
    guid: idl.uint64
    seq: idl.int64
    data: idl.sequence[idl.uint8]


def variants():
    yield "header only", HeaderOnly(guid=1, seq=1)
    yield "three bytes", ThreeBytes(a=1, b=2, c=3)
    yield "string length past the end", Words(guid=1, seq=2, words=[0xFFFFFFF0, 0])
    yield "string length 2^31", Words(guid=1, seq=3, words=[0x80000000, 0x41414141])
    # Bytes: a u32 length (= len(data)) is read as the axis string's length, then the data.
    yield "invalid UTF-8 axis", Bytes(guid=1, seq=4, data=[0xFF, 0xFE, 0xFD, 0x00])
    yield "string without its NUL", Bytes(guid=1, seq=5, data=[0x41, 0x42, 0x43, 0x44])
    yield "bool is 7", Bytes(guid=1, seq=6, data=[0x78, 0x00, 0x00, 0x00, 7, 0, 0, 0])
    yield "truncated after the axis", Bytes(guid=1, seq=7, data=[0x78, 0x00])
    yield "a million bytes of zeros", Bytes(guid=1, seq=8, data=[0] * 1_000_000)


class MalformedCdr(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.proc, cls.domain = ros2_peer.launch(CONFIG, "cdr", env={"RUST_LOG": "error"})
        cls.peer = ros2_peer.Peer(cls.domain)
        cls.power = cls.peer.service("/axis_node/power", "motion_msgs/srv/Power")
        cls.power.wait_for_server()

    @classmethod
    def tearDownClass(cls):
        ros2_peer.stop(cls.proc)

    def test_malformed_requests_are_dropped_and_the_node_keeps_serving(self):
        for name, sample in variants():
            dp = DomainParticipant(self.domain)
            topic = ros2_peer.topic(self.domain, dp, "rq/axis_node/powerRequest", type(sample))
            w = DataWriter(dp, topic, qos=ros2_peer.reliable_qos())
            deadline = time.monotonic() + 10
            while not w.get_matched_subscriptions() and time.monotonic() < deadline:
                time.sleep(0.01)
            self.assertTrue(w.get_matched_subscriptions(), f"{name}: not matched")
            w.write(sample)
            time.sleep(0.2)
            del w, topic, dp
            self.assertIsNone(self.proc.poll(), f"node died after '{name}'")
            r = self.power.call(timeout=10.0, axis="x", enable=True)
            self.assertTrue(r.accepted, f"after '{name}': {r.message}")
            print(f"'{name}': dropped, node still serving", file=sys.stderr)


if __name__ == "__main__":
    unittest.main(verbosity=2)
