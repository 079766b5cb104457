"""``SmNav2Test1``: the machine, its parameters and its nominal transition sequence."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from smacc_py.clients.cl_nav2z.geometry import Pose2D
from smacc_py.core import SmaccStateMachineBase
from smacc_py.ros.context import ros_context
from smacc_py.ros.params import declare_dataclass_params
from smacc_py.state_machines.sm_nav2_test_1 import states as st
from smacc_py.state_machines.sm_nav2_test_1.orthogonals import OrKeyboard, OrNavigation, OrTimer


@dataclass(frozen=True)
class SmNav2Test1Params:
    """ROS parameters of node ``SmNav2Test1`` (x, y in m, yaw in rad, map frame).

    Attributes:
        initial_pose: AMCL's initial pose, the TurtleBot3 spawn pose (-2.0, -0.5, 0).
        waypoint_1: first goal; (2.0, 0.0, 0.0) as in the tutorial.
        waypoint_2: second goal. Upstream uses (0, 0), which is the centre of turtlebot3_world's middle
            pillar (radius 0.15 m; the robot's radius is 0.22 m): the planner's 0.5 m tolerance makes
            that goal succeed about 0.4 m short of it. The default here, so that the robot ends where
            it was asked, (-0.55, 0.55, π), is the centre of the free square between the pillars at (-1.1, 0),
            (0, 0), (-1.1, 1.1) and (0, 1.1): 0.78 m from each pillar centre, 0.63 m of clearance to
            their surfaces (more than Nav2's 0.55 m inflation radius) and > 1.5 m from the walls.
        default_goal_checker: the goal checker id CpGoalCheckerSwitcher selects, SMACC2's default
            "goal_checker" (the tutorial's own Nav2 file names it so). Nav2's own nav2_params.yaml calls
            its goal checker "general_goal_checker": with that file, set this to it
            (config/sm_nav2_test_1_jazzy.yaml), or controller_server answers INVALID_CONTROLLER.
    """

    initial_pose: Pose2D = (-2.0, -0.5, 0.0)
    waypoint_1: Pose2D = (2.0, 0.0, 0.0)
    waypoint_2: Pose2D = (-0.55, 0.55, math.pi)
    default_goal_checker: str = "goal_checker"

    def __post_init__(self) -> None:
        for name in ("initial_pose", "waypoint_1", "waypoint_2"):
            value = getattr(self, name)
            if len(value) != 3 or not all(math.isfinite(v) for v in value):
                raise ValueError(
                    f"SmNav2Test1Params.{name} must be 3 finite numbers (x, y, yaw), got {value!r}"
                )
        if not self.default_goal_checker:
            raise ValueError("SmNav2Test1Params.default_goal_checker must name a goal checker, got ''")


class SmNav2Test1(SmaccStateMachineBase):
    """sm_nav2_gazebo_test_1 (reference/smacc2.md §2); parameters in ``self.config``.

    ``config`` given: the machine uses it instead of declaring its ROS parameters, so it also runs without
    a node (on substitute clients, ``substitutes=``), as the unit test of the mission does.
    """

    initial_state = st.StAllSensorsGo
    config: SmNav2Test1Params

    def __init__(self, *, config: SmNav2Test1Params | None = None, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._given_config = config

    def on_initialize(self) -> None:
        given = self._given_config
        self.config = given if given is not None else declare_dataclass_params(
            ros_context(self).node, SmNav2Test1Params
        )
        self.create_orthogonal(OrTimer)
        self.create_orthogonal(OrKeyboard)
        self.create_orthogonal(OrNavigation)


# Free states declared in states.py are adopted by the machine that reaches them.

NOMINAL_TRANSITIONS: tuple[tuple[str, str, str], ...] = (
    ("StAllSensorsGo", "StSetInitialPose", "NAV2_READY"),
    ("StSetInitialPose", "StNavigateToWaypoint1", "SUCCESS"),
    ("StNavigateToWaypoint1", "StRotate", "SUCCESS"),
    ("StRotate", "StNavigateToWaypoint2", "SUCCESS"),
    ("StNavigateToWaypoint2", "StFinalState", "SUCCESS"),
)
"""(source, target, tag) of the mission when Nav2 is up and every goal succeeds."""
