"""Global planners (pure numpy cores): NavFn-style grid A*/Dijkstra, Theta*, and the server logic."""

from nav_stack.core.planning.common import GlobalPlanner
from nav_stack.core.planning.errors import (
    PlanErrorCode,
    PlanningCancelled,
    PlanningError,
    PlanResult,
    ThroughPosesErrorCode,
)
from nav_stack.core.planning.navfn import NavfnParams, NavfnPlanner
from nav_stack.core.planning.server import PlannerServerCore
from nav_stack.core.planning.theta_star import ThetaStarParams, ThetaStarPlanner

__all__ = [
    "GlobalPlanner",
    "NavfnParams",
    "NavfnPlanner",
    "PlanErrorCode",
    "PlanResult",
    "PlannerServerCore",
    "PlanningCancelled",
    "PlanningError",
    "ThetaStarParams",
    "ThetaStarPlanner",
    "ThroughPosesErrorCode",
]
