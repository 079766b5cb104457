"""A scripted Nav2 world for running shipped smacc_py machines in unit tests, without ROS.

``ScriptedNav2`` is the fake world of one test: a manual machine clock, a robot base, Nav2's servers as
``Nav2Script`` says, and ``substitutes()``, the mapping a machine is built with
(``SmaccStateMachineBase(substitutes=...)``) so that its orthogonals create the stand-ins of
smacc_stand_ins.py instead of the ROS clients and components. A stand-in subclasses the real class and
overrides only its ROS endpoints; states, orthogonals, tags and behaviors (CbWaitNav2Nodes,
CbNavigateGlobalPosition, CbPureSpinning, the timer and keyboard behaviors ...) are the shipped ones.
No rclpy context or node is created; the message classes are used as plain data.

What the world does:

* bonds: each ``ClNav2Z.subscribe_bonds`` (one per CbWaitNav2Nodes entry) takes the next entry of
  ``Nav2Script.bonds``: True, Nav2's servers heartbeat on every poll; False, silence (the behavior times
  out). Past the script, Nav2 is up.
* AMCL: each initial pose CpAmcl publishes comes back at once as AMCL's estimate, unless it was sent
  before ``Nav2Script.amcl_silent_until_s`` (machine clock; ``math.inf``: AMCL never answers).
* actions: a goal ends on the next poll (``sm.update()``). navigate_to_pose takes the next scripted
  ``navigate`` outcome ("succeeded", "aborted", "lost": aborted as when ClNav2Z lost the server, or
  "hold": until cancelled); past the script it succeeds
  unless the goal lies outside turtlebot3_world's map, which aborts with Nav2's GOAL_OUTSIDE_MAP (204).
  Success puts the robot at the goal, so the pose agrees with what Nav2 reported. Cancelled goals end
  CANCELED.
* cmd_vel: every Twist is kept in ``base.twists``; the base moves at the commanded velocity on the
  machine clock unless ``Nav2Script.robot_moves`` is False.
* TF: CpPose gets the base's pose; ``Nav2Script.tf_available`` False makes every lookup fail.
* timers: ClRos2Timer's timers fire on the first poll at or after their period (machine clock).
* keys: ``world.keyboard(sm).press("n")`` is a /keyboard_unicode message.

``drive(sm, until)`` runs a started machine as the ROS runtime would, on the fake clock: advance,
poll, dispatch, until ``until()`` holds. It steps by the shortest ``update_period_s`` of the active
behaviors (CbPureSpinning's 0.1 s control period), else 0.5 s at a time; while an async behavior's
thread runs it steps 0.1 s and gives that thread a few wall milliseconds per step.
"""

from __future__ import annotations

import functools
import math
import threading
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, NamedTuple, TypeVar

from geometry_msgs.msg import Twist
from nav2_msgs.action import NavigateToPose

from ros_tools.tf import TransformError
from smacc_py.clients.cl_keyboard import ClKeyboard
from smacc_py.clients.cl_nav2z import (
    ClNav2Z,
    CpAmcl,
    CpGoalCheckerSwitcher,
    CpOdomTracker,
    CpPlannerSwitcher,
    CpPose,
)
from smacc_py.clients.cl_nav2z.client import ACTION_TYPES, NAVIGATE_TO_POSE, SERVER_LOST, SERVER_LOST_CODE
from smacc_py.clients.cl_nav2z.geometry import quaternion_to_yaw
from smacc_py.clients.cl_ros2_timer import ClRos2Timer
from smacc_py.core import ISmaccUpdatable, SmaccAsyncClientBehavior, SmaccStateMachineBase
from smacc_py.ros.action_client import GoalOutcome
from tests.helpers.smacc_stand_ins import (
    RecordingPublisher,
    ScriptedClKeyboard,
    ScriptedClNav2Z,
    ScriptedClRos2Timer,
    ScriptedCpAmcl,
    ScriptedCpGoalCheckerSwitcher,
    ScriptedCpOdomTracker,
    ScriptedCpPlannerSwitcher,
    ScriptedCpPose,
)

