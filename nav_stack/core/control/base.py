"""Types every controller shares: velocities, FollowPath error codes, the costmap view, footprints.

Controllers work in the local costmap frame (odom in Nav2): the robot pose, the pruned path and
the costmap all share it, so a controller never needs TF. A footprint model turns poses into
costs and says which costs are collisions; DWB, RPP and the behaviors all use it.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass
from typing import NamedTuple, Protocol

import numpy as np
import numpy.typing as npt

from nav_stack.core.geometry import FloatArray, Pose2D
from nav_stack.core.grid import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, NO_INFORMATION, GridSpec

IntArray = npt.NDArray[np.int64]
BoolArray = npt.NDArray[np.bool_]


class Twist2D(NamedTuple):
    """Planar velocity command: forward speed (m/s) and yaw rate (rad/s)."""

    vx: float
    wz: float


class ControllerErrorCode(enum.IntEnum):
    """nav2_msgs/action/FollowPath result codes (Jazzy)."""

    NONE = 0
    UNKNOWN = 100
    INVALID_CONTROLLER = 101
    TF_ERROR = 102
    INVALID_PATH = 103
    PATIENCE_EXCEEDED = 104
    FAILED_TO_MAKE_PROGRESS = 105
    NO_VALID_CONTROL = 106
    CONTROLLER_TIMED_OUT = 107


class ControllerError(Exception):
    """A controller failure with its FollowPath code; the controller server turns it into a result."""

    code = ControllerErrorCode.UNKNOWN

    def __init__(self, message: str) -> None:
        super().__init__(f"{self.code.name}: {message}")
        self.message = message


class NoValidControl(ControllerError):  # noqa: N818 - Nav2's exception name
    """No admissible command exists (all DWB trajectories rejected, RPP collision ahead)."""

    code = ControllerErrorCode.NO_VALID_CONTROL


class InvalidPath(ControllerError):  # noqa: N818 - Nav2's exception name
    """The path is empty or lies outside the local costmap."""

    code = ControllerErrorCode.INVALID_PATH


@dataclass(frozen=True)
class CostGrid:
    """A costmap snapshot: uint8 costs indexed ``[my, mx]`` and where they lie."""

    costs: npt.NDArray[np.uint8]
    spec: GridSpec

    def __post_init__(self) -> None:
        if self.costs.shape != self.spec.shape:
            raise ValueError(f"cost array shape {self.costs.shape} does not match spec {self.spec.shape}")

    def cost_at(self, x: FloatArray | float, y: FloatArray | float) -> IntArray:
        """Cost of the cells under points (NO_INFORMATION off the grid)."""
        mx, my = self.spec.world_to_cell(x, y)
        inside = self.spec.in_bounds(mx, my)
        out = np.full(np.shape(mx), NO_INFORMATION, dtype=np.int64)
        out[inside] = self.costs[my[inside], mx[inside]]
        return out

    def lethal_clearance(self, x: FloatArray, y: FloatArray, reach: float) -> FloatArray:
        """Distance (m) from each point to the nearest lethal cell (to its square, so that the
        distance stays constant along a straight row of cells), among the cells within ``reach`` (m)
        of the points' bounding box; inf where none is that close. Assumes an unrotated grid."""
        spec = self.spec
        mx, my = spec.world_to_cell(np.array([x.min() - reach, x.max() + reach]),
                                    np.array([y.min() - reach, y.max() + reach]))
        x0, y0 = max(int(mx[0]), 0), max(int(my[0]), 0)
        window = self.costs[y0:max(int(my[1]) + 1, y0), x0:max(int(mx[1]) + 1, x0)]
        rows, cols = np.nonzero(window == LETHAL_OBSTACLE)
        if len(rows) == 0:
            return np.full(np.shape(x), np.inf)
        cx, cy = spec.cell_to_world(cols + x0, rows + y0)
        half = 0.5 * spec.resolution
        dx = np.maximum(np.abs(np.subtract.outer(x, cx)) - half, 0.0)
        dy = np.maximum(np.abs(np.subtract.outer(y, cy)) - half, 0.0)
        return np.asarray(np.hypot(dx, dy).min(axis=-1))


class Footprint(Protocol):
    """Footprint cost function: the cost of the robot standing at poses, and which costs collide."""

    def cost(self, grid: CostGrid, x: FloatArray, y: FloatArray, yaw: FloatArray) -> IntArray: ...

    def collides(self, cost: IntArray) -> BoolArray: ...


