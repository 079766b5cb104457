"""Events: classes parameterised by their source and orthogonal, like SMACC2's ``EvCbSuccess<Cb, Or>``.

``EvCbSuccess[CbNavigate, OrNavigation]`` returns a subclass of ``EvCbSuccess`` that is created once and
cached, so the same parameters always give the same class object (``is``-identical, hashable). Transition
tables key on these classes; a transition on the unparameterised template (``EvCbSuccess``) matches every
parameterisation because matching is by subclass. Instances may carry a payload as attributes
(``EvTopicMessage[ClScan, OrPerception](msg=scan)``), which guards and reactors can read (SMACC2 #544).

Every template knows its SMACC2 default transition tag (``getDefaultTransitionTag``): used when a
``Transition`` gives no tag and by introspection.
"""

from __future__ import annotations

import threading
from typing import Any, ClassVar

from smacc_py.core.tags import ABORT, CANCEL, CONTINUELOOP, DEFAULT, ENDLOOP, SUCCESS, TransitionTag

_SPECIALIZE_LOCK = threading.Lock()


def _param_name(param: object) -> str:
    return param.__name__ if isinstance(param, type) else repr(param)


class EventMeta(type):
    """Metaclass that gives event classes the ``Ev[Source, Orthogonal]`` subscription syntax."""

    params: tuple[object, ...]
    param_names: tuple[str, ...]
    template: type[SmaccEvent]
    _specializations: dict[tuple[object, ...], type[SmaccEvent]]

    def __getitem__(cls, params: object) -> type[SmaccEvent]:
        key = params if isinstance(params, tuple) else (params,)
        try:
            hit = cls._specializations.get(key)  # every event class owns its cache (__init_subclass__)
        except TypeError as exc:
            raise TypeError(f"{cls.__name__}{list(key)}: event parameters must be hashable") from exc
        return hit if hit is not None else cls._specialize(key)

    def _specialize(cls, key: tuple[object, ...]) -> type[SmaccEvent]:
        if cls.params:
            raise TypeError(f"{cls.__name__} is already parameterised; subscribe the template instead")
        if len(key) != len(cls.param_names):
            raise TypeError(
                f"{cls.__name__} takes {len(cls.param_names)} parameters {cls.param_names}, got {len(key)}"
            )
        with _SPECIALIZE_LOCK:
            found = cls._specializations.get(key)
            if found is None:
                name = f"{cls.__name__}[{', '.join(_param_name(p) for p in key)}]"
                attrs: dict[str, Any] = {
                    "params": key,
                    "template": cls,
                    "__module__": cls.__module__,
                    "__qualname__": name,
                }
                attrs.update(zip(cls.param_names, key, strict=True))
                created = type(cls)(name, (cls,), attrs)
                assert issubclass(created, SmaccEvent)
                cls._specializations[key] = found = created
            return found

    def __repr__(cls) -> str:
        return cls.__qualname__


class SmaccEvent(metaclass=EventMeta):
    """Base of every event. Subclass it for user events; parameterise with ``Ev[Source, Orthogonal]``.

    SMACC2 events derive from ``boost::statechart::event<Ev>`` and are templates over their source and
    orthogonal; ``EvX[Source, Or]`` is the Python spelling of ``EvX<Source, Or>``.

    Keyword arguments given to the constructor become instance attributes (the payload). Payload names
    may not shadow the parameter names (``source``, ``orthogonal`` ...).
    """

    param_names: ClassVar[tuple[str, ...]] = ("source", "orthogonal")
    default_transition_tag: ClassVar[type[TransitionTag]] = DEFAULT
    params: ClassVar[tuple[object, ...]] = ()
    template: ClassVar[type[SmaccEvent]]

    def __init__(self, **payload: Any) -> None:
        for name in payload:
            if name in self.param_names:
                raise TypeError(f"{type(self).__name__}: payload field {name!r} shadows an event parameter")
        self.__dict__.update(payload)

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        cls._specializations = {}
        if "params" not in cls.__dict__:
            cls.template = cls

    def __repr__(self) -> str:
        payload = ", ".join(f"{k}={v!r}" for k, v in self.__dict__.items())
        return f"{type(self).__qualname__}({payload})"

    @classmethod
    def get_event_label(cls) -> str:
        """Full class name including parameters, e.g. ``EvCbSuccess[CbX, OrY]``."""
        return cls.__qualname__

    @classmethod
    def get_default_transition_tag(cls) -> type[TransitionTag]:
        """The tag a transition on this event gets when it declares none (SMACC2 semantics)."""
        return cls.default_transition_tag

    @classmethod
    def param(cls, index: int) -> object | None:
        """Parameter ``index`` of a parameterised event, or None (template, or fewer parameters)."""
        return cls.params[index] if index < len(cls.params) else None


