"""``OrTimer``: a ClRosTimer ticking every second (``createClient<ClRosTimer>(rclcpp::Duration(1s))``)."""

from __future__ import annotations

from smacc_py.clients.cl_ros_timer import ClRosTimer
from smacc_py.core import Orthogonal

TICK_S = 1.0  # s of node clock between two ticks


class OrTimer(Orthogonal):
    """State1's countdown, in ticks of one client timer."""

    def on_initialize(self) -> None:
        self.create_client(ClRosTimer, TICK_S)
