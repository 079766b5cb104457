"""docs/smacc2-guide.md's "Writing your own client": an action client and a topic client, each with a sync and
an async behavior, and a small machine that uses all four (tests run it against a fake peer).

The part between the ``README:begin`` and ``README:end`` lines is copied verbatim into docs/smacc2-guide.md;
tests/unit/smacc_py/test_readme_client_guide.py fails when the two differ.
"""

from __future__ import annotations

# README:begin
from builtin_interfaces.msg import Duration
from nav2_msgs.action import Wait
from sensor_msgs.msg import Temperature

from smacc_py.clients import GoalOutcome, GoalTicket, SmaccActionClientBase, SmaccSubscriberClient
from smacc_py.core import SmaccAsyncClientBehavior, SmaccClientBehavior


class ClWait(SmaccActionClientBase):
    """Action client of Nav2's `wait` behavior; posts EvActionSucceeded[ClWait, Or] and friends."""

    def __init__(self, action_name: str = "wait") -> None:
        super().__init__(Wait, action_name)


class CbWaitFor(SmaccClientBehavior):
    """Sync: sends the goal on entry and returns; the result posts success or failure."""

    def __init__(self, seconds: int) -> None:
        self.seconds = seconds
        self.ticket: GoalTicket | None = None

    def on_entry(self) -> None:
        goal = Wait.Goal(time=Duration(sec=self.seconds))
        self.ticket = self.requires_client(ClWait).send_goal(goal, on_done=self.on_done)

    def on_done(self, ticket: GoalTicket) -> None:  # executor thread, once the goal ended
        if ticket.abandoned:
            return
        if ticket.outcome is GoalOutcome.SUCCEEDED:
            self.post_success_event()
        else:
            self.post_failure_event(reason=ticket.describe())

    def on_exit(self) -> None:  # the state exits first: cancel the goal, and hear no more of it
        if self.ticket is not None and not self.ticket.done:
            self.ticket.abandon()


class CbWaitForServerAsync(SmaccAsyncClientBehavior):
    """Async: on_entry runs in its own thread, so it may wait, as long as it watches for the exit."""

    def on_entry(self) -> None:
        client = self.requires_client(ClWait)
        while not client.server_ready():
            if self.wait_for_shutdown(0.05):  # the state is exiting: stop waiting
                return
        self.post_success_event()


class ClThermometer(SmaccSubscriberClient):
    """Topic client; posts EvTopicMessage[ClThermometer, Or], and after 2 s of silence
    EvTopicMessageTimeout[ClThermometer, Or]."""

    def __init__(self, topic: str = "/temperature") -> None:
        super().__init__(Temperature, topic, timeout_s=2.0)


class CbWaitHot(SmaccClientBehavior):
    """Sync: listens while its state is active; success on the first reading above a threshold."""

    def __init__(self, celsius: float) -> None:
        self.celsius = celsius

    def on_entry(self) -> None:
        self.disconnect = self.requires_client(ClThermometer).on_message_received(self.on_reading)

    def on_reading(self, msg: Temperature) -> None:  # executor thread, for every message
        if msg.temperature > self.celsius:
            self.disconnect()
            self.post_success_event(celsius=msg.temperature)

    def on_exit(self) -> None:
        self.disconnect()


class CbFirstReadingAsync(SmaccAsyncClientBehavior):
    """Async: waits in its own thread until the client has heard a message, then reports it."""

    def on_entry(self) -> None:
        client = self.requires_client(ClThermometer)
        while client.last_message is None:
            if self.wait_for_shutdown(0.05):
                return
        self.post_success_event(celsius=client.last_message.temperature)
# README:end


# ----------------------------------------------------------------------------- a machine using them
from smacc_py.core import (  # noqa: E402  (after the README part, which must read top to bottom)
    EvActionSucceeded,
    EvCbFailure,
    EvCbSuccess,
    Orthogonal,
    SmaccState,
    SmaccStateMachineBase,
    Transition,
)


class OrWaiting(Orthogonal):
    """Holds ClWait."""

    def on_initialize(self) -> None:
        self.create_client(ClWait)


class OrThermo(Orthogonal):
    """Holds ClThermometer."""

    def on_initialize(self) -> None:
        self.create_client(ClThermometer)


class SmClientGuide(SmaccStateMachineBase):
    """Wait for the server, wait 1 s through it, read a first temperature, wait for a hot one."""

    initial_state = "StWaitServer"

    def on_initialize(self) -> None:
        self.create_orthogonal(OrWaiting)
        self.create_orthogonal(OrThermo)


class StWaitServer(SmaccState, parent=SmClientGuide):
    """The action server is discovered."""

    reactions = (Transition(EvCbSuccess[CbWaitForServerAsync, OrWaiting], "StWaitAction"),)

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrWaiting, CbWaitForServerAsync)


class StWaitAction(SmaccState, parent=SmClientGuide):
    """One `wait` goal; the client's own event moves on."""

    reactions = (Transition(EvActionSucceeded[ClWait, OrWaiting], "StFirstReading"),
                 Transition(EvCbFailure[CbWaitFor, OrWaiting], "StFailed"))

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrWaiting, CbWaitFor, 1)


class StFirstReading(SmaccState, parent=SmClientGuide):
    """A first temperature is known."""

    reactions = (Transition(EvCbSuccess[CbFirstReadingAsync, OrThermo], "StWaitHot"),)

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrThermo, CbFirstReadingAsync)


class StWaitHot(SmaccState, parent=SmClientGuide):
    """Above 30 °C."""

    reactions = (Transition(EvCbSuccess[CbWaitHot, OrThermo], "StDone"),)

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrThermo, CbWaitHot, 30.0)


class StDone(SmaccState, parent=SmClientGuide):
    """The guide ran through."""


class StFailed(SmaccState, parent=SmClientGuide):
    """The wait goal failed."""
