"""``CpWaypointNavigator``: a waypoint list with a cursor; reaching one posts ``EvWaypoint<i>``.

The list comes from a YAML file, from the given poses, or from the node parameter ``waypoints`` (x, y,
yaw triples). ``CbNavigateNextWaypoint`` sends the waypoint under the cursor; when Nav2 reports success
the navigator's WaypointEventDispatcher posts ``EvWaypoint<i>[ClNav2Z, Or]`` and, after the last one,
``EvWaypointFinal[ClNav2Z, Or]``; then the cursor advances. ``find``/``seek_name`` look a name up as
SMACC2's ``seekName`` does: forward from the cursor first, then backwards, so with repeated names
the nearest one ahead wins.
"""

from __future__ import annotations

import threading
from collections.abc import Sequence

from rcl_interfaces.msg import ParameterDescriptor

from smacc_py.clients.cl_nav2z.waypoints_event_dispatcher import WaypointEventDispatcher
from smacc_py.clients.cl_nav2z.waypoints_io import (
    Waypoint,
    load_waypoints_file,
    waypoints_from_flat,
)
from smacc_py.core import ISmaccComponent
from smacc_py.ros.context import ros_context


class CpWaypointNavigator(ISmaccComponent):
    """Waypoints + cursor (``rewind``, ``forward``, ``seek_name``)."""

    def __init__(
        self,
        waypoints: Sequence[Waypoint | tuple[float, float, float]] | None = None,
        *,
        file: str | None = None,
        parameter: str = "waypoints",
    ) -> None:
        self._given = [w if isinstance(w, Waypoint) else Waypoint(*w) for w in waypoints or ()]
        self.file, self.parameter = file, parameter
        self.waypoints: list[Waypoint] = []
        self._lock = threading.Lock()
        self.current_index = 0

    def on_initialize(self) -> None:
        self.dispatcher = WaypointEventDispatcher(self.owner)
        if self.file:
            self.waypoints = load_waypoints_file(self.file)
        elif self._given:
            self.waypoints = list(self._given)
        else:
            node = ros_context(self.sm).node
            if not node.has_parameter(self.parameter):
                node.declare_parameter(self.parameter, [0.0] * 0, ParameterDescriptor(dynamic_typing=True))
            values = node.get_parameter(self.parameter).value or []
            self.waypoints = waypoints_from_flat(
                list(values), f"node {node.get_name()} parameter {self.parameter}"
            )

    def current(self) -> tuple[int, Waypoint] | None:
        """(index, waypoint) under the cursor, or None past the end."""
        with self._lock:
            i = self.current_index
            return (i, self.waypoints[i]) if i < len(self.waypoints) else None

    def rewind(self) -> None:
        """Cursor back to the first waypoint."""
        with self._lock:
            self.current_index = 0

    def forward(self, count: int = 1) -> None:
        """Skip ``count`` waypoints."""
        with self._lock:
            self.current_index = min(self.current_index + count, len(self.waypoints))

    def find(self, name: str) -> int | None:
        """Index of the waypoint called ``name``: the first at or after the cursor, else the nearest
        before it; None when no waypoint has that name."""
        with self._lock:
            start = min(self.current_index, len(self.waypoints))
            order = [*range(start, len(self.waypoints)), *range(start - 1, -1, -1)]
        return next((i for i in order if self.waypoints[i].name == name), None)

    def named(self) -> str:
        """The waypoint names, for error messages ("none" when no waypoint has a name)."""
        return ", ".join(w.name for w in self.waypoints if w.name) or "none"

    def seek_name(self, name: str) -> int:
        """Put the cursor on the waypoint called ``name`` (see ``find``) and return its index; ValueError
        naming the known names when there is none."""
        index = self.find(name)
        if index is None:
            raise ValueError(f"CpWaypointNavigator: no waypoint named {name!r} (named: {self.named()})")
        with self._lock:
            self.current_index = index
        return index

    def on_reached(self, index: int) -> None:
        """Post EvWaypoint<index> (and EvWaypointFinal after the last) for the owning client; advance."""
        if 0 <= index < len(self.waypoints):
            is_last = index == len(self.waypoints) - 1
            self.dispatcher.post_waypoint_event(index, self.waypoints[index], is_last)
        with self._lock:
            if self.current_index == index:
                self.current_index = index + 1
