"""ros_tools.runtime.requests against a real rclpy service whose responses are lost, as rmw_fastrtps
loses one while the server still matches the client: the request is sent again and answered. And
the coroutine runner they rely on (ros_tools.runtime.coroutines) at an executor's shutdown."""

from __future__ import annotations

import warnings
from collections.abc import Iterator
from typing import Any

import pytest
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from std_srvs.srv import Trigger

from navsuite_testing.ros import spin_until, spinning
from ros_tools.runtime.coroutines import spawn
from ros_tools.runtime.requests import call_service, call_until_answered, doubling
from tests.helpers.lossy_service import LoseResponses

pytestmark = pytest.mark.ros


class LossyTrigger:
    """A Trigger service that handles every request and loses the responses to the first ``lose``."""

    def __init__(self, node: Node, lose: int) -> None:
        self.requests = 0
        self.service = node.create_service(Trigger, "lossy_trigger", self._on_request)
        self.loss = LoseResponses(self.service, lose)

    def _on_request(self, _request: Any, response: Any) -> Any:
        self.requests += 1
        response.success, response.message = True, f"request {self.requests}"
        return response


@pytest.fixture
def rig(ros_context: Any) -> Iterator[tuple[Node, SingleThreadedExecutor]]:
    node = Node("requests_rig", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    try:
        yield node, executor
    finally:
        executor.shutdown()
        node.destroy_node()


def _ready_client(node: Node, executor: SingleThreadedExecutor) -> Any:
    client = node.create_client(Trigger, "lossy_trigger")
    spin_until(executor, client.service_is_ready, 10.0, "the lossy service")
    return client


def test_a_lost_response_is_answered_by_the_next_copy(rig: tuple[Node, SingleThreadedExecutor]) -> None:
    node, executor = rig
    server = LossyTrigger(node, lose=1)
    response = call_until_answered(_ready_client(node, executor), Trigger.Request(), 10.0, spinning(executor))
    assert (server.requests, response.message) == (2, "request 2")


def test_the_coroutine_twin_sends_again_without_blocking(rig: tuple[Node, SingleThreadedExecutor]) -> None:
    node, executor = rig
    server = LossyTrigger(node, lose=2)
    done = spawn(node, call_service(node, _ready_client(node, executor), Trigger.Request(), 10.0))
    spin_until(executor, done.done, 15.0, "call_service")
    assert (server.requests, done.result().message) == (3, "request 3")


def test_a_service_that_never_answers_times_out_with_its_name(rig: Any) -> None:
    node, executor = rig
    server = LossyTrigger(node, lose=100)
    client = _ready_client(node, executor)
    with pytest.raises(TimeoutError, match=r"lossy_trigger' did not answer within 3.5 s \(3 copies sent"):
        call_until_answered(client, Trigger.Request(), 3.5, spinning(executor))
    spin_until(executor, lambda: server.requests == 3, 5.0, "every copy to reach the server")
    assert not client._pending_requests  # the unanswered copies were withdrawn


def test_waits_double_and_add_up_to_the_timeout() -> None:
    assert doubling(1.0, 30.0) == [1.0, 2.0, 4.0, 8.0, 15.0]
    assert doubling(1.0, 0.4) == [0.4]
    assert sum(doubling(0.5, 7.25)) == pytest.approx(7.25)


def test_a_coroutine_whose_executor_shut_down_is_not_resumed(rig: Any) -> None:
    """A future completed after the shutdown (as a GC-closed coroutine's finally block completes one)
    neither resumes the coroutine nor raises from the done callback."""
    from rclpy.task import Future

    from ros_tools.runtime.coroutines import until

    node, executor = rig
    gate, resumed = Future(), []

    async def waiter() -> None:
        await until(gate)
        resumed.append(True)

    spawn(node, waiter())
    executor.spin_once(timeout_sec=0.1)  # the coroutine runs up to its await
    executor.shutdown()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        gate.set_result(True)
    assert not resumed
