"""Requests sent again until one copy is answered: service calls here, action goals in :mod:`.actions`.

Why: a client's ``service_is_ready()`` (or ``server_is_ready()``) is the client's own view of the
match. When a request arrives before the server's response writer has matched the client's response
reader, rmw_fastrtps waits 100 ms for that match and then drops the response ("failed to send
response (timeout): client will not receive response"); the client is never told. Seen under load
and late in a long test session: a lifecycle bring-up stalled for its whole 30 s ``service_timeout``
on one lost ``get_state`` answer, and a test waited 10 s for ``reinitialize_global_localization``.
A copy sent later finds the match complete.

So a request that is not answered in time is sent again, after 1, 2, 4 ... s (steady clock), until
the caller's timeout. Only requests that are safe to receive twice are sent again: queries,
idempotent commands, and lifecycle transitions, whose caller checks the node's state afterwards
rather than trusting one answer. A copy answered after the first is ignored. A request that is not
safe twice, or that legitimately takes longer than a second (SaveMap refuses to overwrite the file
its first copy wrote, and waits up to save_map_timeout for a map), passes ``resend_after=None``.

Two twins, as in :mod:`.actions`: :func:`call_service` awaits in a coroutine on the node's own
executor (nothing blocks); :func:`call_until_answered` waits with a caller-supplied :data:`Wait`
(a thread that is not the executor's, or a test that spins the executor itself).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable
from typing import Any

from rclpy.clock import Clock
from rclpy.node import Node
from rclpy.task import Future

from ros_tools.runtime.waiting import first_of, steady_clock, wait_for

#: s (wall) an unanswered service request waits before its first copy is sent; doubles per copy.
SERVICE_RETRY_S = 1.0

#: ``wait(predicate, seconds) -> bool``: True once ``predicate()`` holds, False after ``seconds``.
Wait = Callable[[Callable[[], bool], float], bool]


def poll(predicate: Callable[[], bool], seconds: float, step: float = 0.02) -> bool:
    """A :data:`Wait` for a client whose node an executor spins in another thread: check every
    ``step`` s; True once ``predicate()`` holds, False after ``seconds``."""
    deadline = time.monotonic() + seconds
    while not predicate():
        if time.monotonic() >= deadline:
            return False
        time.sleep(step)
    return True


def doubling(first: float, total: float) -> list[float]:
    """Waits of ``first``, 2·``first``, 4·``first`` ... s that add up to ``total`` s (the last one
    shortened); one wait of ``total`` when it is shorter than ``first``."""
    waits: list[float] = []
    left, wait = total, first
    while left > 1e-9:
        waits.append(min(wait, left))
        left -= waits[-1]
        wait *= 2.0
    return waits or [total]


async def first_answer(node: Node, send: Callable[[], Future], waits: Iterable[float],
                       clock: Clock | None = None,
                       wanted: Callable[[], bool] = lambda: True) -> tuple[Future | None, list[Future]]:
    """Coroutine: ``send()`` a copy, await its answer for the next of ``waits`` (s on ``clock``, a
    steady clock unless given), and send another while none of the copies is answered.

    The first answered copy (None when the waits ran out or ``wanted()`` turned False), and every
    copy sent, so that the caller can withdraw the others.
    """
    clock = steady_clock() if clock is None else clock
    copies: list[Future] = []
    for wait in waits:
        if not wanted():
            break
        copies.append(send())
        answered = first_of(*copies)
        if await wait_for(node, answered, wait, clock):
            return (answered.result() if wanted() else None), copies
    return None, copies


def resend_waits(timeout: float, resend_after: float | None) -> list[float]:
    """How long each copy waits (s): doubling from ``resend_after``, or one wait when it is None."""
    return [timeout] if resend_after is None else doubling(resend_after, timeout)


async def call_service(node: Node, client: Any, request: Any, timeout: float, clock: Clock | None = None,
                       resend_after: float | None = SERVICE_RETRY_S) -> Any | None:
    """Coroutine: the response of ``client`` (a service client of ``node``) to ``request``, sent again
    while unanswered (module docstring); None when no copy is answered within ``timeout`` s."""
    answer, copies = await first_answer(node, lambda: client.call_async(request),
                                        resend_waits(timeout, resend_after), clock)
    _withdraw(client, copies, answer)
    return None if answer is None else answer.result()


def call_until_answered(client: Any, request: Any, timeout: float, wait: Wait = poll,
                        resend_after: float | None = SERVICE_RETRY_S) -> Any:
    """Blocking twin of :func:`call_service` for a thread that may wait (``wait`` spins or polls):
    the response; TimeoutError when no copy is answered within ``timeout`` s (wall)."""
    copies: list[Future] = []
    answered = lambda: any(copy.done() for copy in copies)  # noqa: E731
    for pause in resend_waits(timeout, resend_after):
        copies.append(client.call_async(request))
        if wait(answered, pause):
            answer = next(copy for copy in copies if copy.done())
            _withdraw(client, copies, answer)
            return answer.result()
    _withdraw(client, copies, None)
    raise TimeoutError(f"'{client.srv_name}' did not answer within {timeout:.1f} s "
                       f"({len(copies)} copies sent)")


def _withdraw(client: Any, copies: list[Future], answer: Future | None) -> None:
    """Forget the copies other than ``answer`` that are still pending (their answers are ignored)."""
    for copy in copies:
        if copy is not answer and not copy.done():
            client.remove_pending_request(copy)
