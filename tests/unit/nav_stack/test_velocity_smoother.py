"""velocity_smoother's law (Nav2 Jazzy): limits per axis, braking through zero, eta scaling, deadband,
timeout, OPEN_LOOP vs CLOSED_LOOP, parameter checks, and the checker of recorded command series."""

from __future__ import annotations

import math
import re
from typing import Any

import pytest

from nav_stack.core.velocity_smoother import (
    CLOSED_LOOP,
    ZERO,
    CommandSmoother,
    OdomAverager,
    Velocity,
    VelocitySmootherParams,
    check_command_series,
    limit_axis,
    speeding_up,
)

PERIOD = 0.05  # s, one cycle at the default 20 Hz


def run(smoother: CommandSmoother, start: float, cycles: int) -> list[Velocity | None]:
    """The outputs of ``cycles`` smoothing cycles, the first at ``start`` s."""
    return [smoother.cycle(start + k * PERIOD) for k in range(cycles)]


def xs(outputs: list[Velocity | None]) -> list[float | None]:
    return [None if o is None else round(o[0], 9) for o in outputs]


def test_a_step_ramps_by_max_accel_per_cycle_and_holds_the_target() -> None:
    smoother = CommandSmoother(VelocitySmootherParams())
    smoother.command((0.5, 0.0, 0.0), 0.0)
    assert xs(run(smoother, PERIOD, 6)) == [0.125, 0.25, 0.375, 0.5, 0.5, 0.5]  # 2.5 m/s² / 20 Hz


def test_nothing_is_published_before_a_first_command() -> None:
    smoother = CommandSmoother(VelocitySmootherParams())
    assert run(smoother, 0.0, 3) == [None, None, None]


def test_the_target_is_clamped_and_each_axis_keeps_its_own_limits() -> None:
    p = VelocitySmootherParams(max_velocity=(0.5, 0.3, 2.5), min_velocity=(-0.5, -0.3, -2.5),
                               max_accel=(2.5, 1.0, 3.2))
    smoother = CommandSmoother(p)
    smoother.command((0.9, -1.0, 4.0), 0.0)
    outputs = run(smoother, PERIOD, 20)
    assert outputs[0] == pytest.approx((0.125, -0.05, 0.16))
    assert outputs[-1] == pytest.approx((0.5, -0.3, 2.5))  # clamped to max/min_velocity
    assert check_command_series([o for o in outputs if o is not None], p) == []


def test_the_default_y_limits_hold_a_diff_drive_to_zero_lateral_speed() -> None:
    smoother = CommandSmoother(VelocitySmootherParams())
    smoother.command((0.2, 0.4, 0.0), 0.0)
    assert all(o is not None and o[1] == 0.0 for o in run(smoother, PERIOD, 5))


def test_slowing_down_is_limited_by_max_decel() -> None:
    p = VelocitySmootherParams(max_accel=(1.0, 0.0, 3.2), max_decel=(-2.0, 0.0, -3.2))
    smoother = CommandSmoother(p)
    smoother.command((0.5, 0.0, 0.0), 0.0)
    run(smoother, PERIOD, 10)  # 0.05 m/s per cycle up to 0.5
    smoother.command((0.0, 0.0, 0.0), 0.5)
    assert xs(run(smoother, 0.55, 6)) == [0.4, 0.3, 0.2, 0.1, 0.0, 0.0]  # 0.1 m/s per cycle down


def test_speeding_up_is_judged_with_respect_to_sign() -> None:
    assert speeding_up(0.0, -0.3)  # from standstill either way
    assert speeding_up(-0.1, -0.3)
    assert not speeding_up(0.3, 0.2)
    assert not speeding_up(0.3, -0.3)  # same speed, other way: braking
    assert not speeding_up(-0.3, 0.5)  # faster, other way: still braking


def test_a_reversal_brakes_through_zero_then_accelerates() -> None:
    """accel 1 m/s² and decel -2 m/s² at 10 Hz: steps of 0.1 up, 0.2 down."""
    step = [limit_axis(0.15, -0.5, 1.0, -2.0, 10.0)]
    step.append(limit_axis(step[-1], -0.5, 1.0, -2.0, 10.0))
    assert step == pytest.approx([-0.05, -0.15])  # the first crosses zero at the braking rate


