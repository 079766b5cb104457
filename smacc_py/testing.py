"""Run your machine in a unit test: its own states, orthogonals and behaviors, with no ROS graph.

``MachineHarness`` builds the machine on a manual clock with stand-ins for the ROS ends of the generic
clients (``SmaccStateMachineBase(substitutes=...)``), so a pytest test drives it in milliseconds::

    from smacc_py.testing import MachineHarness

    def test_state_1_loops() -> None:
        with MachineHarness(SmMyMachine) as harness:
            assert harness.drive(lambda: len(harness.transitions()) >= 2, max_sim_s=30.0)
            assert harness.transitions()[:2] == [("StState1", "StState1", "SUCCESS")] * 2
            assert harness.published("heartbeat")

The stand-ins subclass what they replace and change only the I/O: ``CpTopicPublisher`` keeps what it
would publish (``published(topic)``), ``CpTopicSubscriber`` receives what the test ``deliver``s, the
node timers of ``ClRos2Timer`` and ``ClRosTimer`` run on the manual clock, and ``ClKeyboard`` takes
``press("n")``. Everything else, events and their parameters included, is the shipped code, so
transitions match as on the ROS graph. Pass ``substitutes=`` for your own clients' stand-ins (they
win over these).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from types import TracebackType
from typing import Any, Generic, TypeVar

from std_msgs.msg import UInt16

from smacc_py.clients.cl_keyboard import ClKeyboard
from smacc_py.clients.cl_ros2_timer import ClRos2Timer
from smacc_py.clients.cl_ros_timer import ClRosTimer
from smacc_py.core import ISmaccUpdatable, SmaccAsyncClientBehavior, SmaccStateMachineBase
from smacc_py.ros.components.cp_topic_publisher import CpTopicPublisher
from smacc_py.ros.components.cp_topic_subscriber import CpTopicSubscriber

M = TypeVar("M", bound=SmaccStateMachineBase)
STEP_S = 0.05  # s of machine clock per step: the ROS runtime's polling period (20 Hz)
THREAD_SLICE_WALL_S = 0.05  # wall s a step lets async behaviors' threads run while one is busy


class ManualClock:
    """The machine clock of a test (s); only the harness moves it."""

    def __init__(self) -> None:
        self.t = 0.0

    def __call__(self) -> float:
        return self.t


class _Recording:
    """Takes the place of an rclpy Publisher: keeps every message; someone always listens."""

    def __init__(self, messages: list[Any]) -> None:
        self.messages = messages

    def publish(self, msg: Any) -> None:
        self.messages.append(msg)

    def get_subscription_count(self) -> int:
        return 1


class _Silent:
    """Takes the place of an rclpy Subscription: no publisher is matched."""

    def get_publisher_count(self) -> int:
        return 0


class RecordingTopicPublisher(CpTopicPublisher):
    """CpTopicPublisher keeping its messages in ``messages`` instead of publishing them."""

    def on_initialize(self) -> None:
        self.messages: list[Any] = []
        self._publisher = _Recording(self.messages)


class ScriptedTopicSubscriber(CpTopicSubscriber):
    """CpTopicSubscriber without a subscription: it receives what ``MachineHarness.deliver`` gives."""

    def on_initialize(self) -> None:
        self._subscription = _Silent()


class _ManualTimer:
    """A node timer on the manual clock: due every ``period_s`` from its creation."""

    def __init__(self, period_s: float, callback: Callable[[], None], now_s: float) -> None:
        self.period_s, self.callback = period_s, callback
        self.next_s, self.cancelled = now_s + period_s, False

    def cancel(self) -> None:
        self.cancelled = True


class ManualClRos2Timer(ClRos2Timer, ISmaccUpdatable):
    """ClRos2Timer whose timers fire on the machine's polls, on the manual clock."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.timers: list[_ManualTimer] = []

    def create_timer(self, period_s: float, callback: Callable[[], None]) -> _ManualTimer:
        timer = _ManualTimer(period_s, callback, self.sm.now())
        self.timers.append(timer)
        return timer

    def destroy_timer(self, timer: Any) -> None:
        timer.cancel()
        self.timers.remove(timer)

    def update(self) -> None:
        now = self.sm.now()
        for timer in list(self.timers):
            if not timer.cancelled and now >= timer.next_s - 1e-9:
                timer.next_s += timer.period_s
                timer.callback()


class ManualClRosTimer(ManualClRos2Timer, ClRosTimer):
    """ClRosTimer whose timers fire on the machine's polls, on the manual clock."""


