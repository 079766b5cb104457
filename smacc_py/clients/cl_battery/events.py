"""Battery events: the client's per-message event and the two the mission reacts to."""

from __future__ import annotations

from smacc_py.core import ABORT, SUCCESS, SmaccEvent


class EvBatteryState(SmaccEvent):
    """A battery reading (payload ``percentage``, ``low``, ``charged``, ``charging``); params (client, or)."""


class EvBatteryLow(SmaccEvent):
    """The charge fell to the low threshold (posted by a state reactor)."""

    default_transition_tag = ABORT


class EvBatteryCharged(SmaccEvent):
    """The charge reached the charged threshold (posted by a state reactor)."""

    default_transition_tag = SUCCESS


def is_low(event: SmaccEvent) -> bool:
    """SrConditional predicate: an EvBatteryState reading at or below the low threshold."""
    return bool(getattr(event, "low", False))


def is_charged(event: SmaccEvent) -> bool:
    """SrConditional predicate: an EvBatteryState reading at or above the charged threshold."""
    return bool(getattr(event, "charged", False))
