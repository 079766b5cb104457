"""SMACC2's spellings: the named key events EvKeyPressA..Z and ``getLogger()`` / ``get_logger()`` on
states, client behaviors, clients and components."""

from __future__ import annotations

import logging
from typing import Any

import pytest

import smacc_py.clients.cl_keyboard as cl_keyboard
import smacc_py.core as core
from smacc_py.clients.cl_keyboard import CbDefaultKeyboardBehavior, ClKeyboard, EvKeyPressN, EvKeyPressY
from smacc_py.core import (
    SUCCESS,
    EvKeyPress,
    ISmaccClient,
    ISmaccComponent,
    Orthogonal,
    SmaccClientBehavior,
    SmaccState,
    SmaccStateMachineBase,
    Transition,
    key_press_event,
)
from smacc_py.testing import MachineHarness

LETTERS = "ABCDEFGHIJKLMNOPQRSTUVWXYZ"


def test_every_letter_has_its_named_event_in_core_and_cl_keyboard() -> None:
    for letter in LETTERS:
        named = getattr(cl_keyboard, f"EvKeyPress{letter}")
        assert named is getattr(core, f"EvKeyPress{letter}") is key_press_event(letter.lower())
        assert issubclass(named, EvKeyPress) and named.key == letter
        assert named.__name__ == f"EvKeyPress{letter}"
        assert f"EvKeyPress{letter}" in cl_keyboard.__all__ and f"EvKeyPress{letter}" in core.__all__
    with pytest.raises(ValueError, match=r"only letters A\.\.Z"):  # SMACC2's keyboard has no digit events
        key_press_event("1")
    assert not hasattr(cl_keyboard, "EvKeyPress1")


class OrKeyboard(Orthogonal):
    def on_initialize(self) -> None:
        self.create_client(ClKeyboard)


class StWaitKey(SmaccState, parent="SmKeys"):
    reactions = (
        Transition(EvKeyPressN[CbDefaultKeyboardBehavior, OrKeyboard], "StAfterN", SUCCESS),
        Transition(EvKeyPressY[CbDefaultKeyboardBehavior, OrKeyboard], "StAfterY", SUCCESS),
    )

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrKeyboard, CbDefaultKeyboardBehavior)


class StAfterN(SmaccState, parent="SmKeys"):
    pass


class StAfterY(SmaccState, parent="SmKeys"):
    pass


class SmKeys(SmaccStateMachineBase):
    initial_state = StWaitKey

    def on_initialize(self) -> None:
        self.create_orthogonal(OrKeyboard)


@pytest.mark.parametrize(("key", "state"), [("n", "StAfterN"), ("Y", "StAfterY")])
def test_a_transition_on_a_named_key_event_fires_on_that_key_only(key: str, state: str) -> None:
    with MachineHarness(SmKeys) as harness:
        harness.press("q")
        assert harness.sm.current_state_names() == ["StWaitKey"]
        harness.press(key)  # 'y' is EvKeyPressY (SMACC2's humble client mapped it to EvKeyPressI)
        assert harness.sm.current_state_names() == [state]


# ----------------------------------------------------------------------------- getLogger
class Lines:
    """A logger that keeps (level, message), as the runtime's node logger would print them."""

    def __init__(self) -> None:
        self.lines: list[tuple[str, str]] = []

    def __getattr__(self, level: str) -> Any:
        return lambda message: self.lines.append((level, message))


class CpCounter(ISmaccComponent):
    def on_initialize(self) -> None:
        self.getLogger().debug("CpCounter ready")


class ClTalker(ISmaccClient):
    def on_initialize(self) -> None:
        self.create_component(CpCounter)  # its on_initialize runs after every client's
        self.get_logger().info("ClTalker ready")


class OrTalk(Orthogonal):
    def on_initialize(self) -> None:
        self.create_client(ClTalker)


class CbTalk(SmaccClientBehavior):
    def on_entry(self) -> None:
        self.getLogger().warning("CbTalk entry")
        self.get_logger().error("CbTalk again")


class StTalk(SmaccState, parent="SmTalk"):
    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrTalk, CbTalk)

    def on_entry(self) -> None:
        self.getLogger().info("StTalk entry")
        self.get_logger().fatal("StTalk again")


class SmTalk(SmaccStateMachineBase):
    initial_state = StTalk

    def on_initialize(self) -> None:
        self.create_orthogonal(OrTalk)


def test_states_behaviors_clients_and_components_log_through_the_machines_logger() -> None:
    harness = MachineHarness(SmTalk)
    lines = Lines()
    harness.sm.set_logger(lines)
    with harness:
        assert lines.lines == [
            ("info", "ClTalker ready"), ("debug", "CpCounter ready"),
            ("info", "StTalk entry"), ("fatal", "StTalk again"),
            ("warning", "CbTalk entry"), ("error", "CbTalk again"),
        ]
        state = harness.sm.current_state
        assert state is not None and state.getLogger() is state.get_logger() is lines


def test_without_a_runtime_the_logger_is_a_python_logger_named_after_the_machine(
        caplog: pytest.LogCaptureFixture) -> None:
    with caplog.at_level(logging.INFO, logger="smacc_py.SmTalk"), MachineHarness(SmTalk) as harness:
        assert harness.sm.getLogger() is logging.getLogger("smacc_py.SmTalk")
    assert [(r.name, r.getMessage()) for r in caplog.records if r.name == "smacc_py.SmTalk"] == [
        ("smacc_py.SmTalk", m) for m in ("ClTalker ready", "StTalk entry", "StTalk again", "CbTalk entry",
                                         "CbTalk again")
    ]
