"""A synthetic navigation run written with our own BagWriter, for report and info tests.

A 4 m x 3 m walled map with one pillar, a robot driving an ellipse for 20 s (ground truth at
30 Hz), AMCL estimates at 2 Hz with a seeded error, a global plan every 5 s, two goals, one
collision, and a three-state SMACC2 transition log. Times are sim-time stamps starting at 100 s.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from geometry_msgs.msg import Point, PointStamped, PoseStamped, PoseWithCovarianceStamped
from nav_msgs.msg import OccupancyGrid, Odometry
from nav_msgs.msg import Path as PathMsg
from smacc2_msgs.msg import SmaccTransition, SmaccTransitionLogEntry
from std_msgs.msg import Header

from navsuite_tools.bag.writer import BagWriter

T0 = 100.0
DURATION = 20.0
GT_RATE = 30.0
AMCL_RATE = 2.0
RESOLUTION = 0.05
MAP_SHAPE = (60, 80)  # rows (y), cols (x)
ORIGIN = (-2.0, -1.5)
TRANSITIONS = (  # (time since T0, source, target, tag)
    (0.0, "", "StAcquireSensors", "SUCCESS"),
    (2.0, "StAcquireSensors", "StNavigateToWaypoint", "SUCCESS"),
    (12.0, "StNavigateToWaypoint", "StRecovery", "ABORT"),
    (15.0, "StRecovery", "StNavigateToWaypoint", "SUCCESS"),
)


@dataclass(frozen=True)
class SyntheticRun:
    """What was written: counts per topic, for assertions."""

    path: Path
    counts: dict[str, int]


def _time(t: float):
    from builtin_interfaces.msg import Time

    return Time(sec=int(t), nanosec=round((t - int(t)) * 1e9) % 1_000_000_000)


def _ns(t: float) -> int:
    return round(t * 1e9)


def _pose_at(t: float) -> tuple[float, float, float]:
    phase = 2 * np.pi * t / DURATION
    return 1.2 * np.cos(phase), 0.8 * np.sin(phase), phase + np.pi / 2


def _quat(msg_orientation, yaw: float) -> None:
    msg_orientation.z = float(np.sin(yaw / 2))
    msg_orientation.w = float(np.cos(yaw / 2))


def _map() -> OccupancyGrid:
    grid = np.zeros(MAP_SHAPE, dtype=np.int8)
    grid[0, :] = grid[-1, :] = grid[:, 0] = grid[:, -1] = 100
    grid[25:35, 35:45] = 100
    grid[:, 70:] = np.where(grid[:, 70:] == 100, 100, -1)
    msg = OccupancyGrid()
    msg.header = Header(stamp=_time(T0), frame_id="map")
    msg.info.resolution = RESOLUTION
    msg.info.height, msg.info.width = MAP_SHAPE
    msg.info.origin.position.x, msg.info.origin.position.y = ORIGIN
    msg.info.origin.orientation.w = 1.0
    msg.data = grid.ravel().tolist()
    return msg


def write_synthetic_run(path: Path, seed: int = 7) -> SyntheticRun:
    """Write the run to ``path`` and return per-topic counts."""
    rng = np.random.default_rng(seed)
    counts: dict[str, int] = {}

    def put(writer: BagWriter, topic: str, msg: object, t: float) -> None:
        writer.write_message(topic, msg, _ns(t))
        counts[topic] = counts.get(topic, 0) + 1

    with BagWriter(path) as writer:
        put(writer, "/map", _map(), T0)
        for k in range(int(DURATION * GT_RATE) + 1):
            t = k / GT_RATE
            x, y, yaw = _pose_at(t)
            odom = Odometry(header=Header(stamp=_time(T0 + t), frame_id="map"),
                            child_frame_id="base_footprint")
            odom.pose.pose.position.x, odom.pose.pose.position.y = x, y
            _quat(odom.pose.pose.orientation, yaw)
            put(writer, "/ground_truth", odom, T0 + t)
            if k % int(GT_RATE / AMCL_RATE) == 0:
                est = PoseWithCovarianceStamped(header=Header(stamp=_time(T0 + t), frame_id="map"))
                ex, ey = rng.normal(0.0, 0.05, size=2) + 0.1 * np.exp(-t / 5.0)
                est.pose.pose.position.x, est.pose.pose.position.y = x + ex, y + ey
                _quat(est.pose.pose.orientation, yaw)
                put(writer, "/amcl_pose", est, T0 + t)
            if k % int(GT_RATE * 5) == 0:
                plan = PathMsg(header=Header(stamp=_time(T0 + t), frame_id="map"))
                for s in np.linspace(t, t + 5.0, 20):
                    pose = PoseStamped(header=plan.header)
                    pose.pose.position.x, pose.pose.position.y, _ = _pose_at(float(s))
                    plan.poses.append(pose)
                put(writer, "/plan", plan, T0 + t)
        for t, (x, y) in ((0.5, (-1.2, 0.0)), (10.0, (1.2, 0.0))):
            goal = PoseStamped(header=Header(stamp=_time(T0 + t), frame_id="map"))
            goal.pose.position.x, goal.pose.position.y = x, y
            _quat(goal.pose.orientation, np.pi / 2)
            put(writer, "/goal_pose", goal, T0 + t)
        hit = PointStamped(header=Header(stamp=_time(T0 + 13.0), frame_id="map"), point=Point(x=-1.0, y=-0.5))
        put(writer, "/sim2d/collisions", hit, T0 + 13.0)
        for index, (t, source, target, tag) in enumerate(TRANSITIONS):
            entry = SmaccTransitionLogEntry(timestamp=_time(T0 + t), transition=SmaccTransition(
                index=index, transition_name=f"{source}->{target}", transition_type=tag,
                source_state_name=source, destiny_state_name=target,
            ))
            put(writer, "/SmTest/smacc/transition_log", entry, T0 + t)
    return SyntheticRun(path, counts)
