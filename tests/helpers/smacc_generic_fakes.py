"""Fakes for unit tests of the generic clients (smacc_py.ros.client_bases / components / behaviors).

No rclpy context or node is created. ``FakeNode`` stands in for the machine's rclpy node (the one
``ros_context(sm).node`` returns): it records publishers, subscriptions, service clients and servers,
and lets the test deliver messages, answer requests and change the graph. Action clients are the
exception: ``CpActionClient`` builds an rclpy ActionClient, so the machine is given
``FakeCpActionClient`` (``substitutes=ACTION_SUBSTITUTES``), which overrides only that endpoint with
a ``FakeActionClient`` whose goals end when the test says so.

``GenericRig`` runs a machine as the ROS runtime would, on a manual clock: ``poll()`` is one round
of the runtime's ISmaccUpdatable polling followed by the dispatch of the events it caused.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, TypeVar

from smacc_py.core import SmaccStateMachineBase
from smacc_py.ros.action_client import GoalOutcome, GoalTicket
from smacc_py.ros.components import CpActionClient
from smacc_py.ros.context import RosContext, attach_ros_context
from tests.helpers.smacc_fake_nav import ManualClock

M = TypeVar("M", bound=SmaccStateMachineBase)


class FakeFuture:
    """The parts of rclpy's Future that ServiceCall uses."""

    def __init__(self) -> None:
        self._done, self._result, self._error = False, None, None
        self._callbacks: list[Callable[[FakeFuture], None]] = []

    def done(self) -> bool:
        return self._done

    def result(self) -> Any:
        if self._error is not None:
            raise self._error
        return self._result

    def add_done_callback(self, callback: Callable[[FakeFuture], None]) -> None:
        if self._done:
            callback(self)
        else:
            self._callbacks.append(callback)

    def set_result(self, value: Any) -> None:
        self._done, self._result = True, value
        for callback in self._callbacks:
            callback(self)

    def set_exception(self, error: Exception) -> None:
        self._done, self._error = True, error
        for callback in self._callbacks:
            callback(self)


@dataclass
class FakeSubscription:
    msg_type: Any
    topic: str
    callback: Callable[[Any], None]
    qos: Any
    destroyed: bool = False

    def get_publisher_count(self) -> int:
        return 1


@dataclass
class FakePublisher:
    msg_type: Any
    topic: str
    qos: Any
    messages: list[Any] = field(default_factory=list)

    def publish(self, msg: Any) -> None:
        self.messages.append(msg)

    def get_subscription_count(self) -> int:
        return 1


@dataclass
class FakeServiceClient:
    """A service client whose server is up when ``ready``; ``pending`` holds (request, future)."""

    srv_type: Any
    srv_name: str
    ready: bool = True
    pending: list[tuple[Any, FakeFuture]] = field(default_factory=list)
    withdrawn: list[FakeFuture] = field(default_factory=list)
    destroyed: bool = False

    def service_is_ready(self) -> bool:
        return self.ready

    def call_async(self, request: Any) -> FakeFuture:
        future = FakeFuture()
        self.pending.append((request, future))
        return future

    def remove_pending_request(self, future: FakeFuture) -> None:
        self.withdrawn.append(future)

    def answer(self, fill: Callable[[Any, Any], None] | None = None) -> Any:
        """Answer the oldest pending request; ``fill(request, response)`` sets the response's fields."""
        request, future = self.pending.pop(0)
        response = self.srv_type.Response()
        if fill is not None:
            fill(request, response)
        future.set_result(response)
        return response


@dataclass
class FakeService:
    srv_type: Any
    srv_name: str
    callback: Callable[[Any, Any], Any]

    def call(self, request: Any) -> Any:
        """What a remote caller would get back."""
        return self.callback(request, self.srv_type.Response())


