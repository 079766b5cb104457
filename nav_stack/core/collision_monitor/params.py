"""Parameters of Nav2 Jazzy's ``collision_monitor``: the node, each polygon, each observation source.

Why three dataclasses: Nav2 reads its knobs in three layers. The node's own (frames, topics, timeouts)
sit at the top level; each name in ``polygons`` has its block ``<polygon>.*`` and each name in
``observation_sources`` its block ``<source>.*``. Names and defaults are Jazzy's
(nav2_collision_monitor sources and docs.nav2.org "Collision Monitor Node"); a knob Nav2 leaves
without a default (``polygons``, ``<polygon>.type``, ``action_type``, ``radius``) has an empty one
here that validation refuses with the parameter's name, since Nav2 fails its configure on it too.

Units: metres, seconds, m/s and rad/s.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

import yaml

Point2 = tuple[float, float]


class ActionType(enum.IntEnum):
    """What a polygon does to the command (nav2_msgs/CollisionMonitorState's constants)."""

    DO_NOTHING = 0
    STOP = 1
    SLOWDOWN = 2
    APPROACH = 3
    LIMIT = 4


#: ``<polygon>.action_type`` spellings; "none" is Nav2's (a zone that only the detector reports).
ACTION_TYPES = {"stop": ActionType.STOP, "slowdown": ActionType.SLOWDOWN, "limit": ActionType.LIMIT,
                "approach": ActionType.APPROACH, "none": ActionType.DO_NOTHING}
POLYGON_TYPES = ("polygon", "circle")
SOURCE_TYPES = ("scan", "pointcloud")
#: Jazzy types this port does not implement: named in the refusal so a user knows it is not a typo.
UNSUPPORTED = {"velocity_polygon": "polygon", "range": "source", "polygon": "source"}


def _positive(name: str, value: float) -> None:
    if not (math.isfinite(value) and value > 0.0):
        raise ValueError(f"{name} = {value}: must be > 0")


def _non_negative(name: str, value: float) -> None:
    if not (math.isfinite(value) and value >= 0.0):
        raise ValueError(f"{name} = {value}: must be >= 0")


def parse_points(text: str) -> tuple[Point2, ...]:
    """Jazzy's ``points`` string ``"[[x, y], [x, y], ...]"`` (m, base frame) as vertices.

    Raises ValueError for a text that is not a list of [x, y] pairs or holds fewer than 3 of them.
    (Nav2 Jazzy's parser asks for more than three, though its message says "at least three"; a
    triangle is accepted here.)
    """
    try:
        rows = yaml.safe_load(text)
        vertices = tuple((float(x), float(y)) for x, y in rows)
    except (yaml.YAMLError, TypeError, ValueError) as error:
        raise ValueError(f"points = {text!r}: must look like '[[x, y], [x, y], [x, y], ...]'") from error
    if len(vertices) < 3:
        raise ValueError(f"points = {text!r}: a polygon needs at least 3 points, got {len(vertices)}")
    if not all(math.isfinite(v) for p in vertices for v in p):
        raise ValueError(f"points = {text!r}: every coordinate must be finite")
    return vertices


@dataclass(frozen=True)
class CollisionMonitorParams:
    """The node's own parameters (Nav2 Jazzy code defaults; its nav2_params.yaml sets
    ``state_topic: collision_monitor_state``, ``transform_tolerance 0.2``, ``source_timeout 1.0``,
    ``stop_pub_timeout 2.0``)."""

    base_frame_id: str = "base_footprint"
    odom_frame_id: str = "odom"  # the fixed frame of the base shift correction
    cmd_vel_in_topic: str = "cmd_vel_smoothed"
    cmd_vel_out_topic: str = "cmd_vel"
    state_topic: str = ""  # "" publishes no state
    transform_tolerance: float = 0.1  # s a transform may lag the time asked for
    source_timeout: float = 2.0  # s; older data stops the robot; 0 disables the check
    base_shift_correction: bool = True  # move old data by the robot's motion since its stamp
    stop_pub_timeout: float = 1.0  # s of zero commands published after the robot was stopped
    enable_stamped_cmd_vel: bool = False  # TwistStamped instead of Twist, in and out
    polygons: tuple[str, ...] = ()  # required: Nav2 gives no default
    observation_sources: tuple[str, ...] = ()  # required: Nav2 gives no default
    # Accepted for Nav2 parameter files and ignored: a Python node on one executor thread gains
    # nothing from a SCHED_FIFO priority, and setting one needs privileges a user seldom has.
    use_realtime_priority: bool = False

    def __post_init__(self) -> None:
        for name in ("base_frame_id", "odom_frame_id", "cmd_vel_in_topic", "cmd_vel_out_topic"):
            if not getattr(self, name):
                raise ValueError(f"{name} = '': must be named")
        _non_negative("transform_tolerance", self.transform_tolerance)
        _non_negative("source_timeout", self.source_timeout)
        _non_negative("stop_pub_timeout", self.stop_pub_timeout)
        for name in ("polygons", "observation_sources"):
            names = getattr(self, name)
            if not names or not all(names):
                raise ValueError(f"{name} = {list(names)}: must name at least one, none empty")
            if len(set(names)) != len(names):
                raise ValueError(f"{name} = {list(names)}: a name appears twice")


@dataclass(frozen=True)
class PolygonParams:
    """One ``<polygon>.*`` block.

    The shape is ``points`` (a static polygon), else a topic: ``polygon_sub_topic``
    (geometry_msgs/PolygonStamped) for stop/slowdown/limit zones, ``footprint_topic`` (the costmap's
    published footprint) for an approach polygon. A circle takes ``radius``.
    """

    type: str = ""  # "polygon" or "circle"; required
    action_type: str = ""  # stop, slowdown, limit, approach (or none); required
    points: str = ""  # Jazzy: "[[x, y], ...]" in the base frame; "" = from a topic
    radius: float = 0.0  # m, circle only; required there
    footprint_topic: str = "local_costmap/published_footprint"  # approach without points
    polygon_sub_topic: str = ""  # stop/slowdown/limit without points
    polygon_subscribe_transient_local: bool = False
    min_points: int = 4  # data points inside that trigger the action
    # Deprecated by Nav2 (min_points = max_points + 1 when set, with a warning); -1 = not set. Not in
    # Nav2's defaults: Nav2 leaves it undeclared, a ROS parameter here needs a value.
    max_points: int = -1
    slowdown_ratio: float = 0.5  # slowdown: output = ratio * input
    linear_limit: float = 0.5  # m/s, limit
    angular_limit: float = 0.5  # rad/s, limit
    time_before_collision: float = 2.0  # s, approach: keep this far from the first contact
    simulation_time_step: float = 0.1  # s, approach: step of the forward simulation
    visualize: bool = False  # publish the shape on polygon_pub_topic
    polygon_pub_topic: str = ""  # "" = the polygon's name (the node fills it in)
    enabled: bool = True
    # The observation sources this polygon reads; empty = all (Nav2's sources_names, a backport
    # into Jazzy's 1.3.x releases).
    sources_names: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if self.type not in POLYGON_TYPES:
            hint = " (a Jazzy type not implemented here)" if UNSUPPORTED.get(self.type) == "polygon" else ""
            raise ValueError(f"type = {self.type!r}{hint}: must be one of {', '.join(POLYGON_TYPES)}")
        if self.action_type not in ACTION_TYPES:
            raise ValueError(f"action_type = {self.action_type!r}: must be one of {', '.join(ACTION_TYPES)}")
        if self.type == "circle":
            _positive("radius", self.radius)
        elif self.points:
            parse_points(self.points)
        elif self.action == ActionType.APPROACH and not self.footprint_topic:
            raise ValueError("points = '' and footprint_topic = '': an approach polygon needs one")
        elif self.action != ActionType.APPROACH and not self.polygon_sub_topic:
            raise ValueError("points = '' and polygon_sub_topic = '': a polygon needs static points "
                             "or a topic to receive them from")
        if self.min_points < 1:
            raise ValueError(f"min_points = {self.min_points}: must be >= 1")
        if not 0.0 <= self.slowdown_ratio <= 1.0:
            raise ValueError(f"slowdown_ratio = {self.slowdown_ratio}: must be in [0, 1]")
        _non_negative("linear_limit", self.linear_limit)
        _non_negative("angular_limit", self.angular_limit)
        _positive("time_before_collision", self.time_before_collision)
        _positive("simulation_time_step", self.simulation_time_step)

    @property
    def action(self) -> ActionType:
        """The action type as a number."""
        return ACTION_TYPES[self.action_type]

    @property
    def effective_min_points(self) -> int:
        """``min_points``, or ``max_points + 1`` when the deprecated ``max_points`` is set."""
        return self.max_points + 1 if self.max_points >= 0 else self.min_points

    @property
    def static_vertices(self) -> tuple[Point2, ...] | None:
        """The vertices (m, base frame) given by ``points``, or None when they come from a topic."""
        return parse_points(self.points) if self.type == "polygon" and self.points else None


@dataclass(frozen=True)
class SourceParams:
    """One ``<source>.*`` block: a LaserScan (``scan``) or a PointCloud2 (``pointcloud``)."""

    type: str = "scan"
    topic: str = "scan"
    enabled: bool = True
    # s; defaults to the node's source_timeout (the node passes it in); 0 disables the check.
    source_timeout: float = 2.0
    min_height: float = 0.05  # m, pointcloud: points below (base frame z) are ignored
    max_height: float = 0.5  # m, pointcloud: points above are ignored

    def __post_init__(self) -> None:
        if self.type not in SOURCE_TYPES:
            hint = " (a Jazzy type not implemented here)" if UNSUPPORTED.get(self.type) == "source" else ""
            raise ValueError(f"type = {self.type!r}{hint}: must be one of {', '.join(SOURCE_TYPES)}")
        if not self.topic:
            raise ValueError("topic = '': a source needs a topic")
        _non_negative("source_timeout", self.source_timeout)
        if not self.min_height <= self.max_height:
            raise ValueError(f"min_height = {self.min_height} is above max_height = {self.max_height}")