@dataclass(frozen=True)
class CircleFootprint:
    """A round robot on an inflated costmap: the centre cell's cost decides (Nav2's radius mode).

    Costs ≥ 253 (inscribed, lethal, unknown/off-grid) mean the disc touches an obstacle.

    ``body``: the robot's real outline when the circle does not contain it, checked against lethal
    cells as well (:func:`motion_collides`). Nav2's TurtleBot3 waffle has robot_radius 0.22 m, but
    its collision box (0.266 × 0.266 m, centred 0.064 m behind the axle) reaches 0.238 m at the rear
    corners: a turn on the spot with the centre 0.22–0.238 m from a pillar swings a corner into it.
    """

    radius: float = 0.22
    body: PolygonFootprint | None = None

    def cost(self, grid: CostGrid, x: FloatArray, y: FloatArray, yaw: FloatArray) -> IntArray:
        return grid.cost_at(x, y)

    def collides(self, cost: IntArray) -> BoolArray:
        return np.asarray(cost >= INSCRIBED_INFLATED_OBSTACLE)


@dataclass(frozen=True)
class PolygonFootprint:
    """A polygon in the robot frame; its cost is the maximum along the outline, lethal collides."""

    points: tuple[tuple[float, float], ...]
    sample_spacing: float = 0.05  # m between outline samples

    def __post_init__(self) -> None:
        if len(self.points) < 3:
            raise ValueError(f"a polygon footprint needs >= 3 points, got {self.points}")

    def outline(self) -> FloatArray:
        """Outline sample points (K, 2) in the robot frame."""
        corners = np.asarray(self.points, dtype=np.float64)
        samples = []
        for a, b in zip(corners, np.roll(corners, -1, axis=0), strict=True):
            n = max(1, math.ceil(float(np.hypot(*(b - a))) / self.sample_spacing))
            samples.append(a + np.arange(n)[:, None] / n * (b - a))
        return np.vstack(samples)

    def inset(self, margin: float) -> PolygonFootprint:
        """The polygon with every edge moved ``margin`` (m) inward; convex polygons, either winding.

        Each corner moves along the bisector of its edges' inward normals n1, n2 by
        margin·(n1 + n2)/(1 + n1·n2), which puts it ``margin`` from both edges.
        """
        corners = np.asarray(self.points, dtype=np.float64)
        edges = np.roll(corners, -1, axis=0) - corners
        twice_area = float(np.sum(corners[:, 0] * edges[:, 1] - corners[:, 1] * edges[:, 0]))  # > 0: CCW
        normals = np.stack([-edges[:, 1], edges[:, 0]], axis=1) * math.copysign(1.0, twice_area)
        normals /= np.hypot(normals[:, 0], normals[:, 1])[:, None]
        before, after = np.roll(normals, 1, axis=0), normals  # the edges ending and starting at each corner
        shift = margin * (before + after) / (1.0 + np.sum(before * after, axis=1))[:, None]
        return PolygonFootprint(tuple((float(a), float(b)) for a, b in corners + shift), self.sample_spacing)

    def cost(self, grid: CostGrid, x: FloatArray, y: FloatArray, yaw: FloatArray) -> IntArray:
        o = self.outline()
        c, s = np.cos(yaw)[..., None], np.sin(yaw)[..., None]
        px = x[..., None] + c * o[:, 0] - s * o[:, 1]
        py = y[..., None] + s * o[:, 0] + c * o[:, 1]
        return np.asarray(grid.cost_at(px, py).max(axis=-1))

    def collides(self, cost: IntArray) -> BoolArray:
        return np.asarray(cost >= LETHAL_OBSTACLE)  # lethal, or unknown / off the grid (255)


#: cells: how far a body touching lethal cells is inset, in turn, to find how deep it is in
BODY_INSETS = (0.0, 0.5, 1.0, 1.5, 2.0)
#: m: how far inside the inscribed band the centre of a circle with a ``body`` may go (the body's own
#: check keeps it off lethal cells). Why: a planned path may run along the band's edge, which cells
#: make ragged. Stopped there (the battery patrol's charging spot, 0.21 m from a pillar's cells), the
#: waffle could not follow its path round the pillar: every pose 5 cm on was "in the band".
BAND_ENTRY = 0.05


def motion_collides(
    footprint: Footprint, grid: CostGrid, x: FloatArray, y: FloatArray, yaw: FloatArray
) -> bool:
    """Whether one simulated motion collides: poses (m, m, rad) along the arrays, starting where the
    robot stands now (index 0).

    Why the exception: the costmap's cells make obstacles look up to about a cell larger than they are, so
    a round robot that passed a pillar with centimetres to spare can find its own cell in the inscribed
    band (253) on the next update, and then every motion, even a turn on the spot, would "collide" and the
    robot would never leave. A round robot inside the band may therefore move within it as long as no pose
    comes closer to a lethal cell than it is now: it can turn, slide along the obstacle or back out, never
    push further in. A circle with a ``body`` (the real outline, checked on its own below) may also enter
    the band, by up to BAND_ENTRY. Lethal and unknown cells always collide; polygon footprints check
    lethal cost only and need no exception. A circle's ``body`` outline must stay off lethal cells too.
    When it already touches one where the robot stands (a side against a pillar), the outline inset by the
    smallest of ``BODY_INSETS`` cells that clears every lethal cell there must stay clear along the
    motion: the robot may slide along or back out, but not push the body further in than it is, to within
    half a cell. (With the circle's rules alone, a turn on the spot keeps the centre's clearance and
    passed, while the rear corner swung into the centre pillar: the robot wedged there.) Deeper than two
    cells, only the circle's rules decide. RPP and the rotation shim use it; DWB does not: for its 400
    trajectories × 35 poses the clearances take about 30 ms a cycle, which slowed the SLAM exploration
    past its time limit.
    """
    if _footprint_collides(footprint, grid, x, y, yaw):
        return True
    outline = footprint.body if isinstance(footprint, CircleFootprint) else None
    if outline is None:
        return False
    for cells in BODY_INSETS:
        body = outline.inset(cells * grid.spec.resolution) if cells else outline
        if not body.collides(body.cost(grid, x[:1], y[:1], yaw[:1]))[0]:
            return bool(body.collides(body.cost(grid, x, y, yaw)).any())
    return False


