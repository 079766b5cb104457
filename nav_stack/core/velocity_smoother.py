"""The law of Nav2 Jazzy's ``velocity_smoother`` (nav2_velocity_smoother), without ROS.

Why a smoother: controllers may ask for a step in speed from one cycle to the next; motors and their
drivers wear, slip or trip on such steps. At every smoothing cycle (``smoothing_frequency`` Hz, not
the controller's rate) the last command received is shaped, in Nav2's order:

1. the target is clamped to ``[min_velocity, max_velocity]`` per axis (x, y, theta);
2. with ``scale_velocities``, one factor eta (0 < eta < 1) shrinks the change of every axis so the
   output stays on the commanded direction (the curvature of a diff-drive command) while the most
   constrained axis reaches its limit ("the eta furthest from 1" of Nav2's findEtaConstraint);
3. the change of each axis is limited to ``max_accel / smoothing_frequency`` when speeding up, and to
   ``-max_decel / smoothing_frequency`` otherwise. Speeding up means Nav2's test: the target is at
   least as fast as the current velocity *and* of the same sign; a change through zero is braking
   for the whole step;
4. the result becomes the next cycle's current velocity in ``OPEN_LOOP`` (``CLOSED_LOOP`` takes the
   odometry averaged over ``odom_duration`` instead), and only then the deadband zeroes each axis
   whose speed is below ``deadband_velocity``, so the deadband never stalls the ramp.

No command for more than ``velocity_timeout`` s: the target becomes zero and the output brakes to it
within the deceleration limits (Nav2 ramps, it does not jump to zero); once the output is zero,
nothing is published until a new command arrives. A command holding NaN or inf is refused.

:func:`check_command_series` tells whether a recorded series of outputs kept the limits, for tests
and benches. Units: m/s and rad/s, m/s² and rad/s², s, Hz.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass

AXES = ("x", "y", "theta")
OPEN_LOOP = "OPEN_LOOP"
CLOSED_LOOP = "CLOSED_LOOP"

Velocity = tuple[float, float, float]  # (vx m/s, vy m/s, wz rad/s)
ZERO: Velocity = (0.0, 0.0, 0.0)


def _vector(name: str, values: Sequence[float]) -> None:
    if len(values) != len(AXES):
        raise ValueError(f"{name} = {list(values)}: needs {len(AXES)} values ({', '.join(AXES)}); "
                         "6-DOF limits are not supported")
    if not all(math.isfinite(v) for v in values):
        raise ValueError(f"{name} = {list(values)}: every value must be finite")


@dataclass(frozen=True)
class VelocitySmootherParams:
    """velocity_smoother parameters: Nav2 Jazzy's names and code defaults (the docs agree).

    Nav2's nav2_params.yaml sets ``max_velocity [0.5, 0.0, 2.0]`` and ``min_velocity [-0.5, 0.0,
    -2.0]``; the node's own defaults are 2.5 rad/s. Vectors are (x, y, theta).
    """

    smoothing_frequency: float = 20.0  # Hz
    scale_velocities: bool = False
    feedback: str = OPEN_LOOP  # or CLOSED_LOOP
    max_velocity: tuple[float, ...] = (0.5, 0.0, 2.5)  # m/s, m/s, rad/s
    min_velocity: tuple[float, ...] = (-0.5, 0.0, -2.5)  # signed: negative to reverse
    max_accel: tuple[float, ...] = (2.5, 0.0, 3.2)  # m/s², rad/s²; >= 0
    max_decel: tuple[float, ...] = (-2.5, 0.0, -3.2)  # signed: <= 0
    odom_topic: str = "odom"
    odom_duration: float = 0.1  # s of odometry averaged in CLOSED_LOOP
    deadband_velocity: tuple[float, ...] = (0.0, 0.0, 0.0)  # speeds below these are sent as 0
    velocity_timeout: float = 1.0  # s without a command before braking to zero
    enable_stamped_cmd_vel: bool = False  # TwistStamped instead of Twist, in and out
    # Accepted for Nav2 parameter files and ignored: a Python node on one executor thread gains
    # nothing from a SCHED_FIFO priority, and setting one needs privileges a user seldom has.
    use_realtime_priority: bool = False

    def __post_init__(self) -> None:
        if not (math.isfinite(self.smoothing_frequency) and self.smoothing_frequency > 0.0):
            raise ValueError(f"smoothing_frequency = {self.smoothing_frequency}: must be > 0 Hz")
        if self.feedback not in (OPEN_LOOP, CLOSED_LOOP):
            raise ValueError(f"feedback = {self.feedback!r}: must be {OPEN_LOOP!r} or {CLOSED_LOOP!r}")
        for name in ("max_velocity", "min_velocity", "max_accel", "max_decel", "deadband_velocity"):
            _vector(name, getattr(self, name))
        for i, axis in enumerate(AXES):
            if self.min_velocity[i] > self.max_velocity[i]:  # first: the clearest message for a swap
                raise ValueError(f"min_velocity[{i}] ({axis}) = {self.min_velocity[i]} is above "
                                 f"max_velocity[{i}] = {self.max_velocity[i]}")
            checks = (
                ("max_accel", self.max_accel[i] >= 0.0, "must be >= 0 (positive to speed up)"),
                ("max_decel", self.max_decel[i] <= 0.0, "must be <= 0 (negative to slow down)"),
                ("max_velocity", self.max_velocity[i] >= 0.0, "must be >= 0"),
                ("min_velocity", self.min_velocity[i] <= 0.0, "must be <= 0 (signed: negative to reverse)"),
                ("deadband_velocity", self.deadband_velocity[i] >= 0.0, "must be >= 0"),
            )
            for name, ok, rule in checks:
                if not ok:
                    raise ValueError(f"{name}[{i}] ({axis}) = {getattr(self, name)[i]}: {rule}")
        if not self.odom_duration > 0.0:
            raise ValueError(f"odom_duration = {self.odom_duration}: must be > 0 s")
        if not self.velocity_timeout >= 0.0:
            raise ValueError(f"velocity_timeout = {self.velocity_timeout}: must be >= 0 s")


# -- the law, one axis at a time ----------------------------------------------------------------------
def speeding_up(current: float, target: float) -> bool:
    """Nav2's test for the acceleration limit: no slower than now and no sign change."""
    return abs(target) >= abs(current) and current * target >= 0.0


