"""Stand-ins for the ROS endpoints of cl_nav2z, cl_ros2_timer and cl_keyboard (see smacc_fake_nav.py).

Each class subclasses the real client or component and overrides only what touches ROS: the publishers
and subscriptions of ``on_initialize``, ClNav2Z's action clients and bond subscription, ClRos2Timer's
node timers. Everything else (event posting, goal bookkeeping, presets, paths) is the shipped code.
``ScriptedNav2.substitutes()`` maps each real type to its stand-in.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from geometry_msgs.msg import Twist
from std_msgs.msg import UInt16

from smacc_py.clients.cl_keyboard import ClKeyboard
from smacc_py.clients.cl_nav2z import (
    ClNav2Z,
    CpAmcl,
    CpGoalCheckerSwitcher,
    CpOdomTracker,
    CpPlannerSwitcher,
    CpPose,
)
from smacc_py.clients.cl_nav2z.client import ACTION_TYPES, NAVIGATE_TO_POSE
from smacc_py.core import ISmaccUpdatable
from smacc_py.ros.action_client import DoneCallback, FeedbackCallback, GoalOutcome, GoalTicket
from smacc_py.testing import ManualClRos2Timer

if TYPE_CHECKING:
    from tests.helpers.smacc_fake_nav import ScriptedNav2

#: The bond ids Nav2's lifecycle_manager_navigation holds.
NAV2_BOND_NODES = ("controller_server", "planner_server", "behavior_server", "bt_navigator",
                   "waypoint_follower")


class RecordingPublisher:
    """Stands in for an rclpy Publisher: keeps every message."""

    def __init__(self) -> None:
        self.messages: list[Any] = []

    def publish(self, msg: Any) -> None:
        self.messages.append(msg)

    def get_subscription_count(self) -> int:
        """One: someone always listens to a recording."""
        return 1


class BaseCmdVel:
    """Stands in for ClNav2Z's CmdVelPublisher: hands each (vx, wz) to the fake base as a Twist."""

    def __init__(self, base: Any) -> None:
        self.base = base

    def publish(self, vx: float, wz: float, stamp_ns: int | None = None) -> None:
        twist = Twist()
        twist.linear.x, twist.angular.z = float(vx), float(wz)
        self.base.publish(twist)


class ScriptedActionClient:
    """Stands in for RosActionClient: the server is always up; goals end on the next ``settle``."""

    def __init__(self, world: ScriptedNav2, key: str, action_name: str) -> None:
        self.world, self.key, self.action_name = world, key, action_name
        self.goals: list[Any] = []
        self._pending: list[tuple[GoalTicket, str, DoneCallback | None]] = []
        self._lock = threading.Lock()

    def server_ready(self) -> bool:
        return True

    def send_goal(self, goal: Any, on_done: DoneCallback | None = None,
                  on_feedback: FeedbackCallback | None = None) -> GoalTicket:
        ticket = GoalTicket(self.action_name, goal)
        with self._lock:
            self.goals.append(goal)
            self._pending.append((ticket, self.world.decide(self.key, goal), on_done))
        return ticket

    def active_tickets(self) -> list[GoalTicket]:
        with self._lock:
            return [ticket for ticket, _, _ in self._pending]

    def cancel_all(self) -> None:
        for ticket in self.active_tickets():
            ticket.cancel()

    def settle(self) -> None:
        """End every pending goal as decided (a held goal only once cancelled)."""
        with self._lock:
            pending, self._pending = self._pending, []
        held = []
        for ticket, decision, on_done in pending:
            if ticket.cancel_requested:
                outcome = GoalOutcome.CANCELED
            elif decision == "hold":
                held.append((ticket, decision, on_done))
                continue
            else:
                outcome = GoalOutcome.SUCCEEDED if decision == "succeeded" else GoalOutcome.ABORTED
            ticket.finish(outcome, self.world.result(self.key, ticket.goal, outcome, decision))
            if on_done is not None:
                on_done(ticket)
        with self._lock:
            self._pending[:0] = held

    def destroy(self) -> None:
        pass


