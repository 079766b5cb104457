"""The collision monitor's decision: which polygon acts on a command, and what is published.

Nav2 Jazzy's CollisionMonitor::process, per incoming command:

1. If an enabled source gave no valid data (never published, older than its ``source_timeout``, or
   not placeable by TF) and its timeout is not 0, the robot stops: action STOP, polygon name
   ``"invalid source"``; no polygon is looked at.
2. Otherwise the enabled polygons are taken in the order of ``polygons``; a polygon whose shape is
   not set yet (a topic that has not spoken) is skipped. From the command as it came in:

   * stop: ``min_points`` or more data points inside → zero velocity; the loop ends there;
   * slowdown: the command times ``slowdown_ratio``;
   * limit: the linear part scaled down to at most ``linear_limit`` (direction kept), the angular
     part clamped to ``±angular_limit``;
   * approach: the command times ``collision_time / time_before_collision`` (see :mod:`.approach`).

   A slowdown, limit or approach result replaces the current one only if it is *slower*, by Nav2's
   measure: ``vx² + vy² + wz²`` (linear and angular units mixed, as Nav2 mixes them). So the most
   restrictive polygon wins, and among equals the first.
3. The state (action type and polygon name) is reported when the polygon name changes.
4. A zero command is published when the robot has just stopped and for ``stop_pub_timeout`` s
   after that; then the monitor falls silent until a non-zero command, leaving ``cmd_vel`` to
   other publishers (teleop). Nothing is published without an input command: the monitor has no
   timer of its own.

A zero input therefore passes through as zero (no polygon can ask for less), with the state of a
stop polygon if one is triggered. Units: m/s, rad/s, s of the node clock.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from nav_stack.core.collision_monitor.approach import approach_ratio, collision_time
from nav_stack.core.collision_monitor.params import ActionType, CollisionMonitorParams
from nav_stack.core.collision_monitor.shapes import Zone
from nav_stack.core.geometry import FloatArray

INVALID_SOURCE = "invalid source"  # Nav2's polygon name for a stop caused by a source


class Velocity(NamedTuple):
    """A planar command: vx, vy (m/s) and wz (rad/s) in the base frame."""

    x: float
    y: float
    tw: float

    def scaled(self, factor: float) -> Velocity:
        return Velocity(self.x * factor, self.y * factor, self.tw * factor)

    @property
    def is_zero(self) -> bool:
        return self.x == 0.0 and self.y == 0.0 and self.tw == 0.0

    @property
    def size(self) -> float:
        """Nav2's measure for "safer": ``x² + y² + tw²``."""
        return self.x * self.x + self.y * self.y + self.tw * self.tw

    @property
    def finite(self) -> bool:
        return all(math.isfinite(v) for v in self)


ZERO = Velocity(0.0, 0.0, 0.0)


@dataclass(frozen=True)
class Action:
    """What the monitor does to one command: its type, the velocity to send, the polygon that acted."""

    action_type: ActionType
    velocity: Velocity
    polygon_name: str = ""


def zone_points(zone: Zone, points_by_source: Mapping[str, FloatArray]) -> FloatArray:
    """The data points (N, 2) a zone reads: those of its ``sources_names``, or of every source."""
    names = zone.params.sources_names or tuple(points_by_source)
    arrays = [points_by_source[n] for n in names if n in points_by_source]
    return np.concatenate(arrays) if arrays else np.zeros((0, 2))


def limited(velocity: Velocity, linear_limit: float, angular_limit: float) -> Velocity:
    """The limit model: the linear speed scaled to at most ``linear_limit``, wz clamped."""
    linear = math.hypot(velocity.x, velocity.y)
    ratio = min(max(linear_limit / linear, 0.0), 1.0) if linear != 0.0 else 1.0
    return Velocity(velocity.x * ratio, velocity.y * ratio,
                    min(max(velocity.tw, -angular_limit), angular_limit))


def zone_velocity(zone: Zone, points: FloatArray, command: Velocity) -> Velocity | None:
    """The velocity ``zone`` asks for (from the incoming ``command``), or None if it does not act."""
    p = zone.params
    if zone.action == ActionType.APPROACH:
        ratio = approach_ratio(collision_time(zone, points, command), p.time_before_collision)
        return None if ratio is None else command.scaled(ratio)
    if zone.action == ActionType.DO_NOTHING or not zone.triggered(points):
        return None
    if zone.action == ActionType.STOP:
        return ZERO
    if zone.action == ActionType.SLOWDOWN:
        return command.scaled(p.slowdown_ratio)
    return limited(command, p.linear_limit, p.angular_limit)


def decide(command: Velocity, zones: Sequence[Zone],
           points_by_source: Mapping[str, FloatArray] | None) -> Action:
    """The action for ``command``; ``points_by_source`` None means a source was invalid (stop)."""
    if points_by_source is None:
        return Action(ActionType.STOP, ZERO, INVALID_SOURCE)
    action = Action(ActionType.DO_NOTHING, command)
    for zone in zones:
        if not zone.enabled or not zone.is_set:
            continue
        wanted = zone_velocity(zone, zone_points(zone, points_by_source), command)
        if wanted is None:
            continue
        if zone.action == ActionType.STOP:
            return Action(ActionType.STOP, ZERO, zone.name)
        if wanted.size < action.velocity.size:
            action = Action(zone.action, wanted, zone.name)
    return action


class Outcome(NamedTuple):
    """One processed command: the action, whether to publish it, whether the state changed."""

    action: Action
    publish: bool
    state_changed: bool


#: Before the first command: a non-zero "previous" velocity, so the first zero is published.
_START = Action(ActionType.DO_NOTHING, Velocity(-1.0, -1.0, -1.0))


class CollisionMonitor:
    """The decision plus what it remembers between commands: the previous action and when the
    robot was last stopped (for ``stop_pub_timeout``)."""

    def __init__(self, params: CollisionMonitorParams, zones: Sequence[Zone]) -> None:
        self.params = params
        self.zones = list(zones)
        self.previous = _START
        self._stop_stamp = 0.0  # s

    def reset(self) -> None:
        """Forget the previous action (Nav2 does at deactivate)."""
        self.previous = _START

    def process(self, command: Velocity, points_by_source: Mapping[str, FloatArray] | None,
                now: float) -> Outcome:
        """Decide for ``command`` received at ``now`` (s) with the sources' current points."""
        action = decide(command, self.zones, points_by_source)
        publish = True
        if action.velocity.is_zero:
            if not self.previous.velocity.is_zero:
                self._stop_stamp = now  # just stopped
            elif now - self._stop_stamp > self.params.stop_pub_timeout:
                publish = False
        changed = action.polygon_name != self.previous.polygon_name
        self.previous = action
        return Outcome(action, publish, changed)
