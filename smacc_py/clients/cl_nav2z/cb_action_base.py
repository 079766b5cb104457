"""``CbNav2ZActionBase``: a behavior that sends one ClNav2Z action goal and reports its end.

``on_entry`` builds the goal (``make_goal`` returns (action key, goal) or None after posting its own
failure) and sends it at once when the action server is discovered. Otherwise sim time waits for the
server in lockstep (at most DISCOVERY_HOLD_S wall s), and the runtime's polling (ISmaccUpdatable, on
the executor thread) sends the goal as soon as the server appears, or posts
EvCbFailure once ``server_wait_s`` has passed both on the machine clock and on the wall clock
(discovery takes wall time; the machine clock keeps the wait at least as long in sim time however
fast the simulation runs). The goal's end posts ``EvCbSuccess`` or ``EvCbFailure[Cb, Or]`` with the
ticket's ``error_code``/``error_msg`` as payload (ClNav2Z posts its EvAction* events as well).
Unlike SMACC2, a goal still running when the state exits is cancelled (and disowned). Behaviors with
``record_path`` (global, forward and backward navigation, as in SMACC2) push a new CpOdomTracker path
and record into it while their goal runs, so CbUndoPathBackwards can undo the motion.

SMACC2's version is an async behavior whose thread waits for the server. This one never waits:
``on_entry`` returns at once, so the goal leaves at the sim time the state was entered.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any, TypeVar

from smacc_py.clients.cl_nav2z.client import ClNav2Z
from smacc_py.clients.cl_nav2z.cp_odom_tracker import CpOdomTracker
from smacc_py.clients.cl_nav2z.odom_path import WorkingMode
from smacc_py.core import ISmaccUpdatable, SmaccClientBehavior, SmaccLookupError
from smacc_py.ros.action_client import GoalOutcome, GoalTicket, RosActionClient
from smacc_py.ros.context import hold_lockstep

C = TypeVar("C")


class CbNav2ZActionBase(SmaccClientBehavior, ISmaccUpdatable):
    """Subclasses implement ``make_goal``; optionally ``on_goal_done`` for bookkeeping."""

    server_wait_s: float = 10.0
    record_path: bool = False
    ticket: GoalTicket | None = None
    _waiting: tuple[RosActionClient, str, Any, float, float] | None = None  # action, key, goal, since_s, wall
    _key: str = ""
    _unwatch: Callable[[], None] | None = None  # stops the watch of the goal's server

    def make_goal(self) -> tuple[str, Any] | None:
        """(action key, goal message), or None when the behavior already posted a failure."""
        raise NotImplementedError

    def optional_component(self, component_type: type[C]) -> C | None:
        """A component if some client has one, else None."""
        try:
            return self.requires_component(component_type)
        except SmaccLookupError:
            return None

    def on_entry(self) -> None:
        self.client = self.requires_client(ClNav2Z)
        planned = self.make_goal()
        if planned is None:
            return
        key, goal = planned
        action = self.client.action_client(key)
        if action.server_ready():
            self._send(key, goal)
        else:
            self._waiting = (action, key, goal, self.sm.now(), time.monotonic())
            # Discovery takes wall time: sim time waits for the server, so the goal leaves at the
            # same sim time on every run (instead of after however much sim ran meanwhile).
            hold_lockstep(self.sm, lambda: self._waiting is None or action.server_ready())

    def update(self) -> None:
        """While the server is not discovered: send once it is, or fail after ``server_wait_s``. Once
        the goal is accepted, watch its server (ClNav2Z.watch_server): a lost server ends the goal."""
        watch = getattr(self.client, "watch_server", None)  # a test stand-in for ClNav2Z may lack it
        if watch is not None and self.ticket is not None and self._unwatch is None and not self.ticket.done:
            self._unwatch = watch(self._key, self.ticket)
        if self._waiting is None:
            return
        action, key, goal, since_s, since_wall = self._waiting
        if action.server_ready():
            self._waiting = None
            self._send(key, goal)
        elif (self.sm.now() - since_s > self.server_wait_s
              and time.monotonic() - since_wall > self.server_wait_s):
            self._waiting = None
            self.post_failure_event(
                error_code=0,
                error_msg="",
                reason=f"action server '{action.action_name}' not available after {self.server_wait_s:.0f} s",
            )

    def _send(self, key: str, goal: Any) -> None:
        tracker = self.optional_component(CpOdomTracker) if self.record_path else None
        if tracker is not None:
            tracker.push_path(type(self.state).__name__)
            tracker.set_working_mode(WorkingMode.RECORD_PATH)
        self._key = key
        self.ticket = self.client.send_goal(key, goal, on_done=self._on_done)

    def _stop_recording(self) -> None:
        tracker = self.optional_component(CpOdomTracker) if self.record_path else None
        if tracker is not None:
            tracker.set_working_mode(WorkingMode.IDLE)

    def _stop_watching(self) -> None:
        unwatch, self._unwatch = self._unwatch, None
        if unwatch is not None:
            unwatch()

    def _on_done(self, ticket: GoalTicket) -> None:
        self._stop_watching()
        self._stop_recording()
        if ticket.abandoned:
            return
        self.on_goal_done(ticket)
        payload = {"error_code": ticket.error_code, "error_msg": ticket.error_msg, "result": ticket.result}
        if ticket.outcome is GoalOutcome.SUCCEEDED:
            self.post_success_event(**payload)
        else:
            self.post_failure_event(reason=ticket.describe(), **payload)

    def on_goal_done(self, ticket: GoalTicket) -> None:
        """Hook called before the success/failure event (on the executor thread; must be quick)."""

    def on_exit(self) -> None:
        self._waiting = None
        self._stop_watching()
        ticket = self.ticket
        if ticket is not None and not ticket.done:
            ticket.abandon()
            self._stop_recording()