class ScriptedClKeyboard(ClKeyboard):
    """ClKeyboard without the subscription; ``MachineHarness.press`` plays a /keyboard_unicode key."""

    def on_initialize(self) -> None:
        pass


def ros_free_substitutes() -> dict[type, Callable[..., object]]:
    """The stand-ins ``MachineHarness`` uses, by the type each replaces."""
    return {CpTopicPublisher: RecordingTopicPublisher, CpTopicSubscriber: ScriptedTopicSubscriber,
            ClRos2Timer: ManualClRos2Timer, ClRosTimer: ManualClRosTimer, ClKeyboard: ScriptedClKeyboard}


class MachineHarness(Generic[M]):
    """``sm_type`` built on a manual clock and the ROS-free stand-ins; ``drive`` moves time.

    Args:
        sm_type: the machine class.
        substitutes: more stand-ins (your clients'), by replaced type; they win over the defaults.
        step_s: machine-clock seconds per step of ``drive`` and ``advance``.
        sm_kwargs: more keyword arguments for the machine's constructor.
    """

    def __init__(self, sm_type: type[M], *, substitutes: Mapping[type, Callable[..., object]] | None = None,
                 step_s: float = STEP_S, **sm_kwargs: Any) -> None:
        self.clock = ManualClock()
        self.step_s = step_s
        self.sm: M = sm_type(now=self.clock, substitutes={**ros_free_substitutes(), **(substitutes or {})},
                             **sm_kwargs)

    def __enter__(self) -> MachineHarness[M]:
        if not self.sm.is_running:
            self.start()
        return self

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 trace: TracebackType | None) -> None:
        self.close()

    def start(self) -> M:
        """Enter the initial state and dispatch what that posted."""
        self.sm.start()
        self.sm.process_events()
        return self.sm

    def step(self) -> None:
        """One poll: advance the clock by ``step_s``, run the updatables, dispatch the events."""
        self.clock.t = round(self.clock.t + self.step_s, 9)  # 100 steps of 0.05 s are 5.0 s, not 4.99..
        self.sm.update()
        busy = any(isinstance(b, SmaccAsyncClientBehavior) and not b.is_finished()
                   for state in self.sm.active_states() for _, b in state.behaviors)
        if busy:  # let the behavior's thread run a little and post
            self.sm.run_until(lambda: False, THREAD_SLICE_WALL_S)
        else:
            self.sm.process_events()

    def advance(self, seconds: float) -> None:
        """Step for ``seconds`` of machine clock."""
        end = self.clock.t + seconds
        while self.clock.t < end - 1e-9:
            self.step()

    def drive(self, until: Callable[[], bool], max_sim_s: float = 60.0) -> bool:
        """Step until ``until()``; False when ``max_sim_s`` of machine clock passed first."""
        end = self.clock.t + max_sim_s
        self.sm.process_events()
        while not until():
            if self.clock.t >= end:
                return False
            self.step()
        return True

    def transitions(self) -> list[tuple[str, str, str]]:
        """(source, target, tag) of every transition so far, oldest first."""
        return [record.key() for record in self.sm.transition_log]

    def published(self, topic: str) -> list[Any]:
        """Messages the machine published on ``topic`` (through CpTopicPublisher), oldest first."""
        return [msg for pub in self._components(RecordingTopicPublisher) if pub.topic == topic
                for msg in pub.messages]

    def deliver(self, topic: str, msg: Any) -> int:
        """Hand ``msg`` to every subscriber of ``topic`` and dispatch; returns how many got it."""
        subscribers = [sub for sub in self._components(ScriptedTopicSubscriber) if sub.topic == topic]
        for sub in subscribers:
            sub.on_message(msg)
        self.sm.process_events()
        return len(subscribers)

    def press(self, key: str) -> None:
        """Play a key press on every keyboard client and dispatch."""
        for orthogonal in self.sm.orthogonals:
            for client in orthogonal.clients:
                if isinstance(client, ScriptedClKeyboard):
                    client._on_key(UInt16(data=ord(key)))
        self.sm.process_events()

    def close(self) -> None:
        """Stop the machine (behaviors' on_exit run)."""
        if self.sm.is_running:
            self.sm.stop()

    def _components(self, kind: type[Any]) -> list[Any]:
        return [component for orthogonal in self.sm.orthogonals for client in orthogonal.clients
                for component in client.components if isinstance(component, kind)]
