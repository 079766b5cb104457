"""Does the robot respond to its velocity commands? A watchdog for the controller server, and why not.

Why: a robot that ignores cmd_vel (battery empty, driver stopped, simulator gone) looks to Nav2's
progress checker like any robot making no progress. The behavior tree then runs its recoveries
(spin, back up, wait) for minutes, and none of them can move the robot either; the user finally
reads "failed to make progress" and nothing about the cause. Comparing what was commanded with
what odometry measures tells the cases apart within :attr:`ResponseParams.timeout` seconds, and
:func:`diagnose` names the cause from what the node knows (battery state, odometry age).

Units: m/s, rad/s and seconds on the caller's clock (sim time under use_sim_time).
"""

from __future__ import annotations

from dataclasses import dataclass

from nav_stack.core.control.base import ControllerError, ControllerErrorCode, Twist2D


@dataclass(frozen=True)
class ResponseParams:
    """When a robot counts as not responding.

    Attributes:
        timeout: s of continuous significant commands with no measured motion; 0 disables the watchdog.
        min_command_linear: m/s; smaller commands (creeping, deadbands) are never judged.
        min_command_angular: rad/s, likewise.
        moving_linear: m/s of measured speed that shows the robot responds.
        moving_angular: rad/s, likewise.
    """

    timeout: float = 2.0
    min_command_linear: float = 0.05
    min_command_angular: float = 0.2
    moving_linear: float = 0.01
    moving_angular: float = 0.05

    def __post_init__(self) -> None:
        for name in ("timeout", "min_command_linear", "min_command_angular", "moving_linear",
                     "moving_angular"):
            if getattr(self, name) < 0.0:
                raise ValueError(f"response {name} must be >= 0, got {getattr(self, name)}")


class RobotUnresponsive(ControllerError):  # noqa: N818 - named like Nav2's controller exceptions
    """The robot did not move while commanded, for a cause no recovery behavior can fix.

    CONTROLLER_TIMED_OUT (107): Nav2's ``WouldAControllerRecoveryHelp`` does not list it, so the
    default behavior trees end the goal with this message instead of spinning and backing up.
    """

    code = ControllerErrorCode.CONTROLLER_TIMED_OUT


class ResponseWatchdog:
    """Times how long significant commands have gone without any measured motion."""

    def __init__(self, params: ResponseParams | None = None) -> None:
        self.params = params or ResponseParams()
        self._since: float | None = None  # s: start of the current unanswered stretch

    def reset(self) -> None:
        self._since = None

    def update(self, command: Twist2D, measured: Twist2D, now: float) -> float:
        """Record the command sent at ``now`` (s) and the latest measured velocity; the seconds the
        robot has been still under significant commands (0 while it moves or is not asked to)."""
        p = self.params
        significant = abs(command.vx) >= p.min_command_linear or abs(command.wz) >= p.min_command_angular
        moving = abs(measured.vx) >= p.moving_linear or abs(measured.wz) >= p.moving_angular
        if not significant or moving:
            self._since = None
            return 0.0
        if self._since is None:
            self._since = now
        return now - self._since

    def unresponsive(self, still_for: float) -> bool:
        """True once ``still_for`` (from :meth:`update`) reaches the timeout (never when disabled)."""
        return self.params.timeout > 0.0 and still_for >= self.params.timeout


def diagnose(still_for: float, battery_empty: bool, odom_age: float | None,
             stale_after: float) -> RobotUnresponsive | None:
    """The cause of a robot still for ``still_for`` s under commands, as an error to end the goal with;
    None when nothing known explains it (wedged, or a recovery may help: left to the progress checker).

    Args:
        battery_empty: the last battery state read 0 % (or health DEAD).
        odom_age: s since the last odometry message, None when none ever came.
        stale_after: s after which odometry counts as stopped (the caller then measures 0 motion).
    """
    if battery_empty:
        return RobotUnresponsive(f"battery empty: the robot does not respond to cmd_vel "
                                 f"(still for {still_for:.1f} s while commanded)")
    if odom_age is None:
        return RobotUnresponsive("no odometry received: cannot tell whether the robot moves "
                                 "(is the robot driver or the simulator running?)")
    if odom_age >= stale_after:
        return RobotUnresponsive(f"no odometry for {odom_age:.1f} s: the robot driver or the "
                                 "simulator stopped publishing")
    return None


def stillness_note(still_for: float) -> str:
    """What a progress-checker failure adds when the robot did not move at all although commanded."""
    return (f"; the robot did not move at all for the last {still_for:.1f} s although commanded "
            "(wedged against an obstacle, or its motors are off?)") if still_for > 0.0 else ""
