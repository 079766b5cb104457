"""``Transition`` declarations and the deep-history pseudostate.

A transition is a plain, immutable declaration that lives in a state's ``reactions`` list. Its target
may be a state class, the *name* of a state class (a forward reference, resolved when the machine is
compiled, because Python cannot name a class before it exists), or ``History(SsX)`` / ``deep_history``
to resume the last active leaf inside superstate ``SsX``. Everything that can be checked without the
whole machine is checked here, at class-definition time.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from smacc_py.core.errors import InvalidDefinitionError
from smacc_py.core.events import SmaccEvent
from smacc_py.core.tags import TransitionTag, is_tag

Guard = Callable[[Any], bool]


class History:
    """Deep-history pseudostate of a superstate: ``Transition(EvResume, History(MsRunMode))``
    (SMACC2: ``sc::deep_history<MsRunMode::LastDeepState>``).

    Entering it resumes the leaf that was active when the superstate was last left, or enters the
    superstate normally (its inner initial state) when it has never been active.
    """

    __slots__ = ("state",)

    def __init__(self, state: type | str) -> None:
        if not isinstance(state, (type, str)):
            raise InvalidDefinitionError(f"History() needs a superstate class or its name, got {state!r}")
        self.state = state

    def __repr__(self) -> str:
        name = self.state if isinstance(self.state, str) else self.state.__name__
        return f"History({name})"


def deep_history(state: type | str) -> History:
    """SMACC2 spelling of ``History(state)`` (``deep_history<SsX::LastDeepState>``)."""
    return History(state)


Target = type | str | History


class Transition:
    """``Transition(EvX, StY, SUCCESS, guard=lambda ev: ev.value > 3)``: on EvX go to StY with tag SUCCESS.

    SMACC2: ``smacc2::Transition<EvX, StY, SUCCESS>``.

    Args:
        event: the event class (a template matches all of its parameterisations).
        target: a state class, its name (forward reference) or ``History(superstate)``.
        tag: a tag class; omitted means the event's default tag (``getDefaultTransitionTag``).
        guard: optional predicate of the event instance; a transition whose guard is false is skipped
            and dispatch continues with the next candidate (first match in declaration order wins).
    """

    __slots__ = ("event", "guard", "tag", "target")

    def __init__(self, event: type[SmaccEvent], target: Target, tag: type[TransitionTag] | None = None,
                 *, guard: Guard | None = None) -> None:
        if not (isinstance(event, type) and issubclass(event, SmaccEvent)):
            raise InvalidDefinitionError(f"Transition event must be a SmaccEvent class, got {event!r}")
        if not isinstance(target, (type, str, History)):
            raise InvalidDefinitionError(
                f"Transition({event.__qualname__}, ...) target must be a state class, a state name or "
                f"History(...), got {target!r}"
            )
        if tag is not None and not is_tag(tag):
            raise InvalidDefinitionError(
                f"Transition({event.__qualname__}, ...) tag must be a TransitionTag class such as SUCCESS, "
                f"got {tag!r}"
            )
        if guard is not None and not callable(guard):
            raise InvalidDefinitionError(f"Transition({event.__qualname__}, ...) guard is not callable: "
                                         f"{guard!r}")
        self.event = event
        self.target: Target = target
        self.tag: type[TransitionTag] = tag if tag is not None else event.get_default_transition_tag()
        self.guard = guard

    @property
    def is_history(self) -> bool:
        """True when the target is a history pseudostate."""
        return isinstance(self.target, History)

    def target_name(self) -> str:
        """Name of the target for messages and introspection."""
        target = self.target
        if isinstance(target, History):
            return repr(target)
        return target if isinstance(target, str) else target.__name__

    def __repr__(self) -> str:
        guard = ", guard" if self.guard is not None else ""
        return f"Transition({self.event.__qualname__}, {self.target_name()}, {self.tag.__name__}{guard})"
