"""A NavigateToPose goal given up before its acknowledgement: the autonomy node must not exit until the
server has the cancel of the copy it accepted meanwhile.

Seen in a full test run (test_sigterm_cancels_the_running_goal_and_exits): SIGTERM came after the
server had accepted the goal and before the client had the acknowledgement. The client gave the goal
up as "canceled before the server acknowledged the goal", said every cancel was answered, and exited
with the late copy's cancel still in its DDS queue; the goal ran on in the server.

The futures here are rclpy's own (their done callbacks run at once without an executor); the goal
handle is a stand-in that records the cancel it is asked for.
"""

from __future__ import annotations

import pytest

pytest.importorskip("nav2_msgs.action", reason="nav2_msgs is not built (run the interface build)")

from rclpy.task import Future

from nav_stack.ros.autonomy.navigator import RosNavGoal
from nav_stack.ros.autonomy.seed_nodes import NavOutcome
from ros_tools.runtime.actions import Withdrawals


class StandInHandle:
    """A goal handle: ``accepted``, and the cancel requests sent for it (rclpy futures)."""

    def __init__(self, accepted: bool) -> None:
        self.accepted = accepted
        self.cancels: list[Future] = []

    def cancel_goal_async(self) -> Future:
        self.cancels.append(Future())
        return self.cancels[-1]


def test_a_copy_accepted_late_is_canceled_and_settles_only_with_the_cancel_answer() -> None:
    withdrawals, copy, handle = Withdrawals(), Future(), StandInHandle(accepted=True)
    withdrawals.add(copy)
    assert not withdrawals.settled()  # its answer is still on the way
    copy.set_result(handle)
    assert len(handle.cancels) == 1
    assert not withdrawals.settled()  # the cancel is sent, not yet answered
    handle.cancels[0].set_result(object())
    assert withdrawals.settled()


def test_a_copy_rejected_or_lost_settles_without_a_cancel() -> None:
    withdrawals, rejected, lost = Withdrawals(), Future(), Future()
    handle = StandInHandle(accepted=False)
    withdrawals.add(rejected)
    withdrawals.add(lost)
    rejected.set_result(handle)
    lost.set_exception(RuntimeError("client destroyed"))
    assert handle.cancels == []
    assert withdrawals.settled()


def test_a_goal_given_up_before_its_acknowledgement_waits_for_the_late_cancel() -> None:
    """The navigator's path: cancel() before the acknowledgement, the coroutine ends the goal as
    canceled and withdraws the copy; the server's acceptance of it then arrives."""
    goal, copy, handle = RosNavGoal(), Future(), StandInHandle(accepted=True)
    goal.cancel()
    assert not goal.cancel_answered()  # asked for before the acknowledgement
    goal._withdrawals.add(copy)
    goal._finish(NavOutcome.CANCELED, "canceled before the server acknowledged the goal")
    assert not goal.cancel_answered()  # the old code said True here, and the process exited
    copy.set_result(handle)
    assert len(handle.cancels) == 1 and not goal.cancel_answered()
    handle.cancels[0].set_result(object())
    assert goal.cancel_answered()