SmaccEvent.template = SmaccEvent
SmaccEvent._specializations = {}


# --------------------------------------------------------------------------- client behavior events
class EvCbSuccess(SmaccEvent):
    """A client behavior reported success (``post_success_event``). SMACC2: ``smacc2::EvCbSuccess``."""

    default_transition_tag = SUCCESS


class EvCbFailure(SmaccEvent):
    """A client behavior reported failure (``post_failure_event``) or its ``on_entry`` raised.

    SMACC2: ``smacc2::EvCbFailure``.
    """

    default_transition_tag = ABORT


class EvCbFinished(SmaccEvent):
    """An asynchronous client behavior's ``on_entry`` returned (posted automatically).

    SMACC2: ``smacc2::EvCbFinished``.
    """

    default_transition_tag = SUCCESS


# --------------------------------------------------------------------------- action client events
class EvActionSucceeded(SmaccEvent):
    """An action goal succeeded; parameters are (client, orthogonal).

    SMACC2: ``smacc2::default_events::EvActionSucceeded``.
    """

    default_transition_tag = SUCCESS


class EvActionAborted(SmaccEvent):
    """An action goal was aborted by the server. SMACC2: ``smacc2::default_events::EvActionAborted``."""

    default_transition_tag = ABORT


class EvActionCancelled(SmaccEvent):
    """An action goal was cancelled. SMACC2: ``smacc2::default_events::EvActionCancelled``."""

    default_transition_tag = CANCEL


class EvActionFeedback(SmaccEvent):
    """Action feedback arrived (payload ``feedback``).

    SMACC2: ``smacc2::default_events::EvActionFeedback``.
    """


class EvActionResult(SmaccEvent):
    """An action result arrived, whatever its status (payload ``result``).

    SMACC2: ``smacc2::default_events::EvActionResult``.
    """


# --------------------------------------------------------------------------- service events
class EvServiceResponse(SmaccEvent):
    """A service call returned (payload ``response``).

    SMACC2: ``smacc2::default_events::EvServiceResponse``.
    """

    default_transition_tag = SUCCESS


class EvServiceFailure(SmaccEvent):
    """A service call failed or timed out. SMACC2: ``smacc2::default_events::EvServiceFailure``."""

    default_transition_tag = ABORT


# --------------------------------------------------------------------------- topics, timers, keys
class EvTopicMessage(SmaccEvent):
    """A message arrived on a subscribed topic (payload ``msg``).

    SMACC2: ``smacc2::default_events::EvTopicMessage``.
    """


class EvTopicInitialMessage(SmaccEvent):
    """The first message arrived on a subscribed topic (payload ``msg``).

    SMACC2: ``smacc2::default_events::EvTopicInitialMessage``.
    """


class EvTimer(SmaccEvent):
    """A timer (ClRos2Timer countdown or tick) fired. SMACC2: ``cl_ros2_timer::EvTimer``."""


class EvKeyPress(SmaccEvent):
    """Base of ``EvKeyPressA`` .. ``EvKeyPressZ``; a transition on it matches any key.

    SMACC2: ``cl_keyboard::EvKeyPressA..Z``.
    """

    key: ClassVar[str] = ""


# --------------------------------------------------------------------------- control flow (param: state)
class _StateEvent(SmaccEvent):
    param_names = ("state",)


class EvStateRequestFinish(_StateEvent):
    """A state asks to be left (``request_finish``).

    SMACC2: ``smacc2::default_events::EvStateRequestFinish``.
    """

    default_transition_tag = SUCCESS


class EvSequenceFinished(_StateEvent):
    """A sequence inside a state finished (a state posts ``EvSequenceFinished[ThisState]``).

    SMACC2: ``smacc2::default_events::EvSequenceFinished``.
    """

    default_transition_tag = SUCCESS


class EvLoopContinue(_StateEvent):
    """The loop condition held: run another iteration. SMACC2: ``smacc2::default_events::EvLoopContinue``."""

    default_transition_tag = CONTINUELOOP


class EvLoopEnd(_StateEvent):
    """The loop condition failed: leave the loop. SMACC2: ``smacc2::default_events::EvLoopEnd``."""

    default_transition_tag = ENDLOOP


# --------------------------------------------------------------------------- reactors and generators
class EvAllGo(SmaccEvent):
    """SrAllEventsGo saw every input event; parameters are (reactor, object tag).

    SMACC2: ``smacc2::state_reactors::EvAllGo``.
    """

    param_names = ("source", "object_tag")
    default_transition_tag = SUCCESS


