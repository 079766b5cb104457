"""The collision monitor's zones: a polygon or a circle in the robot base frame, and its data count.

Why a class with a mutable shape: a zone's outline may come from a topic (a dynamic polygon, or the
costmap's published footprint for an approach zone), so it is unknown until the first message and
changes with each one. Until then the zone is *not set* and Nav2 skips it (no action, no error).

Inside means Nav2's tests: a polygon by the even-odd ray crossing rule (nav_stack.core.costmap's
``points_in_polygon``, the same half-open edge rule as Nav2's ``isPointInside``), a circle by
``x² + y² < radius²``. Points are (N, 2) arrays in metres.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from nav_stack.core.collision_monitor.params import ActionType, PolygonParams
from nav_stack.core.costmap.footprint import points_in_polygon
from nav_stack.core.geometry import FloatArray

#: Vertices of the outline a circle zone publishes for viewers (Nav2's Circle uses 16 edges).
CIRCLE_OUTLINE_EDGES = 16


class Zone:
    """One named polygon of the collision monitor, with its parameters and current shape."""

    def __init__(self, name: str, params: PolygonParams) -> None:
        self.name = name
        self.params = params
        self._vertices: FloatArray | None = None
        if params.type == "circle":
            angles = np.arange(CIRCLE_OUTLINE_EDGES) * (2.0 * math.pi / CIRCLE_OUTLINE_EDGES)
            self._vertices = params.radius * np.column_stack([np.cos(angles), np.sin(angles)])
        elif params.static_vertices is not None:
            self._vertices = np.array(params.static_vertices, dtype=np.float64)

    @property
    def action(self) -> ActionType:
        return self.params.action

    @property
    def enabled(self) -> bool:
        return self.params.enabled

    @property
    def min_points(self) -> int:
        return self.params.effective_min_points

    @property
    def is_set(self) -> bool:
        """False until a dynamic zone received its first valid shape."""
        return self._vertices is not None

    @property
    def dynamic(self) -> bool:
        """True when the shape comes from a topic rather than from the parameters."""
        return self.params.type == "polygon" and not self.params.points

    @property
    def outline(self) -> FloatArray | None:
        """Vertices (M, 2) in the base frame for viewers; a circle as a 16-gon; None when unset."""
        return None if self._vertices is None else self._vertices.copy()

    def set_shape(self, vertices: npt.ArrayLike) -> None:
        """Take a new outline (M >= 3 vertices, m, base frame) from a topic.

        Raises ValueError for fewer than 3 vertices or non-finite values; the old shape stays.
        """
        if self.params.type == "circle":
            raise ValueError(f"{self.name}: a circle's shape is its radius, not vertices")
        pts = np.asarray(vertices, dtype=np.float64).reshape(-1, 2)
        if len(pts) < 3:
            raise ValueError(f"{self.name}: a polygon needs at least 3 points, got {len(pts)}")
        if not np.all(np.isfinite(pts)):
            raise ValueError(f"{self.name}: polygon points must be finite")
        self._vertices = pts

    def inside(self, points: FloatArray) -> npt.NDArray[np.bool_]:
        """Which of ``points`` (..., 2) lie inside the zone; all False while unset."""
        pts = np.asarray(points, dtype=np.float64)
        if self._vertices is None or pts.size == 0:
            return np.zeros(pts.shape[:-1], dtype=bool)
        x, y = pts[..., 0], pts[..., 1]
        if self.params.type == "circle":
            return np.asarray(x * x + y * y < self.params.radius ** 2)
        return points_in_polygon(x, y, self._vertices)

    def count_inside(self, points: FloatArray) -> int:
        """How many of ``points`` (N, 2) lie inside the zone."""
        return int(np.count_nonzero(self.inside(points)))

    def triggered(self, points: FloatArray) -> bool:
        """True when at least ``min_points`` of ``points`` lie inside (Nav2: ``>= min_points``)."""
        return self.count_inside(points) >= self.min_points