def step_limit(current: float, target: float, accel: float, decel: float, frequency: float) -> float:
    """The largest change (>= 0) of one axis in one cycle: by ``accel`` or by ``decel`` (<= 0)."""
    return (accel if speeding_up(current, target) else -decel) / frequency


def axis_eta(current: float, target: float, accel: float, decel: float, frequency: float) -> float | None:
    """The factor that brings this axis's change within its limit (Nav2's findEtaConstraint), or
    None when the change already fits."""
    change, limit = target - current, step_limit(current, target, accel, decel, frequency)
    return limit / abs(change) if abs(change) > limit else None


def limit_axis(current: float, target: float, accel: float, decel: float, frequency: float,
               eta: float = 1.0) -> float:
    """``current`` moved toward ``target`` by eta times the change, capped at the axis's limit."""
    limit = step_limit(current, target, accel, decel, frequency)
    return current + min(max(eta * (target - current), -limit), limit)


def smooth(current: Velocity, target: Velocity, p: VelocitySmootherParams) -> Velocity:
    """One cycle of the law before the deadband: the velocity to send and to remember."""
    clamped = [min(max(t, lo), hi) for t, lo, hi in zip(target, p.min_velocity, p.max_velocity, strict=True)]
    f = p.smoothing_frequency
    eta = 1.0
    if p.scale_velocities:
        for i in range(len(AXES)):
            e = axis_eta(current[i], clamped[i], p.max_accel[i], p.max_decel[i], f)
            if e is not None and e > 0.0 and abs(1.0 - e) > abs(1.0 - eta):
                eta = e
    vx, vy, wz = (limit_axis(current[i], clamped[i], p.max_accel[i], p.max_decel[i], f, eta)
                  for i in range(len(AXES)))
    return vx, vy, wz


def apply_deadband(velocity: Velocity, deadband: Sequence[float]) -> Velocity:
    """Each axis whose speed is below its deadband becomes 0."""
    vx, vy, wz = (0.0 if abs(v) < d else v for v, d in zip(velocity, deadband, strict=True))
    return vx, vy, wz


