"""Recording topics of a live ROS 2 graph into an MCAP file (``navsuite-bag record``).

Each topic is subscribed with raw (serialized) delivery, so the CDR bytes go to the file without
a deserialize/serialize round trip, and with a QoS adapted to its publishers
(:func:`navsuite_tools.bag.qos.request_for_offers`). Topics are discovered while recording: with
``-a`` (or a regex) every new topic that gets a publisher is added, as ``ros2 bag record`` does.

Log time is the receive time on the node clock in nanoseconds, which is sim time with
``use_sim_time``; messages that arrive before the first ``/clock`` are held back and written with
the first clock value, so a recording never starts at time zero and then jumps.
"""

from __future__ import annotations

import os
import re
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path
from typing import Any, Protocol

import rclpy
from rclpy.clock import Clock, ClockType
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.task import Future
from rclpy.topic_or_service_is_hidden import topic_or_service_is_hidden
from rclpy.validate_full_topic_name import validate_full_topic_name

from navsuite_tools.bag.qos import offered_qos_yaml, request_for_offers
from navsuite_tools.bag.reader import BagError
from navsuite_tools.bag.writer import BagWriter
from ros_tools.runtime.executor import make_executor
from ros_tools.runtime.runner import StopOnSignal, ros_process
from ros_tools.status_line import StatusLine, topic_counts
from ros_tools.types import import_type

SPIN_SLICE = 0.05  # wall s the main loop serves callbacks between its checks


def full_topic_name(name: str) -> str:
    """``scan`` → ``/scan``, validated.

    Raises:
        ValueError: not a valid ROS topic name.
    """
    full = name if name.startswith("/") else "/" + name
    try:
        validate_full_topic_name(full)
    except Exception as exc:  # rclpy raises InvalidTopicNameException with a caret diagram
        raise ValueError(f"invalid topic name '{name}': {str(exc).splitlines()[0]}") from None
    return full


@dataclass(frozen=True)
class RecordOptions:
    """What and how to record.

    Attributes:
        output: the ``.mcap`` file to write (overwritten).
        topics: topics to record (names without a leading slash are made absolute).
        all_topics: record every topic (``-a``), including ones that appear later.
        regex: also record topics whose full name matches this regular expression.
        exclude_regex: never record topics matching this regular expression.
        include_hidden: with ``-a`` or a regex, also record hidden topics (``/_…`` parts).
        max_duration: stop after this many seconds of node clock (sim time with use_sim_time)
            since the first message; 0 records until interrupted.
        use_sim_time: stamp messages with /clock time.
        compression: ``zstd``, ``lz4`` or ``none``.
        discovery_period: seconds (wall clock) between graph polls for new topics.
        topic_timeout: seconds (wall clock) within which every listed topic must get a publisher;
            0 waits forever.
        executor: ``events`` or ``single`` (None: ``$NAVSUITE_EXECUTOR`` or ``events``).
    """

    output: Path
    topics: tuple[str, ...] = ()
    all_topics: bool = False
    regex: str = ""
    exclude_regex: str = ""
    include_hidden: bool = False
    max_duration: float = 0.0
    use_sim_time: bool = False
    compression: str = "zstd"
    discovery_period: float = 0.1
    topic_timeout: float = 10.0
    executor: str | None = None
    _patterns: tuple[Any, Any] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if not (self.topics or self.all_topics or self.regex):
            raise ValueError("nothing to record: give topics, -a (all topics) or --regex")
        if self.max_duration < 0 or self.topic_timeout < 0 or self.discovery_period <= 0:
            raise ValueError("max_duration and topic_timeout must be >= 0 and discovery_period > 0")
        object.__setattr__(self, "topics", tuple(full_topic_name(t) for t in self.topics))
        try:
            patterns = (re.compile(self.regex) if self.regex else None,
                        re.compile(self.exclude_regex) if self.exclude_regex else None)
        except re.error as exc:
            raise ValueError(f"invalid regular expression: {exc}") from None
        object.__setattr__(self, "_patterns", patterns)

    def selects(self, topic: str) -> bool:
        """Whether ``topic`` is to be recorded."""
        include, exclude = self._patterns
        if exclude is not None and exclude.search(topic):
            return False
        if topic in self.topics:
            return True
        if not self.include_hidden and topic_or_service_is_hidden(topic):
            return False
        return self.all_topics or (include is not None and include.fullmatch(topic) is not None)


class TopicSink(Protocol):
    """Where a :class:`Recorder` puts what it receives: a :class:`BagWriter`, or a live stream."""

    def add_topic(self, topic: str, type_name: str, offered_qos: str = "", type_hash: str = "") -> None:
        """Declare a topic before its first message (ValueError: unknown type or definition)."""

    def write(self, topic: str, data: bytes, log_time_ns: int) -> None:
        """Take one CDR-serialized message received at ``log_time_ns`` (node clock, ns)."""


