"""Path smoothing (nav2_smoother): the SimpleSmoother and the smoother server's checks and codes."""

from nav_stack.core.smoothing.collision import first_collision
from nav_stack.core.smoothing.server import (
    SmoothErrorCode,
    SmootherServerCore,
    SmoothingError,
    SmoothResult,
    check_path,
)
from nav_stack.core.smoothing.simple_smoother import (
    SimpleSmoother,
    SimpleSmootherParams,
    SmoothingOutcome,
    directional_segments,
    update_orientations,
)

__all__ = [
    "SimpleSmoother",
    "SimpleSmootherParams",
    "SmoothErrorCode",
    "SmoothResult",
    "SmootherServerCore",
    "SmoothingError",
    "SmoothingOutcome",
    "check_path",
    "directional_segments",
    "first_collision",
    "update_orientations",
]
