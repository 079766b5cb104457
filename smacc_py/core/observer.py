"""Observer interface and transition records: what the ROS runtime needs for introspection.

The engine calls observers synchronously: ``on_event_posted`` on the posting thread (an async
behavior's thread, say), everything else on the machine thread (the ROS runtime's executor), in
order. Observers must be quick (queue the work and publish elsewhere) and must not post events from
``on_transition`` or the exit/entry callbacks. Exceptions they raise are logged and ignored.
``TransitionRecord`` carries the fields of ``smacc2_msgs/SmaccTransitionLogEntry``; treat it as
read-only (it is not frozen only because a frozen dataclass is slow to build, and one is built per
transition on the hot path).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from smacc_py.core.events import SmaccEvent
from smacc_py.core.tags import TransitionTag

if TYPE_CHECKING:
    from smacc_py.core.state import SmaccState
    from smacc_py.core.state_machine import SmaccStateMachineBase


@dataclass(slots=True)
class TransitionRecord:
    """One taken transition (``SmaccTransitionLogEntry``); ``stamp_s`` is the machine clock (s).

    ``target`` is the declared destination (the superstate for ``History``), as in ``SmaccTransition``;
    ``leaf`` is the innermost state the transition ended in (after inner initial states or history).
    """

    index: int
    source: type[SmaccState]
    target: type[SmaccState]
    leaf: type[SmaccState]
    tag: type[TransitionTag]
    event: SmaccEvent
    history: bool
    stamp_s: float

    def key(self) -> tuple[str, str, str]:
        """(source name, target name, tag name): handy for asserting transition sequences."""
        return (self.source.__name__, self.target.__name__, self.tag.__name__)


class SmaccObserver:
    """Base with no-op callbacks; override the ones you need and ``sm.add_observer(obs)``."""

    def on_event_posted(self, sm: SmaccStateMachineBase, event: SmaccEvent) -> None:
        """An event was queued (after the state reactors saw it)."""

    def on_event_dropped(self, sm: SmaccStateMachineBase, event: SmaccEvent) -> None:
        """A CURRENT_STATE event was dropped because the state that posted it has exited."""

    def on_event_unhandled(self, sm: SmaccStateMachineBase, event: SmaccEvent) -> None:
        """No active state had a matching transition whose guard accepted the event."""

    def on_transition(self, sm: SmaccStateMachineBase, record: TransitionRecord) -> None:
        """A transition was taken; called after ``on_exit_<TAG>`` and before any state exits."""

    def on_state_exited(self, sm: SmaccStateMachineBase, state: SmaccState) -> None:
        """A state finished exiting (after its ``on_exit``)."""

    def on_state_entered(self, sm: SmaccStateMachineBase, state: SmaccState) -> None:
        """A state finished entering (after its behaviors', reactors' and generators' ``on_entry``)."""