def body_clear(footprint: Footprint, grid: CostGrid, x: FloatArray, y: FloatArray, yaw: FloatArray,
               cells: float = 0.0) -> bool:
    """Whether a circle's ``body`` outline, inset by ``cells``, stays off lethal cells at every pose;
    True for footprints without a body."""
    outline = footprint.body if isinstance(footprint, CircleFootprint) else None
    if outline is None:
        return True
    body = outline.inset(cells * grid.spec.resolution) if cells else outline
    return not body.collides(body.cost(grid, x, y, yaw)).any()


def body_depth(footprint: Footprint, grid: CostGrid, x: FloatArray, y: FloatArray, yaw: FloatArray,
               levels: tuple[float, ...] = BODY_INSETS) -> float:
    """How deep (cells) a circle's ``body`` outline goes into lethal cells along the poses: the
    smallest of ``levels`` (cells, ascending) whose inset outline stays off them at every pose
    (:func:`body_clear`), found by bisection; inf when even the deepest does not."""
    if body_clear(footprint, grid, x, y, yaw, levels[0]):
        return levels[0]
    low, high = 0, len(levels) - 1  # levels[low] collides; levels[high] is clear once checked
    if not body_clear(footprint, grid, x, y, yaw, levels[high]):
        return math.inf
    while high - low > 1:
        mid = (low + high) // 2
        low, high = (low, mid) if body_clear(footprint, grid, x, y, yaw, levels[mid]) else (mid, high)
    return levels[high]


def _footprint_collides(
    footprint: Footprint, grid: CostGrid, x: FloatArray, y: FloatArray, yaw: FloatArray
) -> bool:
    """The footprint's own rule, with the in-band exception for circles (:func:`motion_collides`)."""
    cost = footprint.cost(grid, x, y, yaw)
    hits = footprint.collides(cost)
    if not hits.any():
        return False
    if not isinstance(footprint, CircleFootprint) or (cost >= LETHAL_OBSTACLE).any():
        return True
    clearance = grid.lethal_clearance(x, y, footprint.radius + grid.spec.resolution)
    if footprint.body is not None:  # the body keeps off lethal cells; the circle may enter the band a little
        floor = min(float(clearance[0]), footprint.radius - BAND_ENTRY)
        return bool(((clearance < floor) & hits).any())
    if cost[0] != INSCRIBED_INFLATED_OBSTACLE:
        return True
    return bool(((clearance < clearance[0]) & hits).any())


def constant_twist_poses(
    pose: Pose2D, cmd: Twist2D, t: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Poses (x, y, yaw arrays) reached from ``pose`` after ``t`` s of the constant command ``cmd``:
    exact circular arcs (a straight line when ``cmd.wz`` is 0), as the collision look-aheads of RPP
    and the behaviors simulate them."""
    yaw = pose.yaw + cmd.wz * t
    if abs(cmd.wz) > 1e-9:
        x = pose.x + cmd.vx / cmd.wz * (np.sin(yaw) - math.sin(pose.yaw))
        y = pose.y - cmd.vx / cmd.wz * (np.cos(yaw) - math.cos(pose.yaw))
    else:
        x = pose.x + cmd.vx * t * math.cos(pose.yaw)
        y = pose.y + cmd.vx * t * math.sin(pose.yaw)
    return x, y, yaw


def turn_in_place(angle: float, current_wz: float, max_wz: float, max_accel: float, period: float) -> float:
    """Angular velocity (rad/s) for an in-place turn of ``angle`` (rad, + = left) this cycle.

    Up to ``max_wz``, at most ``max_accel`` (rad/s²) × ``period`` (s) away from ``current_wz``, and
    never faster than sqrt(2·max_accel·|angle|), the speed from which the turn can still stop on its
    target instead of overshooting it (shared by RPP and the rotation shim).
    """
    dv = max_accel * period
    speed = min(max_wz, math.sqrt(2.0 * max_accel * abs(angle)))
    return min(max(math.copysign(speed, angle), current_wz - dv), current_wz + dv)
