"""Transition tags: the ``SUCCESS``/``ABORT``/... labels SMACC2 attaches to every transition.

Tags are classes that are never instantiated, exactly like SMACC2's empty tag structs, so users derive
their own by subclassing (``class NAV2_READY(SUCCESS): ...``) and introspection can report both the tag
and the family it belongs to. Tag-specific exit hooks are looked up by the *exact* tag name
(``on_exit_SUCCESS`` runs for ``SUCCESS`` but not for ``RETRY(SUCCESS)``), which is what SMACC2's
``onExit(TAG)`` detection does: it matches the exact member-function signature, not a base tag.
"""

from __future__ import annotations


class TransitionTag:
    """Base of every tag. Do not use directly in a transition; use one of the subclasses.

    SMACC2's tags are empty structs in ``smacc2::default_transition_tags`` with no common base.
    """

    def __init__(self) -> None:
        raise TypeError(f"{type(self).__name__} is a transition tag class; use the class, not an instance")

    @classmethod
    def tag_name(cls) -> str:
        """The name used in introspection (``SmaccTransition.transition_type``) and exit hooks."""
        return cls.__name__

    @classmethod
    def family(cls) -> str:
        """The name of the built-in tag this tag derives from (``RETRY(SUCCESS)`` → ``SUCCESS``)."""
        for base in cls.__mro__:
            if base in BUILTIN_TAGS:
                return base.__name__
        return cls.__name__


class DEFAULT(TransitionTag):
    """No particular meaning; used when an event has no natural outcome.

    SMACC2: ``smacc2::default_transition_tags::DEFAULT``.
    """


class SUCCESS(TransitionTag):
    """The state reached its goal. SMACC2: ``smacc2::default_transition_tags::SUCCESS``."""


class ABORT(TransitionTag):
    """The state gave up (an action was aborted, a behavior failed, retries ran out).

    SMACC2: ``smacc2::default_transition_tags::ABORT``.
    """


class CANCEL(TransitionTag):
    """The work of the state was cancelled. SMACC2: ``smacc2::default_transition_tags::CANCEL``."""


class CONTINUELOOP(TransitionTag):
    """Another iteration of a loop (``EvLoopContinue``).

    SMACC2: ``smacc2::default_transition_tags::CONTINUELOOP``.
    """


class ENDLOOP(TransitionTag):
    """The loop condition became false (``EvLoopEnd``).

    SMACC2: ``smacc2::default_transition_tags::ENDLOOP``.
    """


BUILTIN_TAGS: tuple[type[TransitionTag], ...] = (DEFAULT, SUCCESS, ABORT, CANCEL, CONTINUELOOP, ENDLOOP)


def is_tag(obj: object) -> bool:
    """True when ``obj`` is a tag class (``SUCCESS`` or a subclass of any tag)."""
    return isinstance(obj, type) and issubclass(obj, TransitionTag) and obj is not TransitionTag
