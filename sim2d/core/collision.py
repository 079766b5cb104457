"""Collision handling: the robot footprint against the world's static pymunk shapes.

How: the robot is a kinematic pymunk body moved by the drive model, never pushed by a solver.
Each physics step the motion is split into sub-steps no longer than ``max_substep_translation``
(m) and ``max_substep_rotation`` (rad), and the footprint is queried against the static shapes at
each sub-step end (a swept check), so nothing tunnels at any speed. On an overlap the motion is
bisected to the last free fraction and the robot stops there.

A contact counts once: it stays the same contact while the footprint, inflated by
``contact_margin`` (m), still touches an obstacle, however long the robot pushes.

Other robots (sim2d.core.fleet): each is a named kinematic body in this space carrying its own
footprint, moved with :meth:`CollisionModel.place_robot` whenever it moves. They stop this robot like
any obstacle, and a touch reports the name of the robot touched, so the fleet can count the contact
for both. Without them the space holds static shapes only and every answer is as before.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import pymunk

from sim2d.core.geometry import StaticGeometry
from sim2d.core.robot import Pose2D, RobotModel, integrate


@dataclass(frozen=True)
class CollisionParams:
    """Swept-check resolution and contact hysteresis (m, rad)."""

    max_substep_translation: float = 0.02
    max_substep_rotation: float = 0.1
    bisection_iterations: int = 8
    contact_margin: float = 0.01

    def __post_init__(self) -> None:
        for name in ("max_substep_translation", "max_substep_rotation", "contact_margin"):
            if getattr(self, name) <= 0.0:
                raise ValueError(f"collision.{name}: must be > 0, got {getattr(self, name)}")
        if self.bisection_iterations < 1:
            raise ValueError(f"collision.bisection_iterations: must be >= 1, got {self.bisection_iterations}")


@dataclass(frozen=True)
class MoveResult:
    """Where a motion ended, whether it was blocked, and where the robot touched (map frame, m)."""

    pose: Pose2D
    blocked: bool
    contact: tuple[float, float] | None
    other: str | None = None
    """The robot that blocked the motion (its name in :meth:`CollisionModel.add_robot`); None: the world."""


@dataclass(frozen=True)
class Touch:
    """An overlap found by a query: a contact point (m, map frame) and the robot touched (None: the world)."""

    point: tuple[float, float]
    other: str | None = None


def build_space(geometry: StaticGeometry) -> pymunk.Space:
    """A pymunk space holding every obstacle as a static shape (circle, box or convex polygon)."""
    space = pymunk.Space()
    body = space.static_body
    shapes: list[pymunk.Shape] = [pymunk.Circle(body, float(r), (float(x), float(y)))
                                  for x, y, r in geometry.circles]
    shapes += [pymunk.Poly(body, [(x0, y0), (x1, y0), (x1, y1), (x0, y1)])
               for x0, y0, x1, y1 in geometry.boxes.tolist()]
    shapes += [pymunk.Poly(body, [tuple(p) for p in poly.tolist()]) for poly in geometry.polygons]
    space.add(*shapes)
    return space


class CollisionModel:
    """Moves the robot footprint through a static pymunk space without entering any obstacle."""

    def __init__(self, geometry: StaticGeometry, robot: RobotModel, params: CollisionParams) -> None:
        self.params = params
        self.space = build_space(geometry)
        self._body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        self._shape = pymunk.Poly(self._body, robot.footprint())
        self._inflated = pymunk.Poly(self._body, robot.footprint(), radius=params.contact_margin)
        self.in_contact = False
        self._robots: dict[str, pymunk.Body] = {}          # the other robots, by name
        self._robot_of: dict[pymunk.Shape, str] = {}       # their shapes -> their names

    def _touch(self, pose: Pose2D, shape: pymunk.Poly) -> Touch | None:
        """The contact if ``shape`` placed at ``pose`` overlaps an obstacle, else None.

        A robot among the shapes touched is reported before the world, so that a robot pressed against
        a wall and a robot at once still counts the robot contact for both.
        """
        self._body.position = (pose.x, pose.y)
        self._body.angle = pose.yaw
        shape.cache_bb()
        hits = self.space.shape_query(shape)
        if not hits:
            return None
        hit = hits[0]
        if self._robot_of:
            hit = next((h for h in hits if h.shape in self._robot_of), hit)
        other = self._robot_of.get(hit.shape)
        points = hit.contact_point_set.points
        if not points:
            return Touch((pose.x, pose.y), other)
        point = points[0].point_b
        return Touch((float(point.x), float(point.y)), other)

    def add_robot(self, name: str, robot: RobotModel, pose: Pose2D) -> None:
        """Another robot, ``name``, of model ``robot`` at ``pose`` (map frame): an obstacle that moves."""
        if name in self._robots:
            raise ValueError(f"collision: robot {name!r} is already in this space")
        body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        shape = pymunk.Poly(body, robot.footprint())
        self.space.add(body, shape)
        self._robots[name] = body
        self._robot_of[shape] = name
        self.place_robot(name, pose)

    def place_robot(self, name: str, pose: Pose2D) -> None:
        """Move the other robot ``name`` (:meth:`add_robot`) to ``pose`` (map frame)."""
        body = self._robots[name]
        body.position = (pose.x, pose.y)
        body.angle = pose.yaw
        self.space.reindex_shapes_for_body(body)   # pymunk's index follows a moved body only when told

    def circle_overlaps(self, pose: Pose2D, x: float, y: float, radius: float) -> bool:
        """True when a circle at (x, y) of ``radius`` (m, map frame) would overlap the footprint at ``pose``.

        Why here: the robot's pymunk shape is the one that answers "touching?" everywhere else, so a
        dropped obstacle is refused by the same test that stops the robot at a wall.
        """
        circle = pymunk.Circle(self.space.static_body, radius, (x, y))
        self.space.add(circle)
        self._body.position = (pose.x, pose.y)
        self._body.angle = pose.yaw
        self._shape.cache_bb()
        touching = any(hit.shape is circle for hit in self.space.shape_query(self._shape))
        self.space.remove(circle)
        return touching

    def add_circle(self, pose: Pose2D, x: float, y: float, radius: float) -> bool:
        """Add a static circle (m, map frame) unless it would overlap the footprint at ``pose``."""
        if self.circle_overlaps(pose, x, y, radius):
            return False
        self.space.add(pymunk.Circle(self.space.static_body, radius, (x, y)))
        return True

    def touching(self, pose: Pose2D) -> Touch | None:
        """What the footprint at ``pose`` overlaps (the world or another robot), or None."""
        return self._touch(pose, self._shape)

    def overlaps(self, pose: Pose2D) -> bool:
        """True when the footprint at ``pose`` overlaps an obstacle (teleport check)."""
        return self._touch(pose, self._shape) is not None

    def move(self, pose: Pose2D, v: float, w: float, dt: float) -> MoveResult:
        """Move from ``pose`` with body velocity (v, w) for ``dt`` (s), stopping at the first obstacle."""
        p = self.params
        substeps = max(1, math.ceil(max(abs(v) * dt / p.max_substep_translation,
                                        abs(w) * dt / p.max_substep_rotation)))
        h = dt / substeps
        current = pose
        for _ in range(substeps):
            candidate = integrate(current, v, w, h)
            touch = self._touch(candidate, self._shape)
            if touch is not None:
                return MoveResult(self._bisect(current, v, w, h), True, touch.point, touch.other)
            current = candidate
        return MoveResult(current, False, None)

    def _bisect(self, free: Pose2D, v: float, w: float, h: float) -> Pose2D:
        """Last collision-free pose along the sub-step from ``free`` (found by bisection on time)."""
        low, high = 0.0, h
        for _ in range(self.params.bisection_iterations):
            mid = 0.5 * (low + high)
            if self._touch(integrate(free, v, w, mid), self._shape) is None:
                low = mid
            else:
                high = mid
        return integrate(free, v, w, low)

    def update_contact(self, pose: Pose2D, blocked: bool) -> bool:
        """Track contact state after a step; True when a new contact began (count it once)."""
        if blocked:
            new = not self.in_contact
            self.in_contact = True
            return new
        if self.in_contact and self._touch(pose, self._inflated) is None:
            self.in_contact = False
        return False
