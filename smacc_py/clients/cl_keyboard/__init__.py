"""cl_keyboard: ``ClKeyboard`` (std_msgs/UInt16 on ``/keyboard_unicode``) and CbDefaultKeyboardBehavior.

A key press arrives as its unicode code point; ``CbDefaultKeyboardBehavior`` posts
``EvKeyPress<X>[CbDefaultKeyboardBehavior, Or]`` for letters (either case; SMACC2's humble client
mapped 'y' to EvKeyPressI, this one maps every letter to its own event). ``smacc-key n`` sends a key.
"""

from __future__ import annotations

import threading
from collections.abc import Callable

from std_msgs.msg import UInt16

from smacc_py.core import ISmaccClient, SmaccClientBehavior, key_press_event
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
    """Subscribes the keyboard topic and hands each key to the active keyboard behaviors."""

    def __init__(self, topic: str = KEYBOARD_TOPIC) -> None:
        self.topic = topic
        self._lock = threading.Lock()
        self._listeners: list[Callable[[str], None]] = []

    def on_initialize(self) -> None:
        ctx = ros_context(self.sm)
        self._sub = ctx.node.create_subscription(UInt16, self.topic, self._on_key, 10)

    def _on_key(self, msg: UInt16) -> None:
        key = key_of(msg.data)
        if key is None:
            return
        with self._lock:
            listeners = list(self._listeners)
        for listener in listeners:
            listener(key)

    def add_listener(self, listener: Callable[[str], None]) -> None:
        """Call ``listener(letter)`` for each key press."""
        with self._lock:
            self._listeners.append(listener)

    def remove_listener(self, listener: Callable[[str], None]) -> None:
        """Stop calling ``listener``."""
        with self._lock:
            if listener in self._listeners:
                self._listeners.remove(listener)


class CbDefaultKeyboardBehavior(SmaccClientBehavior):
    """Re-posts key presses as ``EvKeyPress<X>[CbDefaultKeyboardBehavior, Or]``."""

    def on_entry(self) -> None:
        self._client = self.requires_client(ClKeyboard)
        self._client.add_listener(self._on_key)

    def on_exit(self) -> None:
        self._client.remove_listener(self._on_key)

    def _on_key(self, key: str) -> None:
        self.post_event(self.own_event(key_press_event(key)))


__all__ = ["KEYBOARD_TOPIC", "CbDefaultKeyboardBehavior", "ClKeyboard", "key_of"]
