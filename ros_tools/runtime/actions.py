"""rclpy's ActionServer, with execute callbacks that run as :func:`.coroutines.spawn` coroutines,
and an ActionClient safe to send from another thread than the one spinning it.

Why: rclpy awaits an ``async def`` execute callback inside an executor task. A goal lasts seconds
to minutes, and while it awaits its outcome that task is re-run on every executor turn (the
EventsExecutor re-posts it at once: a busy core per running goal). This server starts the execute
callback with :func:`.coroutines.spawn` instead, which resumes it only when the future it awaits
completes, then finishes the goal exactly as rclpy does: a goal left active is aborted, and the
result goes to every client waiting for it.

A plain (non-async) execute callback works as in rclpy.
"""

from __future__ import annotations

import inspect
import os
import threading
import time
from collections.abc import Callable
from typing import Any

from rclpy.action import ActionClient as RclpyActionClient
from rclpy.action import ActionServer as RclpyActionServer
from rclpy.task import Future

from ros_tools.runtime.coroutines import spawn
from ros_tools.runtime.requests import Wait, first_answer, poll

#: s a finished goal's result stays on the server: rcl's default and Nav2's ``action_server_result_timeout``.
#: rclpy's own default is 900 s. A navigation stack sends a new FollowPath and ComputePathToPose goal
#: at every replan, so it kept 15 min of paths (the nav2 process grew 137 -> 260 MiB over 30 goals in
#: turtlebot3_house; rclpy issue #1300).
RESULT_TIMEOUT_S = 10


class ActionServer(RclpyActionServer):
    """``rclpy.action.ActionServer`` with the behaviour of the module docstring, and a result kept
    RESULT_TIMEOUT_S s unless ``result_timeout`` (s) says otherwise."""

    def __init__(self, *args: Any, result_timeout: int = RESULT_TIMEOUT_S, **kwargs: Any) -> None:
        super().__init__(*args, result_timeout=result_timeout, **kwargs)

    async def _execute_goal(self, execute_callback: Any, goal_handle: Any) -> None:
        try:
            outcome = execute_callback(goal_handle)
        except Exception:
            self._logger.error(f"execute callback raised: {_traceback()}")
            outcome = self._action_type.Result()
        if inspect.iscoroutine(outcome):
            outcome = spawn(self._node, outcome)
        if isinstance(outcome, Future):
            outcome.add_done_callback(lambda done: self._finish(goal_handle, done))
        else:
            self._conclude(goal_handle, outcome)

    def _finish(self, goal_handle: Any, done: Future) -> None:
        result = done.result() if done.exception() is None else self._action_type.Result()
        self._conclude(goal_handle, result)

    def _conclude(self, goal_handle: Any, result: Any) -> None:
        """rclpy's end of a goal: abort one left active, then answer every result request."""
        if goal_handle.is_active:
            goal_id = bytes(goal_handle.goal_id.uuid).hex()
            self._logger.warning(f"goal state not set, assuming aborted: {goal_id}")
            goal_handle.abort()
        response = self._action_type.Impl.GetResultService.Response()
        response.status = goal_handle.status
        response.result = result
        self._result_futures[bytes(goal_handle.goal_id.uuid)].set_result(response)


def _traceback() -> str:
    import traceback

    return traceback.format_exc()


#: s (wall) an unacknowledged goal request waits before it is sent again.
ACK_RETRY_S = 5.0


def send_until_acknowledged(client: Any, goal: Any, timeout: float, wait: Wait = poll,
                            feedback_callback: Any = None,
                            copies: list[tuple[Future, Any]] | None = None) -> Future:
    """Send ``goal`` and send it again every ACK_RETRY_S s until the server answers one copy; that
    copy's ``send_goal_async`` future (its result may still be a rejection).

    Why: see :mod:`.requests` (a response dropped while the server still matches the client; a
    request that reaches a reader still matching can be dropped the same way). Each copy carries a
    new goal id; a copy acknowledged after the first is canceled if accepted, so that it cannot
    preempt the first. ``feedback_callback`` hears only the acknowledged copy: the server may run
    another copy for a while before its cancel arrives (CI run DS: a second run's feedback
    restarted at 4 m remaining in the first's list). Every copy's (future, goal id) is appended to
    ``copies``, so that a caller interrupted before the acknowledgement can cancel what the server
    accepted. TimeoutError after ``timeout`` s (wall).
    """
    from unique_identifier_msgs.msg import UUID

    copies = [] if copies is None else copies
    feedback = None if feedback_callback is None else _FeedbackOfOneCopy(feedback_callback)
    answered = lambda: any(future.done() for future, _ in copies)  # noqa: E731
    deadline = time.monotonic() + timeout
    while (left := deadline - time.monotonic()) > 0:
        goal_id = UUID(uuid=list(os.urandom(16)))
        copies.append((client.send_goal_async(goal, feedback_callback=feedback, goal_uuid=goal_id), goal_id))
        if wait(answered, min(ACK_RETRY_S, left)):
            first, first_id = next((future, copy_id) for future, copy_id in copies if future.done())
            if feedback is not None:
                feedback.choose(first_id)
            for extra, _ in copies:
                if extra is not first:
                    extra.add_done_callback(cancel_if_accepted)
            return first
    raise TimeoutError(f"'{client._action_name}' did not acknowledge the goal within {timeout:.0f} s "
                       f"({len(copies)} copies sent)")


