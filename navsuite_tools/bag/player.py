"""Replaying an MCAP recording onto the ROS 2 graph (``navsuite-bag play``).

Messages are republished as recorded CDR bytes (no decoding) with the recorded types, at the
recorded log-time spacing divided by ``rate``. Each topic's publisher offers the recorded
publishers' QoS (:func:`navsuite_tools.bag.qos.playback_profile`), so latched topics such as ``/map``
and ``/tf_static`` are transient local again. With ``clock_hz`` the player publishes ``/clock``
from the bag time, so a stack running with ``use_sim_time`` follows the recording (the recorded
``/clock`` topic, if any, is then not replayed).

The player runs in the caller's thread; it waits between messages by spinning the executor with
a timeout (which also serves the node's parameter services), never by blocking callbacks.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import rclpy
from builtin_interfaces.msg import Time
from rclpy.duration import Duration
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rosgraph_msgs.msg import Clock

from navsuite_tools.bag.qos import parse_offered_qos, playback_profile
from navsuite_tools.bag.reader import BagError, BagReader
from navsuite_tools.bag.recorder import full_topic_name, spin_for
from ros_tools.runtime.executor import make_executor
from ros_tools.runtime.runner import StopOnSignal, ros_process
from ros_tools.status_line import StatusLine
from ros_tools.types import import_type

CLOCK_TOPIC = "/clock"


@dataclass(frozen=True)
class PlayOptions:
    """How to replay.

    Attributes:
        bag: the ``.mcap`` file.
        rate: playback speed factor (2.0 plays twice as fast).
        loop: start again at the end, until interrupted.
        clock_hz: publish ``/clock`` from the bag time at this many Hz (wall clock); 0 = off.
        topics: replay only these topics (all recorded topics if empty).
        delay: seconds (wall clock) to wait after creating the publishers, before playing.
        wait_for_subscribers: wait up to this many seconds (wall clock) until every replayed
            topic has a matched subscriber; 0 = do not wait.
        ack_timeout: seconds (wall clock) to wait at the end until reliable subscribers have
            acknowledged everything.
        executor: ``events`` or ``single`` (None: ``$NAVSUITE_EXECUTOR`` or ``events``).
    """

    bag: Path
    rate: float = 1.0
    loop: bool = False
    clock_hz: float = 0.0
    topics: tuple[str, ...] = ()
    delay: float = 0.0
    wait_for_subscribers: float = 0.0
    ack_timeout: float = 2.0
    executor: str | None = None

    def __post_init__(self) -> None:
        if not self.rate > 0:
            raise ValueError(f"rate must be > 0, got {self.rate}")
        if self.clock_hz < 0 or self.delay < 0 or self.wait_for_subscribers < 0 or self.ack_timeout < 0:
            raise ValueError("clock, delay, wait_for_subscribers and ack_timeout must be >= 0")
        object.__setattr__(self, "topics", tuple(full_topic_name(t) for t in self.topics))


def _time_msg(ns: int) -> Time:
    return Time(sec=ns // 1_000_000_000, nanosec=ns % 1_000_000_000)


class Player:
    """Publishers for the recorded topics on an injected node, and the timed replay loop."""

    def __init__(self, node: Node, reader: BagReader, options: PlayOptions,
                 wait: Callable[[float], None], now: Callable[[], float] = time.monotonic) -> None:
        """``wait(seconds)`` must let at most that much wall time pass (e.g. spin with a timeout);
        ``now()`` is the wall clock in s the replay is paced by (a test passes its own)."""
        self._node = node
        self._reader = reader
        self._options = options
        self._wait = wait
        self._now = now
        chosen = reader.check_topics(options.topics) if options.topics else list(reader.topics)
        if options.clock_hz > 0:
            chosen = [topic for topic in chosen if topic != CLOCK_TOPIC]
        self.topics = chosen
        self._publishers: dict[str, Any] = {}
        for topic in chosen:
            info = reader.topics[topic]
            if info.encoding != "cdr":
                raise BagError(f"{reader.path}: topic {topic} has encoding '{info.encoding}', not cdr")
            try:
                cls = import_type(info.type, "msg")
                qos = playback_profile(parse_offered_qos(info.offered_qos, f"{reader.path}: {topic}"))
            except ValueError as exc:
                raise BagError(f"{reader.path}: topic {topic}: {exc}") from None
            self._publishers[topic] = node.create_publisher(cls, topic, qos)
        self._clock_pub = (node.create_publisher(Clock, CLOCK_TOPIC, QoSProfile(depth=10))
                           if options.clock_hz > 0 else None)
        self.published = 0
        self.bag_now_ns = reader.start_ns

    def wait_for_subscribers(self) -> list[str]:
        """Wait until every topic (and /clock) has a matched subscriber; return those still without."""
        deadline = time.monotonic() + self._options.wait_for_subscribers
        publishers = dict(self._publishers)
        if self._clock_pub is not None:
            publishers[CLOCK_TOPIC] = self._clock_pub
        while True:
            lonely = [t for t, pub in publishers.items() if pub.get_subscription_count() == 0]
            if not lonely or time.monotonic() >= deadline:
                return lonely
            self._wait(0.05)

    def _publish_clock(self, bag_ns: int) -> None:
        if self._clock_pub is not None:
            self._clock_pub.publish(Clock(clock=_time_msg(bag_ns)))

    def play_once(self, progress: Callable[[Player], None] = lambda _player: None) -> None:
        """Replay the whole recording once, in real time scaled by ``rate``."""
        rate, start_ns = self._options.rate, self._reader.start_ns
        clock_period = 1.0 / self._options.clock_hz if self._options.clock_hz > 0 else None
        wall_start = self._now()
        next_clock = wall_start
        self.bag_now_ns = start_ns
        self._publish_clock(start_ns)
        for item in self._reader.messages(self.topics):
            due = wall_start + (item.log_time - start_ns) / 1e9 / rate
            while (now := self._now()) < due:
                if clock_period is not None and now >= next_clock:
                    self._publish_clock(start_ns + int((now - wall_start) * rate * 1e9))
                    next_clock = now + clock_period
                step = due - now if clock_period is None else min(due - now, max(0.0, next_clock - now))
                self._wait(step)
                progress(self)
            self.bag_now_ns = item.log_time
            if clock_period is not None and now >= next_clock:
                self._publish_clock(item.log_time)
                next_clock = now + clock_period
            self._publishers[item.topic].publish(item.data)
            self.published += 1
        self._publish_clock(self._reader.end_ns)
        progress(self)

    def flush(self) -> None:
        """Wait (bounded) until reliable subscribers acknowledged every message."""
        timeout = Duration(seconds=self._options.ack_timeout)
        for publisher in self._publishers.values():
            if publisher.qos_profile.reliability == ReliabilityPolicy.RELIABLE:
                publisher.wait_for_all_acked(timeout)


def run_play(options: PlayOptions, status: StatusLine | None = None) -> int:
    """Replay ``options.bag`` (once, or until interrupted with ``loop``); return messages published.

    Raises:
        BagError: unreadable file, unknown topic, or a type that is not installed.
    """
    status = status or StatusLine()
    # Ctrl-C and SIGTERM only raise a flag, checked between spins: a KeyboardInterrupt raised inside the
    # EventsExecutor's spin left callbacks in its C++ callback manager, whose destructor then aborted the
    # process ("Destroying callback manager with callbacks remaining", exit -6, CI 2026-11-29).
    stop = StopOnSignal()

    def wait(seconds: float) -> None:
        spin_for(executor, seconds)
        if stop.requested:
            raise KeyboardInterrupt

    session = ros_process(context=rclpy.Context(), handle_signals=False)  # play()'s signals: its own flag
    with BagReader(options.bag) as reader, session as process:
        context = process.context
        node = Node(f"bag_player_{os.getpid()}", context=context)
        executor = make_executor(options.executor, context)
        executor.add_node(node)
        try:
            player = Player(node, reader, options, wait)
            lonely = player.wait_for_subscribers() if options.wait_for_subscribers > 0 else []
            if lonely:
                status.finish(f"warning: no subscriber on {', '.join(lonely)}; playing anyway")
            end = time.monotonic() + options.delay
            while (left := end - time.monotonic()) > 0:
                wait(left)
            duration = reader.duration_ns / 1e9

            def progress(p: Player) -> None:
                at = (p.bag_now_ns - reader.start_ns) / 1e9
                status.update(f"playing {at:6.1f} / {duration:.1f} s  x{options.rate:g}  {p.published} msgs")

            try:
                player.play_once(progress)
                while options.loop:
                    player.play_once(progress)
            except KeyboardInterrupt:
                pass
            player.flush()
        finally:
            executor.shutdown()
            node.destroy_node()
            stop.restore()
    status.finish(f"played {player.published} messages from {options.bag}")
    return player.published