class Recorder:
    """Subscribes to the selected topics on an injected node and writes what arrives to a sink."""

    def __init__(self, node: Node, writer: TopicSink, options: RecordOptions,
                 warn: Callable[[str], None] | None = None) -> None:
        self._node = node
        self._writer = writer
        self._options = options
        self._warn = warn or node.get_logger().warning
        self._subscriptions: dict[str, Any] = {}
        self._skipped: dict[str, str] = {}
        self._pending: list[tuple[str, bytes]] = []
        self.counts: dict[str, int] = {}
        self.first_ns: int | None = None

    def discover(self) -> None:
        """Subscribe to selected topics that appeared (with at least one publisher) since last time."""
        for topic, types in self._node.get_topic_names_and_types():
            if topic in self._subscriptions or topic in self._skipped or not self._options.selects(topic):
                continue
            if len(types) != 1:
                self._skip(topic, f"it has several types ({', '.join(types)})")
                continue
            publishers = self._node.get_publishers_info_by_topic(topic)
            if not publishers:
                continue  # only subscribers so far: wait until someone offers a QoS
            try:
                cls = import_type(types[0], "msg")
                offers = [info.qos_profile for info in publishers]
                self._writer.add_topic(topic, types[0], offered_qos_yaml(offers),
                                       str(publishers[0].topic_type_hash))
            except ValueError as exc:
                self._skip(topic, str(exc))
                continue
            self._subscriptions[topic] = self._node.create_subscription(
                cls, topic, partial(self._on_message, topic), request_for_offers(offers), raw=True,
            )
            self.counts.setdefault(topic, 0)

    def _skip(self, topic: str, reason: str) -> None:
        self._skipped[topic] = reason
        self._warn(f"not recording {topic}: {reason}")

    def _on_message(self, topic: str, data: bytes) -> None:
        now = self._node.get_clock().now().nanoseconds
        if now == 0:  # use_sim_time and no /clock yet
            self._pending.append((topic, data))
            return
        if self._pending:
            pending, self._pending = self._pending, []
            for held_topic, held_data in pending:
                self._write(held_topic, held_data, now)
        self._write(topic, data, now)

    def _write(self, topic: str, data: bytes, now: int) -> None:
        self._writer.write(topic, data, now)
        self.counts[topic] += 1
        if self.first_ns is None:
            self.first_ns = now

    @property
    def elapsed(self) -> float:
        """Seconds of node clock since the first recorded message (0 before it)."""
        if self.first_ns is None:
            return 0.0
        return max(0.0, (self._node.get_clock().now().nanoseconds - self.first_ns) / 1e9)

    def finished(self) -> bool:
        """Whether ``max_duration`` has been reached."""
        return self._options.max_duration > 0 and self.elapsed >= self._options.max_duration

    def missing(self) -> dict[str, str]:
        """Listed topics not yet recorded, with the reason (no publisher yet, or why skipped)."""
        return {
            topic: self._skipped.get(topic, "no publisher")
            for topic in self._options.topics if topic not in self._subscriptions
        }


def spin_for(executor: Any, seconds: float) -> None:
    """Serve callbacks for ``seconds`` (wall) in one call: the EventsExecutor then runs every event
    in C++ without a Python round trip per message (``spin_once`` returns after each one)."""
    executor.spin_until_future_complete(Future(), timeout_sec=seconds)


def run_record(options: RecordOptions, status: StatusLine | None = None) -> dict[str, int]:
    """Record until ``max_duration``, Ctrl-C/SIGTERM or a missing topic.

    The file is always closed with its summary, also when recording ends with an error. Ctrl-C and
    SIGTERM only raise a flag, from the very start: one that lands in a callback would otherwise be
    printed as a fatal callback exception, and one that lands while the node is being set up would
    end the command without closing the file (CI run AW). Returns the message count per topic.

    Raises:
        BagError: a listed topic did not get a publisher within ``topic_timeout``.
    """
    stop = StopOnSignal()
    try:
        return _record(options, status or StatusLine(), stop)
    finally:
        stop.restore()


def _record(options: RecordOptions, status: StatusLine, stop: StopOnSignal) -> dict[str, int]:
    writer = BagWriter(options.output, options.compression)  # fails early on an unwritable path
    with ros_process(context=rclpy.Context(), handle_signals=False) as process:  # record()'s signals
        return _record_in(process.context, writer, options, status, stop)


def _record_in(context: rclpy.Context, writer: BagWriter, options: RecordOptions, status: StatusLine,
               stop: StopOnSignal) -> dict[str, int]:
    node = Node(f"bag_recorder_{os.getpid()}", context=context,
                parameter_overrides=[Parameter("use_sim_time", value=options.use_sim_time)])
    executor = make_executor(options.executor, context)
    executor.add_node(node)
    recorder = Recorder(node, writer, options, warn=lambda text: status.finish(f"warning: {text}"))
    steady = Clock(clock_type=ClockType.STEADY_TIME)
    node.create_timer(options.discovery_period, recorder.discover, clock=steady)
    started = time.monotonic()
    try:
        recorder.discover()
        while not recorder.finished() and not stop.requested:
            spin_for(executor, SPIN_SLICE)
            missing = recorder.missing()
            if missing and options.topic_timeout and time.monotonic() - started > options.topic_timeout:
                reasons = "; ".join(f"{topic} ({why})" for topic, why in missing.items())
                raise BagError(f"unknown topic: {reasons} after {options.topic_timeout:g} s")
            total = sum(recorder.counts.values())
            status.update(f"recording {recorder.elapsed:6.1f} s  {total} msgs  "
                          f"{topic_counts(recorder.counts)}")
    except KeyboardInterrupt:  # off the main thread no flag is installed
        pass
    finally:
        elapsed = recorder.elapsed
        writer.close()
        executor.shutdown()
        node.destroy_node()
    total = sum(recorder.counts.values())
    status.finish(f"recorded {total} messages on {len(recorder.counts)} topics "
                  f"({elapsed:.1f} s) to {options.output}")
    return dict(recorder.counts)