def test_scaling_keeps_the_commanded_curvature() -> None:
    target = (0.5, 0.0, 2.0)  # wz / vx = 4 rad/m
    plain = CommandSmoother(VelocitySmootherParams())
    scaled = CommandSmoother(VelocitySmootherParams(scale_velocities=True))
    for smoother in (plain, scaled):
        smoother.command(target, 0.0)
    first_plain, first_scaled = plain.cycle(PERIOD), scaled.cycle(PERIOD)
    assert first_plain == pytest.approx((0.125, 0.0, 0.16))  # each axis at its own limit: 1.28 rad/m
    assert first_scaled == pytest.approx((0.04, 0.0, 0.16))  # theta limits; x follows it
    for k in range(2, 14):
        out = scaled.cycle(k * PERIOD)
        assert out is not None and out[2] == pytest.approx(4.0 * out[0])
    assert out == pytest.approx(target)


def test_the_deadband_hides_slow_speeds_without_stalling_the_ramp() -> None:
    smoother = CommandSmoother(VelocitySmootherParams(deadband_velocity=(0.2, 0.0, 0.0)))
    smoother.command((0.5, 0.0, 0.0), 0.0)
    assert xs(run(smoother, PERIOD, 4)) == [0.0, 0.25, 0.375, 0.5]
    smoother.command((0.1, 0.0, 0.0), 0.2)
    assert xs(run(smoother, 0.25, 4)) == [0.375, 0.25, 0.0, 0.0]  # 0.125 and 0.1 are sent as 0
    assert smoother.last_output[0] == pytest.approx(0.1)  # but the ramp went on underneath


def test_no_command_for_velocity_timeout_brakes_to_zero_then_falls_silent() -> None:
    smoother = CommandSmoother(VelocitySmootherParams(velocity_timeout=1.0))
    smoother.command((0.5, 0.0, 0.0), 0.0)
    held = run(smoother, PERIOD, 20)  # up to t = 1.0 s: not yet more than the timeout
    assert xs(held)[-1] == 0.5
    braking = run(smoother, 1.05, 8)
    assert xs(braking) == [0.375, 0.25, 0.125, 0.0, None, None, None, None]  # max_decel, not a jump
    smoother.command((0.2, 0.0, 0.0), 2.0)
    assert xs(run(smoother, 2.05, 2)) == [0.125, 0.2]


def test_a_zero_command_is_repeated_until_the_timeout() -> None:
    smoother = CommandSmoother(VelocitySmootherParams(velocity_timeout=0.5))
    smoother.command(ZERO, 0.0)
    outputs = run(smoother, PERIOD, 14)
    assert outputs[:10] == [ZERO] * 10 and outputs[10:] == [None] * 4  # silent after 0.5 s


@pytest.mark.parametrize("bad", [(math.nan, 0.0, 0.0), (0.1, 0.0, math.inf), (0.0, -math.inf, 0.0)])
def test_a_command_with_nan_or_inf_is_ignored(bad: Velocity) -> None:
    smoother = CommandSmoother(VelocitySmootherParams())
    smoother.command((0.25, 0.0, 0.0), 0.0)
    assert not smoother.command(bad, 0.01)
    assert xs(run(smoother, PERIOD, 3)) == [0.125, 0.25, 0.25]


def test_closed_loop_starts_each_cycle_from_the_averaged_odometry() -> None:
    open_loop = CommandSmoother(VelocitySmootherParams())
    closed = CommandSmoother(VelocitySmootherParams(feedback=CLOSED_LOOP))
    for smoother in (open_loop, closed):
        smoother.odometry.add(0.00, (0.3, 0.0, 0.0))
        smoother.odometry.add(0.05, (0.4, 0.0, 0.0))
        smoother.command((0.5, 0.0, 0.0), 0.05)
    assert xs([open_loop.cycle(0.1)]) == [0.125]  # from its last output, 0
    assert xs([closed.cycle(0.1)]) == [0.475]  # from the mean of 0.3 and 0.4


def test_the_odometry_average_keeps_only_odom_duration_of_history() -> None:
    window = OdomAverager(0.1)
    assert window.velocity == ZERO
    window.add(0.00, (1.0, 0.0, 0.5))
    window.add(0.05, (0.0, 0.0, 0.0))
    assert window.velocity == pytest.approx((0.5, 0.0, 0.25))
    window.add(0.20, (0.2, 0.0, 0.0))  # both older ones are more than 0.1 s before it
    assert window.velocity == pytest.approx((0.2, 0.0, 0.0))


