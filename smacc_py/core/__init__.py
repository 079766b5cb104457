"""The smacc_py core engine: SMACC2's state-machine model in pure Python (stdlib only, no ROS).

Import the public API from here::

    from smacc_py.core import (SmaccStateMachineBase, SmaccState, Transition, SUCCESS, ABORT,
                               Orthogonal, ISmaccClient, SmaccClientBehavior, EvCbSuccess)

The modules form a stack, listed bottom-up; each imports only from the layers below it (an
import-linter ``layers`` contract in pyproject.toml checks this, TYPE_CHECKING imports included).

1. Foundations: ``errors`` (exception types), ``tags`` (``SUCCESS``, ``ABORT`` ...), ``params``
   (``SmaccEngineParams``), ``updatable`` (``ISmaccUpdatable``), ``declared_names`` (the registry of
   ``parent=`` declarations and where each class lives, for resolving names).
2. ``events`` (parameterised event classes) and ``global_data`` (the machine's blackboard).
3. ``transition``: ``Transition`` and ``History`` declarations.
4. ``ports``: the protocols through which parts reach their machine and state (``MachinePort``,
   ``StatePort``), so that nothing below the machine imports it.
5. Parts a state declares: ``client`` (clients, components), then ``client_behavior`` (sync/async
   behaviors), ``reactors`` and ``event_generators``, then ``orthogonal`` (holds clients and behaviors).
6. ``state``: ``SmaccState`` declarations.
7. ``model``: compiles and validates a machine class.
8. ``introspection``: the smacc2_msgs-shaped description of a compiled model.
9. Engine pieces: ``assembly`` (building orthogonals, clients, components; substitutes), ``lifecycle``
   (entry/exit order), ``observer`` (callbacks, transition records), ``state_machine_queries``
   (read-only lookups).
10. ``state_machine``: ``SmaccStateMachineBase``, the queue and run-to-completion dispatch.
11. ``graph_export``: Mermaid/DOT text of a machine.
"""

from smacc_py.core.client import ISmaccClient, ISmaccComponent
from smacc_py.core.client_behavior import ISmaccClientBehavior, SmaccAsyncClientBehavior, SmaccClientBehavior
from smacc_py.core.errors import InvalidDefinitionError, SmaccError, SmaccLookupError
from smacc_py.core.event_generators import (
    ConditionalGeneratorMode,
    EgConditionalGenerator,
    SmaccEventGenerator,
)
from smacc_py.core.events import (
    EvActionAborted,
    EvActionCancelled,
    EvActionFeedback,
    EvActionResult,
    EvActionSucceeded,
    EvAllGo,
    EvCbFailure,
    EvCbFinished,
    EvCbSuccess,
    EvConditionalTrue,
    EvCountdownEnd,
    EvFalse,
    EvGoalWaypointReached,
    EvKeyPress,
    EvKeyPressA,
    EvKeyPressB,
    EvKeyPressC,
    EvKeyPressD,
    EvKeyPressE,
    EvKeyPressF,
    EvKeyPressG,
    EvKeyPressH,
    EvKeyPressI,
    EvKeyPressJ,
    EvKeyPressK,
    EvKeyPressL,
    EvKeyPressM,
    EvKeyPressN,
    EvKeyPressO,
    EvKeyPressP,
    EvKeyPressQ,
    EvKeyPressR,
    EvKeyPressS,
    EvKeyPressT,
    EvKeyPressU,
    EvKeyPressV,
    EvKeyPressW,
    EvKeyPressX,
    EvKeyPressY,
    EvKeyPressZ,
    EvLoopContinue,
    EvLoopEnd,
    EvSequenceFinished,
    EvServiceFailure,
    EvServiceResponse,
    EvStateRequestFinish,
    EvTimer,
    EvTopicInitialMessage,
    EvTopicMessage,
    EvTrue,
    EvWaypoint,
    EvWaypointFinal,
    SmaccEvent,
    key_press_event,
    waypoint_event,
)
from smacc_py.core.graph_export import to_dot, to_mermaid
from smacc_py.core.introspection import StateMachineDescription, describe_state_machine
from smacc_py.core.observer import SmaccObserver, TransitionRecord
from smacc_py.core.orthogonal import Orthogonal
from smacc_py.core.params import SmaccEngineParams
from smacc_py.core.reactors import SrAllEventsGo, SrConditional, SrEventCountdown, StateReactor
from smacc_py.core.state import SmaccState
from smacc_py.core.state_machine import SmaccStateMachineBase
from smacc_py.core.tags import ABORT, CANCEL, CONTINUELOOP, DEFAULT, ENDLOOP, SUCCESS, TransitionTag
from smacc_py.core.transition import History, Transition, deep_history
from smacc_py.core.updatable import ISmaccUpdatable

__all__ = [
    "ABORT", "CANCEL", "CONTINUELOOP", "DEFAULT", "ENDLOOP", "SUCCESS", "ConditionalGeneratorMode",
    "EgConditionalGenerator", "EvActionAborted", "EvActionCancelled", "EvActionFeedback", "EvActionResult",
    "EvActionSucceeded", "EvAllGo", "EvCbFailure", "EvCbFinished", "EvCbSuccess", "EvConditionalTrue",
    "EvCountdownEnd", "EvFalse", "EvGoalWaypointReached", "EvKeyPress", "EvKeyPressA", "EvKeyPressB",
    "EvKeyPressC", "EvKeyPressD", "EvKeyPressE", "EvKeyPressF", "EvKeyPressG", "EvKeyPressH", "EvKeyPressI",
    "EvKeyPressJ", "EvKeyPressK", "EvKeyPressL", "EvKeyPressM", "EvKeyPressN", "EvKeyPressO", "EvKeyPressP",
    "EvKeyPressQ", "EvKeyPressR", "EvKeyPressS", "EvKeyPressT", "EvKeyPressU", "EvKeyPressV", "EvKeyPressW",
    "EvKeyPressX", "EvKeyPressY", "EvKeyPressZ", "EvLoopContinue", "EvLoopEnd", "EvSequenceFinished",
    "EvServiceFailure", "EvServiceResponse", "EvStateRequestFinish", "EvTimer", "EvTopicInitialMessage",
    "EvTopicMessage", "EvTrue", "EvWaypoint", "EvWaypointFinal", "History", "ISmaccClient",
    "ISmaccClientBehavior", "ISmaccComponent", "ISmaccUpdatable", "InvalidDefinitionError", "Orthogonal",
    "SmaccAsyncClientBehavior", "SmaccClientBehavior", "SmaccEngineParams", "SmaccError", "SmaccEvent",
    "SmaccEventGenerator", "SmaccLookupError", "SmaccObserver", "SmaccState", "SmaccStateMachineBase",
    "SrAllEventsGo", "SrConditional", "SrEventCountdown", "StateMachineDescription", "StateReactor",
    "Transition", "TransitionRecord", "TransitionTag", "deep_history", "describe_state_machine",
    "key_press_event", "to_dot", "to_mermaid", "waypoint_event",
]
