"""An observer that turns each transition into one human-readable line (runner and demo output)."""

from __future__ import annotations

from collections.abc import Callable

from smacc_py.core import SmaccObserver, SmaccStateMachineBase, TransitionRecord


def event_reason(event: object) -> str:
    """Why an event happened, from its payload: the Nav2 outcome, or a behavior's ``reason``."""
    parts = []
    error_msg = getattr(event, "error_msg", "")
    if getattr(event, "error_code", 0) or error_msg:
        parts.append(f"error_code {getattr(event, 'error_code', 0)}: {error_msg}")
    reason = getattr(event, "reason", "")
    if reason:
        parts.append(str(reason))
    return "; ".join(parts)


def format_transition(record: TransitionRecord) -> str:
    """``[t=12.30 s] StA -> StB [TAG] on EvX[Src, Or] (why)``; t is the machine clock (sim time)."""
    line = (
        f"[t={record.stamp_s:.2f} s] {record.source.__name__} -> {record.leaf.__name__} "
        f"[{record.tag.__name__}] on {type(record.event).get_event_label()}"
    )
    reason = event_reason(record.event)
    return f"{line} ({reason})" if reason else line


class TransitionPrinter(SmaccObserver):
    """Calls ``out(line)`` for every transition, on the machine thread (``out`` must be quick)."""

    def __init__(self, out: Callable[[str], None]) -> None:
        self.out = out

    def on_transition(self, sm: SmaccStateMachineBase, record: TransitionRecord) -> None:
        self.out(format_transition(record))
