"""An accepted action goal that a server's timer steps until it ends.

Why: controller_server and behavior_server run their goals in periodic cycles (20 Hz / 10 Hz on
the node clock, so sim time paces them) rather than in a loop inside the execute callback. The
execute callback only waits on :class:`GoalRun` (one executor thread blocks, which is why servers
run on a MultiThreadedExecutor); the timer decides the outcome; the execute callback then applies
it to the goal handle. Applying it there, not in the timer, keeps rclpy's goal-state transitions on
the thread that owns the goal, and a cancel is only acknowledged (``canceled``) once rclpy has
moved the goal to CANCELING.
"""

from __future__ import annotations

import enum
import threading
from typing import Any

from rclpy.action.server import ServerGoalHandle
from rclpy.context import Context

WAIT_POLL = 0.1  # s between checks that the context is still alive while waiting


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
        self._done = threading.Event()

    @property
    def finished(self) -> bool:
        return self._done.is_set()

    def finish(self, outcome: Outcome, error_code: int = 0, error_msg: str = "") -> None:
        """End the run (first call wins); ``error_code``/``error_msg`` go into the result."""
        if self._done.is_set():
            return
        self.result.error_code = int(error_code)
        self.result.error_msg = error_msg
        self.outcome = outcome
        self._done.set()

    def wait(self, context: Context) -> Any:
        """Block the execute callback until the run ends, set the goal's final state, return the result."""
        while not self._done.wait(WAIT_POLL):
            if not context.ok():
                self.finish(Outcome.ABORTED, error_msg="the node is shutting down")
        if self.outcome is Outcome.SUCCEEDED:
            self.handle.succeed()
        elif self.outcome is Outcome.CANCELED and self.handle.is_cancel_requested:
            self.handle.canceled()
        elif self.handle.is_active:
            self.handle.abort()
        return self.result