__all__ = ["FakeBase", "ManualClock", "Nav2Script", "RecordingPublisher", "ScriptedNav2", "goal_pose"]

M = TypeVar("M", bound=SmaccStateMachineBase)
Pose2D = tuple[float, float, float]

#: turtlebot3_world's map extent (maps/turtlebot3_world.yaml): x_min, y_min, x_max, y_max in m.
MAP_BOUNDS = (-3.8, -3.9, 5.2, 3.9)
GOAL_OUTSIDE_MAP = 204
ASYNC_STEP_S = 0.1  # clock step while an async behavior's thread runs
IDLE_STEP_S = 0.5
THREAD_SLICE_WALL_S = 0.006  # > the 5 ms an async behavior's machine-clock sleep polls at


@dataclass(frozen=True)
class Nav2Script:
    """What the fake Nav2 does (see the module docstring)."""

    bonds: tuple[bool, ...] = ()
    navigate: tuple[str, ...] = ()
    robot_moves: bool = True
    tf_available: bool = True
    start_pose: Pose2D = (-2.0, -0.5, 0.0)
    amcl_silent_until_s: float = 0.0


class ManualClock:
    """The machine clock (s); only ``drive`` (or the test) moves it."""

    def __init__(self) -> None:
        self.t = 0.0

    def __call__(self) -> float:
        return self.t

class BasePose(NamedTuple):
    """What CpPose reads from a TF lookup."""

    x: float
    y: float
    yaw: float


class FakeBase:
    """The robot: takes cmd_vel Twists (``publish``), integrates them on the machine clock, answers TF."""

    def __init__(self, clock: ManualClock, script: Nav2Script) -> None:
        self.clock, self.script = clock, script
        self.pose: Pose2D = script.start_pose
        self.twists: list[Twist] = []
        self._v = self._w = 0.0
        self._t = clock()
        self._lock = threading.Lock()

    def _advance(self) -> None:
        now = self.clock()
        dt, self._t = now - self._t, now
        if self.script.robot_moves and dt > 0.0:
            x, y, yaw = self.pose
            v, w = self._v, self._w
            self.pose = (x + v * math.cos(yaw) * dt, y + v * math.sin(yaw) * dt, yaw + w * dt)

    def publish(self, twist: Twist) -> None:
        with self._lock:
            self._advance()
            self._v, self._w = twist.linear.x, twist.angular.z
            self.twists.append(twist)

    def lookup(self, target: str, source: str) -> BasePose:
        if not self.script.tf_available:
            raise TransformError(f'"{target}" passed to lookupTransform argument target_frame does not exist')
        with self._lock:
            self._advance()
            return BasePose(*self.pose)

    def teleport(self, pose: Pose2D) -> None:
        with self._lock:
            self._advance()
            self.pose = pose

