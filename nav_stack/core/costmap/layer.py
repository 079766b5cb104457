"""The layer protocol of a layered costmap and the cell window that bounds an update.

Why: as in nav2_costmap_2d, each update cycle first asks every layer which cells it changed
(``update_bounds``), then the master grid resets only that window and asks the layers, in order,
to write their costs into it (``update_costs``). Keeping updates to a window is what makes large
global costmaps cheap to maintain.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from nav_stack.core.costmap.footprint import Footprint
from nav_stack.core.geometry import Pose2D
from nav_stack.core.grid import GridSpec

CostArray = npt.NDArray[np.uint8]


@dataclass(frozen=True)
class Window:
    """A half-open cell rectangle ``[x0, x1) × [y0, y1)``; empty when x0 >= x1 or y0 >= y1."""

    x0: int
    y0: int
    x1: int
    y1: int

    @classmethod
    def empty(cls) -> Window:
        return cls(0, 0, 0, 0)

    @classmethod
    def full(cls, spec: GridSpec) -> Window:
        return cls(0, 0, spec.width, spec.height)

    @classmethod
    def around(cls, mx: npt.NDArray[np.int64], my: npt.NDArray[np.int64]) -> Window:
        """Smallest window holding the cells ``(mx, my)``."""
        if mx.size == 0:
            return cls.empty()
        return cls(int(mx.min()), int(my.min()), int(mx.max()) + 1, int(my.max()) + 1)

    @property
    def is_empty(self) -> bool:
        return self.x0 >= self.x1 or self.y0 >= self.y1

    def union(self, other: Window) -> Window:
        if self.is_empty:
            return other
        if other.is_empty:
            return self
        return Window(min(self.x0, other.x0), min(self.y0, other.y0),
                      max(self.x1, other.x1), max(self.y1, other.y1))

    def expanded(self, cells: int) -> Window:
        if self.is_empty:
            return self
        return Window(self.x0 - cells, self.y0 - cells, self.x1 + cells, self.y1 + cells)

    def clipped(self, spec: GridSpec) -> Window:
        w = Window(max(self.x0, 0), max(self.y0, 0), min(self.x1, spec.width), min(self.y1, spec.height))
        return w if not w.is_empty else Window.empty()

    @property
    def slices(self) -> tuple[slice, slice]:
        """numpy index ``[rows, cols]`` of the window."""
        return slice(self.y0, self.y1), slice(self.x0, self.x1)


class Layer(ABC):
    """One plugin of a layered costmap."""

    name: str = "layer"
    enabled: bool = True

    def on_resize(self, spec: GridSpec) -> None:  # noqa: B027 - optional hook
        """The master grid was (re)allocated with ``spec``; contents start from scratch."""

    def on_shift(self, spec: GridSpec, dx: int, dy: int) -> None:  # noqa: B027 - optional hook
        """A rolling window moved by ``(dx, dy)`` cells to ``spec``; keep what still overlaps."""

    def on_footprint(self, footprint: Footprint) -> None:  # noqa: B027 - optional hook
        """The robot footprint changed."""

    @abstractmethod
    def update_bounds(self, robot_pose: Pose2D, bounds: Window) -> Window:
        """Return ``bounds`` grown by every cell this layer changed since the last cycle."""

    @abstractmethod
    def update_costs(self, master: CostArray, window: Window) -> None:
        """Write this layer's contribution into ``master`` inside ``window``."""

    @abstractmethod
    def reset(self) -> None:
        """Forget dynamic data (clear_entirely); the next update redraws the whole grid."""


def shifted(grid: CostArray, dx: int, dy: int, fill: int) -> CostArray:
    """Contents of ``grid`` after its origin moves by ``(dx, dy)`` cells; uncovered cells get ``fill``.

    The cell that was at ``[y, x]`` ends at ``[y - dy, x - dx]`` (it stays at the same place in the world).
    """
    out = np.full_like(grid, fill)
    h, w = grid.shape
    if abs(dx) >= w or abs(dy) >= h:
        return out
    src_y = slice(max(dy, 0), h + min(dy, 0))
    src_x = slice(max(dx, 0), w + min(dx, 0))
    dst_y = slice(max(-dy, 0), h + min(-dy, 0))
    dst_x = slice(max(-dx, 0), w + min(-dx, 0))
    out[dst_y, dst_x] = grid[src_y, src_x]
    return out