class FakeNode:
    """Stands in for the machine's rclpy node; ``graph`` holds (name, namespace) of visible nodes."""

    def __init__(self) -> None:
        self.subscriptions: list[FakeSubscription] = []
        self.publishers: list[FakePublisher] = []
        self.clients: list[FakeServiceClient] = []
        self.services: list[FakeService] = []
        self.graph: list[tuple[str, str]] = []
        self.service_ready = True

    # rclpy's API
    def create_subscription(self, msg_type: Any, topic: str, callback: Callable[[Any], None],
                            qos: Any) -> FakeSubscription:
        sub = FakeSubscription(msg_type, topic, callback, qos)
        self.subscriptions.append(sub)
        return sub

    def destroy_subscription(self, sub: FakeSubscription) -> None:
        sub.destroyed = True
        self.subscriptions.remove(sub)

    def create_publisher(self, msg_type: Any, topic: str, qos: Any) -> FakePublisher:
        pub = FakePublisher(msg_type, topic, qos)
        self.publishers.append(pub)
        return pub

    def create_client(self, srv_type: Any, srv_name: str) -> FakeServiceClient:
        client = FakeServiceClient(srv_type, srv_name, ready=self.service_ready)
        self.clients.append(client)
        return client

    def destroy_client(self, client: FakeServiceClient) -> None:
        client.destroyed = True

    def create_service(self, srv_type: Any, srv_name: str,
                       callback: Callable[[Any, Any], Any]) -> FakeService:
        service = FakeService(srv_type, srv_name, callback)
        self.services.append(service)
        return service

    def get_node_names_and_namespaces(self) -> list[tuple[str, str]]:
        return list(self.graph)

    # test helpers
    def deliver(self, topic: str, msg: Any) -> int:
        """Give ``msg`` to every live subscription of ``topic``; the number of subscriptions reached."""
        subs = [s for s in self.subscriptions if s.topic == topic and not s.destroyed]
        for sub in subs:
            sub.callback(msg)
        return len(subs)

    def publisher(self, topic: str) -> FakePublisher:
        return next(p for p in self.publishers if p.topic == topic)

    def client(self, srv_name: str) -> FakeServiceClient:
        """The latest service client of ``srv_name``."""
        return [c for c in self.clients if c.srv_name == srv_name][-1]

    def service(self, srv_name: str) -> FakeService:
        return next(s for s in self.services if s.srv_name == srv_name)


class FakeActionClient:
    """Stands in for RosActionClient: goals stay pending until ``finish``; ``ready`` is the server."""

    def __init__(self, action_type: Any, action_name: str) -> None:
        self.action_type, self.action_name = action_type, action_name
        self.ready = True
        self.goals: list[tuple[GoalTicket, Any, Any]] = []  # ticket, on_done, on_feedback

    def server_ready(self) -> bool:
        return self.ready

    def send_goal(self, goal: Any, on_done: Any = None, on_feedback: Any = None) -> GoalTicket:
        ticket = GoalTicket(self.action_name, goal)
        self.goals.append((ticket, on_done, on_feedback))
        return ticket

    def active_tickets(self) -> list[GoalTicket]:
        return [t for t, _, _ in self.goals if not t.done]

    def cancel_all(self) -> None:
        for ticket in self.active_tickets():
            ticket.cancel()

    def _entry(self, ticket: GoalTicket | None) -> tuple[GoalTicket, Any, Any]:
        if ticket is None:
            return self.goals[-1]
        return next(entry for entry in self.goals if entry[0] is ticket)

    def feedback(self, feedback: Any, ticket: GoalTicket | None = None) -> None:
        """The server sends feedback for ``ticket`` (default: the latest goal)."""
        found, _, on_feedback = self._entry(ticket)
        if on_feedback is not None:
            on_feedback(found, feedback)

    def finish(self, outcome: GoalOutcome, result: Any = None,
               ticket: GoalTicket | None = None) -> GoalTicket:
        """End ``ticket`` (default: the latest goal) with ``outcome``."""
        found, on_done, _ = self._entry(ticket)
        found.finish(outcome, result)
        if on_done is not None:
            on_done(found)
        return found


class FakeCpActionClient(CpActionClient):
    """CpActionClient whose rclpy endpoint is a FakeActionClient (everything else is the real code)."""

    def create_ros_client(self) -> Any:
        return FakeActionClient(self.action_type, self.action_name)


ACTION_SUBSTITUTES: dict[type, Any] = {CpActionClient: FakeCpActionClient}


class GenericRig:
    """A machine on a FakeNode and a manual clock, stepped by the test."""

    def __init__(self, sm_type: type[M], **sm_kwargs: Any) -> None:
        self.clock = ManualClock()
        self.node = FakeNode()
        self.sm: Any = sm_type(now=self.clock, substitutes=ACTION_SUBSTITUTES, **sm_kwargs)
        attach_ros_context(self.sm, RosContext(self.node))  # type: ignore[arg-type]

    def start(self) -> GenericRig:
        self.sm.start()
        self.sm.process_events()
        return self

    def poll(self, advance_s: float = 0.0) -> None:
        """Advance the clock, run one round of updatable polling, dispatch what it posted."""
        self.clock.t += advance_s
        self.sm.update()
        self.sm.process_events()

    def dispatch(self) -> None:
        self.sm.process_events()

    def state(self) -> str:
        return str(self.sm.current_state_names()[-1])

    def action_client(self) -> FakeActionClient:
        return self.sm.requires_component(CpActionClient).ros_client  # type: ignore[no-any-return]
