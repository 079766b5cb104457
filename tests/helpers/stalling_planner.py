"""A planner plugin that searches until it is cancelled: for tests of what a long plan must not block.

It polls the same stopper as the real planners (nav_stack.core.planning.common.search_stopper), so
a cancel ends it with PlanningCancelled, and it gives up with TIMEOUT after ``max_planning_time``
wall seconds. ``started`` is set once the search runs (on the planner server's worker thread).
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable

from nav_stack.core.geometry import FloatArray, Pose2D
from nav_stack.core.grid import GridSpec
from nav_stack.core.planning import PlanErrorCode, PlanningError
from nav_stack.core.planning.common import CostArray, never, search_stopper

POLL_S = 0.001  # wall s between two polls, as a real search polls every 2048 expansions


class StallingPlanner:
    """Never finds a path; stops on cancel or after ``max_planning_time`` s (TIMEOUT)."""

    def __init__(self, max_planning_time: float = 20.0) -> None:
        self.max_planning_time = max_planning_time
        self.started = threading.Event()

    def create_plan(self, start: Pose2D, goal: Pose2D, costs: CostArray, spec: GridSpec,
                    cancel_checker: Callable[[], bool] = never) -> FloatArray:
        self.started.set()
        stop = search_stopper(time.monotonic, self.max_planning_time, cancel_checker)
        while not stop():
            time.sleep(POLL_S)
        raise PlanningError(PlanErrorCode.TIMEOUT, f"stalled for {self.max_planning_time} s")
