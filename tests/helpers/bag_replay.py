"""Replaying a recording with ``navsuite-bag play`` and counting what arrives, per topic.

Shared by the bag tests (a few seconds of sim2d) and the demo's system test (the whole mission):
both ask whether ``play`` puts back on the graph exactly what ``info`` says the file holds.

The counting node subscribes to each recorded topic with the QoS the recorder itself would ask
for, derived from the publishers' profiles stored in the file (``request_for_offers``), so
latched topics (/map, /tf_static, /amcl_pose) are received transient local and best-effort ones
match at all. Subscriptions are raw (no deserialisation): at a few hundred messages per second a
Python test process that decoded every LaserScan and Path would fall behind the player. Only
/clock is decoded, to check the replayed time.
"""

from __future__ import annotations

import time
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile
from rclpy.serialization import deserialize_message
from rosgraph_msgs.msg import Clock

from navsuite_testing.ros import start_python, stop_process
from navsuite_tools.bag.qos import parse_offered_qos, request_for_offers
from navsuite_tools.bag.reader import BagReader
from ros_tools.types import import_type

BAG_CLI = "navsuite_tools.bag.main"
#: History depth of the counting subscriptions: a burst from a player catching up must not
#: overwrite messages the test thread has not taken yet.
COUNT_DEPTH = 1000
#: Wall seconds the player waits for the counter's subscriptions before playing anyway.
SUBSCRIBER_WAIT = 20.0


def bag_info(bag: Path, timeout: float = 60.0) -> dict[str, tuple[str, int]]:
    """``{topic: (type, count)}`` as the ``navsuite-bag info`` command prints it."""
    proc = start_python(BAG_CLI, ["info", str(bag)])
    try:
        proc.wait(timeout=timeout)
    finally:
        output = stop_process(proc)
    assert proc.returncode == 0, output
    topics = {}
    for line in output.splitlines():  # "[Topic information: ]Topic: /odom | Type: … | Count: 90 | …"
        if "Topic: " in line:
            name, *rest = line.split("Topic: ", 1)[1].split(" | ")
            fields = dict(part.strip().split(": ", 1) for part in rest)
            topics[name.strip()] = (fields["Type"], int(fields["Count"]))
    return topics


@dataclass
class TopicCounter:
    """Raw subscriptions on one node that count messages per topic and keep /clock values (ns)."""

    node: Node
    counts: dict[str, int] = field(default_factory=dict)
    clock_ns: list[int] = field(default_factory=list)
    _subscriptions: list[Any] = field(default_factory=list)

    def watch(self, topic: str, msg_type: type, latched: bool = False, qos: QoSProfile | None = None) -> None:
        """Count ``topic``: reliable with a deep queue (transient local if ``latched``), or ``qos``."""
        if qos is None:
            qos = QoSProfile(depth=COUNT_DEPTH, durability=DurabilityPolicy.TRANSIENT_LOCAL if latched
                             else DurabilityPolicy.VOLATILE)
        self.counts[topic] = 0

        def on_message(data: bytes) -> None:
            self.counts[topic] += 1
            if topic == "/clock":
                stamp = deserialize_message(data, Clock).clock
                self.clock_ns.append(stamp.sec * 1_000_000_000 + stamp.nanosec)

        self._subscriptions.append(self.node.create_subscription(msg_type, topic, on_message, qos, raw=True))

    def watch_recorded(self, bag: Path, topics: Iterable[str]) -> None:
        """Count ``topics`` of ``bag`` with their recorded types and the recorder's QoS rule."""
        with BagReader(bag) as reader:
            for topic in topics:
                info = reader.topics[topic]
                offers = parse_offered_qos(info.offered_qos, f"{bag}: {topic}")
                self.watch(topic, import_type(info.type, "msg"), qos=request_for_offers(offers, COUNT_DEPTH))


@dataclass
class Replay:
    """What a finished ``play`` delivered, and the player's exit code and output."""

    counter: TopicCounter
    returncode: int | None
    output: str

    @property
    def counts(self) -> dict[str, int]:
        return self.counter.counts


def play_and_count(context: Context, bag: Path, topics: Sequence[str], expected: Mapping[str, int],
                   play_args: Sequence[str] = (), timeout: float = 60.0) -> Replay:
    """``navsuite-bag play bag --topics …`` to a counter on ``context``, until everything arrived.

    Returns once the player has exited and every topic reached its ``expected`` count, or at the
    ``timeout`` (wall s) with whatever arrived, so the caller's comparison shows the difference.
    Afterwards the queues are drained, so surplus messages (a topic played twice) show up too.
    """
    node = Node("bag_replay_counter", context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    player = None
    try:
        counter = TopicCounter(node)
        counter.watch_recorded(bag, topics)
        player = start_python(BAG_CLI, ["play", str(bag), "--topics", *topics,
                                        "--wait-for-subscribers", str(SUBSCRIBER_WAIT), *play_args])
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline and not (
                player.poll() is not None and all(counter.counts[t] >= n for t, n in expected.items())):
            executor.spin_once(timeout_sec=0.02)
        while True:  # drain: spin until one pass delivers nothing more
            before = sum(counter.counts.values())
            executor.spin_once(timeout_sec=0.2)
            if sum(counter.counts.values()) == before:
                break
        output = stop_process(player)
        return Replay(counter, player.returncode, output)
    finally:
        if player is not None:
            stop_process(player)
        executor.shutdown()
        node.destroy_node()
