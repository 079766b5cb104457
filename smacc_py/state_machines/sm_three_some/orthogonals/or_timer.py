"""``OrTimer``: a ClRosTimer ticking every 0.5 s (``createClient<cl_ros_timer::ClRosTimer>(500ms)``)."""

from __future__ import annotations

from smacc_py.clients.cl_ros_timer import ClRosTimer
from smacc_py.core import Orthogonal

TICK_S = 0.5  # s of node clock between two ticks


class OrTimer(Orthogonal):
    """The states' timeouts, counted in ticks of one client timer."""

    def on_initialize(self) -> None:
        self.create_client(ClRosTimer, TICK_S)
