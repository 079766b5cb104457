"""The controller's response watchdog: stillness under commands, and the causes it names."""

from __future__ import annotations

import pytest

from nav_stack.core.control import ControllerErrorCode, Twist2D
from nav_stack.core.control.response import (
    ResponseParams,
    ResponseWatchdog,
    diagnose,
    stillness_note,
)

GO, TURN, CREEP, STILL = Twist2D(0.2, 0.0), Twist2D(0.0, 0.5), Twist2D(0.02, 0.0), Twist2D(0.0, 0.0)


def run(watchdog: ResponseWatchdog, command: Twist2D, measured: Twist2D, seconds: float,
        start: float = 0.0, step: float = 0.05) -> float:
    """Feed 20 Hz cycles for ``seconds``; the last stillness reported."""
    still = 0.0
    for i in range(round(seconds / step) + 1):
        still = watchdog.update(command, measured, start + i * step)
    return still


def test_a_still_robot_under_commands_is_unresponsive_after_the_timeout():
    watchdog = ResponseWatchdog(ResponseParams(timeout=2.0))
    assert not watchdog.unresponsive(run(watchdog, GO, STILL, 1.9))
    assert watchdog.unresponsive(run(watchdog, GO, STILL, 0.1, start=2.0))


@pytest.mark.parametrize(("command", "measured"), [
    (GO, Twist2D(0.05, 0.0)),   # it moves
    (TURN, Twist2D(0.0, 0.3)),  # it turns
    (CREEP, STILL),             # too small a command to judge
    (STILL, STILL),             # not asked to move
])
def test_motion_or_small_commands_never_count(command, measured):
    watchdog = ResponseWatchdog(ResponseParams(timeout=1.0))
    assert run(watchdog, command, measured, 5.0) == 0.0


def test_any_motion_restarts_the_count_and_zero_disables():
    watchdog = ResponseWatchdog(ResponseParams(timeout=2.0))
    run(watchdog, GO, STILL, 1.5)
    watchdog.update(GO, Twist2D(0.1, 0.0), 1.55)
    assert run(watchdog, GO, STILL, 1.5, start=1.6) == pytest.approx(1.5)
    off = ResponseWatchdog(ResponseParams(timeout=0.0))
    assert not off.unresponsive(run(off, GO, STILL, 60.0))


def test_diagnose_names_the_battery_first_then_stopped_odometry():
    battery = diagnose(2.0, battery_empty=True, odom_age=0.03, stale_after=2.0)
    assert battery is not None and battery.code == ControllerErrorCode.CONTROLLER_TIMED_OUT
    assert battery.message.startswith("battery empty: the robot does not respond to cmd_vel")
    never = diagnose(2.0, battery_empty=False, odom_age=None, stale_after=2.0)
    assert never is not None and "no odometry received" in never.message
    stopped = diagnose(2.0, battery_empty=False, odom_age=3.5, stale_after=2.0)
    assert stopped is not None and "no odometry for 3.5 s" in stopped.message


def test_a_wedged_robot_is_left_to_the_progress_checker_with_a_note():
    assert diagnose(2.0, battery_empty=False, odom_age=0.03, stale_after=2.0) is None
    assert "did not move at all for the last 4.0 s" in stillness_note(4.0)
    assert stillness_note(0.0) == ""


def test_negative_figures_are_refused_by_name():
    with pytest.raises(ValueError, match="timeout"):
        ResponseParams(timeout=-1.0)