def test_new_parameters_take_effect_at_the_next_cycle() -> None:
    smoother = CommandSmoother(VelocitySmootherParams())
    smoother.command((0.5, 0.0, 0.0), 0.0)
    smoother.cycle(PERIOD)
    smoother.odometry.add(0.0, (0.1, 0.0, 0.0))
    smoother.update_params(VelocitySmootherParams(max_accel=(1.0, 0.0, 3.2), odom_duration=0.2))
    assert xs([smoother.cycle(2 * PERIOD)]) == [0.175]  # 1.0 m/s² / 20 Hz on top of 0.125
    assert smoother.odometry.velocity == ZERO  # a new window, as Nav2 rebuilds its OdomSmoother


@pytest.mark.parametrize(("overrides", "message"), [
    ({"max_accel": (2.5, -0.1, 3.2)}, "max_accel[1] (y) = -0.1"),
    ({"max_decel": (0.5, 0.0, -3.2)}, "max_decel[0] (x) = 0.5"),
    ({"min_velocity": (0.6, 0.0, -2.5)}, "min_velocity[0] (x) = 0.6 is above max_velocity[0] = 0.5"),
    ({"max_velocity": (-0.1, 0.0, 2.5), "min_velocity": (-0.5, 0.0, -2.5)}, "max_velocity[0] (x) = -0.1"),
    ({"min_velocity": (-0.5, 0.1, -2.5), "max_velocity": (0.5, 0.2, 2.5)}, "min_velocity[1] (y) = 0.1"),
    ({"max_velocity": (0.5, 2.5)}, "max_velocity = [0.5, 2.5]: needs 3 values"),
    ({"deadband_velocity": (0.0,) * 6}, "deadband_velocity = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]: needs 3"),
    ({"deadband_velocity": (-0.1, 0.0, 0.0)}, "deadband_velocity[0] (x) = -0.1"),
    ({"feedback": "ODOMETRY"}, "feedback = 'ODOMETRY'"),
    ({"smoothing_frequency": 0.0}, "smoothing_frequency = 0.0"),
    ({"odom_duration": 0.0}, "odom_duration = 0.0"),
    ({"velocity_timeout": -1.0}, "velocity_timeout = -1.0"),
])
def test_bad_parameters_are_refused_naming_parameter_and_value(overrides: dict[str, Any],
                                                                message: str) -> None:
    with pytest.raises(ValueError, match="^" + re.escape(message)):
        VelocitySmootherParams(**overrides)


def test_the_checker_passes_the_smoothers_own_output() -> None:
    p = VelocitySmootherParams(deadband_velocity=(0.2, 0.0, 0.3), max_decel=(-1.0, 0.0, -3.2))
    smoother = CommandSmoother(p)
    outputs: list[Velocity | None] = []
    for t, target in ((0.0, (0.5, 0.0, 1.0)), (0.5, (-0.4, 0.0, -2.0)), (1.5, (0.3, 0.0, 0.0))):
        smoother.command(target, t)
        outputs += run(smoother, t + PERIOD, 10)
    outputs += run(smoother, 2.05, 40)  # the timeout and its braking
    series = [o for o in outputs if o is not None]
    assert series[-1] == ZERO and check_command_series(series, p) == []


def test_the_checker_catches_each_kind_of_broken_limit() -> None:
    p = VelocitySmootherParams()
    assert [(v.index, v.axis, v.limit_name) for v in check_command_series([(0.5, 0.0, 0.0)], p)] == [
        (0, "x", "max_accel")]  # a step without a ramp
    braking = [(0.125, 0.0, 0.0), (0.25, 0.0, 0.0), (0.0, 0.0, 0.0)]
    found = check_command_series(braking, p)
    assert [(v.index, v.limit_name) for v in found] == [(2, "max_decel")]
    assert str(found[0]) == "sample 2, x: -0.250000 breaks max_decel (+0.125000)"
    reversing = [(0.1, 0.0, 0.0), (-0.1, 0.0, 0.0)]  # a 0.2 change through zero: braking, 0.125 allowed
    assert [v.limit_name for v in check_command_series(reversing, p)] == ["max_decel"]
    too_fast = [(0.125, 0.0, 0.16), (0.25, 0.0, 0.32), (0.375, 0.0, 0.48), (0.5, 0.0, 0.64), (0.6, 0.0, 0.8)]
    assert [(v.index, v.limit_name) for v in check_command_series(too_fast, p)] == [(4, "max_velocity")]
    turning = [(0.0, 0.0, 0.2)]  # 0.2 rad/s in one cycle > 3.2 / 20
    assert [(v.axis, v.limit_name) for v in check_command_series(turning, p)] == [("theta", "max_accel")]
