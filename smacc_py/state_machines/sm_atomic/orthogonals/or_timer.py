"""``OrTimer``: a ClRos2Timer ticking every second (``createClient<ClRos2Timer>(1s)``)."""

from __future__ import annotations

from smacc_py.clients.cl_ros2_timer import ClRos2Timer
from smacc_py.core import Orthogonal

TICK_S = 1.0  # s of node clock between two ticks


class OrTimer(Orthogonal):
    """Timeouts, counted in ticks of one client timer."""

    def on_initialize(self) -> None:
        self.create_client(ClRos2Timer, TICK_S)
