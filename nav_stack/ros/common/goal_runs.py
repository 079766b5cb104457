"""An accepted action goal that a server's timer steps until it ends.

Why: controller_server and behavior_server run their goals in periodic cycles (20 Hz / 10 Hz on
the node clock, so sim time paces them) rather than in a loop inside the execute callback. The
execute callback is a coroutine (run by ros_tools.runtime.actions.ActionServer) that awaits
:meth:`GoalRun.wait`: it suspends on a future and costs nothing until the run ends, while the one
executor thread serves timers, subscriptions and other goals. The timer
decides the outcome (:meth:`GoalRun.finish`); the coroutine then applies it to the goal handle.
Applying it there keeps rclpy's goal-state transitions inside the goal's own execute task, and a
cancel is only acknowledged (``canceled``) once rclpy has moved the goal to CANCELING.
"""

from __future__ import annotations

import enum
from collections.abc import Callable
from typing import Any

from rclpy.action import CancelResponse
from rclpy.action.server import ServerGoalHandle
from rclpy.task import Future

from ros_tools.runtime.coroutines import until


class Outcome(enum.Enum):
    SUCCEEDED = "succeeded"
    ABORTED = "aborted"
    CANCELED = "canceled"


class GoalRun:
    """One goal: its handle, the result being built, and the outcome once finished."""

    def __init__(self, handle: ServerGoalHandle, result: Any) -> None:
        self.handle = handle
        self.result = result
        self.stop_requested = False  # set by the cancel callback: send no more motion commands
        self.outcome: Outcome | None = None
        self._done = Future()

    @property
    def finished(self) -> bool:
        return self._done.done()

    def finish(self, outcome: Outcome, error_code: int = 0, error_msg: str = "") -> None:
        """End the run (first call wins); ``error_code``/``error_msg`` go into the result."""
        if self._done.done():
            return
        self.result.error_code = int(error_code)
        self.result.error_msg = error_msg
        self.outcome = outcome
        self._done.set_result(outcome)

    async def wait(self) -> Any:
        """Suspend the execute coroutine until the run ends, set the goal's final state, return the result."""
        await until(self._done)
        if self.outcome is Outcome.SUCCEEDED:
            self.handle.succeed()
        elif self.outcome is Outcome.CANCELED and self.handle.is_cancel_requested:
            self.handle.canceled()
        elif self.handle.is_active:
            self.handle.abort()
        return self.result


def cancel_current(run: GoalRun | None, handle: ServerGoalHandle,
                   stop_robot: Callable[[], None]) -> CancelResponse:
    """The cancel callback of a server that runs one goal at a time (controller_server, behavior_server,
    docking_server): a request for the running goal stops the robot at once and asks the server's next
    cycle to end the run (``stop_requested``); every request is accepted, as Nav2's servers do."""
    if run is not None and run.handle is handle:
        run.stop_requested = True
        stop_robot()
    return CancelResponse.ACCEPT