class EvConditionalTrue(SmaccEvent):
    """SrConditional's predicate accepted an input event.

    SMACC2: ``smacc2::state_reactors::EvConditionalTrue``.
    """

    param_names = ("source", "object_tag")
    default_transition_tag = SUCCESS


class EvCountdownEnd(SmaccEvent):
    """SrEventCountdown counted its input events down to zero.

    SMACC2: ``smacc2::state_reactors::EvCountdownEnd``.
    """

    param_names = ("source", "object_tag")
    default_transition_tag = SUCCESS


class EvTrue(SmaccEvent):
    """EgConditionalGenerator's predicate is true; parameters are (generator, state).

    SMACC2: ``smacc2::event_generators::EvTrue``.
    """

    param_names = ("source", "state")
    default_transition_tag = SUCCESS


class EvFalse(SmaccEvent):
    """EgConditionalGenerator's predicate is false. SMACC2: ``smacc2::event_generators::EvFalse``."""

    param_names = ("source", "state")
    default_transition_tag = ABORT


# --------------------------------------------------------------------------- waypoints
class EvWaypoint(SmaccEvent):
    """Base of ``EvWaypoint0`` .. ``EvWaypoint44``: waypoint ``index`` was reached.

    SMACC2: ``cl_nav2z::EvWaypoint0..44``.
    """

    index: ClassVar[int] = -1


class EvWaypointFinal(SmaccEvent):
    """The last waypoint of the list was reached. SMACC2: ``cl_nav2z::EvWaypointFinal``."""

    default_transition_tag = SUCCESS


class EvGoalWaypointReached(SmaccEvent):
    """The named goal waypoint was reached (CbNavigateNextWaypointUntilReached).

    SMACC2: ``cl_nav2z::EvGoalWaypointReached``.
    """

    default_transition_tag = SUCCESS


MAX_WAYPOINT_EVENTS = 45  # cl_nav2z declares EvWaypoint0 .. EvWaypoint44

KEY_PRESS_EVENTS: dict[str, type[EvKeyPress]] = {
    letter: type(f"EvKeyPress{letter}", (EvKeyPress,), {"key": letter, "__module__": __name__})
    for letter in "ABCDEFGHIJKLMNOPQRSTUVWXYZ"
}
#: SMACC2's ``cl_keyboard::EvKeyPressA`` .. ``EvKeyPressZ`` by name (its keyboard client has letters only).
(
    EvKeyPressA, EvKeyPressB, EvKeyPressC, EvKeyPressD, EvKeyPressE, EvKeyPressF, EvKeyPressG,
    EvKeyPressH, EvKeyPressI, EvKeyPressJ, EvKeyPressK, EvKeyPressL, EvKeyPressM, EvKeyPressN,
    EvKeyPressO, EvKeyPressP, EvKeyPressQ, EvKeyPressR, EvKeyPressS, EvKeyPressT, EvKeyPressU,
    EvKeyPressV, EvKeyPressW, EvKeyPressX, EvKeyPressY, EvKeyPressZ,
) = (KEY_PRESS_EVENTS[letter] for letter in "ABCDEFGHIJKLMNOPQRSTUVWXYZ")
WAYPOINT_EVENTS: tuple[type[EvWaypoint], ...] = tuple(
    type(f"EvWaypoint{i}", (EvWaypoint,), {"index": i, "__module__": __name__})
    for i in range(MAX_WAYPOINT_EVENTS)
)


def key_press_event(key: str) -> type[EvKeyPress]:
    """The ``EvKeyPress<X>`` template for a letter (case-insensitive); ValueError for other keys."""
    try:
        return KEY_PRESS_EVENTS[key.upper()]
    except KeyError:
        raise ValueError(f"no key-press event for key {key!r}; only letters A..Z have one") from None


def waypoint_event(index: int) -> type[EvWaypoint]:
    """The ``EvWaypoint<index>`` template; ValueError outside 0..44."""
    if not 0 <= index < MAX_WAYPOINT_EVENTS:
        raise ValueError(f"waypoint event index {index} outside 0..{MAX_WAYPOINT_EVENTS - 1}")
    return WAYPOINT_EVENTS[index]


def __getattr__(name: str) -> type[SmaccEvent]:
    """Module attributes ``EvWaypoint0``..``EvWaypoint44``."""
    if name.startswith("EvWaypoint") and name[10:].isdigit() and int(name[10:]) < MAX_WAYPOINT_EVENTS:
        return WAYPOINT_EVENTS[int(name[10:])]
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
