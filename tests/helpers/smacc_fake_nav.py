"""Scripted fakes of the sm_nav2_gazebo_test_1 clients and behaviors for pure (no-ROS) engine tests.

``ClNav2Z`` replays scripted outcomes instead of talking to Nav2: every ``CbWaitNav2Nodes`` entry pops
one readiness outcome ("success", "failure" or "pending"), every navigation goal pops one action outcome
("succeeded" or "aborted"), every spin pops one spin outcome ("success" or "failure"). The timer
countdown is an ISmaccUpdatable driven by the machine's injected clock, and ``ClKeyboard.press`` plays
the role of a ``/keyboard_unicode`` message. The event types and parameterisations are those of the real
package (reference/smacc2.md §2), so a state machine written against these fakes reads like the real one.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Iterable
from dataclasses import dataclass

from smacc_py.core import (
    EvActionAborted,
    EvActionSucceeded,
    EvTimer,
    ISmaccClient,
    ISmaccComponent,
    ISmaccUpdatable,
    Orthogonal,
    SmaccClientBehavior,
    key_press_event,
)


# ----------------------------------------------------------------------------------------- clients
class ClRos2Timer(ISmaccClient):
    """Stands in for cl_ros2_timer::ClRos2Timer; the countdown behaviors do the timing."""


class ClKeyboard(ISmaccClient):
    """Stands in for cl_keyboard::ClKeyboard: ``press('n')`` is a key message."""

    def __init__(self) -> None:
        self.listeners: list[Callable[[str], None]] = []

    def press(self, key: str) -> None:
        for listener in list(self.listeners):
            listener(key)


class CpPose(ISmaccComponent):
    def __init__(self, frame: str = "base_link", reference_frame: str = "odom") -> None:
        self.frame, self.reference_frame = frame, reference_frame


class CpOdomTracker(ISmaccComponent):
    pass


class CpPlannerSwitcher(ISmaccComponent):
    def __init__(self) -> None:
        self.planner = ""

    def set_default_planners(self) -> None:
        self.planner = "GridBased"


class CpGoalCheckerSwitcher(ISmaccComponent):
    pass


class CpAmcl(ISmaccComponent):
    """Records the initial poses it was asked to publish on /initialpose: (x, y, yaw) in map, m/rad."""

    def __init__(self) -> None:
        self.initial_poses: list[tuple[float, float, float]] = []

    def set_initial_pose(self, x: float, y: float, yaw: float) -> None:
        self.initial_poses.append((x, y, yaw))


class ClNav2Z(ISmaccClient):
    """Scripted Nav2 client. Outcomes are consumed in order; running out of script is a test bug."""

    def __init__(self, readiness: Iterable[str] = (), goals: Iterable[str] = (),
                 spins: Iterable[str] = ()) -> None:
        self.readiness = deque(readiness)
        self.goal_outcomes = deque(goals)
        self.spin_outcomes = deque(spins)
        self.goals_sent: list[tuple[float, float, float]] = []

    def next_readiness(self) -> str:
        return self.readiness.popleft() if self.readiness else "pending"

    def send_goal(self, x: float, y: float, yaw: float) -> str:
        """Send a NavigateToPose goal; the scripted result event is posted at once (ABSOLUTE lifetime)."""
        self.goals_sent.append((x, y, yaw))
        outcome = self.goal_outcomes.popleft()
        self.post_event(self.own_event(EvActionSucceeded if outcome == "succeeded" else EvActionAborted))
        return outcome

    def spin(self, yaw: float, max_angular_speed: float) -> str:
        return self.spin_outcomes.popleft()


# ----------------------------------------------------------------------------------------- orthogonals
class OrTimer(Orthogonal):
    def on_initialize(self) -> None:
        self.create_client(ClRos2Timer)


class OrKeyboard(Orthogonal):
    def on_initialize(self) -> None:
        self.create_client(ClKeyboard)


@dataclass(frozen=True)
class NavScript:
    """Outcomes the fake ClNav2Z replays, in order (see the module docstring)."""

    readiness: tuple[str, ...] = ()
    goals: tuple[str, ...] = ()
    spins: tuple[str, ...] = ()


class OrNavigation(Orthogonal):
    """ClNav2Z and its components as in the real package; the script comes from ``sm.nav_script``."""

    def on_initialize(self) -> None:
        script: NavScript = getattr(self.sm, "nav_script", NavScript())
        client = self.create_client(ClNav2Z, script.readiness, script.goals, script.spins)
        client.create_component(CpPose, "base_link", "map")
        client.create_component(CpOdomTracker)
        client.create_component(CpPlannerSwitcher)
        client.create_component(CpGoalCheckerSwitcher)
        client.create_component(CpAmcl)


# ----------------------------------------------------------------------------------------- behaviors
class CbWaitNav2Nodes(SmaccClientBehavior):
    """Success when the scripted readiness says so; failure or nothing otherwise."""

    def on_entry(self) -> None:
        outcome = self.requires_client(ClNav2Z).next_readiness()
        if outcome == "success":
            self.post_success_event()
        elif outcome == "failure":
            self.post_failure_event()


class CbTimerCountdownOnce(SmaccClientBehavior, ISmaccUpdatable):
    """Posts ``EvTimer[CbTimerCountdownOnce, Or]`` once, ``duration_s`` (s) of machine clock after entry."""

    def __init__(self, duration_s: float) -> None:
        self.duration_s = duration_s
        self.started_s = 0.0
        self.fired = False

    def on_entry(self) -> None:
        self.requires_client(ClRos2Timer)
        self.started_s = self.sm.now()

    def update(self) -> None:
        if not self.fired and self.sm.now() - self.started_s >= self.duration_s:
            self.fired = True
            self.post_event(self.own_event(EvTimer))


class CbDefaultKeyboardBehavior(SmaccClientBehavior):
    """Re-posts key presses as ``EvKeyPress<X>[CbDefaultKeyboardBehavior, OrKeyboard]``."""

    def on_entry(self) -> None:
        self.client = self.requires_client(ClKeyboard)
        self.client.listeners.append(self._on_key)

    def on_exit(self) -> None:
        self.client.listeners.remove(self._on_key)

    def _on_key(self, key: str) -> None:
        self.post_event(self.own_event(key_press_event(key)))


class CbNavigateGlobalPosition(SmaccClientBehavior):
    """Sends one goal (x, y in m, yaw in rad); also posts EvCbSuccess/EvCbFailure like the real one."""

    def __init__(self, x: float, y: float, yaw: float) -> None:
        self.goal = (x, y, yaw)

    def on_entry(self) -> None:
        self.requires_component(CpPlannerSwitcher).set_default_planners()
        outcome = self.requires_client(ClNav2Z).send_goal(*self.goal)
        if outcome == "succeeded":
            self.post_success_event()
        else:
            self.post_failure_event()


class CbPureSpinning(SmaccClientBehavior):
    """Spins ``yaw`` rad at up to ``max_angular_speed`` rad/s (scripted outcome)."""

    def __init__(self, yaw: float, max_angular_speed: float = 0.5) -> None:
        self.yaw, self.max_angular_speed = yaw, max_angular_speed

    def on_entry(self) -> None:
        if self.requires_client(ClNav2Z).spin(self.yaw, self.max_angular_speed) == "success":
            self.post_success_event()
        else:
            self.post_failure_event()
