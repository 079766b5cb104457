"""The player's pacing, on a fake wall clock: each message leaves when its recorded log-time offset,
divided by ``rate``, has passed, and /clock tracks the bag time at ``clock_hz``.

Why on a fake clock: measured on the real one, the played rate depends on how loaded the machine is
(a CI run played "--rate 2" at x1.23); here the schedule itself is checked, exactly. The integration
test (tests/integration/navsuite_tools/test_bag_sim.py) checks the replay over real DDS.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pytest
from rclpy.serialization import deserialize_message
from std_msgs.msg import String

from navsuite_tools.bag.player import Player, PlayOptions
from navsuite_tools.bag.reader import BagReader
from navsuite_tools.bag.writer import BagWriter

LOG_TIMES_S = (10.0, 10.1, 10.5, 11.0, 12.0)  # when each message was recorded (bag time)


@dataclass
class FakeClock:
    """Wall time that only ``wait`` advances (s)."""

    now_s: float = 1000.0

    def now(self) -> float:
        return self.now_s

    def wait(self, seconds: float) -> None:
        self.now_s += max(seconds, 0.0)


@dataclass
class FakePublisher:
    clock: FakeClock
    sent: list[tuple[float, Any]] = field(default_factory=list)  # (fake wall s, message)

    def publish(self, msg: Any) -> None:
        self.sent.append((self.clock.now(), msg))


@dataclass
class FakeNode:
    clock: FakeClock
    publishers: dict[str, FakePublisher] = field(default_factory=dict)

    def create_publisher(self, msg_type: Any, topic: str, qos: Any) -> FakePublisher:
        return self.publishers.setdefault(topic, FakePublisher(self.clock))


@pytest.fixture
def bag(tmp_path: Path) -> Path:
    path = tmp_path / "paced.mcap"
    with BagWriter(path) as writer:
        writer.add_topic("/chatter", "std_msgs/msg/String")
        for t in LOG_TIMES_S:
            writer.write_message("/chatter", String(data=f"{t}"), round(t * 1e9))
    return path


@pytest.mark.parametrize("rate", [0.5, 1.0, 2.0, 4.0])
def test_each_message_leaves_at_its_offset_divided_by_the_rate(bag: Path, rate: float) -> None:
    clock = FakeClock()
    node = FakeNode(clock)
    with BagReader(bag) as reader:
        Player(node, reader, PlayOptions(bag=bag, rate=rate), clock.wait, clock.now).play_once()  # type: ignore[arg-type]
    sent = node.publishers["/chatter"].sent
    assert [deserialize_message(raw, String).data for _, raw in sent] == [f"{t}" for t in LOG_TIMES_S]
    offsets = [at - 1000.0 for at, _ in sent]
    assert offsets == pytest.approx([(t - LOG_TIMES_S[0]) / rate for t in LOG_TIMES_S], abs=1e-9)


def test_the_clock_tracks_the_bag_time_at_its_rate(bag: Path) -> None:
    clock = FakeClock()
    node = FakeNode(clock)
    with BagReader(bag) as reader:
        Player(node, reader, PlayOptions(bag=bag, rate=2.0, clock_hz=10.0), clock.wait,  # type: ignore[arg-type]
               clock.now).play_once()
    ticks = node.publishers["/clock"].sent
    bag_s = [msg.clock.sec + msg.clock.nanosec * 1e-9 for _, msg in ticks]
    assert bag_s[0] == pytest.approx(LOG_TIMES_S[0]) and bag_s[-1] == pytest.approx(LOG_TIMES_S[-1])
    assert all(later >= earlier for earlier, later in itertools.pairwise(bag_s))
    # bag time = the start + 2 x the wall time elapsed
    for at, stamp in zip((at for at, _ in ticks), bag_s, strict=True):
        assert stamp == pytest.approx(LOG_TIMES_S[0] + 2.0 * (at - 1000.0), abs=1e-6)
    assert len(ticks) >= 10 * (LOG_TIMES_S[-1] - LOG_TIMES_S[0]) / 2.0  # 10 Hz over 1 s of wall time
