"""A command that the robot does not follow in a tight spot: step straight out, then go on.

Why: the costmap draws obstacles in 5 cm cells, so a body beside a pillar can already touch it while
the cells say that a turn is free (and the other way round: RPP turns where the cells make a 2 cm
clearance look blocked, see rpp.py). Seen in the battery patrol (a loop of the demo, 1 run in 23): the
waffle stopped 11 cm short of location3 with a rear corner against the pillar at (-1.1, -1.1), and
RPP sent the same in-place turn for 2,000 s of sim time. The body never turned, and the recoveries
(spin, back up) were refused, rightly, by the same pillar. The final arc onto the goal heading can
jam the same way.

Odometry tells what the cells cannot. A slow command (an in-place turn, or a creep at most
``max_speed``) that the robot does not follow for ``cycles`` control cycles in a row, every
significant component measured under ``response`` of the commanded one, is blocked. The controller
then steps straight ahead (else back), as far as ``distance``, where the body clears, and goes on;
a step that the robot does not follow either is reversed. Commands faster than ``max_speed`` are
never judged: a robot driving along its path is not in a tight spot.

Units: m, m/s, rad/s; cycles are the controller's (20 Hz by default).
"""

from __future__ import annotations

import math

from nav_stack.core.control.base import Twist2D
from nav_stack.core.geometry import Pose2D

#: rad/s and m/s: smaller components are not judged (the end of a braked turn, deadbands)
MIN_JUDGED_TURN, MIN_JUDGED_SPEED = 0.1, 0.02


def unanswered(sent: Twist2D, measured: Twist2D, response: float) -> bool:
    """Whether the robot did not follow ``sent``: each of its significant components is measured
    under ``response`` (0..1) of the commanded value. False when no component is significant."""
    judged = [(c, m) for c, m, least in ((sent.vx, measured.vx, MIN_JUDGED_SPEED),
                                         (sent.wz, measured.wz, MIN_JUDGED_TURN)) if abs(c) >= least]
    return bool(judged) and all(abs(m) < response * abs(c) for c, m in judged)


class StallEscape:
    """Watches the commands a controller sends and says when, and which way, to step out of a spot
    where they go unanswered. One per controller; :meth:`reset` on every new goal."""

    def __init__(self, distance: float, max_speed: float, cycles: int = 10, response: float = 0.2) -> None:
        if distance <= 0.0 or max_speed <= 0.0 or cycles < 1 or not 0.0 < response < 1.0:
            raise ValueError(f"StallEscape needs distance > 0, max_speed > 0, cycles >= 1 and "
                             f"0 < response < 1, got {distance}, {max_speed}, {cycles}, {response}")
        self.distance, self.max_speed, self.cycles, self.response = distance, max_speed, cycles, response
        self.reset()

    def reset(self) -> None:
        self._sent: Twist2D | None = None
        self._unanswered = 0
        self._origin: tuple[float, float] | None = None  # where the robot stood when it stalled
        self._direction = 1.0  # +1 ahead, -1 back

    @property
    def escaping(self) -> bool:
        return self._origin is not None

    def sent(self, cmd: Twist2D) -> None:
        """The command sent this cycle (a stop when the controller found none)."""
        self._sent = cmd

    def observe(self, robot: Pose2D, measured: Twist2D) -> None:
        """Judge the last command by the velocity measured since (odometry), at the start of a cycle."""
        sent = self._sent
        if sent is None or abs(sent.vx) > self.max_speed or not unanswered(sent, measured, self.response):
            self._unanswered = 0
            return
        self._unanswered += 1
        if self._unanswered < self.cycles:
            return
        self._unanswered = 0
        if self._origin is None:  # stuck: step out, ahead first
            self._origin, self._direction = (robot.x, robot.y), 1.0
        else:  # the step is blocked too: the other way
            self._direction = -self._direction

    def directions(self, robot: Pose2D) -> tuple[float, ...]:
        """The step directions to try this cycle, preferred first; () when no escape is under way
        (none started, or the robot has stepped ``distance`` from where it stalled)."""
        if self._origin is None:
            return ()
        if math.dist(self._origin, (robot.x, robot.y)) >= self.distance:
            self._origin = None
            return ()
        return self._direction, -self._direction

    def stepping(self, direction: float | None) -> None:
        """The step taken (+1 ahead, -1 back), or None when neither way is free: the escape ends."""
        if direction is None:
            self._origin = None
        else:
            self._direction = direction
