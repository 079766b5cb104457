"""``WaypointEventDispatcher``: the events a waypoint navigator posts when the robot reaches a waypoint.

SMACC2's navigator keeps one posting function per ``EvWaypoint<i>`` template, bound to its client
and orthogonal when the orthogonal is allocated. Here the templates are ``smacc_py.core.events``'s
``EvWaypoint0`` .. ``EvWaypoint44`` and the binding is ``client.own_event``, so a reached waypoint ``i``
posts ``EvWaypoint<i>[Client, Or](waypoint_index=i, name=...)`` and, for the last waypoint of the
list, ``EvWaypointFinal[Client, Or]`` after it (ABSOLUTE lifetime: the navigator is a component).

Past waypoint 44 there is no per-index event. SMACC2 wraps the index round (waypoint 45 posts
EvWaypoint0 again), which would fire the transitions written for the first waypoints; this
dispatcher posts nothing per index there instead and logs it once. EvWaypointFinal still comes.
"""

from __future__ import annotations

import logging

from smacc_py.clients.cl_nav2z.waypoints_io import Waypoint
from smacc_py.core import EvWaypointFinal, ISmaccClient
from smacc_py.core.events import MAX_WAYPOINT_EVENTS, waypoint_event

_log = logging.getLogger("smacc_py")


class WaypointEventDispatcher:
    """Posts waypoint events on behalf of ``client`` (the navigator's owner)."""

    def __init__(self, client: ISmaccClient) -> None:
        self.client = client
        self._warned_past_last_event = False

    def post_waypoint_event(self, index: int, waypoint: Waypoint, is_last: bool) -> None:
        """Waypoint ``index`` (0-based) was reached: post its EvWaypoint<index>, then EvWaypointFinal
        when ``is_last``."""
        payload = {"waypoint_index": index, "name": waypoint.name}
        if 0 <= index < MAX_WAYPOINT_EVENTS:
            self.client.post_event(self.client.own_event(waypoint_event(index))(**payload))
        elif not self._warned_past_last_event:
            self._warned_past_last_event = True
            _log.warning("WaypointEventDispatcher: waypoint %d has no EvWaypoint event (only 0..%d); "
                         "no per-index events past it", index, MAX_WAYPOINT_EVENTS - 1)
        if is_last:
            self.client.post_event(self.client.own_event(EvWaypointFinal)(**payload))