class _FeedbackOfOneCopy:
    """A feedback callback that passes on the feedback of one goal id, chosen once its copy was
    acknowledged; feedback that arrives before the choice waits for it (thread-safe: the executor
    may spin in another thread than the sender's)."""

    def __init__(self, callback: Callable[[Any], None]) -> None:
        self._callback = callback
        self._lock = threading.Lock()
        self._chosen: bytes | None = None
        self._early: list[Any] = []

    def __call__(self, msg: Any) -> None:
        with self._lock:  # held while passing on: feedback keeps its order across the choice
            if self._chosen is None:
                self._early.append(msg)
            elif bytes(msg.goal_id.uuid) == self._chosen:
                self._callback(msg)

    def choose(self, goal_id: Any) -> None:
        """Pass on ``goal_id``'s feedback from now on, starting with what arrived before."""
        with self._lock:
            self._chosen = bytes(goal_id.uuid)
            early, self._early = self._early, []
            for msg in early:
                if bytes(msg.goal_id.uuid) == self._chosen:
                    self._callback(msg)


async def acknowledged(node: Any, client: Any, goal: Any, sends: int,
                       wanted: Callable[[], bool] = lambda: True, clock: Any = None,
                       withdrawals: Withdrawals | None = None) -> Future | None:
    """Coroutine twin of :func:`send_until_acknowledged`, for a node's own executor (await it in a
    :func:`.coroutines.spawn` coroutine; nothing blocks): send ``goal``, and again every ACK_RETRY_S s
    (``clock``: a steady clock unless given), at most ``sends`` copies. The acknowledged copy's
    ``send_goal_async`` future; None when no copy was acknowledged or ``wanted()`` turned False.
    Copies acknowledged later, or after the caller stopped wanting the goal, are canceled if accepted;
    pass ``withdrawals`` to know when those cancels have reached the server (:class:`Withdrawals`).
    """
    answer, copies = await first_answer(node, lambda: client.send_goal_async(goal), [ACK_RETRY_S] * sends,
                                        clock, wanted)
    withdrawals = Withdrawals() if withdrawals is None else withdrawals
    for copy in copies:
        if copy is not answer:
            withdrawals.add(copy)
    return answer


def cancel_if_accepted(future: Future) -> Future | None:
    """Done callback for a ``send_goal_async`` future whose goal is no longer wanted: cancel the goal
    if the server accepted it (its acknowledgement was still on the way when the caller gave up).
    The cancel request's future; None when there was nothing to cancel (rejected, or no answer)."""
    handle = future.result() if future.exception() is None else None
    return handle.cancel_goal_async() if handle is not None and handle.accepted else None


class Withdrawals:
    """Copies of a goal the caller no longer wants: each one the server accepts is canceled.

    :meth:`settled` is true once every copy has its answer and every cancel sent for one has its
    response. A process that is about to exit waits for it: a request still in the process's DDS
    queue dies with the process, and the server then goes on with the goal. Seen with SIGTERM
    between the server's acceptance of a goal and the client's receipt of the acknowledgement: the
    client gave the goal up as "canceled before acknowledged", exited, and the goal ran on.
    """

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._unsettled: list[Future] = []  # copies awaiting their answer, cancels awaiting theirs

    def add(self, copy: Future) -> None:
        """Withdraw ``copy`` (a ``send_goal_async`` future): cancel its goal if the server accepts it."""
        with self._lock:
            self._unsettled.append(copy)
        copy.add_done_callback(self._on_answer)

    def settled(self) -> bool:
        with self._lock:
            return not self._unsettled

    def _on_answer(self, copy: Future) -> None:
        cancel = cancel_if_accepted(copy)
        with self._lock:
            self._unsettled.remove(copy)
            if cancel is not None:
                self._unsettled.append(cancel)
        if cancel is not None:
            cancel.add_done_callback(self._forget)

    def _forget(self, cancel: Future) -> None:
        with self._lock:
            self._unsettled.remove(cancel)


class ActionClient(RclpyActionClient):
    """``rclpy.action.ActionClient`` that may send from one thread while an executor spins in another.

    Why: rclpy (7.1.x) sends a goal, cancel or result request first and records it as pending after.
    When an executor spins the client's node in another thread, a fast server's response can be
    taken in between; rclpy then drops it ("Ignoring unexpected goal response") and the future
    never completes. Seen with BasicNavigator-style clients against the stack at a high real-time
    factor. Here sending-and-recording and taking-a-response are made atomic with one lock.
    """

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._request_lock = threading.RLock()

    def send_goal_async(self, *args: Any, **kwargs: Any) -> Future:
        with self._request_lock:
            return super().send_goal_async(*args, **kwargs)

    def _cancel_goal_async(self, goal_handle: Any) -> Future:
        with self._request_lock:
            return super()._cancel_goal_async(goal_handle)

    def _get_result_async(self, goal_handle: Any) -> Future:
        with self._request_lock:
            return super()._get_result_async(goal_handle)

    async def execute(self, taken_data: Any) -> None:
        responses = {key: taken_data.pop(key) for key in _RESPONSES if key in taken_data}
        if responses:
            with self._request_lock:  # rclpy handles responses without awaiting anything
                await super().execute(responses)
        if taken_data:  # feedback and status, in rclpy's order (after the responses)
            await super().execute(taken_data)


_RESPONSES = ("goal", "cancel", "result")