# -- state ---------------------------------------------------------------------------------------------
class OdomAverager:
    """The robot's velocity as the mean of the odometry twists received within ``duration`` s of the
    newest one, by their stamps (nav2_util::OdomSmoother); zero before any odometry."""

    def __init__(self, duration: float) -> None:
        self.duration = duration
        self._history: deque[tuple[float, Velocity]] = deque()

    def add(self, stamp: float, twist: Velocity) -> None:
        """Take one odometry twist stamped ``stamp`` (s)."""
        while self._history and stamp - self._history[0][0] > self.duration:
            self._history.popleft()
        self._history.append((stamp, twist))

    @property
    def velocity(self) -> Velocity:
        n = len(self._history)
        if n == 0:
            return ZERO
        vx, vy, wz = (sum(t[i] for _, t in self._history) / n for i in range(len(AXES)))
        return vx, vy, wz


class CommandSmoother:
    """The smoother's state between cycles: the last command and when it came, the last output."""

    def __init__(self, params: VelocitySmootherParams) -> None:
        self.params = params
        self.odometry = OdomAverager(params.odom_duration)
        self._target: Velocity | None = None  # None until a first command
        self._target_time = 0.0  # s
        self.last_output: Velocity = ZERO  # before the deadband: the OPEN_LOOP current velocity
        self._stopped = True

    def update_params(self, params: VelocitySmootherParams) -> None:
        """Take new parameters at run time; a new odometry window starts empty, as in Nav2."""
        if (params.odom_duration, params.feedback, params.odom_topic) != (
                self.params.odom_duration, self.params.feedback, self.params.odom_topic):
            self.odometry = OdomAverager(params.odom_duration)
        self.params = params

    def command(self, velocity: Velocity, now: float) -> bool:
        """Take a new target received at ``now`` (s); False (and ignored) if it holds NaN or inf."""
        if not all(math.isfinite(v) for v in velocity):
            return False
        self._target, self._target_time = velocity, now
        return True

    def cycle(self, now: float) -> Velocity | None:
        """The command to publish at the smoothing cycle of time ``now`` (s), or None for none."""
        if self._target is None:
            return None
        p = self.params
        if now - self._target_time > p.velocity_timeout:
            if self.last_output == ZERO or self._stopped:
                self._stopped = True
                return None
            self._target = ZERO  # brake within the deceleration limits, then fall silent
        self._stopped = False
        current = self.last_output if p.feedback == OPEN_LOOP else self.odometry.velocity
        self.last_output = smooth(current, self._target, p)
        return apply_deadband(self.last_output, p.deadband_velocity)


# -- checking a recorded series ---------------------------------------------------------------------
@dataclass(frozen=True)
class LimitViolation:
    """One sample of a command series that broke a limit."""

    index: int  # position in the series
    axis: str  # "x", "y" or "theta"
    limit_name: str  # "max_velocity", "min_velocity", "max_accel" or "max_decel"
    value: float  # the velocity (for a bound) or the change from the sample before (for a rate)
    limit: float  # the bound, or the largest change allowed

    def __str__(self) -> str:
        return (f"sample {self.index}, {self.axis}: {self.value:+.6f} breaks {self.limit_name} "
                f"({self.limit:+.6f})")


def check_command_series(series: Sequence[Sequence[float]], p: VelocitySmootherParams,
                         start: Sequence[float] = ZERO, tolerance: float = 1e-9) -> list[LimitViolation]:
    """Every place where a series of published (vx, vy, wz), one per smoothing cycle from ``start``,
    leaves ``[min_velocity, max_velocity]`` or changes faster than the acceleration limits allow.

    The change between two samples is judged as the smoother judges it (speeding up: no slower and no
    sign change, else braking). A change to or from 0 may exceed the limit by the axis's deadband,
    which hides speeds below it. Meant for OPEN_LOOP output: in CLOSED_LOOP each step starts from the
    measured velocity, not from the previous command.
    """
    violations = []
    previous = tuple(start)
    f = p.smoothing_frequency
    for index, sample in enumerate(series):
        for i, axis in enumerate(AXES):
            v, before = sample[i], previous[i]
            if v > p.max_velocity[i] + tolerance:
                violations.append(LimitViolation(index, axis, "max_velocity", v, p.max_velocity[i]))
            if v < p.min_velocity[i] - tolerance:
                violations.append(LimitViolation(index, axis, "min_velocity", v, p.min_velocity[i]))
            allowed = step_limit(before, v, p.max_accel[i], p.max_decel[i], f)
            if v == 0.0 or before == 0.0:
                allowed += p.deadband_velocity[i]
            if abs(v - before) > allowed + tolerance:
                name = "max_accel" if speeding_up(before, v) else "max_decel"
                violations.append(LimitViolation(index, axis, name, v - before, allowed))
        previous = tuple(sample)
    return violations
