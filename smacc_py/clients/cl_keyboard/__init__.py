"""cl_keyboard: ``ClKeyboard`` (std_msgs/UInt16 on ``/keyboard_unicode``) and CbDefaultKeyboardBehavior.

A key press arrives as its unicode code point; ``CbDefaultKeyboardBehavior`` posts
``EvKeyPress<X>[CbDefaultKeyboardBehavior, Or]`` for letters (either case; SMACC2's humble client
mapped 'y' to EvKeyPressI, this one maps every letter to its own event). ``smacc-key n`` sends a key.
The events have SMACC2's names, ``EvKeyPressA`` .. ``EvKeyPressZ`` (importable from here), so
``Transition(EvKeyPressN[CbDefaultKeyboardBehavior, OrKeyboard], "StNext")`` reads as in C++;
``key_press_event("n")`` gives the same class. SMACC2's keyboard client has no digit events, nor
this one.
"""

from __future__ import annotations

from collections.abc import Callable

from std_msgs.msg import UInt16

from smacc_py.core import (
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
    ISmaccClient,
    SmaccClientBehavior,
    key_press_event,
)
from smacc_py.ros.components.signal import SmaccSignal
from smacc_py.ros.context import ros_context

KEYBOARD_TOPIC = "/keyboard_unicode"


def key_of(code: int) -> str | None:
    """The letter (upper case) of a unicode code point, or None for anything else."""
    try:
        char = chr(code)
    except (ValueError, OverflowError):
        return None
    return char.upper() if char.isascii() and char.isalpha() else None


class ClKeyboard(ISmaccClient):
    """Subscribes the keyboard topic and hands each key to the active keyboard behaviors.

    It posts no event itself (a SmaccSubscriberClient would post EvTopicMessage per key): the behaviors
    connected to ``key_pressed`` turn letters into EvKeyPress events of their own.
    """

    def __init__(self, topic: str = KEYBOARD_TOPIC) -> None:
        self.topic = topic
        self.key_pressed: SmaccSignal[str] = SmaccSignal("ClKeyboard.key_pressed")

    def on_initialize(self) -> None:
        ctx = ros_context(self.sm)
        self._sub = ctx.node.create_subscription(UInt16, self.topic, self._on_key, 10)

    def _on_key(self, msg: UInt16) -> None:
        key = key_of(msg.data)
        if key is not None:
            self.key_pressed.emit(key)

    def add_listener(self, listener: Callable[[str], None]) -> Callable[[], None]:
        """Call ``listener(letter)`` for each key press; returns the function that disconnects it."""
        return self.key_pressed.connect(listener)

    def remove_listener(self, listener: Callable[[str], None]) -> None:
        """Stop calling ``listener``."""
        self.key_pressed.disconnect(listener)


class CbDefaultKeyboardBehavior(SmaccClientBehavior):
    """Re-posts key presses as ``EvKeyPress<X>[CbDefaultKeyboardBehavior, Or]``."""

    def on_entry(self) -> None:
        self._client = self.requires_client(ClKeyboard)
        self._client.add_listener(self._on_key)

    def on_exit(self) -> None:
        self._client.remove_listener(self._on_key)

    def _on_key(self, key: str) -> None:
        self.post_event(self.own_event(key_press_event(key)))


__all__ = [
    "KEYBOARD_TOPIC", "CbDefaultKeyboardBehavior", "ClKeyboard", "EvKeyPressA", "EvKeyPressB",
    "EvKeyPressC", "EvKeyPressD", "EvKeyPressE", "EvKeyPressF", "EvKeyPressG", "EvKeyPressH",
    "EvKeyPressI", "EvKeyPressJ", "EvKeyPressK", "EvKeyPressL", "EvKeyPressM", "EvKeyPressN",
    "EvKeyPressO", "EvKeyPressP", "EvKeyPressQ", "EvKeyPressR", "EvKeyPressS", "EvKeyPressT",
    "EvKeyPressU", "EvKeyPressV", "EvKeyPressW", "EvKeyPressX", "EvKeyPressY", "EvKeyPressZ", "key_of",
    "key_press_event",
]
