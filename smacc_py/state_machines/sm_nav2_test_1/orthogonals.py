"""The three orthogonals of sm_nav2_test_1, created in the real package's order."""

from __future__ import annotations

from typing import TYPE_CHECKING, cast

from smacc_py.clients.cl_keyboard import ClKeyboard
from smacc_py.clients.cl_nav2z import (
    ClNav2Z,
    CpAmcl,
    CpGoalCheckerSwitcher,
    CpOdomTracker,
    CpPlannerSwitcher,
    CpPose,
)
from smacc_py.clients.cl_ros2_timer import ClRos2Timer
from smacc_py.core import Orthogonal

if TYPE_CHECKING:  # the machine module imports this one
    from smacc_py.state_machines.sm_nav2_test_1.sm_nav2_test_1 import SmNav2Test1


class OrTimer(Orthogonal):
    """Timeouts (ClRos2Timer)."""

    def on_initialize(self) -> None:
        self.create_client(ClRos2Timer)


class OrKeyboard(Orthogonal):
    """Manual fallback: keys on /keyboard_unicode (ClKeyboard)."""

    def on_initialize(self) -> None:
        self.create_client(ClKeyboard)


class OrNavigation(Orthogonal):
    """ClNav2Z with the components of the real package."""

    def on_initialize(self) -> None:
        client = self.create_client(ClNav2Z)
        client.create_component(CpPose, "base_link", "map")
        client.create_component(CpOdomTracker)
        client.create_component(CpPlannerSwitcher)
        machine = cast("SmNav2Test1", self.sm)
        client.create_component(CpGoalCheckerSwitcher,
                                default_goal_checker=machine.config.default_goal_checker)
        client.create_component(CpAmcl)
