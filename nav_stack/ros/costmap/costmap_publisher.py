"""CostmapPublisher: a costmap's grid topics, published as nav2_costmap_2d's Costmap2DPublisher does.

Topics (all reliable, transient local, depth 1, relative to the costmap node):
- ``costmap`` (nav_msgs/OccupancyGrid) and ``costmap_raw`` (nav2_msgs/Costmap): the whole grid, sent
  on the first publication after activation, when a new subscriber appears on that topic, when the
  grid's size, resolution or origin changes (a rolling window moving), and every cycle when
  ``always_send_full_costmap``;
- ``costmap_updates`` (map_msgs/OccupancyGridUpdate) and ``costmap_raw_updates``
  (nav2_msgs/CostmapUpdate): otherwise, the window of cells redrawn since the last publication.

Each message is built only when its topic has a subscriber, so a costmap nobody watches converts
nothing; the OccupancyGrid values come from Nav2's cost translation table, for the window only. A
subscriber of ``costmap`` keeps its grid current by applying ``costmap_updates`` (as RViz does;
nav_stack.core.costmap.publish.apply_update). Why a new subscriber gets a fresh full grid (Nav2 leaves
it to the latched, possibly old, one): a late viewer would otherwise apply updates to a stale grid.

``costmap_updates`` needs the map_msgs interface package; when it is not installed that one topic is
not offered (the others are).
"""

from __future__ import annotations

import array
from typing import Any

import numpy as np
from nav2_msgs.msg import Costmap, CostmapUpdate
from nav_msgs.msg import OccupancyGrid
from rclpy.node import Node
from rclpy.publisher import Publisher

from nav_stack.core.costmap.layer import CostArray, Window
from nav_stack.core.costmap.publish import PublishTracker, occupancy_of
from nav_stack.core.grid import GridSpec
from nav_stack.ros.common.conversions import costmap_msg, occupancy_msg
from nav_stack.ros.common.qos import LATCHED

try:  # map_msgs is not among the interface packages every install builds
    from map_msgs.msg import OccupancyGridUpdate
except ImportError:  # pragma: no cover - depends on the installed interfaces
    OccupancyGridUpdate = None

class _Topic:
    """One full-grid publisher, its update publisher, and the subscriber count last seen on it."""

    def __init__(self, full: Publisher, update: Publisher | None) -> None:
        self.full, self.update, self.seen = full, update, 0

    def new_subscriber(self) -> bool:
        """True when the full topic has more subscribers than at the last look."""
        count = self.full.get_subscription_count()
        grew, self.seen = count > self.seen, count
        return grew

    def update_subscribed(self) -> Publisher | None:
        """The update publisher when it exists and has a subscriber, else None."""
        return self.update if self.update is not None and self.update.get_subscription_count() > 0 else None


class CostmapPublisher:
    """Publishes a costmap node's grid: :meth:`add_window` after each update, :meth:`prepare` and
    :meth:`send` each publish cycle."""

    def __init__(self, node: Node, frame: str, always_send_full_costmap: bool) -> None:
        self._node, self._frame = node, frame
        self._always_full = always_send_full_costmap
        self._tracker = PublishTracker()
        grid_update = (node.create_publisher(OccupancyGridUpdate, "costmap_updates", LATCHED)
                       if OccupancyGridUpdate is not None else None)
        self._grid = _Topic(node.create_publisher(OccupancyGrid, "costmap", LATCHED), grid_update)
        self._raw = _Topic(node.create_publisher(Costmap, "costmap_raw", LATCHED),
                           node.create_publisher(CostmapUpdate, "costmap_raw_updates", LATCHED))

    @property
    def publishers(self) -> list[Publisher]:
        """Every publisher this made, for the owner to destroy at cleanup."""
        return [p for topic in (self._grid, self._raw) for p in (topic.full, topic.update) if p is not None]

    def add_window(self, window: Window) -> None:
        """Record the window an update redrew (call under the costmap's lock, like the update)."""
        self._tracker.add(window)

    def reset(self) -> None:
        """Send the full grid at the next publication (on activation)."""
        self._tracker.invalidate()

    def prepare(self, costs: CostArray, spec: GridSpec) -> list[tuple[Publisher, Any]]:
        """The messages this cycle needs from ``costs`` (the live master grid), as (publisher, message).

        Call under the costmap's lock: every message holds its own copy of the cells, so the caller
        sends them (:meth:`send`) after releasing it and the planner never waits for DDS.
        """
        new_grid, new_raw = self._grid.new_subscriber(), self._raw.new_subscriber()
        plan = self._tracker.next(spec, force_full=self._always_full)
        stamp = self._node.get_clock().now().to_msg()
        if plan.kind == "full":
            return self._full(costs, spec, stamp, grid=True, raw=True)
        out = self._full(costs, spec, stamp, grid=new_grid, raw=new_raw) if new_grid or new_raw else []
        if plan.kind == "update":
            out += self._update(costs, plan.window, stamp, grid=not new_grid, raw=not new_raw)
        return out

    @staticmethod
    def send(messages: list[tuple[Publisher, Any]]) -> None:
        """Publish what :meth:`prepare` built."""
        for publisher, msg in messages:
            publisher.publish(msg)

    def _full(self, costs: CostArray, spec: GridSpec, stamp: Any, grid: bool, raw: bool
              ) -> list[tuple[Publisher, Any]]:
        out: list[tuple[Publisher, Any]] = []
        if grid and self._grid.full.get_subscription_count() > 0:
            out.append((self._grid.full, occupancy_msg(occupancy_of(costs), spec, self._frame, stamp)))
        if raw and self._raw.full.get_subscription_count() > 0:
            out.append((self._raw.full, costmap_msg(costs, spec, self._frame, stamp)))
        return out

    def _update(self, costs: CostArray, window: Window, stamp: Any, grid: bool, raw: bool
                ) -> list[tuple[Publisher, Any]]:
        out: list[tuple[Publisher, Any]] = []
        cells = costs[window.slices]
        grid_update, raw_update = self._grid.update_subscribed(), self._raw.update_subscribed()
        if grid and grid_update is not None:
            msg = OccupancyGridUpdate()
            msg.header.frame_id, msg.header.stamp = self._frame, stamp
            msg.x, msg.y = window.x0, window.y0
            msg.width, msg.height = window.x1 - window.x0, window.y1 - window.y0
            msg.data = array.array("b", occupancy_of(cells).tobytes())
            out.append((grid_update, msg))
        if raw and raw_update is not None:
            raw_msg = CostmapUpdate()
            raw_msg.header.frame_id, raw_msg.header.stamp = self._frame, stamp
            raw_msg.x, raw_msg.y = window.x0, window.y0
            raw_msg.size_x, raw_msg.size_y = window.x1 - window.x0, window.y1 - window.y0
            raw_msg.data = array.array("B", np.ascontiguousarray(cells).tobytes())
            out.append((raw_update, raw_msg))
        return out
