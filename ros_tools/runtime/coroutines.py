"""Coroutines on a ROS executor that cost nothing while they wait.

Why not rclpy's own tasks: awaiting an rclpy ``Future`` yields ``None`` until it is done, so the
executor must keep re-running the task to find out. rclpy's Python executors re-run every pending
task on each wake-up; the C++ EventsExecutor (rclpy 7.1) re-posts it at once, so one goal
awaiting its outcome kept a core busy (measured: 2.6 s of CPU in a 3 s wait). It also ignores
coroutine timer and service callbacks (they are called, never awaited).

Here a coroutine awaits :func:`until` (or the helpers in :mod:`.waiting`, which use it): it yields
the future it waits for, and :func:`spawn` resumes it from that future's done callback. Between
the two nothing runs. Each resumption is one executor task, on the executor's thread.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Coroutine, Generator
from typing import Any

from rclpy.node import Node
from rclpy.task import Future

_log = logging.getLogger("ros_tools.runtime")


class _Until:
    """The awaitable of :func:`until`: yields its future to :func:`spawn` until it is done."""

    def __init__(self, future: Future) -> None:
        self.future = future

    def __await__(self) -> Generator[Future, None, Any]:
        while not self.future.done():
            yield self.future
        return self.future.result()


def until(future: Future) -> Any:
    """``await until(future)``: suspend until ``future`` is done; its result."""
    return _Until(future)


def spawn(node: Node, coroutine: Coroutine[Any, Any, Any]) -> Future:
    """Run ``coroutine`` on ``node``'s executor; a future of its return value.

    The coroutine must await through :func:`until`; anything else it awaits is retried on the
    next executor turn (correct, but polling). An exception is logged with its traceback and set
    on the returned future.
    """
    result = Future()
    executor = node.executor
    if executor is None:
        raise RuntimeError(f"spawn: node '{node.get_name()}' is not added to an executor")

    def step(*_: Any) -> None:
        try:
            waiting_for = coroutine.send(None)
        except StopIteration as stop:
            result.set_result(stop.value)
            return
        except Exception as error:
            _log.exception("%s: a coroutine raised", node.get_name())
            result.set_exception(error)
            return
        if isinstance(waiting_for, Future):
            waiting_for.add_done_callback(lambda _done: resume())
        else:
            executor.create_task(step)

    def resume() -> None:
        # A future completed after the executor was shut down (e.g. by another coroutine's finally
        # block as the garbage collector closes it): the coroutine is abandoned with its executor.
        # rclpy's Python executors have no public flag for it; the EventsExecutor has no such field.
        if not getattr(executor, "_is_shutdown", False):
            executor.create_task(step)

    executor.create_task(step)
    return result


def in_task(node: Node, coroutine_function: Callable[[], Coroutine[Any, Any, Any]]) -> Callable[[], None]:
    """A plain callback (for a timer) that spawns ``coroutine_function()`` each time it is called."""

    def callback() -> None:
        spawn(node, coroutine_function())

    return callback


class _Pending:
    """A service response still being computed (see :func:`create_async_service`)."""

    def __init__(self, future: Future) -> None:
        self.future = future


def create_async_service(node: Node, srv_type: Any, name: str,
                         handler: Callable[[Any, Any], Coroutine[Any, Any, Any]]) -> Any:
    """A service whose ``handler(request, response)`` is a coroutine; it answers when that returns.

    Works on every executor: the service callback spawns the coroutine and returns a placeholder;
    the service's ``send_response`` waits for the coroutine and then sends the real response to
    the same caller.
    """
    service = node.create_service(srv_type, name, lambda request, response: _Pending(
        spawn(node, handler(request, response))))
    send = service.send_response

    def send_when_done(response: Any, header: Any) -> None:
        if not isinstance(response, _Pending):
            send(response, header)
            return

        def answer(done: Future) -> None:
            reply = done.result() if done.exception() is None else srv_type.Response()
            send(reply, header)

        response.future.add_done_callback(answer)

    setattr(service, "send_response", send_when_done)  # noqa: B010 - an instance override of the method
    return service
