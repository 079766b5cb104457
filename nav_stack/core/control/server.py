"""Plugin selection for the controller server: controllers, goal and progress checkers by id.

FollowPath names its plugins by id (``controller_id``, ``goal_checker_id``,
``progress_checker_id``); an empty id means the only one configured. An unknown id is
INVALID_CONTROLLER (101), raised as :class:`InvalidController` for the node to report.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, Protocol, TypeVar

from nav_stack.core.control.base import ControllerError, ControllerErrorCode, CostGrid, Twist2D
from nav_stack.core.control.checkers import SimpleGoalChecker, SimpleProgressChecker
from nav_stack.core.geometry import FloatArray, Pose2D

T = TypeVar("T")


class LocalController(Protocol):
    """A controller plugin: robot state, local path and costmap in, command out (or ControllerError)."""

    params: Any  # its frozen parameter dataclass, replaced whole when a parameter changes at run time

    def reset(self) -> None: ...

    def compute_velocity(
        self, robot: Pose2D, velocity: Twist2D, path: FloatArray, grid: CostGrid
    ) -> Twist2D: ...


class InvalidController(ControllerError):  # noqa: N818 - Nav2's exception name
    code = ControllerErrorCode.INVALID_CONTROLLER


def _select(plugins: Mapping[str, T], plugin_id: str, kind: str) -> T:
    if plugin_id == "" and len(plugins) == 1:
        return next(iter(plugins.values()))
    if plugin_id not in plugins:
        raise InvalidController(f"{kind} id '{plugin_id}' is not one of {sorted(plugins)}")
    return plugins[plugin_id]


class ControllerPlugins:
    """The configured plugins of one controller server."""

    def __init__(
        self,
        controllers: Mapping[str, LocalController],
        goal_checkers: Mapping[str, SimpleGoalChecker],
        progress_checkers: Mapping[str, SimpleProgressChecker],
    ) -> None:
        if not controllers or not goal_checkers or not progress_checkers:
            raise ValueError(
                "controller server needs at least one controller, goal checker and progress checker"
            )
        self.controllers = dict(controllers)
        self.goal_checkers = dict(goal_checkers)
        self.progress_checkers = dict(progress_checkers)

    def select(
        self, controller_id: str, goal_checker_id: str, progress_checker_id: str
    ) -> tuple[LocalController, SimpleGoalChecker, SimpleProgressChecker]:
        """The plugins a FollowPath goal asks for, reset for a new path."""
        selected = (
            _select(self.controllers, controller_id, "controller"),
            _select(self.goal_checkers, goal_checker_id, "goal checker"),
            _select(self.progress_checkers, progress_checker_id, "progress checker"),
        )
        for plugin in selected:
            plugin.reset()
        return selected
