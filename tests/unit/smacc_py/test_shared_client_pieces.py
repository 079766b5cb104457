"""The pieces the shipped clients share with the generic client library: SmaccSignal (CpAmcl's and
ClKeyboard's listeners) and CbOutcomeBase's timeout rules (the cl_nav2z and cl_battery waits)."""

from __future__ import annotations

import pytest

from smacc_py.core import (
    ABORT,
    EvCbFailure,
    Orthogonal,
    SmaccState,
    SmaccStateMachineBase,
    Transition,
)
from smacc_py.ros.client_behaviors import CbOutcomeBase
from smacc_py.ros.components import SmaccSignal
from tests.helpers.smacc_generic_fakes import GenericRig

TIMEOUT_S = 2.0


def test_signal_disconnects_by_listener_or_by_the_returned_function() -> None:
    heard: list[tuple[str, int]] = []
    signal: SmaccSignal[int] = SmaccSignal("test")
    disconnect_a = signal.connect(lambda v: heard.append(("a", v)))

    def b(value: int) -> None:
        heard.append(("b", value))

    signal.connect(b)
    signal.emit(1)
    disconnect_a()
    signal.disconnect(b)
    signal.disconnect(b)  # twice: nothing
    signal.emit(2)
    assert heard == [("a", 1), ("b", 1)]
    assert len(signal) == 0


def test_signal_keeps_calling_listeners_after_one_raises() -> None:
    heard: list[int] = []
    signal: SmaccSignal[int] = SmaccSignal("test")
    signal.connect(lambda v: 1 // 0)
    signal.connect(heard.append)
    signal.emit(7)
    assert heard == [7]


class CbNever(CbOutcomeBase):
    """Waits for nothing: only its timeout ends it."""

    def __init__(self) -> None:
        self.set_timeout(TIMEOUT_S)


class CbNeverStrict(CbNever):
    strict_timeout = True


class OrTest(Orthogonal):
    pass


def _failed_after(behavior: type[CbOutcomeBase], *steps_s: float) -> list[bool]:
    """Whether ``behavior`` had failed (its EvCbFailure left StRun) after each clock step."""

    class SmTest(SmaccStateMachineBase):
        initial_state = "StRun"

        def on_initialize(self) -> None:
            self.create_orthogonal(OrTest)

    class StRun(SmaccState, parent=SmTest):
        reactions = (Transition(EvCbFailure[behavior, OrTest], "StFailed", ABORT),)

        @classmethod
        def static_configure(cls) -> None:
            cls.configure_orthogonal(OrTest, behavior)

    class StFailed(SmaccState, parent=SmTest):
        pass

    rig = GenericRig(SmTest).start()
    failed = []
    for step_s in steps_s:
        rig.poll(step_s)
        failed.append(rig.state() == "StFailed")
    return failed


@pytest.mark.parametrize(("behavior", "expected"), [(CbNever, [False, True, True]),
                                                    (CbNeverStrict, [False, False, True])])
def test_timeout_fails_at_the_deadline_unless_strict(
    behavior: type[CbOutcomeBase], expected: list[bool],
) -> None:
    assert _failed_after(behavior, 1.0, 1.0, 0.5) == expected  # clock: 1.0, 2.0 (the deadline), 2.5