class ScriptedClNav2Z(ClNav2Z, ISmaccUpdatable):
    """ClNav2Z with scripted action servers, the fake base as cmd_vel subscriber, scripted bonds."""

    def __init__(self, world: ScriptedNav2, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.world = world
        self._bond_listeners: list[Callable[[str, bool], None]] = []
        self.bond_holds: list[Callable[[], bool] | None] = []  # hold_until of each subscribe_bonds

    def on_initialize(self) -> None:
        self._clients = {key: ScriptedActionClient(self.world, key, self.action_names[key])  # type: ignore[misc]
                         for key in ACTION_TYPES}
        self._cmd_vel = BaseCmdVel(self.world.base)  # type: ignore[assignment]  # the base subscribes cmd_vel

    def cancel_every_navigation_goal(self, on_answer: Callable[[int | None], None]) -> None:
        on_answer(0)  # the scripted servers cancel a client's goals through cancel_navigation

    def subscribe_bonds(
        self, callback: Callable[[str, bool], None], topic: str = "/bond",
        hold_until: Callable[[], bool] | None = None,
    ) -> Callable[[], None]:
        self.bond_holds.append(hold_until)  # what a lockstep simulator would wait for
        if not self.world.next_bonds_up():
            return lambda: None
        self._bond_listeners.append(callback)
        return lambda: self._bond_listeners.remove(callback)

    def update(self) -> None:
        for client in self._clients.values():
            client.settle()  # type: ignore[attr-defined]
        for listener in list(self._bond_listeners):
            for node_id in NAV2_BOND_NODES:
                listener(node_id, True)

    def action_log(self, key: str = NAVIGATE_TO_POSE) -> ScriptedActionClient:
        """The scripted server of ``key``, with the goals it received."""
        return self._clients[key]  # type: ignore[return-value]


class ScriptedCpPose(CpPose):
    """CpPose looking the robot up in the fake base instead of TF."""

    def __init__(self, world: ScriptedNav2, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.world = world

    def on_initialize(self) -> None:
        self._listener = self.world.base  # type: ignore[assignment]


class ScriptedCpAmcl(CpAmcl):
    """CpAmcl publishing into a RecordingPublisher; the world's AMCL answers each initial pose with an
    estimate at that pose, unless it was published before ``Nav2Script.amcl_silent_until_s``."""

    def __init__(self, world: ScriptedNav2, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.world = world

    def on_initialize(self) -> None:
        self._pub = RecordingPublisher()  # type: ignore[assignment]

    def set_initial_pose(self, x: float, y: float, yaw: float, *args: Any, **kwargs: Any) -> None:
        super().set_initial_pose(x, y, yaw, *args, **kwargs)
        if self.world.clock() >= self.world.script.amcl_silent_until_s:
            self.on_estimate((float(x), float(y), float(yaw)))


class ScriptedCpOdomTracker(CpOdomTracker):
    """CpOdomTracker without the /odom subscription; paths go to RecordingPublishers."""

    def on_initialize(self) -> None:
        self._path_pub = RecordingPublisher()  # type: ignore[assignment]
        self._stacked_pub = RecordingPublisher()  # type: ignore[assignment]


class ScriptedCpPlannerSwitcher(CpPlannerSwitcher):
    """CpPlannerSwitcher publishing into RecordingPublishers."""

    def on_initialize(self) -> None:
        self._planner_pub = RecordingPublisher()  # type: ignore[assignment]
        self._controller_pub = RecordingPublisher()  # type: ignore[assignment]


class ScriptedCpGoalCheckerSwitcher(CpGoalCheckerSwitcher):
    """CpGoalCheckerSwitcher publishing into a RecordingPublisher."""

    def on_initialize(self) -> None:
        self._pub = RecordingPublisher()  # type: ignore[assignment]


#: ClRos2Timer whose timers fire on the machine's polls: the stand-in smacc_py ships for users' tests.
ScriptedClRos2Timer = ManualClRos2Timer


class ScriptedClKeyboard(ClKeyboard):
    """ClKeyboard without the subscription; ``press`` plays a /keyboard_unicode message."""

    def on_initialize(self) -> None:
        pass

    def press(self, key: str) -> None:
        self._on_key(UInt16(data=ord(key)))
