"""Exception types of the smacc_py core.

Why a small hierarchy: a definition bug (a transition to a state that does not exist, a behavior on an
orthogonal the machine never creates) must fail at import or at ``start()`` with a message naming the
offending class, while runtime lookups that fail (``requires_client`` of a client nobody created) raise a
different type so callers can tell "the model is wrong" from "the wiring is wrong". SMACC2 has no such
hierarchy: its definition errors are C++ compile errors and its failed lookups return null pointers.
"""

from __future__ import annotations


class SmaccError(Exception):
    """Root of every error raised by smacc_py."""


class InvalidDefinitionError(SmaccError, ValueError):
    """A state machine, state or event declaration is wrong; the message names the class at fault."""


class SmaccLookupError(SmaccError, LookupError):
    """A runtime lookup (client, component, orthogonal, behavior, reactor, global datum) found nothing."""


def missing(kind: str, wanted: type, who: str, where: str) -> SmaccLookupError:
    """A SmaccLookupError whose message names what was wanted, who asked and where it looked."""
    return SmaccLookupError(f"{who}: no {kind} of type {wanted.__name__} in {where}")
