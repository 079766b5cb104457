"""A planar laser scan as the cores consume it (the fields of sensor_msgs/LaserScan they use).

Why: the obstacle layer and AMCL both read scans; the ROS node copies the message into this
dataclass and supplies the sensor pose from TF, so the cores never see a message type.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt


@dataclass(frozen=True)
class LaserScan:
    """Ranges (m) of beams at ``angle_min + i·angle_increment`` (rad) in the sensor frame.

    Readings outside ``[range_min, range_max)`` and NaN are invalid; +inf means "nothing seen".
    """

    ranges: npt.NDArray[np.float64]
    angle_min: float
    angle_increment: float
    range_min: float
    range_max: float

    def __post_init__(self) -> None:
        if np.ndim(self.ranges) != 1:
            raise ValueError(f"LaserScan.ranges must be 1-D, got shape {np.shape(self.ranges)}")
        for name in ("angle_min", "angle_increment", "range_min", "range_max"):
            value = getattr(self, name)
            if not math.isfinite(value):
                raise ValueError(f"LaserScan.{name} must be finite, got {value}")
        if not 0.0 <= self.range_min < self.range_max:
            raise ValueError(
                f"LaserScan needs 0 <= range_min < range_max, got {self.range_min}, {self.range_max}")

    @property
    def angles(self) -> npt.NDArray[np.float64]:
        """Beam angles (rad) in the sensor frame."""
        return self.angle_min + self.angle_increment * np.arange(len(self.ranges), dtype=np.float64)
