"""SMACC2-compatible introspection: smacc2_msgs on ``/<SmName>/smacc/*`` from the engine's observer.

Topics (names and message types are SMACC2's, so SMACC2 tools can read them):

* ``/<Sm>/smacc/state_machine_description`` (SmaccStateMachine): built once from ``sm.describe()``,
  republished every 0.5 s.
* ``/<Sm>/smacc/status`` (SmaccStatus): on every state change (``run_mode`` debug) and every 0.5 s.
* ``/<Sm>/smacc/transition_log`` (SmaccTransitionLogEntry): one per transition taken.
* ``/<Sm>/smacc/event_log`` (SmaccEvent): one per posted event (debug mode only).
* service ``/<Sm>/smacc/transition_log_history`` (SmaccGetTransitionHistory): the whole log.

QoS: SMACC2 uses KeepLast(1) for all of them. We keep depth 1 for description and status but make them
reliable + transient local, so a viewer that starts late gets the structure and the current state at
once. The two logs are reliable with depth 100 (transition log also transient local) so bursts of
transitions or events are not overwritten before a subscriber has read them; depth does not affect
QoS compatibility, so SMACC2 subscribers still match.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from builtin_interfaces.msg import Time
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from smacc2_msgs.msg import (
    SmaccEvent as SmaccEventMsg,
)
from smacc2_msgs.msg import (
    SmaccEventGenerator,
    SmaccOrthogonal,
    SmaccState,
    SmaccStateMachine,
    SmaccStateReactor,
    SmaccStatus,
    SmaccTransition,
    SmaccTransitionLogEntry,
)
from smacc2_msgs.srv import SmaccGetTransitionHistory

from smacc_py.core import SmaccEvent, SmaccObserver, SmaccStateMachineBase, TransitionRecord
from smacc_py.core.introspection import EventDescription, StateMachineDescription, TransitionDescription

if TYPE_CHECKING:
    from smacc_py.core import SmaccState as CoreState

LATCHED_QOS = QoSProfile(
    depth=1,
    history=HistoryPolicy.KEEP_LAST,
    reliability=ReliabilityPolicy.RELIABLE,
    durability=DurabilityPolicy.TRANSIENT_LOCAL,
)
TRANSITION_LOG_QOS = QoSProfile(
    depth=100,
    history=HistoryPolicy.KEEP_LAST,
    reliability=ReliabilityPolicy.RELIABLE,
    durability=DurabilityPolicy.TRANSIENT_LOCAL,
)
EVENT_LOG_QOS = QoSProfile(
    depth=100,
    history=HistoryPolicy.KEEP_LAST,
    reliability=ReliabilityPolicy.RELIABLE,
    durability=DurabilityPolicy.VOLATILE,
)
PERIOD_S = 0.5  # SMACC2 republishes description and status every 0.5 s


def stamp(seconds: float) -> Time:
    """Seconds → builtin_interfaces/Time."""
    sec = int(seconds // 1)
    return Time(sec=sec, nanosec=min(round((seconds - sec) * 1e9), 999_999_999))


def event_msg(desc: EventDescription) -> SmaccEventMsg:
    """EventDescription → smacc2_msgs/SmaccEvent."""
    return SmaccEventMsg(
        event_type=desc.event_type,
        event_object_tag=desc.event_object_tag,
        event_source=desc.event_source,
        label=desc.label,
    )


def transition_msg(desc: TransitionDescription) -> SmaccTransition:
    """TransitionDescription → smacc2_msgs/SmaccTransition."""
    return SmaccTransition(
        index=desc.index,
        transition_name=desc.transition_name,
        transition_type=desc.transition_type,
        destiny_state_name=desc.destiny_state_name,
        source_state_name=desc.source_state_name,
        history_node=desc.history_node,
        event=event_msg(desc.event),
    )


def description_msg(desc: StateMachineDescription) -> SmaccStateMachine:
    """The static description → smacc2_msgs/SmaccStateMachine."""
    states = []
    for s in desc.states:
        states.append(
            SmaccState(
                index=s.index,
                name=s.name,
                children_states=list(s.children_states),
                level=s.level,
                transitions=[transition_msg(t) for t in s.transitions],
                orthogonals=[
                    SmaccOrthogonal(
                        name=o.name,
                        client_behavior_names=list(o.client_behavior_names),
                        client_names=list(o.client_names),
                    )
                    for o in s.orthogonals
                ],
                state_reactors=[
                    SmaccStateReactor(
                        index=r.index,
                        type_name=r.type_name,
                        object_tag=r.object_tag,
                        event_sources=[event_msg(e) for e in r.event_sources],
                    )
                    for r in s.state_reactors
                ],
                event_generators=[
                    SmaccEventGenerator(index=g.index, type_name=g.type_name, object_tag=g.object_tag)
                    for g in s.event_generators
                ],
            )
        )
    return SmaccStateMachine(states=states)


class IntrospectionPublisher(SmaccObserver):
    """Observer that publishes the machine's structure, status and logs; callbacks only publish."""

    def __init__(
        self,
        node: Node,
        sm: SmaccStateMachineBase,
        *,
        release_mode: bool = False,
    ) -> None:
        self.node = node
        self.sm = sm
        self.release_mode = release_mode
        prefix = f"/{sm.name}/smacc"
        self._description = description_msg(sm.describe())
        self._transitions = self._index_transitions(sm.describe())
        self._event_descs: dict[type[SmaccEvent], SmaccEventMsg] = {}
        self._pub_description = node.create_publisher(
            SmaccStateMachine, f"{prefix}/state_machine_description", LATCHED_QOS
        )
        self._pub_status = node.create_publisher(SmaccStatus, f"{prefix}/status", LATCHED_QOS)
        self._pub_transition = node.create_publisher(
            SmaccTransitionLogEntry, f"{prefix}/transition_log", TRANSITION_LOG_QOS
        )
        self._pub_event = node.create_publisher(SmaccEventMsg, f"{prefix}/event_log", EVENT_LOG_QOS)
        self._service = node.create_service(
            SmaccGetTransitionHistory,
            f"{prefix}/transition_log_history",
            self._on_history,
        )
        self._timer = node.create_timer(PERIOD_S, self._on_timer)
        self._pub_description.publish(self._description)

    @staticmethod
    def _index_transitions(desc: StateMachineDescription) -> dict[str, list[TransitionDescription]]:
        by_source: dict[str, list[TransitionDescription]] = {}
        for state in desc.states:
            for tr in state.transitions:
                by_source.setdefault(tr.source_state_name, []).append(tr)
        return by_source

    # ------------------------------------------------------------------ messages
    def status_msg(self) -> SmaccStatus:
        """The current SmaccStatus (current states outermost first and the global data)."""
        names, values = self.sm.global_data.as_status()
        msg = SmaccStatus(
            current_states=self.sm.current_state_names(),
            global_variable_names=names,
            global_variable_values=values,
        )
        msg.header.stamp = self.node.get_clock().now().to_msg()
        return msg

    def _event(self, event_type: type[SmaccEvent]) -> SmaccEventMsg:
        msg = self._event_descs.get(event_type)
        if msg is None:
            msg = self._event_descs[event_type] = event_msg(EventDescription.of(event_type))
        return msg

    def log_entry(self, record: TransitionRecord) -> SmaccTransitionLogEntry:
        """TransitionRecord → SmaccTransitionLogEntry (static index of the declared transition)."""
        index = -1
        for tr in self._transitions.get(record.source.__name__, ()):
            if (
                tr.destiny_state_name == record.target.__name__
                and tr.transition_type == record.tag.__name__
                and tr.event.label in _labels(type(record.event))
            ):
                index = tr.index
                break
        target = record.target.__name__
        label = type(record.event).get_event_label()
        transition = SmaccTransition(
            index=index,
            transition_name=f"Transition<{label}, {target}, {record.tag.__name__}>",
            transition_type=record.tag.__name__,
            destiny_state_name=target,
            source_state_name=record.source.__name__,
            history_node=record.history,
            event=self._event(type(record.event)),
        )
        return SmaccTransitionLogEntry(timestamp=stamp(record.stamp_s), transition=transition)

    # ------------------------------------------------------------------ observer callbacks
    def on_event_posted(self, sm: SmaccStateMachineBase, event: SmaccEvent) -> None:
        if not self.release_mode:
            self._pub_event.publish(self._event(type(event)))

    def on_transition(self, sm: SmaccStateMachineBase, record: TransitionRecord) -> None:
        self._pub_transition.publish(self.log_entry(record))

    def on_state_entered(self, sm: SmaccStateMachineBase, state: CoreState) -> None:
        if not self.release_mode and type(state).inner_initial_state is None:
            self._pub_status.publish(self.status_msg())

    # ------------------------------------------------------------------ ROS callbacks
    def _on_timer(self) -> None:
        self._pub_description.publish(self._description)
        self._pub_status.publish(self.status_msg())

    def _on_history(self, request: Any, response: Any) -> Any:
        response.history = [self.log_entry(r) for r in list(self.sm.transition_log)]
        return response

    def destroy(self) -> None:
        """Remove the timer, the service and the publishers."""
        node = self.node
        node.destroy_timer(self._timer)
        node.destroy_service(self._service)
        for pub in (self._pub_description, self._pub_status, self._pub_transition, self._pub_event):
            node.destroy_publisher(pub)


def _labels(event_type: type) -> set[str]:
    """Labels of the event class and every event class it derives from (template matches)."""
    return {
        c.get_event_label() for c in event_type.__mro__ if isinstance(c, type) and issubclass(c, SmaccEvent)
    }