class ScriptedNav2:
    """One test's fake world; ``start(SmType)`` builds and starts a machine on it, ``close()`` stops them."""

    def __init__(self, script: Nav2Script | None = None) -> None:
        self.script = script or Nav2Script()
        self.clock = ManualClock()
        self.base = FakeBase(self.clock, self.script)
        self._bonds = deque(self.script.bonds)
        self._navigate = deque(self.script.navigate)
        self._machines: list[SmaccStateMachineBase] = []

    # ------------------------------------------------------------------ the machine side
    def substitutes(self) -> dict[type, Callable[..., object]]:
        """Real client/component type → stand-in factory, for ``SmaccStateMachineBase(substitutes=...)``."""
        return {
            ClNav2Z: functools.partial(ScriptedClNav2Z, self),
            CpPose: functools.partial(ScriptedCpPose, self),
            CpAmcl: functools.partial(ScriptedCpAmcl, self),
            CpOdomTracker: ScriptedCpOdomTracker,
            CpPlannerSwitcher: ScriptedCpPlannerSwitcher,
            CpGoalCheckerSwitcher: ScriptedCpGoalCheckerSwitcher,
            ClRos2Timer: ScriptedClRos2Timer,
            ClKeyboard: ScriptedClKeyboard,
        }

    def start(self, sm_type: type[M], **kwargs: Any) -> M:
        """Build ``sm_type`` on this world's clock and substitutes, start it and dispatch its first events."""
        sm = sm_type(now=self.clock, substitutes=self.substitutes(), **kwargs)
        self._machines.append(sm)
        sm.start()
        sm.process_events()
        return sm

    def drive(self, sm: SmaccStateMachineBase, until: Callable[[], bool], max_sim_s: float = 300.0) -> bool:
        """Advance the clock, poll and dispatch until ``until()``; False if ``max_sim_s`` passed first."""
        deadline = self.clock.t + max_sim_s
        sm.process_events()
        while not until():
            if self.clock.t >= deadline:
                return False
            behaviors = [b for state in sm.active_states() for _, b in state.behaviors]
            busy = any(isinstance(b, SmaccAsyncClientBehavior) and not b.is_finished() for b in behaviors)
            periods = [b.update_period_s for b in behaviors
                       if isinstance(b, ISmaccUpdatable) and b.update_period_s is not None]
            self.clock.t += min([*periods, ASYNC_STEP_S if busy else IDLE_STEP_S])
            sm.update()
            if busy:
                sm.run_until(until, THREAD_SLICE_WALL_S)
            else:
                sm.process_events()
        return True

    def close(self) -> None:
        """Stop every machine started here (joins their behaviors' threads)."""
        for sm in self._machines:
            if sm.is_running:
                sm.stop()

    # ------------------------------------------------------------------ the Nav2 side
    def next_bonds_up(self) -> bool:
        return self._bonds.popleft() if self._bonds else True

    def decide(self, key: str, goal: Any) -> str:
        """How a new goal will end: "succeeded", "aborted" or "hold"."""
        if key != NAVIGATE_TO_POSE:
            return "succeeded"
        if self._navigate:
            return self._navigate.popleft()
        x, y, _ = goal_pose(goal)
        x_min, y_min, x_max, y_max = MAP_BOUNDS
        return "succeeded" if x_min <= x <= x_max and y_min <= y <= y_max else "aborted"

    def result(self, key: str, goal: Any, outcome: GoalOutcome, decision: str = "") -> Any:
        """The action's result message; navigation success moves the robot to the goal. A "lost" goal
        ends as ClNav2Z ends one whose server it lost (SERVER_LOST_CODE, "server lost: ...")."""
        result = ACTION_TYPES[key].Result()
        if key != NAVIGATE_TO_POSE:
            return result
        if decision == "lost":
            result.error_code = SERVER_LOST_CODE
            result.error_msg = f"{SERVER_LOST}: the server died (scripted)"
        elif outcome is GoalOutcome.SUCCEEDED:
            self.base.teleport(goal_pose(goal))
        elif outcome is GoalOutcome.ABORTED:
            result.error_code, result.error_msg = GOAL_OUTSIDE_MAP, "Goal outside map"
        return result

    def navigation_goals(self, sm: SmaccStateMachineBase) -> list[Pose2D]:
        """(x, y, yaw) of every navigate_to_pose goal the machine sent."""
        nav = sm.requires_client(ClNav2Z)
        assert isinstance(nav, ScriptedClNav2Z)
        return [goal_pose(goal) for goal in nav.action_log().goals]

    @staticmethod
    def keyboard(sm: SmaccStateMachineBase) -> ScriptedClKeyboard:
        """The machine's keyboard client, to ``press`` keys."""
        keyboard = sm.requires_client(ClKeyboard)
        assert isinstance(keyboard, ScriptedClKeyboard)
        return keyboard

def goal_pose(goal: NavigateToPose.Goal) -> Pose2D:
    """(x, y, yaw) of a NavigateToPose goal."""
    p, q = goal.pose.pose.position, goal.pose.pose.orientation
    return p.x, p.y, quaternion_to_yaw(q.x, q.y, q.z, q.w)
