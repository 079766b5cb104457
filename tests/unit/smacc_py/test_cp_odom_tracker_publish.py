"""CpOdomTracker's path topics: what they carry, that each pose's message is built once, and that
nobody's topic costs nothing (the path grows by a pose per odometry message over a mission)."""

from __future__ import annotations

import math
from types import SimpleNamespace

import pytest
from nav_msgs.msg import Odometry, Path

from ros_tools.geometry import yaw_of
from smacc_py.clients.cl_nav2z import CpOdomTracker
from smacc_py.clients.cl_nav2z.odom_path import WorkingMode
from tests.helpers.smacc_stand_ins import RecordingPublisher


class UnheardPublisher(RecordingPublisher):
    """A publisher nobody subscribes to."""

    def get_subscription_count(self) -> int:
        return 0


def odometry(x: float, y: float, yaw: float) -> Odometry:
    msg = Odometry()
    msg.pose.pose.position.x, msg.pose.pose.position.y = x, y
    msg.pose.pose.orientation.z, msg.pose.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    return msg


def recording_tracker(path_pub: RecordingPublisher | None = None) -> CpOdomTracker:
    """A tracker in RECORD_PATH mode on a machine clock standing still at 3 s; publishes every pose."""
    tracker = CpOdomTracker(publish_period_s=0.0)
    tracker.sm = SimpleNamespace(now=lambda: 3.0)  # type: ignore[assignment]
    tracker._path_pub = path_pub or RecordingPublisher()  # type: ignore[assignment]
    tracker._stacked_pub = RecordingPublisher()  # type: ignore[assignment]
    tracker.set_working_mode(WorkingMode.RECORD_PATH)
    return tracker


def drive(tracker: CpOdomTracker, count: int, start: int = 0) -> None:
    """Feed ``count`` odometry poses 0.1 m apart along x (each one is recorded)."""
    for i in range(start, start + count):
        tracker._on_odom(odometry(0.1 * i, 0.0, 0.05 * i))


def test_the_paths_carry_every_recorded_pose_in_the_odom_frame() -> None:
    tracker = recording_tracker()
    drive(tracker, 3)
    tracker.push_path()
    drive(tracker, 2, start=3)
    working: Path = tracker._path_pub.messages[-1]  # type: ignore[attr-defined]
    stacked: Path = tracker._stacked_pub.messages[-1]  # type: ignore[attr-defined]

    def xy_yaw(path: Path) -> list[float]:
        """x, y, yaw of every pose, flattened."""
        flat = []
        for p in path.poses:
            flat += [p.pose.position.x, p.pose.position.y, yaw_of(p.pose.orientation)]
        return flat

    assert xy_yaw(working) == pytest.approx([0.3, 0.0, 0.15, 0.4, 0.0, 0.2])
    assert xy_yaw(stacked) == pytest.approx([v for i in range(5) for v in (0.1 * i, 0.0, 0.05 * i)])
    frames = {working.header.frame_id, stacked.header.frame_id} | {p.header.frame_id for p in stacked.poses}
    assert frames == {"odom"}
    assert working.header.stamp.sec == 3


def test_each_pose_message_is_built_once_and_reused_while_the_pose_is_recorded() -> None:
    tracker = recording_tracker()
    drive(tracker, 4)
    first, later = tracker._stacked_pub.messages[1], tracker._stacked_pub.messages[-1]  # type: ignore[attr-defined]
    assert len(later.poses) == 4
    assert len(first.poses) == 2
    assert all(a is b for a, b in zip(first.poses, later.poses[:2], strict=True))
    assert tracker._path_pub.messages[-1].poses[0] is later.poses[0]  # type: ignore[attr-defined]


def test_poses_cleared_from_the_paths_are_forgotten() -> None:
    tracker = recording_tracker()
    drive(tracker, 4)
    tracker.push_path()
    drive(tracker, 3, start=4)
    tracker.pop_path()
    assert len(tracker._pose_msgs) == 4
    tracker.clear_path()
    assert tracker._pose_msgs == {}


def test_a_path_nobody_subscribes_to_is_not_built() -> None:
    tracker = recording_tracker(path_pub=UnheardPublisher())
    drive(tracker, 3)
    assert tracker._path_pub.messages == []  # type: ignore[attr-defined]
    assert len(tracker._stacked_pub.messages[-1].poses) == 3  # type: ignore[attr-defined]
