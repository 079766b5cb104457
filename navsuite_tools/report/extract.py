"""From a recording to :class:`RunData`: the topics a report draws, as numpy arrays.

Topics are found by type and by the last part of their name, so namespaced runs work too:
an ``OccupancyGrid`` named ``…/map``, an ``Odometry`` named ``…/ground_truth`` (sim2d), a
``PoseWithCovarianceStamped`` named ``…/amcl_pose``, a ``Path`` named ``…/plan``, a
``PoseStamped`` named ``…/goal_pose``, a ``PointStamped`` named ``…/collisions`` (sim2d) and a
``SmaccTransitionLogEntry`` named ``/<Sm>/smacc/transition_log``. Times are message stamps in
seconds (sim time when the run used it); plans are ordered by their log time.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from rclpy.serialization import deserialize_message

from navsuite_tools.bag.reader import BagMessage, BagReader
from navsuite_tools.report.analysis import Trajectory, Transition, make_trajectory
from ros_tools.geometry import yaw_of
from ros_tools.types import import_type

_TRANSITION_SUFFIX = "/smacc/transition_log"
_TRANSITION_TYPE = "smacc2_msgs/msg/SmaccTransitionLogEntry"


@dataclass(frozen=True)
class GridMap:
    """An occupancy grid: ``data`` (rows = y, cols = x) in -1 (unknown) or 0..100, cell size in m,
    and the map origin (x, y in m, yaw in rad) of cell (0, 0)."""

    data: np.ndarray
    resolution: float
    origin: tuple[float, float, float]

    @property
    def extent(self) -> tuple[float, float, float, float]:
        """(x_min, x_max, y_min, y_max) in m (the origin's yaw is not drawn)."""
        height, width = self.data.shape
        x0, y0, _ = self.origin
        return x0, x0 + width * self.resolution, y0, y0 + height * self.resolution


@dataclass
class RunData:
    """Everything a report shows; empty fields mean the topic was not recorded."""

    source: Path
    duration: float = 0.0
    first_map: GridMap | None = None
    last_map: GridMap | None = None
    map_count: int = 0
    truth: Trajectory | None = None
    amcl: Trajectory | None = None
    plans: list[np.ndarray] = field(default_factory=list)
    goals: np.ndarray = field(default_factory=lambda: np.empty((0, 3)))
    collisions: np.ndarray = field(default_factory=lambda: np.empty((0, 3)))
    transitions: list[Transition] = field(default_factory=list)

    def time_origin(self) -> float:
        """The earliest stamp among the timed series (s), the zero of the report's time axes."""
        starts = [series.t[0] for series in (self.truth, self.amcl) if series is not None and len(series)]
        starts += [tr.t for tr in self.transitions]
        starts += list(self.collisions[:, 0])
        return float(min(starts)) if starts else 0.0


def _stamp(stamp: Any) -> float:
    return float(stamp.sec) + float(stamp.nanosec) * 1e-9


def _topics(reader: BagReader, type_name: str, suffix: str) -> list[str]:
    return [name for name, info in reader.topics.items()
            if info.type == type_name and (name == suffix or name.endswith("/" + suffix.lstrip("/")))]


def _grid(msg: Any) -> GridMap:
    info = msg.info
    data = np.asarray(msg.data, dtype=np.int8).reshape(info.height, info.width)
    origin = info.origin
    pose = (origin.position.x, origin.position.y, yaw_of(origin.orientation))
    return GridMap(data, float(info.resolution), pose)


def _decode(message: BagMessage) -> Any:
    return deserialize_message(message.data, import_type(message.type, "msg"))


def _poses(reader: BagReader, topics: list[str]) -> Trajectory | None:
    """Odometry and PoseWithCovarianceStamped both carry ``header`` and ``pose.pose``."""
    t, xy, yaw = [], [], []
    for _item, msg in reader.decoded(topics):
        pose = msg.pose.pose
        t.append(_stamp(msg.header.stamp))
        xy.append((pose.position.x, pose.position.y))
        yaw.append(yaw_of(pose.orientation))
    return make_trajectory(t, xy, yaw) if t else None


def load_run(path: str | Path) -> RunData:
    """Read the report's topics from an MCAP recording.

    Raises:
        BagError: the file cannot be read or a message does not decode.
    """
    with BagReader(path) as reader:
        run = RunData(source=Path(path), duration=reader.duration_ns / 1e9)
        maps = _topics(reader, "nav_msgs/msg/OccupancyGrid", "/map")
        if maps:
            first = last = None
            for item in reader.messages(maps[:1]):
                first = first or item
                last = item
                run.map_count += 1
            if first is not None and last is not None:
                run.first_map, run.last_map = _grid(_decode(first)), _grid(_decode(last))
        run.truth = _poses(reader, _topics(reader, "nav_msgs/msg/Odometry", "ground_truth"))
        run.amcl = _poses(reader, _topics(reader, "geometry_msgs/msg/PoseWithCovarianceStamped", "amcl_pose"))
        for _item, msg in reader.decoded(_topics(reader, "nav_msgs/msg/Path", "plan")):
            if msg.poses:
                run.plans.append(np.array([(p.pose.position.x, p.pose.position.y) for p in msg.poses]))
        goal_topics = _topics(reader, "geometry_msgs/msg/PoseStamped", "goal_pose")
        goals = [(p.pose.position.x, p.pose.position.y, yaw_of(p.pose.orientation))
                 for _item, p in reader.decoded(goal_topics)]
        run.goals = np.array(goals).reshape(-1, 3)
        hit_topics = _topics(reader, "geometry_msgs/msg/PointStamped", "collisions")
        hits = [(_stamp(m.header.stamp), m.point.x, m.point.y) for _item, m in reader.decoded(hit_topics)]
        run.collisions = np.array(hits).reshape(-1, 3)
        logs = [name for name, info in reader.topics.items()
                if info.type == _TRANSITION_TYPE and name.endswith(_TRANSITION_SUFFIX)]
        for item, entry in reader.decoded(logs):
            machine = item.topic[: -len(_TRANSITION_SUFFIX)].strip("/") or "sm"
            tr = entry.transition
            run.transitions.append(Transition(
                _stamp(entry.timestamp), machine, tr.source_state_name, tr.destiny_state_name,
                tr.transition_type, tr.event.event_type,
            ))
    return run
